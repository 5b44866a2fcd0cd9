//! What the repaint tests of both renderers share (stream.rs for the Vulkan renderer,
//! portable.rs for the portable one): a streamed field of 3 × 3 tiles with a trail pressed into
//! it, a mow stroke painted over one of its tiles, and what the stroke may change — the blades
//! under it, and no other blade's pose or collision strength by a bit.
#![allow(dead_code)]

use glam::{Vec2, Vec3};
use sward_core::field::Surface;
use sward_core::instanced::Technique;
use sward_core::paint::Stroke;
use sward_core::stream::TILE_CELLS;
use sward_core::{Blade, Collider, Scene};

/// Blades a tile holds.
const TILE: u32 = TILE_CELLS * TILE_CELLS;

/// A streamed field of 3 × 3 tiles handing over to the instanced grass 6 units from the eye.
pub fn streamed(surface: Surface) -> Scene {
    let mut scene = Scene {
        technique: Technique::Both,
        surface,
        ..Scene::default()
    };
    scene.field.stream = true;
    scene.field.blades = 9 * TILE;
    // Short grass stands under gravity only if stiff.
    scene.field.stiffness = [14.0, 28.0];
    scene.instanced.grid.inner_radius = 6.0;
    scene.instanced.grid.radius = 30.0;
    scene.instanced.lod_distances = [10.0, 15.0, 20.0];
    scene.camera.position = Vec3::new(0.3, 2.0, -0.2);
    scene.camera.target = Vec3::new(0.3, 0.0, 8.0);
    scene.validate("test").unwrap();
    scene
}

/// Where the trail is pressed (world x, z).
pub const TRAIL: Vec2 = Vec2::new(2.0, 3.0);

/// The streamed plane with a ball standing on the trail, its collision strength lasting.
pub fn trailed() -> Scene {
    let mut scene = streamed(Surface::Plane);
    scene.simulation.eta_decay = 0.02;
    scene.colliders = vec![Collider::sphere(Vec3::new(TRAIL.x, 0.3, TRAIL.y), 0.9)];
    scene
}

/// Where the stroke is painted: the middle of the tile at the lowest x and z but one, held
/// around the eye.
pub fn mowed_at(scene: &Scene) -> Vec2 {
    Vec2::splat(-0.5 * scene.stream_window().unwrap().tile_size())
}

/// The stroke: the grass mowed to 0.3 of its height within a unit of [`mowed_at`].
pub fn stroke(scene: &Scene) -> Stroke {
    Stroke::circle(mowed_at(scene), 1.0).mow(0.3)
}

/// `scene` with the stroke painted as a game's edit, the strokes it adds, and the side of a
/// texel of the paint they are painted into, from `paint` (the grown field's).
pub fn painted(
    scene: &Scene,
    paint: &Option<sward_core::paint::GroundPaint>,
) -> (Option<sward_core::paint::GroundPaint>, Vec<Stroke>, f32) {
    let mut edited = scene.clone();
    edited.edits.paint(stroke(scene));
    let added = edited.strokes_added_to(scene).expect("a stroke added").to_vec();
    let mut paint = paint.clone();
    edited.paint_strokes(&mut paint, &added);
    let texel = 1.0 / paint.as_ref().unwrap().map.as_ref().unwrap().texels_per_unit().x;
    (paint, added, texel)
}

/// The blades and collision strengths after the same steps with no stroke (`plain`) and with
/// it (`painted`): every blade beyond the stroke's reach (in its tile or another) the same to
/// the bit, the trail's blades still pressed, the blades under the stroke mowed to 0.3.
pub fn assert_only_the_stroke_changed(scene: &Scene, plain: (&[Blade], &[f32]), painted: (&[Blade], &[f32])) {
    let ((plain, plain_etas), (after, etas)) = (plain, painted);
    let size = scene.stream_window().unwrap().tile_size();
    let mowed_at = mowed_at(scene);
    let tile = (mowed_at / size).floor();
    let in_tile = |b: &Blade| (Vec2::new(b.v0.x, b.v0.z) / size).floor() == tile;
    let (mut kept, mut kept_in_tile, mut mowed) = (0, 0u32, Vec::new());
    for (i, (a, p)) in after.iter().zip(plain).enumerate() {
        // The stroke's radius, and a texel of filtering and a cell beyond it.
        let from_stroke = Vec2::new(p.v0.x, p.v0.z).distance(mowed_at);
        if in_tile(p) && from_stroke < 0.8 && p.height() > 0.0 {
            mowed.push(a.height() / p.height());
        }
        if in_tile(p) && from_stroke < 2.0 {
            continue;
        }
        assert!(
            a == p && etas[i] == plain_etas[i],
            "blade {i}, beyond the stroke's reach (in its tile: {}), is {a:?} (η {}), with no stroke {p:?} (η {})",
            in_tile(p),
            etas[i],
            plain_etas[i]
        );
        kept += 1;
        kept_in_tile += u32::from(in_tile(p));
    }
    let pressed: Vec<usize> = (0..after.len())
        .filter(|&i| after[i].height() > 0.0 && Vec2::new(after[i].v0.x, after[i].v0.z).distance(TRAIL) < 0.5)
        .collect();
    assert!(
        pressed.len() > 20 && pressed.iter().all(|&i| etas[i] > 0.0),
        "the trail's {} blades lost their collision strength",
        pressed.len()
    );
    assert!(
        kept > 8 * TILE && kept_in_tile > TILE / 2 && mowed.len() > 50,
        "{kept} kept ({kept_in_tile} in the stroke's tile), {} mowed",
        mowed.len()
    );
    let tallest = mowed.iter().cloned().fold(0.0, f32::max);
    assert!(
        tallest < 0.35,
        "under the stroke blades stand up to {tallest} of their height, not 0.3"
    );
}
