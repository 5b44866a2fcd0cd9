//! What the passes of both renderers share with the host, declared once here and written into the
//! shader sources from here: the frame set's binding numbers, the override (specialisation
//! constant) ids, the flags and codes (`flags.rs`), the command slots (`commands.rs`) and the
//! frame's uniform blocks (`BLOCKS`: `gpu.rs` `FrameUniforms` cut by subject, each block bound
//! on its own). The WGSL gets them as the module `declared` its modules import from (the blocks
//! as structs and the uniform variables the passes read); the tessellation stages' GLSL as `declared.glsl`. Nothing
//! in a shader spells one of these numbers itself.

use std::fmt::Write;

use glam::{Mat4, UVec4, Vec4};

use crate::gpu::FrameUniforms;

/// The frame set's bindings: one number per resource on both renderers (the Vulkan renderer's
/// one descriptor set, the portable renderer's group 0 of each pipeline, which binds only
/// what the pipeline reads).
pub mod bindings {
    /// The frame's camera block (`BLOCKS[0]`: its matrices, eye, viewport, sun and origin),
    /// which nearly every pass reads.
    pub const CAMERA: u32 = 0;
    /// The Bezier blades.
    pub const BLADES: u32 = 1;
    /// Their collision strengths η.
    pub const ETAS: u32 = 2;
    /// The cull's verdicts.
    pub const VISIBLE: u32 = 3;
    /// The Bezier blades' draw commands and dispatch sizes.
    pub const DRAWS: u32 = 4;
    /// Each cull workgroup's blades per distance bucket, scanned into where its runs start (both
    /// renderers' ordering: bucket_runs.wesl), or the copy variant's culled blades.
    pub const CULLED: u32 = 5;
    /// The ground mesh's vertices (position, normal).
    pub const GROUND: u32 = 6;
    /// The tiles this frame runs.
    pub const ACTIVE_TILES: u32 = 7;
    /// The occluders' depth pyramid (a combined image sampler).
    pub const DEPTH_PYRAMID: u32 = 8;
    /// The sun's shadow map (a combined image sampler).
    pub const SHADOW_MAP: u32 = 9;
    /// The generated grass's patch lists.
    pub const PATCHES: u32 = 10;
    /// The generated grass's visible lists.
    pub const GENERATED_BLADES: u32 = 11;
    /// The generated grass's draw commands and dispatch sizes.
    pub const GENERATED_DRAWS: u32 = 12;
    /// The splat target's cells (`splat.rs`).
    pub const SPLAT_CELLS: u32 = 13;
    /// The billboards' painted grass texture (a combined image sampler).
    pub const GRASS_TEXTURE: u32 = 14;
    /// The visible Bezier blades in draw order.
    pub const ORDERED: u32 = 15;
    /// The generated grass's counts per workgroup and level (`instanced.rs`).
    pub const GENERATED_COUNTS: u32 = 16;
    /// The trample map's texels (`trample.rs`).
    pub const TRAMPLE: u32 = 17;
    /// The caller's depth image, where it gives one for occlusion (a combined image sampler,
    /// caller_depth_fold.wesl). Written only then: only the pass that folds it into the depth
    /// pyramid reads it.
    pub const CALLER_DEPTH: u32 = 18;
    /// The depth pyramid's level 0 as a storage image, which the caller's depth is folded
    /// into.
    pub const PYRAMID_BASE: u32 = 19;
    /// The paint maps' texels (`paint.rs`).
    pub const PAINT: u32 = 20;
    /// The listed blades as a renderer that draws them itself reads them (`drawn_blades.rs`).
    pub const DRAWN_BLADES: u32 = 21;
    /// The splat target's cells again, as 32-bit words: WGSL's 64-bit atomics allow only
    /// `atomicMin`/`atomicMax`, so the plain reads and stores of the same cells go through a
    /// second binding of the buffer.
    pub const SPLAT_WORDS: u32 = 22;
    /// The shadow map's comparison sampler (WGSL samples the map's image, bound at
    /// `SHADOW_MAP`, with it).
    pub const SHADOW_SAMPLER: u32 = 23;
    /// The sampler of the billboards' grass texture (WGSL samples the texture, bound at
    /// `GRASS_TEXTURE`, with it); the last binding of the Vulkan renderer's set.
    pub const GRASS_SAMPLER: u32 = 24;

