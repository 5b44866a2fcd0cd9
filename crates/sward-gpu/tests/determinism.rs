//! Same scene, same picture: the order the GPU's workgroups happen to run in must not reach the
//! image. Where two blades meet at exactly the same depth, the one drawn first keeps the sample,
//! so a visible list compacted in whatever order the cull's workgroups appended to it gave a
//! slightly different picture from run to run on a real GPU (the H100: a handful of pixels at
//! 960×540, by up to 17 levels; lavapipe runs its workgroups in one order and hid it). The
//! visible list is now placed by each blade's fixed slot, so the draw order is the field's.
//!
//! lavapipe always runs workgroups in one order, so the test changes the order on purpose:
//! culling with workgroups of 64 and of 256 invocations (the instanced grass's generating passes
//! with 64 and with a patch's 1024) cuts the field into different workgroups, which before
//! appended their blades in a different order (and gave different pictures); now every route
//! must draw byte-identical frames.

mod common;

use glam::Vec3;
use sward_core::quality::QualityPreset;
use sward_core::Scene;
use sward_gpu::pipelines::ComputeOptions;
use sward_gpu::{DrawRoute, Headless};

use common::{assert_validation_clean, context};

const WIDTH: u32 = 320;
const HEIGHT: u32 = 240;
const STEPS: u32 = 30;

/// The frame of `scene` drawn by `route`, culled by workgroups of `workgroup` invocations (the
/// compute passes', the instanced grass's generating passes'), and
/// the visible lists in the order they were drawn (the Bezier blades', then the generated
/// grass's, each blade its 32 bytes, one after another).
fn frame(scene: &Scene, route: DrawRoute, workgroup: (u32, u32)) -> (Vec<u8>, Vec<u32>) {
    let ctx = context();
    let mut desc =
        sward_gpu::RendererDesc::for_quality(&ctx.info, sward_gpu::target::OFFSCREEN_FORMAT, QualityPreset::High, 1);
    desc.compute = ComputeOptions {
        workgroup: workgroup.0,
        instanced_workgroup: workgroup.1,
        ..ComputeOptions::default()
    };
    let mut headless = Headless::with_desc(&ctx, WIDTH, HEIGHT, &desc).unwrap();
    let field = scene.grow_field().unwrap();
    headless.renderer.upload(&field).unwrap();
    let mut scene = scene.clone();
    scene.quality.route = route;
    let pixels = headless.render_scene(&scene, field.size, STEPS).unwrap();
    let (mut ordered, _) = headless.renderer.read_visible().unwrap();
    for list in headless.renderer.read_generated_lists().unwrap() {
        ordered.extend(list.iter().flatten());
    }
    drop(headless);
    assert_validation_clean(&ctx);
    (pixels, ordered)
}

/// Every shipped scene (their Bezier fields at most 40,000 blades).
fn scenes() -> Vec<(&'static str, Scene)> {
    let load = |name: &'static str, text: &str| {
        let mut scene = Scene::from_toml(text, name).unwrap();
        scene.field.blades = scene.field.blades.min(40_000);
        (name, scene)
    };
    vec![
        load("meadow", include_str!("../../../scenes/meadow.toml")),
        load("trample", include_str!("../../../scenes/trample.toml")),
        load("hills", include_str!("../../../scenes/hills.toml")),
        load("planet", include_str!("../../../scenes/planet.toml")),
        load("prairie", include_str!("../../../scenes/prairie.toml")),
        // Bezier blades, the instanced grass and billboards.
        load("landscape", include_str!("../../../scenes/landscape.toml")),
    ]
}

/// The draw order itself: the visible list, in the order it is drawn, is the same blade for
/// blade whichever way the cull is cut (before, 5,779 of the meadow's 14,044 blades moved, on lavapipe
/// too), and so is every route's picture.
#[test]
fn the_draw_order_and_picture_do_not_depend_on_how_the_cull_is_cut_into_workgroups() {
    for (name, mut scene) in scenes() {
        // Red ground: no blade colour hides in the ground's.
        scene.shading.ground_color = Vec3::new(1.0, 0.0, 0.0);
        // The order is the cull's, the same for every route: each route is drawn on the meadow.
        let routes: &[DrawRoute] = match name {
            "meadow" => &[
                DrawRoute::Tessellation,
                DrawRoute::Strips,
                DrawRoute::Compute,
                DrawRoute::Mesh,
            ],
            _ => &[DrawRoute::Tessellation],
        };
        for &route in routes {
            let shipped = (256, ComputeOptions::default().instanced_workgroup);
            let ((a, list_a), (b, list_b)) = (frame(&scene, route, (64, 64)), frame(&scene, route, shipped));
            let moved = list_a.iter().zip(&list_b).filter(|(x, y)| x != y).count();
            let differing = a
                .as_chunks::<4>()
                .0
                .iter()
                .zip(b.as_chunks::<4>().0.iter())
                .filter(|(p, q)| p != q)
                .count();
            eprintln!(
                "{name}, {}: {} list words, {moved} in another place, {differing} pixels differ",
                route.name(),
                list_a.len()
            );
            assert!(list_a.len() > 1000 && list_a.len() == list_b.len());
            assert_eq!(
                moved,
                0,
                "{name} by {}: {moved} blades drawn in another place",
                route.name()
            );
            assert_eq!(differing, 0, "{name} by {}: {differing} pixels differ", route.name());
        }
    }
}

