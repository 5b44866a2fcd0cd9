//! Headless renders of the shipped meadow on the test device: what a person would see (grass
//! in the lower part, sky on top, no broken pixels), a reviewed reference image, and the split
//! of the tessellated draw that lavapipe needs.

mod common;

use std::path::PathBuf;

use sward_core::Scene;
use sward_gpu::{DrawRoute, Headless};

use common::{assert_validation_clean, context, copy_of_shaders, render_by_route};

const WIDTH: u32 = 320;
const HEIGHT: u32 = 240;
const STEPS: u32 = 120;

fn meadow() -> Scene {
    Scene::from_toml(include_str!("../../../scenes/meadow.toml"), "meadow.toml").unwrap()
}

/// Render `scene` at 320×240 after `STEPS` steps by the reference route (tessellation), with the
/// given draw split (`None`: per driver).
fn render(scene: &Scene, patches_per_draw: Option<u32>) -> Vec<u8> {
    render_by(scene, patches_per_draw, DrawRoute::Tessellation)
}

/// As [`render`], the Bezier blades drawn by `route`.
fn render_by(scene: &Scene, patches_per_draw: Option<u32>, route: DrawRoute) -> Vec<u8> {
    render_by_route(scene, [WIDTH, HEIGHT], STEPS, patches_per_draw, route)
}

/// Grass colours: green above red and blue.
fn greenish([r, g, b, _]: [u8; 4]) -> bool {
    g > r && g > b
}

/// Sky colours: blue above red, and not below green.
fn skyish([r, g, b, _]: [u8; 4]) -> bool {
    b > r && b >= g
}

fn pixel(image: &[u8], x: u32, y: u32) -> [u8; 4] {
    let i = 4 * (y * WIDTH + x) as usize;
    [image[i], image[i + 1], image[i + 2], image[i + 3]]
}

/// Largest channel difference per pixel.
fn difference(a: &[u8], b: &[u8]) -> Vec<u8> {
    a.as_chunks::<4>()
        .0
        .iter()
        .zip(b.as_chunks::<4>().0.iter())
        .map(|(p, q)| (0..3).map(|k| p[k].abs_diff(q[k])).max().unwrap())
        .collect()
}

fn output_dir() -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("render-tests");
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn save(path: &std::path::Path, pixels: &[u8]) {
    image::RgbaImage::from_raw(WIDTH, HEIGHT, pixels.to_vec())
        .unwrap()
        .save(path)
        .unwrap();
}

#[test]
fn meadow_shows_grass_below_sky_and_no_broken_pixels() {
    let scene = meadow();
    let with_grass = render(&scene, None);
    // The same frame with every blade culled: sky and ground only.
    let mut bare = scene.clone();
    bare.cull.distance = true;
    bare.cull.distance_max = 1e-3;
    let without_grass = render(&bare, None);

    let diff = difference(&with_grass, &without_grass);
    let grass_share = diff.iter().filter(|d| **d > 12).count() as f32 / diff.len() as f32;
    assert!(
        (0.3..0.8).contains(&grass_share),
        "grass covers {:.0}% of the image",
        grass_share * 100.0
    );

    // Every pixel of the top fifth is sky: blue above red and green, untouched by grass.
    for y in 0..HEIGHT / 5 {
        for x in 0..WIDTH {
            let [r, g, b, _] = pixel(&with_grass, x, y);
            assert!(b > r && b > g, "pixel ({x}, {y}) = ({r}, {g}, {b}) is not sky");
            assert!(diff[(y * WIDTH + x) as usize] <= 12, "grass at ({x}, {y}) in the sky");
        }
    }
    // The bottom rows are mostly grass: green above red and blue.
    let bottom = (0..WIDTH).filter(|&x| {
        let [r, g, b, _] = pixel(&with_grass, x, HEIGHT - 3);
        g > r && g > b
    });
    assert!(bottom.count() as u32 > WIDTH * 9 / 10, "the bottom row is not grass");
    // NaN/Inf maths shows as magenta (shading.wesl `guard_color`).
    let broken = with_grass
        .as_chunks::<4>()
        .0
        .iter()
        .filter(|p| p[0] > 200 && p[1] < 50 && p[2] > 200)
        .count();
    assert_eq!(broken, 0, "{broken} magenta (NaN/Inf) pixels");
    assert!(
        with_grass.as_chunks::<4>().0.iter().all(|p| p[3] == 255),
        "every pixel is opaque"
    );
}

