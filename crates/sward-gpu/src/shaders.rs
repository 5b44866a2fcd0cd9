//! The SPIR-V of every stage in `shaders/`, compiled by `build.rs` and embedded in the binary.

macro_rules! spirv {
    ($file:literal) => {
        include_bytes!(concat!(env!("OUT_DIR"), "/", $file))
    };
}

pub const SIMULATE_COMP: &[u8] = spirv!("simulate_comp.spv");
pub const CULL_COMP: &[u8] = spirv!("cull_comp.spv");
pub const BLADE_VERT: &[u8] = spirv!("blade_vert.spv");
pub const BLADE_TESC: &[u8] = spirv!("blade_tesc.spv");
pub const BLADE_TESE: &[u8] = spirv!("blade_tese.spv");
pub const BLADE_FRAG: &[u8] = spirv!("blade_frag.spv");
pub const GROUND_VERT: &[u8] = spirv!("ground_vert.spv");
pub const GROUND_FRAG: &[u8] = spirv!("ground_frag.spv");
pub const SKY_VERT: &[u8] = spirv!("sky_vert.spv");
pub const SKY_FRAG: &[u8] = spirv!("sky_frag.spv");
