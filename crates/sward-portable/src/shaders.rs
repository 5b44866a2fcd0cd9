//! The portable renderer's pipelines: each one's entry points and the WESL module it is
//! composed from (`shaders/*.wesl`, joined by `compose.rs`), and the library an engine's own
//! passes draw the blades from.

use crate::compose::{compose, Linking};
use crate::{one_line, PortableError};

/// A portable pipeline's shader: its name, its entry points and the module it is composed from.
#[derive(Clone, Copy, Debug)]
pub struct PipelineSource {
    /// The pipeline's name (`simulate`).
    pub name: &'static str,
    /// The entry point in its source: a compute pipeline's, or a draw's vertex stage.
    pub entry: &'static str,
    /// A draw's fragment stage (None: a compute pipeline).
    pub fragment: Option<&'static str>,
    /// The module that holds its entry points (`shaders/ROOT.wesl`), which imports the rest.
    pub root: &'static str,
    /// The WESL features it is composed with (`@if(subgroups)`); the others are off.
    pub features: &'static [&'static str],
}

impl PipelineSource {
    /// The whole WGSL the device compiles for this pipeline: its root module and what it
    /// imports, composed by WESL with its features.
    pub fn text(&self) -> Result<String, PortableError> {
        compose(self.root, self.features, Linking::Pipeline).map_err(|message| PortableError::Shader {
            pipeline: self.name,
            message: one_line(&message),
        })
    }

    /// [`PipelineSource::text`] with the modules of `replaced` (name, text) in place of the
    /// built-in ones of those names.
    pub fn text_replaced(&self, replaced: &[(String, String)]) -> Result<String, PortableError> {
        crate::compose::compose_replaced(self.root, self.features, replaced).map_err(|message| PortableError::Shader {
            pipeline: self.name,
            message: one_line(&message),
        })
    }

    /// The frame's uniform blocks its entry points read (their bindings, sward-core's
    /// `declared::bindings::FRAME_BLOCKS`): what its group binds of the frame's buffer, each
    /// block at its place (`declared::frame_blocks`).
    pub fn frame_blocks_read(&self) -> Result<Vec<u32>, PortableError> {
        let entries: Vec<&str> = [Some(self.entry), self.fragment].into_iter().flatten().collect();
        crate::bind::blocks_read(&self.text()?, &entries)
    }

    /// Whether the pipeline uses subgroup operations.
    pub fn uses_subgroups(&self) -> bool {
        self.features.contains(&SUBGROUPS)
    }

    /// The whole WGSL as a browser's WebGPU compiles it: with WGSL's `enable subgroups;` first
    /// where the pipeline uses them, which wgpu's naga (30) refuses and a browser's compiler
    /// needs.
    pub fn browser_text(&self) -> Result<String, PortableError> {
        ShaderModules::built_in().browser_text(self)
    }
}

/// The core's WESL modules a renderer makes its pipelines from: the built-in ones, with those a
/// shader directory holds in place of theirs (`--shaders DIR`: a variant measured with the same
/// binary).
#[derive(Clone, Debug, Default)]
pub struct ShaderModules {
    replaced: std::sync::Arc<[(String, String)]>,
}

impl ShaderModules {
    /// The built-in modules.
    pub fn built_in() -> ShaderModules {
        ShaderModules::default()
    }

    /// The built-in modules with `replaced` ((name, text): `NAME.wesl`'s text) in place of
    /// those of their names.
    pub fn replacing(replaced: Vec<(String, String)>) -> ShaderModules {
        ShaderModules {
            replaced: replaced.into(),
        }
    }

    /// The built-in modules with those folder `dir` holds (`NAME.wesl` for a module NAME of
    /// [`MODULES`](crate::MODULES)) in place of theirs; a folder or file that cannot be read said
    /// in one sentence.
    pub fn from_dir(dir: &std::path::Path) -> Result<ShaderModules, String> {
        if !dir.is_dir() {
            return Err(format!("{} is not a folder of shaders", dir.display()));
        }
        let mut replaced = Vec::new();
        for (name, _) in crate::MODULES {
            let path = dir.join(format!("{name}.wesl"));
            if path.exists() {
                let bytes = sward_core::files::read(&path)?;
                let text = String::from_utf8(bytes).map_err(|_| format!("{} is not UTF-8 text", path.display()))?;
                replaced.push((name.to_string(), text));
            }
        }
        Ok(ShaderModules::replacing(replaced))
    }