#[test]
fn meadow_matches_the_reviewed_reference() {
    let actual = render(&meadow(), None);
    compare_with_reference(&actual, "meadow-320x240.png");
}

/// Compare with the reviewed image `name` in tests/reference (SWARD_BLESS=1 rewrites it); on a
/// mismatch the actual image and the difference are saved for review.
fn compare_with_reference(actual: &[u8], name: &str) {
    if std::env::var_os("SWARD_BLESS").is_some() {
        save(&reference_path(name), actual);
    }
    let reference = reference_image(name);
    let diff = difference(actual, &reference);
    let mean = diff.iter().map(|d| *d as f32).sum::<f32>() / diff.len() as f32;
    let large = diff.iter().filter(|d| **d > 64).count() as f32 / diff.len() as f32;
    if mean > 3.0 || large > 0.02 {
        let dir = output_dir();
        save(&dir.join(format!("actual-{name}")), actual);
        let visible: Vec<u8> = diff
            .iter()
            .flat_map(|d| [d.saturating_mul(4), d.saturating_mul(4), d.saturating_mul(4), 255])
            .collect();
        save(&dir.join(format!("difference-{name}")), &visible);
        panic!(
            "{name} differs from the reference: mean {mean:.2}, {:.2}% of pixels by more than 64; see {}",
            large * 100.0,
            dir.display()
        );
    }
}

fn reference_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("tests/reference/{name}"))
}

/// The reviewed image `name` as RGBA8.
fn reference_image(name: &str) -> Vec<u8> {
    let path = reference_path(name);
    image::open(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e} (SWARD_BLESS=1 writes it)", path.display()))
        .to_rgba8()
        .into_raw()
}

/// Every route draws the reference route's picture: the strips and the mesh shaders' strips of
/// the meadow and of the trample scene (spheres, trails, shadows) against tessellated patches,
/// within the tolerance of the reviewed references (a mean channel difference of at most 3, at
/// most 2 % of pixels off by more than 64). The routes differ only in where they cut a blade
/// along its height — the tessellator spaces its rows fractionally, the strips evenly — so
/// edges move by a fraction of a pixel. Measured on Mesa 25's lavapipe: the meadow mean 0.81
/// (strips) and 1.19 (mesh shaders), the trample scene's thousands of thin, strongly bent blades
/// 1.74 and 1.64, never above 0.01 % of pixels beyond 64.
#[test]
fn strips_and_mesh_shaders_draw_the_tessellation_routes_picture() {
    let scenes = [
        ("meadow", meadow()),
        (
            "trample",
            Scene::from_toml(include_str!("../../../scenes/trample.toml"), "trample.toml").unwrap(),
        ),
    ];
    for (name, scene) in scenes {
        let reference = render_by(&scene, None, DrawRoute::Tessellation);
        for route in [DrawRoute::Strips, DrawRoute::Mesh] {
            let drawn = render_by(&scene, None, route);
            let diff = difference(&reference, &drawn);
            let mean = diff.iter().map(|d| *d as f32).sum::<f32>() / diff.len() as f32;
            let large = diff.iter().filter(|d| **d > 64).count() as f32 / diff.len() as f32;
            // Equal would mean the route was not drawn at all (or drew the same patches).
            let changed = diff.iter().filter(|d| **d > 0).count();
            let route = route.name();
            eprintln!(
                "{name}, {route}: mean {mean:.2}, {:.3}% beyond 64, {changed} pixels changed",
                large * 100.0
            );
            if mean > 3.0 || large > 0.02 || changed == 0 {
                let dir = output_dir();
                save(&dir.join(format!("route-tessellation-{name}.png")), &reference);
                save(&dir.join(format!("route-{route}-{name}.png")), &drawn);
                panic!(
                    "{name}: {route} differs from tessellation by mean {mean:.2}, {:.2}% of pixels by more than 64, {changed} pixels changed; see {}",
                    large * 100.0,
                    dir.display()
                );
            }
        }
    }
}

