//! A frame's passes kept recorded from one frame to the next. sward's commands change only when
//! what shapes them changes — the technique, the flags, the counts, the target, a buffer grown —
//! never with the camera, the time or the colliders' places, which every pass reads from the
//! frame's uniforms in memory. So each frame slot keeps its passes in a secondary command
//! buffer, replayed into the caller's command buffer while the frame's [`RecordingKey`] is the
//! one it was recorded with: the host then writes only the uniforms.

use std::sync::Arc;

use ash::vk;
use glam::{Mat4, Vec4};
use sward_core::gpu::FrameUniforms;
use sward_core::quality::DrawRoute;

use crate::context::Context;
use crate::error::{vk_check, Result};
use crate::renderer::Passes;
use crate::target::TargetViews;

/// Everything a frame's commands are recorded from. Two frames with equal keys record the same
/// commands, so the second may replay the first's.
#[derive(Clone, Copy)]
pub(crate) struct RecordingKey {
    /// The frame's uniforms as far as the host reads them while recording ([`shape_of`]).
    pub shape: FrameUniforms,
    pub passes: Passes,
    pub target: Option<TargetViews>,
    /// The timer's query pool, where the frame is timed.
    pub timer: Option<vk::QueryPool>,
    pub route: DrawRoute,
    pub wireframe: bool,
    pub fused: bool,
    /// Whether the splat cells and the trample map are cleared whole (new buffers).
    pub fresh: [bool; 2],
    /// Descriptor writes so far (`Context::descriptor_writes`): a set written since a frame was
    /// recorded makes that recording unusable.
    pub descriptor_writes: u64,
}

impl PartialEq for RecordingKey {
    fn eq(&self, other: &Self) -> bool {
        bytemuck::bytes_of(&self.shape) == bytemuck::bytes_of(&other.shape)
            && self.passes == other.passes
            && self.target == other.target
            && self.timer == other.timer
            && self.route == other.route
            && self.wireframe == other.wireframe
            && self.fused == other.fused
            && self.fresh == other.fresh
            && self.descriptor_writes == other.descriptor_writes
    }
}

/// `uniforms` without what changes from frame to frame and only the shaders read: the camera's
/// and the sun's views, the eye and the time, the frustum's planes, the light's direction, the
/// wind, the colliders' places and the trample map's window; the steps to simulate count only
/// as none or some. (Where the host reads the camera — the tile list of a field too large for
/// the GPU to decide — the frame is not kept at all.)
pub(crate) fn shape_of(uniforms: &FrameUniforms) -> FrameUniforms {
    let mut shape = *uniforms;
    for view in [
        &mut shape.view_proj,
        &mut shape.inv_view_proj,
        &mut shape.sun_view_proj,
        &mut shape.sun_near_view_proj,
    ] {
        *view = Mat4::ZERO;
    }
    shape.camera_position = Vec4::ZERO;
    shape.light_direction = Vec4::ZERO;
    shape.frustum = [Vec4::ZERO; 6];
    shape.winds.fill(Vec4::ZERO);
    shape.colliders.fill(Vec4::ZERO);
    (shape.trample.z, shape.trample.w) = (0, 0);
    shape.counts.y = shape.counts.y.min(1);
    shape
}

/// A secondary command buffer per frame slot and the key it was last recorded with.
pub(crate) struct Recordings {
    pool: vk::CommandPool,
    kept: Vec<(vk::CommandBuffer, Option<RecordingKey>)>,
    /// Whether a caller's query may be open while the passes replay (the device has
    /// inheritedQueries), and the pipeline statistics it may count.
    queries: (bool, vk::QueryPipelineStatisticFlags),
    ctx: Arc<Context>,
}

impl Recordings {
    /// One secondary command buffer for each of `slots` frame slots.
    pub fn new(ctx: &Arc<Context>, slots: usize) -> Result<Recordings> {
        let d = &ctx.device;
        let what = "creating the kept frames' command buffers";
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(ctx.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        let pool = unsafe { d.create_command_pool(&pool_info, None) }.map_err(vk_check(what))?;
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .level(vk::CommandBufferLevel::SECONDARY)
            .command_buffer_count(slots as u32);
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
        Ok(Recordings {
            pool,
            kept: buffers.into_iter().map(|cmd| (cmd, None)).collect(),
            queries: (ctx.info.inherited_queries, statistics),
            ctx: ctx.clone(),
        })
    }

    /// Slot `slot`'s recording, where it was recorded with `key`.
    pub fn kept(&self, slot: usize, key: &RecordingKey) -> Option<vk::CommandBuffer> {
        let (cmd, kept) = &self.kept[slot];
        (kept.as_ref() == Some(key)).then_some(*cmd)
    }

    /// Start recording slot `slot`'s passes anew (its last frame has finished: the caller's
    /// promise for the slot).
    pub fn begin(&mut self, slot: usize) -> Result<vk::CommandBuffer> {
        let (cmd, kept) = &mut self.kept[slot];
        *kept = None;
        // Outside any render pass; a caller's open occlusion or statistics query may span it
        // where the device lets it.
        let inheritance = vk::CommandBufferInheritanceInfo::default()
            .occlusion_query_enable(self.queries.0)
            .pipeline_statistics(self.queries.1);
        let begin = vk::CommandBufferBeginInfo::default().inheritance_info(&inheritance);
        unsafe { self.ctx.device.begin_command_buffer(*cmd, &begin) }.map_err(vk_check("recording a frame"))?;
        Ok(*cmd)
    }

    /// Finish slot `slot`'s recording, kept under `key`.
    pub fn end(&mut self, slot: usize, key: RecordingKey) -> Result<vk::CommandBuffer> {
        let (cmd, kept) = &mut self.kept[slot];
        unsafe { self.ctx.device.end_command_buffer(*cmd) }.map_err(vk_check("recording a frame"))?;
        *kept = Some(key);
        Ok(*cmd)
    }

    /// Drop every kept recording (the renderer's buffers, pipelines or field changed).
    pub fn forget(&mut self) {
        for (_, kept) in &mut self.kept {
            *kept = None;
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
