//! Blade shadows, on the test device: at quality `ultra` the blades near the eye cast shadows
//! (the shadow map's near cascade) onto the ground, on the side away from the sun, and a blade
//! just off screen still casts its shadow into the view. One blade, a grey ground and a low sun,
//! so every darkened pixel is the blade's shadow.

mod common;

use glam::{Vec2, Vec3, Vec4};
use sward_core::blade::Blade;
use sward_core::cull::ShadowCasting;
use sward_core::quality::QualityPreset;
use sward_core::{Camera, Scene};

use common::render_one_blade;

const WIDTH: u32 = 240;
const HEIGHT: u32 = 320;

/// The eye a unit above the ground looking along +z (+x is the image's left), a sun toward +x
/// at height `sun_y` over one unit across, a grey ground, no fog: the ground's brightness
/// changes only where a shadow falls.
fn scene(sun_y: f32, blade_shadow_distance: f32) -> Scene {
    let mut scene = Scene {
        camera: Camera {
            position: Vec3::new(0.0, 1.0, 0.0),
            target: Vec3::new(0.0, 0.2, 5.0),
            fov_y_degrees: 40.0,
            ..Camera::default()
        },
        ..Scene::default()
    };
    scene.quality.preset = QualityPreset::Ultra;
    let s = &mut scene.shading;
    s.light_direction = Vec3::new(1.0, sun_y, 0.0).normalize();
    s.ground_color = Vec3::splat(0.5);
    s.fog_density = 0.0;
    s.blade_shadow_distance = blade_shadow_distance;
    scene
}

/// An upright blade a unit tall at `root`, its width halfway between the sun's rays and the
/// eye's (seen face-on by neither, edge-on by neither: the orientation test keeps it).
fn blade_at(root: Vec3) -> Blade {
    Blade {
        v0: root.extend(std::f32::consts::FRAC_PI_4),
        v1: (root + Vec3::Y).extend(1.0),
        v2: (root + Vec3::Y).extend(0.15),
        up: Vec4::new(0.0, 1.0, 0.0, 1.0),
    }
}

/// The frame of `scene` with only `blade`, drawn by the tessellation route without simulating.
fn render(scene: &Scene, blade: Blade) -> Vec<u8> {
    render_one_blade(scene, blade, [WIDTH, HEIGHT])
}

/// Pixels darker with blade shadows than without by more than 12 levels (summed over the
/// channels), and the most any pixel brightened.
fn shadowed(with: &[u8], without: &[u8]) -> (Vec<(u32, u32)>, i32) {
    let mut dark = Vec::new();
    let mut brightened = 0;
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let i = 4 * (y * WIDTH + x) as usize;
            let sum = |p: &[u8]| p[i..i + 3].iter().map(|&c| c as i32).sum::<i32>();
            let change = sum(with) - sum(without);
            if change < -12 {
                dark.push((x, y));
            }
            brightened = brightened.max(change);
        }
    }
    (dark, brightened)
}

/// Where world point `p` lands in the image, in pixels.
fn on_screen(scene: &Scene, p: Vec3) -> Vec2 {
    let clip = scene.camera.view_projection(WIDTH as f32 / HEIGHT as f32) * p.extend(1.0);
    let ndc = clip.truncate() / clip.w;
    Vec2::new((ndc.x * 0.5 + 0.5) * WIDTH as f32, (ndc.y * 0.5 + 0.5) * HEIGHT as f32)
}

/// A blade in view casts a shadow on the ground, where the sun's rays say: the shadowed pixels'
/// centre lies near the middle of the line from the blade's root to its tip's shadow. Without
/// blade shadows (`blade_shadow_distance = 0`, or any preset below `ultra`) nothing darkens; and
/// a shadow only ever darkens.
#[test]
fn a_blade_casts_its_shadow_on_the_ground_away_from_the_sun() {
    // At the image's left edge; its shadow reaches 1.7 units toward the right.
    let blade = blade_at(Vec3::new(0.8, 0.0, 3.5));
    let with = render(&scene(0.6, 12.0), blade);
    let without = render(&scene(0.6, 0.0), blade);
    let high = |distance: f32| {
        let mut s = scene(0.6, distance);
        s.quality.preset = QualityPreset::High;
        render(&s, blade)
    };
    let high_unchanged = high(12.0) == high(0.0);
    let (dark, brightened) = shadowed(&with, &without);
    let s = scene(0.6, 12.0);
    let casting = ShadowCasting {
        toward_sun: s.shading.light_direction,
        reach: 12.0,
    };
    let expected = 0.5 * (on_screen(&s, blade.v0.truncate()) + on_screen(&s, casting.tip_shadow(&blade)));
    let centre = dark
        .iter()
        .fold(Vec2::ZERO, |c, &(x, y)| c + Vec2::new(x as f32, y as f32))
        / dark.len().max(1) as f32;
    eprintln!(
        "shadow: {} pixels, centre {centre}, expected near {expected}; brightest change {brightened}",
        dark.len()
    );
    assert!(dark.len() > 150, "the shadow covers {} pixels", dark.len());
    assert!(
        centre.distance(expected) < 25.0,
        "shadow centre {centre}, expected near {expected}"
    );
    assert!(brightened <= 3, "a pixel brightened by {brightened}");
    assert!(high_unchanged, "blade shadows changed the picture at quality high");
}

