//! The compute passes on wgpu's Vulkan backend handed over as the SPIR-V the Vulkan renderer
//! runs (`PASSTHROUGH_SHADERS`): naga's, written from the same composed WGSL with its overrides
//! set, without WebGPU's runtime checks, each float-to-integer conversion reading its value
//! rather than the clamp naga writes before it (`sward_core::wgsl::spirv::unclamped_conversions`).
//! wgpu's own translation always clamps, and the splat walks convert at every cell they write:
//! on the H100 the clamps made the instanced grass's generating at 2^26 candidates 7.09 ms
//! against 6.38 without. A module passed through tells wgpu nothing of what it binds, so its
//! group is laid out here from naga's reflection, each binding numbered as wgpu's Vulkan backend
//! numbers a group's: at its rank. A pass whose group holds a kind of binding not laid out here
//! is left to wgpu's translation.

use std::num::NonZeroU64;

use naga::back::spv;
use naga::valid::{Capabilities, ValidationFlags, Validator};

use crate::shaders::{PipelineSource, ShaderModules};
use crate::{catch_errors, PortableError};

/// Whether `device` takes the compute passes of `modules` as SPIR-V: wgpu's Vulkan backend
/// with passthrough shaders, the passes without WebGPU's checks (with them, wgpu's own
/// translation adds them).
pub(crate) fn passes_through(device: &wgpu::Device, modules: &ShaderModules) -> bool {
    !modules.checked()
        && device.features().contains(wgpu::Features::PASSTHROUGH_SHADERS)
        && device.adapter_info().backend == wgpu::Backend::Vulkan
}

/// The compute pipeline of `source` (its composed WGSL `text`) on `device`, its overrides
/// `values` ((id, value): the others at their defaults) set, as SPIR-V passed through; None
/// where its group holds a binding this does not lay out.
pub(crate) fn compute_pipeline(
    device: &wgpu::Device,
    source: &PipelineSource,
    text: &str,
    values: &[(u32, u32)],
) -> Option<Result<wgpu::ComputePipeline, PortableError>> {
    let failed = |message: String| PortableError::Shader {
        pipeline: source.name,
        message,
    };
    let (module, info) = match resolved_module(text, source.entry, values) {
        Ok(resolved) => resolved,
        Err(message) => return Some(Err(failed(message))),
    };
    let at = module.entry_points.iter().position(|e| e.name == source.entry)?;
    let entries = group_entries(&module, info.get_entry_point(at))?;
    let workgroup = module.entry_points[at].workgroup_size;
    let words = match spirv(&module, &info, source.entry, &entries) {
        Ok(words) => words,
        Err(message) => return Some(Err(failed(message))),
    };
    Some(catch_errors(device, source.name, || {
        let desc = wgpu::ShaderModuleDescriptorPassthrough {
            label: Some(source.name),
            entry_points: vec![wgpu::PassthroughShaderEntryPoint {
                name: source.entry.into(),
                workgroup_size: (workgroup[0], workgroup[1], workgroup[2]),
            }]
            .into(),
            spirv: Some(words.into()),
            ..Default::default()
        };
        // SAFETY: naga wrote and validated the module from the core's WGSL, which the Vulkan
        // renderer runs as this same SPIR-V: its indices stay within the buffers it binds, its
        // loops end and every value it converts to an integer is in the integer's range. The
        // only change is the conversions reading their values, not naga's clamps.
        let module = unsafe { device.create_shader_module_passthrough(desc) };
        let group = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(source.name),
            entries: &entries,
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(source.name),
            bind_group_layouts: &[Some(&group)],
            immediate_size: 0,
        });
        device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(source.name),
            layout: Some(&layout),
            module: &module,
            entry_point: Some(source.entry),
            compilation_options: Default::default(),
            cache: None,
        })
    }))
}

/// WGSL `text` parsed and validated, its overrides `values` set for compute entry point
/// `entry`.
fn resolved_module(
    text: &str,
    entry: &str,
    values: &[(u32, u32)],
) -> Result<(naga::Module, naga::valid::ModuleInfo), String> {
    let module = naga::front::wgsl::parse_str(text).map_err(|e| e.emit_to_string(text))?;
    let info = Validator::new(ValidationFlags::all(), Capabilities::all())
        .validate(&module)
        .map_err(|e| e.emit_to_string(text))?;
    let mut constants = naga::back::PipelineConstants::default();
    for (_, o) in module.overrides.iter() {
        if let Some((_, value)) = values.iter().find(|(id, _)| o.id == Some(*id as u16)) {
            constants.insert(o.id.unwrap_or_default().to_string(), f64::from(*value));
        }
    }
    let stage = Some((naga::ShaderStage::Compute, entry));
    let (module, _) = naga::back::pipeline_constants::process_overrides(&module, &info, stage, &constants)
        .map_err(|e| format!("{entry}: {e}"))?;
    // Validated again as it now is (its overrides constants): what the writer reads.
    let module = module.into_owned();
    let info = Validator::new(ValidationFlags::all(), Capabilities::all())
        .validate(&module)
        .map_err(|e| format!("{entry}: {e}"))?;
    Ok((module, info))
}

