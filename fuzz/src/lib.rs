//! What every fuzz target checks of a loaded input, the same rules as the replay in
//! `crates/sward-core/tests/fuzz_inputs.rs`: a loaded scene puts no NaN or infinity on the GPU,
//! a loaded mesh has finite points, and a refusal is one sentence naming the input.

use std::path::PathBuf;

use sward_core::gpu::FrameUniforms;
use sward_core::mesh::Mesh;
use sward_core::Scene;

/// Panic (a finding) if `scene`'s numbers, as the GPU would get them, are not all finite, or if
/// its field, where it needs no file, does not grow (at most 2^16 of its blades).
pub fn check_scene(scene: &Scene) {
    let uniforms = FrameUniforms::as_loaded(scene);
    if let Some(at) = uniforms.first_non_finite() {
        panic!("a NaN or infinity (uniform float {at}) reaches the GPU");
    }
    use sward_core::field::Surface;
    if matches!(scene.surface, Surface::Plane | Surface::Sphere { .. }) && scene.stream_window().is_none() {
        let mut sample = scene.clone();
        sample.field.blades = sample.field.blades.min(1 << 16);
        if let Err(e) = sample.grow_field() {
            assert!(!e.to_string().contains('\n'), "not one sentence: {e}");
        }
    }
}

/// Panic (a finding) unless `message` is one sentence naming `origin`.
pub fn check_sentence(message: &str, origin: &str) {
    assert!(
        !message.is_empty() && !message.contains('\n') && message.contains(origin),
        "not one sentence naming {origin}: {message:?}"
    );
}

/// Load `data` as a mesh file with `extension` (a height map for "png"), as a user's file is
/// loaded, and check the outcome.
pub fn check_mesh_file(data: &[u8], extension: &str) {
    let path = scratch_file(extension);
    std::fs::write(&path, data).expect("the scratch file is writable");
    let loaded = if extension == "png" {
        Mesh::heightmap(&path, glam::Vec2::splat(50.0), 4.0)
    } else {
        Mesh::load(&path, 1.0)
    };
    match loaded {
        Ok(mesh) => assert!(
            mesh.positions.iter().all(|p| p.is_finite()),
            "a loaded {extension} mesh has a point that is not finite"
        ),
        Err(e) => check_sentence(&e.to_string(), &path.display().to_string()),
    }
}

/// This process's scratch file for inputs with `extension` (the loaders read files).
fn scratch_file(extension: &str) -> PathBuf {
    std::env::temp_dir().join(format!("sward-fuzz-{}.{extension}", std::process::id()))
}
