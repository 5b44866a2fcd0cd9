//! The portable renderer: sward's grass through wgpu's safe API alone, in WGSL, on any backend
//! wgpu has with compute shaders and storage buffers (Vulkan, Metal, DX12, GL, a browser's
//! WebGPU), within WebGPU's default limits. Its passes read the frame's uniforms as sward-core
//! packs them for the Vulkan renderer (`FrameUniforms::pack`, from the frame's description and
//! plan), so both renderers run one frame from one set of decisions.
//!
//! It simulates the Bezier field (SPEC §3: recovery, gravity, wind, validation, sphere
//! collisions with a decaying strength, the trample map's trails and mown grass), culls it
//! (orientation, frustum, distance, its tiles, occlusion against a depth pyramid that folds in
//! the caller's depth where it gives it) into visible lists by distance bucket with a draw
//! command each, and draws the visible blades as triangle strips with sward's shading — held to
//! sward-core's CPU reference and the Vulkan renderer's pictures by tests. It streams the field
//! in a window of tiles, and generates the rest of the level-of-detail chain each frame
//! (`passes/generated.rs`): the instanced grass listed at four levels of detail and drawn as
//! strips, the billboards beyond it — the lists the Vulkan renderer makes where it splats
//! nothing. Its passes are one module each (`passes/`), as the Vulkan renderer's.

mod adapter;
mod bind;
mod camera;
mod field;
mod headless;
#[cfg(feature = "blocking")]
mod open;
mod passes;
#[cfg(not(target_arch = "wasm32"))]
mod passthrough;
mod renderer;
mod shaders;

pub use adapter::{adapter_sentence, beyond_webgpu_defaults, portable_features, portable_limits};
pub(crate) use bind::{BindGroups, Bindable, Bound, Reading, FRAME};
pub use camera::sward_projection;
pub use field::{CullLists, PortableField, DRAWN_BUCKETS_OFFSET};
pub use headless::{PortableHeadless, PORTABLE_COLOR};
#[cfg(feature = "blocking")]
pub use open::{describe_adapter, open_device, open_device_with};
pub use passes::draw::{PortableTarget, PortableViews};
pub use passes::generated::GeneratedDraws;
pub use passes::splats::{SPLAT_FEATURES, SPLAT_STORAGE_BUFFERS};
pub use renderer::{
    engine_splat_cells, supports, CallerDepth, FieldView, PortablePasses, PortableRenderer, STORAGE_BUFFERS_PER_STAGE,
};
pub use shaders::{frame_blocks_read, vertex_only, PIPELINES};
pub use sward_core::camera::DepthDirection;
pub use sward_core::wgsl::{
    engine_bindings, engine_library, library, PipelineSource, ShaderModules, MODULES, STREAM_SOURCES, TRAMPLE_SOURCE,
};

/// What went wrong in the portable renderer: one sentence each.
#[derive(Debug, thiserror::Error)]
pub enum PortableError {
    /// The adapter cannot run compute shaders (WebGL2, GL ES below 3.1).
    #[error("this {0} adapter has no compute shaders, which sward's grass is simulated and culled with; it needs Vulkan, Metal, DX12, GL ES 3.1 or WebGPU")]
    NoCompute(String),
    /// The adapter cannot read storage buffers in vertex shaders (WebGL2, some GL ES drivers).
    #[error("this {0} adapter cannot read storage buffers in vertex shaders, which sward's blades are drawn from; it needs Vulkan, Metal, DX12, GL 4.3 or WebGPU")]
    NoVertexStorage(String),
    /// The device binds fewer storage buffers in a shader stage than the passes do.
    #[error(
        "this {adapter} device binds {has} storage buffers in a shader stage, and sward's grass passes bind {needs}"
    )]
    FewStorageBuffers {
        /// The adapter.
        adapter: String,
        /// Storage buffers a stage may bind.
        has: u32,
        /// Storage buffers the passes bind.
        needs: u32,
    },
    /// The field does not fit the device's storage buffers.
    #[error("a field of {blades} blades needs {bytes} bytes of blade storage, more than this device binds at once ({limit} bytes); at most {fits} blades fit")]
    FieldTooLarge {
        /// Blades asked for.
        blades: usize,
        /// Bytes they need.
        bytes: u64,
        /// The device's largest storage binding.
        limit: u64,
        /// Blades that fit.
        fits: u64,
    },
    /// A pipeline's WGSL did not compile on this device.
    #[error("the portable {pipeline} shader does not compile on this device: {message}")]
    Shader {
        /// The pipeline.
        pipeline: &'static str,
        /// What the device said.
        message: String,
    },
    /// No adapter of the backends asked for.
    #[error("wgpu finds no {0} adapter on this machine ({1})")]
    NoAdapter(String, String),
    /// The adapter refused a device.
    #[error("{0} gives no device with WebGPU's default limits ({1})")]
    NoDevice(String, String),
    /// An offscreen target of a size the device cannot make.
    #[error("an image of {width}×{height} pixels does not fit this device: each side must be 1 to {largest}")]
    TargetSize {
        /// Pixels across.
        width: u32,
        /// Pixels down.
        height: u32,
        /// The device's largest texture side.
        largest: u32,
    },
    /// The device reported a fault while drawing: a validation error, or the device was lost.
    #[error("the portable renderer's device reported: {0}")]
    Device(String),
    /// The caller's depth cannot be read by this backend's compute shaders.
    #[error("wgpu's {0} backend reads no depth texture in a compute shader, so the caller's depth is not folded into the depth pyramid there; the grass is culled by sward's own occluders (the ground, the colliders, the nearest blades)")]
    CallerDepthUnread(String),
    /// A frame asked for before a field was uploaded.
    #[error("there is no field to draw: upload one first")]
    NoField,
    /// The GPU's buffers could not be read back.
    #[error("reading the field back from the GPU failed: {0}")]
    Readback(String),
}

