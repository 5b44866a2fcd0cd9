//! Paint over the ground (`sward_core::paint`) holds at every distance: a path painted bare runs
//! from the eye to the horizon through every technique of the landscape chain — Bezier blades
//! (fixed and streamed), the generated blades, the billboards and the tinted ground beyond them —
//! and its edge stands at the same place of the ground in each. Drawn on a red ground, so where
//! grass grows is where the picture is not red.

mod common;

use glam::{Vec2, Vec3};
use sward_core::Scene;
use sward_gpu::DrawRoute;

use common::render_by_route;

const WIDTH: u32 = 480;
const HEIGHT: u32 = 270;
const STEPS: u32 = 60;
/// The path: bare where |x| < PATH_HALF (the map's texels are 0.5 units).
const PATH_HALF: f32 = 4.0;
/// Distances from the eye (along the path) where it is looked at: in the Bezier blades, the
/// generated blades (drawn, then splatted), the billboards and the tinted ground beyond them.
const DISTANCES: [f32; 7] = [5.0, 9.0, 20.0, 40.0, 90.0, 200.0, 500.0];

/// The landscape scene on a red ground, its camera looking along the path; painted with the
/// path where `painted`, its Bezier field streamed where `streamed`.
fn landscape(dir: &std::path::Path, painted: bool, streamed: bool) -> Scene {
    let mut scene = Scene::from_toml(include_str!("../../../scenes/landscape.toml"), "landscape.toml").unwrap();
    scene.shading.ground_color = Vec3::new(1.0, 0.0, 0.0);
    scene.shading.fog_density = 0.0;
    scene.camera.position = Vec3::new(0.0, 2.2, -6.0);
    scene.camera.target = Vec3::new(0.0, 0.0, 40.0);
    if streamed {
        scene.field.stream = true;
        scene.field.blades = 16 * sward_core::stream::TILE_CELLS.pow(2);
    }
    if painted {
        // 2048 units along z in texels of 0.5 × 16 units: bare across |x| < 4 (texels 15 and 16 of
        // 32 over x in -8..8, the edge carrying on beyond them).
        let map = image::GrayImage::from_fn(32, 4, |x, _| image::Luma([if (8..24).contains(&x) { 0 } else { 255 }]));
        let path = dir.join("path.png");
        map.save(&path).unwrap();
        scene.paint.density = Some(path.display().to_string());
        scene.paint.area = [-8.0, -1024.0, 8.0, 1024.0];
    }
    scene.validate("painted landscape").unwrap();
    scene
}

/// Whether a pixel is the red ground.
fn ground(image: &[u8], x: u32, y: u32) -> bool {
    let i = 4 * (y * WIDTH + x) as usize;
    let [r, g, b] = [image[i], image[i + 1], image[i + 2]].map(u32::from);
    r > 60 && r > 2 * g && r > 2 * b
}

/// Where the ground at distance `d` along the path (x = 0) is on screen, and how many pixels
/// one unit across the path is there.
fn on_screen(scene: &Scene, d: f32) -> (Vec2, f32) {
    let view_proj = scene.camera.view_projection(WIDTH as f32 / HEIGHT as f32);
    let z = scene.camera.position.z + d;
    let pixel = |x: f32| {
        let clip = view_proj * glam::Vec4::new(x, 0.0, z, 1.0);
        let ndc = clip.truncate() / clip.w;
        Vec2::new((ndc.x * 0.5 + 0.5) * WIDTH as f32, (ndc.y * 0.5 + 0.5) * HEIGHT as f32)
    };
    let centre = pixel(0.0);
    (centre, (pixel(1.0).x - centre.x).abs())
}

