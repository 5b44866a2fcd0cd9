//! The portable renderer's WGSL (`shaders/wgsl/`): its modules, and each pipeline's source as
//! the device gets it — its modules in order, one text (WGSL has no includes).

/// The frame's uniforms (sward-core's `FrameUniforms`, member for member).
pub const FRAME: &str = include_str!("../../../../shaders/wgsl/frame.wgsl");
/// The physical model of one blade.
pub const PHYSICS: &str = include_str!("../../../../shaders/wgsl/physics.wgsl");
/// The simulation pass.
pub const SIMULATE: &str = include_str!("../../../../shaders/wgsl/simulate.wgsl");

/// A portable pipeline's shader: its name, the entry point, and its modules in order.
#[derive(Clone, Copy, Debug)]
pub struct PipelineSource {
    /// The pipeline's name (`simulate`).
    pub name: &'static str,
    /// The entry point in its source.
    pub entry: &'static str,
    /// Its modules, in the order they are joined.
    pub modules: &'static [&'static str],
}

impl PipelineSource {
    /// The whole WGSL the device compiles for this pipeline.
    pub fn text(&self) -> String {
        self.modules.join("\n")
    }
}

/// The simulation's shader.
pub const SIMULATE_SOURCE: PipelineSource = PipelineSource {
    name: "simulate",
    entry: "simulate",
    modules: &[FRAME, PHYSICS, SIMULATE],
};

/// Every portable pipeline's shader.
pub const PIPELINES: &[PipelineSource] = &[SIMULATE_SOURCE];
