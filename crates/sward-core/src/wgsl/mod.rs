//! The grass core in WGSL, which both renderers run: its WESL modules (`shaders/*.wesl`, joined
//! per pipeline by `compose.rs`, with what [`declared`](crate::declared) declares as the module
//! `declared`), a pipeline's source (its root module, entry points and features), the modules a
//! renderer composes from (the built-in ones, or a shader folder's in place of theirs), the
//! passes both renderers run whole, and the library an engine's own passes draw the blades
//! from. The portable renderer hands the composed text to wgpu, the Vulkan renderer to naga's
//! SPIR-V output; neither keeps a copy of a pass.

mod compose;
pub mod spirv;
pub mod splatting;

pub use compose::MODULES;

use compose::{compose, compose_replaced, Linking};

/// A pipeline's WESL that did not compose: the pipeline (or module) and WESL's message, on one
/// line.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("the {pipeline} shader does not compose: {message}")]
pub struct ShaderError {
    /// The pipeline, or the module composed as a library.
    pub pipeline: &'static str,
    /// WESL's message, its lines joined.
    pub message: String,
}

impl ShaderError {
    fn of(pipeline: &'static str, message: &str) -> ShaderError {
        ShaderError {
            pipeline,
            message: message.split_whitespace().collect::<Vec<_>>().join(" "),
        }
    }
}

/// A pipeline's shader: its name, its entry points and the module it is composed from.
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

/// The WESL feature of the pipelines that use subgroup operations.
pub const SUBGROUPS: &str = "subgroups";

impl PipelineSource {
    /// A compute pipeline `entry` of module `root`, named `name`.
    pub const fn compute(name: &'static str, entry: &'static str, root: &'static str) -> PipelineSource {
        PipelineSource {
            name,
            entry,
            fragment: None,
            root,
            features: &[],
        }
    }

    /// A draw `vertex` then `fragment` of module `root`, named `name`.
    pub const fn draw(
        name: &'static str,
        vertex: &'static str,
        fragment: &'static str,
        root: &'static str,
    ) -> PipelineSource {
        PipelineSource {
            name,
            entry: vertex,
            fragment: Some(fragment),
            root,
            features: &[],
        }
    }

    /// The whole WGSL a device compiles for this pipeline: its root module and what it
    /// imports, composed by WESL with its features.
    pub fn text(&self) -> Result<String, ShaderError> {
        compose(self.root, self.features, Linking::Pipeline).map_err(|message| ShaderError::of(self.name, &message))
    }

    /// Whether the pipeline uses subgroup operations.
    pub fn uses_subgroups(&self) -> bool {
        self.features.contains(&SUBGROUPS)
    }

    /// The whole WGSL as a browser's WebGPU compiles it: with WGSL's `enable subgroups;` first
    /// where the pipeline uses them, which wgpu's naga (30) refuses and a browser's compiler
    /// needs.
    pub fn browser_text(&self) -> Result<String, ShaderError> {
        ShaderModules::built_in().browser_text(self)
    }
}

/// The core's WESL modules a renderer makes its pipelines from: the built-in ones, with those a
/// shader directory holds in place of theirs (`--shaders DIR`: a variant measured with the same
/// binary), and whether the device is to compile them with WebGPU's runtime checks.
#[derive(Clone, Debug, Default)]
pub struct ShaderModules {
    replaced: std::sync::Arc<[(String, String)]>,
    checked: bool,
    narrow_splats: Option<bool>,
    single_splat_binding: bool,
    splat_surface: bool,
}

