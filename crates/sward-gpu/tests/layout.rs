//! The GPU-shared structs agree between Rust (`sward_core::gpu`) and GLSL (`shaders/common.glsl`):
//! member offsets read from the compiled SPIR-V against `offset_of!` in Rust.

use std::collections::HashMap;
use std::mem::offset_of;

use sward_core::gpu::{DrawCommand, FrameUniforms};
use sward_core::Blade;
use sward_gpu::shaders;

const OP_NAME: u32 = 5;
const OP_MEMBER_DECORATE: u32 = 72;
const DECORATION_OFFSET: u32 = 35;

/// Member offsets of every named struct in a SPIR-V module.
fn struct_offsets(spirv: &[u8]) -> HashMap<String, Vec<u32>> {
    let words: Vec<u32> = spirv
        .as_chunks::<4>()
        .0
        .iter()
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    let mut names = HashMap::new();
    let mut offsets: HashMap<u32, Vec<(u32, u32)>> = HashMap::new();
    let mut at = 5;
    while at < words.len() {
        let (count, opcode) = ((words[at] >> 16) as usize, words[at] & 0xffff);
        let operands = &words[at + 1..at + count];
        if opcode == OP_NAME {
            let bytes: Vec<u8> = operands[1..]
                .iter()
                .flat_map(|w| w.to_le_bytes())
                .take_while(|b| *b != 0)
                .collect();
            names.insert(operands[0], String::from_utf8(bytes).unwrap());
        }
        if opcode == OP_MEMBER_DECORATE && operands[2] == DECORATION_OFFSET {
            offsets.entry(operands[0]).or_default().push((operands[1], operands[3]));
        }
        at += count.max(1);
    }
    offsets
        .into_iter()
        .filter_map(|(id, mut members)| {
            members.sort();
            Some((names.get(&id)?.clone(), members.into_iter().map(|(_, o)| o).collect()))
        })
        .collect()
}

#[test]
fn frame_uniforms_match_the_glsl_block() {
    let glsl = &struct_offsets(shaders::SIMULATE_COMP)["Frame"];
    let rust = [
        offset_of!(FrameUniforms, view_proj),
        offset_of!(FrameUniforms, inv_view_proj),
        offset_of!(FrameUniforms, sun_view_proj),
        offset_of!(FrameUniforms, sun_near_view_proj),
        offset_of!(FrameUniforms, camera_position),
        offset_of!(FrameUniforms, gravity),
        offset_of!(FrameUniforms, point_gravity),
        offset_of!(FrameUniforms, simulation),
        offset_of!(FrameUniforms, counts),
        offset_of!(FrameUniforms, cull),
        offset_of!(FrameUniforms, coarse_cull),
        offset_of!(FrameUniforms, modes),
        offset_of!(FrameUniforms, lod),
        offset_of!(FrameUniforms, blade_style),
        offset_of!(FrameUniforms, viewport),
        offset_of!(FrameUniforms, light_direction),
        offset_of!(FrameUniforms, light_color),
        offset_of!(FrameUniforms, root_color),
        offset_of!(FrameUniforms, tip_color),
        offset_of!(FrameUniforms, ground_color),
        offset_of!(FrameUniforms, sky_zenith),
        offset_of!(FrameUniforms, sky_horizon),
        offset_of!(FrameUniforms, shading_model),
        offset_of!(FrameUniforms, shading_extra),
        offset_of!(FrameUniforms, ground_extent),
        offset_of!(FrameUniforms, surface),
        offset_of!(FrameUniforms, instanced_grid),
        offset_of!(FrameUniforms, instanced_shape),
        offset_of!(FrameUniforms, instanced_motion),
        offset_of!(FrameUniforms, instanced_lod),
        offset_of!(FrameUniforms, instanced_lists),
        offset_of!(FrameUniforms, instanced_caps),
        offset_of!(FrameUniforms, instanced_meta),
        offset_of!(FrameUniforms, instanced_ground),
        offset_of!(FrameUniforms, instanced_ground_cells),
        offset_of!(FrameUniforms, billboard_grid),
        offset_of!(FrameUniforms, billboard_shape),
        offset_of!(FrameUniforms, billboard_motion),
        offset_of!(FrameUniforms, billboard_meta),
        offset_of!(FrameUniforms, routes),
        offset_of!(FrameUniforms, occlusion),
        offset_of!(FrameUniforms, patch_cull),
        offset_of!(FrameUniforms, patch_bounds),
        offset_of!(FrameUniforms, tiles),
        offset_of!(FrameUniforms, trample),
        offset_of!(FrameUniforms, mowing),
        offset_of!(FrameUniforms, billboard_far),
        offset_of!(FrameUniforms, instanced_raster),
        offset_of!(FrameUniforms, stream),
        offset_of!(FrameUniforms, stream_reach),
        offset_of!(FrameUniforms, origin),
        offset_of!(FrameUniforms, paint_area),
        offset_of!(FrameUniforms, paint_size),
        offset_of!(FrameUniforms, paint_noise),
        offset_of!(FrameUniforms, paint_tint_noise),
        offset_of!(FrameUniforms, paint_tint_color),
        offset_of!(FrameUniforms, species_meta),
        offset_of!(FrameUniforms, species),
        offset_of!(FrameUniforms, seed_heads),
        offset_of!(FrameUniforms, lamp_meta),
        offset_of!(FrameUniforms, lamps),
        offset_of!(FrameUniforms, frustum),
        offset_of!(FrameUniforms, winds),
        offset_of!(FrameUniforms, colliders),
    ]
    .map(|o| o as u32);
    assert_eq!(
        glsl.as_slice(),
        rust.as_slice(),
        "Frame block (GLSL) vs FrameUniforms (Rust)"
    );
}

