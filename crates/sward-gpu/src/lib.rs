//! sward-gpu: the Vulkan back end of sward.
//!
//! It owns the context (instance, device choice, validation messages), memory, the SPIR-V
//! compiled from `shaders/` at build time, the passes of the grass frame (occluders, simulate,
//! cull, draw, the sun's shadow map) and render targets. It knows nothing of windows, egui or the
//! command line: the renderer records into a command buffer and a target that its caller provides.

pub mod barrier;
pub mod buffer;
pub mod context;
pub mod error;
mod field;
mod frame_set;
pub mod glsl;
mod grass_texture;
mod ground;
pub mod headless;
pub mod image;
mod instanced;
pub mod memory;
pub mod occluders;
pub mod pipelines;
pub mod probe;
pub mod renderer;
pub mod routes;
pub mod shaders;
mod splat;
pub mod swapchain;
pub mod target;
pub mod timer;

pub use context::{Context, ContextDesc, DeviceInfo, Validation, Withheld};
pub use error::{GpuError, Result};
pub use headless::Headless;
pub use renderer::{Passes, Renderer, RendererDesc};
pub use routes::DrawRoute;
pub use target::TargetViews;
