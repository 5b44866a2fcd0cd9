//! The viewer in a real window under Xvfb on the test device: opens, renders 60 frames with the
//! validation layer on, survives a resize half-way, saves a screenshot that shows grass and sky,
//! and exits 0; survives a storm of resizes and panel edits without leaking GPU memory.

use std::path::PathBuf;
use std::process::Command;

/// A light meadow so 60 frames stay quick on a CPU Vulkan driver.
const SCENE: &str = r#"
name = "viewer-test"
[field]
blades = 6000
size = [10.0, 10.0]
height = [0.45, 1.0]
width = [0.03, 0.05]
stiffness = [14.0, 28.0]
[camera]
position = [0.0, 1.6, -7.0]
target = [0.0, 0.5, 0.0]
fov_y_degrees = 55.0
[shading]
ground_color = [0.07, 0.12, 0.03]
"#;

fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("viewer-tests");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// A scratch copy of the test scene `NAME.toml` and the path of its screenshot `NAME.png`,
/// which is not there yet.
fn scene_and_screenshot(name: &str) -> (PathBuf, PathBuf) {
    let scene = scratch(&format!("{name}.toml"));
    std::fs::write(&scene, SCENE).unwrap();
    let shot = scratch(&format!("{name}.png"));
    let _ = std::fs::remove_file(&shot);
    (scene, shot)
}

/// `sward view --validation ARGS` under Xvfb: its output, after checking that it succeeded
/// without a validation message.
fn view(args: &[&str]) -> (String, String) {
    let output = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1024x768x24", env!("CARGO_BIN_EXE_sward"), "view", "--validation"])
        .args(args)
        .env("RUST_LOG", "error")
        .output()
        .unwrap_or_else(|e| panic!("this test runs the viewer under Xvfb and could not start xvfb-run: {e}; install it with apt-get install xvfb xauth"));
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(output.status.success(), "viewer failed: {stderr}");
    assert!(!stderr.contains("validation"), "validation messages: {stderr}");
    (String::from_utf8_lossy(&output.stdout).into_owned(), stderr)
}

/// Whether most of the bottom row's right third (right of the panel) is grass.
fn grass_at_the_bottom_right(image: &image::RgbaImage) -> bool {
    let (w, h) = image.dimensions();
    let grass = (w * 2 / 3..w).filter(|&x| {
        let [r, g, b, _] = image.get_pixel(x, h - 3).0;
        g > r && g > b
    });
    grass.count() as u32 > w / 3 * 8 / 10
}

#[test]
fn viewer_renders_resizes_and_screenshots_under_xvfb() {
    let (scene, shot) = scene_and_screenshot("screenshot");
    let (stdout, _) = view(&[
        "--scene",
        scene.to_str().unwrap(),
        "--width",
        "640",
        "--height",
        "400",
        "--frames",
        "60",
        "--resize-at",
        "30:600x380",
        "--screenshot",
        shot.to_str().unwrap(),
    ]);
    assert!(stdout.contains("drew 60 frames"));

    let image = image::open(&shot).expect("screenshot written").to_rgba8();
    assert_eq!(
        image.dimensions(),
        (600, 380),
        "the screenshot should have the resized window's size"
    );
    // The panel covers the left; look at the right third of the view.
    let w = image.width();
    let sky = (w * 2 / 3..w).all(|x| {
        let [r, g, b, _] = image.get_pixel(x, 4).0;
        b > r && b > g
    });
    assert!(sky, "the top right of the view is not sky");
    assert!(
        grass_at_the_bottom_right(&image),
        "the bottom right of the view is not grass"
    );
}

