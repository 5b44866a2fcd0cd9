//! The portable renderer's frame: the frame's uniforms packed by sward-core from the frame's
//! description (`FrameUniforms::pack`, as the Vulkan renderer packs them), and its passes
//! recorded into the caller's encoder — simulate, cull into distance buckets, then (made for a
//! target) draw.

use sward_core::flags::CULL_OCCLUSION;
use sward_core::gpu::{FramePlan, FrameUniforms};
use sward_core::FrameDesc;

use super::draw::{drawn_scenery, record_draw, DrawInputs, DrawPipelines, DrawnScenery, Scenery};
use super::field::PortableField;
use super::pyramid::{DepthPyramid, PYRAMID_SIZE};
use super::shaders::{CULL_SOURCES, SIMULATE_SOURCE};
use super::{compute_pipeline, dispatch, PortableError, PortableTarget, PortableViews};

/// Invocations per workgroup of the passes that take a blade each (blade.wgsl `WORKGROUP`).
const WORKGROUP: u32 = 64;

/// Which of its passes a frame runs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PortablePasses {
    /// The frame's fixed steps of physics.
    pub simulate: bool,
    /// The depth pyramid's occluders drawn and reduced, where the frame's occlusion test is on.
    pub occluders: bool,
    /// Culling and the visible lists.
    pub cull: bool,
}

impl PortablePasses {
    /// Every pass there is.
    pub const ALL: PortablePasses = PortablePasses {
        simulate: true,
        occluders: true,
        cull: true,
    };
    /// The physics alone.
    pub const SIMULATE: PortablePasses = PortablePasses {
        simulate: true,
        occluders: false,
        cull: false,
    };
    /// A frame's culling: the depth pyramid, then the cull.
    pub const CULL: PortablePasses = PortablePasses {
        simulate: false,
        occluders: true,
        cull: true,
    };
}

/// The portable renderer's pipelines, the frame's uniform buffer and what the draw reads
/// beside the field (the ground mesh, the paint maps).
pub struct PortableRenderer {
    frame: wgpu::Buffer,
    simulate: wgpu::ComputePipeline,
    /// Count the buckets, lay them out, place the blades.
    cull: [wgpu::ComputePipeline; 3],
    /// Made for a target (`with_target`).
    draw: Option<DrawPipelines>,
    /// The occluders' depth, for the occlusion test.
    pyramid: DepthPyramid,
    scenery: Scenery,
    /// What the last recorded frame draws besides the blades.
    drawn: std::cell::Cell<DrawnScenery>,
    max_groups: u32,
}

impl PortableRenderer {
    /// The simulation and culling pipelines on `device` (of `adapter`), or why this device
    /// cannot run them.
    pub fn new(adapter: &wgpu::Adapter, device: &wgpu::Device) -> Result<PortableRenderer, PortableError> {
        let info = adapter.get_info();
        let flags = adapter.get_downlevel_capabilities().flags;
        if !flags.contains(wgpu::DownlevelFlags::COMPUTE_SHADERS) {
            return Err(PortableError::NoCompute(format!("{:?} ({})", info.backend, info.name)));
        }
        if !flags.contains(wgpu::DownlevelFlags::VERTEX_STORAGE) {
            return Err(PortableError::NoVertexStorage(format!(
                "{:?} ({})",
                info.backend, info.name
            )));
        }
        let [count, lay_out, place] = &CULL_SOURCES;
        Ok(PortableRenderer {
            frame: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("sward frame"),
                size: std::mem::size_of::<FrameUniforms>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            simulate: compute_pipeline(device, &SIMULATE_SOURCE)?,
            cull: [
                compute_pipeline(device, count)?,
                compute_pipeline(device, lay_out)?,
                compute_pipeline(device, place)?,
            ],
            draw: None,
            pyramid: DepthPyramid::new(device)?,
            scenery: Scenery::new(device),
            drawn: Default::default(),
            max_groups: device.limits().max_compute_workgroups_per_dimension,
        })
    }

    /// Every pipeline, the draws' made for attachments like `target`.
    pub fn with_target(
        adapter: &wgpu::Adapter,
        device: &wgpu::Device,
        target: &PortableTarget,
    ) -> Result<PortableRenderer, PortableError> {
        let mut renderer = PortableRenderer::new(adapter, device)?;
        renderer.draw = Some(DrawPipelines::new(device, target)?);
        Ok(renderer)
    }

    /// Draw the ground `mesh` from the next frame on (None: the plane or sphere the frame's
    /// description asks for, which the shaders make).
    pub fn upload_ground(&mut self, device: &wgpu::Device, mesh: Option<&sward_core::mesh::Mesh>) {
        self.scenery.set_ground(device, mesh);
    }

