//! The splat cells resolved into the frame on the portable renderer (splat_resolve.wesl): a
//! screen-covering triangle whose fragments take their pixel's cells. At the pixel's rate,
//! covering with its sample mask the samples whose cells hold a blade (`resolve_splats`, the
//! Vulkan renderer's resolve), where the backend can be handed that: Metal and DX12 through
//! wgpu's own translation; Vulkan as naga's SPIR-V mended (`sward_core::wgsl::spirv`: wgpu's
//! own writes the mask as a word where Vulkan asks for an array, gfx-rs/wgpu#7311) and passed
//! through (`PASSTHROUGH_SHADERS`). Elsewhere a sample at a time (`resolve_splat_samples`): the
//! same picture for four times the fragments on a 4× target.

use sward_core::wgsl::splatting::{SPLAT_RESOLVE_MASKED, SPLAT_RESOLVE_SAMPLES};

use super::draw::{render_pipeline, Attachments};
use crate::shaders::ShaderModules;
use crate::{PortableError, Reading};

/// The resolve's pipeline on `device` (of `backend`), for attachments like `target`.
pub(crate) fn resolve_pipeline(
    device: &wgpu::Device,
    backend: wgpu::Backend,
    target: &Attachments,
    modules: &ShaderModules,
) -> Result<Reading<wgpu::RenderPipeline>, PortableError> {
    let list = wgpu::PrimitiveTopology::TriangleList;
    match backend {
        wgpu::Backend::Metal | wgpu::Backend::Dx12 => {
            render_pipeline(device, (&SPLAT_RESOLVE_MASKED, modules), target, list, true)
        }
        #[cfg(not(target_arch = "wasm32"))]
        wgpu::Backend::Vulkan if device.features().contains(wgpu::Features::PASSTHROUGH_SHADERS) => {
            native::passed_through(device, target, modules)
        }
        _ => render_pipeline(device, (&SPLAT_RESOLVE_SAMPLES, modules), target, list, true),
    }
}

/// What only a native backend builds: the resolve as SPIR-V passed through.
#[cfg(not(target_arch = "wasm32"))]
mod native {
    use std::num::NonZeroU64;

    use sward_core::declared;
    use sward_core::wgsl::splatting::SPLAT_RESOLVE_MASKED;

    use super::super::draw::{draw_pipeline, Attachments, DrawStages};
    use crate::shaders::{PipelineSource, ShaderModules};
    use crate::{catch_errors, PortableError, Reading};

