//! The Bezier blades' draw routes on the test device: the compute route (strips near, splats
//! beyond `lod.splat_distance`, and with `lod.compute_raster` the blades between
//! `lod.strip_distance` and the splats rasterized by compute) draws
//! the tessellation route's picture, with its rasterizer alone too; its hand-overs (strips to
//! compute rasterizer, rasterizer to splats) show no seam — moving a hand-over past blades
//! changes almost nothing; what compute draws lies at the hardware's depth; the mesh route
//! draws the same picture (the tests' lavapipe has mesh shaders), and a device without mesh
//! shaders falls back in one sentence; a device without 64-bit atomics draws by strips what
//! others splat.

mod common;

use glam::{Vec2, Vec3};
use sward_core::{Camera, FieldDesc, Scene};
use sward_gpu::{DrawRoute, Headless};

use common::{assert_validation_clean, context, context_without, render_by_route};
use sward_gpu::Withheld;

const WIDTH: u32 = 320;
const HEIGHT: u32 = 240;
const STEPS: u32 = 60;

/// A dense field seen from a little above eye height, reaching 24 units ahead: the hand-over
/// distances below fall well inside the view.
fn field_scene(splat_distance: f32) -> Scene {
    let mut scene = field_scene_split(0.0, splat_distance);
    scene.lod.compute_raster = false;
    scene
}

/// `field_scene` with the compute route's rasterizer on and its hand-overs at
/// `strip_distance` (strips to the rasterizer) and `splat_distance` (to splats).
fn field_scene_split(strip_distance: f32, splat_distance: f32) -> Scene {
    let mut scene = Scene {
        field: FieldDesc {
            blades: 40_000,
            size: Vec2::splat(30.0),
            height: [0.45, 1.0],
            width: [0.02, 0.045],
            ..FieldDesc::default()
        },
        camera: Camera {
            position: Vec3::new(0.0, 2.5, -14.0),
            target: Vec3::new(0.0, 0.0, 2.0),
            fov_y_degrees: 55.0,
            ..Camera::default()
        },
        ..Scene::default()
    };
    scene.lod.splat_distance = splat_distance;
    scene.lod.compute_raster = true;
    scene.lod.strip_distance = strip_distance;
    scene.cull.distance_max = 60.0;
    scene
}

/// `scene` rendered after `STEPS` steps with the Bezier blades drawn by `route`.
fn render(scene: &Scene, route: DrawRoute) -> Vec<u8> {
    render_by_route(scene, [WIDTH, HEIGHT], STEPS, None, route)
}

/// Per pixel, the largest channel difference.
fn difference(a: &[u8], b: &[u8]) -> Vec<u8> {
    a.as_chunks::<4>()
        .0
        .iter()
        .zip(b.as_chunks::<4>().0.iter())
        .map(|(p, q)| (0..3).map(|k| p[k].abs_diff(q[k])).max().unwrap())
        .collect()
}

fn mean(diff: &[u8]) -> f32 {
    diff.iter().map(|d| *d as f32).sum::<f32>() / diff.len() as f32
}

/// `actual` (drawn by `route`) is the tessellation route's picture `reference`: a mean channel
/// difference of at most 3 and at most 2 % of pixels off by more than 64 (the reviewed
/// references' tolerance), and not identical, which would mean the route drew nothing of its own.
fn assert_same_picture(route: &str, reference: &[u8], actual: &[u8]) {
    let diff = difference(reference, actual);
    let large = diff.iter().filter(|d| **d > 64).count() as f32 / diff.len() as f32;
    let m = mean(&diff);
    if m > 3.0 || large > 0.02 || m == 0.0 {
        let dir = save_on_failure(route, &[("tessellation", reference), (route, actual)]);
        panic!(
            "the {route} route differs from tessellation by mean {m:.2}, {:.2}% of pixels by more than 64; see {dir}",
            large * 100.0
        );
    }
}

fn save_on_failure(name: &str, images: &[(&str, &[u8])]) -> String {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("route-tests");
    std::fs::create_dir_all(&dir).unwrap();
    for (label, pixels) in images {
        let path = dir.join(format!("{name}-{label}.png"));
        image::RgbaImage::from_raw(WIDTH, HEIGHT, pixels.to_vec())
            .unwrap()
            .save(path)
            .unwrap();
    }
    dir.display().to_string()
}

