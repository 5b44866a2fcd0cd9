//! What the seam tests of both renderers share (lod_seams.rs for the Vulkan renderer,
//! portable.rs for the portable one): the views they look along, the scenes whose hand-overs
//! they cross, and how a seam is told from the rest of a picture — by the rows of the image
//! whose ground distance falls in it, their change frame to frame against the rows around.
#![allow(dead_code)]

use glam::{Vec2, Vec3, Vec4Swizzles};
use sward_core::instanced::{GridParams, InstancedParams, Technique, SPLAT_BAND};
use sward_core::{Camera, Scene};

/// The seam tests' image size.
pub const WIDTH: u32 = 320;
pub const HEIGHT: u32 = 240;

/// The landscape chain's hand-overs in [`landscape`] as ground distances: instanced blades sink
/// over the last 15 % of their radius, billboards grow in over their fade and sink over the last
/// 10 % of theirs.
pub const LANDSCAPE_SEAMS: [(f32, f32); 3] = [(34.0, 40.0), (32.0, 40.0), (81.0, 90.0)];

/// [`scene`] drawn by the whole chain: Bezier blades near the eye, instanced blades to 40 units,
/// billboards from 32 to 90.
pub fn landscape(eye: Vec3) -> Scene {
    let mut scene = scene(eye);
    scene.technique = Technique::Landscape;
    scene.instanced.grid.inner_radius = 0.0;
    scene.instanced.grid.radius = 40.0;
    scene.instanced.lod_distances = [6.0, 12.0, 30.0];
    scene.billboard.grid.inner_radius = 32.0;
    scene.billboard.fade = 8.0;
    scene.billboard.grid.radius = 90.0;
    scene
}

/// The instanced grass on a plane seen from `eye` down the field: its levels from 6, 12 and 30
/// units, splatted from 20 where the renderer splats.
pub fn scene(eye: Vec3) -> Scene {
    Scene {
        technique: Technique::Instanced,
        instanced: InstancedParams {
            grid: GridParams {
                density: 40.0,
                radius: 60.0,
                ..GridParams::default()
            },
            lod_distances: [6.0, 12.0, 30.0],
            splat_distance: 20.0,
            ..InstancedParams::default()
        },
        camera: Camera {
            position: eye,
            target: eye + Vec3::new(0.0, -5.0, -20.0),
            fov_y_degrees: 50.0,
            ..Camera::default()
        },
        ..Scene::default()
    }
}

/// Horizontal distance from the eye to the ground seen through the middle of each image row
/// (infinite above the horizon).
pub fn row_distances(camera: &Camera) -> Vec<f32> {
    let inverse = camera.view_projection(WIDTH as f32 / HEIGHT as f32).inverse();
    (0..HEIGHT)
        .map(|row| {
            let ndc_y = (row as f32 + 0.5) / HEIGHT as f32 * 2.0 - 1.0;
            let near = inverse * glam::Vec4::new(0.0, ndc_y, 0.0, 1.0);
            let far = inverse * glam::Vec4::new(0.0, ndc_y, 1.0, 1.0);
            let (a, b) = (near.xyz() / near.w, far.xyz() / far.w);
            let direction = b - a;
            if direction.y >= 0.0 {
                return f32::INFINITY;
            }
            let ground = a + direction * (-a.y / direction.y);
            Vec2::new(ground.x - camera.position.x, ground.z - camera.position.z).length()
        })
        .collect()
}

/// Mean over the rows whose ground distance `keep` accepts of each row's mean colour change.
pub fn mean_change(changes: &[f32], distances: &[f32], keep: impl Fn(f32) -> bool) -> (f32, usize) {
    let rows: Vec<f32> = changes
        .iter()
        .zip(distances)
        .filter(|(_, d)| keep(**d))
        .map(|(c, _)| *c)
        .collect();
    (rows.iter().sum::<f32>() / rows.len().max(1) as f32, rows.len())
}

/// Per image row: the mean over its pixels of the largest channel change from `a` to `b`.
pub fn row_changes(a: &[u8], b: &[u8]) -> Vec<f32> {
    a.as_chunks::<{ 4 * WIDTH as usize }>()
        .0
        .iter()
        .zip(b.as_chunks::<{ 4 * WIDTH as usize }>().0.iter())
        .map(|(a, b)| {
            let sum: u32 = a
                .as_chunks::<4>()
                .0
                .iter()
                .zip(b.as_chunks::<4>().0.iter())
                .map(|(p, q)| (0..3).map(|k| p[k].abs_diff(q[k]) as u32).max().unwrap())
                .sum();
            sum as f32 / WIDTH as f32
        })
        .collect()
}

/// Each boundary of `params` as the band of distances where blades change: the geomorph runs over
/// the last 20 % before a level boundary, the dissolve over `SPLAT_BAND` before the splat distance.
pub fn seams(params: &InstancedParams) -> Vec<(f32, f32)> {
    let splat = params.splat_distance;
    let mut seams: Vec<(f32, f32)> = params.lod_distances.iter().map(|&d| (0.8 * d, d)).collect();
    seams.push((splat * (1.0 - SPLAT_BAND), splat));
    seams
}

/// For each seam `lo..hi`: the rows within `pad` of it change no more than 1.5× (+1) the rows
/// between `gap` and `reach` beyond it on either side. `[pad, gap, reach]` in units.
pub fn assert_no_ring(changes: &[f32], distances: &[f32], seams: &[(f32, f32)], [pad, gap, reach]: [f32; 3]) {
    for &(lo, hi) in seams {
        let (at, rows) = mean_change(changes, distances, |d| d >= lo - pad && d <= hi + pad);
        let (around, around_rows) = mean_change(changes, distances, |d| {
            (d >= lo - reach && d < lo - gap) || (d > hi + gap && d <= hi + reach)
        });
        assert!(rows > 0 && around_rows > 0, "no rows at or around {lo}..{hi}");
        assert!(
            at <= 1.5 * around + 1.0,
            "a ring pops at {lo}..{hi}: rows there change by {at:.2} on average, rows around by {around:.2}"
        );
    }
}

/// A streamed field of 3 × 3 tiles seen from `eye`, handing over to the instanced grass at
/// `hand_over`; no wind, so the settled blades hold still and only what the test changes moves.
pub fn streamed(eye: Vec3, hand_over: f32) -> Scene {
    let mut scene = scene(eye);
    scene.technique = Technique::Both;
    scene.field.stream = true;
    scene.field.blades = 9 * sward_core::stream::TILE_CELLS.pow(2);
    scene.instanced.grid.inner_radius = hand_over;
    scene.camera.target = eye + Vec3::new(0.0, -2.0, -20.0);
    scene.wind.0 = vec![sward_core::wind::Wind::calm()];
    scene.instanced.grid.sway = 0.0;
    // Short grass stands under gravity only if stiff (SPEC §3: the pull is the same for every
    // blade, the recovery grows with the bend).
    scene.field.stiffness = [14.0, 28.0];
    scene.validate("streamed").unwrap();
    scene
}

/// The ground distance of a root `d` from an eye `height` above the plane.
pub fn along_ground(d: f32, height: f32) -> f32 {
    (d * d - height * height).max(0.0).sqrt()
}
