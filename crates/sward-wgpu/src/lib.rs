//! sward's responsive grass in a wgpu application: on wgpu's Vulkan backend through sward's
//! Vulkan renderer (below), and on any backend through the [`portable`] renderer — wgpu's safe
//! API and WGSL alone — as it grows (so far: the simulation).
//!
//! - [`open`] opens a `wgpu::Device` on a Vulkan adapter with everything sward needs enabled
//!   beside what the application asks of wgpu — tessellation, synchronization2 and dynamic
//!   rendering included, which wgpu itself never enables — and makes sward's
//!   [`sward_gpu::Context`] on the very same `VkDevice` and queue. [`adopt`] takes such a device
//!   back from an application that kept it (or says why another device cannot carry sward);
//!   [`SwardDevice::routes`] tells which draw routes it allows.
//! - [`GrassRenderer`] is sward's renderer on that device: it records a whole grass frame —
//!   simulation, culling, drawing — into a `wgpu::CommandEncoder`, drawing into the
//!   application's colour and depth `wgpu::TextureView`s ([`FrameTarget`]: multisampled or not,
//!   8-bit sRGB or floating-point HDR, forward or reverse Z), depth-tested against what the
//!   application drew and, with [`FrameTarget::occlusion`], culled where the application's
//!   depth hides it.
//! - Or sward only simulates and culls ([`GrassRenderer::encode_compute`]) and the application
//!   draws the listed Bezier blades itself, in its own passes, from sward's buffers as wgpu
//!   buffers ([`GrassRenderer::drawn_blades`], [`DrawnBlades`]).
//! - [`sward_projection`] turns a wgpu camera's projection into the one sward culls with.
//!
//! ```no_run
//! # fn frame(adapter: &wgpu::Adapter, color: &wgpu::TextureView, depth: &wgpu::TextureView)
//! #     -> Result<(), Box<dyn std::error::Error>> {
//! use sward_core::{FrameDesc, Scene};
//! use sward_wgpu::{FrameTarget, GrassRenderer, TargetDesc};
//!
//! let sward = sward_wgpu::open(adapter, &wgpu::DeviceDescriptor::default(), &Default::default())?;
//! let scene = Scene::default();
//! let target = TargetDesc::new(wgpu::TextureFormat::Rgba8UnormSrgb, wgpu::TextureFormat::Depth32Float);
//! let mut grass = GrassRenderer::new(&sward, &target, scene.quality.preset)?;
//! let field = scene.grow_field()?;
//! grass.upload(&field)?;
//! // Each frame, after the application's own render pass into `color` and `depth`:
//! let desc = FrameDesc::of_scene(&scene, field.size, (0.0, 1), [1280, 720]);
//! let grass_frame = grass.encode(&desc, &FrameTarget::new(color, depth))?;
//! sward.queue.submit(grass_frame);
//! # Ok(()) }
//! ```
//!
//! # Safety contract
//!
//! sward and wgpu share the device and its one queue, and sward's commands are raw Vulkan
//! inside wgpu's command buffers, which wgpu does not track. The application must:
//! - drop every [`GrassRenderer`] and the [`SwardDevice`]'s context before the
//!   `wgpu::Device` ([`SwardDevice`] drops its fields in that order);
//! - not submit wgpu work on another thread while sward uploads or reads back (sward submits on
//!   the shared queue from the thread that calls [`GrassRenderer::upload`] and the read-backs);
//! - submit (or drop) every command buffer sward recorded before it asks sward for
//!   [`FRAMES_IN_FLIGHT`] more frames: sward reuses a frame's uniforms and recordings then, and
//!   waits for the GPU to finish the frame it recorded that many frames before;
//! - hand [`GrassRenderer::record`] an encoder it has not used through wgpu's own API (wgpu
//!   forbids mixing raw and wgpu commands in one encoder), with the target's colour and depth
//!   last used by wgpu as render attachments — or use [`GrassRenderer::encode`], which puts
//!   them there itself.
//!
//! sward leaves the colour in `COLOR_ATTACHMENT_OPTIMAL` and the depth in
//! `DEPTH_STENCIL_ATTACHMENT_OPTIMAL`, the layouts wgpu's tracker holds for attachments, its
//! writes made visible to every later command; it keeps the texture views it drew into alive
//! until the GPU has finished with them.

#![warn(missing_docs)]

mod device;
mod drawn;
mod grass;

mod target;

pub use device::{adopt, allowed_routes, open, SwardDevice};
pub use drawn::{DrawnBlades, DrawnView};
pub use grass::{GrassRenderer, FRAMES_IN_FLIGHT, VIEWS_PER_FRAME};
pub use sward_gpu::DepthDirection;
/// The portable renderer (wgpu's safe API and WGSL alone, any backend): the `sward-portable` crate.
pub use sward_portable as portable;
pub use sward_portable::sward_projection;
pub use target::{FrameTarget, TargetDesc};
/// The wgpu this crate is built on, for applications and tools that name its types.
pub use wgpu;

use ash::vk;

/// What went wrong bringing sward to a wgpu device or target: one sentence each.
#[derive(Debug, thiserror::Error)]
pub enum BridgeError {
    /// The adapter is not on wgpu's Vulkan backend.
    #[error("the wgpu adapter is on the {0:?} backend; sward runs on Vulkan only (create the wgpu instance with Backends::VULKAN)")]
    NotVulkan(wgpu::Backend),
    /// The Vulkan device could not be created with what sward and the application ask.
    #[error("the Vulkan device could not be opened with what sward needs beside the application's wgpu features: {0}")]
    DeviceCreation(vk::Result),
    /// wgpu refused the device.
    #[error("wgpu did not take the device: {0}")]
    Wgpu(String),
    /// The device was opened by wgpu alone.
    #[error("this wgpu device was not opened by sward_wgpu::open: wgpu alone never enables synchronization2, dynamic rendering or tessellation, which sward records with; open the device with sward_wgpu::open and hand that one to the application")]
    NotOpenedForSward,
    /// A texture of the frame's target does not fit what the renderer was made for.
    #[error("{0}")]
    Target(String),
    /// sward could not work on the device (a feature it needs is missing, memory ran out).
    #[error(transparent)]
    Sward(#[from] sward_gpu::GpuError),
}

/// The pages' Rust examples of sward in a Vulkan renderer and from wgpu, compiled as doc tests,
/// so they keep to the API.
#[cfg(doctest)]
#[doc = include_str!("../../../docs/embedding.md")]
struct EmbeddingExamples;
