//! Occlusion culling with the depth pyramid (SPEC §4): a blade wholly behind a wall is culled, one
//! whose tip just clears the wall's top is kept, and blades in front of or beside the wall are kept
//! — by the paper's three-point test and by the whole-blade test. And grass hides grass: with the
//! nearest blades in the pyramid, an eye down in a dense field draws a fraction of the blades it
//! drew, and the same picture. And an application's mesh, given as spheres that only hide grass,
//! hides the blades behind it and presses none. And the instanced grass on a plane, which tests
//! no occlusion, draws what it draws with the test.

mod common;

use glam::{Vec2, Vec3};
use sward_core::frame::Sphere;
use sward_core::mesh::Mesh;
use sward_core::scene::Surface;
use sward_core::FrameDesc;
use sward_core::{Blade, BladeOccluders, Camera, CullParams, Scene};
use sward_gpu::{Passes, Renderer};

use common::{assert_validation_clean, context, renderer};

/// A wall 6 wide and 5 high (y from -1 to 4) across the view, 10 units ahead of the camera.
fn wall() -> Mesh {
    let positions = vec![
        Vec3::new(-3.0, -1.0, -10.0),
        Vec3::new(3.0, -1.0, -10.0),
        Vec3::new(3.0, 4.0, -10.0),
        Vec3::new(-3.0, 4.0, -10.0),
    ];
    Mesh::new(positions, vec![[0, 1, 2], [0, 2, 3]]).unwrap()
}

fn scene(occlusion: bool, blade_occluders: BladeOccluders) -> Scene {
    Scene {
        // The uniforms then tell the shaders to draw the uploaded mesh as the ground.
        surface: Surface::Mesh {
            path: "wall".into(),
            scale: 1.0,
        },
        camera: Camera {
            position: Vec3::new(0.0, 2.0, 0.0),
            target: Vec3::new(0.0, 2.0, -10.0),
            fov_y_degrees: 50.0,
            near: 0.1,
            far: 100.0,
            ..Camera::default()
        },
        cull: CullParams {
            orientation: false,
            distance: false,
            tiles: false,
            occlusion,
            blade_occluders,
            ..CullParams::default()
        },
        ..Scene::default()
    }
}

fn upright(x: f32, z: f32, height: f32) -> Blade {
    Blade::at_rest(Vec3::new(x, 0.0, z), Vec3::Y, 0.0, height, 0.1, 10.0)
}

/// The ids the cull pass keeps of `blades`, seen by `scene`'s camera.
fn visible(renderer: &mut Renderer, scene: &Scene, blades: &[Blade]) -> Vec<u32> {
    renderer.upload_field(blades, &[]).unwrap();
    renderer.upload_ground(Some(&wall())).unwrap();
    let desc = FrameDesc::of_scene(scene, Vec2::splat(30.0), (0.0, 0), [320, 240]);
    renderer.run_compute(&desc, Passes::CULL).unwrap();
    let mut ids = renderer.read_visible().unwrap().0;
    ids.sort();
    ids
}

#[test]
fn blades_behind_a_wall_are_culled_and_barely_visible_ones_kept() {
    let ctx = context();
    let mut renderer = renderer(&ctx, 0, false);
    // Seen from (0, 2, 0) over the wall's top edge, at z = -15 everything below y = 5 is hidden.
    let blades = [
        upright(0.0, -15.0, 1.0),  // 0: wholly behind the wall
        upright(1.0, -15.0, 5.6),  // 1: only its tip clears the wall, by 0.6
        upright(0.0, -5.0, 1.0),   // 2: in front of the wall
        upright(6.5, -15.0, 1.0),  // 3: beside the wall
        upright(-1.0, -15.0, 4.8), // 4: tall, but its tip stays 0.2 below the line of sight
    ];
    // The paper's test: three points of each blade.
    assert_eq!(
        visible(&mut renderer, &scene(true, BladeOccluders::Count(0)), &blades),
        [1, 2, 3]
    );
    assert_eq!(
        visible(&mut renderer, &scene(false, BladeOccluders::Count(0)), &blades),
        [0, 1, 2, 3, 4]
    );
    // The whole-blade test (with blade occluders; none have been drawn yet): it keeps blade 4,
    // whose padded pieces reach the wall's top edge.
    assert_eq!(
        visible(&mut renderer, &scene(true, BladeOccluders::Auto), &blades),
        [1, 2, 3, 4]
    );
    assert_validation_clean(&ctx);
}

/// A sphere that only hides grass (an application's house, packed into spheres), radius 2,
/// standing on the ground 10 ahead of the camera.
const HOUSE: Sphere = Sphere {
    center: Vec3::new(0.0, 1.0, -10.0),
    radius: 2.0,
};

