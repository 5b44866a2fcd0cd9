//! The application's target as sward sees it: the formats a renderer is made for
//! ([`TargetDesc`]) and one frame's colour, resolve and depth views ([`FrameTarget`]), checked
//! against each other and turned into sward's raw views.

use ash::vk;
use sward_gpu::{DepthDirection, TargetFormat};
use wgpu::hal::api::Vulkan;

use crate::BridgeError;

/// Colour formats sward draws into: 8-bit sRGB (sward shades in linear light and the format
/// encodes) and floating point (HDR: linear values for the application's tonemapper).
const COLOR_FORMATS: [wgpu::TextureFormat; 5] = [
    wgpu::TextureFormat::Rgba8UnormSrgb,
    wgpu::TextureFormat::Bgra8UnormSrgb,
    wgpu::TextureFormat::Rgba16Float,
    wgpu::TextureFormat::Rg11b10Ufloat,
    wgpu::TextureFormat::Rgba32Float,
];

/// What a [`crate::GrassRenderer`] draws into: the formats, samples and depth direction of the
/// application's colour and depth attachments.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TargetDesc {
    /// The colour attachment's format (8-bit sRGB or floating point).
    pub color: wgpu::TextureFormat,
    /// The depth attachment's format (any with depth; a stencil part is left alone).
    pub depth: wgpu::TextureFormat,
    /// Samples per pixel of both attachments (1, 2, 4 or 8).
    pub samples: u32,
    /// Which way the application's depth runs: forward (0 near, `Less`) or reverse Z (1 near,
    /// `Greater`, as Bevy's cameras).
    pub depth_direction: DepthDirection,
}

impl TargetDesc {
    /// Single-sample attachments of these formats, forward depth.
    pub fn new(color: wgpu::TextureFormat, depth: wgpu::TextureFormat) -> TargetDesc {
        TargetDesc {
            color,
            depth,
            samples: 1,
            depth_direction: DepthDirection::Forward,
        }
    }

    /// sward's target format for these attachments on `adapter`'s device, or a sentence
    /// saying what is not allowed.
    pub(crate) fn sward_format(&self, adapter: &wgpu::hal::vulkan::Adapter) -> Result<TargetFormat, BridgeError> {
        if !COLOR_FORMATS.contains(&self.color) {
            return Err(BridgeError::Target(format!(
                "sward draws into a colour attachment of format {:?}, {:?}, {:?}, {:?} or {:?}, not {:?}",
                COLOR_FORMATS[0], COLOR_FORMATS[1], COLOR_FORMATS[2], COLOR_FORMATS[3], COLOR_FORMATS[4], self.color
            )));
        }
        if !self.depth.has_depth_aspect() {
            return Err(BridgeError::Target(format!(
                "the depth attachment's format {:?} has no depth; sward needs one with depth (Depth32Float, say)",
                self.depth
            )));
        }
        if ![1, 2, 4, 8].contains(&self.samples) {
            return Err(BridgeError::Target(format!(
                "{} samples per pixel: sward draws with 1, 2, 4 or 8",
                self.samples
            )));
        }
        Ok(TargetFormat {
            color: adapter.texture_format_as_raw(self.color),
            depth: adapter.texture_format_as_raw(self.depth),
            samples: vk::SampleCountFlags::from_raw(self.samples),
            depth_direction: self.depth_direction,
        })
    }
}

/// One frame's attachments: views of the application's textures, drawn by wgpu before (sward
/// loads them and draws over them).
#[derive(Clone, Copy, Debug)]
pub struct FrameTarget<'a> {
    /// The colour attachment (multisampled where the renderer's [`TargetDesc::samples`] is).
    pub color: &'a wgpu::TextureView,
    /// Where the multisampled colour resolves to at the end of sward's drawing (single-sample,
    /// the same format), if sward is the last to draw into it; `None` leaves the resolve to the
    /// application.
    pub resolve: Option<&'a wgpu::TextureView>,
    /// The depth attachment.
    pub depth: &'a wgpu::TextureView,
    /// Cull the grass the application's depth hides before it is simulated and drawn (the depth
    /// texture then needs `TEXTURE_BINDING` usage beside `RENDER_ATTACHMENT`).
    pub occlusion: bool,
}

