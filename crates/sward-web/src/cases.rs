//! The cases a page can draw or measure, and the far field's routes: plain Rust on every
//! target (a native build checks them), read by the page's calls (`page`).

use sward_core::instanced::Technique;
use sward_core::Scene;
use sward_portable::ShaderModules;

/// The shipped scenes a page can grow, by name, from their files at build time.
const SCENES: [(&str, &str); 9] = [
    ("meadow", include_str!("../../../scenes/meadow.toml")),
    ("hills", include_str!("../../../scenes/hills.toml")),
    ("trample", include_str!("../../../scenes/trample.toml")),
    ("planet", include_str!("../../../scenes/planet.toml")),
    ("prairie", include_str!("../../../scenes/prairie.toml")),
    ("landscape", include_str!("../../../scenes/landscape.toml")),
    ("trail", include_str!("../../../scenes/trail.toml")),
    ("park", include_str!("../../../scenes/park.toml")),
    ("openworld", include_str!("../../../scenes/openworld.toml")),
];

/// The cases a page can measure: every shipped scene, and the meadow by each technique.
pub fn case_names() -> Vec<String> {
    let scenes = SCENES.iter().map(|(name, _)| name.to_string());
    let meadows = Technique::ALL[1..].iter().map(|t| format!("meadow·{}", t.name()));
    scenes.chain(meadows).collect()
}

/// The case `name` names: a shipped scene, drawn by the technique after a `·` where there is
/// one.
pub fn case_scene(name: &str) -> Result<Scene, String> {
    let (scene_name, technique) = match name.split_once('·') {
        Some((scene, technique)) => (scene, Some(technique)),
        None => (name, None),
    };
    let Some((_, text)) = SCENES.iter().find(|(n, _)| *n == scene_name) else {
        return Err(format!(
            "no case named '{name}'; the cases are {}",
            case_names().join(", ")
        ));
    };
    let mut scene = Scene::from_toml(text, scene_name).map_err(|e| e.to_string())?;
    if let Some(technique) = technique {
        scene.technique = *Technique::ALL
            .iter()
            .find(|t| t.name() == technique)
            .ok_or_else(|| format!("no technique named '{technique}' in '{name}'"))?;
    }
    Ok(scene)
}

/// How the far field beyond the Bezier blades is drawn: `splatted` (the device's own choice: on
/// a browser's WebGPU, into 32-bit cells) or `drawn` (as geometry).
pub fn far_field_modules(far_field: &str) -> Result<ShaderModules, String> {
    let modules = ShaderModules::built_in();
    match far_field {
        "splatted" => Ok(modules),
        "drawn" => Ok(modules.with_narrow_splats(false)),
        other => Err(format!("no far field route named '{other}'; it is splatted or drawn")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_case_a_page_offers_grows_its_scene() {
        for name in case_names() {
            let scene = case_scene(&name).unwrap_or_else(|e| panic!("{name}: {e}"));
            if let Some((_, technique)) = name.split_once('·') {
                assert_eq!(scene.technique.name(), technique);
            }
        }
        let wrong = case_scene("medow").unwrap_err();
        assert!(
            wrong.contains("no case named 'medow'") && wrong.contains("meadow·billboard"),
            "{wrong}"
        );
        assert!(far_field_modules("geometry").is_err());
        assert_eq!(far_field_modules("drawn").unwrap().narrow_splats(), Some(false));
        assert_eq!(far_field_modules("splatted").unwrap().narrow_splats(), None);
    }
}