/// With the hand-over at 9 units most of the field is splatted, and the picture is still the
/// tessellation route's: a mean channel difference of at most 3 (splats shade at three points
/// per blade and cover whole cells) and at most 2 % of pixels off by more than 64. The splats
/// must have drawn something: with the splat pass skipped the far field would be bare ground,
/// far more than these bounds.
#[test]
fn the_compute_route_draws_the_tessellation_routes_picture() {
    let scene = field_scene(9.0);
    let reference = render(&scene, DrawRoute::Tessellation);
    assert_same_picture("compute", &reference, &render(&scene, DrawRoute::Compute));
}

/// With every blade rasterized by compute (no strips, no splats) the picture is the
/// tessellation route's within a tighter bound than the splats': a mean channel difference of
/// at most 2 and at most 1 % of pixels off by more than 64 (measured 1.77 and 0.001 %). It
/// samples where 4× MSAA samples and cuts blades as the strips do, so what differs is the
/// segment count per distance bucket (as for strips) and the shading rate, not coverage.
#[test]
fn the_compute_rasterizer_alone_draws_the_tessellation_routes_picture() {
    let scene = field_scene_split(0.0, 1000.0);
    let reference = render(&scene, DrawRoute::Tessellation);
    let actual = render(&scene, DrawRoute::Compute);
    let diff = difference(&reference, &actual);
    let large = diff.iter().filter(|d| **d > 64).count() as f32 / diff.len() as f32;
    let m = mean(&diff);
    eprintln!(
        "rasterizer vs tessellation: mean {m:.3}, {:.3}% by more than 64",
        large * 100.0
    );
    assert_same_picture("rasterizer", &reference, &actual);
    assert!(
        m <= 2.0 && large <= 0.01,
        "mean {m:.2}, {:.2}% by more than 64",
        large * 100.0
    );
}

/// The rasterizer's first pass trusts the last frame's tile depths and its second draws what
/// they wrongly hid: a frame of the test view drawn right after one from the far side of the
/// field (whose depths say near where this view sees far) is byte for byte the test view drawn
/// first. Neither the passes' split nor the order blades ran in shows in the picture.
#[test]
fn the_rasterizers_second_pass_draws_what_the_last_frame_hid() {
    let scene = field_scene_split(0.0, 1000.0);
    let mut turned = scene.clone();
    turned.camera.position = Vec3::new(0.0, 2.5, 14.0);
    turned.camera.target = Vec3::new(0.0, 0.0, -2.0);
    let fresh = render(&scene, DrawRoute::Compute);
    let ctx = context();
    let field = scene.grow_field().unwrap();
    let mut headless = Headless::new(&ctx, WIDTH, HEIGHT, None).unwrap();
    assert_eq!(headless.renderer.set_route(DrawRoute::Compute), None);
    headless.renderer.upload(&field).unwrap();
    let by_compute = |scene: &Scene| Scene {
        quality: sward_core::quality::Quality {
            route: DrawRoute::Compute,
            ..scene.quality
        },
        ..scene.clone()
    };
    let before = headless.render_scene(&by_compute(&turned), field.size, STEPS).unwrap();
    let after = headless.render_scene(&by_compute(&scene), field.size, 0).unwrap();
    drop(headless);
    assert_validation_clean(&ctx);
    assert!(
        mean(&difference(&before, &fresh)) > 5.0,
        "the turned view shows another picture"
    );
    if after != fresh {
        let dir = save_on_failure("second-pass", &[("fresh", &fresh), ("after-turn", &after)]);
        let diff = difference(&fresh, &after);
        let off = diff.iter().filter(|d| **d > 0).count();
        panic!(
            "after a turned frame the view differs in {off} pixels (mean {:.3}); see {dir}",
            mean(&diff)
        );
    }
}

/// Moving the hand-over from 8 to 11 units turns the blades between from strips into splats and
/// changes nothing else. A seam a person sees is a band that turns brighter, darker or another
/// hue; per-pixel speckle where a splat covers its cells a little differently from the strip's
/// rasterized edges is not. Bounds: the mean colour of no band of 5 rows moves by more than 2.5
/// in any channel (about 2 % of 125, where a band starts to show; measured 2.4 — 1.4 before
/// blades were rounded: a splat is shaded at one point across its blade with the unrounded
/// normal, the strips average the rounded width), the whole image changes by at most 1 per pixel
/// (measured 0.85) and the most changed row by at most 12 per pixel (measured 9.9: thin blades
/// of one to three pixels, whose splat cells land on neighbouring pixels).
#[test]
fn moving_the_compute_hand_over_past_blades_changes_almost_nothing() {
    let near = render(&field_scene(8.0), DrawRoute::Compute);
    let far = render(&field_scene(11.0), DrawRoute::Compute);
    assert_no_seam("hand-over", &near, &far, [1.0, 12.0, 2.5]);
}

