//! How the frame's pipelines are made — the builder each pass uses for its own set (`field.rs`,
//! `routes.rs`, `ground.rs`, `occluders.rs`, `instanced.rs`, `splat.rs`; gathered into one by
//! `frame_pipelines.rs`, so the viewer's hot reload swaps them as one), the formats, and the one
//! descriptor layout they share: binding
//! 0 the frame uniforms, 1 blades, 2 collision strengths η, 3 visible indices, 4 draw commands, …
//! (sward-core `declared::bindings`).

use std::borrow::Cow;
use std::sync::Arc;

use ash::vk;
pub use sward_core::camera::DepthDirection;
use sward_core::flags;
use sward_core::instanced::PATCH_BLADES;

use crate::context::{Context, DeviceInfo};
use crate::error::{vk_check, GpuError, Result};
use crate::shaders::{entry_point, spirv_bytes, ShaderSet, ShaderStage};
use sward_core::wgsl::PipelineSource;

/// The depth attachments' format.
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;
/// The depth pyramid's texels: one depth each.
pub const HIZ_FORMAT: vk::Format = vk::Format::R32_SFLOAT;

/// How the compute passes are built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ComputeOptions {
    /// Invocations per workgroup (a multiple of the subgroup size; 64–1024).
    pub workgroup: u32,
    /// Invocations per workgroup of the instanced grass's generating passes (a multiple of the
    /// subgroup size dividing a patch's 1024 cells; where the device cannot run it, `workgroup`).
    pub instanced_workgroup: u32,
    /// Aggregate the visible-list atomics per subgroup (where the device has subgroup ballot).
    pub subgroup_atomics: bool,
    /// Cull copies whole 64-byte blades for the draw instead of 4-byte indices (only to measure
    /// what the index list saves; SPEC §5.4).
    pub copy_blades: bool,
    /// The core's WGSL translated with naga's safety checks (bounds, loop bounds, zeroed
    /// workgroup memory), as wgpu gives it to the portable renderer's devices (only to measure
    /// what they cost; `wgsl.rs`).
    pub wgsl_checks: bool,
}

impl ComputeOptions {
    /// Invocations per workgroup of the instanced grass's generating passes on a device with
    /// `info`: `instanced_workgroup` where the device can run it, else `workgroup`.
    /// Why a patch's 1024 by default: the splatting lanes wait on memory, and a workgroup of 1024
    /// caps the compiler at 64 registers a lane, so more warps are resident to hide it (and the
    /// queue sorts four times the blades by their walk). On the H200 the instanced grass at
    /// 2^26 candidates generated in 7.28 ms instead of 7.98; the billboards' grid, which queues
    /// no splats, read 1.2 % slower so, and keeps `workgroup` (docs/benchmarks-history.md).
    pub fn instanced_workgroup_on(&self, info: &DeviceInfo) -> u32 {
        let wanted = self.instanced_workgroup;
        let runs =
            wanted <= info.max_workgroup_invocations && counting_shared_bytes(wanted) <= info.max_workgroup_shared;
        if runs && PATCH_BLADES.is_multiple_of(wanted) {
            wanted
        } else {
            self.workgroup
        }
    }

    /// Generating workgroups a patch has on a device with `info`: the instanced grass's, the
    /// billboards'.
    pub fn patch_groups_on(&self, info: &DeviceInfo) -> [u32; 2] {
        [self.instanced_workgroup_on(info), self.workgroup].map(|w| PATCH_BLADES.div_ceil(w))
    }
}

/// Shared memory the instanced grass's counting pass declares with workgroups of `invocations`
/// (generate_grid.wesl, the most of its two passes): the level and bin counts and the splat
/// queue's 20-byte slot per invocation.
fn counting_shared_bytes(invocations: u32) -> u32 {
    4 * 6 + 4 * 64 + 20 * invocations
}

impl Default for ComputeOptions {
    fn default() -> Self {
        ComputeOptions {
            workgroup: 256,
            instanced_workgroup: PATCH_BLADES,
            subgroup_atomics: true,
            copy_blades: false,
            wgsl_checks: false,
        }
    }
}

/// What the graphics pipelines render into.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TargetFormat {
    /// The colour attachment's format (`UNDEFINED`: depth only).
    pub color: vk::Format,
    /// The depth attachment's format: any with depth ([`DEPTH_FORMAT`] for sward's own
    /// targets). A stencil part is left alone.
    pub depth: vk::Format,
    /// Samples per pixel.
    pub samples: vk::SampleCountFlags,
    /// Which way the depth attachment runs.
    pub depth_direction: DepthDirection,
}