/// What `make` makes on `device`, or the validation error it raised (a shader that does not
/// compile, a pipeline the device refuses) in one sentence naming `pipeline` — caught in an
/// error scope rather than left to the device's uncaptured-error handler, which panics.
pub(crate) fn catch_errors<T>(
    device: &wgpu::Device,
    pipeline: &'static str,
    make: impl FnOnce() -> T,
) -> Result<T, PortableError> {
    // A shader a backend's language cannot express is an internal error, not a validation one.
    let internal = device.push_error_scope(wgpu::ErrorFilter::Internal);
    let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let made = make();
    let invalid = ready(validation.pop()).flatten();
    let inexpressible = ready(internal.pop()).flatten();
    match invalid.or(inexpressible) {
        None => Ok(made),
        Some(error) => Err(PortableError::Shader {
            pipeline,
            message: one_line(&error.to_string()),
        }),
    }
}

/// A message of several lines as one.
fn one_line(message: &str) -> String {
    message.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// `source` as a shader module's description: parsed here and handed to wgpu as naga's module,
/// as Bevy hands over its shaders. Made from WGSL text, a module carries that text (under
/// wgpu's debug flag, which sward's validation messenger on its Vulkan device needs) as SPIR-V
/// source of a language, WGSL, that some validation layers do not know (Debian 12's refuses
/// every such module).
#[cfg(all(feature = "naga-ir", not(target_arch = "wasm32")))]
pub(crate) fn shader_module(
    source: &shaders::PipelineSource,
    modules: &shaders::ShaderModules,
) -> Result<wgpu::ShaderModuleDescriptor<'static>, PortableError> {
    let text = modules.text(source)?;
    let module = wgpu::naga::front::wgsl::parse_str(&text).map_err(|e| PortableError::Shader {
        pipeline: source.name,
        message: one_line(&e.emit_to_string(&text)),
    })?;
    Ok(wgpu::ShaderModuleDescriptor {
        label: Some(source.name),
        source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(module)),
    })
}

/// `source` as a shader module's description: the WGSL text, as Bevy hands over its own shaders
/// (the device reports a shader error through the error scope), and in a browser the text its
/// WebGPU compiles.
#[cfg(any(not(feature = "naga-ir"), target_arch = "wasm32"))]
pub(crate) fn shader_module(
    source: &shaders::PipelineSource,
    modules: &shaders::ShaderModules,
) -> Result<wgpu::ShaderModuleDescriptor<'static>, PortableError> {
    Ok(wgpu::ShaderModuleDescriptor {
        label: Some(source.name),
        source: wgpu::ShaderSource::Wgsl(shader_text(source, modules)?.into()),
    })
}

/// The device's module of `desc`, compiled with WebGPU's runtime checks only where `modules`
/// ask for them ([`ShaderModules::with_checks`]): the bounds on every index and loop cost the
/// simulation and the cull up to twice their time. Integer division keeps its guard against a
/// zero divisor, as the Vulkan renderer's passes do, so a pass divides alike on both.
pub(crate) fn device_module(
    device: &wgpu::Device,
    desc: wgpu::ShaderModuleDescriptor<'_>,
    modules: &shaders::ShaderModules,
) -> wgpu::ShaderModule {
    if modules.checked() {
        return device.create_shader_module(desc);
    }
    let checks = wgpu::ShaderRuntimeChecks {
        int_div_checks: true,
        ..wgpu::ShaderRuntimeChecks::unchecked()
    };
    // SAFETY: the modules are the core's passes (or a variant of them the user measures): each
    // keeps its indices within the buffers it is bound to and every loop it runs ends, as the
    // Vulkan renderer, which runs the same WGSL without the checks, relies on.
    unsafe { device.create_shader_module_trusted(desc, checks) }
}

