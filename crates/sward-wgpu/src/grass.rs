//! sward's renderer on a wgpu device: a grass frame recorded as one raw region into a wgpu
//! command encoder, over the application's attachments, and the bookkeeping wgpu does not do
//! for raw commands — which frame slot the GPU has finished with, and the views it still reads.

use std::sync::Arc;

use ash::vk;
use sward_core::quality::QualityPreset;
use sward_core::{Field, FrameDesc};
use sward_gpu::barrier::{self, Access};
use sward_gpu::buffer::Buffer;
use sward_gpu::gpu_allocator::MemoryLocation;
use sward_gpu::timer::{GpuTimer, PassTimes, Stamp};
use sward_gpu::{CallerDepth, Context, Passes, Renderer, RendererDesc, TargetFormat, TargetViews};
use wgpu::hal::api::Vulkan;

use crate::target::{raw_image, raw_view};
use crate::{BridgeError, DrawnBlades, FrameTarget, SwardDevice, TargetDesc};

/// Frames sward may have recorded that the GPU has not finished: the application submits each
/// before it asks for this many more.
pub const FRAMES_IN_FLIGHT: usize = 3;

pub use sward_core::frame::VIEWS_PER_FRAME;

/// Every earlier command's writes, before or after sward's region: wgpu inserts no barrier
/// around raw commands, and what the application does on either side is its own.
const EVERYTHING: Access = Access {
    stages: vk::PipelineStageFlags2::ALL_COMMANDS,
    access: vk::AccessFlags2::from_raw(
        vk::AccessFlags2::MEMORY_READ.as_raw() | vk::AccessFlags2::MEMORY_WRITE.as_raw(),
    ),
};

/// sward's grass renderer on a wgpu device, drawing into the application's attachments.
pub struct GrassRenderer {
    /// sward's buffers as wgpu's, where the application draws the blades itself (before the
    /// renderer: wgpu's aliases go before sward's memory).
    drawn: Option<DrawnBlades>,
    /// Where the application draws the blades itself: the blades as the last frame drew them
    /// (copied before each frame simulates, where `keeps_previous`), for its motion vectors.
    previous: Option<Buffer>,
    keeps_previous: bool,
    /// Whether the frames list the blades for the application ([`GrassRenderer::set_drawn_blades`]).
    listing: bool,
    /// Where the application draws the blades itself: each view's draw commands, copied after
    /// its cull (the next view's cull rewrites sward's own before the application draws).
    view_draws: Vec<Buffer>,
    renderer: Renderer,
    /// Frame slots: [`FRAMES_IN_FLIGHT`] frames of `views` views each.
    slots: Vec<Slot>,
    /// Views each frame has room for (grows to [`VIEWS_PER_FRAME`] as views appear).
    views: usize,
    /// Frames begun (by their view 0).
    frames: u32,
    /// Host-visible: the number of the last recording whose sward commands the GPU has run.
    finished: Buffer,
    recorded: u32,
    target: TargetDesc,
    /// Per view, the depth-only view its occlusion test reads, of the depth texture it was
    /// made for.
    depth_readers: Vec<Option<(wgpu::Texture, wgpu::TextureView)>>,
    timing: bool,
    last_times: Option<PassTimes>,
    /// Host time the last frame recorded waited for the GPU to free its slot.
    last_wait: std::time::Duration,
    /// sward's context, dropped before the wgpu device it lives on (fields drop in order).
    ctx: Arc<Context>,
    device: wgpu::Device,
}

/// What one frame slot's commands hold until the GPU has run them.
#[derive(Default)]
struct Slot {
    /// The frame recorded in this slot last.
    frame: Option<u32>,
    /// The views its commands draw into and read (wgpu keeps nothing alive for raw commands).
    views: Vec<wgpu::TextureView>,
    timer: Option<GpuTimer>,
}