/// `scene`'s frame over the plane ground with `hiding` spheres that only hide grass and
/// `pushing` ones that press it.
fn frame_with(scene: &Scene, hiding: &[Sphere], pushing: &[Sphere]) -> FrameDesc {
    let mut desc = FrameDesc::of_scene(scene, Vec2::splat(30.0), (0.0, 4), [320, 240]);
    desc.colliders.hiding = hiding.to_vec();
    desc.colliders.pushing = pushing.to_vec();
    desc
}

#[test]
fn spheres_that_only_hide_grass_cull_the_blades_behind_them_and_press_none() {
    let ctx = context();
    let mut renderer = renderer(&ctx, 0, false);
    let scene = Scene {
        surface: Surface::Plane,
        ..scene(true, BladeOccluders::Count(0))
    };
    let blades = [
        upright(0.0, -15.0, 1.0), // 0: behind the house
        upright(0.0, -5.0, 1.0),  // 1: in front of it
        upright(6.5, -15.0, 1.0), // 2: beside it
        upright(0.0, -10.0, 1.0), // 3: inside it
    ];
    let mut cull = |hiding: &[Sphere]| {
        renderer.upload_field(&blades, &[]).unwrap();
        renderer.upload_ground(None).unwrap();
        renderer
            .run_compute(&frame_with(&scene, hiding, &[]), Passes::CULL)
            .unwrap();
        let mut ids = renderer.read_visible().unwrap().0;
        ids.sort();
        ids
    };
    assert_eq!(cull(&[]), [0, 1, 2, 3]);
    assert_eq!(cull(&[HOUSE]), [1, 2]);
    // Stepped with the house around blade 3, it stands as it stood without one; a pushing
    // sphere there (the control) bends it.
    let mut stepped = |hiding: &[Sphere], pushing: &[Sphere]| {
        renderer.upload_field(&blades, &[]).unwrap();
        renderer
            .run_compute(&frame_with(&scene, hiding, pushing), Passes::SIMULATE)
            .unwrap();
        renderer.read_blades().unwrap()[3]
    };
    let alone = stepped(&[], &[]);
    assert_eq!(
        stepped(&[HOUSE], &[]),
        alone,
        "a sphere that only hides pressed the blade"
    );
    let pressed = stepped(&[], &[HOUSE]);
    assert_ne!(pressed, alone, "the control: a pushing sphere presses the blade");
    assert_validation_clean(&ctx);
}

/// An eye at 0.8 looking level into a dense field whose near edge is 2.5 ahead, as cis565's is:
/// the first rows of blades stand taller than the eye and hide almost all behind them.
fn inside_the_grass(occlusion: bool, blade_occluders: BladeOccluders) -> Scene {
    Scene {
        field: sward_core::FieldDesc {
            blades: 1 << 14,
            size: Vec2::splat(6.0),
            ..sward_core::FieldDesc::default()
        },
        camera: Camera {
            position: Vec3::new(0.0, 0.8, 5.5),
            target: Vec3::new(0.0, 0.8, 0.0),
            fov_y_degrees: 45.0,
            near: 0.1,
            far: 100.0,
            ..Camera::default()
        },
        cull: CullParams {
            occlusion,
            blade_occluders,
            distance_max: 20.0,
            ..CullParams::default()
        },
        ..Scene::default()
    }
}

/// The picture of `scene` after 30 steps (the cull before the frame leaves its occluders), and
/// how many blades the frame drew.
fn render_counting(scene: &Scene) -> (Vec<u8>, usize) {
    let ctx = context();
    let field = scene.grow_field().unwrap();
    let mut headless = sward_gpu::Headless::new(&ctx, 240, 180, None).unwrap();
    headless.renderer.upload(&field).unwrap();
    let pixels = headless.render_scene(scene, field.size, 30).unwrap();
    let drawn = headless.renderer.read_visible().unwrap().0.len();
    drop(headless);
    assert_validation_clean(&ctx);
    (pixels, drawn)
}

#[test]
fn grass_hides_grass_and_the_picture_stays() {
    let (reference, all) = render_counting(&inside_the_grass(false, BladeOccluders::Count(0)));
    let (_, by_ground) = render_counting(&inside_the_grass(true, BladeOccluders::Count(0)));
    let (pixels, by_grass) = render_counting(&inside_the_grass(true, BladeOccluders::Auto));
    // The flat ground hides nothing from an eye above it; the nearest blades hide most.
    assert_eq!(by_ground, all, "the ground alone hid blades");
    assert!(
        by_grass * 3 < all,
        "the nearest blades hid too few: {by_grass} of {all} drawn"
    );
    let diff: Vec<u8> = reference
        .as_chunks::<4>()
        .0
        .iter()
        .zip(pixels.as_chunks::<4>().0.iter())
        .map(|(p, q)| (0..3).map(|k| p[k].abs_diff(q[k])).max().unwrap())
        .collect();
    let mean = diff.iter().map(|d| *d as f32).sum::<f32>() / diff.len() as f32;
    let off = diff.iter().filter(|d| **d > 32).count();
    // A culled blade is one nothing of which was seen: the picture may differ only where a
    // blade on the threshold of the test's tolerance sways.
    assert!(
        mean < 0.1 && off * 1000 < diff.len(),
        "the picture changed: mean channel difference {mean}, {off} pixels off by more than 32"
    );
}

