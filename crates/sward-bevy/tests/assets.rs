//! The grass as Bevy content, without a GPU: scene files in an app's asset folder loaded through
//! Bevy's `AssetServer` grow each `GrassSource`'s `Grass`, a changed file reaches it when Bevy
//! loads it again, and a broken file fails as a Bevy asset error naming the file, line and key;
//! a game paints strokes over the grass and asks it what grows where (`GrassSampling`).

// A native test: it writes and reads its folders on disk.
#![allow(clippy::disallowed_methods)]

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
    asset_app_with(folder, |_| {}, |_| {})
}

/// [`asset_app`], `before` the asset plugin (where asset sources are registered) and `beside`
/// the plugin (assets of its own).
fn asset_app_with(folder: &Path, before: impl FnOnce(&mut App), beside: impl FnOnce(&mut App)) -> App {
    let mut app = App::new();
    before(&mut app);
    app.add_plugins((
        MinimalPlugins,
        AssetPlugin {
            file_path: folder.display().to_string(),
            // Bevy's file watcher (the `file_watcher` feature), as a game in development runs.
            watch_for_changes_override: Some(true),
            ..default()
        },
        bevy::transform::TransformPlugin,
    ));
    app.init_asset::<Mesh>();
    beside(&mut app);
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

/// Update `app` (letting the asset server's threads and the file watcher work between frames)
/// until `done` holds, for at most 10 seconds; whether it did.
fn update_until(app: &mut App, mut done: impl FnMut(&mut World) -> bool) -> bool {
    let start = std::time::Instant::now();
    while start.elapsed() < Duration::from_secs(10) {
        app.update();
        if done(app.world_mut()) {
            return true;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    false
}

/// A height map of `size`² pixels rising along x to `top` (0 to 255) at its far edge.
fn hills(folder: &Path, top: u8) {
    let map = image::GrayImage::from_fn(16, 16, |x, _| image::Luma([(x * top as u32 / 15) as u8]));
    map.save(folder.join("grass/hills.png"))
        .expect("the height map written");
}

/// The `Grass` of `entity`, where it has one.
fn grass_of(world: &World, entity: Entity) -> Option<&Grass> {
    world.get::<Grass>(entity)
}

#[test]
fn a_scene_file_in_the_asset_folder_grows_the_grass_and_a_changed_file_reaches_it() {
    let folder = asset_folder("grows");
    std::fs::write(folder.join("grass/field.grass.toml"), field_file(500)).unwrap();
    hills(&folder, 255);
    // Any name, loaded as a scene: the meadow the repository ships.
    let meadow = include_str!("../../../scenes/meadow.toml");
    std::fs::write(folder.join("grass/meadow.toml"), meadow).unwrap();
    let mut app = asset_app(&folder);
    let server = app.world().resource::<AssetServer>().clone();
    let field = app
        .world_mut()
        .spawn((
            GrassSource(server.load("grass/field.grass.toml")),
            GrassSampling::default(),
        ))
        .id();
    let shipped = app
        .world_mut()
        .spawn(GrassSource(server.load::<GrassScene>("grass/meadow.toml")))
        .id();
    let grown = update_until(&mut app, |world| {
        grass_of(world, field).is_some() && grass_of(world, shipped).is_some()
    });
    assert!(grown, "the grass was not grown from its scene files in 10 s");
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
        path, "grass/hills.png",
        "the height map is named relative to the scene file in the asset folder"
    );
    assert!(
        scene.contents.get(path).is_some(),
        "the height map's bytes came with the scene, read by the asset server"
    );

    // The app's own settings on the grass stay when the file changes: saved, Bevy's file watcher
    // loads it again.
    app.world_mut().get_mut::<Grass>(field).unwrap().lighting = GrassLighting::Scene;
    // So does a game's edit in world space: painted again over the file loaded anew.
    let burnt = Stroke::circle(Vec2::new(1.0, 1.0), 1.5).burn();
    app.world_mut().write_message(GrassEdit(burnt.clone()));
    app.update();
    let edited = grass_of(app.world(), field).unwrap().scene.edits.clone();
    assert_eq!(edited.pending(), [burnt], "the edit was not painted");
    std::fs::write(folder.join("grass/field.grass.toml"), field_file(800)).unwrap();
    let reloaded = update_until(&mut app, |world| {
        grass_of(world, field).is_some_and(|g| g.scene.field.blades == 800)
    });
    assert!(reloaded, "the saved file did not reach the grass in 10 s");
    let grass = grass_of(app.world(), field).unwrap();
    assert_eq!(grass.lighting, GrassLighting::Scene, "the app's lighting was replaced");
    assert_eq!(
        grass.scene.edits, edited,
        "the edit was lost when the file was loaded again"
    );
    assert_eq!(grass.shadow_distance, Grass::SHADOW_DISTANCE);

    // The height map the scene names is its dependency: saved lower, the ground the grass
    // grows on is lower (as the sampler, which reads the map again, says).
    let far_edge = Vec3::new(3.5, 0.0, 0.0);
    let ground = |world: &World| {
        world
            .get::<GrassSampling>(field)
            .and_then(|s| s.at(far_edge))
            .and_then(|s| s.ground)
    };
    let high = ground(app.world()).expect("the grass is sampled on its height map");
    assert!(high > 1.5, "the height map's far edge stands {high} high");
    hills(&folder, 64);
    let lowered = update_until(&mut app, |world| ground(world).is_some_and(|h| h < 0.6));
    assert!(
        lowered,
        "the saved height map did not reach the grass in 10 s: {:?}",
        ground(app.world())
    );
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
    let error = load_error(&mut app, &handle).expect("the broken file did not fail to load in 10 s");
    eprintln!("{error}");
    for named in ["broken.grass.toml", "line 2", "field.blades"] {
        assert!(error.contains(named), "the asset error does not name {named}: {error}");
    }
    assert!(grass_of(app.world(), source).is_none(), "a broken file grew grass");
    // A file naming a map that is not there fails too, naming it.
    std::fs::write(folder.join("grass/lost.grass.toml"), field_file(100)).unwrap();
    let handle: Handle<GrassScene> = server.load("grass/lost.grass.toml");
    let error = load_error(&mut app, &handle).expect("a scene naming a missing map did not fail to load in 10 s");
    assert!(
        error.contains("lost.grass.toml") && error.contains("hills.png"),
        "{error}"
    );
    // A file naming a map outside the asset folder (the plugin reads only through the asset
    // server) fails, saying so.
    std::fs::write(folder.join("hills.png"), b"not read").unwrap();
    let outside = field_file(100).replace("\"hills.png\"", "\"../../hills.png\"");
    std::fs::write(folder.join("grass/outside.grass.toml"), outside).unwrap();
    let handle: Handle<GrassScene> = server.load("grass/outside.grass.toml");
    let error = load_error(&mut app, &handle).expect("a scene naming a map outside the folder loaded");
    assert!(error.contains("outside the asset folder"), "{error}");
    let _ = std::fs::remove_dir_all(&folder);
}

/// The error `handle`'s load failed with, once it has (within 10 seconds of updates).
fn load_error(app: &mut App, handle: &Handle<GrassScene>) -> Option<String> {
    let server = app.world().resource::<AssetServer>().clone();
    let mut error = None;
    update_until(app, |_| match server.load_state(handle) {
        LoadState::Failed(e) => {
            error = Some(e.to_string());
            true
        }
        _ => false,
    });
    error
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

/// The ground a scene grows its grass on is a Bevy mesh the plugin makes (`GrassGround`, on an
/// entity of its own): the
/// park's terrain vertex for vertex, the plane as wide as the grass reaches, made again when
/// the scene's ground changes.
#[test]
fn the_plugin_makes_the_ground_the_grass_grows_on() {
    let folder = asset_folder("ground");
    let mut app = asset_app(&folder);
    let park = Scene::from_toml(include_str!("../../../scenes/park.toml"), "park.toml").unwrap();
    let grass = app
        .world_mut()
        .spawn((Grass::new(park.clone()).unwrap(), GrassSampling::default()))
        .id();
    let ground = app.world_mut().spawn(GrassGround::of(grass)).id();
    app.update();
    let positions = |app: &App| {
        let handle = app.world().get::<Mesh3d>(ground).expect("the ground's mesh").0.clone();
        let mesh = app
            .world()
            .resource::<Assets<Mesh>>()
            .get(&handle)
            .expect("made")
            .clone();
        let Some(bevy::mesh::VertexAttributeValues::Float32x3(p)) = mesh.attribute(Mesh::ATTRIBUTE_POSITION) else {
            panic!("the ground has no positions");
        };
        p.clone()
    };
    let terrain = park.surface.mesh(&park.contents).unwrap().expect("the park's terrain");
    let made = positions(&app);
    assert_eq!(made.len(), terrain.positions.len());
    assert!(made
        .iter()
        .zip(&terrain.positions)
        .all(|(a, b)| Vec3::from_array(*a) == *b));
    // Where the grass stands, by the sampler, is on the mesh's vertices.
    let sampling = app.world().get::<GrassSampling>(grass).unwrap();
    for p in made.iter().step_by(4099).map(|p| Vec3::from_array(*p)) {
        let ground = sampling
            .at(p)
            .and_then(|s| s.ground)
            .expect("ground under the terrain's vertex");
        assert!((ground - p.y).abs() < 1e-3, "at {p}: the grass stands at {ground}");
    }
    // The ground changed to the plane: a plane as wide as the billboards reach.
    app.world_mut().get_mut::<Grass>(grass).unwrap().scene.surface = Surface::Plane;
    app.update();
    let plane = positions(&app);
    let width =
        plane.iter().map(|p| p[0]).fold(f32::MIN, f32::max) - plane.iter().map(|p| p[0]).fold(f32::MAX, f32::min);
    assert_eq!(
        width,
        sward_bevy::plane_reach(&app.world().get::<Grass>(grass).unwrap().scene).x
    );
    assert!(plane.iter().all(|p| p[1] == 0.0));
}

/// The components are reflected and registered, the whole scene inside a `Grass` with them: an
/// inspector (or any reflection path) reads and changes every value of it.
#[test]
fn an_inspector_reaches_every_value_of_the_grass_through_reflection() {
    use bevy::reflect::{GetPath, ReflectMut};
    let folder = asset_folder("reflect");
    let mut app = asset_app(&folder);
    let grass = app.world_mut().spawn(Grass::new(Scene::default()).unwrap()).id();
    let registry = app.world().resource::<AppTypeRegistry>().clone();
    let registry = registry.read();
    for name in [
        "Grass",
        "GrassCollider",
        "GrassOccluder",
        "GrassSource",
        "GrassSampling",
        "GrassGround",
        "GrassLighting",
        "GrassScene",
    ] {
        assert!(
            registry.get_with_short_type_path(name).is_some(),
            "{name} is not registered"
        );
    }
    let reflect_grass = registry
        .get_type_data::<ReflectComponent>(std::any::TypeId::of::<Grass>())
        .expect("Grass reflects as a component");
    let mut entity = app.world_mut().entity_mut(grass);
    let mut reflected = reflect_grass.reflect_mut(&mut entity).expect("the grass");
    *reflected.path_mut::<u32>("scene.field.blades").unwrap() = 1234;
    *reflected.path_mut::<f32>("scene.shading.root_color.y").unwrap() = 0.5;
    *reflected.path_mut::<f32>("scene.wind.0[0].strength").unwrap() = 7.0;
    let ReflectMut::Struct(fields) = reflected.reflect_mut() else {
        panic!("Grass reflects as a struct");
    };
    assert!(fields.field("lighting").is_some() && fields.field("shadow_distance").is_some());
    let scene = &app.world().get::<Grass>(grass).unwrap().scene;
    assert_eq!(scene.field.blades, 1234);
    assert_eq!(scene.shading.root_color.y, 0.5);
    assert_eq!(scene.wind.0[0].strength, 7.0);
}

/// Twelve presets by biome ship inside the crate as scene assets: each loads through the asset
/// server from its embedded path as the scene it is, mixes kinds of grass with flowering stalks
/// or flowers, and grows Bezier blades with their physics near the eye.
#[test]
fn the_presets_by_biome_load_as_assets() {
    let folder = asset_folder("presets");
    let mut app = asset_app(&folder);
    let server = app.world().resource::<AssetServer>().clone();
    assert!(GrassPreset::ALL.len() >= 12, "{} presets", GrassPreset::ALL.len());
    let handles: Vec<(GrassPreset, Handle<GrassScene>)> =
        GrassPreset::ALL.iter().map(|&p| (p, server.load(p.path()))).collect();
    let loaded = update_until(&mut app, |world| {
        let scenes = world.resource::<Assets<GrassScene>>();
        handles.iter().all(|(_, h)| scenes.get(h).is_some())
    });
    assert!(
        loaded,
        "the presets did not load in 10 s: {:?}",
        handles
            .iter()
            .map(|(p, h)| (p.name(), server.load_state(h)))
            .collect::<Vec<_>>()
    );
    let scenes = app.world().resource::<Assets<GrassScene>>();
    let mut names = std::collections::HashSet::new();
    for (preset, handle) in &handles {
        let GrassScene(scene) = scenes.get(handle).unwrap();
        assert_eq!(*scene, preset.scene(), "{}", preset.name());
        assert!(names.insert(scene.name.clone()), "two presets named {}", scene.name);
        assert!(scene.species.len() >= 2, "{}: one kind of grass", preset.name());
        assert!(
            scene.species.iter().any(|s| s.seed_heads.is_some()),
            "{}: nothing in flower",
            preset.name()
        );
        assert!(
            scene.bezier_blades() > 0,
            "{}: no Bezier blades near the eye",
            preset.name()
        );
    }
}

/// A field placed by its `Transform` (moved, turned, twice as large) is asked at world points:
/// what it says there is what the field says at the point its transform carries there, its
/// heights twice as tall, and the colliders press it where they stand in the world.
#[test]
fn a_placed_field_is_asked_where_its_transform_puts_it() {
    let folder = asset_folder("placed-sampling");
    let mut app = asset_app(&folder);
    let mut park = Scene::from_toml(include_str!("../../../scenes/park.toml"), "park.toml").unwrap();
    park.technique = sward_core::instanced::Technique::Instanced;
    let (meadow, path) = (Vec3::new(40.0, 0.0, -30.0), Vec3::new(0.0, 0.0, -20.0));
    let placed = Transform::from_xyz(500.0, 3.0, -200.0)
        .with_rotation(Quat::from_rotation_y(1.2))
        .with_scale(Vec3::splat(2.0));
    let grass = app
        .world_mut()
        .spawn((Grass::new(park.clone()).unwrap(), GrassSampling::default(), placed))
        .id();
    let unplaced = sward_core::sample::GrassSampler::new(&park).unwrap();
    let ground = unplaced.at(meadow.xz()).ground.unwrap();
    let in_world = |p: Vec3| placed.transform_point(p);
    app.world_mut().spawn((
        GrassCollider::sphere(1.0),
        Transform::from_translation(in_world(meadow + Vec3::Y * (ground + 0.3))),
    ));
    app.update();
    app.update();
    let said = |at: Vec3| {
        app.world()
            .get::<GrassSampling>(grass)
            .unwrap()
            .at(at)
            .expect("sampled")
    };
    let beside = meadow + Vec3::X * 4.0;
    let (here, there) = (said(in_world(beside)), unplaced.at(beside.xz()));
    assert_eq!((here.density, here.species), (there.density, there.species), "{here:?}");
    assert!((here.height - 2.0 * there.height).abs() < 1e-4, "{here:?} {there:?}");
    assert!((here.ground.unwrap() - in_world(beside + Vec3::Y * there.ground.unwrap()).y).abs() < 1e-3);
    assert!(
        said(in_world(meadow)).pressed > 0.5,
        "the ball presses the placed field under it"
    );
    assert_eq!(said(in_world(beside)).pressed, 0.0, "nothing presses beside it");
    assert_eq!(
        said(in_world(path)).density,
        0.0,
        "the path is bare where the field's is"
    );
}

/// A grey PNG of `side`² pixels whose value is `value(x, y)`, as bytes.
fn grey_png(side: u32, value: impl Fn(u32, u32) -> u8) -> Vec<u8> {
    let map = image::GrayImage::from_fn(side, side, |x, y| image::Luma([value(x, y)]));
    let mut png = Vec::new();
    map.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    png
}

/// A closed cube of side 1 about its origin, as OBJ text.
const CUBE_OBJ: &str = "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\n\
    v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\n\
    f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 4 8 7\nf 4 7 3\nf 1 5 8\nf 1 8 4\nf 2 3 7\nf 2 7 6\n";

/// A scene read from an asset source in memory, with the height map, paint map and mesh it
/// names beside it there: its field grows, its ground has the map's heights, its paint leaves
/// out what the map leaves out and its body is the mesh's, with not one file on disk (the
/// asset folder is empty): the plugin reads only through the asset server.
#[test]
fn a_scene_read_from_memory_grows_with_no_file_on_disk() {
    use bevy::asset::io::memory::{Dir, MemoryAssetReader};
    use bevy::asset::io::AssetSourceBuilder;
    let dir = Dir::new(PathBuf::new());
    let scene = "[field]\nblades = 2000\nsize = [8.0, 8.0]\n\n\
        [surface]\ntype = \"heightmap\"\npath = \"maps/../maps/ramp.png\"\nheight = 2.0\nsize = [8.0, 8.0]\n\n\
        [paint]\narea = [-4.0, -4.0, 4.0, 4.0]\ndensity = \"maps/east.png\"\n\n\
        [[body]]\nshape = { type = \"mesh\", path = \"rock.obj\", scale = 1.0 }\nspheres = 8\ncenter = [0.0, 1.0, 0.0]\n";
    dir.insert_asset(Path::new("fields/memory.grass.toml"), scene.as_bytes().to_vec());
    // Height rising along x; grass only on the east half (x > 0).
    dir.insert_asset(
        Path::new("fields/maps/ramp.png"),
        grey_png(9, |x, _| (x * 255 / 8) as u8),
    );
    dir.insert_asset(
        Path::new("fields/maps/east.png"),
        grey_png(8, |x, _| if x < 4 { 0 } else { 255 }),
    );
    dir.insert_asset(Path::new("fields/rock.obj"), CUBE_OBJ.as_bytes().to_vec());
    let folder = asset_folder("memory");
    let register = |app: &mut App| {
        let root = dir.clone();
        app.register_asset_source(
            "mem",
            AssetSourceBuilder::new(move || Box::new(MemoryAssetReader { root: root.clone() })),
        );
    };
    let mut app = asset_app_with(&folder, register, |_| {});
    let handle = app
        .world()
        .resource::<AssetServer>()
        .load("mem://fields/memory.grass.toml");
    let field = app.world_mut().spawn(GrassSource(handle.clone())).id();
    let grown = update_until(&mut app, |world| grass_of(world, field).is_some());
    let error = load_error(&mut app, &handle);
    assert!(grown, "the scene in memory did not grow: {error:?}");
    assert!(
        std::fs::read_dir(&folder).unwrap().flatten().all(|e| e.path().is_dir()),
        "the asset folder on disk holds no file"
    );
    let scene = grass_of(app.world(), field).unwrap().scene.clone();
    let names: Vec<&str> = scene.contents.names().collect();
    assert_eq!(
        names,
        [
            "fields/maps/../maps/ramp.png",
            "fields/maps/east.png",
            "fields/rock.obj"
        ],
        "every file it names came with it"
    );
    let blades = scene
        .grow_field()
        .expect("the field grows from what came with it")
        .blades;
    assert!(blades.len() > 500, "{} blades", blades.len());
    for blade in &blades {
        let root = blade.root();
        assert!(root.x > -0.6, "a blade grew where the map is black: {root}");
        let ramp = (root.x + 4.0) / 8.0 * 2.0;
        assert!((root.y - ramp).abs() < 0.1, "a root at {root} is off the ramp ({ramp})");
    }
    let rock = scene.colliders_at(0.0);
    assert_eq!(rock.len(), 8, "the body is packed from the cube");
    assert!(
        rock.iter().all(|s| (s.center - Vec3::Y).length() + s.radius < 0.9),
        "{rock:?}"
    );
    let _ = std::fs::remove_dir_all(&folder);
}

/// A field's ground and paint given as Bevy assets made in code (`GrassContent`): a height
/// function baked to an image, a density function baked to a map, then a Bevy mesh; the grass
/// grows on them and the sampler answers from them, and an image changed in place reaches the
/// grass the next frame. A weight map for a kind the grass does not grow is said, not applied.
#[test]
fn a_field_grows_on_ground_and_paint_given_as_bevy_assets() {
    let folder = asset_folder("content");
    // Bevy's images beside the plugin (the other tests' apps have none: the plugin needs none).
    let mut app = asset_app_with(&folder, |_| {}, |app| _ = app.init_asset::<Image>());
    let mut scene = Scene::default();
    scene.field.blades = 3000;
    scene.field.size = Vec2::splat(8.0);
    let area = Rect::new(-4.0, -4.0, 4.0, 4.0);
    let (ground, density) = {
        let mut images = app.world_mut().resource_mut::<Assets<Image>>();
        let ground = GroundContent::from_height(&mut images, Vec2::splat(8.0), 3.0, 65, |p| 1.0 + 0.25 * p.y);
        let density = GrassContent::bake_map(&mut images, area, 4.0, |p| if p.x < 0.0 { 0.0 } else { 1.0 });
        (ground, density)
    };
    let content = GrassContent {
        ground: Some(ground),
        density: Some(density.clone()),
        area: Some(area),
        ..default()
    };
    let field = app
        .world_mut()
        // No `GrassSampling` spawned: every `Grass` has one.
        .spawn((Grass::new(scene.clone()).unwrap(), content))
        .id();
    app.update();
    let grass = grass_of(app.world(), field).unwrap().scene.clone();
    assert!(
        matches!(grass.surface, Surface::Heightmap { height: 3.0, .. }),
        "{:?}",
        grass.surface
    );
    let blades = grass.grow_field().unwrap().blades;
    assert!(blades.len() > 500, "{} blades", blades.len());
    for blade in &blades {
        let root = blade.root();
        assert!(root.x > -0.3, "a blade grew where the density map is black: {root}");
        assert!(
            (root.y - (1.0 + 0.25 * root.z)).abs() < 0.05,
            "a root at {root} is off the baked ground"
        );
    }
    let sampled = |app: &App, at: Vec3| {
        app.world()
            .get::<GrassSampling>(field)
            .unwrap()
            .at(at)
            .expect("sampled")
    };
    let here = sampled(&app, Vec3::new(2.0, 0.0, 2.0));
    assert!(
        (here.ground.unwrap() - 1.5).abs() < 0.05 && here.density == 1.0,
        "{here:?}"
    );
    assert_eq!(
        sampled(&app, Vec3::new(-2.0, 0.0, 2.0)).density,
        0.0,
        "bare where the map is black"
    );

    // The density image changed in place (all white): the grass and the sampler follow.
    {
        let mut images = app.world_mut().resource_mut::<Assets<Image>>();
        let mut image = images.get_mut(&density).unwrap();
        image.data.as_mut().unwrap().fill(255);
    }
    app.update();
    app.update();
    assert_eq!(
        sampled(&app, Vec3::new(-2.0, 0.0, 2.0)).density,
        1.0,
        "the changed map reached the grass"
    );

    // A Bevy mesh as the ground: a square at y = 0.5, two triangles facing up.
    let square = Mesh::new(bevy::mesh::PrimitiveTopology::TriangleList, default())
        .with_inserted_attribute(
            Mesh::ATTRIBUTE_POSITION,
            vec![[-4.0, 0.5, -4.0], [4.0, 0.5, -4.0], [4.0, 0.5, 4.0], [-4.0, 0.5, 4.0]],
        )
        .with_inserted_indices(bevy::mesh::Indices::U32(vec![0, 2, 1, 0, 3, 2]));
    let square = app.world_mut().resource_mut::<Assets<Mesh>>().add(square);
    app.world_mut().get_mut::<GrassContent>(field).unwrap().ground = Some(GroundContent::Mesh(square));
    app.update();
    let grass = grass_of(app.world(), field).unwrap().scene.clone();
    assert!(matches!(grass.surface, Surface::Mesh { .. }), "{:?}", grass.surface);
    let blades = grass.grow_field().unwrap().blades;
    assert!(!blades.is_empty() && blades.iter().all(|b| (b.root().y - 0.5).abs() < 1e-4));

    // A weight map for a kind it does not grow: said, and the grass keeps what it had.
    let kept = grass.clone();
    app.world_mut().get_mut::<GrassContent>(field).unwrap().weight_maps = vec![("clover".into(), density)];
    app.update();
    assert_eq!(
        grass_of(app.world(), field).unwrap().scene,
        kept,
        "a bad content is not applied"
    );
    let _ = std::fs::remove_dir_all(&folder);
}
