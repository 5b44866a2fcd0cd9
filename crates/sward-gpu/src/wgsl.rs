//! The core's WGSL as the Vulkan renderer runs it: a pass's module composed by WESL
//! (sward-core's `wgsl` modules, one source for both renderers), its overrides given the values the
//! GLSL stages' specialisation constants get, then written as SPIR-V by naga.
//!
//! naga adds by default what WebGPU's safety asks of untrusted shaders: a bounds check on every
//! index, a bound on every loop, the workgroup memory zeroed before each workgroup starts and a
//! clamp before every conversion of a float to an integer. The Vulkan renderer's inputs are
//! sward's own and its GLSL never had them, so here they are off (the clamps taken out of
//! naga's output: `unclamped_conversions`); integer division keeps its guard against a zero
//! divisor, so a pass divides as it does on the portable renderer.

use naga::back::spv;
use naga::valid::{Capabilities, ValidationFlags, Validator};

pub use naga::ShaderStage;

/// The SPIR-V (1.5, as Vulkan 1.2 on reads it) of entry point `entry` of stage `stage` in
/// WGSL `text`, its overrides with ids in `constants` (id, value) set to those values (the
/// others keep their defaults), with naga's safety checks where `checked` (to measure them);
/// naga's message where it cannot.
pub fn spirv(
    text: &str,
    (entry, stage): (&str, ShaderStage),
    constants: &[(u32, u32)],
    checked: bool,
) -> Result<Vec<u32>, String> {
    let module = naga::front::wgsl::parse_str(text).map_err(|e| e.emit_to_string(text))?;
    let info = Validator::new(ValidationFlags::all(), Capabilities::all())
        .validate(&module)
        .map_err(|e| e.emit_to_string(text))?;
    // Only the overrides the module has: naga refuses a value for one it lacks.
    let mut values = naga::back::PipelineConstants::default();
    for (_, o) in module.overrides.iter() {
        if let Some((_, value)) = constants.iter().find(|(id, _)| o.id == Some(*id as u16)) {
            values.insert(o.id.unwrap_or_default().to_string(), f64::from(*value));
        }
    }
    let (module, info) =
        naga::back::pipeline_constants::process_overrides(&module, &info, Some((stage, entry)), &values)
            .map_err(|e| format!("{entry}: {e}"))?;
    let pipeline = spv::PipelineOptions {
        shader_stage: stage,
        entry_point: entry.to_string(),
    };
    let mut options = match checked {
        true => checked_options(),
        false => options(),
    };
    // The core's vertex stages write wgpu's clip space, whose y runs up (`target_clip`): naga
    // turns it back into Vulkan's, as wgpu's Vulkan backend has it do.
    if stage == ShaderStage::Vertex {
        options.flags |= spv::WriterFlags::ADJUST_COORDINATE_SPACE;
    }
    let words = spv::write_vec(&module, &info, &options, Some(&pipeline)).map_err(|e| format!("{entry}: {e}"))?;
    let words = sward_core::wgsl::spirv::sample_masks_as_arrays(words);
    Ok(match checked {
        true => words,
        false => sward_core::wgsl::spirv::unclamped_conversions(words),
    })
}

/// The functions of the core's WGSL `text` that compute entry point `entry` reaches, written as
/// GLSL by naga for the tessellation stages to call (WGSL has no tessellation stages): its
/// structs, constants, the frame set's buffers at the WGSL's binding numbers (set 0) and every
/// function but the entry point itself, which only reaches them. The vertex struct the
/// fragments read is named `BladeVertex` there, as in the WGSL.
pub fn glsl_functions(text: &str, entry: &str) -> Result<String, String> {
    use naga::back::glsl;
    let module = naga::front::wgsl::parse_str(text).map_err(|e| e.emit_to_string(text))?;
    let info = Validator::new(ValidationFlags::all(), Capabilities::all())
        .validate(&module)
        .map_err(|e| e.emit_to_string(text))?;
    let binding_map = module
        .global_variables
        .iter()
        .filter_map(|(_, global)| global.binding)
        .map(|binding| {
            let number = u8::try_from(binding.binding).map_err(|_| format!("binding {} is past 255", binding.binding));
            number.map(|n| (binding, n))
        })
        .collect::<Result<glsl::BindingMap, String>>()?;
    let options = glsl::Options {
        version: glsl::Version::Desktop(460),
        writer_flags: glsl::WriterFlags::empty(),
        binding_map,
        zero_initialize_workgroup_memory: false,
    };
    let pipeline = glsl::PipelineOptions {
        shader_stage: ShaderStage::Compute,
        entry_point: entry.to_string(),
        multiview: None,
    };
    let unchecked = naga::proc::BoundsCheckPolicies::default();
    let mut written = String::new();
    glsl::Writer::new(&mut written, &module, &info, &options, &pipeline, unchecked)
        .and_then(|mut writer| writer.write().map(|_| ()))
        .map_err(|e| format!("{entry}: {e}"))?;
    Ok(functions_only(&written))
}

