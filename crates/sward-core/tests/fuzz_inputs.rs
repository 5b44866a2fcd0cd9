//! Damaged inputs, replayed: thousands of mutations of the shipped scenes (as files and as
//! `--set` values), of OBJ and glTF (GLB) meshes and of PNG height maps go through the same
//! loaders a user's files go through. Every one must end in success or in one sentence that names
//! the input — never a panic, a hang (each input has a time bound), or a value that could put a
//! NaN on the GPU (a loaded scene's numbers are finite and of sane size; a loaded mesh's points
//! are finite). The mutations are seeded, so a failure names an input that replays.
//!
//! Found by this replay and fixed: a field size with no room for its blades (`field.size =
//! [24.0, 1e-30]`) panicked growing the field (loaded scenes on a plane or a sphere are grown
//! here, at most `SAMPLE_BLADES` of their blades); a scene number of absurd size
//! (`camera.position = [1e30, …]`) was accepted; a mesh whose triangles were bad said so without naming the file; damaged OBJ
//! and glTF files made their readers panic, and a binary glTF header could ask for 4 GiB.

// A native test: it reads its inputs from disk and runs each under a time bound on a thread.
#![allow(clippy::disallowed_methods)]

mod fuzz;

use std::time::{Duration, Instant};

use sward_core::gpu::FrameUniforms;
use sward_core::mesh::Mesh;
use sward_core::Scene;

use fuzz::{Mutator, Worker};

/// Mutated inputs per format.
const INPUTS: usize = 10_000;
/// The most one input may take to load.
const BOUND: Duration = Duration::from_secs(2);

const SCENES: [(&str, &str); 7] = [
    ("meadow", include_str!("../../../scenes/meadow.toml")),
    ("trample", include_str!("../../../scenes/trample.toml")),
    ("hills", include_str!("../../../scenes/hills.toml")),
    ("planet", include_str!("../../../scenes/planet.toml")),
    ("landscape", include_str!("../../../scenes/landscape.toml")),
    ("prairie", include_str!("../../../scenes/prairie.toml")),
    ("park", include_str!("../../../scenes/park.toml")),
];

/// A loaded scene's numbers, as the GPU would get them, are finite.
fn assert_sane_scene(scene: &Scene, input: &str) {
    let uniforms = FrameUniforms::as_loaded(scene);
    if let Some(at) = uniforms.first_non_finite() {
        panic!(
            "a NaN or infinity (uniform float {at}) reaches the GPU; camera {:?}, from:\n{input}",
            scene.camera
        );
    }
}

/// An error is one sentence: one line, naming where the input came from.
fn assert_one_sentence(message: &str, origin: &str, input: &dyn std::fmt::Debug) {
    assert!(
        !message.is_empty() && !message.contains('\n') && message.contains(origin),
        "not one sentence naming {origin}: {message:?}\ninput: {input:?}"
    );
}

/// The most blades a loaded scene's field is grown with here: enough that a field size too
/// thin for its blades shows (the meadow's 60000 on 24 × 1e-30 units panicked), few enough that
/// thousands of inputs grow in seconds.
const SAMPLE_BLADES: u32 = 1 << 16;

/// Grow a loaded scene's field, as `sward render` does, where it needs no file (a plane or a
/// sphere, not streamed): a scene that validation let through must grow without a panic. Its
/// blades are capped at `SAMPLE_BLADES`; a paint map's file that cannot be read is an error,
/// which must be one sentence naming it.
fn grow_a_sample(scene: &Scene) {
    use sward_core::field::Surface;
    if !matches!(scene.surface, Surface::Plane | Surface::Sphere { .. }) || scene.stream_window().is_some() {
        return;
    }
    let mut sample = scene.clone();
    sample.field.blades = sample.field.blades.min(SAMPLE_BLADES);
    if let Err(e) = sample.grow_field() {
        let message = e.to_string();
        assert!(
            !message.is_empty() && !message.contains('\n'),
            "not one sentence: {message:?}"
        );
    }
}

