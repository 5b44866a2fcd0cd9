//! GLSL → SPIR-V with glslang, shared by `build.rs` (which includes this file as a module) and the viewer's
//! shader hot reload, so both compile exactly alike. Keep glslang's API behind these functions.

use std::path::{Path, PathBuf};

use glslang::include::{IncludeHandler, IncludeResult, IncludeType};
use glslang::{
    Compiler, CompilerOptions, ShaderInput, ShaderSource, ShaderStage, SourceLanguage, SpirvVersion, Target,
    VulkanVersion,
};

/// The stage a shader file holds, by its extension.
pub fn stage_of(path: &Path) -> Option<ShaderStage> {
    Some(match path.extension()?.to_str()? {
        "vert" => ShaderStage::Vertex,
        "tesc" => ShaderStage::TesselationControl,
        "tese" => ShaderStage::TesselationEvaluation,
        "frag" => ShaderStage::Fragment,
        "comp" => ShaderStage::Compute,
        "mesh" => ShaderStage::Mesh,
        _ => return None,
    })
}

/// Resolves `#include "x.glsl"` against the shader directory; `declared.glsl` is what sward-core
/// writes (`declared::glsl`).
struct Includes {
    dir: PathBuf,
}

/// The header sward-core writes rather than a file.
const DECLARED: &str = "declared.glsl";

impl IncludeHandler for Includes {
    fn include(&mut self, _ty: IncludeType, header: &str, _includer: &str, _depth: usize) -> Option<IncludeResult> {
        if header == DECLARED {
            return Some(IncludeResult {
                name: DECLARED.to_string(),
                data: sward_core::declared::glsl(),
            });
        }
        let path = self.dir.join(header);
        let data = std::fs::read_to_string(&path).ok()?;
        Some(IncludeResult {
            name: path.display().to_string(),
            data,
        })
    }
}

/// Compile one stage for Vulkan 1.3 / SPIR-V 1.6. Errors carry the file name and glslang's log.
pub fn compile_file(dir: &Path, path: &Path) -> Result<Vec<u32>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    compile_text(dir, path, text)
}

/// Compile GLSL `text` of the stage `name`'s extension says (`blade.tese`: a tessellation evaluation shader) —
/// for an application's own shaders; `#include`s are resolved in sward's shader directory.
pub fn compile_source(name: &str, text: &str) -> Result<Vec<u32>, String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    compile_text(&dir, Path::new(name), text.to_string())
}

fn compile_text(dir: &Path, path: &Path, text: String) -> Result<Vec<u32>, String> {
    let stage = stage_of(path).ok_or_else(|| format!("{}: not a shader stage file", path.display()))?;
    let compiler = Compiler::acquire().ok_or("glslang could not be initialised")?;
    let source = ShaderSource::from(text);
    let options = CompilerOptions {
        source_language: SourceLanguage::GLSL,
        target: Target::Vulkan {
            version: VulkanVersion::Vulkan1_3,
            spirv_version: SpirvVersion::SPIRV1_6,
        },
        ..CompilerOptions::default()
    };
    let mut includes = Includes { dir: dir.to_path_buf() };
    let input = ShaderInput::new(
        &source,
        stage,
        &options,
        None::<&[(&str, Option<&str>)]>,
        Some(&mut includes),
    )
    .map_err(|e| format!("{}: {e}", path.display()))?;
    let shader = compiler
        .create_shader(input)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    shader.compile().map_err(|e| format!("{}: {e}", path.display()))
}