/// `op`, a test written for forward depth, turned round for `direction`.
fn compare(direction: DepthDirection, op: vk::CompareOp) -> vk::CompareOp {
    match (direction, op) {
        (DepthDirection::Reverse, vk::CompareOp::LESS) => vk::CompareOp::GREATER,
        (DepthDirection::Reverse, vk::CompareOp::LESS_OR_EQUAL) => vk::CompareOp::GREATER_OR_EQUAL,
        _ => op,
    }
}

/// A pipeline, destroyed when dropped: every pass holds its own.
pub struct Pipeline {
    /// The Vulkan pipeline.
    pub raw: vk::Pipeline,
    ctx: Arc<Context>,
}

impl Drop for Pipeline {
    fn drop(&mut self) {
        unsafe { self.ctx.device.destroy_pipeline(self.raw, None) };
    }
}

/// The frame's one descriptor set layout and pipeline layout, which every pass's pipelines share.
pub struct FrameLayout {
    /// The frame's descriptor set layout.
    pub set_layout: vk::DescriptorSetLayout,
    /// The pipeline layout of that one set.
    pub layout: vk::PipelineLayout,
    ctx: Arc<Context>,
}

impl FrameLayout {
    pub(crate) fn new(ctx: &Arc<Context>) -> Result<FrameLayout> {
        let d = &ctx.device;
        let set_layout = create_set_layout(d, ctx.info.mesh_shaders)?;
        let set_layouts = [set_layout];
        let layout_info = vk::PipelineLayoutCreateInfo::default().set_layouts(&set_layouts);
        match unsafe { d.create_pipeline_layout(&layout_info, None) } {
            Ok(layout) => Ok(FrameLayout {
                set_layout,
                layout,
                ctx: ctx.clone(),
            }),
            Err(e) => {
                unsafe { d.destroy_descriptor_set_layout(set_layout, None) };
                Err(vk_check("creating the pipeline layout")(e))
            }
        }
    }
}

impl Drop for FrameLayout {
    fn drop(&mut self) {
        unsafe {
            self.ctx.device.destroy_pipeline_layout(self.layout, None);
            self.ctx.device.destroy_descriptor_set_layout(self.set_layout, None);
        }
    }
}

/// What every pass needs to build its pipelines: the device, the frame's layout, the target,
/// the compute options and the SPIR-V.
pub(crate) struct Builder<'a> {
    pub ctx: &'a Arc<Context>,
    pub layout: vk::PipelineLayout,
    pub target: TargetFormat,
    pub options: ComputeOptions,
    pub shaders: &'a ShaderSet,
}

