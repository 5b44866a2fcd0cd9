//! A frame's passes kept recorded from one frame to the next. sward's commands change only when
//! what shapes them changes — the technique, the flags, the counts, the target's size, a buffer
//! grown — never with the camera, the time or the colliders' places, which every pass reads
//! from the frame's uniforms in memory. So each frame slot keeps its passes in secondary command
//! buffers, replayed into the caller's command buffer while the frame's [`RecordingKey`] is the
//! one they were recorded with: the host then writes only the uniforms. The key is built from
//! named parts of the frame's description and plan ([`FrameShape`]), and the passes record from
//! that shape alone, so a part that shapes commands cannot be left out of it. Two buffers per
//! recording: the passes before the draw, and the draw itself (continuing a rendering the
//! caller's buffer begins), so that nothing kept names the caller's images — a view destroyed
//! and another made with the same handle cannot be drawn into through a stale recording. (A
//! frame that reads the caller's depth names its image, but writes its descriptor every frame,
//! so its key is never met again.)

use std::sync::Arc;

use ash::vk;
use sward_core::frame::{FrameDesc, GroundShape};
use sward_core::gpu::{FramePlan, GeneratedLayout};
use sward_core::instanced::Technique;
use sward_core::quality::{DrawRoute, QualityPreset};

use crate::context::Context;
use crate::error::{vk_check, Result};
use crate::pipelines::TargetFormat;

/// The parts of a frame's description and plan that shape its commands: everything the host
/// reads while recording a frame, and nothing else (the passes record from this, never from
/// the description or the packed block). The camera, the time, the winds and the colliders'
/// places are not here — every pass reads them from the frame's uniforms in memory — so frames
/// that differ only in them replay one recording.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct FrameShape {
    /// Which grass the frame draws.
    pub technique: Technique,
    /// The quality preset (its distances and shadows).
    pub quality: QualityPreset,
    /// The route asked for (the key holds the route resolved too).
    pub route_asked: DrawRoute,
    /// The instanced grass and the billboards are generated this frame.
    pub generated: bool,
    /// The frame steps the physics (how many steps the GPU reads).
    pub steps: bool,
    /// The target's size in pixels, as the description gives it.
    pub viewport: [u32; 2],
    /// Bezier blades in the field.
    pub blade_count: u32,
    /// Collider spheres: pushing, cutting, and those only drawn into the depth pyramid.
    pub colliders: [u32; 3],
    /// The ground is the sphere the shaders make (else the plane or the uploaded mesh).
    pub sphere_ground: bool,
    /// The trample map's texels along a side (0: off).
    pub trample_texels: u32,
    /// The depth pyramid is drawn, with the nearest blades in it.
    pub depth_pyramid: bool,
    pub blade_occluders: bool,
    /// The sun's shadow map is drawn; blades cast into its near cascade.
    pub shadows: bool,
    pub blade_shadows: bool,
    /// How the field cascade's ground gets into it (`ShadowMap::record_field`).
    pub shadow_ground: ShadowGround,
    /// The first Bezier distance bucket that casts no shadow, and the instanced levels that cast.
    pub casting: [u32; 2],
    /// The first Bezier bucket rasterized by compute and the first splatted; whether any
    /// Bezier blade is.
    pub buckets: [u32; 2],
    pub bezier_splats: bool,
    /// The splat target is in use; generated grass splats; instanced blades and billboards are
    /// rasterized by compute; billboards are drawn with a depth pre-pass.
    pub splatting: bool,
    pub generated_splats: bool,
    pub blades_rasterized: bool,
    pub billboards_rasterized: bool,
    pub billboard_depth_prepass: bool,
    /// Where the generated grass's lists sit.
    pub layout: GeneratedLayout,
}

impl FrameShape {
    /// The shape of a frame described by `desc`, as the renderer planned it (`plan`; the splat
    /// target in use: `splatting`).
    pub fn of(desc: &FrameDesc, plan: &FramePlan, splatting: bool) -> FrameShape {
        let colliders = desc.colliders.packed_counts();
        let decided = &plan.decided;
        FrameShape {
            technique: desc.technique,
            quality: desc.quality,
            route_asked: desc.route,
            generated: decided.generates,
            steps: desc.steps > 0,
            viewport: desc.viewport,
            blade_count: plan.blade_count,
            colliders,
            sphere_ground: matches!(desc.ground, GroundShape::Sphere { radius, .. } if radius > 0.0),
            trample_texels: match (&desc.trample, plan.trample) {
                (Some(t), true) => t.resolution,
                _ => 0,
            },
            depth_pyramid: decided.depth_pyramid,
            blade_occluders: decided.blade_occluders > 0,
            shadows: decided.shadows,
            blade_shadows: decided.blade_shadows,
            // The renderer knows what it drew last.
            shadow_ground: ShadowGround::Drawn,
            casting: decided.casting,
            buckets: decided.buckets,
            bezier_splats: decided.bezier_splats,
            splatting,
            generated_splats: decided.generated_splats,
            blades_rasterized: decided.blades_rasterized,
            billboards_rasterized: decided.billboards_rasterized,
            billboard_depth_prepass: desc.billboard.depth_prepass,
            layout: plan.generated,
        }
    }
}

