//! Grass as an asset, hot-reloaded: a valley of meadow grass whose scene file and the two images
//! it names (a height map and a density map with a footpath mown along the valley floor) are
//! read by Bevy's asset server from `assets/valley/`. Edit `valley.grass.toml`, `height.png` or
//! `paths.png` and save while it runs: Bevy's file watcher loads the scene again and the grass
//! grows from what was saved (the log says so), the ground under it with it.
//!
//! `cargo run --release -p sward-bevy --example assets` (Bevy's own device: any backend; the
//! asset folder is `crates/sward-bevy/assets`, or `$BEVY_ASSET_ROOT/assets`). Esc quits.
//!
//! `-- --shot OUT.png [--frames N] [--size W H]` draws it headless instead.

#[path = "common/run.rs"]
mod run;

use std::error::Error;

use bevy::asset::AssetLoadFailedEvent;
use bevy::prelude::*;
use sward_bevy::{Grass, GrassGround, GrassScene, GrassSource};

/// The scene file, in the asset folder.
const VALLEY: &str = "valley/valley.grass.toml";

fn main() -> Result<(), Box<dyn Error>> {
    let mut app = App::new();
    app.insert_resource(ClearColor(Color::srgb(0.62, 0.7, 0.82)))
        .add_systems(Startup, setup)
        .add_systems(Update, (say_grown, say_failed));
    run::run(app)
}

fn setup(mut commands: Commands, assets: Res<AssetServer>, mut materials: ResMut<Assets<StandardMaterial>>) {
    // The grass is given its `Grass` once the file and the images it names have loaded.
    let valley = commands.spawn(GrassSource(assets.load(VALLEY))).id();
    // The ground the grass grows on (the height map's terrain), drawn with a soil of our own.
    commands.spawn((
        GrassGround::of(valley),
        MeshMaterial3d(materials.add(StandardMaterial {
            base_color: Color::srgb(0.16, 0.17, 0.07),
            perceptual_roughness: 1.0,
            ..default()
        })),
    ));
    commands.spawn((
        DirectionalLight {
            illuminance: 25_000.0,
            shadow_maps_enabled: true,
            ..default()
        },
        Transform::from_xyz(-1.0, 1.6, 0.8).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    // Above the footpath, looking up the valley.
    commands.spawn((
        Camera3d::default(),
        Msaa::Sample4,
        Transform::from_xyz(-7.6, 5.0, -30.0).looking_at(Vec3::new(8.3, 1.5, 20.0), Vec3::Y),
    ));
    info!("edit and save assets/{VALLEY} or the images it names: the grass grows again from them");
}

/// Say each time the valley's grass was grown from its files (the first time, and after each
/// save).
fn say_grown(grown: Query<&Grass, Changed<Grass>>) {
    for grass in &grown {
        let named: Vec<&str> = grass.scene.contents.names().collect();
        info!(
            "the {} grows from {VALLEY} and {} (read by the asset server)",
            grass.scene.name,
            named.join(", ")
        );
    }
}

/// A save that does not parse or validate keeps the grass as it was, and Bevy says why.
fn say_failed(mut failed: MessageReader<AssetLoadFailedEvent<GrassScene>>) {
    for failure in failed.read() {
        warn!("{}: the grass stays as it was", failure.error);
    }
}