/// The depth pyramid the cull tests against: level 0 holds the occluders (here the nearest
/// blades, at thousands of depths), and every texel of every level above is the farthest
/// of the four below it — exactly, or the test would cull what shows.
#[test]
fn each_level_of_the_depth_pyramid_keeps_the_farthest_depth_below_it() {
    let ctx = context();
    let scene = inside_the_grass(true, BladeOccluders::Auto);
    let field = scene.grow_field().unwrap();
    let mut headless = sward_gpu::Headless::new(&ctx, 240, 180, None).unwrap();
    headless.renderer.upload(&field).unwrap();
    headless.render_scene(&scene, field.size, 2).unwrap();
    let levels = headless.renderer.read_depth_pyramid().unwrap();
    let mut depths: Vec<u32> = levels[0].iter().map(|d| d.to_bits()).collect();
    depths.sort_unstable();
    depths.dedup();
    assert!(depths.len() > 1000, "level 0 holds only {} depths", depths.len());
    for (k, pair) in levels.windows(2).enumerate() {
        let (finer, coarser) = (&pair[0], &pair[1]);
        let side = (finer.len() as f64).sqrt() as usize;
        let half = side / 2;
        assert_eq!(coarser.len(), half * half, "level {}", k + 1);
        for y in 0..half {
            for x in 0..half {
                let below = [(0, 0), (1, 0), (0, 1), (1, 1)]
                    .map(|(dx, dy)| finer[(2 * y + dy) * side + 2 * x + dx])
                    .into_iter()
                    .fold(0.0f32, f32::max);
                assert_eq!(coarser[y * half + x], below, "level {} texel ({x}, {y})", k + 1);
            }
        }
    }
    drop(headless);
    assert_validation_clean(&ctx);
}

/// The instanced grass on the plane tests no occlusion (a plane seen from above hides nothing
/// standing on it): the same frame with the test forced on — a sphere that only hides grass,
/// far behind the eye, joins the pyramid — lists the same blades at every level and draws the
/// same pixels.
#[test]
fn the_generated_grass_on_a_plane_draws_the_same_without_the_occlusion_test() {
    use sward_core::plan::{FrameDecisions, RendererCan};
    let ctx = context();
    let scene = Scene {
        technique: sward_core::instanced::Technique::Instanced,
        surface: Surface::Plane,
        ..Scene::default()
    };
    let mut headless = sward_gpu::Headless::new(&ctx, 240, 180, None).unwrap();
    let plain = headless.frame(&scene, Vec2::splat(24.0), (0.0, 0));
    let behind = plain.camera.eye + (plain.camera.eye - scene.camera.target).normalize() * 40.0;
    let mut forced = plain.clone();
    forced.colliders.hiding.push(Sphere {
        center: behind,
        radius: 1.0,
    });
    let generated = RendererCan {
        bezier_field: false,
        ..RendererCan::strips()
    };
    let tested = |desc: &FrameDesc| FrameDecisions::of(desc, generated).occlusion_tested;
    assert!(
        !tested(&plain) && tested(&forced),
        "the frames do not differ in the test"
    );
    let passes = Passes {
        simulate: false,
        cull: true,
        draw: true,
    };
    let mut drawn = |desc: &FrameDesc| {
        let pixels = headless.render(desc, passes).unwrap();
        let counts: Vec<u32> = headless
            .renderer
            .read_instanced_draws()
            .unwrap()
            .iter()
            .map(|d| d.instance_count)
            .collect();
        (pixels, counts)
    };
    let (pixels, counts) = drawn(&plain);
    let (pixels_tested, counts_tested) = drawn(&forced);
    assert!(
        counts.iter().sum::<u32>() > 1000,
        "the view holds too few blades: {counts:?}"
    );
    assert_eq!(counts, counts_tested, "the occlusion test culled blades on the plane");
    let apart = pixels
        .as_chunks::<4>()
        .0
        .iter()
        .zip(pixels_tested.as_chunks::<4>().0.iter())
        .filter(|(a, b)| a != b)
        .count();
    assert_eq!(apart, 0, "{apart} pixels apart with the occlusion test");
    drop(headless);
    assert_validation_clean(&ctx);
}