impl<'a> FrameTarget<'a> {
    /// Colour and depth, no resolve, the application's depth culling the grass it hides where
    /// the texture can be read (`TEXTURE_BINDING`).
    pub fn new(color: &'a wgpu::TextureView, depth: &'a wgpu::TextureView) -> FrameTarget<'a> {
        let occlusion = depth.texture().usage().contains(wgpu::TextureUsages::TEXTURE_BINDING);
        FrameTarget {
            color,
            resolve: None,
            depth,
            occlusion,
        }
    }

    /// The same, resolving the multisampled colour into `resolve` at the end.
    pub fn resolving_into(self, resolve: &'a wgpu::TextureView) -> FrameTarget<'a> {
        FrameTarget {
            resolve: Some(resolve),
            ..self
        }
    }

    /// The attachments' size, after checking every texture against `desc`.
    pub(crate) fn checked_extent(&self, desc: &TargetDesc) -> Result<vk::Extent2D, BridgeError> {
        let color = self.color.texture();
        let depth = self.depth.texture();
        expect(color, "colour", desc.color, desc.samples)?;
        expect(depth, "depth", desc.depth, desc.samples)?;
        if let Some(resolve) = self.resolve {
            expect(resolve.texture(), "resolve", desc.color, 1)?;
            same_size(color, resolve.texture(), "resolve")?;
        }
        same_size(color, depth, "depth")?;
        let usage = depth.usage();
        if self.occlusion && !usage.contains(wgpu::TextureUsages::TEXTURE_BINDING) {
            return Err(BridgeError::Target(
                "occlusion culling reads the depth texture, which was made without TEXTURE_BINDING usage; add it or set FrameTarget::occlusion to false".into(),
            ));
        }
        Ok(vk::Extent2D {
            width: color.width(),
            height: color.height(),
        })
    }
}

/// Fail unless `texture` has `format` and `samples`, naming the attachment.
fn expect(texture: &wgpu::Texture, which: &str, format: wgpu::TextureFormat, samples: u32) -> Result<(), BridgeError> {
    if texture.format() != format || texture.sample_count() != samples {
        return Err(BridgeError::Target(format!(
            "the {which} texture is {:?} with {} sample(s); this renderer was made for {format:?} with {samples}",
            texture.format(),
            texture.sample_count()
        )));
    }
    if !texture.usage().contains(wgpu::TextureUsages::RENDER_ATTACHMENT) {
        return Err(BridgeError::Target(format!(
            "the {which} texture was made without RENDER_ATTACHMENT usage, which sward draws with"
        )));
    }
    Ok(())
}

/// Fail unless `other` is as large as `color`.
fn same_size(color: &wgpu::Texture, other: &wgpu::Texture, which: &str) -> Result<(), BridgeError> {
    if color.size() != other.size() {
        return Err(BridgeError::Target(format!(
            "the {which} texture is {:?}, the colour texture {:?}: they must be the same size",
            other.size(),
            color.size()
        )));
    }
    Ok(())
}

/// The raw Vulkan view behind a wgpu view.
pub(crate) fn raw_view(view: &wgpu::TextureView) -> vk::ImageView {
    let hal = unsafe { view.as_hal::<Vulkan>() }.expect("a view of a texture on the Vulkan device");
    unsafe { hal.raw_handle() }
}

/// The raw Vulkan image behind a wgpu texture.
pub(crate) fn raw_image(texture: &wgpu::Texture) -> vk::Image {
    let hal = unsafe { texture.as_hal::<Vulkan>() }.expect("a texture on the Vulkan device");
    unsafe { hal.raw_handle() }
}