impl Builder<'_> {
    /// A compute pipeline of the core's WGSL pass `pass` (`shaders::wgsl_passes`).
    pub fn compute_wgsl(&self, pass: &PipelineSource) -> Result<Pipeline> {
        self.compute_wgsl_with(pass, &[])
    }

    /// [`Builder::compute_wgsl`] with the pass's own overrides as given: (id from
    /// [`constants`], value).
    pub fn compute_wgsl_with(&self, pass: &PipelineSource, constants: &[(u32, u32)]) -> Result<Pipeline> {
        self.own(compute_wgsl(
            self.ctx,
            self.layout,
            (self.shaders, pass),
            self.options,
            constants,
        )?)
    }

    /// Whether the cull aggregates its atomics per subgroup on this device.
    pub fn cull_subgroups(&self) -> bool {
        self.options.subgroup_atomics && self.ctx.info.subgroup_ballot
    }

    /// A graphics pipeline of `stages` (the core's WGSL or GLSL) into the frame's target.
    pub fn draw(&self, desc: &GraphicsDesc, stages: &[Stage]) -> Result<Pipeline> {
        self.draw_into(self.target, desc, stages)
    }

    /// A graphics pipeline of `stages` into `target`. Its stages learn whose eyes it draws
    /// through (`VIEW`) and which way the renderer's own target runs (`REVERSED_DEPTH`: the
    /// caller's depth folded into the pyramid, the splats' depths), whatever `target` is.
    pub fn draw_into(&self, target: TargetFormat, desc: &GraphicsDesc, stages: &[Stage]) -> Result<Pipeline> {
        let reversed = self.target.depth_direction == DepthDirection::Reverse;
        let values = [
            (constants::COPY_BLADES, desc.copy_blades as u32),
            (constants::VIEW, desc.view as u32),
            (constants::REVERSED_DEPTH, reversed as u32),
        ];
        // Fragments that write no depth run after the depth test (the billboards' shading after
        // their pre-pass), as a GLSL stage says with `early_fragment_tests`.
        let early_tests = desc.depth == Depth::SameSurface;
        let spirv = stages
            .iter()
            .map(|stage| self.stage_spirv(*stage, &values, early_tests))
            .collect::<Result<Vec<_>>>()?;
        self.own(graphics(self.ctx, self.layout, target, (desc, &values), &spirv)?)
    }

    /// The SPIR-V of `stage` with its constants `values`: a GLSL stage's takes them as
    /// specialisation constants when its pipeline is made, a WGSL stage's overrides are set
    /// here, and a WGSL fragment stage runs its fragments' tests first where `early_tests`.
    fn stage_spirv(&self, stage: Stage, values: &[(u32, u32)], early_tests: bool) -> Result<StageSpirv<'_>> {
        let wgsl = |pass: &PipelineSource, which: ShaderStage, flag: vk::ShaderStageFlags| {
            let shader_error = |message| GpuError::Shader {
                pass: pass.name.to_string(),
                message,
            };
            let entry = entry_point(pass, which).map_err(shader_error)?;
            let mut words = self
                .shaders
                .wgsl_stage(pass, which, values, self.options.wgsl_checks)
                .map_err(shader_error)?;
            if early_tests && which == ShaderStage::Fragment {
                words = crate::wgsl::early_fragment_tests(words);
            }
            Ok(StageSpirv {
                flag,
                spirv: Cow::Owned(spirv_bytes(&words)),
                entry: std::ffi::CString::new(entry).expect("an entry point's name has no NUL"),
            })
        };
        match stage {
            Stage::Glsl(name) => Ok(StageSpirv {
                flag: crate::shaders::stage_flag(name),
                spirv: Cow::Borrowed(self.shaders.get(name)),
                entry: c"main".to_owned(),
            }),
            Stage::Vertex(pass) => wgsl(pass, ShaderStage::Vertex, vk::ShaderStageFlags::VERTEX),
            Stage::Fragment(pass) => wgsl(pass, ShaderStage::Fragment, vk::ShaderStageFlags::FRAGMENT),
        }
    }

    fn own(&self, raw: vk::Pipeline) -> Result<Pipeline> {
        Ok(Pipeline {
            raw,
            ctx: self.ctx.clone(),
        })
    }

    /// The description of drawn geometry that tests and writes depth (ground, colliders).
    pub fn opaque(&self) -> GraphicsDesc {
        GraphicsDesc {
            copy_blades: self.options.copy_blades,
            depth: Depth::TestAndWrite,
            tessellated: false,
            strip: false,
            alpha_to_coverage: false,
            writes_color: true,
            wireframe: false,
            view: View::Camera,
        }
    }
}

