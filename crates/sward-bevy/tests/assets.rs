//! The grass as Bevy content, without a GPU: scene files in an app's asset folder loaded through
//! Bevy's `AssetServer` grow each `GrassSource`'s `Grass`, a changed file reaches it when Bevy
//! loads it again, and a broken file fails as a Bevy asset error naming the file, line and key;
//! a game paints strokes over the grass and asks it what grows where (`GrassSampling`).

use std::path::{Path, PathBuf};
use std::time::Duration;

use bevy::asset::{AssetPlugin, AssetServer, LoadState};
use bevy::prelude::*;
use sward_bevy::prelude::*;
use sward_core::field::Surface;

/// A folder of its own for a test's asset files (removed and made again).
fn asset_folder(test: &str) -> PathBuf {
    let folder = std::env::temp_dir().join(format!("sward-assets-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&folder);
    std::fs::create_dir_all(folder.join("grass")).expect("a temporary asset folder");
    folder
}

/// An app with Bevy's asset server on `folder`, its meshes (which occluders are packed from),
/// its transforms (which place the colliders) and the plugin, no renderer.
fn asset_app(folder: &Path) -> App {
    let mut app = App::new();
    app.add_plugins((
        MinimalPlugins,
        AssetPlugin {
            file_path: folder.display().to_string(),
            ..default()
        },
        bevy::transform::TransformPlugin,
    ));
    app.init_asset::<Mesh>();
    app.add_plugins(SwardPlugin::default());
    app.finish();
    app.cleanup();
    app
}

/// A small field on a height map named relative to the scene file, of `blades` blades.
fn field_file(blades: u32) -> String {
    format!(
        "[field]\nblades = {blades}\nsize = [8.0, 8.0]\n\n[surface]\ntype = \"heightmap\"\npath = \"hills.png\"\nheight = 2.0\nsize = [8.0, 8.0]\n"
    )
}

/// Update `app` (letting the asset server's threads work between frames) until `done` holds,
/// at most 400 frames; whether it did.
fn update_until(app: &mut App, mut done: impl FnMut(&mut World) -> bool) -> bool {
    for _ in 0..400 {
        app.update();
        if done(app.world_mut()) {
            return true;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    false
}

/// The `Grass` of `entity`, where it has one.
fn grass_of(world: &World, entity: Entity) -> Option<&Grass> {
    world.get::<Grass>(entity)
}

#[test]
fn a_scene_file_in_the_asset_folder_grows_the_grass_and_a_changed_file_reaches_it() {
    let folder = asset_folder("grows");
    std::fs::write(folder.join("grass/field.grass.toml"), field_file(500)).unwrap();
    // Any name, loaded as a scene: the meadow the repository ships.
    let meadow = include_str!("../../../scenes/meadow.toml");
    std::fs::write(folder.join("grass/meadow.toml"), meadow).unwrap();
    let mut app = asset_app(&folder);
    let server = app.world().resource::<AssetServer>().clone();
    let field = app
        .world_mut()
        .spawn(GrassSource(server.load("grass/field.grass.toml")))
        .id();
    let shipped = app
        .world_mut()
        .spawn(GrassSource(server.load::<GrassScene>("grass/meadow.toml")))
        .id();
    let grown = update_until(&mut app, |world| {
        grass_of(world, field).is_some() && grass_of(world, shipped).is_some()
    });
    assert!(grown, "the grass was not grown from its scene files in 400 frames");
    let world = app.world();
    let expected = Scene::from_toml(meadow, "meadow").unwrap();
    assert_eq!(
        grass_of(world, shipped).unwrap().scene,
        expected,
        "the meadow as loaded"
    );
    let scene = &grass_of(world, field).unwrap().scene;
    assert_eq!(scene.field.blades, 500);
    let Surface::Heightmap { path, .. } = &scene.surface else {
        panic!("the field's surface is {:?}", scene.surface);
    };
    assert_eq!(
        Path::new(path),
        folder.join("grass/hills.png"),
        "the height map is named relative to the scene file in the asset folder"
    );

    // The app's own settings on the grass stay when the file changes.
    app.world_mut().get_mut::<Grass>(field).unwrap().lighting = GrassLighting::Scene;
    std::fs::write(folder.join("grass/field.grass.toml"), field_file(800)).unwrap();
    // What Bevy's file watcher does when the file changes.
    server.reload("grass/field.grass.toml");
    let reloaded = update_until(&mut app, |world| {
        grass_of(world, field).is_some_and(|g| g.scene.field.blades == 800)
    });
    assert!(reloaded, "the changed file did not reach the grass in 400 frames");
    let grass = grass_of(app.world(), field).unwrap();
    assert_eq!(grass.lighting, GrassLighting::Scene, "the app's lighting was replaced");
    assert_eq!(grass.shadow_distance, Grass::SHADOW_DISTANCE);
    let _ = std::fs::remove_dir_all(&folder);
}

#[test]
fn a_broken_scene_file_fails_as_a_bevy_asset_error_naming_the_file_line_and_key() {
    let folder = asset_folder("broken");
    std::fs::write(folder.join("grass/broken.grass.toml"), "[field]\nblades = \"many\"\n").unwrap();
    let mut app = asset_app(&folder);
    let server = app.world().resource::<AssetServer>().clone();
    let handle: Handle<GrassScene> = server.load("grass/broken.grass.toml");
    let source = app.world_mut().spawn(GrassSource(handle.clone())).id();
    let mut error = None;
    let failed = update_until(&mut app, |_| match server.load_state(&handle) {
        LoadState::Failed(e) => {
            error = Some(e.to_string());
            true
        }
        _ => false,
    });
    assert!(failed, "the broken file did not fail to load in 400 frames");
    let error = error.unwrap();
    eprintln!("{error}");
    for named in ["broken.grass.toml", "line 2", "field.blades"] {
        assert!(error.contains(named), "the asset error does not name {named}: {error}");
    }
    assert!(grass_of(app.world(), source).is_none(), "a broken file grew grass");
    let _ = std::fs::remove_dir_all(&folder);
}

/// A scene is built or changed in code with Bevy's own maths types (one glam across sward and
/// Bevy).
#[test]
fn a_scene_takes_bevy_s_vectors() {
    let mut scene = Scene::from_toml(include_str!("../../../scenes/meadow.toml"), "meadow").unwrap();
    scene.shading.root_color = Vec3::new(0.1, 0.3, 0.05);
    scene.field.size = Vec2::splat(20.0);
    let grass = Grass::new(scene).expect("the meadow, changed");
    assert_eq!(grass.scene.field.size, Vec2::new(20.0, 20.0));
    assert_eq!(grass.scene.shading.root_color.y, 0.3);
}

#[test]
fn a_game_paints_the_grass_and_asks_it_what_grows_where() {
    let folder = asset_folder("sampling");
    let mut app = asset_app(&folder);
    let mut park = Scene::from_toml(include_str!("../../../scenes/park.toml"), "park.toml").unwrap();
    park.technique = sward_core::instanced::Technique::Instanced;
    let (meadow, path) = (Vec3::new(40.0, 0.0, -30.0), Vec3::new(0.0, 0.0, -20.0));
    let grass = app
        .world_mut()
        .spawn((Grass::new(park.clone()).unwrap(), GrassSampling::default()))
        .id();
    // A ball in the meadow, down in the grass.
    let ground = sward_core::sample::GrassSampler::new(&park)
        .unwrap()
        .at(meadow.xz())
        .ground
        .unwrap();
    app.world_mut().spawn((
        GrassCollider::sphere(0.5),
        Transform::from_translation(meadow + Vec3::Y * (ground + 0.3)),
    ));
    app.update();
    app.update();
    let said = |app: &App, at: Vec3| {
        app.world()
            .get::<GrassSampling>(grass)
            .unwrap()
            .at(at)
            .expect("sampled")
    };
    let here = said(&app, meadow);
    assert!(here.pressed > 0.5, "the ball presses the grass under it: {here:?}");
    assert!(
        here.density == 1.0 && here.height > 0.5,
        "meadow grass grows there: {here:?}"
    );
    assert_eq!(
        said(&app, meadow + Vec3::X * 3.0).pressed,
        0.0,
        "nothing presses beside it"
    );
    assert_eq!(said(&app, path).density, 0.0, "the park's gravel path is bare");
    // Mown around the ball, burnt beyond: the sampler follows the strokes the next frame.
    let tall = said(&app, meadow + Vec3::X * 2.0).height;
    let mut g = app.world_mut().get_mut::<Grass>(grass).unwrap();
    g.paint(Stroke::circle(meadow.xz(), 3.0).softness(0.0).mow(0.25))
        .paint(Stroke::circle(meadow.xz() + Vec2::new(10.0, 0.0), 2.0).burn());
    app.update();
    let mown = said(&app, meadow + Vec3::X * 2.0);
    assert!(
        (mown.height / tall - 0.25).abs() < 0.01,
        "mown to a quarter: {} of {tall}",
        mown.height
    );
    assert!(
        mown.pressed == 0.0 && said(&app, meadow).pressed > 0.5,
        "the trail is kept"
    );
    // As a sampler of the scene painted so from the start says.
    let painted = app.world().get::<Grass>(grass).unwrap().scene.clone();
    let made = sward_core::sample::GrassSampler::new(&painted).unwrap();
    for at in [
        meadow + Vec3::X * 2.0,
        meadow + Vec3::X * 10.0,
        meadow + Vec3::X * 11.5,
        path,
    ] {
        let (held, fresh) = (said(&app, at), made.at(at.xz()));
        assert_eq!(
            (held.density, held.height, held.tint),
            (fresh.density, fresh.height, fresh.tint),
            "at {at}"
        );
    }
    // Another field (the kinds of grass changed): sampled anew, the presses kept.
    app.world_mut().get_mut::<Grass>(grass).unwrap().scene.species[0].height[1] += 0.5;
    app.update();
    let regrown = said(&app, meadow + Vec3::X * 2.0);
    assert!(
        regrown.height > mown.height && said(&app, meadow).pressed > 0.5,
        "{regrown:?}"
    );
}