    /// The WGSL of pipeline `source` composed from these modules.
    pub fn text(&self, source: &PipelineSource) -> Result<String, PortableError> {
        match self.replaced.is_empty() {
            true => source.text(),
            false => source.text_replaced(&self.replaced),
        }
    }

    /// The same as a browser's WebGPU compiles it ([`PipelineSource::browser_text`]).
    pub fn browser_text(&self, source: &PipelineSource) -> Result<String, PortableError> {
        let text = self.text(source)?;
        Ok(match source.uses_subgroups() {
            true => format!("enable subgroups;\n{text}"),
            false => text,
        })
    }
}

/// The WESL feature of the pipelines that use subgroup operations.
const SUBGROUPS: &str = "subgroups";

/// A compute pipeline `entry` of module `root`, named `name`.
const fn compute(name: &'static str, entry: &'static str, root: &'static str) -> PipelineSource {
    PipelineSource {
        name,
        entry,
        fragment: None,
        root,
        features: &[],
    }
}

/// A draw `vertex` then `fragment` of module `root`, named `name`.
const fn draw(name: &'static str, vertex: &'static str, fragment: &'static str, root: &'static str) -> PipelineSource {
    PipelineSource {
        name,
        entry: vertex,
        fragment: Some(fragment),
        root,
        features: &[],
    }
}

/// The simulation.
pub const SIMULATE_SOURCE: PipelineSource = compute("simulate", "simulate", "simulate");

/// The trample map's frame, before the simulation reads it: the one pass that writes the map
/// (`trample_pass`).
pub const TRAMPLE_SOURCE: PipelineSource = PipelineSource {
    features: &["trample_pass"],
    ..compute("trample", "trample", "trample")
};

/// The streamed field's passes, before the trample map and the simulation: every held blade
/// carried to a moved frame origin, the blades of the tiles entering the window made.
pub const STREAM_SOURCES: [PipelineSource; 2] = [
    compute("rebase_field", "rebase_field", "stream"),
    compute("make_entering_tiles", "make_entering_tiles", "stream"),
];

/// The cull's three passes: count each distance bucket's blades, lay the buckets out, place
/// each blade in its bucket's list.
pub const CULL_SOURCES: [PipelineSource; 3] = [
    compute("count_buckets", "count_buckets", "cull"),
    compute("lay_out_buckets", "lay_out_buckets", "cull"),
    compute("place_blades", "place_blades", "cull"),
];

/// A cull pass where the device has subgroups.
const fn with_subgroups(name: &'static str, pass: PipelineSource) -> PipelineSource {
    PipelineSource {
        name,
        features: &[SUBGROUPS],
        ..pass
    }
}

/// The cull's passes where the device has subgroups (`wgpu::Features::SUBGROUP`): the lanes of
/// a subgroup in one bucket take their places with one workgroup atomic.
pub const CULL_SUBGROUP_SOURCES: [PipelineSource; 3] = [
    with_subgroups("count_buckets_subgroups", CULL_SOURCES[0]),
    with_subgroups("lay_out_buckets_subgroups", CULL_SOURCES[1]),
    with_subgroups("place_blades_subgroups", CULL_SOURCES[2]),
];

/// The generated grass's passes, after the depth pyramid: both grids' patches kept, then per
/// grid (the instanced grass's, the billboards') each workgroup's blades per list counted, the
/// counts scanned, the blades placed in their lists.
pub const GENERATED_SOURCES: [PipelineSource; 7] = [
    compute("cull_patches", "cull_patches", "generated"),
    compute("count_generated", "count_generated", "generated"),
    compute("scan_generated", "scan_generated", "generated"),
    compute("place_generated", "place_generated", "generated"),
    compute("count_billboards", "count_billboards", "generated"),
    compute("scan_billboards", "scan_billboards", "generated"),
    compute("place_billboards", "place_billboards", "generated"),
];