/// A stage of a graphics pipeline.
#[derive(Clone, Copy)]
pub(crate) enum Stage<'a> {
    /// A GLSL stage, by its file's name in the shader directory.
    Glsl(&'a str),
    /// The vertex stage of a draw of the core's WGSL (`shaders::wgsl_draw_stages`).
    Vertex(&'a PipelineSource),
    /// The fragment stage of a draw of the core's WGSL.
    Fragment(&'a PipelineSource),
}

/// A stage's SPIR-V as a pipeline takes it.
pub(crate) struct StageSpirv<'a> {
    flag: vk::ShaderStageFlags,
    spirv: Cow<'a, [u8]>,
    entry: std::ffi::CString,
}

/// The frame set's bindings and the specialisation constants' ids: declared once in sward-core
/// (`declared.rs`), which writes them into the shaders too.
pub use sward_core::declared::{bindings, constants};

/// Storage buffers of the frame's set from `bindings::BLADES` on: blades, η, visible, draws,
/// culled copies, ground vertices, active tiles.
pub(crate) const STORAGE_BINDINGS: u32 = 7;
/// Sampled images of the frame's set after them: the depth pyramid and the sun's shadow map.
pub(crate) const IMAGE_BINDINGS: u32 = 2;
/// Storage buffers of the generated grass from `bindings::PATCHES` on: patches, visible
/// blades, draws, and the splat target's cells.
pub(crate) const INSTANCED_BINDINGS: u32 = 4;

const _: () = assert!(bindings::DEPTH_PYRAMID == 1 + STORAGE_BINDINGS);
const _: () = assert!(bindings::PATCHES == bindings::DEPTH_PYRAMID + IMAGE_BINDINGS);
const _: () = assert!(bindings::SPLAT_CELLS == bindings::PATCHES + INSTANCED_BINDINGS - 1);

/// The frame's set layout; its bindings reach the mesh stage too where the device has one.
pub(crate) fn create_set_layout(d: &ash::Device, mesh: bool) -> Result<vk::DescriptorSetLayout> {
    let mut stages = vk::ShaderStageFlags::COMPUTE
        | vk::ShaderStageFlags::VERTEX
        | vk::ShaderStageFlags::TESSELLATION_CONTROL
        | vk::ShaderStageFlags::TESSELLATION_EVALUATION
        | vk::ShaderStageFlags::FRAGMENT;
    if mesh {
        stages |= vk::ShaderStageFlags::MESH_EXT;
    }
    use bindings::*;
    let bindings: Vec<vk::DescriptorSetLayoutBinding> = (0..=GRASS_SAMPLER)
        // The frame's blocks past the camera's (which is binding 0).
        .chain(FRAME_BLOCKS[1..].iter().copied())
        .map(|binding| {
            let kind = match binding {
                _ if FRAME_BLOCKS.contains(&binding) => vk::DescriptorType::UNIFORM_BUFFER,
                DEPTH_PYRAMID | SHADOW_MAP | GRASS_TEXTURE | CALLER_DEPTH => vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                PYRAMID_BASE => vk::DescriptorType::STORAGE_IMAGE,
                SHADOW_SAMPLER | GRASS_SAMPLER => vk::DescriptorType::SAMPLER,
                _ => vk::DescriptorType::STORAGE_BUFFER,
            };
            vk::DescriptorSetLayoutBinding::default()
                .binding(binding)
                .descriptor_type(kind)
                .descriptor_count(1)
                .stage_flags(stages)
        })
        .collect();
    let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
    unsafe { d.create_descriptor_set_layout(&info, None) }.map_err(vk_check("creating the descriptor set layout"))
}

/// A set layout for a compute-only helper pass: `bindings`, each one descriptor of type `ty`.
pub(crate) fn compute_set_layout(
    d: &ash::Device,
    ty: vk::DescriptorType,
    bindings: &[u32],
    what: &'static str,
) -> Result<vk::DescriptorSetLayout> {
    let bindings: Vec<_> = bindings
        .iter()
        .map(|&binding| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(binding)
                .descriptor_type(ty)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::COMPUTE)
        })
        .collect();
    let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
    unsafe { d.create_descriptor_set_layout(&info, None) }.map_err(vk_check(what))
}

pub(crate) fn shader_module(d: &ash::Device, spirv: &[u8]) -> Result<vk::ShaderModule> {
    let words: Vec<u32> = spirv
        .as_chunks::<4>()
        .0
        .iter()
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    let info = vk::ShaderModuleCreateInfo::default().code(&words);
    unsafe { d.create_shader_module(&info, None) }.map_err(vk_check("creating a shader module"))
}

/// The map entries and data of specialisation constants given as (id, value), 4 bytes each.
fn specialization_of(values: &[(u32, u32)]) -> (Vec<vk::SpecializationMapEntry>, Vec<u8>) {
    let entries = (0..)
        .zip(values)
        .map(|(k, &(constant_id, _))| vk::SpecializationMapEntry {
            constant_id,
            offset: 4 * k,
            size: 4,
        })
        .collect();
    let data = values.iter().flat_map(|(_, v)| v.to_le_bytes()).collect();
    (entries, data)
}

/// The specialisation constants (id, value) a compute pass gets: every shader's (workgroups,
/// subgroups, the copy variant), a shader's own (`own`) in place of those of the same id.
fn constant_values(ctx: &Context, options: ComputeOptions, own: &[(u32, u32)]) -> Vec<(u32, u32)> {
    let use_subgroups = options.subgroup_atomics && ctx.info.subgroup_ballot;
    let every = [
        (constants::WORKGROUP, options.workgroup),
        (
            constants::INSTANCED_WORKGROUP,
            options.instanced_workgroup_on(&ctx.info),
        ),
        (constants::USE_SUBGROUPS, use_subgroups as u32),
        (constants::COPY_BLADES, options.copy_blades as u32),
    ];
    every
        .iter()
        .filter(|(id, _)| own.iter().all(|(o, _)| o != id))
        .chain(own)
        .copied()
        .collect()
}

