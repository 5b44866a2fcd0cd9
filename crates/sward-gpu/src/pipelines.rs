//! How the frame's pipelines are made — the builder each pass uses for its own set (`field.rs`,
//! `routes.rs`, `ground.rs`, `occluders.rs`, `instanced.rs`, `splat.rs`; gathered into one by
//! `frame_pipelines.rs`, so the viewer's hot reload swaps them as one), the formats, and the one
//! descriptor layout they share: binding
//! 0 the frame uniforms, 1 blades, 2 collision strengths η, 3 visible indices, 4 draw commands, …
//! (see the constants below).

use std::sync::Arc;

use ash::vk;

use crate::context::Context;
use crate::error::{vk_check, Result};
use crate::shaders::ShaderSet;

/// The depth attachments' format.
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;
/// The depth pyramid's texels: one depth each.
pub const HIZ_FORMAT: vk::Format = vk::Format::R32_SFLOAT;

/// How the compute passes are built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ComputeOptions {
    /// Invocations per workgroup (a multiple of the subgroup size; 64–1024).
    pub workgroup: u32,
    /// Aggregate the visible-list atomics per subgroup (where the device has subgroup ballot).
    pub subgroup_atomics: bool,
    /// Cull copies whole 64-byte blades for the draw instead of 4-byte indices (only to measure
    /// what the index list saves; SPEC §5.4).
    pub copy_blades: bool,
}

impl Default for ComputeOptions {
    fn default() -> Self {
        ComputeOptions {
            workgroup: 256,
            subgroup_atomics: true,
            copy_blades: false,
        }
    }
}

