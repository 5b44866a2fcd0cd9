//! The open world the `openworld` and `bench` examples draw: the scene (`scenes/openworld.toml`),
//! its grass on the terrain the plugin makes of it, the afternoon sun casting into cascades, and
//! the camera with the scene's lens, HDR and distance fog.

use bevy::camera::RenderTarget;
use bevy::light::CascadeShadowConfigBuilder;
use bevy::prelude::*;
use sward_bevy::{Grass, GrassGround};
use sward_core::Scene;

/// The open world's scene (`scenes/openworld.toml` from the working directory, else from the
/// source tree).
pub fn scene() -> Result<Scene, sward_core::SceneError> {
    let here = std::path::Path::new("scenes/openworld.toml");
    match here.exists() {
        true => Scene::load(here),
        false => Scene::load(concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/openworld.toml").as_ref()),
    }
}

/// Spawn `scene`'s grass (hidden unless `grass`: its terrain stays), the terrain under it, the
/// sun and the camera (into `target` where headless); returns the camera.
pub fn spawn(
    commands: &mut Commands,
    materials: &mut Assets<StandardMaterial>,
    (scene, grass): (&Scene, bool),
    target: Option<&Handle<Image>>,
) -> Entity {
    // Far off the ground is seen between the blades: the colour at their roots.
    let [r, g, b] = scene.shading.root_color.to_array();
    let soil = materials.add(StandardMaterial {
        base_color: Color::linear_rgb(r * 0.8, g * 0.8, b * 0.8),
        perceptual_roughness: 1.0,
        reflectance: 0.1,
        ..default()
    });
    let shown = match grass {
        true => Visibility::Inherited,
        false => Visibility::Hidden,
    };
    let grass = commands
        .spawn((
            Grass::new(scene.clone()).expect("the shipped open world is valid"),
            shown,
        ))
        .id();
    // The plugin makes the mesh of the terrain the grass grows on; the game gives it soil.
    commands.spawn((GrassGround::of(grass), MeshMaterial3d(soil)));
    // The afternoon sun: cascades to 150 m, the grass casting within its shadow distance.
    commands.spawn((
        DirectionalLight {
            color: Color::srgb(1.0, 0.93, 0.8),
            illuminance: 20_000.0,
            shadow_maps_enabled: true,
            ..default()
        },
        CascadeShadowConfigBuilder {
            maximum_distance: 150.0,
            first_cascade_far_bound: 10.0,
            ..default()
        }
        .build(),
        Transform::from_xyz(-1.0, 1.1, 0.6).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    let mut camera = commands.spawn((
        Camera3d::default(),
        Projection::Perspective(PerspectiveProjection {
            fov: scene.camera.fov_y_degrees.to_radians(),
            near: scene.camera.near,
            ..default()
        }),
        bevy::camera::Hdr,
        DistanceFog {
            color: Color::srgb(0.62, 0.7, 0.82),
            falloff: FogFalloff::Exponential { density: 0.002 },
            ..default()
        },
        Transform::default(),
    ));
    if let Some(target) = target {
        camera.insert(RenderTarget::Image(target.clone().into()));
    }
    camera.id()
}
