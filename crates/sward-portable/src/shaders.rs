//! The portable renderer's WGSL (`shaders/*.wgsl`): its modules, and each pipeline's source as
//! the device gets it — its modules in order, one text (WGSL has no includes).

/// The frame's uniforms (sward-core's `FrameUniforms`, member for member).
pub const FRAME: &str = include_str!("../shaders/frame.wgsl");
/// A Bezier blade: its layout and frame, the hash.
pub const BLADE: &str = include_str!("../shaders/blade.wgsl");
/// The physical model of one blade.
pub const PHYSICS: &str = include_str!("../shaders/physics.wgsl");
/// Hashing and noise.
pub const NOISE: &str = include_str!("../shaders/noise.wgsl");
/// Distance buckets and their strips.
pub const BUCKETS: &str = include_str!("../shaders/buckets.wgsl");
/// The paint, the kinds of grass, a blade's look and its shading.
pub const SHADING: &str = include_str!("../shaders/shading.wgsl");
/// The blades drawn as triangle strips.
pub const STRIPS: &str = include_str!("../shaders/strips.wgsl");
/// A blade's outline across its width, and its rounded normal.
pub const OUTLINE: &str = include_str!("../shaders/outline.wgsl");
/// Where a strip's vertex lies on its blade (no entry points: an engine's passes draw from it).
pub const STRIP_SURFACE: &str = include_str!("../shaders/strip_surface.wgsl");
/// The occluders' fragment stage: their depth as bits.
pub const OCCLUDER_DEPTH: &str = include_str!("../shaders/occluder_depth.wgsl");
/// The ground, the collider spheres and the sky.
pub const SCENERY: &str = include_str!("../shaders/scenery.wgsl");
/// The depth pyramid's reduction.
pub const PYRAMID: &str = include_str!("../shaders/pyramid.wgsl");
/// Where the depth pyramid's levels lie in its buffer.
pub const PYRAMID_LEVELS: &str = include_str!("../shaders/pyramid_levels.wgsl");
/// The trample map's texels as the passes read them.
pub const TRAMPLE_MAP: &str = include_str!("../shaders/trample_map.wgsl");
/// The trample map's frame.
pub const TRAMPLE: &str = include_str!("../shaders/trample.wgsl");
/// The ground's height grid.
pub const GROUND_GRID: &str = include_str!("../shaders/ground_grid.wgsl");
/// The streamed field's cells: a cell's hash, a slot's world tile.
pub const STREAM_CELLS: &str = include_str!("../shaders/stream_cells.wgsl");
/// An instanced blade of the grid and how the frame poses it.
pub const TWIN: &str = include_str!("../shaders/twin.wgsl");
/// The streamed field's entering tiles and its moving origin.
pub const STREAM: &str = include_str!("../shaders/stream.wgsl");
/// The caller's depth folded into the depth pyramid.
pub const CALLER_DEPTH: &str = include_str!("../shaders/caller_depth.wgsl");
/// Which blade an invocation takes: through the tiles a frame runs, or over the whole field.
pub const TILES: &str = include_str!("../shaders/tiles.wgsl");
/// The simulation pass.
pub const SIMULATE: &str = include_str!("../shaders/simulate.wgsl");
/// The depth pyramid as the culls test against it.
pub const OCCLUSION: &str = include_str!("../shaders/occlusion.wgsl");
/// Culling and compaction into distance buckets.
pub const CULL: &str = include_str!("../shaders/cull.wgsl");
/// How a blade joins its bucket's run, in WebGPU's core.
pub const CULL_JOIN: &str = include_str!("../shaders/cull_join.wgsl");
/// How a blade joins its bucket's run, with subgroups.
pub const CULL_JOIN_SUBGROUPS: &str = include_str!("../shaders/cull_join_subgroups.wgsl");
/// The generated grass's passes: its patches, counts, their scan and its lists.
pub const GENERATED: &str = include_str!("../shaders/generated.wgsl");
/// The generated grass's lists as the draws read them.
pub const LISTED: &str = include_str!("../shaders/listed.wgsl");
/// A listed blade's strip at its level: its curve, width and geomorphed points.
pub const GENERATED_BLADES: &str = include_str!("../shaders/generated_blades.wgsl");
/// The generated grass's listed blades drawn as strips.
pub const GENERATED_STRIPS: &str = include_str!("../shaders/generated_strips.wgsl");
/// A billboard's quads, sway, trampling and painted coverage.
pub const BILLBOARD_QUADS: &str = include_str!("../shaders/billboard_quads.wgsl");
/// The billboards drawn.
pub const BILLBOARDS: &str = include_str!("../shaders/billboards.wgsl");
/// A drawn blade's vertex as its fragments read it, and their shading.
pub const BLADE_FRAGMENT: &str = include_str!("../shaders/blade_fragment.wgsl");
/// The subgroups extension enabled: first in a pipeline that uses it.
pub const SUBGROUPS: &str = include_str!("../shaders/subgroups.wgsl");

