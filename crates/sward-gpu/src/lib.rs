//! sward-gpu: the Vulkan back end of sward.
//!
//! It owns the context (instance, device choice, validation messages), memory, the SPIR-V
//! compiled from `shaders/` at build time, the passes of the grass frame (occluders, simulate,
//! cull, draw, the sun's shadow map) and render targets. It knows nothing of windows, egui or the
//! command line: the renderer records into a command buffer and a target that its caller provides.
//!
//! A frame of a scene, headless (what `sward render` does):
//!
//! ```
//! use sward_core::Scene;
//! use sward_gpu::{Context, ContextDesc, Headless};
//!
//! let mut scene = Scene::default();
//! scene.field.blades = 2000;
//! let ctx = Context::new(&ContextDesc::default())?;
//! let mut headless = Headless::new(&ctx, 160, 90, None)?;
//! let field = scene.grow_field()?;
//! headless.renderer.upload(&field)?;
//! headless.renderer.upload_ground(field.ground.as_ref())?;
//! // 30 fixed steps of physics, then one frame, read back as RGBA8.
//! let rgba = headless.render_scene(&scene, field.size, 30)?;
//! assert_eq!(rgba.len(), 160 * 90 * 4);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! `cargo run -p sward-gpu --example scene` loads a scene file, changes it from code and writes
//! a still.
//!
//! # A frame, from its description to the passes
//!
//! - **Where the description comes from.** Whoever drives sward builds a
//!   [`sward_core::FrameDesc`] each frame — the technique, the camera, the clock, the winds and
//!   colliders where they are now, each subsystem's settings, the route and the quality —
//!   usually [`FrameDesc::of_scene`](sward_core::FrameDesc::of_scene) from the scene file and
//!   then changed in code: [`Headless`] for `sward render`, `bench` and `soak`, the viewer's
//!   frame loop, an application embedding sward (the `embed` example).
//! - **Where it is packed.** [`Renderer::record_frame`] plans the frame against the renderer's
//!   own state (`prepare_frame` in `renderer.rs`: the route resolved, where the generated
//!   grass's lists sit, which distance buckets are splatted, the splat cells, the tiles — a
//!   [`sward_core::gpu::FramePlan`]) and packs the two once
//!   ([`sward_core::gpu::FrameUniforms::pack`]) into the slot's uniform buffer, write-only, each
//!   block at its place (`sward_core::declared::write_frame`).
//!   Lists and counts the GPU decides stay in GPU buffers.
//! - **What may be replayed.** The parts of the description and plan that shape the commands
//!   (`recordings.rs` `FrameShape`: technique, quality, route, counts, target size, which
//!   passes run) are the key of the kept recordings; the passes record from that shape alone,
//!   never from the packed block, so the camera, the time, the wind and the colliders' places
//!   change only the uniforms.
//! - **Which pass reads what.** On the GPU each pass reads the frame's blocks it names
//!   (sward-core `declared::BLOCKS`: the camera's, the forces', the culls', the looks', the
//!   terrain's, the grids'; each a range of the slot's uniform buffer at its own binding); on
//!   the host, each module of [`passes`] records from the shape: the occluders the
//!   depth pyramid and shadow flags, the trample map its texels, the Bezier field the steps and
//!   the bucket hand-overs, the generated grass and billboards the technique, the rasterizer
//!   and depth pre-pass switches and the list layout, the ground and colliders the ground's
//!   shape and the collider counts.

#![warn(missing_docs)]

pub mod barrier;
pub mod buffer;
pub mod context;
pub mod error;
mod frame_pipelines;
mod frame_set;
pub mod glsl;
pub mod headless;
pub mod image;
pub mod memory;
pub mod passes;
pub mod pipelines;
pub mod probe;
mod recordings;
pub mod renderer;
pub mod shaders;
pub mod swapchain;
pub mod target;
pub mod timer;
pub mod wgsl;

pub use context::{
    create_device_for, list_devices, Context, ContextDesc, DeviceCandidate, DeviceInfo, ExistingDevice, Validation,
    Withheld,
};
pub use error::{GpuError, Result};
pub use frame_pipelines::Pipelines;
/// The memory allocator sward uses, for an application that shares its own
/// ([`ExistingDevice::allocator`]).
pub use gpu_allocator;
pub use headless::Headless;
pub use passes::routes::DrawRoute;
pub use pipelines::{DepthDirection, TargetFormat};
pub use renderer::{DrawnBladeBuffers, Passes, Renderer, RendererDesc};
pub use target::{CallerDepth, TargetViews};