    // What only the portable renderer and an engine's passes bind today.

    /// Each Bezier blade's distance bucket (the portable cull's three passes).
    pub const BUCKET_OF: u32 = 25;
    /// The portable cull's counters: per bucket its count, next free place and start, then the
    /// buckets drawn.
    pub const CULL_COUNTERS: u32 = 26;
    /// The portable generated grass's dispatch sizes.
    pub const GENERATED_DISPATCH: u32 = 27;
    /// Which level of the depth pyramid a reduction makes.
    pub const PYRAMID_STEP: u32 = 28;
    /// The occluders' depth the pyramid's level 0 is made from.
    pub const OCCLUDER_DEPTH: u32 = 29;
    /// The caller's depth image where it is multisampled.
    pub const CALLER_DEPTH_SAMPLES: u32 = 30;
    /// The blades as the last frame left them (an engine's motion vectors).
    pub const PREVIOUS_BLADES: u32 = 31;

    // The frame's other uniform blocks (`super::BLOCKS`), each bound by the passes that read it.

    /// The forces that bend the blades: gravity, the simulation's step, the winds, the
    /// colliders.
    pub const FORCES: u32 = 32;
    /// What the culls test: thresholds, levels of detail, routes, occlusion, tiles.
    pub const CULLING: u32 = 33;
    /// How the grass looks: colours, shading, species, seed heads, lamps.
    pub const LOOKS: u32 = 34;
    /// The ground the grass stands on: its extent and placement, the streamed window, the paint
    /// and trample maps.
    pub const TERRAIN: u32 = 35;
    /// The generated grass's and billboards' grids.
    pub const GRIDS: u32 = 36;

    /// The frame's uniform blocks' bindings, in `BLOCKS`' order.
    pub const FRAME_BLOCKS: [u32; 6] = [CAMERA, FORCES, CULLING, LOOKS, TERRAIN, GRIDS];

    /// Every binding with its name, as the shaders spell it.
    pub const ALL: [(&str, u32); 37] = [
        ("BINDING_CAMERA", CAMERA),
        ("BINDING_BLADES", BLADES),
        ("BINDING_ETAS", ETAS),
        ("BINDING_VISIBLE", VISIBLE),
        ("BINDING_DRAWS", DRAWS),
        ("BINDING_CULLED", CULLED),
        ("BINDING_GROUND", GROUND),
        ("BINDING_ACTIVE_TILES", ACTIVE_TILES),
        ("BINDING_DEPTH_PYRAMID", DEPTH_PYRAMID),
        ("BINDING_SHADOW_MAP", SHADOW_MAP),
        ("BINDING_PATCHES", PATCHES),
        ("BINDING_GENERATED_BLADES", GENERATED_BLADES),
        ("BINDING_GENERATED_DRAWS", GENERATED_DRAWS),
        ("BINDING_SPLAT_CELLS", SPLAT_CELLS),
        ("BINDING_GRASS_TEXTURE", GRASS_TEXTURE),
        ("BINDING_ORDERED", ORDERED),
        ("BINDING_GENERATED_COUNTS", GENERATED_COUNTS),
        ("BINDING_TRAMPLE", TRAMPLE),
        ("BINDING_CALLER_DEPTH", CALLER_DEPTH),
        ("BINDING_PYRAMID_BASE", PYRAMID_BASE),
        ("BINDING_PAINT", PAINT),
        ("BINDING_DRAWN_BLADES", DRAWN_BLADES),
        ("BINDING_SPLAT_WORDS", SPLAT_WORDS),
        ("BINDING_SHADOW_SAMPLER", SHADOW_SAMPLER),
        ("BINDING_GRASS_SAMPLER", GRASS_SAMPLER),
        ("BINDING_BUCKET_OF", BUCKET_OF),
        ("BINDING_CULL_COUNTERS", CULL_COUNTERS),
        ("BINDING_GENERATED_DISPATCH", GENERATED_DISPATCH),
        ("BINDING_PYRAMID_STEP", PYRAMID_STEP),
        ("BINDING_OCCLUDER_DEPTH", OCCLUDER_DEPTH),
        ("BINDING_CALLER_DEPTH_SAMPLES", CALLER_DEPTH_SAMPLES),
        ("BINDING_PREVIOUS_BLADES", PREVIOUS_BLADES),
        ("BINDING_FORCES", FORCES),
        ("BINDING_CULLING", CULLING),
        ("BINDING_LOOKS", LOOKS),
        ("BINDING_TERRAIN", TERRAIN),
        ("BINDING_GRIDS", GRIDS),
    ];
}