/// A portable pipeline's shader: its name, its entry points, and its modules in order.
#[derive(Clone, Copy, Debug)]
pub struct PipelineSource {
    /// The pipeline's name (`simulate`).
    pub name: &'static str,
    /// The entry point in its source: a compute pipeline's, or a draw's vertex stage.
    pub entry: &'static str,
    /// A draw's fragment stage (None: a compute pipeline).
    pub fragment: Option<&'static str>,
    /// Its modules, in the order they are joined.
    pub modules: &'static [&'static str],
}

impl PipelineSource {
    /// The whole WGSL the device compiles for this pipeline.
    pub fn text(&self) -> String {
        self.modules.join("\n")
    }

    /// Whether the pipeline uses subgroup operations.
    pub fn uses_subgroups(&self) -> bool {
        self.modules.contains(&SUBGROUPS)
    }

    /// The whole WGSL as a browser's WebGPU compiles it: with WGSL's `enable subgroups;` first
    /// where the pipeline uses them, which wgpu's naga (30) refuses and a browser's compiler
    /// needs.
    pub fn browser_text(&self) -> String {
        match self.uses_subgroups() {
            true => format!("enable subgroups;\n{}", self.text()),
            false => self.text(),
        }
    }
}

/// The simulation.
pub const SIMULATE_SOURCE: PipelineSource = PipelineSource {
    name: "simulate",
    entry: "simulate",
    fragment: None,
    modules: &[
        FRAME,
        BLADE,
        NOISE,
        SHADING,
        TRAMPLE_MAP,
        PHYSICS,
        GROUND_GRID,
        STREAM_CELLS,
        OUTLINE,
        TWIN,
        TILES,
        SIMULATE,
    ],
};

/// The trample map's frame, before the simulation reads it.
pub const TRAMPLE_SOURCE: PipelineSource = PipelineSource {
    name: "trample",
    entry: "trample",
    fragment: None,
    modules: &[FRAME, BLADE, TRAMPLE_MAP, GROUND_GRID, TRAMPLE],
};

/// The modules of the streamed field's passes.
const STREAM_MODULES: &[&str] = &[
    FRAME,
    BLADE,
    NOISE,
    SHADING,
    TRAMPLE_MAP,
    PHYSICS,
    GROUND_GRID,
    OUTLINE,
    TWIN,
    STREAM_CELLS,
    STREAM,
];

/// The streamed field's passes, before the trample map and the simulation: every held blade
/// carried to a moved frame origin, the blades of the tiles entering the window made.
pub const STREAM_SOURCES: [PipelineSource; 2] = [
    PipelineSource {
        name: "rebase_field",
        entry: "rebase_field",
        fragment: None,
        modules: STREAM_MODULES,
    },
    PipelineSource {
        name: "make_entering_tiles",
        entry: "make_entering_tiles",
        fragment: None,
        modules: STREAM_MODULES,
    },
];

/// The cull's modules in WebGPU's core.
const CULL_MODULES: &[&str] = &[FRAME, BLADE, BUCKETS, PYRAMID_LEVELS, OCCLUSION, TILES, CULL_JOIN, CULL];

/// The cull's modules where the device has subgroups.
const CULL_SUBGROUP_MODULES: &[&str] = &[
    SUBGROUPS,
    FRAME,
    BLADE,
    BUCKETS,
    PYRAMID_LEVELS,
    OCCLUSION,
    TILES,
    CULL_JOIN_SUBGROUPS,
    CULL,
];

/// A compute pipeline `entry` of `modules`, named `name`.
const fn compute(name: &'static str, entry: &'static str, modules: &'static [&'static str]) -> PipelineSource {
    PipelineSource {
        name,
        entry,
        fragment: None,
        modules,
    }
}

/// The cull's three passes: count each distance bucket's blades, lay the buckets out, place
/// each blade in its bucket's list.
pub const CULL_SOURCES: [PipelineSource; 3] = [
    compute("count_buckets", "count_buckets", CULL_MODULES),
    compute("lay_out_buckets", "lay_out_buckets", CULL_MODULES),
    compute("place_blades", "place_blades", CULL_MODULES),
];

