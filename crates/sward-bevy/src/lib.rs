//! sward's responsive grass in Bevy.
//!
//! ```no_run
//! use bevy::prelude::*;
//! use sward_bevy::prelude::Scene;
//! use sward_bevy::{Grass, GrassCollider, SwardPlugin};
//!
//! fn main() {
//!     App::new()
//!         // Bevy's renderer on the device it opens (Vulkan, Metal, DX12, GL, WebGPU), and the plugin.
//!         .add_plugins((DefaultPlugins, SwardPlugin::default()))
//!         .add_systems(Startup, |mut commands: Commands| {
//!             // sward's default meadow, built in code: no file to read.
//!             commands.spawn(Grass::new(Scene::default()).expect("the meadow"));
//!             commands.spawn((
//!                 Camera3d::default(),
//!                 Transform::from_xyz(0.0, 4.0, -20.0).looking_at(Vec3::ZERO, Vec3::Y),
//!             ));
//!             // Bevy's sun lights the grass as it lights every mesh.
//!             commands.spawn((
//!                 DirectionalLight::default(),
//!                 Transform::from_xyz(1.0, 3.0, -2.0).looking_at(Vec3::ZERO, Vec3::Y),
//!             ));
//!             // A ball that presses the grass wherever it goes.
//!             commands.spawn((GrassCollider::sphere(0.5), Transform::from_xyz(0.0, 0.4, 0.0)));
//!         })
//!         .run();
//! }
//! ```
//!
//! - On the device Bevy opens itself, whatever its backend, sward's portable passes (WGSL
//!   through wgpu's safe API: `sward_portable`) simulate the Bezier blades (grown once, or
//!   a window that streams around the camera), cull them for each camera and generate the far
//!   grass (the instanced grass's levels, the billboards) into its lists, and Bevy draws all of
//!   it in its own passes: every technique, the open world to the horizon included. [`GrassRoute`] says which route the
//!   grass took; on an adapter without compute shaders or enough storage buffers it says why
//!   there is no grass (also said once as a warning), and the app runs on.
//! - Opt-in, with the `vulkan` feature (ash, gpu-allocator and a C++ build of glslang), for
//!   the Vulkan renderer's extras — its far grass splatted by compute, its
//!   tessellated and mesh-shader routes, sward's own pass ([`GrassLighting::Bevy`],
//!   [`GrassLighting::Scene`])
//!   — `render_plugin` opens Bevy's render device through `sward_wgpu::open`
//!   (`DefaultPlugins.set(sward_bevy::render_plugin()?)`): wgpu's Vulkan backend, with
//!   everything Bevy asks of the adapter and everything sward needs beside it; the plugin takes
//!   that device back with sward's Vulkan renderer on it.
//! - Either way, each frame the plugin fills sward's frame description from Bevy's world: each
//!   [`Grass`] entity's scene (change it from any system and the next frame uses it) and where
//!   its `Transform` places it (any number of fields, each moved, turned and scaled as the game
//!   runs), Bevy's camera, the colliders (every field's) and the lights. The fields a camera
//!   sees are culled together against one depth pyramid of all their occluders, and share one
//!   [`GrassBudget`] of Bezier blades (each entity's [`GrassShare`] says what it grows).
//! - Bevy draws the grass itself (the default, [`GrassLighting::Pbr`]), as items of its own
//!   opaque, prepass, deferred and shadow phases: sward's compute passes list the blades before
//!   Bevy renders, and Bevy's mesh and prepass pipelines (with sward's vertex stages) draw them:
//!   every technique on either device (on sward's Vulkan device the portable passes list every
//!   technique but the Bezier blades), the far grass casting within [`Grass::shadow_distance`].
//!   Bevy's PBR lights them, with every light's shadows and environment maps; they
//!   cast into Bevy's shadow maps (`NotShadowCaster` and `NotShadowReceiver` are followed), and
//!   are in the depth, normal and motion-vector prepass (each blade's own motion included) and
//!   a deferred camera's G-buffer. The grass follows `Visibility` and `RenderLayers`.
//!
//! - Or, on the device `render_plugin` (the `vulkan` feature) opens, with [`GrassLighting::Bevy`], sward's own pass
//!   draws it in Bevy's main pass, after the opaque meshes and before the transparent ones,
//!   into the camera's own colour (MSAA or not, HDR or not) and depth: depth-tested against
//!   Bevy's meshes, culled where their depth hides it (the plugin lets the cull read each 3D
//!   camera's depth texture), and lit by Bevy's sun (the brightest
//!   `DirectionalLight`), point and spot lights, ambient light, exposure and distance fog.
//!
//! - In either shape, a mesh with a [`GrassOccluder`] (a house, a rock) hides the grass behind
//!   it from the cull: packed into spheres inside it, as sward's own occluders are.
//!
//! - With the `avian` feature, Avian's colliders press and cut the grass in their own shapes
//!   (`GrassFromCollider` beside an Avian `Collider`).
//!
//! - Several cameras (split screen, a minimap): each of a frame's first
//!   [`sward_core::frame::VIEWS_PER_FRAME`] 3D cameras that see the grass culls it for itself, with
//!   its own level of detail; the first (by `Camera::order`) steps the grass and, where the
//!   field streams, carries the window.

