//! Any bytes as a binary glTF mesh file: a mesh with finite points, or one sentence naming the file.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| sward_fuzz::check_mesh_file(data, "glb"));