/// The cull's passes where the device has subgroups (`wgpu::Features::SUBGROUP`): the lanes of
/// a subgroup in one bucket take their places with one workgroup atomic.
pub const CULL_SUBGROUP_SOURCES: [PipelineSource; 3] = [
    compute("count_buckets_subgroups", "count_buckets", CULL_SUBGROUP_MODULES),
    compute("lay_out_buckets_subgroups", "lay_out_buckets", CULL_SUBGROUP_MODULES),
    compute("place_blades_subgroups", "place_blades", CULL_SUBGROUP_MODULES),
];

/// A draw of what surrounds the grass (scenery.wgsl): its name and its two stages.
const fn scenery(name: &'static str, vertex: &'static str, fragment: &'static str) -> PipelineSource {
    PipelineSource {
        name,
        entry: vertex,
        fragment: Some(fragment),
        modules: &[FRAME, BLADE, NOISE, SHADING, SCENERY, OCCLUDER_DEPTH],
    }
}

/// The modules of the pipelines that draw blades as strips (the camera's, the occluders').
const STRIP_MODULES: &[&str] = &[
    FRAME,
    BLADE,
    NOISE,
    BUCKETS,
    SHADING,
    STREAM_CELLS,
    OUTLINE,
    STRIP_SURFACE,
    BLADE_FRAGMENT,
    STRIPS,
    OCCLUDER_DEPTH,
];

/// The modules of the generated grass's passes.
const GENERATED_MODULES: &[&str] = &[
    FRAME,
    BLADE,
    NOISE,
    BUCKETS,
    SHADING,
    TRAMPLE_MAP,
    PHYSICS,
    GROUND_GRID,
    STREAM_CELLS,
    OUTLINE,
    TWIN,
    PYRAMID_LEVELS,
    OCCLUSION,
    GENERATED,
];

/// The generated grass's passes, after the depth pyramid: both grids' patches kept, then per
/// grid (the instanced grass's, the billboards') each workgroup's blades per list counted, the
/// counts scanned, the blades placed in their lists.
pub const GENERATED_SOURCES: [PipelineSource; 7] = [
    compute("cull_patches", "cull_patches", GENERATED_MODULES),
    compute("count_generated", "count_generated", GENERATED_MODULES),
    compute("scan_generated", "scan_generated", GENERATED_MODULES),
    compute("place_generated", "place_generated", GENERATED_MODULES),
    compute("count_billboards", "count_billboards", GENERATED_MODULES),
    compute("scan_billboards", "scan_billboards", GENERATED_MODULES),
    compute("place_billboards", "place_billboards", GENERATED_MODULES),
];

/// The draws: the blades' strips, the ground, the collider spheres, the sky, the generated
/// grass's strips, the billboards.
pub const DRAW_SOURCES: [PipelineSource; 6] = [
    PipelineSource {
        name: "strips",
        entry: "strip_vertex",
        fragment: Some("strip_fragment"),
        modules: STRIP_MODULES,
    },
    scenery("ground", "ground_vertex", "ground_fragment"),
    scenery("colliders", "collider_vertex", "collider_fragment"),
    scenery("sky", "sky_vertex", "sky_fragment"),
    PipelineSource {
        name: "generated_strips",
        entry: "generated_vertex",
        fragment: Some("strip_fragment"),
        modules: &[
            FRAME,
            BLADE,
            NOISE,
            BUCKETS,
            SHADING,
            OUTLINE,
            LISTED,
            GENERATED_BLADES,
            BLADE_FRAGMENT,
            GENERATED_STRIPS,
        ],
    },
    PipelineSource {
        name: "billboards",
        entry: "billboard_vertex",
        fragment: Some("billboard_fragment"),
        modules: &[
            FRAME,
            BLADE,
            NOISE,
            SHADING,
            TRAMPLE_MAP,
            LISTED,
            BILLBOARD_QUADS,
            BILLBOARDS,
        ],
    },
];

/// The depth pyramid: the blades, the ground and the colliders drawn as the bits of their depth
/// (into an `r32uint` target: pipelines named `occluder_*`), and a level of the pyramid's buffer
/// copied from them or reduced from the one below.
pub const PYRAMID_SOURCES: [PipelineSource; 4] = [
    PipelineSource {
        name: "occluder_blades",
        entry: "occluder_vertex",
        fragment: Some("occluder_depth"),
        modules: STRIP_MODULES,
    },
    scenery("occluder_ground", "occluder_ground_vertex", "occluder_depth"),
    scenery("occluder_colliders", "collider_vertex", "occluder_depth"),
    PipelineSource {
        name: "reduce_pyramid",
        entry: "reduce_level",
        fragment: None,
        modules: &[PYRAMID_LEVELS, PYRAMID],
    },
];

