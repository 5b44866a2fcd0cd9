//! Shaders compiled at run time (the viewer's hot reload) build the same pipelines as the embedded
//! ones, and a broken shader is reported with its file and line instead of replacing anything.

mod common;

use sward_gpu::headless::HEADLESS_FORMAT;
use sward_gpu::shaders::{self, ShaderSet, ShaderStage};
use sward_gpu::Pipelines;

use common::{assert_validation_clean, context, copy_of_shaders};

#[test]
fn runtime_compiled_shaders_build_pipelines() {
    let ctx = context();
    let dir = copy_of_shaders("shaders-ok");
    let set = ShaderSet::compile(&dir).expect("the shipped shaders compile");
    if let Err(e) = Pipelines::with_shaders(&ctx, HEADLESS_FORMAT, Default::default(), &set) {
        panic!("the pipelines are not made: {e}");
    }
    assert_validation_clean(&ctx);
}

#[test]
fn a_broken_shader_names_its_file_and_line() {
    let dir = copy_of_shaders("shaders-broken");
    let path = dir.join("blade.tese");
    let text = std::fs::read_to_string(&path).unwrap();
    std::fs::write(
        &path,
        text.replace("void main() {", "void main() {\n    float broken = 1.0"),
    )
    .unwrap();
    let error = ShaderSet::compile(&dir).expect_err("a missing semicolon must not compile");
    assert!(error.contains("blade.tese") && error.contains("ERROR"), "{error}");
}

/// A WESL module in the shader directory replaces the core's built-in one for the Vulkan
/// renderer's WGSL passes (`--shaders DIR`: a variant measured with the same binary), and a
/// broken one is reported with its module and line.
#[test]
fn a_shader_directory_replaces_the_core_wgsl() {
    let ctx = context();
    let dir = copy_of_shaders("shaders-wesl");
    let core = concat!(env!("CARGO_MANIFEST_DIR"), "/../sward-core/shaders/trample.wesl");
    let text = std::fs::read_to_string(core).unwrap();
    let variant = text.replace("const STUBBLE: f32 = 0.02;", "const STUBBLE: f32 = 0.03;");
    assert_ne!(variant, text, "the variant changes the trample pass");
    std::fs::write(dir.join("trample.wesl"), &variant).unwrap();
    let set = ShaderSet::compile(&dir).expect("the variant compiles");
    let built_in = ShaderSet::embedded().wgsl(&shaders::TRAMPLE, &[], false).unwrap();
    assert_ne!(set.wgsl(&shaders::TRAMPLE, &[], false).unwrap(), built_in);
    if let Err(e) = Pipelines::with_shaders(&ctx, HEADLESS_FORMAT, Default::default(), &set) {
        panic!("the pipelines are not made: {e}");
    }
    assert_validation_clean(&ctx);
    std::fs::write(
        dir.join("trample.wesl"),
        text.replace("fn trample(", "fn trample(broken"),
    )
    .unwrap();
    let error = ShaderSet::compile(&dir).expect_err("a broken module must not compile");
    assert!(error.contains("trample"), "{error}");
}

/// What naga adds to the core's WGSL by default (bounds checks, loop bounds, zeroed workgroup
/// memory) is left out of the Vulkan renderer's SPIR-V: every pass's is smaller without them.
#[test]
fn the_vulkan_renderer_runs_the_wgsl_without_naga_checks() {
    let set = ShaderSet::embedded();
    for pass in shaders::wgsl_passes() {
        let unchecked = set.wgsl(&pass, &[], false).unwrap().len();
        let checked = set.wgsl(&pass, &[], true).unwrap().len();
        println!(
            "{} ({:?}): {checked} words with naga's checks, {unchecked} without",
            pass.name, pass.features
        );
        assert!(
            unchecked < checked,
            "{}: {unchecked} words unchecked, {checked} checked",
            pass.name
        );
    }
    // The draws' stages, some of which index nothing: never larger without the checks, and the
    // ground's and the splats' resolve's (which index the mesh's vertices, the cells) smaller.
    for (draw, stage) in shaders::wgsl_draw_stages() {
        let unchecked = set.wgsl_stage(&draw, stage, &[], false).unwrap().len();
        let checked = set.wgsl_stage(&draw, stage, &[], true).unwrap().len();
        println!(
            "{} {stage:?}: {checked} words with naga's checks, {unchecked} without",
            draw.name
        );
        let indexed = (draw.name == "ground" && stage == ShaderStage::Vertex) || draw.name == "splat_resolve";
        assert!(
            unchecked < checked || (!indexed && unchecked == checked),
            "{} {stage:?}: {unchecked} words unchecked, {checked} checked",
            draw.name
        );
    }
}

/// The GLSL stages are glue: no function of theirs has a body in the core's WGSL too, so the
/// core's functions are written once (the stages call them as naga writes them,
/// `tessellation.glsl`).
#[test]
fn no_glsl_function_is_written_again_in_the_core() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let mut glsl_functions = Vec::new();
    for entry in std::fs::read_dir(&dir).unwrap().flatten() {
        let text = std::fs::read_to_string(entry.path()).unwrap();
        for line in text.lines().filter(|l| !l.starts_with(' ') && l.ends_with(") {")) {
            let name = line.split('(').next().unwrap().split_whitespace().last().unwrap();
            glsl_functions.push((entry.file_name().to_string_lossy().to_string(), name.to_string()));
        }
    }
    assert!(glsl_functions.iter().any(|(_, f)| f == "main"), "no stage was read");
    for (file, function) in glsl_functions.iter().filter(|(_, f)| f != "main") {
        for (module, text) in sward_core::wgsl::MODULES {
            assert!(
                !text.contains(&format!("fn {function}(")),
                "{file}'s {function} is written again in {module}.wesl"
            );
        }
    }
}