/// Mesa's lavapipe garbles single tessellated draws of more than ~1024 patches. Whatever the
/// driver, the default draw must look like a draw split into small commands.
#[test]
fn default_draw_matches_a_finely_split_draw() {
    let scene = meadow();
    let default = render(&scene, None);
    let split = render(&scene, Some(256));
    let diff = difference(&default, &split);
    let large = diff.iter().filter(|d| **d > 64).count() as f32 / diff.len() as f32;
    if large > 0.01 {
        let dir = output_dir();
        save(&dir.join("split-default.png"), &default);
        save(&dir.join("split-256.png"), &split);
        panic!(
            "the default draw differs from a 256-patch split in {:.1}% of pixels; see {}",
            large * 100.0,
            dir.display()
        );
    }
}

/// Grass on a closed mesh: the planet scene shows a ball of grass against the sky, with blades
/// standing out of its silhouette on every side (their `up` is the sphere's normal).
#[test]
fn planet_is_a_ball_of_grass_in_the_sky() {
    let scene = Scene::from_toml(include_str!("../../../scenes/planet.toml"), "planet.toml").unwrap();
    let image = render(&scene, None);
    assert!(
        greenish(pixel(&image, WIDTH / 2, HEIGHT / 2)),
        "the planet's centre is not grass"
    );
    for (x, y) in [(2, 2), (WIDTH - 3, 2), (2, HEIGHT - 3), (WIDTH - 3, HEIGHT - 3)] {
        assert!(skyish(pixel(&image, x, y)), "corner ({x}, {y}) is not sky");
    }
    // Walk out from the centre in four directions: grass, then sky, each way.
    for (dx, dy) in [(1i32, 0i32), (-1, 0), (0, 1), (0, -1)] {
        let (mut x, mut y) = ((WIDTH / 2) as i32, (HEIGHT / 2) as i32);
        while x > 0
            && y > 0
            && x < WIDTH as i32 - 1
            && y < HEIGHT as i32 - 1
            && !skyish(pixel(&image, x as u32, y as u32))
        {
            x += dx;
            y += dy;
        }
        let edge = ((x - (WIDTH / 2) as i32).abs() + (y - (HEIGHT / 2) as i32).abs()) as u32;
        assert!(
            (40..HEIGHT).contains(&edge),
            "the grass ends {edge} px from the centre going ({dx}, {dy})"
        );
    }
}

/// Grass on a terrain mesh drawn with its own ground: hills below, sky above, nothing broken.
#[test]
fn hills_grow_grass_on_the_terrain_mesh() {
    let scene = Scene::from_toml(include_str!("../../../scenes/hills.toml"), "hills.toml").unwrap();
    let image = render(&scene, None);
    let row_share = |y: u32, f: &dyn Fn([u8; 4]) -> bool| (0..WIDTH).filter(|&x| f(pixel(&image, x, y))).count() as u32;
    assert_eq!(row_share(2, &skyish), WIDTH, "the top row is sky");
    assert!(
        row_share(HEIGHT - 3, &greenish) > WIDTH * 9 / 10,
        "the bottom row is grass"
    );
    let broken = image
        .as_chunks::<4>()
        .0
        .iter()
        .filter(|p| p[0] > 200 && p[1] < 50 && p[2] > 200)
        .count();
    assert_eq!(broken, 0, "{broken} magenta (NaN/Inf) pixels");
}

/// Collider spheres are drawn, and the ground still shows between the blades around them.
#[test]
fn trample_draws_its_spheres_over_grass_and_ground() {
    let scene = Scene::from_toml(include_str!("../../../scenes/trample.toml"), "trample.toml").unwrap();
    let image = render(&scene, None);
    // Stone grey: red, green and blue within a few steps of each other, not sky-bright.
    let stone = image
        .as_chunks::<4>()
        .0
        .iter()
        .filter(|p| {
            let (lo, hi) = (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]));
            hi - lo < 30 && hi > 40 && hi < 140
        })
        .count();
    assert!(stone > 500, "only {stone} stone-grey pixels: are the spheres drawn?");
    let bottom = (0..WIDTH).filter(|&x| greenish(pixel(&image, x, HEIGHT - 3))).count() as u32;
    assert!(
        bottom > WIDTH * 9 / 10,
        "the bottom row is not grass and ground ({bottom} of {WIDTH})"
    );
}