/// The compute pipeline of entry point `entry` of `module` (destroyed here) specialised as
/// `specialization` says.
fn compute_of(
    ctx: &Context,
    layout: vk::PipelineLayout,
    (module, entry): (vk::ShaderModule, &std::ffi::CStr),
    specialization: &vk::SpecializationInfo,
) -> Result<vk::Pipeline> {
    let d = &ctx.device;
    let stage = vk::PipelineShaderStageCreateInfo::default()
        .stage(vk::ShaderStageFlags::COMPUTE)
        .module(module)
        .name(entry)
        .specialization_info(specialization);
    let info = [vk::ComputePipelineCreateInfo::default().stage(stage).layout(layout)];
    let result = unsafe { d.create_compute_pipelines(vk::PipelineCache::null(), &info, None) };
    unsafe { d.destroy_shader_module(module, None) };
    result
        .map(|p| p[0])
        .map_err(|(_, e)| vk_check("creating a compute pipeline")(e))
}

/// The compute pipeline of the core's WGSL pass `pass` (`shaders::wgsl_passes`), its
/// overrides set to the values the GLSL passes' specialisation constants get (`own` in place of
/// those of the same id).
pub(crate) fn compute_wgsl(
    ctx: &Context,
    layout: vk::PipelineLayout,
    (shaders, pass): (&ShaderSet, &PipelineSource),
    options: ComputeOptions,
    own: &[(u32, u32)],
) -> Result<vk::Pipeline> {
    let values = constant_values(ctx, options, own);
    let words = shaders
        .wgsl(pass, &values, options.wgsl_checks)
        .map_err(|message| GpuError::Shader {
            pass: pass.name.to_string(),
            message,
        })?;
    let module = shader_module(&ctx.device, &spirv_bytes(&words))?;
    let entry = std::ffi::CString::new(pass.entry).expect("an entry point's name has no NUL");
    compute_of(ctx, layout, (module, &entry), &vk::SpecializationInfo::default())
}

/// How a pipeline uses the depth buffer.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Depth {
    /// Nearest surface wins and is recorded.
    TestAndWrite,
    /// Only where the depth buffer is still cleared to the far plane; records nothing.
    BehindEverything,
    /// Only where this very surface won a depth pre-pass; records nothing, so the fragment's
    /// tests may run before it is shaded. Both passes run the same vertex module with the same
    /// constants, so their depths agree to the bit (`invariant` would promise it, but lavapipe
    /// warns about it on `gl_Position`'s block; tests compare the pictures with and without
    /// the pre-pass).
    SameSurface,
}

/// Whose eyes a pipeline draws through: specialisation constant `VIEW` of the vertex stages
/// (`flags::VIEW_*`).
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum View {
    Camera = flags::VIEW_CAMERA as isize,
    /// The sun's orthographic view of the field, for the shadow map's field cascade
    /// (depth-biased against shadow acne).
    Sun = flags::VIEW_SUN_FIELD as isize,
    /// The sun's view of the ball around the eye, for the shadow map's near cascade (biased too).
    SunNear = flags::VIEW_SUN_NEAR as isize,
    /// The camera, drawing the nearest blades narrowed into the depth pyramid as occluders.
    Occluder = flags::VIEW_OCCLUDERS as isize,
}

impl View {
    /// Whether this is the sun's view (a shadow map's, drawn depth-biased).
    fn is_sun(self) -> bool {
        matches!(self, View::Sun | View::SunNear)
    }
}

#[derive(Clone, Copy)]
pub(crate) struct GraphicsDesc {
    pub copy_blades: bool,
    pub depth: Depth,
    pub tessellated: bool,
    /// Triangle strips (the instanced blades) instead of lists.
    pub strip: bool,
    /// The fragment's alpha sets the sample coverage (the billboards' painted texture).
    pub alpha_to_coverage: bool,
    /// Whether colour reaches the target (false: a depth pre-pass).
    pub writes_color: bool,
    pub wireframe: bool,
    pub view: View,
}

