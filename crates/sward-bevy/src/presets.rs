//! Presets by biome: twelve scenes of grass — lawn to reed marsh, savanna to frosted meadow —
//! shipped inside the crate as scene assets (`embedded://sward_bevy/presets/NAME.grass.toml`),
//! each a mix of kinds of grass with flowering stalks or flowers, the whole chain from Bezier
//! blades with their physics near the eye to billboards at the horizon. A game loads one as any
//! scene asset (`GrassSource(asset_server.load(GrassPreset::Meadow.path()))`), or takes its
//! scene to change in code (`GrassPreset::Meadow.scene()`).

use bevy::app::App;
use sward_core::Scene;

/// Declares the presets: each variant, its file's name and its file.
macro_rules! presets {
    ($($preset:ident $name:literal $file:literal,)*) => {
        /// A shipped scene of grass, by biome.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, bevy::reflect::Reflect)]
        pub enum GrassPreset {
            $(#[doc = concat!("`", $name, "`")] $preset,)*
        }

        impl GrassPreset {
            /// Every preset.
            pub const ALL: &[GrassPreset] = &[$(GrassPreset::$preset,)*];

            /// Its name, its file's (`wildflower-meadow`).
            pub fn name(self) -> &'static str {
                match self {
                    $(GrassPreset::$preset => $name,)*
                }
            }

            /// Its scene file's text.
            fn text(self) -> &'static str {
                match self {
                    $(GrassPreset::$preset => include_str!($file),)*
                }
            }
        }

        /// The presets as embedded assets of the app's asset server.
        pub(crate) fn build(app: &mut App) {
            if app.world().contains_resource::<bevy::asset::io::embedded::EmbeddedAssetRegistry>() {
                $(bevy::asset::embedded_asset!(app, $file);)*
            }
        }
    };
}

presets! {
    Lawn "lawn" "presets/lawn.grass.toml",
    Meadow "meadow" "presets/meadow.grass.toml",
    WildflowerMeadow "wildflower-meadow" "presets/wildflower-meadow.grass.toml",
    Prairie "prairie" "presets/prairie.grass.toml",
    Pampas "pampas" "presets/pampas.grass.toml",
    ReedMarsh "reed-marsh" "presets/reed-marsh.grass.toml",
    DuneGrass "dune-grass" "presets/dune-grass.grass.toml",
    Savanna "savanna" "presets/savanna.grass.toml",
    Alpine "alpine" "presets/alpine.grass.toml",
    ForestFloor "forest-floor" "presets/forest-floor.grass.toml",
    FrostedMeadow "frosted-meadow" "presets/frosted-meadow.grass.toml",
    Stylised "stylised" "presets/stylised.grass.toml",
}

impl GrassPreset {
    /// The asset path the plugin serves it at: `embedded://sward_bevy/presets/NAME.grass.toml`.
    pub fn path(self) -> String {
        format!("embedded://sward_bevy/presets/{}.grass.toml", self.name())
    }

    /// Its scene, to change in code before the grass is grown from it.
    pub fn scene(self) -> Scene {
        Scene::from_toml(self.text(), self.name()).expect("a shipped preset is a valid scene")
    }
}
