//! The core's WGSL as the Vulkan renderer runs it: a pass's module composed by WESL
//! (sward-portable's modules, one source for both renderers), its overrides given the values the
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
    Ok(match checked {
        true => words,
        false => unclamped_conversions(words),
    })
}

/// SPIR-V's opcodes and GLSL.std.450's instruction that `unclamped_conversions` reads.
const OP_EXT_INST_IMPORT: u32 = 11;
const OP_EXT_INST: u32 = 12;
const OP_CONVERT_F_TO_U: u32 = 109;
const OP_CONVERT_F_TO_S: u32 = 110;
const GLSL_FCLAMP: u32 = 43;

/// naga's SPIR-V `words` with each float-to-integer conversion reading the value naga clamped
/// into the integer's range rather than the clamp (left to the driver to drop): naga writes
/// the clamp (WGSL defines an out-of-range conversion; SPIR-V does not) right before the
/// conversion, and nothing else writes a clamp there. Every value sward converts is in range.
/// Measured on the H100: the instanced grass's splat walk converts at each cell it writes, and
/// with the clamps its generating at 2^26 candidates took 7.09 ms against the GLSL's 6.45.
fn unclamped_conversions(mut words: Vec<u32>) -> Vec<u32> {
    let glsl = glsl_std_450(&words);
    // (result id, clamped value) of the clamp just read.
    let mut clamp: Option<(u32, u32)> = None;
    let mut at = 5; // past the header
    while at < words.len() {
        let count = (words[at] >> 16) as usize;
        let opcode = words[at] & 0xffff;
        if count == 0 || at + count > words.len() {
            break; // malformed: leave the rest as naga wrote it
        }
        let converts = opcode == OP_CONVERT_F_TO_S || opcode == OP_CONVERT_F_TO_U;
        match clamp {
            Some((id, value)) if converts && count == 4 && words[at + 3] == id => words[at + 3] = value,
            _ => {}
        }
        let is_clamp =
            opcode == OP_EXT_INST && count == 8 && Some(words[at + 3]) == glsl && words[at + 4] == GLSL_FCLAMP;
        clamp = match is_clamp {
            true => Some((words[at + 2], words[at + 5])),
            false => None,
        };
        at += count;
    }
    words
}

/// The id SPIR-V `words` import GLSL.std.450's instructions by, if they do.
fn glsl_std_450(words: &[u32]) -> Option<u32> {
    let name: Vec<u32> = b"GLSL.std.450\0\0\0\0"
        .chunks(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    let mut at = 5;
    while at < words.len() {
        let count = (words[at] >> 16) as usize;
        if count == 0 || at + count > words.len() {
            return None;
        }
        if words[at] & 0xffff == OP_EXT_INST_IMPORT && words[at + 2..at + count] == name[..count - 2] {
            return Some(words[at + 1]);
        }
        at += count;
    }
    None
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
}