/// A blade just off screen, the low sun behind it, casts its shadow into the view: the cull
/// keeps blades whose tip's shadow is in view (`cull::ShadowCasting`); before, the frustum test
/// dropped the blade and its shadow with it.
#[test]
fn a_blade_off_screen_casts_its_shadow_into_the_view() {
    // 1.5 units beyond the image's left edge; its shadow reaches 3.3 units toward the right.
    let blade = blade_at(Vec3::new(2.6, 0.0, 4.0));
    let s = scene(0.3, 12.0);
    let root = on_screen(&s, blade.v0.truncate());
    let tip = on_screen(&s, blade.v2.truncate());
    let off = |p: Vec2| p.x < 0.0 || p.x >= WIDTH as f32;
    assert!(off(root) && off(tip), "the blade is in view: root {root}, tip {tip}");
    let (dark, _) = shadowed(&render(&s, blade), &render(&scene(0.3, 0.0), blade));
    eprintln!("shadow of the blade off screen: {} pixels", dark.len());
    assert!(dark.len() > 100, "the shadow covers {} pixels", dark.len());
}

/// The shadow map's field cascade keeps a ground that stands still in an image of its own and
/// copies it in: frames of the hills (terrain casting shadows on the grass) with a ball rolling
/// over them and the camera moving, the sun turning halfway — the ground drawn into the cascade
/// (frames 0 and 3: what places it changed), kept anew (1 and 4), copied in (2 and 5; in 5 the
/// ball gone, so no collider is drawn over the copy and the last frame's ball casts nothing) —
/// are pixel for pixel what a renderer draws that draws the ground into the cascade every frame
/// (`keep_shadow_ground` off, as before it was kept), and the hills' shadows are in them.
#[test]
fn the_field_cascade_s_kept_ground_shades_as_the_ground_drawn_every_frame() {
    use sward_core::Collider;
    use sward_gpu::{Headless, Passes};
    let ctx = common::context();
    let mut scene = Scene::from_toml(include_str!("../../../scenes/hills.toml"), "hills").unwrap();
    scene.field.blades = 3000;
    // A low sun: the hills' shadows fall across the grass and the ground.
    scene.shading.light_direction = Vec3::new(1.0, 0.3, 0.4).normalize();
    let field = scene.grow_field().unwrap();
    let headless = |keep: bool| {
        let mut headless = Headless::new(&ctx, WIDTH, HEIGHT, None).unwrap();
        headless.renderer.keep_shadow_ground = keep;
        headless.renderer.upload(&field).unwrap();
        headless.renderer.upload_ground(field.ground.as_ref()).unwrap();
        headless
    };
    let (mut kept, mut drawn) = (headless(true), headless(false));
    // The blades stand still (no steps): both renderers cull and draw the same poses.
    let passes = Passes {
        simulate: false,
        cull: true,
        draw: true,
    };
    let mut shadowed = 0;
    for frame in 0..6 {
        let mut scene = scene.clone();
        scene.camera.position += Vec3::new(0.4, 0.0, 0.3) * frame as f32;
        if frame < 5 {
            scene.colliders = vec![Collider::sphere(Vec3::new(-2.0 + frame as f32, 5.0, -8.0), 1.5)];
        }
        if frame >= 3 {
            scene.shading.light_direction = Vec3::new(-0.6, 0.35, 1.0).normalize();
        }
        let desc = kept.frame(&scene, field.size, (0.0, 0));
        let [copied, reference] = [&mut kept, &mut drawn].map(|h| h.render(&desc, passes).unwrap());
        let apart = copied
            .as_chunks::<4>()
            .0
            .iter()
            .zip(reference.as_chunks::<4>().0.iter())
            .filter(|(a, b)| a != b)
            .count();
        assert_eq!(apart, 0, "frame {frame}: {apart} pixels apart");
        scene.shading.shadows = false;
        let open = drawn
            .render(&drawn.frame(&scene, field.size, (0.0, 0)), passes)
            .unwrap();
        shadowed += shadowed_pixels(&reference, &open);
    }
    assert!(
        shadowed > 6 * 300,
        "the shadows darken {shadowed} pixels over six frames"
    );
    drop((kept, drawn));
    common::assert_validation_clean(&ctx);
}

/// Pixels of `with` darker than in `without` by more than 12 levels, summed over the channels.
fn shadowed_pixels(with: &[u8], without: &[u8]) -> usize {
    let sum = |p: &[u8; 4]| p[..3].iter().map(|&c| c as i32).sum::<i32>();
    with.as_chunks::<4>()
        .0
        .iter()
        .zip(without.as_chunks::<4>().0.iter())
        .filter(|(w, o)| sum(o) - sum(w) > 12)
        .count()
}