/// Mean of all colour channels.
fn brightness(image: &[u8]) -> f32 {
    let sum: u64 = image
        .as_chunks::<4>()
        .0
        .iter()
        .map(|p| p[0] as u64 + p[1] as u64 + p[2] as u64)
        .sum();
    sum as f32 / (3 * image.len() / 4) as f32
}

#[test]
fn colliders_shadow_the_grass_under_a_low_sun() {
    let mut scene = Scene::from_toml(include_str!("../../../scenes/trample.toml"), "trample.toml").unwrap();
    scene.shading.light_direction = glam::Vec3::new(1.0, 0.35, 0.3);
    let lit = {
        let mut s = scene.clone();
        s.shading.shadows = false;
        render(&s, None)
    };
    let shadowed = render(&scene, None);
    let darker = lit
        .as_chunks::<4>()
        .0
        .iter()
        .zip(shadowed.as_chunks::<4>().0.iter())
        .filter(|(a, b)| (a[1] as i32 - b[1] as i32) > 12)
        .count() as f32
        / (WIDTH * HEIGHT) as f32;
    let brighter = lit
        .as_chunks::<4>()
        .0
        .iter()
        .zip(shadowed.as_chunks::<4>().0.iter())
        .filter(|(a, b)| (b[1] as i32 - a[1] as i32) > 12)
        .count();
    assert!(darker > 0.01, "only {:.2}% of pixels fall into shadow", darker * 100.0);
    assert_eq!(brighter, 0, "a shadow never brightens a pixel");
}

#[test]
fn every_shading_term_changes_the_meadow() {
    let mut base = meadow();
    base.field.blades = 12_000;
    // Looking toward the sun, so back-scatter shows.
    base.shading.light_direction = glam::Vec3::new(0.0, 0.4, 1.0);
    let reference = render(&base, None);
    type Change = fn(&mut Scene);
    let variants: [(&str, Change); 4] = [
        ("Lambert", |s| s.shading.model = sward_core::look::ShadingModel::Lambert),
        ("no translucency", |s| s.shading.translucency = 0.0),
        ("no ambient occlusion", |s| s.shading.ambient_occlusion = 0.0),
        ("no clump variation", |s| s.shading.clump_variation = 0.0),
    ];
    for (name, change) in variants {
        let mut scene = base.clone();
        change(&mut scene);
        let image = render(&scene, None);
        let mean = difference(&image, &reference).iter().map(|&d| d as f32).sum::<f32>() / (WIDTH * HEIGHT) as f32;
        // The smallest, the highlight, measures 0.18: looking into the sun the eye sees
        // mostly the blades' far sides, lit through rather than reflecting.
        assert!(
            mean > 0.15,
            "{name}: the image hardly changes (mean difference {mean:.2})"
        );
        if name == "Lambert" {
            assert!(
                brightness(&reference) > brightness(&image),
                "the highlight only adds light"
            );
        }
    }
    let mut no_translucency = base.clone();
    no_translucency.shading.translucency = 0.0;
    assert!(
        brightness(&reference) > brightness(&render(&no_translucency, None)),
        "back-scatter brightens grass seen against the sun"
    );
}

/// Render the meadow's view with a generated technique alone (no Bezier field), check that the
/// bottom row is grass and compare with the reviewed image `reference`.
fn generated_matches_reference(technique: sward_core::instanced::Technique, reference: &str) {
    let mut scene = meadow();
    scene.technique = technique;
    let actual = render_generated(&scene);
    compare_with_reference(&actual, reference);
}

