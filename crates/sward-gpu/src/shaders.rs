//! The SPIR-V of every stage: the GLSL stages in `shaders/` compiled by `build.rs` and embedded
//! in the binary, or compiled at run time from a shader directory (the viewer's hot reload,
//! `--shaders`); the passes written once in the core's WGSL (sward-portable) translated by naga
//! as their pipelines are made, with the modules a shader directory holds in place of the
//! built-in ones.

use std::borrow::Cow;
use std::collections::HashMap;
use std::path::Path;

use ash::vk;
use sward_portable::{PipelineSource, MODULES, PIPELINES};

macro_rules! spirv {
    ($file:literal) => {
        include_bytes!(concat!(env!("OUT_DIR"), "/", $file))
    };
}

/// The simulate pass's SPIR-V (tests build pipelines of it alone).
pub const SIMULATE_COMP: &[u8] = spirv!("simulate_comp.spv");
/// The cull pass's SPIR-V.
pub const CULL_COMP: &[u8] = spirv!("cull_comp.spv");

/// (file name, embedded SPIR-V) of every stage.
const EMBEDDED: [(&str, &[u8]); 44] = [
    ("collider.vert", spirv!("collider_vert.spv")),
    ("collider.frag", spirv!("collider_frag.spv")),
    ("simulate.comp", SIMULATE_COMP),
    ("cull.comp", CULL_COMP),
    ("simulate_cull.comp", spirv!("simulate_cull_comp.spv")),
    ("order_buckets.comp", spirv!("order_buckets_comp.spv")),
    ("order_counts.comp", spirv!("order_counts_comp.spv")),
    ("order_scan.comp", spirv!("order_scan_comp.spv")),
    ("order_blades.comp", spirv!("order_blades_comp.spv")),
    ("order_sort.comp", spirv!("order_sort_comp.spv")),
    ("drawn_blades.comp", spirv!("drawn_blades_comp.spv")),
    ("tile_cull.comp", spirv!("tile_cull_comp.spv")),
    ("stream_tiles.comp", spirv!("stream_tiles_comp.spv")),
    ("rebase_field.comp", spirv!("rebase_field_comp.spv")),
    ("splat_blades.comp", spirv!("splat_blades_comp.spv")),
    ("raster_blades.comp", spirv!("raster_blades_comp.spv")),
    ("splat_tiles.comp", spirv!("splat_tiles_comp.spv")),
    ("billboard_raster.comp", spirv!("billboard_raster_comp.spv")),
    ("blade_strip.vert", spirv!("blade_strip_vert.spv")),
    ("blade.mesh", spirv!("blade_mesh.spv")),
    ("bandwidth.comp", spirv!("bandwidth_comp.spv")),
    ("hiz_reduce.comp", spirv!("hiz_reduce_comp.spv")),
    ("occluder.frag", spirv!("occluder_frag.spv")),
    ("caller_depth.comp", spirv!("caller_depth_comp.spv")),
    ("caller_depth_ms.comp", spirv!("caller_depth_ms_comp.spv")),
    ("instanced.comp", spirv!("instanced_comp.spv")),
    ("instanced_drawn.comp", spirv!("instanced_drawn_comp.spv")),
    ("instanced_raster.comp", spirv!("instanced_raster_comp.spv")),
    ("generated_scan.comp", spirv!("generated_scan_comp.spv")),
    ("patch_cull.comp", spirv!("patch_cull_comp.spv")),
    ("instanced.vert", spirv!("instanced_vert.spv")),
    ("splat.frag", spirv!("splat_frag.spv")),
    ("billboard.vert", spirv!("billboard_vert.spv")),
    ("billboard.frag", spirv!("billboard_frag.spv")),
    ("billboard_depth.frag", spirv!("billboard_depth_frag.spv")),
    ("billboard_nearest.frag", spirv!("billboard_nearest_frag.spv")),
    ("blade.vert", spirv!("blade_vert.spv")),
    ("blade.tesc", spirv!("blade_tesc.spv")),
    ("blade.tese", spirv!("blade_tese.spv")),
    ("blade.frag", spirv!("blade_frag.spv")),
    ("ground.vert", spirv!("ground_vert.spv")),
    ("ground.frag", spirv!("ground_frag.spv")),
    ("sky.vert", spirv!("sky_vert.spv")),
    ("sky.frag", spirv!("sky_frag.spv")),
];