/// The specialisation constants' (WGSL: overrides') ids: each id means one thing in every
/// shader that has it, and a shader ignores the ids it lacks.
pub mod constants {
    /// The compute passes' workgroup size.
    pub const WORKGROUP: u32 = 0;
    /// Subgroup-aggregated atomics in the cull.
    pub const USE_SUBGROUPS: u32 = 1;
    /// The bench's variant that copies whole culled blades (`ComputeOptions::copy_blades`).
    pub const COPY_BLADES: u32 = 2;
    /// Whose eyes a pipeline's vertex stages draw through (`flags::VIEW_*`).
    pub const VIEW: u32 = 3;
    /// The generating passes run over the billboards' grid (else the instanced grass's).
    pub const BILLBOARDS: u32 = 4;
    /// Which chunk of its list instanced_raster.wesl rasterizes.
    pub const CHUNK: u32 = 6;
    /// The second pass of the Bezier blades' compute rasterizer, or of the splat tiles' depths.
    pub const SECOND_PASS: u32 = 7;
    /// The splat tiles' depths between the generated grass's rasterizer chunks.
    pub const GENERATED: u32 = 8;
    /// The renderer's target runs its depth reversed (`DepthDirection::Reverse`).
    pub const REVERSED_DEPTH: u32 = 9;
    /// The instanced grass's generating passes' workgroup size (the billboards' grid and every
    /// other pass run `WORKGROUP`), which every pass reading their counts is told.
    pub const INSTANCED_WORKGROUP: u32 = 10;

    /// Every id with its name, as the shaders spell it.
    pub const ALL: [(&str, u32); 10] = [
        ("CONSTANT_WORKGROUP", WORKGROUP),
        ("CONSTANT_USE_SUBGROUPS", USE_SUBGROUPS),
        ("CONSTANT_COPY_BLADES", COPY_BLADES),
        ("CONSTANT_VIEW", VIEW),
        ("CONSTANT_BILLBOARDS", BILLBOARDS),
        ("CONSTANT_CHUNK", CHUNK),
        ("CONSTANT_SECOND_PASS", SECOND_PASS),
        ("CONSTANT_GENERATED", GENERATED),
        ("CONSTANT_REVERSED_DEPTH", REVERSED_DEPTH),
        ("CONSTANT_INSTANCED_WORKGROUP", INSTANCED_WORKGROUP),
    ];
}

/// Every named number the shaders read: flags, codes, command slots, bindings and override ids.
pub fn numbers() -> impl Iterator<Item = (&'static str, u32)> {
    crate::flags::ALL
        .into_iter()
        .chain(crate::flags::CODES)
        .chain(crate::commands::ALL)
        .chain(crate::commands::generated::ALL)
        .chain(bindings::ALL)
        .chain(constants::ALL)
}

/// A member type of a block the shaders read, as WGSL and GLSL spell it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MemberType {
    /// Four floats.
    Vec4,
    /// Four unsigned integers.
    UVec4,
    /// A 4 × 4 float matrix, column major.
    Mat4,
    /// An array of `n` four-float vectors.
    Vec4Array(usize),
}

impl MemberType {
    fn wgsl(self) -> String {
        match self {
            MemberType::Vec4 => "vec4<f32>".into(),
            MemberType::UVec4 => "vec4<u32>".into(),
            MemberType::Mat4 => "mat4x4<f32>".into(),
            MemberType::Vec4Array(n) => format!("array<vec4<f32>, {n}>"),
        }
    }

    /// Its size in bytes (in std140 and in Rust alike: only 16-byte members).
    pub const fn size(self) -> usize {
        match self {
            MemberType::Vec4 | MemberType::UVec4 => 16,
            MemberType::Mat4 => 64,
            MemberType::Vec4Array(n) => 16 * n,
        }
    }
}