/// The meadow's view of `scene`'s generated grass, its bottom row checked to be grass.
fn render_generated(scene: &Scene) -> Vec<u8> {
    let ctx = context();
    let mut headless = Headless::new(&ctx, WIDTH, HEIGHT, None).unwrap();
    let actual = headless.render_scene(scene, glam::Vec2::splat(60.0), 0).unwrap();
    drop(headless);
    assert_validation_clean(&ctx);
    let grass = (0..WIDTH).filter(|&x| greenish(pixel(&actual, x, HEIGHT - 3))).count() as u32;
    assert!(
        grass > WIDTH * 9 / 10,
        "the bottom row is not grass ({grass} of {WIDTH})"
    );
    actual
}

#[test]
fn instanced_field_matches_its_reviewed_reference() {
    generated_matches_reference(sward_core::instanced::Technique::Instanced, "instanced-320x240.png");
}

/// The billboards drawn by the raster hardware match the reviewed reference (its tolerance); the
/// billboards rasterized by compute (`billboard.raster_distance`, the default where the device has
/// 64-bit atomics) match it band by band: every 20 rows' mean colour within 4 of 255 (measured:
/// 3.8 in blue in the band just below the horizon, where billboards a few pixels tall are seen
/// through the field and lavapipe's alpha-to-coverage covers a little more than the texture's
/// coverage says; elsewhere within 2.5; on the H100 at 1920 × 1080 every 120 rows within 0.6).
/// Pixel by pixel they differ as two dither patterns do (each sample kept by an ordered
/// threshold rather than by the hardware's alpha-to-coverage): a mean of 4.3.
#[test]
fn billboards_match_their_reviewed_reference() {
    let mut scene = meadow();
    scene.technique = sward_core::instanced::Technique::Billboard;
    let rasterized = render_generated(&scene);
    scene.billboard.raster_distance = 1.0e6;
    let drawn = render_generated(&scene);
    compare_with_reference(&drawn, "billboard-320x240.png");
    let reference = reference_image("billboard-320x240.png");
    let band_mean = |image: &[u8], band: usize| -> [f32; 3] {
        let rows = &image[band * 20 * 4 * WIDTH as usize..(band + 1) * 20 * 4 * WIDTH as usize];
        let n = (rows.len() / 4) as f32;
        [0, 1, 2].map(|k| rows.as_chunks::<4>().0.iter().map(|p| p[k] as f32).sum::<f32>() / n)
    };
    for band in 0..HEIGHT as usize / 20 {
        let (r, o) = (band_mean(&reference, band), band_mean(&rasterized, band));
        let worst = (0..3).map(|k| (r[k] - o[k]).abs()).fold(0.0, f32::max);
        assert!(
            worst <= 4.0,
            "rows {}..{}: the rasterized billboards average {o:?}, the reference {r:?}",
            band * 20,
            band * 20 + 20
        );
    }
}

/// The landscape chain renders as one field: grass from the bottom row up to just below the
/// horizon (Bezier blades, instanced blades, billboards, tinted ground in turn), sky above, and no
/// broken pixels.
#[test]
fn landscape_is_grass_from_the_feet_to_the_horizon() {
    let scene = Scene::from_toml(include_str!("../../../scenes/landscape.toml"), "landscape.toml").unwrap();
    let actual = render(&scene, None);
    let magenta = actual
        .as_chunks::<4>()
        .0
        .iter()
        .filter(|p| p[0] > 200 && p[1] < 50 && p[2] > 200)
        .count();
    assert_eq!(magenta, 0, "broken (NaN) pixels");
    let grass_rows = (HEIGHT / 2 + 12..HEIGHT)
        .filter(|&y| (0..WIDTH).filter(|&x| greenish(pixel(&actual, x, y))).count() as u32 > WIDTH * 9 / 10)
        .count() as u32;
    assert_eq!(grass_rows, HEIGHT / 2 - 12, "every row below the horizon band is grass");
    assert!(skyish(pixel(&actual, WIDTH / 2, 4)), "the top is sky");
}