#![warn(missing_docs)]

mod assets;
#[cfg(feature = "avian")]
mod avian;
mod budget;
mod changes;
mod components;
mod content;
mod edits;
mod ground;
mod lighting;
mod occluders;
mod presets;
mod quality;
mod render_world;
mod sampling;
mod spheres;
mod timings;

pub use assets::{GrassScene, GrassSource};
#[cfg(feature = "avian")]
pub use avian::{spheres_of, GrassFromCollider};
pub use budget::{GrassBudget, GrassShare};
pub use components::{Grass, GrassCollider};
pub use content::{GrassContent, GroundContent, MAX_HEIGHT_SAMPLES, MAX_MAP_TEXELS};
pub use edits::GrassEdit;
pub use ground::{ground_mesh, plane_reach, GrassGround};
pub use lighting::GrassLighting;
pub use occluders::GrassOccluder;
pub use presets::GrassPreset;
pub use quality::GrassQuality;
#[cfg(feature = "vulkan")]
pub use render_world::{render_plugin, render_plugin_with, SwardContext};
pub use render_world::{GrassRoute, GrassSplats};
pub use sampling::{GrassSampler, GrassSampling};
pub use spheres::GrassSpheres;
pub use timings::{GrassFrameTimes, GrassTimings};

use bevy::app::{App, Plugin};
use bevy::ecs::schedule::SystemSet;

/// Everything a game needs of sward: `use sward_bevy::prelude::*;`.
pub mod prelude {
    #[cfg(feature = "vulkan")]
    pub use crate::render_plugin;
    #[cfg(feature = "avian")]
    pub use crate::GrassFromCollider;
    pub use crate::{
        Grass, GrassBudget, GrassCollider, GrassContent, GrassEdit, GrassGround, GrassLighting, GrassOccluder,
        GrassPreset, GrassQuality, GrassRoute, GrassSampler, GrassSampling, GrassScene, GrassShare, GrassSource,
        GrassSpheres, GrassSystems, GrassTimings, GroundContent, SwardPlugin,
    };
    /// A stroke a game paints over the grass ([`Grass::paint`]).
    pub use sward_core::paint::Stroke;
    /// What [`GrassSampling::at`] says of the grass at a point.
    pub use sward_core::sample::GrassSample;
    /// A scene built or changed in code (every parameter of the grass).
    pub use sward_core::Scene;
    /// Whether sward reports the validation layer's messages ([`SwardPlugin::validation`]).
    #[cfg(feature = "vulkan")]
    pub use sward_gpu::Validation;
}

/// sward's systems in the main world, in `PostUpdate` after Bevy's asset events: grass grown
/// from its scene asset, the colliders and occluders followed, the cameras' depth made readable.
/// A system that changes a [`Grass`], a collider or an occluder in `Update` (or anywhere before
/// this set) is drawn the same frame.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct GrassSystems;

/// sward's grass in a Bevy app: add it beside `DefaultPlugins` (or, for the Vulkan renderer's
/// extras, `DefaultPlugins.set(sward_bevy::render_plugin()?)`).
pub struct SwardPlugin {
    /// Whether sward reports the validation layer's messages (tests ask for them:
    /// [`SwardContext`] holds them), with the `vulkan` feature.
    #[cfg(feature = "vulkan")]
    pub validation: sward_gpu::Validation,
    /// Whether sward measures itself each frame: its GPU passes and the host time it adds,
    /// in the [`GrassTimings`] resource (a few timestamp queries a frame).
    pub timing: bool,
    /// How Bevy's passes get the far field: splatted where the device can (the default), in
    /// 32-bit cells on any device, or drawn as geometry.
    pub splats: GrassSplats,
}

impl Default for SwardPlugin {
    /// Validation as sward's own default: where the layer is installed, in debug builds.
    fn default() -> Self {
        SwardPlugin {
            #[cfg(feature = "vulkan")]
            validation: sward_gpu::ContextDesc::default().validation,
            timing: false,
            splats: GrassSplats::default(),
        }
    }
}

impl Plugin for SwardPlugin {
    fn build(&self, app: &mut App) {
        reflected(app);
        assets::build(app);
        budget::build(app);
        changes::build(app);
        content::build(app);
        edits::build(app);
        presets::build(app);
        occluders::build(app);
        spheres::build(app);
        sampling::build(app);
        ground::build(app);
        #[cfg(feature = "avian")]
        avian::build(app);
        render_world::build(app, self.splats);
    }

