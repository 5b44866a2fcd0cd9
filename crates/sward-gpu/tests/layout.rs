//! The GPU-shared structs agree between Rust (`sward_core::gpu`) and the shaders (the core's WGSL
//! as naga writes it, and as GLSL the tessellation stages compile): member offsets read from the
//! compiled SPIR-V against `offset_of!` in Rust.

use std::collections::HashMap;
use std::mem::offset_of;

use sward_core::declared::{self, Block, BLOCKS};
use sward_core::gpu::DrawCommand;
use sward_core::Blade;
use sward_gpu::shaders::{self, ShaderSet};

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

/// The struct of the module `structs` whose name (less WESL's module path) is `name`.
fn named<'a>(structs: &'a HashMap<String, Vec<u32>>, name: &str) -> &'a [u32] {
    let found = structs
        .iter()
        .find(|(n, _)| *n == name || n.ends_with(&format!("_{name}")));
    found
        .map(|(_, offsets)| offsets.as_slice())
        .unwrap_or_else(|| panic!("no {name} in {:?}", structs.keys()))
}

/// Where each member of `block` lies in the block as Rust declares it: its members back to
/// back (`declared::BLOCKS`, whose members the compiler holds to `FrameUniforms`).
fn declared_offsets(block: &Block) -> Vec<u32> {
    let sizes = block.members.iter().map(|(_, ty, _)| ty.size() as u32);
    sizes
        .scan(0, |at, size| Some(std::mem::replace(at, *at + size)))
        .collect()
}

/// Each of the frame's blocks that `structs` holds is laid out as declared; returns their names.
fn frame_blocks_match(structs: &HashMap<String, Vec<u32>>, what: &str) -> Vec<&'static str> {
    let mut found = Vec::new();
    for block in &BLOCKS {
        let suffix = format!("_{}", block.ty);
        let Some((_, offsets)) = structs.iter().find(|(n, _)| **n == block.ty || n.ends_with(&suffix)) else {
            continue;
        };
        assert_eq!(
            offsets,
            &declared_offsets(block),
            "{} block ({what}) vs declared.rs",
            block.ty
        );
        found.push(block.ty);
    }
    found
}

/// The frame's blocks as glslang lays out the GLSL naga writes for the tessellation and mesh
/// stages (std140) are as Rust declares them.
#[test]
fn frame_blocks_match_the_glsl_blocks() {
    let mut found = Vec::new();
    for stage in ["blade.tese", "blade.mesh"] {
        found.extend(frame_blocks_match(
            &struct_offsets(ShaderSet::embedded().get(stage)),
            stage,
        ));
    }
    assert!(found.contains(&"Camera"), "no stage reads the camera block: {found:?}");
}

/// The frame's blocks in every pass and draw stage, and the blade, as naga lays out the core's
/// WGSL for the Vulkan renderer (the uniform and storage layout rules), are Rust's too.
#[test]
fn frame_blocks_and_blades_match_the_wgsl_structs() {
    let mut found = Vec::new();
    let set = ShaderSet::embedded();
    let passes = shaders::wgsl_passes().map(|pass| (pass, set.wgsl(&pass, &[], false)));
    let draws = shaders::wgsl_draw_stages().map(|(draw, stage)| (draw, set.wgsl_stage(&draw, stage, &[], false)));
    for (source, words) in passes.chain(draws) {
        let words = words.unwrap_or_else(|e| panic!("{}: {e}", source.name));
        let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
        let structs = struct_offsets(&bytes);
        found.extend(frame_blocks_match(&structs, source.name));
        if source.name == shaders::SIMULATE.name {
            // WESL names a module's declarations by their module's path too
            // (`package_blade_Blade`).
            let blade = [
                offset_of!(Blade, v0),
                offset_of!(Blade, v1),
                offset_of!(Blade, v2),
                offset_of!(Blade, up),
            ];
            assert_eq!(
                named(&structs, "Blade"),
                blade.map(|o| o as u32),
                "Blade (WGSL) vs Blade (Rust)"
            );
        }
    }
    for block in &BLOCKS {
        assert!(
            found.contains(&block.ty),
            "no pass checked reads the {} block",
            block.ty
        );
    }
}

#[test]
fn blade_and_draw_command_match_the_glsl_structs() {
    let structs = struct_offsets(ShaderSet::embedded().get("blade.tese"));
    // The mesh stage reads the draw commands (the tessellation stages do not).
    let commands = struct_offsets(ShaderSet::embedded().get("blade.mesh"));
    let blade = [
        offset_of!(Blade, v0),
        offset_of!(Blade, v1),
        offset_of!(Blade, v2),
        offset_of!(Blade, up),
    ]
    .map(|o| o as u32);
    assert_eq!(named(&structs, "Blade"), blade);
    let draw = [
        offset_of!(DrawCommand, vertex_count),
        offset_of!(DrawCommand, instance_count),
        offset_of!(DrawCommand, first_vertex),
        offset_of!(DrawCommand, first_instance),
    ]
    .map(|o| o as u32);
    assert_eq!(named(&commands, "DrawCommand"), draw);
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

/// Every number sward-core declares reaches the GLSL by its name with its value, and no shader
/// file declares one of those names itself.
#[test]
fn the_shaders_take_every_declared_number_from_sward_core() {
    let declared: HashMap<String, u32> = glsl_constants(&declared::glsl()).into_iter().collect();
    for (name, value) in declared::numbers() {
        assert_eq!(declared.get(name), Some(&value), "declared.glsl: {name}");
    }
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/shaders");
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let source = std::fs::read_to_string(&path).unwrap();
        for (name, _) in glsl_constants(&source) {
            assert!(
                !declared.contains_key(&name),
                "{} declares {name}, which sward-core declares",
                path.display()
            );
        }
    }
}

/// No shader of the frame's set names a binding or a specialisation constant by its number:
/// every one by its name from sward-core (declared.glsl, the WESL module `declared`). (The depth
/// pyramid's reduction and the bandwidth probe have sets of their own.)
#[test]
fn shaders_name_every_binding_and_constant() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/shaders");
    let glsl = std::fs::read_dir(dir).unwrap().map(|entry| {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        (name, std::fs::read_to_string(&path).unwrap())
    });
    let wesl = sward_core::wgsl::MODULES
        .iter()
        .filter(|(name, _)| !["hiz_reduce", "bandwidth"].contains(name))
        .map(|(name, text)| (format!("{name}.wesl"), text.to_string()));
    let keys = [
        "binding = ",
        "constant_id = ",
        "local_size_x_id = ",
        "@binding(",
        "@id(",
    ];
    for (name, source) in glsl.chain(wesl) {
        for (k, line) in source.lines().enumerate() {
            for key in keys {
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
        "crates/sward-core/shaders",
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