/// The Rust types a shared block's members may have.
pub trait Member {
    /// How the shaders spell it.
    const TYPE: MemberType;
}

impl Member for Vec4 {
    const TYPE: MemberType = MemberType::Vec4;
}

impl Member for UVec4 {
    const TYPE: MemberType = MemberType::UVec4;
}

impl Member for Mat4 {
    const TYPE: MemberType = MemberType::Mat4;
}

impl<const N: usize> Member for [Vec4; N] {
    const TYPE: MemberType = MemberType::Vec4Array(N);
}

/// A block's members in order: name, type, byte offset.
pub type Members = &'static [(&'static str, MemberType, usize)];

/// The members of a `#[repr(C)]` struct, each with its type and offset, checked by the compiler
/// against the struct: `members!(FrameUniforms { view_proj: Mat4, ... })`.
macro_rules! members {
    ($block:ty { $($name:ident: $ty:ty),* $(,)? }) => {{
        // Each named member has the type said (a wrong one does not compile).
        const _: fn(&$block) = |block| { $(let _: &$ty = &block.$name;)* };
        &[$((stringify!($name), <$ty as Member>::TYPE, std::mem::offset_of!($block, $name))),*]
    }};
}

/// A uniform block of the frame's: its name in WGSL (struct and variable), its binding and its
/// members, each at its offset in `FrameUniforms`.
pub struct Block {
    /// The WGSL struct's name.
    pub ty: &'static str,
    /// The WGSL variable's name, which the passes read it by.
    pub var: &'static str,
    /// Its binding (`bindings::FRAME_BLOCKS`).
    pub binding: u32,
    /// Its members, in order.
    pub members: Members,
}

/// The frame's uniforms as the passes bind them: blocks by what they describe, each pass
/// binding the blocks it reads (a pipeline's group holds only those), the camera's nearly
/// always. By subject rather than one block per pass, because a WGSL function reads the
/// globals it names and the core's functions (a blade's look, the wind) are called from several
/// passes: a block per pass would need those functions once per block. On the GPU each block
/// starts at a multiple of `BLOCK_ALIGNMENT` in the frame's buffer (`frame_bytes`).
pub const BLOCKS: [Block; 6] = [
    // The camera's: its view and projection, eye, viewport, the sun and the frame origin (nearly every pass reads it).
    Block {
        ty: "Camera",
        var: "camera",
        binding: bindings::CAMERA,
        members: members!(FrameUniforms {
            view_proj: Mat4,
            inv_view_proj: Mat4,
            sun_view_proj: Mat4,
            sun_near_view_proj: Mat4,
            camera_position: Vec4,
            viewport: Vec4,
            light_direction: Vec4,
            light_color: Vec4,
            origin: Vec4,
            frustum: [Vec4; 6],
        }),
    },
    // The forces: gravity, the simulation's step and counts, the winds and the colliders.
    Block {
        ty: "Forces",
        var: "forces",
        binding: bindings::FORCES,
        members: members!(FrameUniforms {
            gravity: Vec4,
            point_gravity: Vec4,
            simulation: Vec4,
            counts: UVec4,
            winds: [Vec4; 3 * crate::wind::MAX_WINDS],
            colliders: [Vec4; crate::physics::MAX_COLLIDERS],
        }),
    },
    // The culls': their tests and thresholds, levels of detail, routes, occlusion, patches and tiles.
    Block {
        ty: "Culling",
        var: "culling",
        binding: bindings::CULLING,
        members: members!(FrameUniforms {
            cull: Vec4,
            coarse_cull: Vec4,
            modes: UVec4,
            lod: Vec4,
            routes: UVec4,
            occlusion: UVec4,
            patch_cull: UVec4,
            patch_bounds: Vec4,
            tiles: UVec4,
        }),
    },
    // The grass's looks: the blade's style, colours, sky, shading, species, seed heads and lamps.
    Block {
        ty: "Looks",
        var: "looks",
        binding: bindings::LOOKS,
        members: members!(FrameUniforms {
            blade_style: Vec4,
            root_color: Vec4,
            tip_color: Vec4,
            ground_color: Vec4,
            sky_zenith: Vec4,
            sky_horizon: Vec4,
            shading_model: Vec4,
            shading_extra: Vec4,
            species_meta: UVec4,
            species: [Vec4; 4 * crate::species::MAX_SPECIES],
            seed_heads: [Vec4; 2 * crate::species::MAX_SPECIES],
            lamp_meta: UVec4,
            lamps: [Vec4; 3 * crate::look::MAX_LAMPS],
        }),
    },
    // The ground's: its extent, surface and placement, the streamed window, the paint maps and the trample map.
    Block {
        ty: "Terrain",
        var: "terrain",
        binding: bindings::TERRAIN,
        members: members!(FrameUniforms {
            ground_extent: Vec4,
            surface: Vec4,
            placed: Mat4,
            placed_before: Mat4,
            stream: UVec4,
            stream_reach: Vec4,
            paint_area: Vec4,
            paint_size: UVec4,
            paint_noise: Vec4,
            paint_tint_noise: Vec4,
            paint_tint_color: Vec4,
            trample: UVec4,
            mowing: UVec4,
            trample_scale: Vec4,
        }),
    },
    // The generated grass's and the billboards' grids, shapes, motion, levels and lists.
    Block {
        ty: "Grids",
        var: "grids",
        binding: bindings::GRIDS,
        members: members!(FrameUniforms {
            instanced_grid: Vec4,
            instanced_shape: Vec4,
            instanced_motion: Vec4,
            instanced_lod: Vec4,
            instanced_lists: UVec4,
            instanced_caps: UVec4,
            instanced_meta: UVec4,
            instanced_ground: Vec4,
            instanced_ground_cells: UVec4,
            billboard_grid: Vec4,
            billboard_shape: Vec4,
            billboard_motion: Vec4,
            billboard_meta: UVec4,
            billboard_far: Vec4,
            instanced_raster: UVec4,
        }),
    },
];

