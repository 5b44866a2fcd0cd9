//! Blade shading up close, on the test device, one blade at a time (where nothing hides it):
//! a blade lit from behind glows with the light passing through it, and a blade is rounded —
//! shaded across its width — instead of one flat colour. And the ground: wet ground is standing
//! water that mirrors the sky where it is bare, darker soil where the grass grows.
//!
//! The dark, stair-stepped masses the meadow once showed near the camera were back-lit blades:
//! with the sun on the far side of a blade, its face got ambient light only, one flat dark
//! colour from root to tip and edge to edge; its top outline, where the blade's own sunlit tip
//! folds over it toward the eye, is a straight line, and overlapping blades' outlines read as
//! stair steps in screen-aligned rows. Both tests failed on that shading (the midrib's
//! brightness did not change from root to tip; the two edges were one colour).

mod common;

use glam::{Vec3, Vec4};
use sward_core::blade::Blade;
use sward_core::look::ShadingModel;
use sward_core::{Camera, Scene};

use common::render_one_blade;

const WIDTH: u32 = 240;
const HEIGHT: u32 = 320;

/// One blade at the origin, facing the eye, its tip `lean` away from it, lit by a sun toward
/// `sun`; every shading term that varies along the blade for
/// its own sake (colour gradient, jitter, clumps, ambient occlusion, fog, shadows, the highlight)
/// is off, so what remains is the light; the blade is fully translucent.
fn blade_scene(sun: Vec3, blade_colour: Vec3, lean: f32) -> (Scene, Blade) {
    let mut scene = Scene {
        camera: Camera {
            position: Vec3::new(0.0, 0.55, -2.2),
            target: Vec3::new(0.0, 0.55, 0.0),
            fov_y_degrees: 40.0,
            ..Camera::default()
        },
        ..Scene::default()
    };
    let s = &mut scene.shading;
    s.light_direction = sun.normalize();
    s.root_color = blade_colour;
    s.tip_color = blade_colour;
    s.color_jitter = 0.0;
    s.clump_variation = 0.0;
    s.ambient_occlusion = 0.0;
    s.fog_density = 0.0;
    s.shadows = false;
    s.model = ShadingModel::Lambert;
    s.translucency = 1.0;
    // Orientation 0: its width along x, facing the eye (−z); its tip `lean` away.
    let blade = Blade {
        v0: Vec4::new(0.0, 0.0, 0.0, 0.0),
        v1: Vec4::new(0.0, 1.1, 0.3 * lean, 1.1),
        v2: Vec4::new(0.0, 1.1 - 0.3 * lean, lean, 0.12),
        up: Vec4::new(0.0, 1.0, 0.0, 1.0),
    };
    (scene, blade)
}

/// The frame of `scene` with only `blade`, drawn by the tessellation route without simulating.
fn render(scene: &Scene, blade: Blade) -> Vec<u8> {
    render_one_blade(scene, blade, [WIDTH, HEIGHT])
}

/// Brightness along the blade's midrib (the image's middle column), root to tip: the pixels the
/// blade covers, found in the same frame with the blade painted pure green and the ground red
/// (the sky is blue).
fn midrib_brightness(sun: Vec3) -> Vec<f32> {
    let (scene, blade) = blade_scene(sun, Vec3::new(0.25, 0.5, 0.1), 0.0);
    let lit = render(&scene, blade);
    let (mut mask_scene, _) = blade_scene(sun, Vec3::new(0.0, 1.0, 0.0), 0.0);
    mask_scene.shading.ground_color = Vec3::new(1.0, 0.0, 0.0);
    let mask = render(&mask_scene, blade);
    (0..HEIGHT)
        .rev()
        .filter(|&y| on_blade(&mask, WIDTH / 2, y))
        .map(|y| brightness(&lit, WIDTH / 2, y))
        .collect()
}

/// With the sun behind the blade, high and to the side — on the far side of the blade from the
/// eye, but not in the eye's direction — the blade's face was ambient-only before: one flat
/// colour from root to tip (the flat dark masses). Now light passes through it (translucency 1
/// here, to see it plainly), more toward the thin tip: the middle half of the midrib is brighter
/// than its lowest quarter by more than 3 levels (measured 7.5; before, 0.9 from the
/// into-the-sun highlight alone; the narrowing tip is left out).
#[test]
fn a_blade_lit_from_behind_glows_toward_its_tip() {
    let brightness = midrib_brightness(Vec3::new(0.9, 0.5, 0.3));
    let n = brightness.len();
    assert!(n > 100, "the blade covers {n} midrib pixels");
    let mean = |v: &[f32]| v.iter().sum::<f32>() / v.len() as f32;
    let (root, middle) = (mean(&brightness[..n / 4]), mean(&brightness[n / 4..3 * n / 4]));
    eprintln!("back-lit midrib: root quarter {root:.1}, middle half {middle:.1}");
    assert!(
        middle > root + 3.0,
        "back-lit: root quarter {root:.1}, middle half {middle:.1}"
    );
}