/// The trail scene after ten seconds (balls rolling out through every level of detail, a mower
/// cutting a lane) matches its reviewed picture.
#[test]
fn trail_matches_its_reviewed_reference() {
    let scene = Scene::from_toml(include_str!("../../../scenes/trail.toml"), "trail.toml").unwrap();
    let actual = render_by_route(&scene, [WIDTH, HEIGHT], 1200, None, DrawRoute::Tessellation);
    compare_with_reference(&actual, "trail-320x240.png");
}

/// The park (paint strokes and noise, three kinds of grass, a streamed field through the whole
/// chain) matches its reviewed picture: the gravel path bare from the feet to the horizon, the
/// lawns beside it short, the meadow beyond with its dry grass and patches.
#[test]
fn park_matches_its_reviewed_reference() {
    let scene = Scene::from_toml(include_str!("../../../scenes/park.toml"), "park.toml").unwrap();
    let actual = render_by_route(&scene, [WIDTH, HEIGHT], 240, None, DrawRoute::Tessellation);
    compare_with_reference(&actual, "park-320x240.png");
}

/// Billboard wind: with the scene's wind at strength 0 the billboards stand still however much time
/// passes; with a wind blowing, the same two moments differ.
#[test]
fn billboards_sway_with_the_scene_wind_and_stand_still_without() {
    let ctx = context();
    let mut headless = Headless::new(&ctx, WIDTH, HEIGHT, None).unwrap();
    let mut moments = |strength: f32| {
        let mut scene = meadow();
        scene.technique = sward_core::instanced::Technique::Billboard;
        scene.wind.0[0].strength = strength;
        let field = glam::Vec2::splat(60.0);
        let early = headless.render_scene(&scene, field, 0).unwrap();
        let late = headless.render_scene(&scene, field, 90).unwrap();
        difference(&early, &late).iter().filter(|d| **d > 8).count()
    };
    let calm = moments(0.0);
    let windy = moments(6.0);
    drop(headless);
    assert_validation_clean(&ctx);
    assert_eq!(calm, 0, "billboards moved without wind");
    assert!(
        windy > (WIDTH * HEIGHT / 50) as usize,
        "the wind moved only {windy} pixels"
    );
}

/// The billboards' depth pre-pass (`billboard.depth_prepass`, on by default) shades only the
/// nearest billboard at each sample and keeps the one-pass picture: measured on lavapipe, 2 of the
/// meadow's 307,200 channels differ from one-pass billboards' by more than 8 levels, mean 0.001. A
/// pre-pass whose depths the shading pass does not meet (its `equal` test) loses billboards, and
/// shading all overlapping quads without alpha-to-coverage in either pass changes edges.
#[test]
fn the_billboards_depth_prepass_keeps_their_picture() {
    let ctx = context();
    let mut headless = Headless::new(&ctx, WIDTH, HEIGHT, None).unwrap();
    let mut billboards = |depth_prepass: bool| {
        let mut scene = meadow();
        scene.technique = sward_core::instanced::Technique::Billboard;
        scene.billboard.depth_prepass = depth_prepass;
        headless.render_scene(&scene, glam::Vec2::splat(60.0), 0).unwrap()
    };
    let (prepassed, one_pass) = (billboards(true), billboards(false));
    drop(headless);
    assert_validation_clean(&ctx);
    let diff = difference(&prepassed, &one_pass);
    let mean = diff.iter().map(|&d| d as f32).sum::<f32>() / diff.len() as f32;
    let off = diff.iter().filter(|&&d| d > 8).count();
    eprintln!("pre-pass against one pass: mean {mean:.4}, {off} channels off by more than 8");
    assert!(
        mean < 0.05 && off <= diff.len() / 2000,
        "the pre-passed billboards differ from one-pass billboards: mean {mean:.3}, {off} channels off by more than 8"
    );
}

