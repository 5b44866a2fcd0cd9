//! Presenting to a window: the surface, the swapchain with one render-finished semaphore per
//! image (images come back in any order), and the multisampled colour and depth attachments the
//! grass frame renders into before resolving into the swapchain image. Recreated on resize.

use std::sync::Arc;

use ash::{khr, vk};
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};

use crate::context::Context;
use crate::error::{vk_check, GpuError, Result};
use crate::image::Image;
use crate::pipelines::{TargetFormat, DEPTH_FORMAT};
use crate::target::TargetViews;

/// Preferred formats, sRGB first so shaders write linear colour.
const FORMATS: [vk::Format; 2] = [vk::Format::B8G8R8A8_SRGB, vk::Format::R8G8B8A8_SRGB];

/// A window's Vulkan surface, destroyed when dropped.
pub struct Surface {
    /// The Vulkan surface.
    pub raw: vk::SurfaceKHR,
    loader: khr::surface::Instance,
    ctx: Arc<Context>,
}

impl Surface {
    /// The surface of `window` on `display`.
    pub fn new(ctx: &Arc<Context>, display: RawDisplayHandle, window: RawWindowHandle) -> Result<Surface> {
        let raw = unsafe { ash_window::create_surface(&ctx.entry, &ctx.instance, display, window, None) }
            .map_err(vk_check("creating the window surface"))?;
        let loader = khr::surface::Instance::new(&ctx.entry, &ctx.instance);
        let supported =
            unsafe { loader.get_physical_device_surface_support(ctx.physical_device, ctx.queue_family, raw) }
                .map_err(vk_check("querying present support"))?;
        if !supported {
            unsafe { loader.destroy_surface(raw, None) };
            return Err(GpuError::NoSuitableDevice(format!(
                "{} cannot present to this window",
                ctx.info.name
            )));
        }
        Ok(Surface {
            raw,
            loader,
            ctx: ctx.clone(),
        })
    }

    /// The sRGB format the swapchain will use.
    pub fn format(&self) -> Result<vk::SurfaceFormatKHR> {
        let formats = unsafe {
            self.loader
                .get_physical_device_surface_formats(self.ctx.physical_device, self.raw)
        }
        .map_err(vk_check("querying surface formats"))?;
        FORMATS
            .iter()
            .find_map(|f| formats.iter().find(|s| s.format == *f).copied())
            .or_else(|| formats.first().copied())
            .ok_or(GpuError::NoSuitableDevice(
                "the window surface offers no formats".into(),
            ))
    }
}

impl Drop for Surface {
    fn drop(&mut self) {
        unsafe { self.loader.destroy_surface(self.raw, None) };
    }
}

/// What happened when acquiring or presenting.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SwapStatus {
    /// It worked.
    Ok,
    /// The swapchain no longer matches the window: recreate it.
    OutOfDate,
}

/// A swapchain with the multisampled colour and depth images frames are drawn into before they resolve into its images.
pub struct Swapchain {
    /// The Vulkan swapchain.
    pub raw: vk::SwapchainKHR,
    /// Its images.
    pub images: Vec<vk::Image>,
    /// A view of each image.
    pub views: Vec<vk::ImageView>,
    /// Signalled when rendering into image i is done; presenting image i waits on it.
    pub render_finished: Vec<vk::Semaphore>,
    /// Size of its images.
    pub extent: vk::Extent2D,
    /// Colour format and samples frames are drawn with.
    pub format: TargetFormat,
    /// The multisampled colour image (the swapchain image where one sample).
    pub color: Image,
    /// The depth image.
    pub depth: Image,
    loader: khr::swapchain::Device,
    ctx: Arc<Context>,
}

