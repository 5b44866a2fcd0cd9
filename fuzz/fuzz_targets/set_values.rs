//! Any bytes as `--set KEY=VALUE` overrides of the trampling scene (one per line): a scene whose
//! numbers reach the GPU finite, or one sentence naming `--set`.
#![no_main]

use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use sward_core::Scene;

fn trample() -> &'static Scene {
    static SCENE: OnceLock<Scene> = OnceLock::new();
    SCENE.get_or_init(|| {
        Scene::from_toml(include_str!("../../scenes/trample.toml"), "trample").expect("the shipped scene loads")
    })
}

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let sets: Vec<(String, String)> = text
        .lines()
        .filter_map(|line| line.split_once('='))
        .map(|(key, value)| (key.to_string(), value.to_string()))
        .collect();
    match trample().with_overrides(&sets) {
        Ok(scene) => sward_fuzz::check_scene(&scene),
        Err(e) => sward_fuzz::check_sentence(&e.to_string(), "--set"),
    }
});