/// The row of the ground at distance `d`, as (ground share across |x| < inner, the bare
/// stretch's half-width in units of ground: the farthest out from the path's middle where
/// ground shows in most of the rows of the band).
fn look_at(image: &[u8], scene: &Scene, d: f32) -> (f32, f32) {
    let (centre, per_unit) = on_screen(scene, d);
    // The row may be flipped by the projection's y; the band is three rows.
    let row = centre.y.round().clamp(1.0, HEIGHT as f32 - 2.0) as u32;
    let rows = [row - 1, row, row + 1];
    let bare_at = |x: i64| {
        let x = x.clamp(0, WIDTH as i64 - 1) as u32;
        rows.iter().filter(|&&y| ground(image, x, y)).count() >= 2
    };
    let inner = (0.5 * PATH_HALF * per_unit).max(1.0) as i64;
    let c = centre.x.round() as i64;
    let inside = (-inner..=inner).filter(|&dx| bare_at(c + dx)).count() as f32 / (2 * inner + 1) as f32;
    // Out from the middle on both sides to the first pixel of grass; the mean of the two.
    let reach = |step: i64| {
        let mut dx = 0;
        while bare_at(c + step * (dx + 1)) && dx < WIDTH as i64 {
            dx += 1;
        }
        dx as f32 / per_unit
    };
    (inside, 0.5 * (reach(1) + reach(-1)))
}

fn save(name: &str, image: &[u8]) {
    common::save_rgba(name, [WIDTH, HEIGHT], image);
}

fn check_path(streamed: bool) {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("paint-{streamed}"));
    std::fs::create_dir_all(&dir).unwrap();
    let size = [WIDTH, HEIGHT];
    let route = DrawRoute::Tessellation;
    let plain_scene = landscape(&dir, false, streamed);
    let painted_scene = landscape(&dir, true, streamed);
    let plain = render_by_route(&plain_scene, size, STEPS, None, route);
    let painted = render_by_route(&painted_scene, size, STEPS, None, route);
    save(&format!("path-plain-{streamed}.png"), &plain);
    save(&format!("path-painted-{streamed}.png"), &painted);
    for d in DISTANCES {
        let (grown, _) = look_at(&plain, &plain_scene, d);
        let (bare, edge) = look_at(&painted, &painted_scene, d);
        // Blades lean over the edge by up to a unit; far off a pixel spans more than that.
        let slack = 1.5f32.max(2.0 / on_screen(&painted_scene, d).1);
        eprintln!(
            "{d:5} units: ground shows over {:.0} % of the path unpainted, {:.0} % painted; bare {edge:.1} units out",
            grown * 100.0,
            bare * 100.0
        );
        assert!(
            grown < 0.35,
            "unpainted, grass covers the path's place {d} units away: {:.0} % ground",
            grown * 100.0
        );
        assert!(
            bare > 0.9,
            "painted bare, the path {d} units away shows ground over only {:.0} %",
            bare * 100.0
        );
        assert!(
            (edge - PATH_HALF).abs() < slack,
            "the path's edge {d} units away stands {edge:.1} units from its middle, painted at {PATH_HALF} (± {slack:.1})"
        );
    }
}

#[test]
fn a_painted_path_is_bare_at_every_distance_with_the_same_edge() {
    check_path(false);
}

#[test]
fn a_painted_path_is_bare_in_a_streamed_field_too() {
    check_path(true);
}

/// The world ground point (y = 0) pixel (x, y) of `scene`'s view looks at, if it looks down.
fn ground_point(scene: &Scene, x: u32, y: u32) -> Option<Vec2> {
    let inverse = scene.camera.view_projection(WIDTH as f32 / HEIGHT as f32).inverse();
    let ndc = Vec2::new(
        (x as f32 + 0.5) / WIDTH as f32 * 2.0 - 1.0,
        (y as f32 + 0.5) / HEIGHT as f32 * 2.0 - 1.0,
    );
    let at = |depth: f32| {
        let p = inverse * glam::Vec4::new(ndc.x, ndc.y, depth, 1.0);
        p.truncate() / p.w
    };
    let (near, far) = (at(0.0), at(1.0));
    let t = near.y / (near.y - far.y);
    (t > 0.0 && t < 1.0).then(|| {
        let p = near + (far - near) * t;
        Vec2::new(p.x, p.z)
    })
}