/// What the graphics pipelines render into.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TargetFormat {
    /// The colour attachment's format (`UNDEFINED`: depth only).
    pub color: vk::Format,
    /// The depth attachment's format: any with depth, 0 at the near plane and 1 at the far
    /// ([`DEPTH_FORMAT`] for sward's own targets). A stencil part is left alone.
    pub depth: vk::Format,
    /// Samples per pixel.
    pub samples: vk::SampleCountFlags,
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
    /// A compute pipeline of shader file `name` (specialisation as in [`compute`]).
    pub fn compute(&self, name: &str) -> Result<Pipeline> {
        self.own(compute(self.ctx, self.layout, self.shaders.get(name), self.options)?)
    }

    /// [`Builder::compute`] with specialisation constant 4 set: the variant of a shader that
    /// has two (`BILLBOARDS` of instanced.comp, `SECOND_PASS` of the compute rasterizer's).
    pub fn compute_variant(&self, name: &str) -> Result<Pipeline> {
        self.compute_with(name, [true, false])
    }

    /// [`Builder::compute`] with specialisation constants 4 and 5 (a shader's variants: the
    /// billboards' grid and the placing pass of instanced.comp) as given.
    pub fn compute_with(&self, name: &str, variant: [bool; 2]) -> Result<Pipeline> {
        self.compute_constants(name, [variant[0] as u32, variant[1] as u32, 0])
    }

    /// [`Builder::compute`] with specialisation constants 4, 5 and 6 as given (constant 6:
    /// which chunk of its list instanced_raster.comp rasterizes).
    pub fn compute_constants(&self, name: &str, constants: [u32; 3]) -> Result<Pipeline> {
        self.own(compute_variant(
            self.ctx,
            self.layout,
            self.shaders.get(name),
            self.options,
            constants,
        )?)
    }

    /// A graphics pipeline of `stages` (shader file names) into the frame's target.
    pub fn graphics(&self, desc: &GraphicsDesc, stages: &[&str]) -> Result<Pipeline> {
        self.graphics_into(self.target, desc, stages)
    }

    /// A graphics pipeline of `stages` into another target (the occluder passes').
    pub fn graphics_into(&self, target: TargetFormat, desc: &GraphicsDesc, stages: &[&str]) -> Result<Pipeline> {
        let stages = self.shaders.stages(stages);
        self.own(graphics(self.ctx, self.layout, target, desc, &stages)?)
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

/// Storage buffers of the frame's set, bindings 1..=7: blades, η, visible, draws, culled copies,
/// ground vertices, active tiles (binding 0 is the frame's uniforms).
pub(crate) const STORAGE_BINDINGS: u32 = 7;
/// Sampled images of the frame's set, bindings 8 and 9: the depth pyramid and the sun's shadow map.
pub(crate) const IMAGE_BINDINGS: u32 = 2;
/// Storage buffers of the instanced field, bindings 10..=13: patches, visible blades, draws, and
/// the splat target's cells.
pub(crate) const INSTANCED_BINDINGS: u32 = 4;
/// The first binding of the instanced field.
pub(crate) const INSTANCED_FIRST: u32 = 1 + STORAGE_BINDINGS + IMAGE_BINDINGS;
/// The splat target's cells (`splat.rs`), the last of the instanced field's four bindings.
pub(crate) const SPLAT_BINDING: u32 = INSTANCED_FIRST + INSTANCED_BINDINGS - 1;
/// The billboards' grass texture (a combined image sampler), after the instanced field's buffers.
pub(crate) const GRASS_TEXTURE_BINDING: u32 = INSTANCED_FIRST + INSTANCED_BINDINGS;
/// The visible blades in draw order (a storage buffer), after the grass texture.
pub(crate) const ORDERED_BINDING: u32 = GRASS_TEXTURE_BINDING + 1;
/// The generated grass's counts per workgroup and level (a storage buffer, instanced.rs).
pub(crate) const GENERATED_COUNTS_BINDING: u32 = ORDERED_BINDING + 1;
/// The trample map's texels (a storage buffer, trample.rs).
pub(crate) const TRAMPLE_BINDING: u32 = GENERATED_COUNTS_BINDING + 1;
/// The caller's depth image, where it gives one for occlusion (a combined image sampler,
/// caller_depth.glsl), the last binding. Written only then: only the pass that folds it into
/// the depth pyramid reads it.
pub(crate) const CALLER_DEPTH_BINDING: u32 = TRAMPLE_BINDING + 1;

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
    let bindings: Vec<vk::DescriptorSetLayoutBinding> = (0..=CALLER_DEPTH_BINDING)
        .map(|binding| {
            let kind = match binding {
                0 => vk::DescriptorType::UNIFORM_BUFFER,
                GRASS_TEXTURE_BINDING | CALLER_DEPTH_BINDING => vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                ORDERED_BINDING | GENERATED_COUNTS_BINDING | TRAMPLE_BINDING => vk::DescriptorType::STORAGE_BUFFER,
                b if b <= STORAGE_BINDINGS || b >= INSTANCED_FIRST => vk::DescriptorType::STORAGE_BUFFER,
                _ => vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
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
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    let info = vk::ShaderModuleCreateInfo::default().code(&words);
    unsafe { d.create_shader_module(&info, None) }.map_err(vk_check("creating a shader module"))
}

/// A compute pipeline with the grass passes' specialisation constants: 0 = workgroup size,
/// 1 = subgroup-aggregated atomics (shaders without them ignore them).
pub(crate) fn compute(
    ctx: &Context,
    layout: vk::PipelineLayout,
    spirv: &[u8],
    options: ComputeOptions,
) -> Result<vk::Pipeline> {
    compute_variant(ctx, layout, spirv, options, [0; 3])
}

/// [`compute`] with specialisation constants 4, 5 and 6 (a shader's variants,
/// [`Builder::compute_constants`]) as given.
fn compute_variant(
    ctx: &Context,
    layout: vk::PipelineLayout,
    spirv: &[u8],
    options: ComputeOptions,
    variant: [u32; 3],
) -> Result<vk::Pipeline> {
    let d = &ctx.device;
    let module = shader_module(d, spirv)?;
    let entries = [
        vk::SpecializationMapEntry {
            constant_id: 0,
            offset: 0,
            size: 4,
        },
        vk::SpecializationMapEntry {
            constant_id: 1,
            offset: 4,
            size: 4,
        },
        COPY_BLADES_ENTRY,
        vk::SpecializationMapEntry {
            constant_id: 4,
            offset: 12,
            size: 4,
        },
        vk::SpecializationMapEntry {
            constant_id: 5,
            offset: 16,
            size: 4,
        },
        vk::SpecializationMapEntry {
            constant_id: 6,
            offset: 20,
            size: 4,
        },
    ];
    let use_subgroups = options.subgroup_atomics && ctx.info.subgroup_ballot;
    let data: Vec<u8> = [
        options.workgroup,
        use_subgroups as u32,
        options.copy_blades as u32,
        variant[0],
        variant[1],
        variant[2],
    ]
    .iter()
    .flat_map(|v| v.to_le_bytes())
    .collect();
    let specialization = vk::SpecializationInfo::default().map_entries(&entries).data(&data);
    let stage = vk::PipelineShaderStageCreateInfo::default()
        .stage(vk::ShaderStageFlags::COMPUTE)
        .module(module)
        .name(c"main")
        .specialization_info(&specialization);
    let info = [vk::ComputePipelineCreateInfo::default().stage(stage).layout(layout)];
    let result = unsafe { d.create_compute_pipelines(vk::PipelineCache::null(), &info, None) };
    unsafe { d.destroy_shader_module(module, None) };
    result
        .map(|p| p[0])
        .map_err(|(_, e)| vk_check("creating a compute pipeline")(e))
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

/// Specialisation constant 2 of every shader: `COPY_BLADES` (see [`ComputeOptions::copy_blades`]).
const COPY_BLADES_ENTRY: vk::SpecializationMapEntry = vk::SpecializationMapEntry {
    constant_id: 2,
    offset: 8,
    size: 4,
};

/// Whose eyes a pipeline draws through: specialisation constant 3 (`VIEW`) of the vertex stages.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum View {
    Camera = 0,
    /// The sun's orthographic view of the field, for the shadow map's field cascade
    /// (depth-biased against shadow acne).
    Sun = 1,
    /// The sun's view of the ball around the eye, for the shadow map's near cascade (biased too).
    SunNear = 2,
    /// The camera, drawing the nearest blades narrowed into the depth pyramid as occluders.
    Occluder = 3,
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

fn graphics(
    ctx: &Context,
    layout: vk::PipelineLayout,
    target: TargetFormat,
    desc: &GraphicsDesc,
    stages: &[(vk::ShaderStageFlags, &[u8])],
) -> Result<vk::Pipeline> {
    let d = &ctx.device;
    let modules = stages
        .iter()
        .map(|(_, spirv)| shader_module(d, spirv))
        .collect::<Result<Vec<_>>>()?;
    let entries = [
        vk::SpecializationMapEntry {
            constant_id: 2,
            offset: 0,
            size: 4,
        },
        vk::SpecializationMapEntry {
            constant_id: 3,
            offset: 4,
            size: 4,
        },
    ];
    let data: Vec<u8> = [desc.copy_blades as u32, desc.view as u32]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let specialization = vk::SpecializationInfo::default().map_entries(&entries).data(&data);
    let stage_infos: Vec<_> = stages
        .iter()
        .zip(&modules)
        .map(|((stage, _), module)| {
            vk::PipelineShaderStageCreateInfo::default()
                .stage(*stage)
                .module(*module)
                .name(c"main")
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
        // not shadow themselves (acne) where the sun grazes them.
        .depth_bias_enable(desc.view != View::Camera)
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
        .depth_compare_op(match desc.depth {
            Depth::TestAndWrite => vk::CompareOp::LESS,
            Depth::BehindEverything => vk::CompareOp::LESS_OR_EQUAL,
            Depth::SameSurface => vk::CompareOp::EQUAL,
        });
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