/// naga's GLSL of a compute entry point less what makes it one (its version, extensions,
/// workgroup size and `main`), with WESL's module path taken off the vertex struct's name.
fn functions_only(written: &str) -> String {
    let body = written.split("\nvoid main()").next().unwrap_or(written);
    let kept: Vec<&str> = body
        .lines()
        .filter(|line| !line.starts_with('#') && !line.starts_with("layout(local_size"))
        .collect();
    let text = kept.join("\n") + "\n";
    let vertex = text
        .split(|c: char| !(c.is_alphanumeric() || c == '_'))
        .find(|word| word.ends_with("_BladeVertex"));
    match vertex {
        Some(mangled) => text.replace(mangled, "BladeVertex"),
        None => text,
    }
}

/// SPIR-V's opcodes and execution modes that the fix-ups read.
const OP_ENTRY_POINT: u32 = 15;
const OP_EXECUTION_MODE: u32 = 16;
const EXECUTION_MODEL_FRAGMENT: u32 = 4;
const EARLY_FRAGMENT_TESTS: u32 = 9;

/// A fragment stage's SPIR-V `words` with its depth and stencil tests run before it
/// (`EarlyFragmentTests`), for a pipeline whose fragments write no depth: WGSL's
/// `@early_depth_test(force)` says so, but only naga reads it, and WESL's parser (which
/// composes every pass) refuses it. Unchanged where `words` hold no fragment entry point.
pub fn early_fragment_tests(mut words: Vec<u32>) -> Vec<u32> {
    let mut entry = None;
    let mut first_mode = None;
    let mut at = 5; // past the header
    while at < words.len() {
        let count = (words[at] >> 16) as usize;
        if count == 0 || at + count > words.len() {
            return words; // malformed: left as naga wrote it
        }
        match words[at] & 0xffff {
            OP_ENTRY_POINT if count > 2 && words[at + 1] == EXECUTION_MODEL_FRAGMENT => entry = Some(words[at + 2]),
            OP_EXECUTION_MODE if first_mode.is_none() => first_mode = Some(at),
            _ => {}
        }
        at += count;
    }
    // Execution modes follow the entry points: the new one goes before naga's first.
    if let (Some(entry), Some(at)) = (entry, first_mode) {
        words.splice(at..at, [(3 << 16) | OP_EXECUTION_MODE, entry, EARLY_FRAGMENT_TESTS]);
    }
    words
}

/// The checks wgpu asks of naga for a device without robust buffer access: every index
/// clamped into its array, loops bounded, workgroup memory zeroed (and conversions clamped).
fn checked_options() -> spv::Options<'static> {
    let restrict = naga::proc::BoundsCheckPolicy::Restrict;
    spv::Options {
        bounds_check_policies: naga::proc::BoundsCheckPolicies {
            index: restrict,
            buffer: restrict,
            image_load: restrict,
            binding_array: restrict,
        },
        zero_initialize_workgroup_memory: spv::ZeroInitializeWorkgroupMemoryMode::Polyfill,
        force_loop_bounding: true,
        ..options()
    }
}