impl GrassRenderer {
    /// A renderer on `sward`'s device drawing into attachments as `target` describes, at the
    /// quality `quality` (its shadow map; the samples are the target's).
    pub fn new(sward: &SwardDevice, target: &TargetDesc, quality: QualityPreset) -> Result<GrassRenderer, BridgeError> {
        let ctx = sward.context.clone();
        let format = {
            let hal = unsafe { sward.adapter.as_hal::<Vulkan>() }
                .ok_or(BridgeError::NotVulkan(sward.adapter.get_info().backend))?;
            target.sward_format(&hal)?
        };
        check_samples(&ctx, format)?;
        let slots = FRAMES_IN_FLIGHT * VIEWS_PER_FRAME;
        let desc = RendererDesc {
            target: format,
            ..RendererDesc::for_quality(&ctx.info, format.color, quality, slots)
        };
        let renderer = Renderer::new(&ctx, &desc)?;
        let mut finished = Buffer::new(
            &ctx,
            "sward's finished frames",
            4,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        // None yet: the frame before frame 0.
        // The mapping may be longer than the 4 bytes asked for (the allocation's granularity).
        finished.mapped_mut().expect("a host-visible buffer")[..4].copy_from_slice(&u32::MAX.to_le_bytes());
        Ok(GrassRenderer {
            drawn: None,
            previous: None,
            keeps_previous: true,
            listing: false,
            view_draws: Vec::new(),
            renderer,
            slots: (0..slots).map(|_| Slot::default()).collect(),
            views: 1,
            frames: 0,
            finished,
            recorded: 0,
            target: *target,
            depth_readers: Vec::new(),
            timing: false,
            last_times: None,
            last_wait: std::time::Duration::ZERO,
            ctx,
            device: sward.device.clone(),
        })
    }

    /// Put a field of blades (and its ground, for the shadows it receives) on the GPU; waits
    /// for the upload on the shared queue.
    pub fn upload(&mut self, field: &Field) -> Result<(), BridgeError> {
        self.wait_idle();
        self.let_go_of_drawn();
        self.renderer.upload(field)?;
        self.renderer.upload_ground(field.ground.as_ref())?;
        Ok(())
    }

    /// sward's own renderer, for what this bridge does not wrap (its route, its read-backs).
    /// Changing what it holds (a new field) while frames are in flight needs
    /// [`GrassRenderer::wait_idle`] first.
    pub fn renderer_mut(&mut self) -> &mut Renderer {
        &mut self.renderer
    }

    /// Whether each frame lists the Bezier blades for the application to draw itself
    /// ([`GrassRenderer::drawn_blades`]); waits for the GPU.
    pub fn set_drawn_blades(&mut self, on: bool) -> Result<(), BridgeError> {
        self.wait_idle();
        self.let_go_of_drawn();
        self.listing = on;
        self.renderer.set_drawn_blades(if on { self.views } else { 0 })?;
        Ok(())
    }

    /// Whether each frame keeps the blades as the last frame drew them (for the application's
    /// motion vectors, [`DrawnBlades::previous_blades`]): a copy of every blade a frame, so
    /// off where no view draws motion vectors. On by default.
    pub fn set_previous_blades(&mut self, on: bool) {
        self.keeps_previous = on;
    }

    /// sward's buffers the application's own draw of the Bezier blades reads, as wgpu buffers,
    /// and which of each view's uniforms the last frame wrote (`DrawnView::uniforms[k]`);
    /// `None` where there is no field or the frames do not list them
    /// ([`GrassRenderer::set_drawn_blades`]). The buffers stay the same until the next upload
    /// or a frame with more views than before.
    pub fn drawn_blades(&mut self) -> Result<Option<(&DrawnBlades, usize)>, BridgeError> {
        let frame = self.frames.wrapping_sub(1) as usize % FRAMES_IN_FLIGHT;
        if self.drawn.is_none() {
            let Some(buffers) = self.renderer.drawn_blade_buffers(0) else {
                return Ok(None);
            };
            let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST;
            let previous = Buffer::new(
                &self.ctx,
                "the blades last drawn",
                buffers.blades.size,
                usage,
                MemoryLocation::GpuOnly,
            )?;
            // As they are now, until a frame copies them.
            copy_now(buffers.blades, &previous)?;
            let mut views = Vec::new();
            for view in 0..self.views {
                let slots: Vec<usize> = (0..FRAMES_IN_FLIGHT).map(|f| self.slot_at(f, view)).collect();
                let listed = self.renderer.drawn_blade_buffers(slots[0]).expect("listed above");
                let uniforms: Vec<&Buffer> = slots
                    .iter()
                    .filter_map(|&k| self.renderer.drawn_blade_buffers(k).map(|b| b.uniforms))
                    .collect();
                let Some(draws) = self.view_draws.get(view) else {
                    // No frame listed the blades for this view yet.
                    return Ok(None);
                };
                views.push(crate::drawn::DrawnView::wrap(
                    &self.device,
                    listed.drawn,
                    draws,
                    &uniforms,
                )?);
            }
            self.drawn = Some(DrawnBlades::wrap(&self.device, buffers.blades, &previous, views)?);
            self.previous = Some(previous);
        }
        Ok(self.drawn.as_ref().map(|drawn| (drawn, frame)))
    }

    /// Where the frames list the blades, a buffer for each view's draw commands up to `view`.
    fn make_view_draws(&mut self, view: usize) -> Result<(), BridgeError> {
        let Some(size) = self.renderer.drawn_blade_buffers(0).map(|b| b.draws.size) else {
            return Ok(());
        };
        while self.view_draws.len() <= view {
            let usage = vk::BufferUsageFlags::INDIRECT_BUFFER
                | vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_DST;
            let draws = Buffer::new(
                &self.ctx,
                "a view's draw commands",
                size,
                usage,
                MemoryLocation::GpuOnly,
            )?;
            self.view_draws.push(draws);
        }
        Ok(())
    }

    /// The wgpu aliases of sward's buffers and the copies made for them, before what they
    /// alias changes.
    fn let_go_of_drawn(&mut self) {
        (self.drawn, self.previous) = (None, None);
        self.view_draws.clear();
    }

    /// Make room for `views` views in every frame before the frame's first is recorded (room
    /// made later, between views, waits for the GPU and remakes the lists an unsubmitted view
    /// may read). Fails past [`VIEWS_PER_FRAME`].
    pub fn reserve_views(&mut self, views: usize) -> Result<(), BridgeError> {
        self.make_room_for(views.max(1) - 1)
    }

    /// Make room for `view` in every frame: more lists and slots per frame, where it is a view
    /// more than before (waits for the GPU).
    fn make_room_for(&mut self, view: usize) -> Result<(), BridgeError> {
        if view < self.views {
            return Ok(());
        }
        if view >= VIEWS_PER_FRAME {
            return Err(BridgeError::Target(format!(
                "a frame has at most {VIEWS_PER_FRAME} views that cull the grass for themselves, and view {view} was asked for"
            )));
        }
        self.wait_idle();
        self.views = view + 1;
        if self.listing {
            self.let_go_of_drawn();
            self.renderer.set_drawn_blades(self.views)?;
        }
        Ok(())
    }

    /// The frame slot `view` records into: view 0 begins a frame, the others join the frame it
    /// began.
    fn slot_of(&mut self, view: usize) -> usize {
        if view == 0 {
            self.frames = self.frames.wrapping_add(1);
            self.last_wait = std::time::Duration::ZERO;
        }
        self.slot_at(self.frames.wrapping_sub(1) as usize % FRAMES_IN_FLIGHT, view)
    }

    /// The frame slot of `view` in frame `frame` of those in flight: each frame's views side
    /// by side (so slot `k` is view `k % views`, the list it writes).
    fn slot_at(&self, frame: usize, view: usize) -> usize {
        frame * self.views + view
    }

    /// The target this renderer draws into.
    pub fn target(&self) -> &TargetDesc {
        &self.target
    }

    /// Time sward's passes with GPU timestamps ([`GrassRenderer::pass_times`]).
    pub fn set_timing(&mut self, on: bool) {
        self.timing = on;
    }

    /// sward's passes in the newest frame the GPU has finished, where timing is on: those of
    /// its first view (the simulation, and the first camera's cull).
    pub fn pass_times(&self) -> Option<&PassTimes> {
        self.last_times.as_ref()
    }

    /// Host time the last frame recorded (all its views) spent waiting for the GPU to finish
    /// the frame [`FRAMES_IN_FLIGHT`] before it (zero where the GPU keeps up): the part of
    /// [`GrassRenderer::encode`]'s time that is the GPU's, not the host's work.
    pub fn gpu_wait(&self) -> std::time::Duration {
        self.last_wait
    }

    /// Wait until the GPU has run everything submitted on the device.
    pub fn wait_idle(&self) {
        let _ = self.device.poll(wgpu::PollType::wait_indefinitely());
    }

    /// The frame `desc` describes as two command buffers to submit in order: wgpu's own, which
    /// puts the target's textures in the attachment states sward draws in (whatever wgpu last
    /// did with them), then sward's region ([`GrassRenderer::record`]).
    pub fn encode(&mut self, desc: &FrameDesc, target: &FrameTarget) -> Result<[wgpu::CommandBuffer; 2], BridgeError> {
        self.encode_view(desc, target, 0)
    }

    /// View `view` of a frame (split screen, a minimap, up to [`VIEWS_PER_FRAME`]), as
    /// [`GrassRenderer::encode`]: view 0 is the whole frame; a later view of the same frame
    /// culls and draws the grass view 0 stepped for its own camera (`desc`'s steps are not
    /// run again).
    pub fn encode_view(
        &mut self,
        desc: &FrameDesc,
        target: &FrameTarget,
        view: usize,
    ) -> Result<[wgpu::CommandBuffer; 2], BridgeError> {
        let mut attachments = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("sward: the attachments in"),
        });
        let color = target.color.texture();
        let resolve = target.resolve.map(|r| r.texture());
        let depth = target.depth.texture();
        let colors = std::iter::once(color)
            .chain(resolve)
            .map(|texture| wgpu::TextureTransition {
                texture,
                selector: None,
                state: wgpu::TextureUses::COLOR_TARGET,
            });
        let depth = wgpu::TextureTransition {
            texture: depth,
            selector: None,
            state: wgpu::TextureUses::DEPTH_STENCIL_WRITE,
        };
        attachments.transition_resources(std::iter::empty(), colors.chain(std::iter::once(depth)));
        let mut grass = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("sward: the grass"),
        });
        self.record_view(&mut grass, desc, target, view)?;
        Ok([attachments.finish(), grass.finish()])
    }

    /// The frame `desc` describes without its draw, as one command buffer: the Bezier blades
    /// simulated, culled and listed, for the application to draw itself in its own passes
    /// ([`GrassRenderer::drawn_blades`]) after submitting it. `desc.viewport` is the size of
    /// the view the blades are culled for. View 0 steps the grass; each later view of the frame
    /// (up to [`VIEWS_PER_FRAME`]) culls and lists it for its own camera, into
    /// [`DrawnBlades::views`]`[view]`.
    pub fn encode_compute(&mut self, desc: &FrameDesc, view: usize) -> Result<wgpu::CommandBuffer, BridgeError> {
        let mut encoder = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("sward: the grass's compute passes"),
        });
        self.make_room_for(view)?;
        self.make_view_draws(view)?;
        let slot = self.slot_of(view);
        self.free_slot(slot)?;
        let frame = self.recorded;
        let passes = Passes {
            simulate: view == 0,
            draw: false,
            ..Passes::ALL
        };
        let recorded = unsafe {
            encoder.as_hal_mut::<Vulkan, _, _>(|hal| {
                let cmd = hal.map(|hal| hal.raw_handle())?;
                if view == 0 && self.keeps_previous {
                    self.keep_previous_blades(cmd);
                }
                self.record_region(cmd, (slot, frame), desc, (passes, None));
                self.keep_view_draws(cmd, view);
                Some(())
            })
        };
        recorded.ok_or(BridgeError::NotVulkan(wgpu::Backend::Noop))?;
        self.slots[slot].frame = Some(frame);
        self.recorded = self.recorded.wrapping_add(1);
        Ok(encoder.finish())
    }

    /// Where the application draws the blades itself: `view`'s draw commands, copied where its
    /// draws read them once the cull has written them.
    fn keep_view_draws(&self, cmd: vk::CommandBuffer, view: usize) {
        let (Some(to), Some(now)) = (self.view_draws.get(view), self.renderer.drawn_blade_buffers(0)) else {
            return;
        };
        let d = &self.ctx.device;
        barrier::memory(d, cmd, EVERYTHING, Access::TRANSFER_WRITE);
        let region = vk::BufferCopy::default().size(now.draws.size.min(to.size));
        unsafe { d.cmd_copy_buffer(cmd, now.draws.raw, to.raw, &[region]) };
        barrier::memory(d, cmd, Access::TRANSFER_WRITE, EVERYTHING);
    }

    /// Where the application draws the blades itself: the blades as the last frame left them,
    /// copied before this frame simulates them (its motion vectors are drawn from both).
    fn keep_previous_blades(&self, cmd: vk::CommandBuffer) {
        let (Some(previous), Some(now)) = (&self.previous, self.renderer.drawn_blade_buffers(0)) else {
            return;
        };
        let d = &self.ctx.device;
        barrier::memory(d, cmd, EVERYTHING, Access::TRANSFER_WRITE);
        let region = vk::BufferCopy::default().size(now.blades.size.min(previous.size));
        unsafe { d.cmd_copy_buffer(cmd, now.blades.raw, previous.raw, &[region]) };
    }

    /// Record the frame `desc` describes into `encoder` as raw Vulkan: simulate, cull and draw
    /// over the application's colour and depth in `target`. `encoder` must not have been used
    /// through wgpu's own API (wgpu panics: it forbids mixing the two), and the target's
    /// textures must be in their attachment states: last used by wgpu as render attachments,
    /// as after the application's own render pass into them (or use
    /// [`GrassRenderer::encode`]). `desc.viewport` is the target's size. See the crate's
    /// safety contract.
    pub fn record(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        desc: &FrameDesc,
        target: &FrameTarget,
    ) -> Result<(), BridgeError> {
        self.record_view(encoder, desc, target, 0)
    }

    /// View `view` of a frame into `encoder`, as [`GrassRenderer::record`] records the whole
    /// frame (view 0); see [`GrassRenderer::encode_view`].
    pub fn record_view(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        desc: &FrameDesc,
        target: &FrameTarget,
        view: usize,
    ) -> Result<(), BridgeError> {
        let extent = target.checked_extent(&self.target)?;
        if desc.viewport != [extent.width, extent.height] {
            return Err(BridgeError::Target(format!(
                "the frame's viewport is {}×{} but its target {}×{}: describe the frame at the target's size",
                desc.viewport[0], desc.viewport[1], extent.width, extent.height
            )));
        }
        self.make_room_for(view)?;
        let slot = self.slot_of(view);
        self.free_slot(slot)?;
        let reader = target.occlusion.then(|| self.depth_reader(target.depth, view));
        let views = TargetViews {
            color: raw_view(target.color),
            resolve: target.resolve.map(raw_view),
            depth: raw_view(target.depth),
            extent,
            keep_depth: true,
            over_caller: true,
            occlusion: reader.as_ref().map(|reader| CallerDepth {
                image: raw_image(target.depth.texture()),
                view: raw_view(reader),
            }),
        };
        let frame = self.recorded;
        let recorded = unsafe {
            encoder.as_hal_mut::<Vulkan, _, _>(|hal| {
                let cmd = hal.map(|hal| hal.raw_handle())?;
                let passes = Passes {
                    simulate: view == 0,
                    ..Passes::ALL
                };
                self.record_region(cmd, (slot, frame), desc, (passes, Some(&views)));
                Some(())
            })
        };
        recorded.ok_or(BridgeError::NotVulkan(wgpu::Backend::Noop))?;
        let kept = &mut self.slots[slot];
        kept.frame = Some(frame);
        kept.views = [target.color, target.depth]
            .into_iter()
            .chain(target.resolve)
            .chain(reader.as_ref())
            .cloned()
            .collect();
        self.recorded = self.recorded.wrapping_add(1);
        Ok(())
    }

    /// sward's frame in `cmd`: everything before it made visible, the frame, everything it
    /// wrote made visible to what follows, and the frame's number written where the host reads
    /// which frames have finished.
    fn record_region(
        &mut self,
        cmd: vk::CommandBuffer,
        (slot, frame): (usize, u32),
        desc: &FrameDesc,
        (passes, views): (Passes, Option<&TargetViews>),
    ) {
        let d = &self.ctx.device;
        barrier::memory(d, cmd, EVERYTHING, EVERYTHING);
        let timer = self.slots[slot].timer.as_mut();
        if let Some(timer) = timer {
            timer.begin(cmd);
        }
        let timer = self.slots[slot].timer.as_ref();
        self.renderer.record_frame(cmd, slot, desc, passes, views, timer);
        if let Some(timer) = timer {
            // Every stamp written, or the pool's results are never ready: sward's frame ends here.
            timer.stamp(cmd, Stamp::Ui);
        }
        barrier::memory(d, cmd, EVERYTHING, EVERYTHING);
        unsafe { d.cmd_fill_buffer(cmd, self.finished.raw, 0, 4, frame) };
        barrier::memory(d, cmd, Access::TRANSFER_WRITE, Access::HOST_READ);
    }

    /// Make `slot` free to record into: the GPU has run the frame recorded in it before, or that
    /// frame was never submitted. Its timings are read then, and its views let go.
    fn free_slot(&mut self, slot: usize) -> Result<(), BridgeError> {
        if let Some(frame) = self.slots[slot].frame {
            if !self.has_finished(frame) {
                // Everything submitted so far: if the frame is still not done, its command
                // buffer was dropped unsubmitted, and nothing will ever run it.
                let start = std::time::Instant::now();
                self.wait_idle();
                // Every view's wait of the frame.
                self.last_wait += start.elapsed();
            }
            // The times of a frame's first view: the frame's simulation and its camera's cull.
            if self.has_finished(frame) && slot.is_multiple_of(self.views) {
                if let Some(timer) = &self.slots[slot].timer {
                    self.last_times = timer.read().or(self.last_times.take());
                }
            }
        }
        let kept = &mut self.slots[slot];
        kept.views.clear();
        if self.timing && kept.timer.is_none() {
            kept.timer = Some(GpuTimer::new(&self.ctx)?);
        } else if !self.timing {
            kept.timer = None;
        }
        Ok(())
    }

    /// Whether the GPU has run sward's commands of `frame`.
    fn has_finished(&self, frame: u32) -> bool {
        let bytes = self.finished.mapped().expect("a host-visible buffer");
        let last = u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]);
        // Frame numbers wrap: `frame` is done if `last` is at or past it.
        (last.wrapping_sub(frame) as i32) >= 0
    }

    /// A depth-only view of `depth`'s texture for view `of`'s occlusion test to read, kept
    /// while the texture is the same.
    fn depth_reader(&mut self, depth: &wgpu::TextureView, of: usize) -> wgpu::TextureView {
        let texture = depth.texture();
        if self.depth_readers.len() <= of {
            self.depth_readers.resize(of + 1, None);
        }
        if let Some((kept, view)) = &self.depth_readers[of] {
            if kept == texture {
                return view.clone();
            }
        }
        let view = texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some("sward: the application's depth, read"),
            aspect: wgpu::TextureAspect::DepthOnly,
            ..Default::default()
        });
        self.depth_readers[of] = Some((texture.clone(), view.clone()));
        view
    }
}

impl Drop for GrassRenderer {
    /// The GPU done with sward's commands before its buffers and recordings go.
    fn drop(&mut self) {
        self.wait_idle();
    }
}

/// Copy `from` into `to` and wait (once, when the copy is made).
fn copy_now(from: &Buffer, to: &Buffer) -> Result<(), BridgeError> {
    let bytes = from.download()?;
    to.upload(0, &bytes[..bytes.len().min(to.size as usize)])?;
    Ok(())
}

/// Fail unless the device draws with the target's samples.
fn check_samples(ctx: &Context, format: TargetFormat) -> Result<(), BridgeError> {
    let samples = format.samples;
    if ctx.info.samples_up_to(samples.as_raw()) != samples {
        return Err(BridgeError::Target(format!(
            "{} lacks {} samples per pixel for its attachments",
            ctx.info.name,
            samples.as_raw()
        )));
    }
    Ok(())
}