impl Swapchain {
    /// A swapchain of `size` pixels (clamped to what the surface allows), 4× MSAA attachments.
    pub fn new(
        ctx: &Arc<Context>,
        surface: &Surface,
        size: [u32; 2],
        present_mode: vk::PresentModeKHR,
        samples: vk::SampleCountFlags,
        old: Option<&Swapchain>,
    ) -> Result<Swapchain> {
        let caps = unsafe {
            surface
                .loader
                .get_physical_device_surface_capabilities(ctx.physical_device, surface.raw)
        }
        .map_err(vk_check("querying surface capabilities"))?;
        let extent = if caps.current_extent.width != u32::MAX {
            caps.current_extent
        } else {
            vk::Extent2D {
                width: size[0].clamp(caps.min_image_extent.width, caps.max_image_extent.width),
                height: size[1].clamp(caps.min_image_extent.height, caps.max_image_extent.height),
            }
        };
        let surface_format = surface.format()?;
        let format = TargetFormat {
            color: surface_format.format,
            depth: DEPTH_FORMAT,
            samples,
            depth_direction: crate::pipelines::DepthDirection::Forward,
        };
        // The attachments first: if they do not fit the GPU memory, the old swapchain is still
        // whole and the caller may try again with fewer samples.
        let color_usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSIENT_ATTACHMENT;
        let color = Image::new_2d(ctx, "window colour", extent, format.color, format.samples, color_usage)?;
        let depth_usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT;
        let depth = Image::new_2d(ctx, "window depth", extent, format.depth, format.samples, depth_usage)?;
        let present_mode = choose_present_mode(ctx, surface, present_mode)?;
        let mut image_count = caps.min_image_count + 1;
        if caps.max_image_count > 0 {
            image_count = image_count.min(caps.max_image_count);
        }
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(surface.raw)
            .min_image_count(image_count)
            .image_format(surface_format.format)
            .image_color_space(surface_format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(caps.current_transform)
            .composite_alpha(vk::CompositeAlphaFlagsKHR::OPAQUE)
            .present_mode(present_mode)
            .clipped(true)
            .old_swapchain(old.map_or(vk::SwapchainKHR::null(), |o| o.raw));
        let loader = khr::swapchain::Device::new(&ctx.instance, &ctx.device);
        let raw = unsafe { loader.create_swapchain(&info, None) }.map_err(vk_check("creating the swapchain"))?;
        let images = unsafe { loader.get_swapchain_images(raw) }.map_err(vk_check("getting swapchain images"))?;
        let views = images
            .iter()
            .map(|image| create_view(ctx, *image, surface_format.format))
            .collect::<Result<Vec<_>>>()?;
        let render_finished = images
            .iter()
            .map(|_| unsafe { ctx.device.create_semaphore(&vk::SemaphoreCreateInfo::default(), None) })
            .collect::<std::result::Result<Vec<_>, _>>()
            .map_err(vk_check("creating semaphores"))?;
        log::info!(
            "swapchain {}×{}, {} images, {:?}",
            extent.width,
            extent.height,
            images.len(),
            present_mode
        );
        Ok(Swapchain {
            raw,
            images,
            views,
            render_finished,
            extent,
            format,
            color,
            depth,
            loader,
            ctx: ctx.clone(),
        })
    }

    /// Acquire the next image; `signal` is signalled when it may be written.
    pub fn acquire(&self, signal: vk::Semaphore) -> Result<(u32, SwapStatus)> {
        match unsafe {
            self.loader
                .acquire_next_image(self.raw, u64::MAX, signal, vk::Fence::null())
        } {
            Ok((index, false)) => Ok((index, SwapStatus::Ok)),
            // Suboptimal still acquired the image and signals the semaphore: use it, recreate after.
            Ok((index, true)) => Ok((index, SwapStatus::OutOfDate)),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok((u32::MAX, SwapStatus::OutOfDate)),
            Err(e) => Err(vk_check("acquiring a swapchain image")(e)),
        }
    }

    /// Present image `index` once its render-finished semaphore is signalled.
    pub fn present(&self, index: u32) -> Result<SwapStatus> {
        let wait = [self.render_finished[index as usize]];
        let swapchains = [self.raw];
        let indices = [index];
        let info = vk::PresentInfoKHR::default()
            .wait_semaphores(&wait)
            .swapchains(&swapchains)
            .image_indices(&indices);
        match unsafe { self.loader.queue_present(self.ctx.queue, &info) } {
            Ok(false) => Ok(SwapStatus::Ok),
            Ok(true) | Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(SwapStatus::OutOfDate),
            Err(e) => Err(vk_check("presenting")(e)),
        }
    }

    /// Attachments for rendering into image `index`: the multisampled colour resolving into it,
    /// or with one sample per pixel the image itself.
    pub fn views(&self, index: u32) -> TargetViews {
        let image = self.views[index as usize];
        let (color, resolve) = if self.format.samples == vk::SampleCountFlags::TYPE_1 {
            (image, None)
        } else {
            (self.color.view, Some(image))
        };
        TargetViews {
            color,
            resolve,
            depth: self.depth.view,
            extent: self.extent,
            keep_depth: false,
            over_caller: false,
            occlusion: None,
        }
    }
}

impl Drop for Swapchain {
    fn drop(&mut self) {
        let d = &self.ctx.device;
        unsafe {
            let _ = d.device_wait_idle();
            for semaphore in &self.render_finished {
                d.destroy_semaphore(*semaphore, None);
            }
            for view in &self.views {
                d.destroy_image_view(*view, None);
            }
            self.loader.destroy_swapchain(self.raw, None);
        }
    }
}

/// `wanted` if the surface offers it, else FIFO (vsync), which every surface offers.
fn choose_present_mode(ctx: &Context, surface: &Surface, wanted: vk::PresentModeKHR) -> Result<vk::PresentModeKHR> {
    let modes = unsafe {
        surface
            .loader
            .get_physical_device_surface_present_modes(ctx.physical_device, surface.raw)
    }
    .map_err(vk_check("querying present modes"))?;
    if modes.contains(&wanted) {
        return Ok(wanted);
    }
    log::warn!("present mode {wanted:?} is not offered by this window; using FIFO (vsync)");
    Ok(vk::PresentModeKHR::FIFO)
}

fn create_view(ctx: &Context, image: vk::Image, format: vk::Format) -> Result<vk::ImageView> {
    let info = vk::ImageViewCreateInfo::default()
        .image(image)
        .view_type(vk::ImageViewType::TYPE_2D)
        .format(format)
        .subresource_range(crate::image::subresource_range(vk::ImageAspectFlags::COLOR));
    unsafe { ctx.device.create_image_view(&info, None) }.map_err(vk_check("creating a swapchain image view"))
}
