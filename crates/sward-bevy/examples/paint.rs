//! Painting the grass with the mouse: a left drag over the wildflower meadow sends `GrassEdit`s along the
//! ground under the cursor, in world space, and every field the stroke reaches paints it.
//!
//! `cargo run --release -p sward-bevy --example paint` (Bevy's own device: any backend).
//! Keys choose the brush: 1 mows, 2 clears, 3 burns, 4 regrows, 5 thins, 6 sows flowers, 7 tints
//! the grass yellow; Esc quits.
//!
//! `-- --shot OUT.png [--frames N] [--size W H]` draws it headless instead, a path mown, a patch
//! burnt, one cleared, flowers sown and a patch tinted by the same messages a drag sends.

#[path = "common/run.rs"]
mod run;

use std::error::Error;

use bevy::prelude::*;
use bevy::window::PrimaryWindow;
use sward_bevy::prelude::Stroke;
use sward_bevy::{Grass, GrassEdit, GrassLighting, GrassPreset};

/// How wide the brush paints, and how often a drag sends what it has gone over (seconds): each
/// message is one stroke along the points since the last.
const BRUSH: f32 = 1.2;
const SEND_EVERY: f32 = 0.1;

/// What the brush does, chosen with the number keys.
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
enum Brush {
    Mow,
    Clear,
    Burn,
    Regrow,
    Thin,
    Flowers,
    Tint,
}

impl Brush {
    /// The stroke this brush paints along `points` (world x and z).
    fn stroke(self, points: &[Vec2]) -> Stroke {
        let stroke = Stroke::path(points, BRUSH).softness(0.4);
        match self {
            Brush::Mow => stroke.mow(0.2),
            Brush::Clear => stroke.clear(),
            Brush::Burn => stroke.burn(),
            Brush::Regrow => stroke.regrow(),
            Brush::Thin => stroke.density(0.25),
            // The wildflower meadow's poppies, alone where it paints.
            Brush::Flowers => stroke.species("poppy"),
            Brush::Tint => stroke.tint(Vec3::new(1.5, 1.25, 0.55)),
        }
    }
}

/// The ground points a drag has gone over since it last sent them.
#[derive(Resource, Default)]
struct Drag {
    points: Vec<Vec2>,
    since: f32,
}

fn main() -> Result<(), Box<dyn Error>> {
    let mut app = App::new();
    app.insert_resource(ClearColor(Color::srgb(0.62, 0.7, 0.82)))
        .insert_resource(Brush::Mow)
        .init_resource::<Drag>()
        .add_systems(Startup, setup)
        .add_systems(
            PostStartup,
            scripted_strokes.run_if(resource_equals(run::Headless(true))),
        )
        .add_systems(
            Update,
            (choose_brush, drag).run_if(resource_equals(run::Headless(false))),
        );
    run::run(app)
}

fn setup(mut commands: Commands, mut meshes: ResMut<Assets<Mesh>>, mut materials: ResMut<Assets<StandardMaterial>>) {
    let scene = GrassPreset::WildflowerMeadow.scene();
    assert!(
        scene.species.iter().any(|s| s.name == "poppy"),
        "the preset grows poppies"
    );
    let mut grass = Grass::new(scene).expect("the wildflower meadow preset");
    grass.lighting = GrassLighting::Pbr;
    commands.spawn(grass);
    commands.spawn((
        Mesh3d(meshes.add(Plane3d::default().mesh().size(400.0, 400.0))),
        MeshMaterial3d(materials.add(StandardMaterial {
            base_color: Color::srgb(0.2, 0.16, 0.09),
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
        Transform::from_xyz(-1.0, 2.0, -1.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    commands.spawn((
        Camera3d::default(),
        Msaa::Sample4,
        Transform::from_xyz(0.0, 7.0, -9.0).looking_at(Vec3::new(0.0, 0.0, 4.0), Vec3::Y),
    ));
}

/// The shot's strokes: what a player's drags would send.
fn scripted_strokes(mut edits: MessageWriter<GrassEdit>) {
    let path = |points: &[[f32; 2]]| points.iter().map(|&p| Vec2::from(p)).collect::<Vec<_>>();
    let strokes = [
        (Brush::Mow, path(&[[-6.0, 1.0], [-2.0, 3.0], [2.0, 3.0], [6.0, 6.0]])),
        (Brush::Burn, path(&[[-4.0, 7.0]])),
        (Brush::Clear, path(&[[4.0, 10.0], [5.0, 10.5]])),
        (Brush::Flowers, path(&[[-1.0, 9.0], [1.0, 11.0]])),
        (Brush::Tint, path(&[[5.0, 1.0], [6.0, 2.0]])),
    ];
    for (brush, points) in strokes {
        edits.write(GrassEdit(brush.stroke(&points)));
    }
}

/// 1 to 7 choose the brush.
fn choose_brush(keys: Res<ButtonInput<KeyCode>>, mut brush: ResMut<Brush>) {
    let brushes = [
        (KeyCode::Digit1, Brush::Mow),
        (KeyCode::Digit2, Brush::Clear),
        (KeyCode::Digit3, Brush::Burn),
        (KeyCode::Digit4, Brush::Regrow),
        (KeyCode::Digit5, Brush::Thin),
        (KeyCode::Digit6, Brush::Flowers),
        (KeyCode::Digit7, Brush::Tint),
    ];
    for (key, chosen) in brushes {
        if keys.just_pressed(key) {
            *brush = chosen;
            info!("brush: {chosen:?}");
        }
    }
}

/// While the left button is held, the ground under the cursor joins the drag; every
/// `SEND_EVERY` seconds, and when the button is let go, the drag is sent as one edit.
fn drag(
    (mouse, time, brush): (Res<ButtonInput<MouseButton>>, Res<Time>, Res<Brush>),
    window: Query<&Window, With<PrimaryWindow>>,
    camera: Single<(&Camera, &GlobalTransform)>,
    mut drag: ResMut<Drag>,
    mut edits: MessageWriter<GrassEdit>,
) {
    let (camera, eye) = *camera;
    let cursor = window.single().ok().and_then(Window::cursor_position);
    let ground = cursor
        .and_then(|c| camera.viewport_to_world(eye, c).ok())
        .and_then(|ray| Some(ray.get_point(ray.intersect_plane(Vec3::ZERO, InfinitePlane3d::new(Vec3::Y))?)));
    if let (true, Some(at)) = (mouse.pressed(MouseButton::Left), ground) {
        drag.points.push(at.xz());
    }
    drag.since += time.delta_secs();
    let let_go = mouse.just_released(MouseButton::Left);
    if !drag.points.is_empty() && (drag.since >= SEND_EVERY || let_go) {
        edits.write(GrassEdit(brush.stroke(&drag.points)));
        // The next stroke starts where this one ended, so a drag paints without gaps.
        let last = *drag.points.last().unwrap();
        drag.points = if let_go { Vec::new() } else { vec![last] };
        drag.since = 0.0;
    }
}
