//! Any bytes as a scene file: a scene whose numbers reach the GPU finite, or one sentence
//! naming the file.
#![no_main]

use libfuzzer_sys::fuzz_target;
use sward_core::Scene;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    match Scene::from_toml(&text, "fuzzed.toml") {
        Ok(scene) => sward_fuzz::check_scene(&scene),
        Err(e) => sward_fuzz::check_sentence(&e.to_string(), "fuzzed.toml"),
    }
});
