//! The SPIR-V of every stage: the passes written once in the core's WGSL (sward-core's `wgsl`)
//! translated by naga as their pipelines are made, and the tessellation and mesh routes' GLSL stages in
//! `shaders/` — glue around the core's functions, which naga writes as GLSL — compiled by
//! glslang once a process; either with the modules and stages a shader directory holds in place
//! of the built-in ones (the viewer's hot reload, `--shaders`).

use std::collections::HashMap;
use std::path::Path;
use std::sync::OnceLock;

use ash::vk;
use sward_core::wgsl::{PipelineSource, ShaderModules};

pub use crate::wgsl::ShaderStage;
pub use sward_core::wgsl::splatting::{
    BILLBOARD_RASTER, GENERATED_SCAN, GENERATE_DRAWN, GENERATE_PLACE, GENERATE_SPLATS, INSTANCED_RASTER, SPLAT_BLADES,
    SPLAT_RESOLVE, SPLAT_TILES,
};

/// Both generated grids' patch lists and dispatch sizes (`patch_cull.wesl`), reading the depth
/// pyramid as its image.
pub const PATCH_CULL: PipelineSource = sward_core::wgsl::splatting::patch_cull(&["pyramid_image"]);

/// (file name, GLSL) of the tessellation route's stages, which WGSL has no way to write, and the
/// mesh route's (naga's mesh stages are slower): glue that calls the core's functions
/// ([`TESSELLATION`]), included as `tessellation.glsl`.
const GLSL_STAGES: [(&str, &str); 4] = [
    ("blade.mesh", include_str!("../shaders/blade.mesh")),
    ("blade.vert", include_str!("../shaders/blade.vert")),
    ("blade.tesc", include_str!("../shaders/blade.tesc")),
    ("blade.tese", include_str!("../shaders/blade.tese")),
];

/// The core's functions the tessellation and mesh stages call (`tessellation.wesl`: the blade a
/// patch draws, its level, each vertex), written as GLSL by naga (`wgsl::glsl_functions`).
pub const TESSELLATION: PipelineSource = PipelineSource {
    name: "tessellation",
    entry: "tessellation_functions",
    fragment: None,
    root: "tessellation",
    features: &["shadow_map"],
};

/// The trample map's frame (both renderers run it).
pub const TRAMPLE: PipelineSource = sward_core::wgsl::TRAMPLE_SOURCE;
/// The streamed field carried to a moved frame origin (both renderers run it).
pub const REBASE_FIELD: PipelineSource = sward_core::wgsl::STREAM_SOURCES[0];
/// The blades of the tiles entering the streamed window made (both renderers run it; the
/// Vulkan renderer keeps the entering tiles after its tile list).
pub const STREAM_TILES: PipelineSource = PipelineSource {
    features: &["entering_after_tiles"],
    ..sward_core::wgsl::STREAM_SOURCES[1]
};

/// One of the Vulkan renderer's simulate and cull passes (`cull_slots.wesl`), composed with the
/// depth pyramid as its image and `features`.
const fn cull_slots(name: &'static str, entry: &'static str, features: &'static [&'static str]) -> PipelineSource {
    PipelineSource {
        name,
        entry,
        fragment: None,
        root: "cull_slots",
        features,
    }
}

/// The simulate and cull passes by whether they aggregate with subgroups and whether they copy
/// whole blades (the bench's variant): `[plain, subgroups, copy, subgroups and copy]`.
const CULL_FEATURES: [&[&str]; 4] = [
    &["pyramid_image"],
    &["pyramid_image", "subgroups"],
    &["pyramid_image", "copy_blades"],
    &["pyramid_image", "subgroups", "copy_blades"],
];

/// The fused simulate and cull, in its four variants ([`cull_variant`]).
pub const SIMULATE_CULL: [PipelineSource; 4] = [
    cull_slots("simulate_cull", "simulate_cull", CULL_FEATURES[0]),
    cull_slots("simulate_cull", "simulate_cull", CULL_FEATURES[1]),
    cull_slots("simulate_cull", "simulate_cull", CULL_FEATURES[2]),
    cull_slots("simulate_cull", "simulate_cull", CULL_FEATURES[3]),
];
/// The cull alone, in its four variants ([`cull_variant`]).
pub const CULL: [PipelineSource; 4] = [
    cull_slots("cull", "cull_blades", CULL_FEATURES[0]),
    cull_slots("cull", "cull_blades", CULL_FEATURES[1]),
    cull_slots("cull", "cull_blades", CULL_FEATURES[2]),
    cull_slots("cull", "cull_blades", CULL_FEATURES[3]),
];
/// The simulation alone.
pub const SIMULATE: PipelineSource = cull_slots("simulate", "simulate_blades", CULL_FEATURES[0]);