    fn finish(&self, app: &mut App) {
        let timings = self.timing.then(GrassTimings::default);
        #[cfg(feature = "vulkan")]
        let route = {
            let context = sward_gpu::ContextDesc {
                validation: self.validation,
                ..Default::default()
            };
            let Some((route, context)) = render_world::finish(app, &context, timings.clone()) else {
                return;
            };
            if let Some(context) = context {
                app.insert_resource(context);
            }
            route
        };
        #[cfg(not(feature = "vulkan"))]
        let Some(route) = render_world::finish(app, timings.clone()) else {
            return;
        };
        app.insert_resource(route);
        if let Some(timings) = timings {
            app.insert_resource(timings);
        }
    }
}

/// The public components (and the scene inside a `Grass`, every table of it) in the app's type
/// registry: inspectors show and edit them, and reflection paths reach every scene value
/// (`"scene.field.blades"`).
fn reflected(app: &mut App) {
    app.register_type::<Grass>()
        .register_type::<GrassQuality>()
        .init_resource::<GrassQuality>()
        .register_type::<GrassCollider>()
        .register_type::<GrassOccluder>()
        .register_type::<GrassSource>()
        .register_type::<GrassSampling>()
        .register_type::<GrassGround>()
        .register_type::<GrassContent>()
        .register_type::<GrassLighting>()
        .register_type::<GrassScene>();
    #[cfg(feature = "avian")]
    app.register_type::<GrassFromCollider>();
}

#[cfg(test)]
mod tests {
    /// The README's Bevy example is this crate's documented one, which rustdoc compiles: the
    /// same lines after its first (the dependency line).
    #[test]
    fn the_readme_s_bevy_example_is_the_compiled_one() {
        let documented: Vec<&str> = include_str!("lib.rs")
            .lines()
            .skip_while(|l| *l != "//! ```no_run")
            .skip(1)
            .take_while(|l| *l != "//! ```")
            .map(|l| l.strip_prefix("//! ").unwrap_or(l.trim_start_matches("//!")))
            .collect();
        let readme: Vec<&str> = include_str!("../../../README.md")
            .lines()
            .skip_while(|l| !l.starts_with("// Cargo.toml: sward-bevy"))
            .skip(1)
            .take_while(|l| *l != "```")
            .collect();
        assert!(documented.len() > 10, "the crate's example: {documented:?}");
        assert_eq!(readme, documented, "README.md's Bevy example differs from lib.rs's");
    }

    /// Bevy's render internals are met in `render_world/` alone: no other source file names
    /// them (Bevy's fog component, which a game spawns, is not one), and each touch point its
    /// table lists names app tests that exist.
    #[test]
    #[allow(clippy::disallowed_methods)] // It reads the crate's sources, natively.
    fn bevy_s_render_internals_are_met_in_one_module_each_touch_point_with_its_test() {
        // Spelled apart, so this test's own source names none of them.
        let internals = [
            concat!("bevy", "::render"),
            concat!("bevy", "::core_pipeline"),
            concat!("bevy", "::pbr::"),
            concat!("bevy_", "render::"),
            concat!("bevy_", "pbr::"),
        ];
        // The crate's own `render_plugin` after `sward_bevy` is not one: a name starts after no
        // word character.
        let names = |line: &str, internal: &str| {
            line.match_indices(internal)
                .any(|(at, _)| !line[..at].ends_with(|c: char| c.is_alphanumeric() || c == '_'))
        };
        let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
        let mut outside = Vec::new();
        for entry in std::fs::read_dir(&src).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_none_or(|e| e != "rs") {
                continue;
            }
            let text = std::fs::read_to_string(&path).unwrap();
            for (n, line) in text.lines().enumerate() {
                let public_fog = line.contains("bevy::pbr::{DistanceFog, FogFalloff}");
                if !public_fog && internals.iter().any(|i| names(line, i)) {
                    outside.push(format!("{}:{}: {line}", path.display(), n + 1));
                }
            }
        }
        assert!(
            outside.is_empty(),
            "render internals outside render_world/:\n{}",
            outside.join("\n")
        );

        let table = include_str!("render_world/mod.rs");
        let tests = include_str!("../tests/app.rs");
        let rows: Vec<&str> = table
            .lines()
            .filter(|l| l.starts_with("//! | ") && !l.contains("---"))
            .skip(1)
            .collect();
        assert!(rows.len() >= 10, "the touch points: {rows:?}");
        for row in rows {
            let cells: Vec<&str> = row.split(" | ").collect();
            let named: Vec<&str> = cells[3].split(", ").map(|t| t.trim_matches('`')).collect();
            for test in named {
                assert!(
                    tests.contains(&format!("fn {test}()")),
                    "{row}\nnames no app test `{test}`"
                );
            }
            for file in cells[2].split(", ").map(|f| f.trim_matches('`')) {
                assert!(
                    src.join("render_world").join(file).exists(),
                    "{row}\nnames no file `{file}`"
                );
            }
        }
    }
}
