//! Compiles every GLSL stage in `shaders/` to SPIR-V with glslang, into `OUT_DIR`. A shader error
//! fails the build with glslang's own message (file, line, what is wrong).

use std::path::{Path, PathBuf};

use glslang::include::{IncludeHandler, IncludeResult, IncludeType};
use glslang::{
    Compiler, CompilerOptions, ShaderInput, ShaderSource, ShaderStage, SourceLanguage, SpirvVersion, Target,
    VulkanVersion,
};

fn stage_of(path: &Path) -> Option<ShaderStage> {
    Some(match path.extension()?.to_str()? {
        "vert" => ShaderStage::Vertex,
        "tesc" => ShaderStage::TesselationControl,
        "tese" => ShaderStage::TesselationEvaluation,
        "frag" => ShaderStage::Fragment,
        "comp" => ShaderStage::Compute,
        _ => return None,
    })
}

/// Resolves `#include "x.glsl"` against the shader directory.
struct Includes {
    dir: PathBuf,
}

impl IncludeHandler for Includes {
    fn include(&mut self, _ty: IncludeType, header: &str, _includer: &str, _depth: usize) -> Option<IncludeResult> {
        let path = self.dir.join(header);
        let data = std::fs::read_to_string(&path).ok()?;
        Some(IncludeResult {
            name: path.display().to_string(),
            data,
        })
    }
}

fn compile(compiler: &Compiler, dir: &Path, path: &Path, stage: ShaderStage) -> Result<Vec<u32>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
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

fn main() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shaders");
    let dir = dir.canonicalize().unwrap_or(dir);
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    println!("cargo:rerun-if-changed={}", dir.display());
    let compiler = Compiler::acquire().expect("glslang initialises once per process");
    let mut failures = Vec::new();
    let mut entries: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("shaders/ exists")
        .flatten()
        .map(|e| e.path())
        .collect();
    entries.sort();
    for path in entries {
        println!("cargo:rerun-if-changed={}", path.display());
        let Some(stage) = stage_of(&path) else {
            continue;
        };
        match compile(compiler, &dir, &path, stage) {
            Ok(words) => {
                let name = path.file_name().unwrap().to_string_lossy().replace('.', "_") + ".spv";
                std::fs::write(out.join(name), bytemuck_words(&words)).expect("OUT_DIR is writable");
            }
            Err(message) => failures.push(message),
        }
    }
    if !failures.is_empty() {
        eprintln!("shader compilation failed:\n{}", failures.join("\n"));
        std::process::exit(1);
    }
}

fn bytemuck_words(words: &[u32]) -> Vec<u8> {
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}
