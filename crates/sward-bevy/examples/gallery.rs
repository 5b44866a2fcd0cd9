//! Every biome preset side by side: twelve plots of grass, each a preset's kinds of grass with
//! their physics as Bezier blades, placed in a grid by their transforms, all sharing one budget
//! of blades (`GrassBudget`), under one sun, the wind blowing through them. Left to right, front
//! row first: lawn, meadow, wildflower meadow, prairie; pampas, reed marsh, dune grass,
//! savanna; alpine, forest floor, frosted meadow, stylised.
//!
//! `cargo run --release -p sward-bevy --example gallery` (Bevy's own device: any backend).
//! Arrow keys walk the camera along the rows; Esc quits.
//!
//! `-- --shot OUT.png [--frames N] [--size W H]` draws it headless instead (the camera still).

#[path = "common/run.rs"]
mod run;

use std::error::Error;

use bevy::light::CascadeShadowConfigBuilder;
use bevy::prelude::*;
use sward_bevy::{Grass, GrassBudget, GrassLighting, GrassPreset, GrassShare};
use sward_core::instanced::Technique;

/// Every preset, in the grid's order (front row first, left to right).
const PRESETS: [GrassPreset; 12] = [
    GrassPreset::Lawn,
    GrassPreset::Meadow,
    GrassPreset::WildflowerMeadow,
    GrassPreset::Prairie,
    GrassPreset::Pampas,
    GrassPreset::ReedMarsh,
    GrassPreset::DuneGrass,
    GrassPreset::Savanna,
    GrassPreset::Alpine,
    GrassPreset::ForestFloor,
    GrassPreset::FrostedMeadow,
    GrassPreset::Stylised,
];

/// A plot's side and the path between plots, in metres.
const PLOT: f32 = 6.0;
const PATH: f32 = 1.5;
/// Blades a plot grows, as the presets grow them near the eye (about 300 a square metre), and
/// the budget all twelve share: three quarters of what they ask together.
const PLOT_BLADES: u32 = 10_800;
const BUDGET: u32 = PLOT_BLADES * 9;

fn main() -> Result<(), Box<dyn Error>> {
    let mut app = App::new();
    app.insert_resource(ClearColor(Color::srgb(0.62, 0.7, 0.82)))
        .insert_resource(GrassBudget { blades: BUDGET })
        .add_systems(Startup, setup)
        .add_systems(Update, (walk, say_shares));
    run::run(app)
}

/// A preset's grass as a plot: its kinds of grass, colours, wind and paint, grown as a fixed
/// square of Bezier blades with their physics (the preset streams them around the eye and
/// generates grass to the horizon, which twelve side by side would overlap).
fn plot(preset: GrassPreset) -> Grass {
    let mut scene = preset.scene();
    scene.technique = Technique::Bezier;
    scene.field.stream = false;
    scene.field.size = Vec2::splat(PLOT);
    scene.field.blades = PLOT_BLADES;
    let mut grass = Grass::new(scene).expect("a preset's plot is a valid scene");
    grass.lighting = GrassLighting::Pbr;
    grass
}

/// Where plot `k` stands: four to a row, left to right as the camera sees them (looking
/// along +z, its right is -x), rows going away from it.
fn plot_place(k: usize) -> Vec3 {
    let step = PLOT + PATH;
    Vec3::new(1.5 * step - (k % 4) as f32 * step, 0.0, (k / 4) as f32 * step)
}

fn setup(mut commands: Commands, mut meshes: ResMut<Assets<Mesh>>, mut materials: ResMut<Assets<StandardMaterial>>) {
    for (k, preset) in PRESETS.into_iter().enumerate() {
        commands.spawn((
            plot(preset),
            Transform::from_translation(plot_place(k)),
            Name::new(preset.name()),
        ));
    }
    // Soil under the plots, paths of gravel between them.
    commands.spawn((
        Mesh3d(meshes.add(Plane3d::default().mesh().size(200.0, 200.0))),
        MeshMaterial3d(materials.add(StandardMaterial {
            base_color: Color::srgb(0.45, 0.42, 0.36),
            perceptual_roughness: 1.0,
            ..default()
        })),
    ));
    let soil = materials.add(StandardMaterial {
        base_color: Color::srgb(0.16, 0.12, 0.07),
        perceptual_roughness: 1.0,
        ..default()
    });
    // The reed marsh's pools (its bare ground) are still, dark water.
    let water = materials.add(StandardMaterial {
        base_color: Color::srgb(0.03, 0.05, 0.05),
        perceptual_roughness: 0.05,
        reflectance: 0.6,
        ..default()
    });
    for (k, preset) in PRESETS.into_iter().enumerate() {
        let ground = if preset == GrassPreset::ReedMarsh {
            &water
        } else {
            &soil
        };
        commands.spawn((
            Mesh3d(meshes.add(Plane3d::default().mesh().size(PLOT, PLOT))),
            MeshMaterial3d(ground.clone()),
            Transform::from_translation(plot_place(k) + Vec3::Y * 0.01),
        ));
    }
    commands.spawn((
        DirectionalLight {
            illuminance: 25_000.0,
            shadow_maps_enabled: true,
            ..default()
        },
        CascadeShadowConfigBuilder {
            maximum_distance: 60.0,
            ..default()
        }
        .build(),
        Transform::from_xyz(-1.0, 2.5, -1.5).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    commands.spawn((
        Camera3d::default(),
        Msaa::Sample4,
        Transform::from_xyz(0.0, 15.0, -15.0).looking_at(Vec3::new(0.0, 0.0, 8.0), Vec3::Y),
    ));
}

/// The arrow keys walk the camera along and between the rows.
fn walk(keys: Res<ButtonInput<KeyCode>>, time: Res<Time>, mut camera: Single<&mut Transform, With<Camera3d>>) {
    let step = 6.0 * time.delta_secs();
    let along = |key, v: Vec3| if keys.pressed(key) { v * step } else { Vec3::ZERO };
    camera.translation += along(KeyCode::ArrowLeft, Vec3::X)
        + along(KeyCode::ArrowRight, -Vec3::X)
        + along(KeyCode::ArrowUp, Vec3::Z)
        + along(KeyCode::ArrowDown, -Vec3::Z);
}

/// Each plot's share of the budget, said once it is known.
fn say_shares(shares: Query<(&Name, &GrassShare), Added<GrassShare>>) {
    for (name, share) in &shares {
        info!("{name}: {} blades of the shared budget", share.blades);
    }
}