/// One of the ordering passes (`order.wesl`).
const fn order(entry: &'static str) -> PipelineSource {
    PipelineSource {
        name: entry,
        entry,
        fragment: None,
        root: "order",
        features: &[],
    }
}

/// The ordering passes, in the order they run: the buckets laid out, each cull workgroup's
/// counts, the counts scanned, each blade in its place, runs of the drawn part sorted.
pub const ORDER: [PipelineSource; 5] = [
    order("order_buckets"),
    order("order_counts"),
    order("order_scan"),
    order("order_blades"),
    order("order_sort"),
];

/// The tiles the frame runs, decided on the GPU (`tile_cull.wesl`).
pub const TILE_CULL: PipelineSource = PipelineSource {
    name: "tile_cull",
    entry: "tile_cull",
    fragment: None,
    root: "tile_cull",
    features: &[],
};

/// Three levels of the depth pyramid reduced from the one below them (`hiz_reduce.wesl`; its own
/// set: the level read, the three written).
pub const HIZ_REDUCE: PipelineSource = PipelineSource {
    name: "hiz_reduce",
    entry: "reduce_depth",
    fragment: None,
    root: "hiz_reduce",
    features: &[],
};

/// The listed blades with what a renderer that draws them itself needs (`drawn_blades.wesl`).
pub const DRAWN_BLADES: PipelineSource = PipelineSource {
    name: "drawn_blades",
    entry: "list_drawn_blades",
    fragment: None,
    root: "drawn_blades",
    features: &[],
};

/// The compute route's rasterizer (`raster_blades.wesl`; which pass by
/// `constants::SECOND_PASS`), lit with the shadow map.
pub const RASTER_BLADES: PipelineSource = PipelineSource {
    name: "raster_blades",
    entry: "raster_blades",
    fragment: None,
    root: "raster_blades",
    features: &["shadow_map"],
};

/// The bench's memory bandwidth probe (`bandwidth.wesl`; its own set: bindings 1 and 2).
pub const BANDWIDTH: PipelineSource = PipelineSource {
    name: "bandwidth",
    entry: "copy_words",
    fragment: None,
    root: "bandwidth",
    features: &[],
};

/// The caller's depth folded into the depth pyramid's level 0 (`caller_depth_fold.wesl`): its
/// single-sampled image, then its multisampled one.
pub const CALLER_DEPTH_FOLD: [PipelineSource; 2] = [
    PipelineSource {
        name: "caller_depth_fold",
        entry: "fold_caller_depth",
        fragment: None,
        root: "caller_depth_fold",
        features: &[],
    },
    PipelineSource {
        name: "caller_depth_fold",
        entry: "fold_caller_depth",
        fragment: None,
        root: "caller_depth_fold",
        features: &["caller_samples"],
    },
];

/// A draw of the scenery (`scenery.wesl`, lit with the shadow map): `vertex`'s and `fragment`'s
/// entry points.
const fn scenery(name: &'static str, entry: &'static str, fragment: &'static str) -> PipelineSource {
    PipelineSource {
        name,
        entry,
        fragment: Some(fragment),
        root: "scenery",
        features: &["shadow_map"],
    }
}

/// The sky: one triangle covering the screen at the far plane.
pub const SKY: PipelineSource = scenery("sky", "sky_vertex", "sky_fragment");
/// The ground (its vertex stage also draws it into the shadow map and the depth pyramid).
pub const GROUND: PipelineSource = scenery("ground", "ground_vertex", "ground_fragment");
/// The collider spheres (their vertex stage too).
pub const COLLIDERS: PipelineSource = scenery("colliders", "collider_vertex", "collider_fragment");
/// The occluders' depths in the depth pyramid's level 0: its fragment stage, after any vertex
/// stage that places them.
pub const OCCLUDER_DEPTH: PipelineSource = scenery("occluder_depth", "occluder_depth_float", "occluder_depth_float");

