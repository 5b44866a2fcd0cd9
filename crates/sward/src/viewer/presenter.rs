//! The window's GPU side: surface and swapchain, two frames in flight (fence, acquire semaphore,
//! command buffer, timestamp queries, visible-count read-back, egui textures to free), the grass
//! renderer drawing into the swapchain image through the same `record_frame` as `sward render`,
//! the egui pass on top, and screenshots.

use std::path::Path;
use std::sync::Arc;

use anyhow::Context as _;
use ash::vk;
use egui_ash_renderer::{DynamicRendering, Options, RenderMode};
use gpu_allocator::MemoryLocation;
use sward_core::quality::QualityPreset;
use sward_core::FrameDesc;
use sward_gpu::barrier::{self, Access};
use sward_gpu::buffer::Buffer;
use sward_gpu::error::vk_check;
use sward_gpu::swapchain::{Surface, SwapStatus, Swapchain};
use sward_gpu::timer::{GpuTimer, PassTimes, Stamp};
use sward_gpu::{Context, DrawRoute, Passes, Renderer, RendererDesc};

pub const FRAMES_IN_FLIGHT: usize = 2;

/// One frame in flight.
struct PerFrame {
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    acquired: vk::Semaphore,
    timer: GpuTimer,
    visible_count: Buffer,
    /// egui textures freed by the UI of the frame that last used this slot.
    textures_to_free: Vec<egui::TextureId>,
    submitted: bool,
}

/// What one frame's UI hands to the GPU.
pub struct UiFrame {
    pub primitives: Vec<egui::ClippedPrimitive>,
    pub textures_delta: egui::TexturesDelta,
    pub pixels_per_point: f32,
}

/// Read-backs of the frame slot about to be reused (its fence has signalled).
#[derive(Default)]
pub struct Readback {
    pub gpu: Option<PassTimes>,
    pub visible: Option<u32>,
}

pub struct Presenter {
    // Fields drop in this order: everything holding GPU objects before the context.
    egui: egui_ash_renderer::Renderer<egui_ash_renderer::allocator::GpuAllocator>,
    frames: Vec<PerFrame>,
    pub renderer: Renderer,
    pub swapchain: Swapchain,
    surface: Surface,
    command_pool: vk::CommandPool,
    present_mode: vk::PresentModeKHR,
    /// The renderer's shadow map side, as its quality preset set it.
    shadow_map_size: u32,
    /// The preset drawn, and the samples per pixel the renderer's pipelines were built for.
    quality: QualityPreset,
    renderer_samples: vk::SampleCountFlags,
    /// The most samples per pixel that fit the GPU memory at the window's size, where the
    /// preset's did not (until the window is resized).
    samples_cap: Option<vk::SampleCountFlags>,
    frame: usize,
    screenshot_buffer: Option<Buffer>,
    pub ctx: Arc<Context>,
}