/// Where a uniform block may start in a buffer (WebGPU's and every Vulkan device's
/// `minUniformBufferOffsetAlignment` is at most this).
pub const BLOCK_ALIGNMENT: usize = 256;

/// A block's size in bytes: its members back to back (each a multiple of 16 bytes, so std140
/// and WGSL's uniform layout put them where Rust's sum does).
pub const fn block_size(block: &Block) -> usize {
    let mut size = 0;
    let mut i = 0;
    while i < block.members.len() {
        size += block.members[i].1.size();
        i += 1;
    }
    size
}

/// Where block `index` of `BLOCKS` starts in the frame's buffer: after the blocks before it,
/// at a multiple of `BLOCK_ALIGNMENT`.
pub const fn block_offset(index: usize) -> usize {
    let mut at = 0;
    let mut i = 0;
    while i < index {
        at += block_size(&BLOCKS[i]).div_ceil(BLOCK_ALIGNMENT) * BLOCK_ALIGNMENT;
        i += 1;
    }
    at
}

/// The frame's buffer's size: every block at its offset.
pub const FRAME_BYTES: usize = block_offset(BLOCKS.len() - 1) + block_size(&BLOCKS[BLOCKS.len() - 1]);

/// Each block of the frame's buffer: its binding, byte offset and size.
pub fn frame_blocks() -> impl Iterator<Item = (u32, u64, u64)> {
    BLOCKS
        .iter()
        .enumerate()
        .map(|(i, b)| (b.binding, block_offset(i) as u64, block_size(b) as u64))
}

/// `uniforms` as the frame's buffer holds them (`FRAME_BYTES`): each block's members copied
/// to the block's place.
pub fn frame_bytes(uniforms: &FrameUniforms) -> Vec<u8> {
    let mut bytes = vec![0; FRAME_BYTES];
    write_frame(uniforms, &mut bytes);
    bytes
}

/// `uniforms` written into `bytes` (at least `FRAME_BYTES` long) as the frame's buffer holds
/// them.
pub fn write_frame(uniforms: &FrameUniforms, bytes: &mut [u8]) {
    let from = bytemuck::bytes_of(uniforms);
    for (i, block) in BLOCKS.iter().enumerate() {
        let mut at = block_offset(i);
        for (_, ty, offset) in block.members {
            bytes[at..at + ty.size()].copy_from_slice(&from[*offset..offset + ty.size()]);
            at += ty.size();
        }
    }
}