    /// The pixel-rate resolve as SPIR-V written by naga, its sample mask mended, passed to Vulkan
    /// as it is, with its group laid out here (a module passed through tells wgpu nothing of it):
    /// the frame's blocks it reads and the splat cells.
    pub(super) fn passed_through(
        device: &wgpu::Device,
        target: &Attachments,
        modules: &ShaderModules,
    ) -> Result<Reading<wgpu::RenderPipeline>, PortableError> {
        let source = &SPLAT_RESOLVE_MASKED;
        let text = modules.text(source)?;
        let fragment = source.fragment.unwrap_or(source.entry);
        let probe = Reading::new((), &text, &[source.entry, fragment])?;
        let mut bindings = probe.bindings_used().to_vec();
        bindings.sort_unstable();
        let vertex_words =
            spirv(&text, (source.entry, naga::ShaderStage::Vertex), &bindings).map_err(|m| failed(source, m))?;
        let fragment_words =
            spirv(&text, (fragment, naga::ShaderStage::Fragment), &bindings).map_err(|m| failed(source, m))?;
        let fragment_words = sward_core::wgsl::spirv::sample_masks_as_arrays(fragment_words);
        let pipeline = catch_errors(device, source.name, || {
            let module = |words: Vec<u32>, entry: &str| {
                let desc = wgpu::ShaderModuleDescriptorPassthrough {
                    label: Some(source.name),
                    entry_points: vec![wgpu::PassthroughShaderEntryPoint {
                        name: entry.to_string().into(),
                        workgroup_size: (1, 1, 1),
                    }]
                    .into(),
                    spirv: Some(words.into()),
                    ..Default::default()
                };
                // Safety: naga wrote and validated the module from the core's WGSL; the only change
                // is its sample mask made the array Vulkan asks for, which the validation layer
                // checks in the tests.
                unsafe { device.create_shader_module_passthrough(desc) }
            };
            let vertex = module(vertex_words, source.entry);
            let fragment_module = module(fragment_words, fragment);
            let group = group_layout(device, &bindings);
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(source.name),
                bind_group_layouts: &[Some(&group)],
                immediate_size: 0,
            });
            let stages = DrawStages {
                vertex: (&vertex, source.entry),
                fragment: Some((&fragment_module, fragment)),
                layout: Some(&layout),
            };
            let list = wgpu::PrimitiveTopology::TriangleList;
            draw_pipeline(device, source.name, stages, target, (list, true, false))
        })?;
        Reading::new(pipeline, &text, &[source.entry, fragment])
    }

    /// `source`'s SPIR-V could not be written, in one sentence.
    fn failed(source: &PipelineSource, message: String) -> PortableError {
        PortableError::Shader {
            pipeline: source.name,
            message,
        }
    }

    /// The SPIR-V (1.0, wgpu's) of `entry` of `stage` in WGSL `text`, its overrides at their
    /// defaults, with wgpu's own writer options (a vertex stage's clip space turned into Vulkan's)
    /// and its group's `bindings` (in order) renumbered as wgpu's Vulkan backend lays out a group:
    /// each at its rank.
    fn spirv(text: &str, (entry, stage): (&str, naga::ShaderStage), bindings: &[u32]) -> Result<Vec<u32>, String> {
        use naga::valid::{Capabilities, ValidationFlags, Validator};
        let module = naga::front::wgsl::parse_str(text).map_err(|e| e.emit_to_string(text))?;
        let info = Validator::new(ValidationFlags::all(), Capabilities::all())
            .validate(&module)
            .map_err(|e| e.emit_to_string(text))?;
        let defaults = naga::back::PipelineConstants::default();
        let (module, info) =
            naga::back::pipeline_constants::process_overrides(&module, &info, Some((stage, entry)), &defaults)
                .map_err(|e| e.to_string())?;
        let pipeline = naga::back::spv::PipelineOptions {
            shader_stage: stage,
            entry_point: entry.to_string(),
        };
        let binding_map = (0..)
            .zip(bindings)
            .map(|(rank, &binding)| {
                let at = naga::ResourceBinding { group: 0, binding };
                let info = naga::back::spv::BindingInfo {
                    descriptor_set: 0,
                    binding: rank,
                    binding_array_size: None,
                };
                (at, info)
            })
            .collect();
        let options = naga::back::spv::Options {
            flags: naga::back::spv::WriterFlags::ADJUST_COORDINATE_SPACE
                | naga::back::spv::WriterFlags::CLAMP_FRAG_DEPTH,
            binding_map,
            fake_missing_bindings: false,
            ..Default::default()
        };
        naga::back::spv::write_vec(&module, &info, &options, Some(&pipeline)).map_err(|e| e.to_string())
    }

    /// The group the resolve binds: the frame's blocks among `bindings` as uniform buffers of their
    /// sizes, the rest (the splat cells) as read-only storage.
    fn group_layout(device: &wgpu::Device, bindings: &[u32]) -> wgpu::BindGroupLayout {
        let entries: Vec<wgpu::BindGroupLayoutEntry> = bindings
            .iter()
            .map(|&binding| {
                let block = declared::frame_blocks().find(|(b, ..)| *b == binding);
                let ty = match block {
                    Some((.., size)) => wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: NonZeroU64::new(size),
                    },
                    None => wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Storage { read_only: true },
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                };
                wgpu::BindGroupLayoutEntry {
                    binding,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty,
                    count: None,
                }
            })
            .collect();
        device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward splat resolve"),
            entries: &entries,
        })
    }
}