/// A blade is rounded, not a flat card: across its width at mid-height the brightness changes
/// by more than 6 levels from edge to edge (lit from the side, the edge facing the sun is
/// brighter; measured 24), where a flat card is one colour (measured 0 before).
#[test]
fn a_blade_is_shaded_across_its_width() {
    let sun = Vec3::new(0.8, 0.5, -0.3);
    let (scene, blade) = blade_scene(sun, Vec3::new(0.25, 0.5, 0.1), 0.35);
    let lit = render(&scene, blade);
    let (mut mask_scene, _) = blade_scene(sun, Vec3::new(0.0, 1.0, 0.0), 0.35);
    mask_scene.shading.ground_color = Vec3::new(1.0, 0.0, 0.0);
    let mask = render(&mask_scene, blade);
    let rows: Vec<u32> = (0..HEIGHT).filter(|&y| on_blade(&mask, WIDTH / 2, y)).collect();
    let y = rows[rows.len() / 2];
    // The row's blade pixels, one in from each edge (edges are blended with the background).
    let across: Vec<f32> = (0..WIDTH)
        .filter(|&x| on_blade(&mask, x, y))
        .map(|x| brightness(&lit, x, y))
        .collect();
    assert!(across.len() >= 6, "the blade is {} pixels wide", across.len());
    let (left, right) = (across[1], across[across.len() - 2]);
    eprintln!("across the blade at row {y}: edges {left:.1} and {right:.1}");
    assert!((left - right).abs() > 6.0, "edge to edge: {left:.1} and {right:.1}");
}

fn pixel(image: &[u8], x: u32, y: u32) -> [f32; 3] {
    let i = 4 * (y * WIDTH + x) as usize;
    [image[i] as f32, image[i + 1] as f32, image[i + 2] as f32]
}

fn brightness(image: &[u8], x: u32, y: u32) -> f32 {
    let [r, g, b] = pixel(image, x, y);
    0.25 * r + 0.625 * g + 0.125 * b
}

/// Whether pixel (x, y) of the mask frame (blade pure green, ground red, sky blue) is blade.
fn on_blade(mask: &[u8], x: u32, y: u32) -> bool {
    let [r, g, b] = pixel(mask, x, y);
    g > 40.0 && g > 2.0 * r && g > 2.0 * b
}

/// The meadow at night (no sun, a faint sky), 6000 blades, drawn by `route` once without lamps
/// and once with each of `lamps`: the mean brightness of the lower half of each picture.
fn night_meadow_brightness(route: sward_gpu::DrawRoute, lamps: &[Vec<sward_core::look::Lamp>]) -> Vec<f32> {
    let mut scene = Scene::from_toml(include_str!("../../../scenes/meadow.toml"), "meadow.toml").unwrap();
    scene.field.blades = 6000;
    scene.field.size = glam::Vec2::splat(8.0);
    scene.camera.position = Vec3::new(0.0, 1.2, -4.5);
    scene.shading.light_color = Vec3::ZERO;
    scene.shading.sky_zenith *= 0.1;
    scene.quality.route = route;
    let (width, height) = (160, 120);
    let ctx = common::context();
    let field = scene.grow_field().unwrap();
    let mut headless = sward_gpu::Headless::new(&ctx, width, height, None).unwrap();
    headless.renderer.set_route(route);
    headless.renderer.upload(&field).unwrap();
    headless.renderer.upload_ground(field.ground.as_ref()).unwrap();
    headless.simulate(&scene, field.size, 0, 30).unwrap();
    let draw = sward_gpu::Passes {
        simulate: false,
        cull: true,
        draw: true,
    };
    let mut out = Vec::new();
    for with in std::iter::once(&Vec::new()).chain(lamps) {
        let mut desc = headless.frame(&scene, field.size, (0.25, 0));
        desc.lamps = with.clone();
        let pixels = headless.render(&desc, draw).unwrap();
        let lower = &pixels[pixels.len() / 2..];
        out.push(
            lower
                .as_chunks::<4>()
                .0
                .iter()
                .map(|p| p[0] as f32 + p[1] as f32 + p[2] as f32)
                .sum::<f32>()
                / (lower.len() / 4) as f32,
        );
    }
    drop(headless);
    common::assert_validation_clean(&ctx);
    out
}