/// Moving the hand-over from strips to the compute rasterizer from 4 to 7 units (splats from 9)
/// turns the blades between from hardware strips into compute-rasterized triangles: a band's
/// colour may move by at most 2, the image by at most 0.5 per pixel and 8 in the worst row
/// (measured 0.34, 0.45 and 2.2; the rasterizer shades per sample, the hardware per pixel, which
/// shows a little across rounded blades).
#[test]
fn moving_the_rasterizer_hand_over_past_blades_changes_almost_nothing() {
    let near = render(&field_scene_split(4.0, 9.0), DrawRoute::Compute);
    let far = render(&field_scene_split(7.0, 9.0), DrawRoute::Compute);
    assert_no_seam("rasterizer-hand-over", &near, &far, [0.5, 8.0, 2.0]);
}

/// `near` and `far` differ only by a hand-over moved past blades: the whole image changes by at
/// most `limits[0]` per pixel (and by something: the hand-over moved blades), its worst row by
/// at most `limits[1]`, and no band of 5 rows moves its mean colour by more than `limits[2]`
/// in any channel.
fn assert_no_seam(name: &str, near: &[u8], far: &[u8], limits: [f32; 3]) {
    let diff = difference(near, far);
    let whole = mean(&diff);
    let worst_row = diff
        .as_chunks::<{ WIDTH as usize }>()
        .0
        .iter()
        .map(|row| mean(row))
        .fold(0.0f32, f32::max);
    let row_colour = |image: &[u8], row: usize, k: usize| {
        let pixels = &image[row * 4 * WIDTH as usize..(row + 1) * 4 * WIDTH as usize];
        pixels.as_chunks::<4>().0.iter().map(|p| p[k] as f32).sum::<f32>() / WIDTH as f32
    };
    const BAND: usize = 5;
    let band_shift = |first: usize, k: usize| {
        let rows = first..first + BAND;
        rows.map(|row| row_colour(far, row, k) - row_colour(near, row, k))
            .sum::<f32>()
            .abs()
            / BAND as f32
    };
    let shift = (0..=HEIGHT as usize - BAND)
        .flat_map(|first| (0..3).map(move |k| (first, k)))
        .map(|(first, k)| band_shift(first, k))
        .fold(0.0f32, f32::max);
    eprintln!("{name}: {whole:.3} per pixel, worst row {worst_row:.2}, band shift {shift:.2}");
    if whole > limits[0] || worst_row > limits[1] || shift > limits[2] || whole == 0.0 {
        let dir = save_on_failure(name, &[("near", near), ("far", far)]);
        panic!(
            "moving the hand-over changed the image by {whole:.2} per pixel, {worst_row:.2} in the worst row, a band's mean colour by {shift:.2}; see {dir}"
        );
    }
}

/// The mesh route (a task shader culls and a mesh shader builds each blade's strip) draws the
/// tessellation route's picture, within the reviewed references' tolerance, with the validation
/// layer silent. It needs a device with mesh shaders, and fails where it finds none: the tests'
/// lavapipe (Mesa 25, which the scripts install) has them.
#[test]
fn the_mesh_route_draws_the_tessellation_routes_picture() {
    let ctx = context();
    assert!(
        ctx.info.mesh_shaders,
        "this test needs a device with mesh shaders (VK_EXT_mesh_shader), and {} has none: on Debian 12, Mesa 25's lavapipe from bookworm-backports (scripts/setup.sh installs it)",
        ctx.info.name
    );
    drop(ctx);
    let scene = field_scene(9.0);
    let reference = render(&scene, DrawRoute::Tessellation);
    let mesh = render_on(&context(), &scene, DrawRoute::Mesh, None);
    assert_same_picture("mesh", &reference, &mesh);
}