/// The WGSL module `declared`: every named number as a `const`, and each of the frame's blocks
/// as a struct and the uniform variable the passes read it by.
pub fn wgsl() -> String {
    let mut text = String::from("// Written by sward-core declared.rs: change it there.\n");
    for (name, value) in numbers() {
        let _ = writeln!(text, "const {name}: u32 = {value}u;");
    }
    for block in &BLOCKS {
        let _ = writeln!(text, "\nstruct {} {{", block.ty);
        for (name, ty, _) in block.members {
            let _ = writeln!(text, "    {name}: {},", ty.wgsl());
        }
        text.push_str("}\n");
        let _ = writeln!(
            text,
            "@group(0) @binding({}) var<uniform> {}: {};",
            block.binding, block.var, block.ty
        );
    }
    text
}

/// `declared.glsl`: every named number as a `const` (the tessellation stages' specialisation
/// constant ids; the structs and the frame block come with the core's WGSL written as GLSL).
pub fn glsl() -> String {
    let mut text = String::from("// Written by sward-core declared.rs: change it there.\n");
    for (name, value) in numbers() {
        // Bindings and ids are ints where GLSL's layout qualifiers read them.
        let ty = if name.starts_with("BINDING_") || name.starts_with("CONSTANT_") {
            "int"
        } else {
            "uint"
        };
        let suffix = if ty == "uint" { "u" } else { "" };
        let _ = writeln!(text, "const {ty} {name} = {value}{suffix};");
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_blocks_hold_every_member_of_the_frame_once() {
        let mut members: Vec<(usize, usize)> = BLOCKS
            .iter()
            .flat_map(|b| b.members.iter().map(|(_, ty, at)| (*at, ty.size())))
            .collect();
        members.sort();
        let mut at = 0;
        for (offset, size) in members {
            assert_eq!(
                offset, at,
                "a member of FrameUniforms at {at} is in no block, or in two"
            );
            at += size;
        }
        assert_eq!(at, std::mem::size_of::<FrameUniforms>());
    }

    #[test]
    fn each_block_starts_aligned_after_the_one_before() {
        let mut end = 0;
        for (i, (binding, offset, size)) in frame_blocks().enumerate() {
            assert_eq!(binding, bindings::FRAME_BLOCKS[i]);
            assert_eq!(offset as usize % BLOCK_ALIGNMENT, 0);
            assert!(offset >= end, "block {i} overlaps the one before");
            end = offset + size;
        }
        assert_eq!(end as usize, FRAME_BYTES);
    }

    #[test]
    fn the_frame_s_bytes_hold_each_member_in_its_block() {
        let mut uniforms: FrameUniforms = bytemuck::Zeroable::zeroed();
        uniforms.trample_scale = Vec4::new(1.0, 2.0, 3.0, 4.0);
        uniforms.view_proj = Mat4::from_diagonal(Vec4::splat(5.0));
        let bytes = frame_bytes(&uniforms);
        let terrain = BLOCKS.iter().position(|b| b.var == "terrain").unwrap();
        let scale = BLOCKS[terrain]
            .members
            .iter()
            .take_while(|(n, _, _)| *n != "trample_scale");
        let at = block_offset(terrain) + scale.map(|(_, ty, _)| ty.size()).sum::<usize>();
        assert_eq!(
            bytemuck::cast_slice::<u8, f32>(&bytes[at..at + 16]),
            &[1.0, 2.0, 3.0, 4.0]
        );
        assert_eq!(bytemuck::cast_slice::<u8, f32>(&bytes[0..4]), &[5.0]);
    }

    #[test]
    fn every_name_is_declared_once() {
        let mut names: Vec<&str> = numbers().map(|(n, _)| n).collect();
        let all = names.len();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), all);
    }

    #[test]
    fn the_binding_numbers_are_distinct() {
        let mut numbers: Vec<u32> = bindings::ALL.iter().map(|(_, b)| *b).collect();
        numbers.sort();
        numbers.dedup();
        assert_eq!(numbers.len(), bindings::ALL.len());
    }
}