#[test]
fn damaged_scene_files_end_in_a_scene_or_one_sentence() {
    let seeds: Vec<&str> = SCENES.iter().map(|(_, text)| *text).collect();
    let mut mutator = Mutator::new(0x5ce7e);
    let mut worker = Worker::new(BOUND);
    let (mut loaded, mut refused) = (0, 0);
    for k in 0..INPUTS {
        let text = mutator.text(&seeds);
        let input = text.clone();
        let outcome = worker.run(&format!("scene input {k}"), move || {
            let scene = Scene::from_toml(&text, "fuzzed.toml").map_err(|e| e.to_string())?;
            grow_a_sample(&scene);
            Ok::<Scene, String>(scene)
        });
        match outcome {
            Ok(scene) => {
                assert_sane_scene(&scene, &input);
                loaded += 1;
            }
            Err(message) => {
                assert_one_sentence(&message, "fuzzed.toml", &input);
                refused += 1;
            }
        }
    }
    eprintln!("scene files: {loaded} loaded, {refused} refused in one sentence");
    assert!(loaded > 100 && refused > 1000, "{loaded} loaded, {refused} refused");
}

#[test]
fn damaged_set_values_end_in_a_scene_or_one_sentence() {
    // The trampling scene with four of its colliders: every kind of key, a quick scene to copy.
    let mut base = Scene::from_toml(SCENES[1].1, "trample").unwrap();
    base.colliders.truncate(4);
    let keys = fuzz::scene_keys(&base);
    let mut mutator = Mutator::new(0x5e7);
    let mut worker = Worker::new(BOUND);
    let (mut loaded, mut refused) = (0, 0);
    for k in 0..INPUTS {
        let sets = mutator.sets(&keys);
        let (scene, input) = (base.clone(), sets.clone());
        match worker.run(&format!("--set input {k}"), move || {
            let scene = scene.with_overrides(&sets).map_err(|e| e.to_string())?;
            grow_a_sample(&scene);
            Ok::<Scene, String>(scene)
        }) {
            Ok(scene) => {
                assert_sane_scene(&scene, &format!("{input:?}"));
                loaded += 1;
            }
            Err(message) => {
                assert_one_sentence(&message, "--set", &input);
                refused += 1;
            }
        }
    }
    eprintln!("--set values: {loaded} loaded, {refused} refused in one sentence");
    assert!(loaded > 100 && refused > 1000, "{loaded} loaded, {refused} refused");
}