impl Presenter {
    /// A presenter drawing the grass as `quality` asks (samples and shadow map; `set_quality`
    /// changes them), the Bezier blades by `route` until a frame asks for another.
    pub fn new(
        ctx: &Arc<Context>,
        surface: Surface,
        size: [u32; 2],
        present_mode: vk::PresentModeKHR,
        quality: QualityPreset,
        route: DrawRoute,
    ) -> anyhow::Result<Presenter> {
        let samples = ctx.info.samples_up_to(quality.msaa_samples());
        let swapchain = Swapchain::new(ctx, &surface, size, present_mode, samples, None)?;
        let desc = RendererDesc::for_quality(&ctx.info, swapchain.format.color, quality, FRAMES_IN_FLIGHT);
        let mut renderer = Renderer::new(ctx, &desc)?;
        renderer.set_route(route);
        let shadow_map_size = desc.shadow_map_size;
        let d = &ctx.device;
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(ctx.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        let command_pool = unsafe { d.create_command_pool(&pool_info, None) }?;
        let frames = (0..FRAMES_IN_FLIGHT)
            .map(|_| PerFrame::new(ctx, command_pool))
            .collect::<anyhow::Result<_>>()?;
        let mode = RenderMode::DynamicRendering(DynamicRendering {
            color_attachment_format: swapchain.format.color,
            depth_attachment_format: None,
            stencil_attachment_format: None,
        });
        let options = Options {
            in_flight_frames: FRAMES_IN_FLIGHT,
            srgb_framebuffer: true,
            ..Options::default()
        };
        let egui = egui_ash_renderer::Renderer::with_gpu_allocator(ctx.shared_allocator(), d.clone(), mode, options)
            .context("creating the UI renderer")?;
        Ok(Presenter {
            egui,
            frames,
            renderer,
            swapchain,
            surface,
            command_pool,
            present_mode,
            shadow_map_size,
            quality,
            renderer_samples: samples,
            samples_cap: None,
            frame: 0,
            screenshot_buffer: None,
            ctx: ctx.clone(),
        })
    }

    /// Samples per pixel of the window's colour and depth targets.
    pub fn samples(&self) -> u32 {
        self.swapchain.format.samples.as_raw()
    }

    /// Rebuild the swapchain for a window of `size` pixels with the preset's samples per pixel
    /// — or, where those targets do not fit the GPU memory at this size, with one sample per
    /// pixel, which the answer's note says. Where the samples change, the renderer is built
    /// again for them (`renderer_rebuilt`: the caller uploads the field and ground again).
    pub fn resize(&mut self, size: [u32; 2]) -> anyhow::Result<Resized> {
        let wanted = self.ctx.info.samples_up_to(self.quality.msaa_samples());
        self.samples_cap = None;
        let note = match self.rebuild_swapchain(size, wanted) {
            Ok(()) => None,
            Err(e) if wanted != vk::SampleCountFlags::TYPE_1 && out_of_memory(&e) => {
                self.rebuild_swapchain(size, vk::SampleCountFlags::TYPE_1)?;
                self.samples_cap = Some(vk::SampleCountFlags::TYPE_1);
                Some(format!(
                    "a {}×{} window at {}× MSAA does not fit the GPU memory ({e:#}), so it is drawn with one sample per pixel until it is resized",
                    size[0],
                    size[1],
                    wanted.as_raw()
                ))
            }
            Err(e) => return Err(e),
        };
        let renderer_rebuilt = self.match_renderer_to_swapchain()?;
        Ok(Resized { renderer_rebuilt, note })
    }

    /// Build the renderer again if its pipelines are for other samples than the swapchain's.
    fn match_renderer_to_swapchain(&mut self) -> anyhow::Result<bool> {
        if self.renderer_samples == self.swapchain.format.samples {
            return Ok(false);
        }
        let desc = self.renderer_desc(self.quality);
        self.renderer = Renderer::new(&self.ctx, &desc)?;
        self.renderer_samples = desc.target.samples;
        self.shadow_map_size = desc.shadow_map_size;
        Ok(true)
    }

    /// The renderer `quality` asks for, drawing into the swapchain as it is (each frame names
    /// its route).
    fn renderer_desc(&self, quality: QualityPreset) -> RendererDesc {
        let desc = RendererDesc::for_quality(&self.ctx.info, self.swapchain.format.color, quality, FRAMES_IN_FLIGHT);
        RendererDesc {
            target: self.swapchain.format,
            ..desc
        }
    }

    /// A new swapchain of `size` pixels with `samples` per pixel, once the GPU is idle.
    fn rebuild_swapchain(&mut self, size: [u32; 2], samples: vk::SampleCountFlags) -> anyhow::Result<()> {
        unsafe { self.ctx.device.device_wait_idle() }?;
        let old = Some(&self.swapchain);
        self.swapchain = Swapchain::new(&self.ctx, &self.surface, size, self.present_mode, samples, old)?;
        Ok(())
    }

    /// Wait until the next frame slot is free and read what its last frame left behind.
    pub fn begin_frame(&mut self) -> anyhow::Result<Readback> {
        let f = &mut self.frames[self.frame];
        let d = &self.ctx.device;
        unsafe { d.wait_for_fences(&[f.fence], true, u64::MAX) }.map_err(vk_check("waiting for a frame"))?;
        for id in f.textures_to_free.drain(..) {
            self.egui.free_texture(id)?;
        }
        if !f.submitted {
            return Ok(Readback::default());
        }
        let visible = f
            .visible_count
            .mapped()
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
        Ok(Readback {
            gpu: f.timer.read(),
            visible,
        })
    }

    /// Acquire an image, record the grass frame and the UI, submit and present. Returns false if
    /// the swapchain was out of date (it is rebuilt at `size`; the frame is skipped).
    pub fn draw(
        &mut self,
        desc: &FrameDesc,
        mut ui: UiFrame,
        screenshot: Option<&Path>,
        size: [u32; 2],
    ) -> anyhow::Result<bool> {
        for (id, deltas) in std::mem::take(&mut ui.textures_delta.set) {
            for delta in &deltas {
                self.egui.set_texture(self.ctx.queue, self.command_pool, id, delta)?;
            }
        }
        // Freed only once the frame that last used them has finished (see `begin_frame`).
        let freed = std::mem::take(&mut ui.textures_delta.free);
        let slot = self.frame;
        let (image, status) = self.swapchain.acquire(self.frames[slot].acquired)?;
        if image == u32::MAX {
            self.frames[slot].textures_to_free.extend(freed);
            self.resize(size)?;
            return Ok(false);
        }
        let cmd = self.frames[slot].cmd;
        self.record(cmd, slot, image, desc, &ui, screenshot.is_some())?;
        self.submit(slot, image)?;
        let f = &mut self.frames[slot];
        f.textures_to_free.extend(freed);
        f.submitted = true;
        if let Some(path) = screenshot {
            self.save_screenshot(slot, path)?;
        }
        self.frame = (self.frame + 1) % FRAMES_IN_FLIGHT;
        let presented = self.swapchain.present(image)?;
        if status == SwapStatus::OutOfDate || presented == SwapStatus::OutOfDate {
            self.resize(size)?;
        }
        Ok(true)
    }

    fn record(
        &mut self,
        cmd: vk::CommandBuffer,
        slot: usize,
        image: u32,
        desc: &FrameDesc,
        ui: &UiFrame,
        screenshot: bool,
    ) -> anyhow::Result<()> {
        let d = self.ctx.device.clone();
        unsafe {
            d.reset_command_buffer(cmd, vk::CommandBufferResetFlags::empty())?;
            d.begin_command_buffer(cmd, &vk::CommandBufferBeginInfo::default())?;
        }
        let f = &mut self.frames[slot];
        f.timer.begin(cmd);
        let swap_image = self.swapchain.images[image as usize];
        begin_attachments(&d, cmd, &self.swapchain, swap_image);
        let views = self.swapchain.views(image);
        self.renderer
            .record_frame(cmd, slot, desc, Passes::ALL, Some(&views), Some(&f.timer));
        self.renderer.record_copy_visible_count(cmd, &f.visible_count);
        self.record_ui(cmd, image, ui)?;
        let f = &self.frames[slot];
        f.timer.stamp(cmd, Stamp::Ui);
        let (layout, access) = (vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL, Access::COLOR_ATTACHMENT);
        if screenshot {
            let src = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
            let color = vk::ImageAspectFlags::COLOR;
            barrier::image(
                &d,
                cmd,
                swap_image,
                color,
                (layout, access),
                (src, Access::TRANSFER_READ),
            );
            self.record_screenshot_copy(cmd, swap_image)?;
            barrier::image(
                &d,
                cmd,
                swap_image,
                color,
                (src, Access::TRANSFER_READ),
                (vk::ImageLayout::PRESENT_SRC_KHR, Access::PRESENT),
            );
        } else {
            let present = vk::ImageLayout::PRESENT_SRC_KHR;
            barrier::image(
                &d,
                cmd,
                swap_image,
                vk::ImageAspectFlags::COLOR,
                (layout, access),
                (present, Access::PRESENT),
            );
        }
        unsafe { d.end_command_buffer(cmd) }?;
        Ok(())
    }

    fn record_ui(&mut self, cmd: vk::CommandBuffer, image: u32, ui: &UiFrame) -> anyhow::Result<()> {
        let d = &self.ctx.device;
        let color = [vk::RenderingAttachmentInfo::default()
            .image_view(self.swapchain.views[image as usize])
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::LOAD)
            .store_op(vk::AttachmentStoreOp::STORE)];
        let extent = self.swapchain.extent;
        sward_gpu::target::begin_rendering(d, cmd, &color, None, extent);
        self.egui.cmd_draw(cmd, extent, ui.pixels_per_point, &ui.primitives)?;
        unsafe { d.cmd_end_rendering(cmd) };
        Ok(())
    }