/// The group (0) the entry point of `used` binds, laid out as wgpu would derive it, in binding
/// order; None where it binds outside group 0 or a kind not laid out here.
fn group_entries(module: &naga::Module, used: &naga::valid::FunctionInfo) -> Option<Vec<wgpu::BindGroupLayoutEntry>> {
    let globals = module
        .global_variables
        .iter()
        .filter(|(handle, _)| !used[*handle].is_empty());
    let bound: Vec<(&naga::GlobalVariable, naga::ResourceBinding)> =
        globals.filter_map(|(_, g)| g.binding.map(|b| (g, b))).collect();
    // A float texture is filterable where the pass samples with a filtering sampler.
    let filters = bound
        .iter()
        .any(|(g, _)| matches!(module.types[g.ty].inner, naga::TypeInner::Sampler { comparison: false }));
    let mut entries = Vec::new();
    for (global, at) in bound {
        if at.group != 0 {
            return None;
        }
        entries.push(wgpu::BindGroupLayoutEntry {
            binding: at.binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: binding_type(module, global, filters)?,
            count: None,
        });
    }
    entries.sort_by_key(|e| e.binding);
    Some(entries)
}

/// What `global` binds, as wgpu derives it from a shader; None for a kind not laid out here.
fn binding_type(module: &naga::Module, global: &naga::GlobalVariable, filters: bool) -> Option<wgpu::BindingType> {
    let buffer = |ty| wgpu::BindingType::Buffer {
        ty,
        has_dynamic_offset: false,
        min_binding_size: None,
    };
    match global.space {
        naga::AddressSpace::Uniform => {
            let size = module.types[global.ty].inner.size(module.to_ctx());
            return Some(wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: NonZeroU64::new(u64::from(size)),
            });
        }
        naga::AddressSpace::Storage { access } => {
            let read_only = !access.contains(naga::StorageAccess::STORE);
            return Some(buffer(wgpu::BufferBindingType::Storage { read_only }));
        }
        naga::AddressSpace::Handle => {}
        _ => return None,
    }
    match module.types[global.ty].inner {
        naga::TypeInner::Sampler { comparison: true } => {
            Some(wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison))
        }
        naga::TypeInner::Sampler { comparison: false } => {
            Some(wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering))
        }
        naga::TypeInner::Image { dim, arrayed, class } => image_type(view_dimension(dim, arrayed)?, class, filters),
        _ => None,
    }
}

/// A texture's binding of `class` seen as `dimension`.
fn image_type(
    view_dimension: wgpu::TextureViewDimension,
    class: naga::ImageClass,
    filters: bool,
) -> Option<wgpu::BindingType> {
    match class {
        naga::ImageClass::Sampled { kind, multi } => {
            let sample_type = match kind {
                naga::ScalarKind::Float => wgpu::TextureSampleType::Float {
                    filterable: filters && !multi,
                },
                naga::ScalarKind::Sint => wgpu::TextureSampleType::Sint,
                naga::ScalarKind::Uint => wgpu::TextureSampleType::Uint,
                _ => return None,
            };
            Some(wgpu::BindingType::Texture {
                sample_type,
                view_dimension,
                multisampled: multi,
            })
        }
        naga::ImageClass::Depth { multi } => Some(wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Depth,
            view_dimension,
            multisampled: multi,
        }),
        naga::ImageClass::Storage { format, access } => {
            let access = match (
                access.contains(naga::StorageAccess::LOAD),
                access.contains(naga::StorageAccess::STORE),
            ) {
                (true, true) => wgpu::StorageTextureAccess::ReadWrite,
                (true, false) => wgpu::StorageTextureAccess::ReadOnly,
                _ => wgpu::StorageTextureAccess::WriteOnly,
            };
            Some(wgpu::BindingType::StorageTexture {
                access,
                format: storage_format(format)?,
                view_dimension,
            })
        }
        _ => None,
    }
}

/// A texture view's dimension as naga's image type gives it.
fn view_dimension(dim: naga::ImageDimension, arrayed: bool) -> Option<wgpu::TextureViewDimension> {
    use wgpu::TextureViewDimension as D;
    Some(match (dim, arrayed) {
        (naga::ImageDimension::D1, false) => D::D1,
        (naga::ImageDimension::D2, false) => D::D2,
        (naga::ImageDimension::D2, true) => D::D2Array,
        (naga::ImageDimension::D3, false) => D::D3,
        (naga::ImageDimension::Cube, false) => D::Cube,
        (naga::ImageDimension::Cube, true) => D::CubeArray,
        _ => return None,
    })
}

/// The texture format of a storage texture the core's passes declare.
fn storage_format(format: naga::StorageFormat) -> Option<wgpu::TextureFormat> {
    use naga::StorageFormat as S;
    Some(match format {
        S::R32Float => wgpu::TextureFormat::R32Float,
        S::R32Uint => wgpu::TextureFormat::R32Uint,
        S::R32Sint => wgpu::TextureFormat::R32Sint,
        S::Rgba8Unorm => wgpu::TextureFormat::Rgba8Unorm,
        S::Rgba16Float => wgpu::TextureFormat::Rgba16Float,
        S::Rgba32Float => wgpu::TextureFormat::Rgba32Float,
        _ => return None,
    })
}

