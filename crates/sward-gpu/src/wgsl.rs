//! The core's WGSL as the Vulkan renderer runs it: a pass's module composed by WESL
//! (sward-portable's modules, one source for both renderers), its overrides given the values the
//! GLSL stages' specialisation constants get, then written as SPIR-V by naga.
//!
//! naga adds by default what WebGPU's safety asks of untrusted shaders: a bounds check on every
//! index, a bound on every loop and the workgroup memory zeroed before each workgroup starts.
//! The Vulkan renderer's inputs are sward's own and its GLSL never had them, so here they are
//! off; integer division keeps its guard against a zero divisor, so a pass divides as it does
//! on the portable renderer.

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
    spv::write_vec(&module, &info, &options, Some(&pipeline)).map_err(|e| format!("{entry}: {e}"))
}

/// The checks wgpu asks of naga for a device without robust buffer access: every index
/// clamped into its array, loops bounded, workgroup memory zeroed.
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