/// The passes the Vulkan renderer runs from the core's WGSL, by their portable pipeline's name.
pub const WGSL_PASSES: [&str; 1] = ["trample"];

/// The core's pipeline `name` (one of [`WGSL_PASSES`]).
fn core_pass(name: &str) -> &'static PipelineSource {
    PIPELINES
        .iter()
        .find(|p| p.name == name)
        .unwrap_or_else(|| panic!("the core has no pipeline {name}"))
}

/// SPIR-V for every stage, by shader file name, and the core's WESL modules that replace the
/// built-in ones (none: the built-in ones).
#[derive(Clone, Debug)]
pub struct ShaderSet {
    modules: HashMap<&'static str, Cow<'static, [u8]>>,
    wesl: Vec<(String, String)>,
}

impl ShaderSet {
    /// The SPIR-V built into sward.
    pub fn embedded() -> ShaderSet {
        ShaderSet {
            modules: EMBEDDED
                .iter()
                .map(|(name, spirv)| (*name, Cow::Borrowed(*spirv)))
                .collect(),
            wesl: Vec::new(),
        }
    }

    /// Compile every GLSL stage from `dir`, with the core's WESL modules `dir` holds
    /// (`NAME.wesl`) in place of the built-in ones; the error is glslang's or naga's message for
    /// the first broken stage.
    pub fn compile(dir: &Path) -> Result<ShaderSet, String> {
        let mut modules = HashMap::new();
        for (name, _) in EMBEDDED {
            let words = crate::glsl::compile_file(dir, &dir.join(name))?;
            modules.insert(name, Cow::Owned(words.iter().flat_map(|w| w.to_le_bytes()).collect()));
        }
        let set = ShaderSet {
            modules,
            wesl: wesl_modules(dir)?,
        };
        for name in WGSL_PASSES {
            set.wgsl(name, &[])?;
        }
        Ok(set)
    }

    /// The SPIR-V of the core's compute pass `name` (one of [`WGSL_PASSES`]), its overrides
    /// set as `constants` (id, value) say.
    pub fn wgsl(&self, name: &str, constants: &[(u32, u32)]) -> Result<Vec<u32>, String> {
        let source = core_pass(name);
        let text = source.text_replaced(&self.wesl).map_err(|e| e.to_string())?;
        crate::wgsl::spirv(&text, (source.entry, crate::wgsl::ShaderStage::Compute), constants)
    }

    /// The entry point of the core's pass `name` (one of [`WGSL_PASSES`]).
    pub fn wgsl_entry(&self, name: &str) -> &'static str {
        core_pass(name).entry
    }

    /// The SPIR-V of the stage in file `name`.
    pub fn get(&self, name: &str) -> &[u8] {
        &self.modules[name]
    }

    /// (stage, SPIR-V) for the named files.
    pub fn stages(&self, names: &[&str]) -> Vec<(vk::ShaderStageFlags, &[u8])> {
        names.iter().map(|n| (stage_flag(n), self.get(n))).collect()
    }
}

/// The core's WESL modules in `dir` (name, text), those of the names the core has.
fn wesl_modules(dir: &Path) -> Result<Vec<(String, String)>, String> {
    let mut replaced = Vec::new();
    for (name, _) in MODULES {
        let path = dir.join(format!("{name}.wesl"));
        if path.exists() {
            let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
            replaced.push((name.to_string(), text));
        }
    }
    Ok(replaced)
}

fn stage_flag(name: &str) -> vk::ShaderStageFlags {
    match name.rsplit('.').next() {
        Some("vert") => vk::ShaderStageFlags::VERTEX,
        Some("tesc") => vk::ShaderStageFlags::TESSELLATION_CONTROL,
        Some("tese") => vk::ShaderStageFlags::TESSELLATION_EVALUATION,
        Some("frag") => vk::ShaderStageFlags::FRAGMENT,
        Some("mesh") => vk::ShaderStageFlags::MESH_EXT,
        _ => vk::ShaderStageFlags::COMPUTE,
    }
}