/// naga's SPIR-V options for the Vulkan renderer (see the module's note).
fn options() -> spv::Options<'static> {
    let unchecked = naga::proc::BoundsCheckPolicy::Unchecked;
    spv::Options {
        lang_version: (1, 5),
        // Names kept (a validation message names the variable).
        flags: spv::WriterFlags::DEBUG | spv::WriterFlags::LABEL_VARYINGS,
        // Each binding as the WGSL declares it (sward-core's numbers): no map.
        fake_missing_bindings: true,
        bounds_check_policies: naga::proc::BoundsCheckPolicies {
            index: unchecked,
            buffer: unchecked,
            image_load: unchecked,
            binding_array: unchecked,
        },
        zero_initialize_workgroup_memory: spv::ZeroInitializeWorkgroupMemoryMode::None,
        force_loop_bounding: false,
        ..spv::Options::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sward_core::wgsl::spirv::{
        instructions_of, BUILT_IN_SAMPLE_MASK, DECORATION_BUILT_IN, GLSL_FCLAMP, OP_ACCESS_CHAIN, OP_CONSTANT,
        OP_CONVERT_F_TO_S, OP_CONVERT_F_TO_U, OP_DECORATE, OP_EXT_INST, OP_STORE, OP_TYPE_ARRAY, OP_TYPE_POINTER,
        OP_VARIABLE,
    };

    /// A pass that converts floats to integers: plainly, and after a clamp of its own.
    const CONVERTS: &str = "
        @group(0) @binding(0) var<storage, read_write> out: array<i32>;
        @group(0) @binding(1) var<storage, read_write> values: array<f32>;
        @compute @workgroup_size(1)
        fn convert() {
            out[0] = i32(floor(values[0]));
            out[1] = i32(clamp(values[1], 0.0, 5.0));
            out[2] = i32(u32(values[2]));
        }";

    /// The operands (ids) the float-to-integer conversions of SPIR-V `words` read, and the ids of
    /// the FClamps.
    fn conversions_and_clamps(words: &[u32]) -> (Vec<u32>, Vec<u32>) {
        let (mut converted, mut clamps) = (Vec::new(), Vec::new());
        let mut at = 5;
        while at < words.len() {
            let count = (words[at] >> 16) as usize;
            let opcode = words[at] & 0xffff;
            if opcode == OP_CONVERT_F_TO_S || opcode == OP_CONVERT_F_TO_U {
                converted.push(words[at + 3]);
            }
            if opcode == OP_EXT_INST && words[at + 4] == GLSL_FCLAMP {
                clamps.push(words[at + 2]);
            }
            at += count;
        }
        (converted, clamps)
    }

    #[test]
    fn conversions_read_the_unclamped_value_unless_checked() {
        let entry = ("convert", ShaderStage::Compute);
        let plain = spirv(CONVERTS, entry, &[], false).unwrap();
        let (converted, clamps) = conversions_and_clamps(&plain);
        assert_eq!(converted.len(), 3, "three conversions");
        // naga's three clamps are still there (the driver drops them), and the shader's own.
        assert_eq!(clamps.len(), 4, "the clamps naga wrote and the shader's own");
        // The second reads the shader's own clamp, the others no clamp.
        let read: Vec<bool> = converted.iter().map(|id| clamps.contains(id)).collect();
        assert_eq!(read, [false, true, false], "which conversions read a clamp");
        let checked = spirv(CONVERTS, entry, &[], true).unwrap();
        let (converted, clamps) = conversions_and_clamps(&checked);
        assert!(
            converted.iter().all(|id| clamps.contains(id)),
            "with naga's checks every conversion reads its clamp"
        );
    }

    /// The execution modes SPIR-V `words` give their entry points: (entry id, mode).
    fn execution_modes(words: &[u32]) -> Vec<(u32, u32)> {
        let mut modes = Vec::new();
        let mut at = 5;
        while at < words.len() {
            let count = (words[at] >> 16) as usize;
            if words[at] & 0xffff == OP_EXECUTION_MODE {
                modes.push((words[at + 1], words[at + 2]));
            }
            at += count;
        }
        modes
    }

    #[test]
    fn a_fragment_stage_asked_for_early_tests_gets_them_and_nothing_else_changes() {
        let shade = "
            @fragment
            fn shade(@location(0) colour: vec4<f32>) -> @location(0) vec4<f32> {
                return colour;
            }";
        let plain = spirv(shade, ("shade", ShaderStage::Fragment), &[], false).unwrap();
        let early = early_fragment_tests(plain.clone());
        let before = execution_modes(&plain);
        let after = execution_modes(&early);
        assert!(
            !before.iter().any(|(_, m)| *m == EARLY_FRAGMENT_TESTS),
            "naga asks for none"
        );
        let entry = before[0].0;
        assert_eq!(after.len(), before.len() + 1, "one mode more");
        assert!(
            after.contains(&(entry, EARLY_FRAGMENT_TESTS)),
            "the entry point tests early"
        );
        assert_eq!(early.len(), plain.len() + 3, "one instruction of three words more");
        // A compute pass holds no fragment entry point: left as it is.
        let pass = spirv(CONVERTS, ("convert", ShaderStage::Compute), &[], false).unwrap();
        assert_eq!(early_fragment_tests(pass.clone()), pass);
    }

    #[test]
    fn a_sample_mask_output_is_an_array_of_one_word_stored_through_its_element() {
        let masked = "
            struct Covered {
                @location(0) colour: vec4<f32>,
                @builtin(sample_mask) samples: u32,
            }
            @fragment
            fn cover(@builtin(position) at: vec4<f32>) -> Covered {
                return Covered(at, u32(at.x) & 15u);
            }";
        let words = spirv(masked, ("cover", ShaderStage::Fragment), &[], false).unwrap();
        let instructions = instructions_of(&words);
        let find = |opcode: u32, id_at: usize, id: u32| {
            instructions
                .iter()
                .find(|i| i[0] & 0xffff == opcode && i.len() > id_at && i[id_at] == id)
                .copied()
        };
        let mask = instructions
            .iter()
            .find(|i| i[0] & 0xffff == OP_DECORATE && i[2..] == [DECORATION_BUILT_IN, BUILT_IN_SAMPLE_MASK])
            .map(|i| i[1])
            .expect("a sample mask output");
        let variable = find(OP_VARIABLE, 2, mask).expect("its variable");
        let pointer = find(OP_TYPE_POINTER, 1, variable[1]).expect("its pointer type");
        let array = find(OP_TYPE_ARRAY, 1, pointer[3]).expect("an array, as Vulkan asks");
        let length = find(OP_CONSTANT, 2, array[3]).expect("its length");
        assert_eq!(length[3], 1, "one word");
        let stores = |to: u32| {
            instructions
                .iter()
                .filter(|i| i[0] & 0xffff == OP_STORE && i[1] == to)
                .count()
        };
        assert_eq!(stores(mask), 0, "nothing stores the whole array");
        let element = find(OP_ACCESS_CHAIN, 3, mask).expect("its element");
        assert_eq!(stores(element[2]), 1, "the mask is stored through its element");
        let new_ids = [array[1], pointer[1], length[2], element[2]];
        assert!(
            new_ids.iter().all(|id| *id < words[3]),
            "the id bound covers the new ids"
        );
    }

    /// The GLSL the tessellation stages include holds the functions the entry point reaches,
    /// the buffers at the WGSL's binding numbers and the vertex struct by its own name, and
    /// nothing that would make it a compute shader.
    #[test]
    fn glsl_functions_are_the_functions_alone() {
        let text = "
            struct package_1blade_fragment_BladeVertex { @builtin(position) clip: vec4<f32>, @location(0) v: f32 }
            @group(0) @binding(15) var<storage, read> ordered: array<u32>;
            fn first_vertex(i: u32) -> package_1blade_fragment_BladeVertex {
                var out: package_1blade_fragment_BladeVertex;
                out.v = f32(ordered[i]);
                return out;
            }
            @compute @workgroup_size(1)
            fn reach() { let v = first_vertex(0u); }
        ";
        let glsl = glsl_functions(text, "reach").expect("naga writes it");
        assert!(glsl.contains("BladeVertex first_vertex(uint i)"), "{glsl}");
        assert!(glsl.contains("binding = 15"), "{glsl}");
        for absent in ["#version", "#extension", "local_size", "void main", "package_1blade"] {
            assert!(!glsl.contains(absent), "{absent} in {glsl}");
        }
    }
}