/// Out of GPU memory at a new window size (provoked by `--gpu-memory`, a budget below the
/// device's): the viewer does not end; it draws the new size with one sample per pixel (and says
/// why in its panel), grass and all, with the validation layer silent.
#[test]
fn a_window_too_large_for_the_gpu_memory_is_drawn_with_one_sample() {
    let (scene, shot) = scene_and_screenshot("fewer-samples");
    let (stdout, _) = view(&[
        "--gpu-memory",
        "160",
        "--scene",
        scene.to_str().unwrap(),
        "--width",
        "320",
        "--height",
        "240",
        "--frames",
        "10",
        "--resize-at",
        "3:2400x1800",
        "--screenshot",
        shot.to_str().unwrap(),
    ]);
    assert!(
        stdout.contains("drew 10 frames") && stdout.contains("at 1× MSAA"),
        "{stdout}"
    );
    let image = image::open(&shot).expect("screenshot written").to_rgba8();
    assert_eq!(image.dimensions(), (2400, 1800), "the window's new size");
    assert!(grass_at_the_bottom_right(&image), "no grass after the resize");
}

/// Picking another quality preset in a running viewer rebuilds its targets with the preset's
/// samples and keeps drawing grass: `low` is one sample per pixel, validation stays silent.
#[test]
fn the_viewer_switches_quality_presets_while_running() {
    let (scene, shot) = scene_and_screenshot("quality");
    let (stdout, _) = view(&[
        "--scene",
        scene.to_str().unwrap(),
        "--width",
        "480",
        "--height",
        "320",
        "--frames",
        "20",
        "--quality-at",
        "8:low",
        "--screenshot",
        shot.to_str().unwrap(),
    ]);
    assert!(
        stdout.contains("drew 20 frames") && stdout.contains("at 1× MSAA"),
        "{stdout}"
    );
    let image = image::open(&shot).expect("screenshot written").to_rgba8();
    assert!(grass_at_the_bottom_right(&image), "no grass after the switch");
}

/// Every shipped scene runs in the viewer, two frames in flight, with the validation layer's
/// synchronization validation and not one message: 12 frames each here (every frame slot
/// reused six times over). 600 frames of each scene ran once with the same command at 160×120
/// (docs/benchmarks-history.md, "Reliability"): under synchronization validation a frame takes from 0.06 s
/// (meadow) to 1.1 s (landscape) on lavapipe, so 600 × 6 would add 17 minutes to every run.
#[test]
fn every_shipped_scene_runs_in_the_viewer_without_a_hazard() {
    for name in ["meadow", "planet", "hills", "trample", "landscape", "prairie"] {
        // Fewer blades keep the frames quick on a CPU Vulkan driver.
        let args = ["--scene", name, "--width", "320", "--height", "240", "--frames", "12"];
        let (stdout, _) = view(&[&args[..], &["--set", "field.blades=3000"]].concat());
        assert!(stdout.contains("drew 12 frames"), "{name}");
    }
}

/// On foot (`--walk`) through the trail scene with the trample map shown in the panel: grass in
/// the view and not one validation message (the map is read back for the panel's picture while
/// frames are in flight). Where the walker goes and how it treads the grass: the unit tests of
/// `sward_core::walk` and the viewer's camera control.
#[test]
fn walking_through_the_trail_with_the_map_shown_runs_without_a_hazard() {
    let shot = scratch("walk.png");
    let _ = std::fs::remove_file(&shot);
    // Wide enough for the panel: the trail scene's collider rows (paths, speeds) widen it.
    let args = [
        "--scene", "trail", "--width", "960", "--height", "400", "--frames", "24",
    ];
    let (stdout, _) = view(
        &[
            &args[..],
            &[
                "--walk",
                "--show-trample-map",
                // The trail streams: a small window (2 × 2 tiles of a sparser grid) keeps
                // lavapipe quick, and the walk still crosses streamed tiles.
                "--set",
                "field.blades=16384",
                "--set",
                "instanced.density=20",
                "--set",
                "instanced.inner_radius=5",
                "--screenshot",
            ],
            &[shot.to_str().unwrap()],
        ]
        .concat(),
    );
    assert!(stdout.contains("drew 24 frames"), "{stdout}");
    let image = image::open(&shot).unwrap().to_rgba8();
    assert!(grass_at_the_bottom_right(&image));
}

