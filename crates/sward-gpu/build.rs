//! Compiles every GLSL stage in `shaders/` to SPIR-V with glslang, into `OUT_DIR`. A shader error
//! fails the build with glslang's own message (file, line, what is wrong).

use std::path::{Path, PathBuf};

#[allow(dead_code)]
#[path = "src/glsl.rs"]
mod glsl;

fn main() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let dir = dir.canonicalize().unwrap_or(dir);
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    println!("cargo:rerun-if-changed={}", dir.display());
    let mut entries: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("shaders/ exists")
        .flatten()
        .map(|e| e.path())
        .collect();
    entries.sort();
    let mut failures = Vec::new();
    for path in entries {
        println!("cargo:rerun-if-changed={}", path.display());
        if glsl::stage_of(&path).is_none() {
            continue;
        }
        match glsl::compile_file(&dir, &path) {
            Ok(words) => {
                let name = path.file_name().unwrap().to_string_lossy().replace('.', "_") + ".spv";
                let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
                std::fs::write(out.join(name), bytes).expect("OUT_DIR is writable");
            }
            Err(message) => failures.push(message),
        }
    }
    if !failures.is_empty() {
        eprintln!("shader compilation failed:\n{}", failures.join("\n"));
        std::process::exit(1);
    }
}