/// The SPIR-V of compute entry point `entry` of `module`, its group's bindings (`entries`, in
/// binding order) renumbered by rank, its conversions unclamped.
fn spirv(
    module: &naga::Module,
    info: &naga::valid::ModuleInfo,
    entry: &str,
    entries: &[wgpu::BindGroupLayoutEntry],
) -> Result<Vec<u32>, String> {
    let binding_map = (0..)
        .zip(entries)
        .map(|(rank, e)| {
            let at = naga::ResourceBinding {
                group: 0,
                binding: e.binding,
            };
            let info = spv::BindingInfo {
                descriptor_set: 0,
                binding: rank,
                binding_array_size: None,
            };
            (at, info)
        })
        .collect();
    let options = spv::Options {
        // What every Vulkan 1.1 device reads (wgpu's own writes up to its device's version).
        lang_version: (1, 3),
        flags: spv::WriterFlags::empty(),
        binding_map,
        fake_missing_bindings: false,
        // No bound on an index (naga's default policies) or a loop, no workgroup memory zeroed.
        bounds_check_policies: naga::proc::BoundsCheckPolicies::default(),
        zero_initialize_workgroup_memory: spv::ZeroInitializeWorkgroupMemoryMode::None,
        force_loop_bounding: false,
        ..spv::Options::default()
    };
    let pipeline = spv::PipelineOptions {
        shader_stage: naga::ShaderStage::Compute,
        entry_point: entry.to_string(),
    };
    let words = spv::write_vec(module, info, &options, Some(&pipeline)).map_err(|e| format!("{entry}: {e}"))?;
    Ok(sward_core::wgsl::spirv::unclamped_conversions(words))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pass binding one of each kind the core's passes bind, and one it leaves unused.
    const BINDS: &str = "
        struct Frame { size: vec4<f32> }
        @group(0) @binding(3) var<uniform> frame: Frame;
        @group(0) @binding(0) var<storage, read> blades: array<u32>;
        @group(0) @binding(7) var<storage, read_write> lists: array<atomic<u32>>;
        @group(0) @binding(9) var pyramid: texture_2d<f32>;
        @group(0) @binding(12) var levels: texture_storage_2d<r32float, write>;
        @group(0) @binding(5) var<storage, read> unused: array<u32>;
        @id(0) override LANES: u32 = 64u;
        @compute @workgroup_size(LANES)
        fn pass_of(@builtin(global_invocation_id) id: vec3<u32>) {
            let depth = textureLoad(pyramid, vec2<u32>(id.xy), 0).r;
            textureStore(levels, vec2<u32>(id.xy), vec4<f32>(depth * frame.size.x));
            atomicAdd(&lists[blades[id.x]], 1u);
        }";

    #[test]
    fn a_pass_group_is_laid_out_as_wgpu_derives_it_in_binding_order() {
        let (module, info) = resolved_module(BINDS, "pass_of", &[]).unwrap();
        let entries = group_entries(&module, info.get_entry_point(0)).unwrap();
        let bindings: Vec<u32> = entries.iter().map(|e| e.binding).collect();
        assert_eq!(bindings, [0, 3, 7, 9, 12], "the used bindings, in order");
        let storage = |read_only| wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        };
        assert_eq!(entries[0].ty, storage(true));
        assert_eq!(entries[2].ty, storage(false));
        assert!(matches!(
            entries[1].ty,
            wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                min_binding_size: Some(size),
                ..
            } if size.get() == 16
        ));
        // No sampler in the pass: its float texture is read unfiltered.
        assert_eq!(
            entries[3].ty,
            wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            }
        );
        assert_eq!(
            entries[4].ty,
            wgpu::BindingType::StorageTexture {
                access: wgpu::StorageTextureAccess::WriteOnly,
                format: wgpu::TextureFormat::R32Float,
                view_dimension: wgpu::TextureViewDimension::D2,
            }
        );
    }

    #[test]
    fn the_spirv_binds_each_binding_at_its_rank_with_its_overrides_set() {
        let (module, info) = resolved_module(BINDS, "pass_of", &[(0, 128)]).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(module.entry_points[0].workgroup_size, [128, 1, 1], "LANES set");
        let entries = group_entries(&module, info.get_entry_point(0)).unwrap();
        let words = spirv(&module, &info, "pass_of", &entries).unwrap();
        // OpDecorate id Binding n: the bindings written are the ranks 0..5.
        let mut ranks: Vec<u32> = sward_core::wgsl::spirv::instructions_of(&words)
            .iter()
            .filter(|i| i[0] & 0xffff == sward_core::wgsl::spirv::OP_DECORATE && i.len() == 4 && i[2] == 33)
            .map(|i| i[3])
            .collect();
        ranks.sort_unstable();
        assert_eq!(ranks, [0, 1, 2, 3, 4]);
    }
}