/// The draws: the blades' strips, the ground, the collider spheres, the sky, the generated
/// grass's strips, the billboards.
pub const DRAW_SOURCES: [PipelineSource; 6] = [
    draw("strips", "strip_vertex", "strip_fragment", "strips"),
    draw("ground", "ground_vertex", "ground_fragment", "scenery"),
    draw("colliders", "collider_vertex", "collider_fragment", "scenery"),
    draw("sky", "sky_vertex", "sky_fragment", "scenery"),
    draw(
        "generated_strips",
        "generated_vertex",
        "strip_fragment",
        "generated_strips",
    ),
    draw("billboards", "billboard_vertex", "billboard_fragment", "billboards"),
];

/// The depth pyramid: the blades, the ground and the colliders drawn as the bits of their depth
/// (into an `r32uint` target: pipelines named `occluder_*`), and a level of the pyramid's buffer
/// copied from them or reduced from the one below.
pub const PYRAMID_SOURCES: [PipelineSource; 4] = [
    draw("occluder_blades", "occluder_vertex", "occluder_depth", "strips"),
    draw("occluder_ground", "occluder_ground_vertex", "occluder_depth", "scenery"),
    draw("occluder_colliders", "collider_vertex", "occluder_depth", "scenery"),
    compute("reduce_pyramid", "reduce_level", "pyramid"),
];

/// The caller's depth folded into the depth pyramid's level 0: from a single-sampled depth
/// texture, from a multisampled one.
pub const CALLER_DEPTH_SOURCES: [PipelineSource; 2] = [
    compute("fold_caller_depth", "fold_caller_depth", "caller_depth"),
    compute("fold_caller_depth_samples", "fold_caller_depth_samples", "caller_depth"),
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

/// The bindings of the engine library ([`engine_library`]), in its bind group: sward-core's
/// numbers (`declared::bindings`), which the library's declarations name.
pub mod engine_bindings {
    use sward_core::declared::bindings;

    /// The frame's uniform blocks, each a range of the frame's buffer: sward-core's
    /// `declared::frame_blocks()` says each one's binding (these), offset and size.
    pub const FRAME_BLOCKS: [u32; 6] = bindings::FRAME_BLOCKS;
    /// The blades (sward-core's `Blade`), read only.
    pub const BLADES: u32 = bindings::BLADES;
    /// The view's visible blades, bucket by bucket.
    pub const VISIBLE: u32 = bindings::VISIBLE;
    /// The view's cull counters (where each bucket's list starts).
    pub const COUNTERS: u32 = bindings::CULL_COUNTERS;
    /// The paint maps' texels.
    pub const PAINT: u32 = bindings::PAINT;
    /// The trample map's texels (the billboards lie down where it says).
    pub const TRAMPLE: u32 = bindings::TRAMPLE;
    /// The generated grass's visible lists: its four levels, then the billboards.
    pub const LISTED: u32 = bindings::GENERATED_BLADES;
    /// The billboards' painted texture.
    pub const GRASS_TEXTURE: u32 = bindings::GRASS_TEXTURE;
    /// Its sampler (trilinear, clamped).
    pub const GRASS_SAMPLER: u32 = bindings::GRASS_SAMPLER;
}

/// The WGSL an engine's own passes draw the blades from (`shaders/engine.wesl`), with their
/// own entry points and lighting: the strips' modules (the frame, the blade, noise, the
/// buckets, the shading's looks and colours, where a strip's vertex lies) without an entry
/// point, sward's bindings moved to bind group `group` (at [`engine_bindings`]). A vertex stage
/// finds its point by `strip_place(vertex_index, instance_index)` and `blade_point`, for each
/// bucket's command of the view's lists; a generated blade's by
/// `generated_point(vertex_index, instance_index)` for each level's command, a billboard's by
/// `billboard_corner`, and a billboard's fragment its coverage by `billboard_painted`. Every
/// declaration keeps its name, so an engine's WESL imports them by name.
pub fn engine_library(group: u32) -> Result<String, PortableError> {
    Ok(library("engine")?.replace("@group(0)", &format!("@group({group})")))
}

/// Module `root` (one of [`MODULES`](crate::MODULES)) as a library: every declaration of it and
/// of each module it reaches, under its own name, its bindings in group 0.
pub fn library(root: &'static str) -> Result<String, PortableError> {
    compose(root, &[], Linking::Library).map_err(|message| PortableError::Shader {
        pipeline: root,
        message: one_line(&message),
    })
}