/// In motion the mesh route hands its blades from level to level of detail as the tessellator
/// does (each blade's segments follow its distance): a step of the camera (5 cm forward)
/// changes the mesh route's picture about as much as it changes the tessellation route's — a
/// ring of blades popping between levels would add to it. Measured on Mesa 25's lavapipe: mean
/// 9.06 (tessellation) and 9.03 (mesh); allowed: a tenth more.
#[test]
fn a_step_of_the_camera_changes_the_mesh_routes_picture_as_much_as_the_tessellators() {
    let scene = field_scene(9.0);
    let mut stepped = scene.clone();
    let step = glam::Vec3::new(0.0, 0.0, 0.05);
    stepped.camera.position += step;
    stepped.camera.target += step;
    let change = |route: DrawRoute| {
        let (before, after) = (render(&scene, route), render(&stepped, route));
        let diff = difference(&before, &after);
        eprintln!(
            "{}: a step changes the picture by mean {:.3}",
            route.name(),
            mean(&diff)
        );
        (mean(&diff), before, after)
    };
    let (tessellated, ..) = change(DrawRoute::Tessellation);
    let (mesh, before, after) = change(DrawRoute::Mesh);
    assert!(tessellated > 0.0, "the step moved the picture");
    if mesh > tessellated * 1.1 {
        let dir = save_on_failure("mesh-step", &[("before", &before), ("after", &after)]);
        panic!("a step changed the mesh route's picture by mean {mesh:.3}, the tessellator's by {tessellated:.3}; see {dir}");
    }
}

/// Where a device has no mesh shaders, asking for the mesh route falls back to the route `auto`
/// picks, with one sentence naming what is missing and the route drawn instead, said once.
#[test]
fn a_device_without_mesh_shaders_falls_back_in_one_sentence() {
    let ctx = context_without(Withheld {
        mesh_shaders: true,
        ..Withheld::default()
    });
    let mut headless = Headless::new(&ctx, WIDTH, HEIGHT, None).unwrap();
    let note = headless.renderer.set_route(DrawRoute::Mesh).map(str::to_string);
    let note = note.expect("a route the device lacks is said");
    assert!(
        note.contains("mesh shaders (VK_EXT_mesh_shader)") && note.contains("drawing by the compute route instead"),
        "{note}"
    );
    assert_eq!(note.lines().count(), 1, "{note}");
    assert_eq!(
        headless.renderer.route(),
        DrawRoute::Compute,
        "the route auto picks draws"
    );
    assert_eq!(headless.renderer.set_route(DrawRoute::Compute), None, "said once");
    drop(headless);
    assert_validation_clean(&ctx);
}

/// The compute route's splats sit where the hardware draws the same blades: with every blade
/// splatted (hand-over at 0) and the ground painted red, the pixels that are grass in both the
/// tessellated and the splatted frame hold nearly the same depth. Measured as view depth
/// (distance along the view axis), the median pixel differs by under 1 % and three quarters of
/// them by under 5 % (measured 0.32 % and 0.85 % over 24,000 pixels): splats take the depth of
/// the blade's centre line, so a blade seen at a slant differs a little, and where an edge falls
/// differently another blade shows through.
#[test]
fn splatted_blades_lie_at_the_hardware_routes_depth() {
    let [median, upper] = compute_depth_against_hardware(field_scene(0.0));
    assert!(
        median < 0.01 && upper < 0.05,
        "splat depth vs hardware depth: median {:.2} %, 75th percentile {:.2} %",
        median * 100.0,
        upper * 100.0
    );
}

/// The compute rasterizer's samples lie where the hardware's do: with every blade rasterized by
/// compute, the median grass pixel's view depth differs from the tessellated frame's by under
/// 0.1 % and three quarters by under 1 % (measured 0.01 % and 0.02 %): the same triangles,
/// interpolated alike.
#[test]
fn rasterized_blades_lie_at_the_hardware_routes_depth() {
    let [median, upper] = compute_depth_against_hardware(field_scene_split(0.0, 1000.0));
    assert!(
        median < 0.001 && upper < 0.01,
        "rasterized depth vs hardware depth: median {:.3} %, 75th percentile {:.3} %",
        median * 100.0,
        upper * 100.0
    );
}