/// Frames of `scene` as the viewer runs them — a cull and a draw each, every other one a step
/// of the physics too, the camera moving and the colliders rolling — with each frame's passes
/// replayed from an earlier frame's recording where nothing that shapes them changed (`keep`)
/// or recorded anew every frame.
/// Halfway, occlusion culling is switched (the depth pyramid's passes come or go); two frames
/// before the end, the other half of the colliders join (more spheres drawn). Returns the images and how many frames were recorded.
fn moving_frames(scene: &Scene, keep: bool) -> (Vec<Vec<u8>>, u64) {
    let ctx = context();
    let mut headless = Headless::new(&ctx, WIDTH, HEIGHT, None).unwrap();
    headless.renderer.keep_recordings = keep;
    let field = scene.grow_field().unwrap();
    headless.renderer.upload(&field).unwrap();
    headless.renderer.upload_ground(field.ground.as_ref()).unwrap();
    let mut scene = scene.clone();
    let colliders = std::mem::take(&mut scene.colliders);
    scene.colliders = colliders[..colliders.len() / 2].to_vec();
    let mut images = Vec::new();
    for frame in 0..MOVING_FRAMES {
        if frame == MOVING_FRAMES / 2 {
            scene.cull.occlusion = !scene.cull.occlusion;
        }
        if frame == MOVING_FRAMES - 2 {
            scene.colliders = colliders.clone();
        }
        scene.camera.position += Vec3::new(0.3, 0.0, 0.2);
        let clock = (frame as f32 * scene.simulation.step, 1 - frame % 2);
        let desc = headless.frame(&scene, field.size, clock);
        images.push(headless.render(&desc, sward_gpu::Passes::ALL).unwrap());
    }
    let recorded = headless.renderer.frames_recorded();
    drop(headless);
    assert_validation_clean(&ctx);
    (images, recorded)
}

const MOVING_FRAMES: u32 = 12;

/// A frame replayed from the last one's recording (only its uniforms written) draws the very
/// bytes a frame recorded anew does, while the camera moves and the colliders roll; a change
/// that shapes the commands (occlusion culling switched, colliders added) is recorded again, not
/// replayed.
#[test]
fn replayed_frames_draw_what_frames_recorded_anew_draw() {
    let scenes = scenes();
    for (name, mut scene) in scenes.into_iter().filter(|(n, _)| ["trample", "landscape"].contains(n)) {
        scene.field.blades = scene.field.blades.min(20_000);
        let (kept, kept_recorded) = moving_frames(&scene, true);
        let (anew, anew_recorded) = moving_frames(&scene, false);
        eprintln!("{name}: {kept_recorded} of {MOVING_FRAMES} frames recorded when kept, {anew_recorded} anew");
        assert_ne!(
            kept[0],
            kept[MOVING_FRAMES as usize - 1],
            "{name}: the frames must move"
        );
        for (k, (a, b)) in kept.iter().zip(&anew).enumerate() {
            let differing = a
                .as_chunks::<4>()
                .0
                .iter()
                .zip(b.as_chunks::<4>().0.iter())
                .filter(|(p, q)| p != q)
                .count();
            assert_eq!(
                differing, 0,
                "{name}, frame {k}: {differing} pixels differ from a frame recorded anew"
            );
        }
        assert_eq!(anew_recorded, MOVING_FRAMES as u64);
        // Frames with and without a step alternate: each kind is recorded once and replayed
        // after (a slot keeps several recordings); recorded again are only the frames after
        // the first (the splat cells and trample map no longer new), after occlusion culling
        // switched and after colliders came — 8 of 12 at most (every frame, with one kept).
        assert!(
            (4..=8).contains(&kept_recorded),
            "{name}: {kept_recorded} frames recorded with recordings kept"
        );
    }
}
