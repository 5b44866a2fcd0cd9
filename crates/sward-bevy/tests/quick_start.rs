//! The README's Bevy quick start where a game is: pasted unchanged as the `main.rs` of a new
//! project outside this workspace, whose only dependency beside Bevy (its default features, as
//! `cargo new` and `cargo add bevy` give) is sward-bevy, with no file of this repository to read;
//! and Bevy's own `3d_scene` example (from the Bevy crate cargo fetched) with the quick start's
//! plugin and grass added, a second program of that project. Built in a folder of the
//! workspace's target folder, from the workspace's lock file, and run under Xvfb on Bevy's own
//! device (lavapipe here) with Bevy's own CI testing, which takes a screenshot of the window at
//! a frame and exits: each picture must show grass.

// A native test: it writes and reads its folders on disk.
#![allow(clippy::disallowed_methods)]

use std::path::{Path, PathBuf};
use std::process::Command;

/// The frame whose screenshot is checked: Bevy compiles its pipelines in the background, so
/// the grass appears some frames after the first — on lavapipe with two cores between the 16th
/// and the 24th (screenshots every four frames, three runs), so a shot at the 20th was blank
/// about half the time; the 60th leaves room (each frame with grass about 0.4 s there).
const SHOT_FRAME: u32 = 60;

/// The README's Bevy example: the lines after its Cargo.toml comment, to the block's end.
fn readme_quick_start() -> String {
    let readme = std::fs::read_to_string(workspace().join("README.md")).expect("README.md is readable");
    let code: Vec<&str> = readme
        .lines()
        .skip_while(|l| !l.starts_with("// Cargo.toml: sward-bevy"))
        .skip(1)
        .take_while(|l| *l != "```")
        .collect();
    assert!(code.len() > 10, "README.md has no Bevy quick start: {code:?}");
    code.join("\n") + "\n"
}

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .canonicalize()
        .unwrap()
}

/// The workspace's target folder: this test's executable is in `<target>/<profile>/deps/`.
fn target_folder() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    exe.ancestors()
        .nth(3)
        .expect("the test runs from a target folder")
        .to_path_buf()
}

/// A new game's project: Bevy with its default features and Bevy's CI testing (screenshots
/// and exit at given frames), sward-bevy by path, and the README's code as its `main.rs`.
fn new_project(dir: &Path) {
    std::fs::create_dir_all(dir.join("src")).unwrap();
    let sward_bevy = workspace().join("crates/sward-bevy");
    let manifest = format!(
        r#"[package]
name = "quick-start"
version = "0.1.0"
edition = "2024"
publish = false

[dependencies]
bevy = {{ version = "0.20", features = ["bevy_ci_testing"] }}
sward-bevy = {{ path = {path:?} }}

# Its own workspace, not sward's.
[workspace]

# Dependencies without debug information: a smaller target folder, a shorter link.
[profile.dev.package."*"]
debug = false
"#,
        path = sward_bevy.display().to_string()
    );
    std::fs::write(dir.join("Cargo.toml"), manifest).unwrap();
    // The versions sward is tested with; what Bevy's default features add is resolved anew.
    std::fs::copy(workspace().join("Cargo.lock"), dir.join("Cargo.lock")).unwrap();
    std::fs::write(dir.join("src/main.rs"), readme_quick_start()).unwrap();
    std::fs::create_dir_all(dir.join("src/bin")).unwrap();
    std::fs::write(dir.join("src/bin/three_d_scene.rs"), three_d_scene_with_grass()).unwrap();
}

/// Bevy's `examples/3d/3d_scene.rs` as the Bevy crate in cargo's registry holds it.
fn bevy_s_3d_scene() -> String {
    let home = std::env::var_os("CARGO_HOME")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(std::env::var_os("HOME").expect("HOME is set")).join(".cargo"));
    let registries = std::fs::read_dir(home.join("registry/src")).expect("cargo's registry holds sources");
    let example = registries
        .flatten()
        .map(|r| r.path().join("bevy-0.20.1/examples/3d/3d_scene.rs"))
        .find(|p| p.is_file())
        .expect("cargo's registry holds bevy 0.20.1's sources (a build of sward-bevy fetches them)");
    std::fs::read_to_string(example).unwrap()
}