/// The median and 75th percentile of the relative view-depth difference between the compute
/// route's and the tessellation route's frames of `scene`, over pixels that are grass in both
/// (red ground, no fog, one sample per pixel).
fn compute_depth_against_hardware(mut scene: Scene) -> [f32; 2] {
    let ctx = context();
    scene.shading.ground_color = Vec3::new(1.0, 0.0, 0.0);
    scene.shading.fog_density = 0.0;
    let frame = |route: DrawRoute| {
        // One sample per pixel: the depth buffer then holds one depth per pixel to read back.
        let desc = sward_gpu::RendererDesc::for_quality(
            &ctx.info,
            sward_gpu::target::OFFSCREEN_FORMAT,
            sward_core::quality::QualityPreset::Low,
            1,
        );
        let mut headless = Headless::with_desc(&ctx, WIDTH, HEIGHT, &desc).unwrap();
        let field = scene.grow_field().unwrap();
        headless.renderer.upload(&field).unwrap();
        let mut scene = scene.clone();
        scene.quality.route = route;
        let pixels = headless.render_scene(&scene, field.size, STEPS).unwrap();
        let depth = headless.target.read_depth().unwrap().expect("a single-sample target");
        (pixels, depth)
    };
    let (hw_pixels, hw_depth) = frame(DrawRoute::Tessellation);
    let (splat_pixels, splat_depth) = frame(DrawRoute::Compute);
    assert_validation_clean(&ctx);
    let grass = |p: &[u8; 4]| p[1] > p[0] && p[1] > p[2];
    let (near, far) = (scene.camera.near, scene.camera.far);
    let view_depth = |z: f32| near * far / (far - z * (far - near));
    let mut differences: Vec<f32> = hw_pixels
        .as_chunks::<4>()
        .0
        .iter()
        .zip(splat_pixels.as_chunks::<4>().0.iter())
        .zip(hw_depth.iter().zip(&splat_depth))
        .filter(|((a, b), _)| grass(a) && grass(b))
        .map(|(_, (&a, &b))| (view_depth(a) - view_depth(b)).abs() / view_depth(a))
        .collect();
    assert!(
        differences.len() > (WIDTH * HEIGHT / 5) as usize,
        "only {} pixels are grass in both frames",
        differences.len()
    );
    differences.sort_by(f32::total_cmp);
    let at = |q: f32| differences[((differences.len() - 1) as f32 * q) as usize];
    eprintln!(
        "depth differences: median {:.4}, 75th percentile {:.4}",
        at(0.5),
        at(0.75)
    );
    [at(0.5), at(0.75)]
}

/// A device without 64-bit atomics (withheld here) cannot splat: the compute route falls back
/// to strips, said once, and the instanced grass draws its far blades at its last level — the
/// same picture as the splats make, within the routes' tolerance, with the validation layer
/// silent. The Bezier field with its far half splatted, and the shipped landscape (Bezier,
/// instanced with splats, billboards).
#[test]
fn a_device_without_int64_atomics_draws_what_others_splat() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/landscape.toml");
    let landscape = Scene::load(&path).unwrap();
    for (name, scene) in [("field", field_scene(9.0)), ("landscape", landscape)] {
        let with = render_on(&context(), &scene, DrawRoute::Compute, None);
        let note = "needs 64-bit buffer atomics (shaderBufferInt64Atomics)";
        let without = render_on(
            &context_without(Withheld {
                int64_atomics: true,
                ..Withheld::default()
            }),
            &scene,
            DrawRoute::Compute,
            Some(note),
        );
        assert_same_picture(&format!("{name} without int64 atomics"), &with, &without);
    }
}

/// `scene` drawn on `ctx` by `route`, expecting the renderer's note about it to contain
/// `note` (or to be silent); fails on any validation message.
fn render_on(ctx: &std::sync::Arc<sward_gpu::Context>, scene: &Scene, route: DrawRoute, note: Option<&str>) -> Vec<u8> {
    let field = scene.grow_field().unwrap();
    let mut headless = Headless::new(ctx, WIDTH, HEIGHT, None).unwrap();
    let said = headless.renderer.set_route(route).map(str::to_string);
    match (note, &said) {
        (None, None) => {}
        (Some(words), Some(said)) if said.contains(words) => {}
        _ => panic!("expected a note containing {note:?}, the renderer said {said:?}"),
    }
    headless.renderer.upload(&field).unwrap();
    headless.renderer.upload_ground(field.ground.as_ref()).unwrap();
    let mut scene = scene.clone();
    scene.quality.route = route;
    let pixels = headless.render_scene(&scene, field.size, STEPS).unwrap();
    drop(headless);
    assert_validation_clean(ctx);
    pixels
}