/// The generated grass's levels' strips (`generated_strips.wesl`, its vertex stage; in the
/// near shadow cascade too) and every drawn blade's fragments (Bezier and instanced, every
/// route), shaded as the portable renderer's (`blade_fragment.wesl`).
pub const BLADE_STRIPS: PipelineSource = PipelineSource {
    name: "blade_strips",
    entry: "generated_vertex",
    fragment: Some("strip_fragment"),
    root: "generated_strips",
    features: &["shadow_map"],
};

/// The Bezier blades' strips (`bezier_strips.wesl`): the strip route's vertex stage, also the
/// blade occluders' in the depth pyramid and the near shadow cascade's.
pub const BEZIER_STRIPS: PipelineSource = PipelineSource {
    name: "bezier_strips",
    entry: "bezier_strip_vertex",
    fragment: Some("strip_fragment"),
    root: "bezier_strips",
    features: &["shadow_map"],
};

/// The billboards the compute rasterizer leaves (`billboards.wesl`'s `left_billboard_vertex`):
/// `[in one pass, the depth pre-pass, the nearest shaded after it]`.
pub const BILLBOARD_DRAWS: [PipelineSource; 3] = [
    billboard_draw("billboards", "billboard_fragment"),
    billboard_draw("billboard_depth", "billboard_depth_fragment"),
    billboard_draw("billboard_nearest", "billboard_nearest_fragment"),
];

const fn billboard_draw(name: &'static str, fragment: &'static str) -> PipelineSource {
    PipelineSource {
        name,
        entry: "left_billboard_vertex",
        fragment: Some(fragment),
        root: "billboards",
        features: &["shadow_map"],
    }
}

/// Every stage the Vulkan renderer draws with from the core's WGSL: the draw and which of its
/// stages.
pub fn wgsl_draw_stages() -> impl Iterator<Item = (PipelineSource, ShaderStage)> {
    let both = [SKY, GROUND, COLLIDERS, BLADE_STRIPS, BEZIER_STRIPS]
        .into_iter()
        .chain(BILLBOARD_DRAWS)
        .flat_map(|draw| [ShaderStage::Vertex, ShaderStage::Fragment].map(|stage| (draw, stage)));
    both.chain([OCCLUDER_DEPTH, SPLAT_RESOLVE].map(|draw| (draw, ShaderStage::Fragment)))
}

/// Which of [`SIMULATE_CULL`]'s and [`CULL`]'s variants a device runs.
pub fn cull_variant(subgroups: bool, copy_blades: bool) -> usize {
    subgroups as usize + 2 * copy_blades as usize
}

/// Every pass the Vulkan renderer runs from the core's WGSL.
pub fn wgsl_passes() -> impl Iterator<Item = PipelineSource> {
    [
        TRAMPLE,
        REBASE_FIELD,
        STREAM_TILES,
        TILE_CULL,
        HIZ_REDUCE,
        PATCH_CULL,
        GENERATE_DRAWN,
        GENERATE_PLACE,
        GENERATED_SCAN,
        DRAWN_BLADES,
        SPLAT_BLADES,
        SPLAT_TILES,
        RASTER_BLADES,
        BILLBOARD_RASTER,
        INSTANCED_RASTER,
        BANDWIDTH,
        SIMULATE,
    ]
    .into_iter()
    .chain(GENERATE_SPLATS)
    .chain(SIMULATE_CULL)
    .chain(CULL)
    .chain(ORDER)
    .chain(CALLER_DEPTH_FOLD)
}

/// The GLSL stages' SPIR-V (tessellation, mesh), by shader file name, and the core's WESL modules that
/// replace the built-in ones (none: the built-in ones).
#[derive(Clone, Debug)]
pub struct ShaderSet {
    modules: HashMap<&'static str, Vec<u8>>,
    wesl: ShaderModules,
}

impl ShaderSet {
    /// The shaders built into sward (the GLSL stages compiled on the first call).
    pub fn embedded() -> ShaderSet {
        static BUILT_IN: OnceLock<ShaderSet> = OnceLock::new();
        BUILT_IN
            .get_or_init(|| {
                let built_in = ShaderSet {
                    modules: HashMap::new(),
                    wesl: ShaderModules::built_in(),
                };
                // Held by the tests, which compile the built-in stages.
                built_in
                    .with_glsl_stages(None)
                    .unwrap_or_else(|e| panic!("the built-in GLSL stages do not compile: {e}"))
            })
            .clone()
    }