/// Bevy's 3D scene with the quick start's lines added: sward's plugin beside Bevy's, and the
/// default meadow grown around the cube.
fn three_d_scene_with_grass() -> String {
    let mut code = bevy_s_3d_scene();
    let edits = [
        (
            "use bevy::prelude::*;\n",
            "use bevy::prelude::*;\nuse sward_bevy::prelude::Scene;\nuse sward_bevy::{Grass, SwardPlugin};\n",
        ),
        (
            ".add_plugins(DefaultPlugins)",
            ".add_plugins((DefaultPlugins, SwardPlugin::default()))",
        ),
        (
            ".add_systems(Startup, scene.spawn())",
            ".add_systems(Startup, scene.spawn())\n        .add_systems(Startup, |mut commands: Commands| {\n            commands.spawn(Grass::new(Scene::default()).expect(\"the meadow\"));\n        })",
        ),
    ];
    for (from, to) in edits {
        assert!(code.contains(from), "Bevy's 3d_scene example no longer has `{from}`");
        code = code.replacen(from, to, 1);
    }
    code
}

/// Build the project's programs (the cargo that runs this test, without the workspace's lint
/// wrapper): the folder they are in.
fn build(dir: &Path, target: &Path) -> PathBuf {
    let status = Command::new(env!("CARGO"))
        .args(["build", "--quiet", "--manifest-path"])
        .arg(dir.join("Cargo.toml"))
        .env("CARGO_TARGET_DIR", target)
        .env_remove("RUSTC_WORKSPACE_WRAPPER")
        .env_remove("CLIPPY_ARGS")
        .status()
        .expect("cargo runs");
    assert!(status.success(), "the quick start does not build in a new project");
    target.join("debug")
}

/// The game run under Xvfb from `dir` (nothing of this repository there), Bevy's CI testing
/// taking the window's screenshot at [`SHOT_FRAME`] and exiting: that picture, and its path.
fn run_headless(game: &Path, dir: &Path) -> (image::RgbaImage, PathBuf) {
    let config = dir.join("ci_testing_config.ron");
    let events = format!("(setup: (fixed_frame_time: Some(0.03)), events: [({SHOT_FRAME}, ScreenshotAndExit)])");
    std::fs::write(&config, events).unwrap();
    let shot = dir.join(format!("screenshot-{SHOT_FRAME}.png"));
    let _ = std::fs::remove_file(&shot);
    let output = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1280x800x24"])
        .arg(game)
        .current_dir(dir)
        .env("CI_TESTING_CONFIG", &config)
        .env("RUST_LOG", "warn")
        .output()
        .unwrap_or_else(|e| panic!("this test runs the game under Xvfb and could not start xvfb-run: {e}; install it with apt-get install xvfb xauth"));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "the quick start failed: {stderr}");
    assert!(!stderr.contains("sward draws no grass"), "sward said: {stderr}");
    let picture = image::open(&shot)
        .unwrap_or_else(|e| panic!("no screenshot at {} ({e}): {stderr}", shot.display()))
        .to_rgba8();
    // Kept beside the game, named for it, to look at after a failure.
    let kept = dir.join(format!("{}.png", game.file_name().unwrap().to_string_lossy()));
    std::fs::rename(&shot, &kept).unwrap();
    (picture, kept)
}

/// The share of the picture that is grass green (Bevy's default clear colour is grey, and the
/// quick start has no ground): the meadow seen whole from beside it covers about a quarter.
fn grass_share(image: &image::RgbaImage) -> f32 {
    let green = image
        .pixels()
        .filter(|p| {
            let [r, g, b, _] = p.0;
            g > 30 && g as u32 * 10 > r as u32 * 11 && g as u32 * 10 > b as u32 * 11
        })
        .count();
    green as f32 / (image.width() * image.height()) as f32
}

#[test]
fn the_readme_s_quick_start_draws_grass_in_a_new_project_and_in_bevy_s_3d_scene() {
    let target = target_folder().join("quick-start");
    let dir = target.join("project");
    let _ = std::fs::remove_dir_all(&dir);
    new_project(&dir);
    let programs = build(&dir, &target);
    for game in ["quick-start", "three_d_scene"] {
        let (picture, path) = run_headless(&programs.join(game), &dir);
        let share = grass_share(&picture);
        assert!(
            share > 0.1,
            "{game}'s picture ({}) is {:.0} % grass",
            path.display(),
            share * 100.0
        );
    }
}