/// The WESL feature of the splatting passes' 32-bit cells ([`ShaderModules::with_narrow_splats`]).
pub const NARROW_SPLATS: &str = "narrow_splats";
/// The WESL feature of splat cells that keep a surface for an engine to light
/// ([`ShaderModules::with_splat_surface`]).
pub const SPLAT_SURFACE: &str = "splat_surface";
/// The WESL feature of 32-bit cells bound once a pass
/// ([`ShaderModules::with_single_splat_binding`]).
pub const SINGLE_SPLAT_BINDING: &str = "single_splat_binding";

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
            ..ShaderModules::default()
        }
    }

    /// These modules, compiled with the runtime checks WebGPU asks of untrusted shaders where
    /// `checked` (a bound on every index and loop, workgroup memory zeroed before a workgroup
    /// starts: to measure what they cost). Without them (the default) a device compiles the
    /// passes as the Vulkan renderer runs them: their inputs are sward's own, every index into
    /// a buffer is kept within it by the pass itself and every loop ends. A browser's WebGPU
    /// checks whatever it is given.
    pub fn with_checks(self, checked: bool) -> ShaderModules {
        ShaderModules { checked, ..self }
    }

    /// Whether the device is to compile these modules with WebGPU's runtime checks
    /// ([`ShaderModules::with_checks`]).
    pub fn checked(&self) -> bool {
        self.checked
    }

    /// These modules with the splatting passes' cells 32 bits wide where `narrow` (the
    /// [`NARROW_SPLATS`] feature on in every pipeline): a 16-bit depth key above a 16-bit colour,
    /// kept by a 32-bit atomicMin, as a device without 64-bit atomic min and max (WebGPU, GL)
    /// splats; where not `narrow`, such a device splats nothing (its far field drawn).
    pub fn with_narrow_splats(self, narrow: bool) -> ShaderModules {
        ShaderModules {
            narrow_splats: Some(narrow),
            ..self
        }
    }

    /// These modules with the 32-bit cells bound once a pass where `single` (the
    /// [`SINGLE_SPLAT_BINDING`] feature on beside [`NARROW_SPLATS`]): their words read and stored
    /// through the cells' own atomics, as a browser's WebGPU needs (it refuses a pass that binds
    /// one buffer twice where either binding is writable), rather than through a second, plain
    /// view of the buffer (2 ms of 17 faster at the instanced 2^26 grass on the H100), which
    /// every native backend allows.
    pub fn with_single_splat_binding(self, single: bool) -> ShaderModules {
        ShaderModules {
            single_splat_binding: single,
            ..self
        }
    }

    /// These modules with the splat cells keeping, where `surface`, each point's surface (its
    /// albedo, normal and height along the blade: splat_words.wesl) in place of the colour
    /// sward's lighting gives it (the [`SPLAT_SURFACE`] feature on in every pipeline): for an
    /// engine that lights the splats in its own pass, as sward-bevy does with Bevy's lights. A
    /// narrow (32-bit) cell keeps the albedo alone, as its colour.
    pub fn with_splat_surface(self, surface: bool) -> ShaderModules {
        ShaderModules {
            splat_surface: surface,
            ..self
        }
    }

    /// Whether 32-bit cells are asked to be bound once a pass
    /// ([`ShaderModules::with_single_splat_binding`]; a browser's device binds them so anyway).
    pub fn single_splat_binding(&self) -> bool {
        self.single_splat_binding
    }

    /// Whether the splatting passes' cells are asked to be 32 bits wide
    /// ([`ShaderModules::with_narrow_splats`]; None: as the device allows).
    pub fn narrow_splats(&self) -> Option<bool> {
        self.narrow_splats
    }

    /// The built-in modules with those folder `dir` holds (`NAME.wesl` for a module NAME of
    /// [`MODULES`]) in place of theirs; a folder or file that cannot be read said in one
    /// sentence.
    pub fn from_dir(dir: &std::path::Path) -> Result<ShaderModules, String> {
        if !dir.is_dir() {
            return Err(format!("{} is not a folder of shaders", dir.display()));
        }
        let mut replaced = Vec::new();
        for (name, _) in MODULES {
            let path = dir.join(format!("{name}.wesl"));
            if path.exists() {
                let bytes = crate::files::read(&path)?;
                let text = String::from_utf8(bytes).map_err(|_| format!("{} is not UTF-8 text", path.display()))?;
                replaced.push((name.to_string(), text));
            }
        }
        Ok(ShaderModules::replacing(replaced))
    }

    /// The WGSL of pipeline `source` composed from these modules.
    pub fn text(&self, source: &PipelineSource) -> Result<String, ShaderError> {
        let narrow = (self.narrow_splats == Some(true)).then_some(NARROW_SPLATS);
        let single = (narrow.is_some() && self.single_splat_binding).then_some(SINGLE_SPLAT_BINDING);
        let surface = self.splat_surface.then_some(SPLAT_SURFACE);
        let features: Vec<&str> = source
            .features
            .iter()
            .copied()
            .chain(narrow)
            .chain(single)
            .chain(surface)
            .collect();
        compose_replaced(source.root, &features, &self.replaced)
            .map_err(|message| ShaderError::of(source.name, &message))
    }

    /// The same as a browser's WebGPU compiles it ([`PipelineSource::browser_text`]).
    pub fn browser_text(&self, source: &PipelineSource) -> Result<String, ShaderError> {
        let text = self.text(source)?;
        Ok(match source.uses_subgroups() {
            true => format!("enable subgroups;\n{text}"),
            false => text,
        })
    }
}

