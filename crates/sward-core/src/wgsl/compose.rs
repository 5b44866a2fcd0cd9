//! The core's WGSL joined by WESL, with the `wesl` crate Bevy's shader cache composes its own
//! shaders with: a pipeline's text is its root module (`shaders/NAME.wesl`, the one with its
//! entry points) and what it imports, under the features it is composed with (`@if`). Each
//! module imports what it uses (`import super::blade::Blade;`), so a pipeline carries exactly
//! the declarations its entry points reach, in the order WESL links them.

use std::borrow::Cow;
use std::collections::HashMap;
use std::sync::{Mutex, OnceLock};

use wesl::pass::Feature;
use wesl::resolver::VirtualResolver;
use wesl::{CompileOptions, ManglerKind};

/// One of the core's WESL modules: `include!`d by name.
macro_rules! modules {
    ($($name:literal),* $(,)?) => {
        /// The core's WESL modules, by name (`shaders/NAME.wesl`), which both renderers'
        /// pipelines are composed from.
        pub const MODULES: &[(&str, &str)] =
            &[$(($name, include_str!(concat!("../../shaders/", $name, ".wesl")))),*];
    };
}

modules!(
    "bandwidth",
    "bezier_strips",
    "billboard_quads",
    "billboard_raster",
    "billboards",
    "bitonic",
    "blade",
    "blade_fragment",
    "bucket_runs",
    "buckets",
    "caller_depth",
    "caller_depth_fold",
    "cull",
    "cull_join",
    "cull_slots",
    "drawn_blades",
    "engine",
    "exact_order",
    "generated",
    "generate_grid",
    "generated_blades",
    "generated_commands",
    "generated_scan",
    "generated_strips",
    "instanced_raster",
    "ground_grid",
    "hiz_reduce",
    "listed",
    "noise",
    "occluder_depth",
    "occlusion",
    "order",
    "outline",
    "pass_view",
    "patch_cull",
    "patches",
    "physics",
    "pyramid",
    "pyramid_levels",
    "raster_blades",
    "scenery",
    "shading",
    "simulate",
    "splat",
    "splat_blades",
    "splat_resolve",
    "splat_words",
    "splat_tiles",
    "stream",
    "stream_cells",
    "strip_surface",
    "strips",
    "tessellation",
    "tile_cull",
    "tiles",
    "trample",
    "trample_map",
    "twin",
    "visibility",
);

/// How a text is composed from its root module.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum Linking {
    /// A pipeline's: the declarations its entry points reach, those of imported modules
    /// renamed by their module (WESL's escaped paths), so two modules may use one name.
    Pipeline,
    /// A library an engine's shaders import from: every declaration of every module the root
    /// imports, under its own name.
    Library,
}

/// The WESL compiler's options for `features` and `linking`.
fn options(features: &[&str], linking: Linking) -> CompileOptions {
    let mut options = CompileOptions {
        mangler: match linking {
            Linking::Pipeline => ManglerKind::Escape,
            Linking::Library => ManglerKind::None,
        },
        strip: linking == Linking::Pipeline,
        ..CompileOptions::default()
    };
    for feature in features {
        options.features.flags.insert(feature.to_string(), Feature::Enable);
    }
    options
}

/// The resolver that finds each module at `package::NAME` (the text in `replaced` where it
/// names the module, else the built-in one), and at `package::declared` what sward-core
/// declares for the shaders (`declared::wgsl`).
fn resolver(replaced: &[(String, String)]) -> VirtualResolver<'static> {
    let mut resolver = VirtualResolver::new();
    let declared = "package::declared".parse().expect("a WESL path");
    resolver.add_module(declared, Cow::Owned(crate::declared::wgsl()));
    for (name, text) in MODULES {
        let path = format!("package::{name}")
            .parse()
            .expect("a module's name is a WESL path");
        let text = match replaced.iter().find(|(n, _)| n == name) {
            Some((_, own)) => Cow::Owned(own.clone()),
            None => Cow::Borrowed(*text),
        };
        resolver.add_module(path, text);
    }
    resolver
}

/// The WGSL of root module `root` composed with `features` as a pipeline's, with the modules
/// of `replaced` (name, text) in place of the built-in ones of those names: a shader variant
/// measured with the same binary (`--shaders DIR`). Not kept: composed anew each time.
pub(crate) fn compose_replaced(root: &str, features: &[&str], replaced: &[(String, String)]) -> Result<String, String> {
    if replaced.is_empty() {
        return compose(root, features, Linking::Pipeline);
    }
    let path = format!("package::{root}")
        .parse()
        .map_err(|_| format!("{root} is not a module's name"))?;
    Ok(
        wesl::compile(&path, &options(features, Linking::Pipeline), &resolver(replaced))
            .map_err(|e| e.to_string())?
            .syntax
            .to_string(),
    )
}

/// The WGSL of root module `root` composed with `features` (the others off), or WESL's message.
pub(crate) fn compose(root: &str, features: &[&str], linking: Linking) -> Result<String, String> {
    let key = (root.to_string(), features.join(","), linking);
    let composed = COMPOSED.get_or_init(Default::default);
    if let Some(text) = lock(composed).get(&key) {
        return Ok(text.clone());
    }
    let path = format!("package::{root}")
        .parse()
        .map_err(|_| format!("{root} is not a module's name"))?;
    let text = wesl::compile(&path, &options(features, linking), &resolver(&[]))
        .map_err(|e| e.to_string())?
        .syntax
        .to_string();
    lock(composed).insert(key, text.clone());
    Ok(text)
}

/// Texts composed so far: each pipeline's, composed once a process (a renderer makes its
/// pipelines again for each device).
type Composed = Mutex<HashMap<(String, String, Linking), String>>;
static COMPOSED: OnceLock<Composed> = OnceLock::new();

/// The composed texts, also after a thread panicked holding them (a text is whole or absent).
fn lock(composed: &Composed) -> std::sync::MutexGuard<'_, HashMap<(String, String, Linking), String>> {
    composed.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}