/// Patches painted by noise: where the CPU's noise says the ground is bare the picture shows
/// ground, where it says grass grows it shows grass — through the Bezier blades and the
/// generated ones alike (up to 40 units away).
#[test]
fn noise_paints_the_same_patches_on_the_gpu_as_on_the_cpu() {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"));
    let mut scene = landscape(&dir, false, false);
    let noise = sward_core::paint::PaintNoise {
        scale: 0.08,
        cover: 0.5,
        softness: 0.0,
    };
    scene.paint.noise = Some(noise);
    let image = render_by_route(&scene, [WIDTH, HEIGHT], STEPS, None, DrawRoute::Tessellation);
    save("noise-patches.png", &image);
    let paint = sward_core::paint::GroundPaint {
        noise: Some(noise),
        ..Default::default()
    };
    // Per side (bare, grown by the CPU's noise): ground pixels, all pixels.
    let mut counts = [[0u32; 2]; 2];
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let Some(xz) = ground_point(&scene, x, y) else {
                continue;
            };
            let dist = (xz - Vec2::new(scene.camera.position.x, scene.camera.position.z)).length();
            let density = paint.at(xz).density;
            // Away from the patches' edges (blades lean over them), within 40 units.
            let near_edge = (noise.density(xz + Vec2::X) != density) || (noise.density(xz + Vec2::Y) != density);
            if dist > 40.0 || near_edge {
                continue;
            }
            let side = (density > 0.5) as usize;
            counts[side][0] += ground(&image, x, y) as u32;
            counts[side][1] += 1;
        }
    }
    let share = |[shown, all]: [u32; 2]| shown as f32 / all.max(1) as f32;
    let (bare, grown) = (share(counts[0]), share(counts[1]));
    eprintln!(
        "ground shows on {:.0} % of {} bare pixels, {:.0} % of {} grown",
        bare * 100.0,
        counts[0][1],
        grown * 100.0,
        counts[1][1]
    );
    assert!(
        counts[0][1] > 2000 && counts[1][1] > 2000,
        "both kinds of patch in sight: {counts:?}"
    );
    assert!(
        bare > 0.85,
        "the noise's bare patches show ground on only {:.0} %",
        bare * 100.0
    );
    assert!(
        grown < 0.35,
        "the noise's grass patches show ground on {:.0} %",
        grown * 100.0
    );
}

/// The landscape scene unpainted and painted with `map` (64 × 4 texels over 400 × 400 units:
/// its left half is x < 0), set as the map `set` names; each with its picture, kept as
/// `{name}-plain.png` and `{name}-painted.png`.
fn painted_half(
    name: &str,
    map: image::DynamicImage,
    set: impl FnOnce(&mut sward_core::paint::PaintParams, String),
) -> [(Scene, Vec<u8>); 2] {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("paint-{name}"));
    std::fs::create_dir_all(&dir).unwrap();
    let plain = landscape(&dir, false, false);
    let mut painted = plain.clone();
    let path = dir.join(format!("{name}.png"));
    map.save(&path).unwrap();
    set(&mut painted.paint, path.display().to_string());
    painted.paint.area = [-200.0, -200.0, 200.0, 200.0];
    [(plain, "plain"), (painted, "painted")].map(|(scene, which)| {
        let image = render_by_route(&scene, [WIDTH, HEIGHT], STEPS, None, DrawRoute::Tessellation);
        save(&format!("{name}-{which}.png"), &image);
        (scene, image)
    })
}

/// The mean colour of the grass (not the red ground) on either side of x = 0 within 40 units,
/// as (x < 0, x > 0).
fn grass_colour_by_side(image: &[u8], scene: &Scene) -> [[f32; 3]; 2] {
    let mut sums = [[0.0f32; 4]; 2];
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let Some(xz) = ground_point(scene, x, y) else {
                continue;
            };
            let dist = (xz - Vec2::new(scene.camera.position.x, scene.camera.position.z)).length();
            if dist > 40.0 || xz.x.abs() < 4.0 || ground(image, x, y) {
                continue;
            }
            let i = 4 * (y * WIDTH + x) as usize;
            let side = &mut sums[(xz.x > 0.0) as usize];
            for k in 0..3 {
                side[k] += image[i + k] as f32;
            }
            side[3] += 1.0;
        }
    }
    sums.map(|s| [s[0] / s[3], s[1] / s[3], s[2] / s[3]])
}