#[test]
fn blade_and_draw_command_match_the_glsl_structs() {
    let structs = struct_offsets(shaders::CULL_COMP);
    let blade = [
        offset_of!(Blade, v0),
        offset_of!(Blade, v1),
        offset_of!(Blade, v2),
        offset_of!(Blade, up),
    ]
    .map(|o| o as u32);
    assert_eq!(structs["Blade"], blade);
    let draw = [
        offset_of!(DrawCommand, vertex_count),
        offset_of!(DrawCommand, instance_count),
        offset_of!(DrawCommand, first_vertex),
        offset_of!(DrawCommand, first_instance),
    ]
    .map(|o| o as u32);
    assert_eq!(structs["DrawCommand"], draw);
}

/// `const uint NAME = VALUE;` and `const int NAME = VALUE;` lines of a GLSL source, as
/// (name, value).
fn glsl_constants(source: &str) -> Vec<(String, u32)> {
    source
        .lines()
        .filter_map(|line| {
            let line = line.trim();
            let rest = line
                .strip_prefix("const uint ")
                .or_else(|| line.strip_prefix("const int "))?;
            let (name, value) = rest.split_once('=')?;
            let value = value.trim().trim_end_matches(';').trim_end_matches('u');
            Some((name.trim().to_string(), value.parse().ok()?))
        })
        .collect()
}

fn common_glsl() -> String {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/shaders/common.glsl");
    std::fs::read_to_string(path).expect("shaders/common.glsl is readable")
}

/// Each of `rust`'s names has its value in `glsl`, and every GLSL name with one of
/// `prefixes` is one of `rust`'s.
fn agree(glsl: &HashMap<String, u32>, rust: &[(&str, u32)], prefixes: &[&str], what: &str) {
    for (name, value) in rust {
        assert_eq!(glsl.get(*name), Some(value), "{name}: common.glsl vs {what}");
    }
    let named_in_glsl = glsl.keys().filter(|n| prefixes.iter().any(|p| n.starts_with(p)));
    for name in named_in_glsl {
        assert!(
            rust.iter().any(|(n, _)| n == name),
            "common.glsl defines {name}, which {what} lacks"
        );
    }
}

#[test]
fn flags_and_command_slots_match_the_glsl_constants() {
    let glsl: HashMap<String, u32> = glsl_constants(&common_glsl()).into_iter().collect();
    agree(
        &glsl,
        &sward_core::flags::ALL,
        &["FORCE_", "CULL_", "DRAW_"],
        "flags.rs",
    );
    agree(&glsl, &sward_core::commands::ALL, &["COMMAND_"], "gpu.rs commands");
}

#[test]
fn codes_bindings_and_specialisation_constants_match_the_glsl_names() {
    let glsl: HashMap<String, u32> = glsl_constants(&common_glsl()).into_iter().collect();
    let codes = ["TECHNIQUE_", "WIND_", "BLADE_", "SHADING_", "GROUND_", "VIEW_"];
    agree(&glsl, &sward_core::flags::CODES, &codes, "flags.rs codes");
    agree(
        &glsl,
        &sward_gpu::pipelines::bindings::ALL,
        &["BINDING_"],
        "pipelines.rs bindings",
    );
    agree(
        &glsl,
        &sward_gpu::pipelines::constants::ALL,
        &["CONSTANT_"],
        "pipelines.rs constants",
    );
}

/// No shader of the frame's set names a binding or a specialisation constant by its number:
/// every one by its name from common.glsl. (The depth pyramid's reduction and the bandwidth
/// probe have sets of their own.)
#[test]
fn shaders_name_every_binding_and_constant() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/shaders");
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if ["hiz_reduce.comp", "bandwidth.comp"].contains(&name.as_str()) {
            continue;
        }
        let source = std::fs::read_to_string(&path).unwrap();
        for (k, line) in source.lines().enumerate() {
            for key in ["binding = ", "constant_id = ", "local_size_x_id = "] {
                if let Some(at) = line.find(key) {
                    let after = &line[at + key.len()..];
                    assert!(
                        !after.starts_with(|c: char| c.is_ascii_digit()),
                        "{name}:{}: a number where a name belongs: {line}",
                        k + 1
                    );
                }
            }
        }
    }
}

/// One name per concept: the shaders and the renderer say "billboard", never "tuft".
#[test]
fn billboards_have_one_name() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    for dir in [
        "crates/sward-gpu/shaders",
        "crates/sward-portable/shaders",
        "crates/sward-gpu/src",
        "crates/sward-gpu/src/passes",
        "crates/sward-core/src",
    ] {
        for entry in std::fs::read_dir(format!("{root}/{dir}")).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                continue;
            }
            let name = path.file_name().unwrap().to_string_lossy().to_lowercase();
            let text = std::fs::read_to_string(&path).unwrap().to_lowercase();
            assert!(
                !name.contains("tuft") && !text.contains("tuft"),
                "{dir}/{name} says tuft"
            );
        }
    }
}