/// The shipped shaders copied to the tests' folder `name` with each file's replacements made
/// (each `from` must still be there; a core WESL module, `NAME.wesl`, is taken from the built-in
/// ones and replaces it), compiled at run time.
fn patched_shaders(name: &str, edits: &[(&str, Vec<(&str, String)>)]) -> sward_gpu::shaders::ShaderSet {
    let dst = copy_of_shaders(name);
    for (file, replacements) in edits {
        let path = dst.join(file);
        let core = sward_core::wgsl::MODULES
            .iter()
            .find(|(module, _)| file.strip_suffix(".wesl") == Some(*module));
        let mut text = match core {
            Some((_, text)) => text.to_string(),
            None => std::fs::read_to_string(&path).unwrap(),
        };
        for (from, to) in replacements {
            assert!(text.contains(from), "{file} no longer holds `{from}`");
            text = text.replace(from, to);
        }
        std::fs::write(&path, text).unwrap();
    }
    sward_gpu::shaders::ShaderSet::compile(&dst)
        .unwrap_or_else(|e| panic!("the shaders of {name} do not compile: {e:?}"))
}

/// A copy of the shipped shaders where the drawn blades' and billboards' colour variation is
/// found at each fragment, as it once was: every vertex stage hands the fragments the blade's
/// key (exact, in two halves, flat) where it hands them the variation found at its vertices.
fn shaders_varied_at_each_fragment() -> sward_gpu::shaders::ShaderSet {
    // The key is not interpolated.
    let flat_out = (" out vec3 out_vary", " flat out vec3 out_vary".to_string());
    patched_shaders(
        "shaders-varied-per-fragment",
        &[
            (
                "bezier_strips.wesl",
                vec![(
                    "albedo_variation(point.position, key, out.look)",
                    "vec3<f32>(f32(key & 0xffffu), f32(key >> 16u), 0.0)".to_string(),
                )],
            ),
            (
                "tessellation.wesl",
                vec![(
                    "albedo_variation(point.position, key, out.look)",
                    "vec3<f32>(f32(key & 0xffffu), f32(key >> 16u), 0.0)".to_string(),
                )],
            ),
            ("blade.tese", vec![flat_out.clone()]),
            ("blade.mesh", vec![flat_out.clone()]),
            (
                "generated_strips.wesl",
                vec![(
                    "albedo_variation(g.point.position, g.hash, out.look)",
                    "vec3<f32>(f32(g.hash & 0xffffu), f32(g.hash >> 16u), 0.0)".to_string(),
                )],
            ),
            (
                "billboards.wesl",
                vec![
                    (
                        "albedo_variation(b.position, b.hash, out.look)",
                        "vec3<f32>(f32(b.hash & 0xffffu), f32(b.hash >> 16u), 0.0)".to_string(),
                    ),
                    (
                        "in.look, in.vary, sunlight",
                        "in.look, albedo_variation(in.position, u32(in.vary.x) | (u32(in.vary.y) << 16u), in.look), sunlight"
                            .to_string(),
                    ),
                    (
                        "@location(3) vary: vec3<f32>",
                        "@location(3) @interpolate(flat) vary: vec3<f32>".to_string(),
                    ),
                ],
            ),
            (
                "blade_fragment.wesl",
                vec![
                    (
                        "in.look, in.vary, sunlight",
                        "in.look, albedo_variation(in.position, u32(in.vary.x) | (u32(in.vary.y) << 16u), in.look), sunlight"
                            .to_string(),
                    ),
                    (
                        "@location(3) vary: vec3<f32>",
                        "@location(3) @interpolate(flat) vary: vec3<f32>".to_string(),
                    ),
                    (
                        "import super::shading::{guard_color,",
                        "import super::shading::{albedo_variation, guard_color,".to_string(),
                    ),
                ],
            ),
        ],
    )
}

/// `scene` drawn as `sward render` draws it, by `shaders`.
fn render_with(scene: &Scene, shaders: &sward_gpu::shaders::ShaderSet) -> Vec<u8> {
    let ctx = context();
    let field = scene.grow_field().unwrap();
    let mut headless = Headless::new(&ctx, WIDTH, HEIGHT, None).unwrap();
    headless.renderer.use_shaders(shaders).unwrap();
    headless.renderer.upload(&field).unwrap();
    headless.renderer.upload_ground(field.ground.as_ref()).unwrap();
    let pixels = headless.render_scene(scene, field.size, 30).unwrap();
    drop(headless);
    assert_validation_clean(&ctx);
    pixels
}

