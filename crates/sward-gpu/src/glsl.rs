//! GLSL → SPIR-V with glslang: the tessellation and mesh stages (built in, or from a shader
//! directory for the viewer's hot reload and `--shaders`), whose functions are the core's WGSL
//! written as GLSL (`tessellation.glsl`), and an application's own stages. Keep glslang's API
//! behind these functions.

use std::path::{Path, PathBuf};

use glslang::include::{IncludeHandler, IncludeResult, IncludeType};
use glslang::{
    Compiler, CompilerOptions, ShaderInput, ShaderSource, ShaderStage, SourceLanguage, SpirvVersion, Target,
    VulkanVersion,
};

/// The stage a shader file holds, by its extension.
fn stage_of(path: &Path) -> Option<ShaderStage> {
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

/// Resolves `#include "x.glsl"`: `declared.glsl` is what sward-core writes (`declared::glsl`),
/// `tessellation.glsl` the core's functions the stage calls, anything else a file of the shader
/// directory.
struct Includes<'a> {
    dir: PathBuf,
    core: &'a str,
}

/// The header sward-core writes rather than a file.
const DECLARED: &str = "declared.glsl";
/// The header of the core's functions, written from its WGSL (`wgsl::glsl_functions`).
pub const CORE_FUNCTIONS: &str = "tessellation.glsl";

impl IncludeHandler for Includes<'_> {
    fn include(&mut self, _ty: IncludeType, header: &str, _includer: &str, _depth: usize) -> Option<IncludeResult> {
        let written = match header {
            DECLARED => Some(sward_core::declared::glsl()),
            CORE_FUNCTIONS => Some(self.core.to_string()),
            _ => None,
        };
        if let Some(data) = written {
            return Some(IncludeResult {
                name: header.to_string(),
                data,
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

/// Compile GLSL `text` of the stage `path`'s extension says (`blade.tese`: a tessellation
/// evaluation shader) for Vulkan 1.3 / SPIR-V 1.6, its `#include`s resolved in `dir` and
/// `tessellation.glsl` being `core`. Errors carry the file name and glslang's log.
pub fn compile_stage(dir: &Path, path: &Path, text: &str, core: &str) -> Result<Vec<u32>, String> {
    let stage = stage_of(path).ok_or_else(|| format!("{}: not a shader stage file", path.display()))?;
    let compiler = Compiler::acquire().ok_or("glslang could not be initialised")?;
    let source = ShaderSource::from(text.to_string());
    let options = CompilerOptions {
        source_language: SourceLanguage::GLSL,
        target: Target::Vulkan {
            version: VulkanVersion::Vulkan1_3,
            spirv_version: SpirvVersion::SPIRV1_6,
        },
        ..CompilerOptions::default()
    };
    let mut includes = Includes {
        dir: dir.to_path_buf(),
        core,
    };
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

/// Compile GLSL `text` of the stage `name`'s extension says (`world.frag`: a fragment shader) —
/// for an application's own shaders, which may include `declared.glsl` (sward's binding
/// numbers, flags and codes).
pub fn compile_source(name: &str, text: &str) -> Result<Vec<u32>, String> {
    compile_stage(Path::new("."), Path::new(name), text, "")
}