/// Added to the test scene for the stress test: small generated grass too, so a storm's frames
/// in the instanced and landscape techniques stay quick on a CPU Vulkan driver (the storm is
/// about its acts, not about how much grass each frame draws).
const SMALL_GENERATED_GRASS: &str = r#"
[instanced]
density = 4.0
radius = 12.0
lod_distances = [3.0, 6.0, 9.0]
splat_distance = 10.0
[billboard]
density = 0.5
radius = 20.0
"#;

/// A restless user (`--stress`): 400 frames, two storms act for act alike, with over 60
/// resizes and minimises in all — to nothing, to one pixel, 16384 pixels wide and tall — and
/// panel edits of blade count, technique, draw route (mesh included, which lavapipe lacks) and
/// quality preset (so the MSAA), under the validation layer: not one message, no panic, and
/// after the second storm, back at the start's scene and size, the same GPU memory in use as
/// after the first (sward's bytes and the allocator's allocations).
#[test]
fn the_viewer_survives_a_storm_of_resizes_and_edits_without_leaking() {
    let scene = scratch("stress.toml");
    std::fs::write(&scene, format!("{SCENE}{SMALL_GENERATED_GRASS}")).unwrap();
    let args = [
        "--width",
        "120",
        "--height",
        "90",
        "--frames",
        "400",
        "--stress",
        "1",
        "--set",
        "field.blades=1500",
    ];
    let (stdout, _) = view(&[&["--scene", scene.to_str().unwrap()][..], &args].concat());
    assert!(stdout.contains("drew 400 frames"), "{stdout}");
    let line = stdout
        .lines()
        .find(|l| l.starts_with("stress:"))
        .expect("a stress report");
    let resizes: u32 = line["stress: ".len()..].split(' ').next().unwrap().parse().unwrap();
    assert!(resizes >= 60, "{line}");
    let (_, after) = line.split_once("after each storm: ").unwrap();
    let (first, second) = after.split_once(", then ").expect("two storms measured");
    assert_eq!(first, second, "GPU memory grew from one storm to the next: {line}");
}

/// The row of the 640×400 view where the ground at (0, 0, `z`) of the test scene is.
fn row_of_ground(z: f32) -> u32 {
    let scene = sward_core::Scene::from_toml(SCENE, "viewer-test").unwrap();
    let clip = scene.camera.view_projection(640.0 / 400.0) * glam::Vec4::new(0.0, 0.0, z, 1.0);
    ((clip.y / clip.w * 0.5 + 0.5) * 400.0).round() as u32
}

/// The paint brush, dragged across the field (as `--brush-at` drags it, dab by dab through the
/// viewer's own painting), leaves a bare path the very next frames show: the fixed field grown
/// again without the blades under it, the ground showing through (red here), while the grass
/// beyond it stands.
#[test]
fn the_brush_paints_a_bare_path_the_viewer_shows_at_once() {
    let (scene, shot) = scene_and_screenshot("brush");
    view(&[
        "--scene",
        scene.to_str().unwrap(),
        "--set",
        "shading.ground_color=[1.0, 0.0, 0.0]",
        "--width",
        "640",
        "--height",
        "400",
        "--frames",
        "30",
        "--brush-at",
        "5:-8,-3,8,-3",
        "--screenshot",
        shot.to_str().unwrap(),
    ]);
    let image = image::open(&shot).expect("screenshot written").to_rgba8();
    let red_share = |y: u32| {
        let red = (640 * 2 / 3..640).filter(|&x| {
            let [r, g, b, _] = image.get_pixel(x, y).0;
            r > 80 && r as u32 > 2 * g as u32 && r as u32 > 2 * b as u32
        });
        red.count() as f32 / (640.0 / 3.0)
    };
    let (path, meadow) = (red_share(row_of_ground(-3.0)), red_share(row_of_ground(2.0)));
    assert!(
        path > 0.8,
        "the brushed path shows the ground on {:.0} % of its row",
        path * 100.0
    );
    assert!(
        meadow < 0.3,
        "beyond the path the ground shows on {:.0} % of the row",
        meadow * 100.0
    );
}