    /// The core's WESL modules `dir` holds (`NAME.wesl`) in place of the built-in ones, and the
    /// tessellation and mesh routes' GLSL stages compiled from `dir` where it holds any of them
    /// (else the built-in ones); the error is glslang's or naga's message for the first broken
    /// stage.
    pub fn compile(dir: &Path) -> Result<ShaderSet, String> {
        let set = ShaderSet {
            modules: HashMap::new(),
            wesl: ShaderModules::from_dir(dir)?,
        };
        let glsl_here = GLSL_STAGES.iter().any(|(name, _)| dir.join(name).exists());
        let set = set.with_glsl_stages(glsl_here.then_some(dir))?;
        for pass in wgsl_passes() {
            set.wgsl(&pass, &[], false)?;
        }
        for (draw, stage) in wgsl_draw_stages() {
            set.wgsl_stage(&draw, stage, &[], false)?;
        }
        Ok(set)
    }

    /// The SPIR-V of the core's compute pass `pass` (one of [`wgsl_passes`]), its overrides
    /// set as `constants` (id, value) say, with naga's safety checks if `checked` (`wgsl.rs`).
    pub fn wgsl(&self, pass: &PipelineSource, constants: &[(u32, u32)], checked: bool) -> Result<Vec<u32>, String> {
        self.wgsl_stage(pass, ShaderStage::Compute, constants, checked)
    }

    /// The SPIR-V of stage `stage` of the core's pipeline `pass`: a compute pass's, or a draw's
    /// (one of [`wgsl_draw_stages`]) vertex or fragment stage, as [`ShaderSet::wgsl`] makes it.
    pub fn wgsl_stage(
        &self,
        pass: &PipelineSource,
        stage: ShaderStage,
        constants: &[(u32, u32)],
        checked: bool,
    ) -> Result<Vec<u32>, String> {
        let entry = entry_point(pass, stage)?;
        let text = self.wesl.text(pass).map_err(|e| e.to_string())?;
        crate::wgsl::spirv(&text, (entry, stage), constants, checked)
    }

    /// The SPIR-V of the GLSL stage in file `name` (`blade.tese`).
    pub fn get(&self, name: &str) -> &[u8] {
        &self.modules[name]
    }

    /// This set with the GLSL stages compiled: their GLSL from `dir` (None: the built-in
    /// GLSL), the core's functions they call from this set's WESL modules.
    fn with_glsl_stages(mut self, dir: Option<&Path>) -> Result<ShaderSet, String> {
        let text = self.wesl.text(&TESSELLATION).map_err(|e| e.to_string())?;
        let core = crate::wgsl::glsl_functions(&text, TESSELLATION.entry)?;
        for (name, built_in) in GLSL_STAGES {
            let words = match dir {
                Some(dir) => {
                    let path = dir.join(name);
                    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
                    crate::glsl::compile_stage(dir, &path, &text, &core)?
                }
                None => crate::glsl::compile_stage(Path::new("."), Path::new(name), built_in, &core)?,
            };
            self.modules.insert(name, spirv_bytes(&words));
        }
        Ok(self)
    }
}

/// The entry point of stage `stage` of the core's pipeline `pass`: a draw's fragment stage's, or
/// its vertex stage's or a compute pass's.
pub fn entry_point(pass: &PipelineSource, stage: ShaderStage) -> Result<&'static str, String> {
    match (stage, pass.fragment) {
        (ShaderStage::Fragment, Some(fragment)) => Ok(fragment),
        (ShaderStage::Fragment, None) => Err(format!("{} has no fragment stage", pass.name)),
        _ => Ok(pass.entry),
    }
}

/// SPIR-V words as the bytes a shader module is made of.
pub(crate) fn spirv_bytes(words: &[u32]) -> Vec<u8> {
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}

/// The stage of the GLSL file `name`, by its extension.
pub(crate) fn stage_flag(name: &str) -> vk::ShaderStageFlags {
    match name.rsplit('.').next() {
        Some("vert") => vk::ShaderStageFlags::VERTEX,
        Some("tesc") => vk::ShaderStageFlags::TESSELLATION_CONTROL,
        Some("tese") => vk::ShaderStageFlags::TESSELLATION_EVALUATION,
        Some("frag") => vk::ShaderStageFlags::FRAGMENT,
        Some("mesh") => vk::ShaderStageFlags::MESH_EXT,
        _ => vk::ShaderStageFlags::COMPUTE,
    }
}
