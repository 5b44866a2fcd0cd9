//! Shaders compiled at run time (the viewer's hot reload) build the same pipelines as the embedded
//! ones, and a broken shader is reported with its file and line instead of replacing anything.

mod common;

use sward_gpu::headless::HEADLESS_FORMAT;
use sward_gpu::shaders::ShaderSet;
use sward_gpu::Pipelines;

use common::{assert_validation_clean, context, copy_of_shaders};

#[test]
fn runtime_compiled_shaders_build_pipelines() {
    let ctx = context();
    let dir = copy_of_shaders("shaders-ok");
    let set = ShaderSet::compile(&dir).expect("the shipped shaders compile");
    assert!(Pipelines::with_shaders(&ctx, HEADLESS_FORMAT, Default::default(), &set).is_ok());
    assert_validation_clean(&ctx);
}

#[test]
fn a_broken_shader_names_its_file_and_line() {
    let dir = copy_of_shaders("shaders-broken");
    let path = dir.join("blade.frag");
    let text = std::fs::read_to_string(&path).unwrap();
    std::fs::write(
        &path,
        text.replace("void main() {", "void main() {\n    float broken = 1.0"),
    )
    .unwrap();
    let error = ShaderSet::compile(&dir).expect_err("a missing semicolon must not compile");
    assert!(error.contains("blade.frag") && error.contains("ERROR"), "{error}");
}