    /// Shade with `paint`'s maps from the next frame on (None: nothing painted). The frame's
    /// plan must say where they lie (`FramePlan::paint`).
    pub fn upload_paint(&mut self, device: &wgpu::Device, paint: Option<&sward_core::paint::GroundPaint>) {
        self.scenery.set_paint(device, paint);
    }

    /// Write the frame `desc` describes for `field` (its `steps` fixed steps from its time, seen
    /// by its camera), and record its `passes` into `encoder`.
    pub fn record(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        desc: &FrameDesc,
        field: &PortableField,
        passes: PortablePasses,
    ) {
        let plan = FramePlan {
            blade_count: field.count(),
            paint: self.scenery.paint_area,
            blade_occluders: true,
            depth_pyramid: true,
            pyramid_size: PYRAMID_SIZE,
            ..FramePlan::default()
        };
        let uniforms = FrameUniforms::pack(desc, &plan);
        self.drawn.set(drawn_scenery(&uniforms));
        queue.write_buffer(&self.frame, 0, bytemuck::bytes_of(&uniforms));
        let per_blade = groups(field.count(), self.max_groups);
        if passes.simulate && desc.steps > 0 && field.count() > 0 {
            let entries = [&self.frame, &field.blades, &field.etas].map(|b| b.as_entire_binding());
            let [frame, blades, etas] = entries;
            dispatch(
                device,
                encoder,
                &self.simulate,
                [(0, frame), (1, blades), (2, etas)],
                per_blade,
            );
        }
        if passes.occluders && uniforms.modes[0] & CULL_OCCLUSION != 0 {
            self.pyramid.record(device, encoder, &self.draw_inputs(field));
        }
        if passes.cull {
            encoder.clear_buffer(&field.counters, 0, None);
            let [count, lay_out, place] = &self.cull;
            let whole = wgpu::Buffer::as_entire_binding;
            let pyramid = whole(&self.pyramid.levels);
            let entries = [
                (0, whole(&self.frame)),
                (1, whole(&field.blades)),
                (5, whole(&field.bucket_of)),
                (6, whole(&field.counters)),
                (8, pyramid),
            ];
            dispatch(device, encoder, count, entries, per_blade);
            let entries = [
                (0, whole(&self.frame)),
                (4, whole(&field.draws)),
                (6, whole(&field.counters)),
            ];
            dispatch(device, encoder, lay_out, entries, [1, 1]);
            let entries = [
                (0, whole(&self.frame)),
                (3, whole(&field.visible)),
                (5, whole(&field.bucket_of)),
                (6, whole(&field.counters)),
            ];
            dispatch(device, encoder, place, entries, per_blade);
        }
    }

    /// What the draws (and the pyramid's occluders) read this frame.
    fn draw_inputs<'a>(&'a self, field: &'a PortableField) -> DrawInputs<'a> {
        DrawInputs {
            frame: &self.frame,
            field,
            scenery: &self.scenery,
            drawn: self.drawn.get(),
        }
    }

    /// Level `level` of the depth pyramid as the last culled frame left it, row by row: each
    /// texel's farthest occluder depth, as the bits of a float (for tests and tools).
    pub fn read_pyramid(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        level: u32,
    ) -> Result<Vec<u32>, PortableError> {
        self.pyramid.read_level(device, queue, level)
    }

    /// Record the frame the last [`PortableRenderer::record`] wrote, culled there, into
    /// `views`: the visible blades as strips, the colliders, the ground and the sky. Nothing
    /// where the renderer was made without a target ([`PortableRenderer::new`]).
    pub fn draw(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        field: &PortableField,
        views: &PortableViews,
    ) {
        if let Some(pipelines) = &self.draw {
            record_draw(device, encoder, pipelines, &self.draw_inputs(field), views);
        }
    }
}

/// Workgroups across and down for one invocation per blade, at most `max` a dimension: a row of
/// them first, then as many rows as it takes (blade.wgsl `blade_index` finds the blade from both).
fn groups(blades: u32, max: u32) -> [u32; 2] {
    let needed = blades.div_ceil(WORKGROUP).max(1);
    let across = needed.min(max.max(1));
    [across, needed.div_ceil(across)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_big_field_takes_rows_of_workgroups_within_the_limit() {
        assert_eq!(groups(1, 65535), [1, 1]);
        assert_eq!(groups(0, 65535), [1, 1]);
        assert_eq!(groups(64 * 65535, 65535), [65535, 1]);
        let [x, y] = groups(64 * 65535 + 1, 65535);
        assert_eq!([x, y], [65535, 2]);
        assert!(x as u64 * y as u64 * 64 > 64 * 65535);
    }
}
