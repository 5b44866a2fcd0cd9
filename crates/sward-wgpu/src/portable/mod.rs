//! The portable renderer: sward's grass through wgpu's safe API alone, in WGSL, on any backend
//! wgpu has with compute shaders and storage buffers (Vulkan, Metal, DX12, GL, a browser's
//! WebGPU), within WebGPU's default limits. Its passes read the frame's uniforms as sward-core
//! packs them for the Vulkan renderer (`FrameUniforms::pack`, from the frame's description and
//! plan), so both renderers run one frame from one set of decisions.
//!
//! So far it simulates the Bezier field (SPEC §3: recovery, gravity, wind, validation, sphere
//! collisions with a decaying strength) and culls it (orientation, frustum, distance, the
//! streamed field's hand-over) into visible lists by distance bucket with a draw command each,
//! held to sward-core's CPU reference by tests. The trample map, the occlusion test, streaming's
//! tiles and the draw are the Vulkan renderer's alone for now.

mod field;
mod renderer;
mod shaders;

pub use field::PortableField;
pub use renderer::{PortablePasses, PortableRenderer};
pub use shaders::{PipelineSource, PIPELINES};

/// What went wrong in the portable renderer: one sentence each.
#[derive(Debug, thiserror::Error)]
pub enum PortableError {
    /// The adapter cannot run compute shaders (WebGL2, GL ES below 3.1).
    #[error("this {0} adapter has no compute shaders, which sward's grass is simulated and culled with; it needs Vulkan, Metal, DX12, GL ES 3.1 or WebGPU")]
    NoCompute(String),
    /// The field does not fit the device's storage buffers.
    #[error("a field of {blades} blades needs {bytes} bytes of blade storage, more than this device binds at once ({limit} bytes); at most {fits} blades fit")]
    FieldTooLarge {
        /// Blades asked for.
        blades: usize,
        /// Bytes they need.
        bytes: u64,
        /// The device's largest storage binding.
        limit: u64,
        /// Blades that fit.
        fits: u64,
    },
    /// A pipeline's WGSL did not compile on this device.
    #[error("the portable {pipeline} shader does not compile on this device: {message}")]
    Shader {
        /// The pipeline.
        pipeline: &'static str,
        /// What the device said.
        message: String,
    },
    /// The GPU's buffers could not be read back.
    #[error("reading the field back from the GPU failed: {0}")]
    Readback(String),
}

/// The value of a future that is ready when first polled, as wgpu's error scopes and
/// buffer mappings are on native backends once the device was polled; None where it is not.
pub(crate) fn ready<F: std::future::Future>(future: F) -> Option<F::Output> {
    let mut future = std::pin::pin!(future);
    let mut context = std::task::Context::from_waker(std::task::Waker::noop());
    match future.as_mut().poll(&mut context) {
        std::task::Poll::Ready(value) => Some(value),
        std::task::Poll::Pending => None,
    }
}