/// The drawn blades' and billboards' colour variation (their own shade and hue, their clump's,
/// the paint's tint) is found at their vertices and interpolated (blade_fragment.wesl says
/// why): the
/// meadow by its Bezier blades, by the instanced grass and as a landscape (Bezier, instanced
/// grass and billboards) draws within 3 levels of 255 of the variation found at each fragment,
/// on under 0.5 % of the pixels (measured on lavapipe: 17, 26 and 21 pixels of 76,800, by 1, 3
/// and 1; at 1920 × 1080 at most 601 pixels, by 1). Finding none (every blade unvaried) puts
/// the instanced grass 41,377 pixels and 11 levels off.
#[test]
fn colour_variation_found_at_the_vertices_matches_the_fragments() {
    // Both compiled at run time, so the two differ in where the variation is found only.
    let shipped = patched_shaders("shaders-shipped", &[]);
    let per_fragment = shaders_varied_at_each_fragment();
    use sward_core::instanced::Technique;
    for technique in [Technique::Bezier, Technique::Instanced, Technique::Landscape] {
        let mut scene = meadow();
        scene.technique = technique;
        let at_vertices = render_with(&scene, &shipped);
        let at_fragments = render_with(&scene, &per_fragment);
        let diff = difference(&at_vertices, &at_fragments);
        let worst = diff.iter().copied().max().unwrap();
        let off = diff.iter().filter(|d| **d > 0).count();
        eprintln!("{technique:?}: {off} pixels differ, by up to {worst} of 255");
        assert!(
            worst <= 3 && off * 200 < diff.len(),
            "{technique:?}: {off} pixels differ, by up to {worst} of 255"
        );
        let grass = at_vertices
            .as_chunks::<4>()
            .0
            .iter()
            .filter(|p| greenish([p[0], p[1], p[2], p[3]]))
            .count();
        assert!(grass > diff.len() / 4, "{technique:?}: grass in {grass} pixels only");
    }
}

/// The shipped shaders with generate_grid.wesl's workgroups queueing their splatted blades
/// from `queue_from` of them up (a WGSL expression), compiled at run time.
fn shaders_queueing_from(queue_from: &str) -> sward_gpu::shaders::ShaderSet {
    patched_shaders(
        &format!("shaders-queue-{}", queue_from.replace(' ', "")),
        &[(
            "generate_grid.wesl",
            vec![("return WORKGROUP - WORKGROUP / 4u;", format!("return {queue_from};"))],
        )],
    )
}

/// A workgroup of the instanced grass whose blades are mostly splatted queues them by the shape
/// of their walk before splatting them (generate_grid.wesl `queue_splats`): each splat cell
/// keeps the nearest of what reaches it whatever the order, so the picture is byte for byte the
/// one splatted as the blades come. The meadow's instanced grass and the landscape are drawn
/// with every workgroup that splats queueing, with none queueing, and as shipped (from three
/// quarters); a queue that lost or repeated a blade, or splatted one with another's shape,
/// would differ.
#[test]
fn splatted_blades_queued_by_their_walk_draw_the_same_picture() {
    let shipped = patched_shaders("shaders-queue-shipped", &[]);
    let always = shaders_queueing_from("1u");
    let never = shaders_queueing_from("WORKGROUP + 1u");
    use sward_core::instanced::Technique;
    for technique in [Technique::Instanced, Technique::Landscape] {
        let mut scene = meadow();
        scene.technique = technique;
        let unqueued = render_with(&scene, &never);
        let grass = unqueued
            .as_chunks::<4>()
            .0
            .iter()
            .filter(|p| greenish([p[0], p[1], p[2], p[3]]))
            .count();
        assert!(
            grass > unqueued.len() / 16,
            "{technique:?}: grass in {grass} pixels only"
        );
        for (name, shaders) in [
            ("every splatting workgroup queueing", &always),
            ("as shipped", &shipped),
        ] {
            let queued = render_with(&scene, shaders);
            let diff = difference(&unqueued, &queued);
            let off = diff.iter().filter(|d| **d > 0).count();
            assert!(
                off == 0,
                "{technique:?}, {name}: {off} pixels differ from the unqueued splats"
            );
        }
    }
}
