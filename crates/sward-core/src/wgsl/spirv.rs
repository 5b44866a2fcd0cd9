//! SPIR-V as naga writes it, mended where Vulkan asks otherwise: each fragment stage's
//! `SampleMask` output an array of one word (VUID-SampleMask-SampleMask-04359), where naga 30
//! writes one word (gfx-rs/wgpu#7311); and where sward's own values make it needless, without
//! the clamp naga writes before each float-to-integer conversion. Both renderers hand such
//! SPIR-V to Vulkan: the Vulkan renderer every stage, the portable renderer on wgpu's Vulkan
//! backend its splat resolve and its compute passes.

/// `OpConstant`.
pub const OP_CONSTANT: u32 = 43;
/// `OpTypeArray`.
pub const OP_TYPE_ARRAY: u32 = 28;
/// `OpTypePointer`.
pub const OP_TYPE_POINTER: u32 = 32;
/// `OpVariable`.
pub const OP_VARIABLE: u32 = 59;
/// `OpStore`.
pub const OP_STORE: u32 = 62;
/// `OpAccessChain`.
pub const OP_ACCESS_CHAIN: u32 = 65;
/// `OpDecorate`.
pub const OP_DECORATE: u32 = 71;
/// The `BuiltIn` decoration.
pub const DECORATION_BUILT_IN: u32 = 11;
/// The `SampleMask` built-in.
pub const BUILT_IN_SAMPLE_MASK: u32 = 20;
/// The `Output` storage class.
pub const STORAGE_CLASS_OUTPUT: u32 = 3;

/// SPIR-V `words` with each `SampleMask` output (WGSL's `@builtin(sample_mask)`) an array of
/// one word, as Vulkan asks (VUID-SampleMask-SampleMask-04359), where naga writes one word
/// (gfx-rs/wgpu#7311): the variable's type becomes `array<u32, 1>` and each store to it a store
/// to its element 0.
pub fn sample_masks_as_arrays(words: Vec<u32>) -> Vec<u32> {
    let instructions = instructions_of(&words);
    let masks: Vec<u32> = instructions
        .iter()
        .filter(|i| i[0] & 0xffff == OP_DECORATE && i.len() == 4)
        .filter(|i| i[2] == DECORATION_BUILT_IN && i[3] == BUILT_IN_SAMPLE_MASK)
        .map(|i| i[1])
        .collect();
    if masks.is_empty() {
        return words;
    }
    // The pointee type of each Output pointer type.
    let pointee = |pointer: u32| {
        instructions
            .iter()
            .find(|i| i[0] & 0xffff == OP_TYPE_POINTER && i[1] == pointer && i[2] == STORAGE_CLASS_OUTPUT)
            .map(|i| i[3])
    };
    let mut bound = words[3];
    let mut fresh = || {
        bound += 1;
        bound - 1
    };
    let mut out = words[..5].to_vec();
    // Per mask variable: its word's pointer type, and the constant 0 that indexes its element.
    let mut arrays: Vec<(u32, u32, u32)> = Vec::new();
    for i in &instructions {
        let opcode = i[0] & 0xffff;
        if opcode == OP_VARIABLE && masks.contains(&i[2]) {
            if let Some(word) = pointee(i[1]) {
                let (one, zero, array, pointer) = (fresh(), fresh(), fresh(), fresh());
                out.extend([(4 << 16) | OP_CONSTANT, word, one, 1]);
                out.extend([(4 << 16) | OP_CONSTANT, word, zero, 0]);
                out.extend([(4 << 16) | OP_TYPE_ARRAY, array, word, one]);
                out.extend([(4 << 16) | OP_TYPE_POINTER, pointer, STORAGE_CLASS_OUTPUT, array]);
                out.extend([i[0], pointer, i[2], i[3]]);
                out.extend(&i[4..]);
                arrays.push((i[2], i[1], zero));
                continue;
            }
        }
        if opcode == OP_STORE {
            if let Some(&(_, word_pointer, zero)) = arrays.iter().find(|(v, _, _)| *v == i[1]) {
                let element = fresh();
                out.extend([(5 << 16) | OP_ACCESS_CHAIN, word_pointer, element, i[1], zero]);
                out.extend([i[0], element]);
                out.extend(&i[2..]);
                continue;
            }
        }
        out.extend(i.iter());
    }
    out[3] = bound;
    out
}

/// `OpExtInstImport`.
pub const OP_EXT_INST_IMPORT: u32 = 11;
/// `OpExtInst`.
pub const OP_EXT_INST: u32 = 12;
/// `OpConvertFToU`.
pub const OP_CONVERT_F_TO_U: u32 = 109;
/// `OpConvertFToS`.
pub const OP_CONVERT_F_TO_S: u32 = 110;
/// GLSL.std.450's `FClamp`.
pub const GLSL_FCLAMP: u32 = 43;

/// naga's SPIR-V `words` with each float-to-integer conversion reading the value naga clamped
/// into the integer's range rather than the clamp (left to the driver to drop): naga writes
/// the clamp (WGSL defines an out-of-range conversion; SPIR-V does not) right before the
/// conversion, and nothing else writes a clamp there. Every value sward converts is in range.
/// Measured on the H100: the instanced grass's splat walk converts at each cell it writes, and
/// with the clamps its generating at 2^26 candidates took 7.09 ms against the GLSL's 6.45.
pub fn unclamped_conversions(mut words: Vec<u32>) -> Vec<u32> {
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

/// The instructions of SPIR-V `words` past the header, each with its words; none where they
/// are malformed.
pub fn instructions_of(words: &[u32]) -> Vec<&[u32]> {
    let mut instructions = Vec::new();
    let mut at = 5;
    while at < words.len() {
        let count = (words[at] >> 16) as usize;
        if count == 0 || at + count > words.len() {
            return Vec::new();
        }
        instructions.push(&words[at..at + count]);
        at += count;
    }
    instructions
}