/// The caller's depth folded into the depth pyramid's level 0: from a single-sampled depth
/// texture, from a multisampled one.
pub const CALLER_DEPTH_SOURCES: [PipelineSource; 2] = [
    PipelineSource {
        name: "fold_caller_depth",
        entry: "fold_caller_depth",
        fragment: None,
        modules: &[CALLER_DEPTH],
    },
    PipelineSource {
        name: "fold_caller_depth_samples",
        entry: "fold_caller_depth_samples",
        fragment: None,
        modules: &[CALLER_DEPTH],
    },
];

/// Every portable pipeline's shader.
pub const PIPELINES: &[PipelineSource] = &[
    STREAM_SOURCES[0],
    STREAM_SOURCES[1],
    TRAMPLE_SOURCE,
    SIMULATE_SOURCE,
    CULL_SOURCES[0],
    CULL_SOURCES[1],
    CULL_SOURCES[2],
    CULL_SUBGROUP_SOURCES[0],
    CULL_SUBGROUP_SOURCES[1],
    CULL_SUBGROUP_SOURCES[2],
    DRAW_SOURCES[0],
    DRAW_SOURCES[1],
    DRAW_SOURCES[2],
    DRAW_SOURCES[3],
    DRAW_SOURCES[4],
    DRAW_SOURCES[5],
    GENERATED_SOURCES[0],
    GENERATED_SOURCES[1],
    GENERATED_SOURCES[2],
    GENERATED_SOURCES[3],
    GENERATED_SOURCES[4],
    GENERATED_SOURCES[5],
    GENERATED_SOURCES[6],
    PYRAMID_SOURCES[0],
    PYRAMID_SOURCES[1],
    PYRAMID_SOURCES[2],
    PYRAMID_SOURCES[3],
    CALLER_DEPTH_SOURCES[0],
    CALLER_DEPTH_SOURCES[1],
];

/// The bindings of the engine library ([`engine_library`]), in its bind group.
pub mod engine_bindings {
    /// The frame's uniforms (sward-core's `FrameUniforms`).
    pub const FRAME: u32 = 0;
    /// The blades (sward-core's `Blade`), read only.
    pub const BLADES: u32 = 1;
    /// The view's visible blades, bucket by bucket.
    pub const VISIBLE: u32 = 3;
    /// The view's cull counters (where each bucket's list starts).
    pub const COUNTERS: u32 = 6;
    /// The paint maps' texels.
    pub const PAINT: u32 = 20;
    /// The trample map's texels (the billboards lie down where it says).
    pub const TRAMPLE: u32 = 9;
    /// The generated grass's visible lists: its four levels, then the billboards.
    pub const LISTED: u32 = 12;
    /// The billboards' painted texture.
    pub const GRASS_TEXTURE: u32 = 16;
    /// Its sampler (trilinear, clamped).
    pub const GRASS_SAMPLER: u32 = 17;
}

/// The modules of the engine library: the strips' up to the first with an entry point, then
/// the generated grass's and the billboards' placing (the trample map, the lists, the levels'
/// strips, the billboards' quads).
fn engine_modules() -> Vec<&'static str> {
    let strips = STRIP_MODULES
        .iter()
        .copied()
        .take_while(|&module| module != BLADE_FRAGMENT);
    strips
        .chain([TRAMPLE_MAP, LISTED, GENERATED_BLADES, BILLBOARD_QUADS])
        .collect()
}

/// The WGSL an engine's own passes draw the blades from, with their own entry points and
/// lighting: the strips' modules (the frame, the blade, noise, the buckets, the shading's looks
/// and colours, where a strip's vertex lies) without an entry point, sward's bindings moved to
/// bind group `group` (at [`engine_bindings`]). A vertex stage finds its point by
/// `strip_place(vertex_index, instance_index)` and `blade_point`, for each bucket's command of
/// the view's lists; a generated blade's by `generated_point(vertex_index, instance_index)` for
/// each level's command, a billboard's by `billboard_corner`, and a billboard's fragment its
/// coverage by `billboard_painted`.
pub fn engine_library(group: u32) -> String {
    engine_modules()
        .join("\n")
        .replace("@group(0)", &format!("@group({group})"))
}