/// Mutations of mesh files of one kind (`extension`), from `seeds`, loaded as a user's mesh.
fn replay_mesh_files(extension: &str, seeds: &[Vec<u8>], seed: u64, text: bool) {
    let dir = std::env::temp_dir().join(format!("sward-fuzz-{extension}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut mutator = Mutator::new(seed);
    let mut worker = Worker::new(BOUND);
    let (mut loaded, mut refused) = (0, 0);
    let started = Instant::now();
    for k in 0..INPUTS {
        let bytes = if text {
            let seeds: Vec<String> = seeds.iter().map(|s| String::from_utf8_lossy(s).into_owned()).collect();
            let seeds: Vec<&str> = seeds.iter().map(String::as_str).collect();
            mutator.text(&seeds).into_bytes()
        } else {
            mutator.bytes(seeds)
        };
        let path = dir.join(format!("input-{}.{extension}", k % 8));
        std::fs::write(&path, &bytes).unwrap();
        let origin = path.display().to_string();
        let load = path.clone();
        let height_map = extension == "png";
        let outcome = worker.run(&format!("{extension} input {k}"), move || {
            let mesh = if height_map {
                Mesh::heightmap(&load, glam::Vec2::splat(50.0), 4.0)
            } else {
                Mesh::load(&load, 1.0)
            };
            mesh.map(|m| m.positions.iter().all(|p| p.is_finite()))
                .map_err(|e| e.to_string())
        });
        match outcome {
            Ok(finite) => {
                assert!(
                    finite,
                    "a loaded {extension} mesh has a point that is not finite: {bytes:?}"
                );
                loaded += 1;
            }
            Err(message) => {
                assert_one_sentence(&message, &origin, &String::from_utf8_lossy(&bytes));
                refused += 1;
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    eprintln!(
        "{extension} files: {loaded} loaded, {refused} refused in one sentence, in {:.1} s",
        started.elapsed().as_secs_f32()
    );
    assert!(loaded > 10 && refused > 100, "{loaded} loaded, {refused} refused");
}

#[test]
fn damaged_obj_files_end_in_a_mesh_or_one_sentence() {
    replay_mesh_files("obj", &fuzz::obj_seeds(), 0x0b1, true);
}

#[test]
fn damaged_glb_files_end_in_a_mesh_or_one_sentence() {
    replay_mesh_files("glb", &[fuzz::glb_seed()], 0x61b, false);
}

#[test]
fn damaged_height_maps_end_in_a_mesh_or_one_sentence() {
    replay_mesh_files("png", &fuzz::png_seeds(), 0x9a9, false);
}

/// What the replay found, kept as regression cases: each once passed as a scene (and put a NaN
/// or infinity on the GPU, or panicked) or failed without naming the file; each must now be
/// refused in one sentence naming the input and the key.
#[test]
fn inputs_the_replay_found_are_refused_in_one_sentence() {
    for (text, key) in fuzz::FOUND_SCENES {
        let message = Scene::from_toml(text, "found.toml")
            .map(|_| ())
            .unwrap_err()
            .to_string();
        assert_one_sentence(&message, "found.toml", &text);
        assert!(message.contains(key), "{key} not named: {message}");
    }
    let dir = std::env::temp_dir().join(format!("sward-found-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let files = fuzz::found_mesh_files();
    for (name, bytes) in files {
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        let message = Mesh::load(&path, 1.0).map(|_| ()).unwrap_err().to_string();
        assert_one_sentence(&message, &path.display().to_string(), &name);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The cargo-fuzz targets' corpus (`fuzz/corpus/TARGET/`, see fuzz/README.md) starts from this
/// replay's seeds and keeps what it found, so both fuzzers start from the same inputs and a
/// finding stays a regression case in both. `SWARD_WRITE_CORPUS=1 cargo test -p sward-core
/// --test fuzz_inputs corpus` writes it; the test fails when it has drifted from the seeds.
#[test]
fn the_fuzz_corpus_holds_the_replays_seeds_and_findings() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/corpus");
    let mut files: Vec<(String, Vec<u8>)> = Vec::new();
    for (name, text) in SCENES {
        files.push((format!("scene_file/{name}.toml"), text.into()));
    }
    for (k, (text, _)) in fuzz::FOUND_SCENES.iter().enumerate() {
        files.push((format!("scene_file/found-{k}.toml"), text.as_bytes().into()));
    }
    let mut base = Scene::from_toml(SCENES[1].1, "trample").unwrap();
    base.colliders.truncate(4);
    let keys = fuzz::scene_keys(&base);
    for k in 0..4 {
        let sets = Mutator::new(k).sets(&keys);
        let lines: Vec<String> = sets.iter().map(|(key, value)| format!("{key}={value}\n")).collect();
        files.push((format!("set_values/seed-{k}.txt"), lines.concat().into_bytes()));
    }
    for (k, obj) in fuzz::obj_seeds().into_iter().enumerate() {
        files.push((format!("obj_mesh/seed-{k}.obj"), obj));
    }
    files.push(("glb_mesh/seed-0.glb".into(), fuzz::glb_seed()));
    for (k, png) in fuzz::png_seeds().into_iter().enumerate() {
        files.push((format!("height_map/seed-{k}.png"), png));
    }
    for (name, bytes) in fuzz::found_mesh_files() {
        let target = if name.ends_with(".obj") { "obj_mesh" } else { "glb_mesh" };
        files.push((format!("{target}/found-{name}"), bytes));
    }
    let write = std::env::var_os("SWARD_WRITE_CORPUS").is_some();
    for (name, bytes) in files {
        let path = root.join(&name);
        if write {
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(&path, &bytes).unwrap();
        }
        let kept = std::fs::read(&path).unwrap_or_default();
        assert!(
            kept == bytes,
            "fuzz/corpus/{name} is missing or differs from the replay's input; write the corpus again with SWARD_WRITE_CORPUS=1"
        );
    }
}
