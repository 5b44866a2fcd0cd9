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
    /// (copied before each frame simulates), for its motion vectors.
    previous: Option<Buffer>,
    renderer: Renderer,
    slots: Vec<Slot>,
    /// Host-visible: the number of the last frame whose sward commands the GPU has run.
    finished: Buffer,
    recorded: u32,
    target: TargetDesc,
    /// The depth-only view the occlusion test reads, of the depth texture it was made for.
    depth_reader: Option<(wgpu::Texture, wgpu::TextureView)>,
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
        let desc = RendererDesc {
            target: format,
            ..RendererDesc::for_quality(&ctx.info, format.color, quality, FRAMES_IN_FLIGHT)
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
            renderer,
            slots: (0..FRAMES_IN_FLIGHT).map(|_| Slot::default()).collect(),
            finished,
            recorded: 0,
            target: *target,
            depth_reader: None,
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
        (self.drawn, self.previous) = (None, None);
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
        (self.drawn, self.previous) = (None, None);
        self.renderer.set_drawn_blades(on)?;
        Ok(())
    }

    /// sward's buffers the application's own draw of the Bezier blades reads, as wgpu buffers,
    /// and which frame slot's uniforms the last frame recorded wrote; `None` where there is no
    /// field or the frames do not list them ([`GrassRenderer::set_drawn_blades`]). The buffers
    /// stay the same until the next upload.
    pub fn drawn_blades(&mut self) -> Result<Option<(&DrawnBlades, usize)>, BridgeError> {
        let slot = (self.recorded as usize + FRAMES_IN_FLIGHT - 1) % FRAMES_IN_FLIGHT;
        if self.drawn.is_none() {
            let Some(buffers) = self.renderer.drawn_blade_buffers(0) else {
                return Ok(None);
            };
            let uniforms: Vec<&Buffer> = (0..FRAMES_IN_FLIGHT)
                .filter_map(|k| self.renderer.drawn_blade_buffers(k).map(|b| b.uniforms))
                .collect();
            let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST;
            let size = buffers.blades.size;
            let previous = Buffer::new(&self.ctx, "the blades last drawn", size, usage, MemoryLocation::GpuOnly)?;
            // As they are now, until a frame copies them.
            copy_now(buffers.blades, &previous)?;
            self.drawn = Some(DrawnBlades::wrap(&self.device, buffers, (&uniforms, &previous))?);
            self.previous = Some(previous);
        }
        Ok(self.drawn.as_ref().map(|drawn| (drawn, slot)))
    }

    /// The target this renderer draws into.
    pub fn target(&self) -> &TargetDesc {
        &self.target
    }

    /// Time sward's passes with GPU timestamps ([`GrassRenderer::pass_times`]).
    pub fn set_timing(&mut self, on: bool) {
        self.timing = on;
    }

    /// sward's passes in the newest frame the GPU has finished, where timing is on.
    pub fn pass_times(&self) -> Option<&PassTimes> {
        self.last_times.as_ref()
    }

    /// Host time the last frame recorded spent waiting for the GPU to finish the frame
    /// [`FRAMES_IN_FLIGHT`] before it (zero where the GPU keeps up): the part of
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
        self.record(&mut grass, desc, target)?;
        Ok([attachments.finish(), grass.finish()])
    }

    /// The frame `desc` describes without its draw, as one command buffer: the Bezier blades
    /// simulated, culled and listed, for the application to draw itself in its own passes
    /// ([`GrassRenderer::drawn_blades`]) after submitting it. `desc.viewport` is the size of
    /// the view the blades are culled for.
    pub fn encode_compute(&mut self, desc: &FrameDesc) -> Result<wgpu::CommandBuffer, BridgeError> {
        let mut encoder = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("sward: the grass's compute passes"),
        });
        let slot = self.recorded as usize % FRAMES_IN_FLIGHT;
        self.free_slot(slot)?;
        let frame = self.recorded;
        let passes = Passes {
            draw: false,
            ..Passes::ALL
        };
        let recorded = unsafe {
            encoder.as_hal_mut::<Vulkan, _, _>(|hal| {
                let cmd = hal.map(|hal| hal.raw_handle())?;
                self.keep_previous_blades(cmd);
                self.record_region(cmd, (slot, frame), desc, (passes, None));
                Some(())
            })
        };
        recorded.ok_or(BridgeError::NotVulkan(wgpu::Backend::Noop))?;
        self.slots[slot].frame = Some(frame);
        self.recorded = self.recorded.wrapping_add(1);
        Ok(encoder.finish())
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
        let extent = target.checked_extent(&self.target)?;
        if desc.viewport != [extent.width, extent.height] {
            return Err(BridgeError::Target(format!(
                "the frame's viewport is {}×{} but its target {}×{}: describe the frame at the target's size",
                desc.viewport[0], desc.viewport[1], extent.width, extent.height
            )));
        }
        let slot = self.recorded as usize % FRAMES_IN_FLIGHT;
        self.free_slot(slot)?;
        let reader = target.occlusion.then(|| self.depth_reader(target.depth));
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
                self.record_region(cmd, (slot, frame), desc, (Passes::ALL, Some(&views)));
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
        self.last_wait = std::time::Duration::ZERO;
        if let Some(frame) = self.slots[slot].frame {
            if !self.has_finished(frame) {
                // Everything submitted so far: if the frame is still not done, its command
                // buffer was dropped unsubmitted, and nothing will ever run it.
                let start = std::time::Instant::now();
                self.wait_idle();
                self.last_wait = start.elapsed();
            }
            if self.has_finished(frame) {
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

    /// A depth-only view of `depth`'s texture for the occlusion test to read, kept while the
    /// texture is the same.
    fn depth_reader(&mut self, depth: &wgpu::TextureView) -> wgpu::TextureView {
        let texture = depth.texture();
        if let Some((kept, view)) = &self.depth_reader {
            if kept == texture {
                return view.clone();
            }
        }
        let view = texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some("sward: the application's depth, read"),
            aspect: wgpu::TextureAspect::DepthOnly,
            ..Default::default()
        });
        self.depth_reader = Some((texture.clone(), view.clone()));
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