/// A graphics pipeline of `stages` into `target`, drawn as `desc` says, the GLSL stages'
/// specialisation constants set to `values` (the WGSL stages' overrides already are).
fn graphics(
    ctx: &Context,
    layout: vk::PipelineLayout,
    target: TargetFormat,
    (desc, values): (&GraphicsDesc, &[(u32, u32)]),
    stages: &[StageSpirv],
) -> Result<vk::Pipeline> {
    let d = &ctx.device;
    let modules = stages
        .iter()
        .map(|stage| shader_module(d, &stage.spirv))
        .collect::<Result<Vec<_>>>()?;
    let (entries, data) = specialization_of(values);
    let specialization = vk::SpecializationInfo::default().map_entries(&entries).data(&data);
    let stage_infos: Vec<_> = stages
        .iter()
        .zip(&modules)
        .map(|(stage, module)| {
            vk::PipelineShaderStageCreateInfo::default()
                .stage(stage.flag)
                .module(*module)
                .name(&stage.entry)
                .specialization_info(&specialization)
        })
        .collect();
    let vertex_input = vk::PipelineVertexInputStateCreateInfo::default();
    let topology = if desc.tessellated {
        vk::PrimitiveTopology::PATCH_LIST
    } else if desc.strip {
        vk::PrimitiveTopology::TRIANGLE_STRIP
    } else {
        vk::PrimitiveTopology::TRIANGLE_LIST
    };
    let assembly = vk::PipelineInputAssemblyStateCreateInfo::default().topology(topology);
    let tessellation = vk::PipelineTessellationStateCreateInfo::default().patch_control_points(1);
    let viewport = vk::PipelineViewportStateCreateInfo::default()
        .viewport_count(1)
        .scissor_count(1);
    let raster = vk::PipelineRasterizationStateCreateInfo::default()
        .polygon_mode(if desc.wireframe {
            vk::PolygonMode::LINE
        } else {
            vk::PolygonMode::FILL
        })
        .cull_mode(vk::CullModeFlags::NONE)
        .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
        .line_width(1.0)
        // The shadow map's depths sit a little behind the casters' surfaces, so lit surfaces do
        // not shadow themselves (acne) where the sun grazes them. Only the sun's: biased, the
        // depth pyramid's blade occluders would lose their depth test to farther ones, and the
        // pyramid would hide less than the portable renderer's, which draws them unbiased.
        .depth_bias_enable(desc.view.is_sun())
        .depth_bias_constant_factor(2.0)
        .depth_bias_slope_factor(2.5);
    // Alpha that only picks the coverage must not reach the image (it stays opaque).
    let write_mask = if !desc.writes_color {
        vk::ColorComponentFlags::empty()
    } else if desc.alpha_to_coverage {
        vk::ColorComponentFlags::R | vk::ColorComponentFlags::G | vk::ColorComponentFlags::B
    } else {
        vk::ColorComponentFlags::RGBA
    };
    let multisample = vk::PipelineMultisampleStateCreateInfo::default()
        .rasterization_samples(target.samples)
        .alpha_to_coverage_enable(desc.alpha_to_coverage);
    let depth = vk::PipelineDepthStencilStateCreateInfo::default()
        .depth_test_enable(true)
        .depth_write_enable(desc.depth == Depth::TestAndWrite)
        .depth_compare_op(compare(
            target.depth_direction,
            match desc.depth {
                Depth::TestAndWrite => vk::CompareOp::LESS,
                Depth::BehindEverything => vk::CompareOp::LESS_OR_EQUAL,
                Depth::SameSurface => vk::CompareOp::EQUAL,
            },
        ));
    let blend_attachments = [vk::PipelineColorBlendAttachmentState::default().color_write_mask(write_mask)];
    let has_color = target.color != vk::Format::UNDEFINED;
    let blend_attachments = if has_color { &blend_attachments[..] } else { &[] };
    let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(blend_attachments);
    let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
    let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
    let color_formats = [target.color];
    let color_formats = if has_color { &color_formats[..] } else { &[] };
    let mut rendering = vk::PipelineRenderingCreateInfo::default()
        .color_attachment_formats(color_formats)
        .depth_attachment_format(target.depth);
    let mut info = vk::GraphicsPipelineCreateInfo::default()
        .stages(&stage_infos)
        .vertex_input_state(&vertex_input)
        .input_assembly_state(&assembly)
        .viewport_state(&viewport)
        .rasterization_state(&raster)
        .multisample_state(&multisample)
        .depth_stencil_state(&depth)
        .color_blend_state(&blend)
        .dynamic_state(&dynamic)
        .layout(layout)
        .push_next(&mut rendering);
    if desc.tessellated {
        info = info.tessellation_state(&tessellation);
    }
    let result = unsafe { d.create_graphics_pipelines(vk::PipelineCache::null(), &[info], None) };
    for module in modules {
        unsafe { d.destroy_shader_module(module, None) };
    }
    result
        .map(|p| p[0])
        .map_err(|(_, e)| vk_check("creating a graphics pipeline")(e))
}
