//! The portable renderer's WGSL (`shaders/*.wgsl`): its modules, and each pipeline's source as
//! the device gets it — its modules in order, one text (WGSL has no includes).

/// The frame's uniforms (sward-core's `FrameUniforms`, member for member).
pub const FRAME: &str = include_str!("../../../../shaders/frame.wgsl");
/// A Bezier blade: its layout and frame, the hash.
pub const BLADE: &str = include_str!("../../../../shaders/blade.wgsl");
/// The physical model of one blade.
pub const PHYSICS: &str = include_str!("../../../../shaders/physics.wgsl");
/// The simulation pass.
pub const SIMULATE: &str = include_str!("../../../../shaders/simulate.wgsl");
/// Culling and compaction into distance buckets.
pub const CULL: &str = include_str!("../../../../shaders/cull.wgsl");

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

/// The simulation.
pub const SIMULATE_SOURCE: PipelineSource = PipelineSource {
    name: "simulate",
    entry: "simulate",
    modules: &[FRAME, BLADE, PHYSICS, SIMULATE],
};

/// The cull's three passes: count each distance bucket's blades, lay the buckets out, place
/// each blade in its bucket's list.
pub const CULL_SOURCES: [PipelineSource; 3] = [
    PipelineSource {
        name: "count_buckets",
        entry: "count_buckets",
        modules: &[FRAME, BLADE, CULL],
    },
    PipelineSource {
        name: "lay_out_buckets",
        entry: "lay_out_buckets",
        modules: &[FRAME, BLADE, CULL],
    },
    PipelineSource {
        name: "place_blades",
        entry: "place_blades",
        modules: &[FRAME, BLADE, CULL],
    },
];

/// Every portable pipeline's shader.
pub const PIPELINES: &[PipelineSource] = &[SIMULATE_SOURCE, CULL_SOURCES[0], CULL_SOURCES[1], CULL_SOURCES[2]];