/// The trample map's frame, before the simulation reads it: the one pass that writes the map
/// (`trample_pass`). Both renderers run it whole.
pub const TRAMPLE_SOURCE: PipelineSource = PipelineSource {
    features: &["trample_pass"],
    ..PipelineSource::compute("trample", "trample", "trample")
};

/// The streamed field's passes, before the trample map and the simulation: every held blade
/// carried to a moved frame origin, the blades of the tiles entering the window made. Both
/// renderers run them (the Vulkan renderer's list of entering tiles composed after its tiles).
pub const STREAM_SOURCES: [PipelineSource; 2] = [
    PipelineSource::compute("rebase_field", "rebase_field", "stream"),
    PipelineSource::compute("make_entering_tiles", "make_entering_tiles", "stream"),
];

/// The bindings of the engine library ([`engine_library`]), in its bind group: the numbers
/// [`declared::bindings`](crate::declared::bindings) declares, which the library's
/// declarations name.
pub mod engine_bindings {
    use crate::declared::bindings;

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
pub fn engine_library(group: u32) -> Result<String, ShaderError> {
    Ok(library("engine")?.replace("@group(0)", &format!("@group({group})")))
}

/// Module `root` (one of [`MODULES`]) as a library: every declaration of it and of each module
/// it reaches, under its own name, its bindings in group 0.
pub fn library(root: &'static str) -> Result<String, ShaderError> {
    compose(root, &[], Linking::Library).map_err(|message| ShaderError::of(root, &message))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_folder_s_module_stands_in_for_the_built_in_one_and_its_fault_is_one_line() {
        ShaderModules::built_in()
            .text(&TRAMPLE_SOURCE)
            .unwrap_or_else(|e| panic!("{e}"));
        let broken = ShaderModules::replacing(vec![("trample".into(), "fn (\n{".into())]);
        let error = broken.text(&TRAMPLE_SOURCE).expect_err("a module that does not parse");
        assert_eq!(error.pipeline, "trample");
        assert!(!error.message.is_empty() && !error.message.contains('\n'), "{error}");
        let elsewhere = ShaderModules::replacing(vec![("splat".into(), "fn (".into())]);
        elsewhere
            .text(&TRAMPLE_SOURCE)
            .unwrap_or_else(|e| panic!("a module trample does not import: {e}"));
    }

    #[test]
    fn the_engine_library_keeps_the_names_an_engine_imports_in_its_group() {
        let library = engine_library(2).unwrap_or_else(|e| panic!("{e}"));
        for function in [
            "strip_place",
            "blade_point",
            "strip_walk",
            "generated_point",
            "billboard_corner",
            "billboard_painted",
            "blade_look",
            "albedo_variation",
            "may_flower",
        ] {
            assert!(
                library.contains(&format!("fn {function}(")),
                "the library lacks {function}"
            );
        }
        let blocks = crate::declared::BLOCKS.map(|b| format!("{}: {}", b.var, b.ty));
        for binding in blocks.iter().map(String::as_str).chain([
            "blades: array<Blade>",
            "visible: array<u32>",
            "listed: array<vec4<u32>>",
        ]) {
            assert!(library.contains(binding), "the library lacks {binding}");
        }
        assert!(!library.contains("@group(0)"), "a binding was left in group 0");
        assert!(
            !library.contains("@compute") && !library.contains("@vertex"),
            "an entry point in the library"
        );
    }
}