/// The WGSL text handed over: a browser's compiler needs `enable subgroups;`, naga refuses it.
#[cfg(any(not(feature = "naga-ir"), target_arch = "wasm32"))]
fn shader_text(source: &shaders::PipelineSource, modules: &shaders::ShaderModules) -> Result<String, PortableError> {
    Ok(match cfg!(target_arch = "wasm32") {
        true => modules.browser_text(source)?,
        false => modules.text(source)?,
    })
}

/// A compute pipeline from `source` composed of `modules`, its compile errors said in one
/// sentence.
pub(crate) fn compute_pipeline(
    device: &wgpu::Device,
    source: &shaders::PipelineSource,
    modules: &shaders::ShaderModules,
) -> Result<Reading<wgpu::ComputePipeline>, PortableError> {
    compute_pipeline_with(device, source, modules, &[])
}

/// [`compute_pipeline`] with its overrides set: `overrides` by id (`declared::constants`), those
/// the composed module declares (a pass composed without a feature may lack one).
pub(crate) fn compute_pipeline_with(
    device: &wgpu::Device,
    source: &shaders::PipelineSource,
    modules: &shaders::ShaderModules,
    overrides: &[(u32, u32)],
) -> Result<Reading<wgpu::ComputePipeline>, PortableError> {
    let text = modules.text(source)?;
    let declared = bind::overrides_declared(&text)?;
    let keys: Vec<(String, f64)> = overrides
        .iter()
        .filter(|(id, _)| declared.contains(id))
        .map(|&(id, value)| (id.to_string(), f64::from(value)))
        .collect();
    let constants: Vec<(&str, f64)> = keys.iter().map(|(k, v)| (k.as_str(), *v)).collect();
    #[cfg(not(target_arch = "wasm32"))]
    if passthrough::passes_through(device, modules) {
        if let Some(pipeline) = passthrough::compute_pipeline(device, source, &text, overrides) {
            return Reading::new(pipeline?, &text, &[source.entry]);
        }
    }
    let module = shader_module(source, modules)?;
    let pipeline = catch_errors(device, source.name, || {
        let module = device_module(device, module, modules);
        device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(source.name),
            layout: None,
            module: &module,
            entry_point: Some(source.entry),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: &constants,
                // Every pass writes the workgroup memory it reads first.
                zero_initialize_workgroup_memory: modules.checked(),
            },
            cache: None,
        })
    })?;
    Reading::new(pipeline, &text, &[source.entry])
}

/// How many workgroups a dispatch runs: across and down, or as an earlier pass wrote them into
/// a buffer (at a byte offset).
#[derive(Clone, Copy)]
pub(crate) enum Groups<'a> {
    Direct([u32; 2]),
    Indirect(&'a wgpu::Buffer, u64),
}

/// One dispatch of a compute pass: the pipeline, what its group 0 binds, its workgroups.
pub(crate) type Dispatch<'a> = (&'a Reading<wgpu::ComputePipeline>, &'a [(u32, Bound<'a>)], Groups<'a>);

/// Record `dispatches` in order in one compute pass (wgpu orders each one's reads after the
/// writes before it), each pipeline's bind group made once (`groups`): one pass rather than one
/// each, since every pass is host work of the frame; no pass where there is nothing to dispatch.
pub(crate) fn dispatch(
    (device, groups): (&wgpu::Device, &BindGroups),
    encoder: &mut wgpu::CommandEncoder,
    dispatches: &[Dispatch],
) {
    if dispatches.is_empty() {
        return;
    }
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
    for &(pipeline, resources, workgroups) in dispatches {
        let bind = groups.of(device, Bindable::Compute(pipeline), resources);
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &bind, &[]);
        match workgroups {
            Groups::Direct([x, y]) => pass.dispatch_workgroups(x, y, 1),
            Groups::Indirect(buffer, offset) => pass.dispatch_workgroups_indirect(buffer, offset),
        }
    }
}

/// The value of a future that is ready when first polled, as wgpu's error scopes and
/// buffer mappings are on native backends once the device was polled; None where it is not.
pub(crate) fn ready<F: std::future::Future>(future: F) -> Option<F::Output> {
    let mut future = std::pin::pin!(future);
    let mut context = std::task::Context::from_waker(std::task::Waker::noop());
    match future.as_mut().poll(&mut context) {
        std::task::Poll::Ready(value) => Some(value),
        std::task::Poll::Pending => None,
    }
}