/// How the ground gets into the shadow map's field cascade.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ShadowGround {
    /// Drawn into the cascade itself: where what places it changed since the last frame, and
    /// every frame with `Renderer::keep_shadow_ground` off (the reference the kept ground is
    /// compared with).
    Drawn,
    /// Drawn into the map's ground image, which is copied in: where what places the ground
    /// changed since the last frame that drew it (`changed`), else as it was.
    Kept { changed: bool },
}

/// Everything a frame's commands are recorded from. Two frames with equal keys record the same
/// commands, so the second may replay the first's.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) struct RecordingKey {
    /// What of the frame's description and plan shapes its commands.
    pub shape: FrameShape,
    /// The frame's passes: simulate, cull, draw (`Passes`).
    pub passes: [bool; 3],
    /// The target's size and whether sward draws over the caller's picture, where it draws.
    pub target: Option<(vk::Extent2D, bool)>,
    /// The timer (`GpuTimer::id`), where the frame is timed.
    pub timer: Option<u64>,
    /// The route the blades are drawn by (resolved).
    pub route: DrawRoute,
    pub wireframe: bool,
    pub fused: bool,
    /// Whether the splat cells and the trample map are cleared whole (new buffers).
    pub fresh: [bool; 2],
    /// The listed blades are written for a renderer that draws them itself.
    pub drawn_blades: bool,
    /// Descriptor writes so far (`Context::descriptor_writes`): a set written since a frame was
    /// recorded makes that recording unusable.
    pub descriptor_writes: u64,
}

impl RecordingKey {
    /// The target's size and over-caller flag, where the frame draws.
    pub fn drawn_target(&self) -> Option<(vk::Extent2D, bool)> {
        self.target.filter(|_| self.passes[2])
    }
}

/// Recordings kept per frame slot: a slot that alternates frames that step the physics with
/// frames that do not, or draws into targets of two sizes, keeps one for each.
const KEPT_PER_SLOT: usize = 4;

/// A recording to replay: the passes before the draw, and the draw where the frame draws.
#[derive(Clone, Copy)]
pub(crate) struct Replay {
    pub passes: vk::CommandBuffer,
    pub draws: Option<vk::CommandBuffer>,
}

/// A slot's secondary command buffers and the key they were last recorded with.
struct Kept {
    passes: vk::CommandBuffer,
    draws: vk::CommandBuffer,
    key: Option<RecordingKey>,
}

impl Kept {
    fn replay(&self, key: &RecordingKey) -> Replay {
        let draws = key.drawn_target().map(|_| self.draws);
        Replay {
            passes: self.passes,
            draws,
        }
    }
}

/// Secondary command buffers per frame slot and the keys they were last recorded with.
pub(crate) struct Recordings {
    pool: vk::CommandPool,
    kept: Vec<Vec<Kept>>,
    /// Per slot, the recording replaced next when none is free (each in turn).
    next: Vec<usize>,
    /// Whether a caller's query may be open while the passes replay (the device has
    /// inheritedQueries), and the pipeline statistics it may count.
    queries: (bool, vk::QueryPipelineStatisticFlags),
    ctx: Arc<Context>,
}

impl Recordings {
    /// `KEPT_PER_SLOT` recordings for each of `slots` frame slots.
    pub fn new(ctx: &Arc<Context>, slots: usize) -> Result<Recordings> {
        let d = &ctx.device;
        let what = "creating the kept frames' command buffers";
        let pool = crate::context::command_pool(d, ctx.queue_family, what)?;
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .level(vk::CommandBufferLevel::SECONDARY)
            .command_buffer_count((2 * slots * KEPT_PER_SLOT) as u32);
        let buffers = match unsafe { d.allocate_command_buffers(&alloc) } {
            Ok(buffers) => buffers,
            Err(e) => {
                unsafe { d.destroy_command_pool(pool, None) };
                return Err(vk_check(what)(e));
            }
        };
        // Every core statistic: the caller's query may count any of them.
        let statistics = match ctx.info.inherited_queries && ctx.info.pipeline_statistics {
            true => vk::QueryPipelineStatisticFlags::from_raw(0x7ff),
            false => vk::QueryPipelineStatisticFlags::empty(),
        };
        let kept = buffers
            .chunks(2 * KEPT_PER_SLOT)
            .map(|slot| {
                let kept = |pair: &[vk::CommandBuffer]| Kept {
                    passes: pair[0],
                    draws: pair[1],
                    key: None,
                };
                slot.chunks(2).map(kept).collect()
            })
            .collect();
        Ok(Recordings {
            pool,
            kept,
            next: vec![0; slots],
            queries: (ctx.info.inherited_queries, statistics),
            ctx: ctx.clone(),
        })
    }