/// Lamps (point and spot lights besides the sun) light the grass in every route this device
/// has: a point light above the grass before the eye brightens the lower half of the picture;
/// a spot light there pointing up, away from the grass, leaves it as dark as without.
#[test]
fn lamps_light_the_grass_in_every_route() {
    use sward_core::look::{Lamp, Spot};
    let lamp = Lamp {
        position: Vec3::new(0.0, 1.5, -2.5),
        color: Vec3::splat(3.0),
        range: 12.0,
        spot: None,
    };
    let away = Lamp {
        spot: Some(Spot {
            direction: Vec3::Y,
            inner_cos: 0.9,
            outer_cos: 0.8,
        }),
        ..lamp
    };
    for route in [
        sward_gpu::DrawRoute::Tessellation,
        sward_gpu::DrawRoute::Strips,
        sward_gpu::DrawRoute::Compute,
    ] {
        let b = night_meadow_brightness(route, &[vec![lamp], vec![away]]);
        eprintln!(
            "{route:?}: dark {:.1}, a lamp {:.1}, a spot pointing away {:.1}",
            b[0], b[1], b[2]
        );
        assert!(
            b[1] > 1.5 * b[0] + 10.0,
            "{route:?}: a lamp lights the grass from {:.1} to {:.1} only",
            b[0],
            b[1]
        );
        assert!(
            (b[2] - b[0]).abs() < 0.1 * b[0] + 2.0,
            "{route:?}: a spot pointing away changes {:.1} to {:.1}",
            b[0],
            b[2]
        );
    }
}

/// The mean colour of the pixels in rows `rows` and columns `columns`.
fn mean_colour(image: &[u8], rows: std::ops::Range<u32>, columns: std::ops::Range<u32>) -> [f32; 3] {
    let mut sum = [0.0; 3];
    let mut count = 0.0;
    for y in rows {
        for x in columns.clone() {
            let p = pixel(image, x, y);
            (0..3).for_each(|c| sum[c] += p[c]);
            count += 1.0;
        }
    }
    sum.map(|s| s / count)
}

/// Wet ground (`[shading] ground_water`): where the ground is bare — a disc painted clear six
/// units ahead, seen at a glancing angle from a metre up — it is standing water that mirrors
/// the sky (brighter and bluer than the dry soil there), and where the grass grows (the ground
/// near the eye) the soil is darker and mirrors nothing. No grass drawn: its one blade is far
/// out of view.
#[test]
fn wet_ground_is_standing_water_where_bare_and_darker_soil_under_the_grass() {
    let mut scene = Scene {
        camera: Camera {
            position: Vec3::new(0.0, 1.0, 0.0),
            target: Vec3::new(0.0, 0.0, 6.0),
            ..Camera::default()
        },
        ..Scene::default()
    };
    scene.shading.fog_density = 0.0;
    scene.shading.shadows = false;
    scene.paint.strokes = vec![sward_core::paint::Stroke::circle(glam::Vec2::new(0.0, 6.0), 2.0).clear()];
    let paint = scene.grow_field().unwrap().paint;
    let far = Blade {
        v0: Vec4::new(150.0, 0.0, 150.0, 0.0),
        v1: Vec4::new(150.0, 0.5, 150.0, 0.5),
        v2: Vec4::new(150.0, 0.5, 150.0, 0.05),
        up: Vec4::new(0.0, 1.0, 0.0, 1.0),
    };
    let picture = |water: f32| {
        let mut scene = scene.clone();
        scene.shading.ground_water = water;
        let ctx = common::context();
        let mut headless = sward_gpu::Headless::new(&ctx, WIDTH, HEIGHT, None).unwrap();
        headless.renderer.upload_field(&[far], &[]).unwrap();
        headless.renderer.upload_paint(paint.as_ref()).unwrap();
        let pixels = headless.render_scene(&scene, glam::Vec2::splat(400.0), 0).unwrap();
        drop(headless);
        common::assert_validation_clean(&ctx);
        common::save_rgba(&format!("wet-ground-{water}.png"), [WIDTH, HEIGHT], &pixels);
        pixels
    };
    let (dry, wet) = (picture(0.0), picture(1.0));
    // The disc's middle is the middle of the picture (the camera looks at it); the bottom rows
    // are the ground two to three units ahead, where the grass grows.
    let pool = |image: &[u8]| mean_colour(image, HEIGHT / 2 - 6..HEIGHT / 2 + 6, WIDTH / 2 - 10..WIDTH / 2 + 10);
    let near = |image: &[u8]| mean_colour(image, HEIGHT - 24..HEIGHT, 0..WIDTH);
    let sum = |c: [f32; 3]| c[0] + c[1] + c[2];
    let (dry_pool, wet_pool, dry_near, wet_near) = (pool(&dry), pool(&wet), near(&dry), near(&wet));
    eprintln!("pool {dry_pool:.0?} dry, {wet_pool:.0?} wet; near the eye {dry_near:.0?} dry, {wet_near:.0?} wet");
    assert!(
        sum(wet_pool) > 1.5 * sum(dry_pool) && wet_pool[2] > wet_pool[0] + 15.0,
        "the bare ground does not mirror the sky: {wet_pool:.0?} wet, {dry_pool:.0?} dry"
    );
    assert!(
        sum(wet_near) < 0.95 * sum(dry_near) && wet_near[2] <= wet_near[0] + 5.0,
        "the soil under the grass is not darker and dull: {wet_near:.0?} wet, {dry_near:.0?} dry"
    );
}
