//! The Bezier field's passes (the core's `simulate.wesl` and `cull.wesl`, which the Vulkan
//! renderer's `passes/bezier.rs` runs fused): the simulation over view 0's tiles, then each
//! view's cull into its lists — count each workgroup's blades per distance bucket, lay the
//! buckets out, scan the workgroups' counts per bucket, place each blade in its bucket's list
//! after those of the workgroups and lanes before it (the same list every run).

use sward_core::commands::DISTANCE_BUCKETS;
use sward_core::declared::bindings;
use sward_core::gpu::DrawCommand;

use super::FrameParts;
use crate::field::{CullLists, PortableField};
use crate::shaders::{ShaderModules, CULL_SOURCES, CULL_SUBGROUP_SOURCES, SIMULATE_SOURCE, SORT_SOURCES};
use crate::{compute_pipeline, dispatch, Bound, Groups, PortableError, Reading, FRAME};

/// The Bezier field's pipelines.
#[derive(Clone)]
pub(crate) struct BezierPasses {
    simulate: Reading<wgpu::ComputePipeline>,
    /// Count the buckets, lay them out, scan the workgroups' counts, place the blades.
    cull: [Reading<wgpu::ComputePipeline>; 5],
}

impl BezierPasses {
    /// The pipelines on `device`, the cull's with subgroups where the device has them
    /// (open_device asks for them).
    pub fn new(device: &wgpu::Device, modules: &ShaderModules) -> Result<BezierPasses, PortableError> {
        let [count, scan, place] = match device.features().contains(wgpu::Features::SUBGROUP) {
            true => CULL_SUBGROUP_SOURCES,
            false => [CULL_SOURCES[0], CULL_SOURCES[2], CULL_SOURCES[3]],
        };
        let [lay_out, sort] = &SORT_SOURCES[usize::from(!sorts_wide(device))];
        Ok(BezierPasses {
            simulate: compute_pipeline(device, &SIMULATE_SOURCE, modules)?,
            cull: [
                compute_pipeline(device, &count, modules)?,
                compute_pipeline(device, lay_out, modules)?,
                compute_pipeline(device, &scan, modules)?,
                compute_pipeline(device, &place, modules)?,
                compute_pipeline(device, sort, modules)?,
            ],
        })
    }

    /// The frame's steps over `field` (`per_blade` workgroups: view 0's tiles, or the whole
    /// field), the blades last drawn kept first where the field keeps them. A streamed blade
    /// eases into its instanced twin, made from the ground and paint.
    pub fn record_simulation(
        &self,
        parts: &FrameParts,
        encoder: &mut wgpu::CommandEncoder,
        field: &PortableField,
        per_blade: [u32; 2],
    ) {
        if let Some(previous) = &field.previous {
            encoder.copy_buffer_to_buffer(&field.blades, 0, previous, 0, field.blades.size());
        }
        let buffer = Bound::Buffer;
        let simulating = [
            (FRAME, buffer(parts.frame)),
            (bindings::BLADES, buffer(&field.blades)),
            (bindings::ETAS, buffer(&field.etas)),
            (bindings::GROUND, buffer(parts.ground)),
            (bindings::TRAMPLE, buffer(parts.trample)),
            (bindings::ACTIVE_TILES, buffer(&field.views[0].active_tiles)),
            (bindings::PAINT, buffer(parts.paint)),
        ];
        let simulation = (&self.simulate, &simulating[..], Groups::Direct(per_blade));
        dispatch((parts.device, parts.groups), encoder, &[simulation]);
    }

    /// A view's cull of `field` into its `lists`, tested against its depth pyramid's `levels`.
    pub fn record_cull(
        &self,
        parts: &FrameParts,
        encoder: &mut wgpu::CommandEncoder,
        (field, lists): (&PortableField, &CullLists),
        (levels, per_blade): (&wgpu::Buffer, [u32; 2]),
    ) {
        encoder.clear_buffer(&lists.counters, 0, None);
        let [count, lay_out, scan, place, sort] = &self.cull;
        let buffer = Bound::Buffer;
        let counting = [
            (FRAME, buffer(parts.frame)),
            (bindings::BLADES, buffer(&field.blades)),
            (bindings::BUCKET_OF, buffer(&lists.bucket_of)),
            (bindings::CULL_COUNTERS, buffer(&lists.counters)),
            (bindings::CULLED, buffer(&lists.group_runs)),
            (bindings::DEPTH_PYRAMID, buffer(levels)),
            (bindings::ACTIVE_TILES, buffer(&lists.active_tiles)),
        ];
        let laying_out = [
            (FRAME, buffer(parts.frame)),
            (bindings::DRAWS, buffer(&lists.draws)),
            (bindings::CULL_COUNTERS, buffer(&lists.counters)),
        ];
        let scanning = [
            (bindings::CULL_COUNTERS, buffer(&lists.counters)),
            (bindings::CULLED, buffer(&lists.group_runs)),
        ];
        let placing = [
            (FRAME, buffer(parts.frame)),
            (bindings::VISIBLE, buffer(&lists.visible)),
            (bindings::BUCKET_OF, buffer(&lists.bucket_of)),
            (bindings::CULL_COUNTERS, buffer(&lists.counters)),
            (bindings::CULLED, buffer(&lists.group_runs)),
            (bindings::ACTIVE_TILES, buffer(&lists.active_tiles)),
        ];
        let sorting = [
            (FRAME, buffer(parts.frame)),
            (bindings::BLADES, buffer(&field.blades)),
            (bindings::VISIBLE, buffer(&lists.visible)),
            (bindings::BUCKET_OF, buffer(&lists.bucket_of)),
            (bindings::CULL_COUNTERS, buffer(&lists.counters)),
        ];
        let sorted = SORT_DRAWN_COMMAND * std::mem::size_of::<DrawCommand>() as u64;
        let passes = [
            (count, &counting[..], Groups::Direct(per_blade)),
            (lay_out, &laying_out[..], Groups::Direct([1, 1])),
            (scan, &scanning[..], Groups::Direct([DISTANCE_BUCKETS, 1])),
            (place, &placing[..], Groups::Direct(per_blade)),
            (sort, &sorting[..], Groups::Indirect(&lists.draws, sorted)),
        ];
        dispatch((parts.device, parts.groups), encoder, &passes);
    }
}

/// Where the portable renderer's list is sorted in the buffers (buckets.wesl
/// `SORT_DRAWN_COMMAND`): after the buckets', the occluders' and the splats' commands.
const SORT_DRAWN_COMMAND: u64 = DISTANCE_BUCKETS as u64 + 2;

/// Whether `device` sorts runs of 8,192 blades by 1,024 invocations in 32 KiB of workgroup
/// memory (bitonic.wesl), as the Vulkan renderer does, rather than within WebGPU's defaults.
fn sorts_wide(device: &wgpu::Device) -> bool {
    let limits = device.limits();
    limits.max_compute_invocations_per_workgroup >= 1024
        && limits.max_compute_workgroup_size_x >= 1024
        && limits.max_compute_workgroup_storage_size >= 32 * 1024
}