/// A colour map tints the grass where it is painted, through every technique in sight, and
/// leaves it as it was elsewhere: the x < 0 half painted yellower (red × 1.6, blue × 0.5).
#[test]
fn a_colour_map_tints_the_grass_where_it_is_painted() {
    // Texels of 6.25 units: the tint blends from one side to the other over |x| < 3.1.
    let map = image::RgbImage::from_fn(64, 4, |x, _| image::Rgb(if x < 32 { [205, 128, 64] } else { [128; 3] }));
    let [(plain_scene, plain), (tinted_scene, tinted)] =
        painted_half("tint", map.into(), |paint, path| paint.color = Some(path));
    let before = grass_colour_by_side(&plain, &plain_scene);
    let after = grass_colour_by_side(&tinted, &tinted_scene);
    eprintln!("grass colour by side, unpainted {before:?}, painted {after:?}");
    let warmth = |c: [f32; 3]| c[0] / c[2].max(1.0);
    assert!(
        warmth(after[0]) > 1.3 * warmth(before[0]),
        "the painted half's grass: {:?} against {:?} unpainted",
        after[0],
        before[0]
    );
    let change = (0..3).map(|k| (after[1][k] - before[1][k]).abs()).fold(0.0, f32::max);
    assert!(
        (warmth(after[1]) / warmth(before[1]) - 1.0).abs() < 0.05 && change < 4.0,
        "the unpainted half's grass: {:?} against {:?}",
        after[1],
        before[1]
    );
}

/// The share of the pixels looking at the ground on either side of x = 0 (within 40 units,
/// |x| > 4) that show the red ground between the blades, as (x < 0, x > 0).
fn ground_share_by_side(image: &[u8], scene: &Scene) -> [f32; 2] {
    let mut counts = [[0.0f32; 2]; 2];
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let Some(xz) = ground_point(scene, x, y) else {
                continue;
            };
            let dist = (xz - Vec2::new(scene.camera.position.x, scene.camera.position.z)).length();
            if dist > 40.0 || xz.x.abs() < 4.0 {
                continue;
            }
            let side = &mut counts[(xz.x > 0.0) as usize];
            side[0] += ground(image, x, y) as u32 as f32;
            side[1] += 1.0;
        }
    }
    counts.map(|[bare, all]| bare / all.max(1.0))
}

/// A length map shortens the grass where it is painted, through every technique in sight, and
/// leaves it as it was elsewhere: the x < 0 half painted to 0.3 of its height shows more of the
/// ground between its blades.
#[test]
fn a_length_map_shortens_the_grass_where_it_is_painted() {
    let map = image::GrayImage::from_fn(64, 4, |x, _| image::Luma([if x < 32 { 77 } else { 255 }]));
    let [(plain_scene, plain), (mown_scene, mown)] =
        painted_half("length", map.into(), |paint, path| paint.length = Some(path));
    let before = ground_share_by_side(&plain, &plain_scene);
    let after = ground_share_by_side(&mown, &mown_scene);
    eprintln!("ground showing by side, unpainted {before:?}, painted {after:?}");
    assert!(
        after[0] > before[0] + 0.1,
        "the painted half shows {:.2} of its ground against {:.2} unpainted",
        after[0],
        before[0]
    );
    assert!(
        (after[1] - before[1]).abs() < 0.03,
        "the unpainted half shows {:.2} of its ground against {:.2}",
        after[1],
        before[1]
    );
}

/// The landscape's generated grass seen from above (the camera 20 units up), with strokes a
/// game painted: a disc cleared at x = -6, one burnt at x = +6.
fn stroked_from_above(dir: &std::path::Path, strokes: bool) -> Scene {
    let mut scene = landscape(dir, false, false);
    scene.technique = sward_core::instanced::Technique::Instanced;
    scene.camera.position = Vec3::new(0.0, 20.0, -4.0);
    scene.camera.target = Vec3::new(0.0, 0.0, 14.0);
    if strokes {
        use sward_core::paint::Stroke;
        scene.paint.strokes = vec![
            Stroke::circle(CLEARED, 4.0).softness(0.0).clear(),
            Stroke::circle(BURNT_AT, 4.0).softness(0.0).burn(),
        ];
    }
    scene.validate("stroked landscape").unwrap();
    scene
}
const CLEARED: Vec2 = Vec2::new(-6.0, 14.0);
const BURNT_AT: Vec2 = Vec2::new(6.0, 14.0);