    /// Slot `slot`'s recording made with `key`, if it keeps one.
    pub fn kept(&self, slot: usize, key: &RecordingKey) -> Option<Replay> {
        self.kept[slot]
            .iter()
            .find(|kept| kept.key.as_ref() == Some(key))
            .map(|kept| kept.replay(key))
    }

    /// A place for slot `slot`'s next recording: a free one, else each in turn (every earlier
    /// frame of the slot has finished: the caller's promise).
    pub fn take(&mut self, slot: usize) -> usize {
        let place = match self.kept[slot].iter().position(|kept| kept.key.is_none()) {
            Some(free) => free,
            None => {
                let next = self.next[slot];
                self.next[slot] = (next + 1) % KEPT_PER_SLOT;
                next
            }
        };
        self.kept[slot][place].key = None;
        place
    }

    /// Begin recording the passes before the draw at `place` of slot `slot`.
    pub fn begin_passes(&self, slot: usize, place: usize) -> Result<vk::CommandBuffer> {
        let cmd = self.kept[slot][place].passes;
        self.begin(cmd, vk::CommandBufferUsageFlags::empty(), None)?;
        Ok(cmd)
    }

    /// Begin recording the draw at `place` of slot `slot`: inside a rendering into a target of
    /// `format` that the caller's buffer begins.
    pub fn begin_draws(&self, slot: usize, place: usize, format: TargetFormat) -> Result<vk::CommandBuffer> {
        let cmd = self.kept[slot][place].draws;
        let colors = [format.color];
        // The depth attachment alone: sward's renderings bind no stencil.
        let mut rendering = vk::CommandBufferInheritanceRenderingInfo::default()
            .color_attachment_formats(&colors)
            .depth_attachment_format(format.depth)
            .rasterization_samples(format.samples);
        let usage = vk::CommandBufferUsageFlags::RENDER_PASS_CONTINUE;
        self.begin(cmd, usage, Some(&mut rendering))?;
        Ok(cmd)
    }

    fn begin(
        &self,
        cmd: vk::CommandBuffer,
        usage: vk::CommandBufferUsageFlags,
        rendering: Option<&mut vk::CommandBufferInheritanceRenderingInfo>,
    ) -> Result<()> {
        // A caller's open occlusion or statistics query may span it where the device lets it.
        let mut inheritance = vk::CommandBufferInheritanceInfo::default()
            .occlusion_query_enable(self.queries.0)
            .pipeline_statistics(self.queries.1);
        if let Some(rendering) = rendering {
            inheritance = inheritance.push_next(rendering);
        }
        let begin = vk::CommandBufferBeginInfo::default()
            .flags(usage)
            .inheritance_info(&inheritance);
        unsafe { self.ctx.device.begin_command_buffer(cmd, &begin) }.map_err(vk_check("recording a frame"))
    }

    /// Finish the recording at `place` of slot `slot` (its draw too, where `key` draws), kept
    /// under `key`.
    pub fn end(&mut self, slot: usize, place: usize, key: RecordingKey) -> Result<Replay> {
        let kept = &mut self.kept[slot][place];
        let replay = kept.replay(&key);
        for cmd in std::iter::once(replay.passes).chain(replay.draws) {
            unsafe { self.ctx.device.end_command_buffer(cmd) }.map_err(vk_check("recording a frame"))?;
        }
        kept.key = Some(key);
        Ok(replay)
    }

    /// Drop every kept recording (the renderer's buffers, pipelines or field changed).
    pub fn forget(&mut self) {
        for kept in self.kept.iter_mut().flatten() {
            kept.key = None;
        }
    }
}

impl Drop for Recordings {
    fn drop(&mut self) {
        unsafe {
            // A replay may still be queued in a caller's frame.
            let _ = self.ctx.device.device_wait_idle();
            self.ctx.device.destroy_command_pool(self.pool, None);
        }
    }
}