    fn submit(&self, slot: usize, image: u32) -> anyhow::Result<()> {
        let f = &self.frames[slot];
        let d = &self.ctx.device;
        let waits = [f.acquired];
        let stages = [vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT];
        let signals = [self.swapchain.render_finished[image as usize]];
        let cmds = [f.cmd];
        let submit = vk::SubmitInfo::default()
            .wait_semaphores(&waits)
            .wait_dst_stage_mask(&stages)
            .command_buffers(&cmds)
            .signal_semaphores(&signals);
        unsafe {
            d.reset_fences(&[f.fence])?;
            self.ctx
                .submit(&[submit], f.fence)
                .map_err(vk_check("submitting a frame"))?;
        }
        Ok(())
    }

    fn record_screenshot_copy(&mut self, cmd: vk::CommandBuffer, image: vk::Image) -> anyhow::Result<()> {
        let extent = self.swapchain.extent;
        let bytes = 4 * extent.width as u64 * extent.height as u64;
        let buffer = Buffer::new(
            &self.ctx,
            "screenshot",
            bytes,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        let region = vk::BufferImageCopy {
            image_subresource: vk::ImageSubresourceLayers {
                aspect_mask: vk::ImageAspectFlags::COLOR,
                mip_level: 0,
                base_array_layer: 0,
                layer_count: 1,
            },
            image_extent: vk::Extent3D {
                width: extent.width,
                height: extent.height,
                depth: 1,
            },
            ..Default::default()
        };
        let d = &self.ctx.device;
        unsafe { d.cmd_copy_image_to_buffer(cmd, image, vk::ImageLayout::TRANSFER_SRC_OPTIMAL, buffer.raw, &[region]) };
        barrier::memory(d, cmd, Access::TRANSFER_WRITE, Access::HOST_READ);
        self.screenshot_buffer = Some(buffer);
        Ok(())
    }

    /// Wait for the frame in `slot` and write its screenshot.
    fn save_screenshot(&mut self, slot: usize, path: &Path) -> anyhow::Result<()> {
        unsafe {
            self.ctx
                .device
                .wait_for_fences(&[self.frames[slot].fence], true, u64::MAX)
        }
        .map_err(vk_check("waiting for a screenshot"))?;
        let buffer = self.screenshot_buffer.take().context("no screenshot was recorded")?;
        let extent = self.swapchain.extent;
        let mut pixels = buffer.mapped().context("screenshot memory is host visible")?.to_vec();
        if self.swapchain.format.color == vk::Format::B8G8R8A8_SRGB
            || self.swapchain.format.color == vk::Format::B8G8R8A8_UNORM
        {
            pixels.as_chunks_mut::<4>().0.iter_mut().for_each(|p| p.swap(0, 2));
        }
        pixels.as_chunks_mut::<4>().0.iter_mut().for_each(|p| p[3] = 255);
        let image = image::RgbaImage::from_raw(extent.width, extent.height, pixels).context("screenshot size")?;
        image
            .save(path)
            .with_context(|| format!("cannot write screenshot {}", path.display()))?;
        log::info!("screenshot written to {}", path.display());
        Ok(())
    }

    /// Render as `quality` asks from the next frame on: a new swapchain with its samples per
    /// pixel and a new renderer with its shadow map, the route kept. The caller uploads the field
    /// and ground again (the new renderer starts empty). Nothing happens if samples and shadow
    /// map stay as they are (the preset's blade segments reach the shaders by the uniforms).
    pub fn set_quality(&mut self, quality: QualityPreset) -> anyhow::Result<bool> {
        self.quality = quality;
        let mut samples = self.ctx.info.samples_up_to(quality.msaa_samples());
        if let Some(cap) = self.samples_cap {
            samples = samples.min(cap);
        }
        let shadow_map_size = self.renderer_desc(quality).shadow_map_size;
        if samples == self.swapchain.format.samples && shadow_map_size == self.shadow_map_size {
            return Ok(false);
        }
        let size = [self.swapchain.extent.width, self.swapchain.extent.height];
        self.rebuild_swapchain(size, samples)?;
        let desc = self.renderer_desc(quality);
        self.renderer = Renderer::new(&self.ctx, &desc)?;
        self.renderer_samples = desc.target.samples;
        self.shadow_map_size = desc.shadow_map_size;
        Ok(true)
    }

    /// Replace the grass pipelines (shader hot reload).
    pub fn reload_shaders(&mut self, shaders: &sward_gpu::shaders::ShaderSet) -> anyhow::Result<()> {
        self.renderer.use_shaders(shaders)?;
        Ok(())
    }
}

impl Drop for Presenter {
    fn drop(&mut self) {
        let d = &self.ctx.device;
        unsafe {
            let _ = d.device_wait_idle();
            for f in &self.frames {
                d.destroy_fence(f.fence, None);
                d.destroy_semaphore(f.acquired, None);
            }
            d.destroy_command_pool(self.command_pool, None);
        }
    }
}

impl PerFrame {
    fn new(ctx: &Arc<Context>, pool: vk::CommandPool) -> anyhow::Result<PerFrame> {
        let d = &ctx.device;
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .command_buffer_count(1);
        let cmd = unsafe { d.allocate_command_buffers(&alloc) }?[0];
        let fence = unsafe {
            d.create_fence(
                &vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED),
                None,
            )
        }?;
        let acquired = unsafe { d.create_semaphore(&vk::SemaphoreCreateInfo::default(), None) }?;
        let visible_count = Buffer::new(
            ctx,
            "visible and simulated counts read-back",
            8,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        Ok(PerFrame {
            cmd,
            fence,
            acquired,
            timer: GpuTimer::new(ctx)?,
            visible_count,
            textures_to_free: Vec::new(),
            submitted: false,
        })
    }
}

/// Swapchain image, multisampled colour and depth into attachment layouts. The source stage is
/// colour output, the stage the acquire semaphore is waited at, so the transition follows it.
fn begin_attachments(d: &ash::Device, cmd: vk::CommandBuffer, swapchain: &Swapchain, image: vk::Image) {
    let undefined = vk::ImageLayout::UNDEFINED;
    let color_layout = vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL;
    let color = vk::ImageAspectFlags::COLOR;
    for target in [image, swapchain.color.raw] {
        barrier::image(
            d,
            cmd,
            target,
            color,
            (undefined, Access::COLOR_ATTACHMENT),
            (color_layout, Access::COLOR_ATTACHMENT),
        );
    }
    let depth_layout = vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL;
    barrier::image(
        d,
        cmd,
        swapchain.depth.raw,
        vk::ImageAspectFlags::DEPTH,
        (undefined, Access::DEPTH_ATTACHMENT),
        (depth_layout, Access::DEPTH_ATTACHMENT),
    );
}

/// What a resize did beyond the new swapchain.
pub struct Resized {
    /// The renderer was built again (other samples per pixel): upload the field and ground.
    pub renderer_rebuilt: bool,
    /// Why the window is drawn with fewer samples than its preset's, where it is.
    pub note: Option<String>,
}

/// Whether `e` is the GPU running out of memory.
fn out_of_memory(e: &anyhow::Error) -> bool {
    matches!(
        e.downcast_ref::<sward_gpu::GpuError>(),
        Some(sward_gpu::GpuError::OutOfMemory { .. } | sward_gpu::GpuError::ImageOutOfMemory { .. })
    )
}