/// Strokes a game paints are drawn where `GrassSampler` says they are: where it says nothing
/// grows the picture shows the ground, where it says the grass is burnt the picture's grass is
/// dark; and painted into the paint the renderer holds (`upload_paint`, as the Bevy plugin does
/// with `Grass::paint`) they draw the picture a field grown with them draws.
#[test]
fn a_game_s_strokes_are_drawn_where_the_sampler_says_and_need_no_new_field() {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("paint-strokes");
    std::fs::create_dir_all(&dir).unwrap();
    let stroked = stroked_from_above(&dir, true);
    let grown = render_by_route(&stroked, [WIDTH, HEIGHT], STEPS, None, DrawRoute::Tessellation);
    save("strokes-grown.png", &grown);
    let sampler = sward_core::sample::GrassSampler::new(&stroked).unwrap();
    // Pixels looking at ground well inside each disc (blades outside lean in by up to a unit),
    // and at the grass around them.
    let (mut cleared, mut burnt, mut around) = ([0.0f32; 2], [0.0f32; 2], [0.0f32; 2]);
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let Some(xz) = ground_point(&stroked, x, y) else {
                continue;
            };
            let said = sampler.at(xz);
            let count = |into: &mut [f32; 2], seen: bool| *into = [into[0] + seen as u32 as f32, into[1] + 1.0];
            if xz.distance(CLEARED) < 2.5 {
                assert_eq!(said.density, 0.0, "the sampler says {xz} is cleared");
                count(&mut cleared, ground(&grown, x, y));
            } else if xz.distance(BURNT_AT) < 2.5 {
                assert!(
                    said.tint.distance(sward_core::paint::BURNT) < 0.01,
                    "the sampler says {xz} is burnt"
                );
                count(&mut burnt, green(&grown, x, y));
            } else if (5.5..12.0).contains(&xz.distance(CLEARED).min(xz.distance(BURNT_AT))) {
                // (The landscape's own tint noise tints it, by up to a fifth.)
                let untouched = said.density == 1.0 && said.tint.distance(sward_core::paint::BURNT) > 0.5;
                assert!(untouched, "the sampler says {xz} is untouched: {said:?}");
                count(&mut around, green(&grown, x, y));
            }
        }
    }
    let share = |[seen, all]: [f32; 2]| seen / all.max(1.0);
    eprintln!(
        "cleared: {:.2} ground; burnt: {:.2} green; around: {:.2} green",
        share(cleared),
        share(burnt),
        share(around)
    );
    assert!(
        cleared[1] > 500.0 && share(cleared) > 0.9,
        "where the sampler says bare, {:.2} ground",
        share(cleared)
    );
    assert!(
        burnt[1] > 500.0 && share(burnt) < 0.1,
        "where it says burnt, {:.2} green",
        share(burnt)
    );
    assert!(
        share(around) > 0.4,
        "where it says untouched, {:.2} green",
        share(around)
    );
    // The same strokes painted into the paint of a field grown without them.
    let ctx = common::context();
    let plain = stroked_from_above(&dir, false);
    let mut field = plain.grow_field().unwrap();
    let mut headless = sward_gpu::Headless::new(&ctx, WIDTH, HEIGHT, None).unwrap();
    headless.renderer.set_route(DrawRoute::Tessellation);
    headless.renderer.upload(&field).unwrap();
    let added = stroked.strokes_added_to(&plain).expect("only strokes were added");
    stroked.paint_strokes(&mut field.paint, added);
    headless.renderer.upload_paint(field.paint.as_ref()).unwrap();
    let painted = headless.render_scene(&stroked, field.size, STEPS).unwrap();
    drop(headless);
    common::assert_validation_clean(&ctx);
    save("strokes-painted.png", &painted);
    let differing = grown.chunks(4).zip(painted.chunks(4)).filter(|(a, b)| a != b).count();
    eprintln!("{differing} pixels differ between the field grown with the strokes and the strokes painted in");
    assert!(
        differing * 1000 < (WIDTH * HEIGHT) as usize,
        "{differing} pixels differ between the field grown with the strokes and the strokes painted in"
    );
}

/// Whether a pixel is living grass: green no less than four fifths of red (yellow-green to
/// green), above blue, and not dark. Burnt stubble (red times 0.22, green 0.16) is below.
fn green(image: &[u8], x: u32, y: u32) -> bool {
    let [r, g, b] = [0, 1, 2].map(|k| image[4 * (y * WIDTH + x) as usize + k] as f32);
    g >= 0.8 * r && g > b && g > 20.0
}
