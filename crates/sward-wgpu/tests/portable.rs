//! The portable renderer (`sward_wgpu::portable`): its WGSL against sward-core's layouts and
//! flags and translated for Metal and DX12; its simulation and its cull against the CPU
//! reference on wgpu's Vulkan backend (lavapipe on a machine without a GPU) and GL backend
//! (Mesa's llvmpipe through EGL), within WebGPU's default limits, with validation on.

#[path = "../../sward-gpu/tests/common/parity_cases.rs"]
mod parity_cases;
#[path = "../../sward-gpu/tests/common/repaint.rs"]
mod repaint;
#[path = "browser/runner.rs"]
mod runner;
#[path = "../../sward-gpu/tests/common/seams.rs"]
mod seams;
mod support;

use std::sync::Mutex;

use glam::Vec2;
use sward_core::commands::{bucket_range, distance_bucket, DISTANCE_BUCKETS};
use sward_core::cull::{cull_blade, cull_blade_loosened, CullVerdict};
use sward_core::gpu::{DrawCommand, FrameUniforms};
use sward_core::physics::simulate;
use sward_core::plan::{FrameDecisions, RendererCan};
use sward_core::rng::Pcg32;
use sward_core::wind::WindKind;
use sward_core::{Blade, FrameDesc, Scene};
use sward_wgpu::portable::{
    PortableError, PortableField, PortableHeadless, PortablePasses, PortableRenderer, ShaderModules, PIPELINES,
};
use wgpu::naga;

use parity_cases::{ill_conditioned, random_blades, random_camera, random_cull, random_scene, worst_error, TOLERANCE};
use runner::{chromium, run_page};

/// Blades: not a multiple of the workgroup (the `i < count` guard).
const BLADES: usize = 3001;
const STEPS: u32 = 240;
const STEPS_PER_FRAME: u32 = 24;

/// Every member of a WGSL struct `name` in `source`: its name and byte offset, and the size.
fn wgsl_layout(source: &str, name: &str) -> (Vec<(String, u32)>, u32) {
    let module = naga::front::wgsl::parse_str(source).unwrap_or_else(|e| panic!("{}", e.emit_to_string(source)));
    let inner = module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref() == Some(name))
        .map(|(_, t)| t.inner.clone())
        .unwrap_or_else(|| panic!("no struct {name}"));
    match inner {
        naga::TypeInner::Struct { members, span } => (
            members
                .iter()
                .map(|m| (m.name.clone().unwrap_or_default(), m.offset))
                .collect(),
            span,
        ),
        other => panic!("{name} is not a struct: {other:?}"),
    }
}

/// The members of `FrameUniforms` in order, with their offsets.
macro_rules! offsets {
    ($t:ty; $($field:ident),* $(,)?) => {
        vec![$((stringify!($field).to_string(), std::mem::offset_of!($t, $field) as u32)),*]
    };
}

/// Every member of `FrameUniforms` is in one of the WGSL's frame blocks, with the size it has in
/// Rust (each block's members back to back, in std140 and WGSL's uniform layout alike).
#[test]
fn the_wgsl_frame_blocks_are_sward_cores_frame_uniforms_member_for_member() {
    let source = sward_wgpu::portable::library("engine").expect("the engine library composes");
    let mut rust = offsets!(FrameUniforms;
        view_proj, inv_view_proj, sun_view_proj, sun_near_view_proj, camera_position, gravity,
        point_gravity, simulation, counts, cull, coarse_cull, modes, lod, blade_style, viewport,
        light_direction, light_color, root_color, tip_color, ground_color, sky_zenith, sky_horizon,
        shading_model, shading_extra, ground_extent, surface, instanced_grid, instanced_shape,
        instanced_motion, instanced_lod, instanced_lists, instanced_caps, instanced_meta,
        instanced_ground, instanced_ground_cells, billboard_grid, billboard_shape, billboard_motion,
        billboard_meta, routes, occlusion, patch_cull, patch_bounds, tiles, trample, mowing,
        trample_scale, billboard_far, instanced_raster, stream, stream_reach, origin, paint_area,
        paint_size, paint_noise, paint_tint_noise, paint_tint_color, species_meta, species,
        seed_heads, lamp_meta, lamps, frustum, winds, colliders, placed, placed_before);
    // Each member's size in Rust: to the next member, or the struct's end.
    rust.sort_by_key(|(_, at)| *at);
    let ends = rust
        .iter()
        .skip(1)
        .map(|(_, at)| *at)
        .chain([std::mem::size_of::<FrameUniforms>() as u32]);
    let rust_sizes: Vec<(String, u32)> = rust
        .iter()
        .zip(ends)
        .map(|((n, at), end)| (n.clone(), end - at))
        .collect();
    let mut wgsl_sizes = Vec::new();
    for block in &sward_core::declared::BLOCKS {
        let (members, span) = wgsl_layout(&source, block.ty);
        let ends = members.iter().skip(1).map(|(_, at)| *at).chain([span]);
        wgsl_sizes.extend(members.iter().zip(ends).map(|((n, at), end)| (n.clone(), end - at)));
    }
    wgsl_sizes.sort();
    let mut rust_sizes = rust_sizes;
    rust_sizes.sort();
    assert_eq!(
        wgsl_sizes, rust_sizes,
        "the WGSL's frame blocks and FrameUniforms differ"
    );
}

#[test]
fn the_wgsl_flags_and_counts_are_sward_cores() {
    use sward_core::flags::*;
    // The modules that declare them, each as a library: every declaration under its own name.
    let modules: Vec<naga::Module> = ["physics", "cull", "blade", "outline", "shading", "scenery", "buckets"]
        .into_iter()
        .map(|root| {
            let text = sward_wgpu::portable::library(root).unwrap_or_else(|e| panic!("{e}"));
            naga::front::wgsl::parse_str(&text).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&text)))
        })
        .collect();
    let value = |name: &str| -> u32 {
        let (module, c) = modules
            .iter()
            .find_map(|m| {
                m.constants
                    .iter()
                    .find(|(_, c)| c.name.as_deref() == Some(name))
                    .map(|(_, c)| (m, c))
            })
            .unwrap_or_else(|| panic!("the portable WGSL has no {name}"));
        match module.global_expressions[c.init] {
            naga::Expression::Literal(naga::Literal::U32(v)) => v,
            ref other => panic!("{name} is {other:?}"),
        }
    };
    let expected = [
        ("FORCE_RECOVERY", FORCE_RECOVERY),
        ("FORCE_GRAVITY", FORCE_GRAVITY),
        ("FORCE_WIND", FORCE_WIND),
        ("FORCE_COLLISIONS", FORCE_COLLISIONS),
        ("WIND_NONE", WIND_NONE),
        ("WIND_WAVES", WIND_WAVES),
        ("WIND_NOISE", WIND_NOISE),
        ("WIND_ANALYTIC", WIND_ANALYTIC),
        ("WIND_RADIAL", WIND_RADIAL),
        ("WIND_WHIRL", WIND_WHIRL),
        ("CULL_ORIENTATION", CULL_ORIENTATION),
        ("CULL_FRUSTUM", CULL_FRUSTUM),
        ("CULL_DISTANCE", CULL_DISTANCE),
        ("DRAW_SHADOWS", DRAW_SHADOWS),
        ("DRAW_BLADE_SHADOWS", DRAW_BLADE_SHADOWS),
        ("DRAW_BLADE_RIDGE", DRAW_BLADE_RIDGE),
        ("BLADE_QUAD", BLADE_QUAD),
        ("BLADE_TRIANGLE", BLADE_TRIANGLE),
        ("BLADE_QUADRATIC", BLADE_QUADRATIC),
        ("SHADING_BLINN_PHONG", SHADING_BLINN_PHONG),
        ("GROUND_PLANE", GROUND_PLANE),
        ("GROUND_SPHERE", GROUND_SPHERE),
        ("GROUND_MESH", GROUND_MESH),
        ("TECHNIQUE_BEZIER", TECHNIQUE_BEZIER),
        ("TECHNIQUE_BILLBOARD", TECHNIQUE_BILLBOARD),
        ("TECHNIQUE_LANDSCAPE", TECHNIQUE_LANDSCAPE),
        ("DISTANCE_BUCKETS", sward_core::commands::DISTANCE_BUCKETS),
    ];
    for (name, flag) in expected {
        assert_eq!(value(name), flag, "{name}");
    }
}

/// A validator for `pipeline`'s module: WebGPU's core, or its `subgroups` feature where the
/// pipeline enables it (and only those). WebGPU's core has `pack2x16float` and
/// `unpack2x16float` (naga's SHADER_FLOAT16_IN_FLOAT32; wgpu grants it to every adapter with
/// the compliant downlevel flags, GL 4.5 included).
fn validator(pipeline: &sward_wgpu::portable::PipelineSource) -> naga::valid::Validator {
    let subgroups = pipeline.uses_subgroups();
    let core = naga::valid::Capabilities::SHADER_FLOAT16_IN_FLOAT32;
    let capabilities = match subgroups {
        true => core | naga::valid::Capabilities::SUBGROUP,
        false => core,
    };
    let mut validator = naga::valid::Validator::new(naga::valid::ValidationFlags::all(), capabilities);
    if subgroups {
        validator
            .subgroup_stages(naga::valid::ShaderStages::COMPUTE)
            .subgroup_operations(naga::valid::SubgroupOperationSet::all());
    }
    validator
}

#[test]
fn every_portable_pipeline_is_valid_wgsl() {
    for pipeline in PIPELINES {
        let text = pipeline.text().unwrap_or_else(|e| panic!("{e}"));
        let module = naga::front::wgsl::parse_str(&text)
            .unwrap_or_else(|e| panic!("{}: {}", pipeline.name, e.emit_to_string(&text)));
        validator(pipeline)
            .validate(&module)
            .unwrap_or_else(|e| panic!("{}: {}", pipeline.name, e.emit_to_string(&text)));
        for entry in [Some(pipeline.entry), pipeline.fragment].into_iter().flatten() {
            assert!(
                module.entry_points.iter().any(|e| e.name == entry),
                "{} has no entry point {entry}",
                pipeline.name
            );
        }
    }
}

/// Each stage of a portable pipeline: its entry point and its naga stage.
fn stages(pipeline: &sward_wgpu::portable::PipelineSource) -> Vec<(naga::ShaderStage, &'static str)> {
    match pipeline.fragment {
        None if sward_wgpu::portable::vertex_only(pipeline) => vec![(naga::ShaderStage::Vertex, pipeline.entry)],
        // A fragment stage alone (the Vulkan renderer's splat resolve, over the sky's triangle).
        Some(fragment) if fragment == pipeline.entry => vec![(naga::ShaderStage::Fragment, fragment)],
        None => vec![(naga::ShaderStage::Compute, pipeline.entry)],
        Some(fragment) => vec![
            (naga::ShaderStage::Vertex, pipeline.entry),
            (naga::ShaderStage::Fragment, fragment),
        ],
    }
}

#[test]
fn every_portable_pipeline_translates_to_metal_and_dx12() {
    let webgpu = ((2, 4), naga::back::hlsl::ShaderModel::V6_0);
    translates_to_metal_and_dx12(PIPELINES, validator, webgpu, &ShaderModules::built_in());
}

/// The splatting passes (the far field on a device with 64-bit atomic min/max: Metal 3.1,
/// DX12's shader model 6.6) translate as the rest.
#[test]
fn the_splatting_pipelines_translate_to_metal_and_dx12() {
    let int64 = |_: &sward_wgpu::portable::PipelineSource| {
        use naga::valid::Capabilities as Can;
        let capabilities = Can::SHADER_FLOAT16_IN_FLOAT32
            | Can::SHADER_INT64
            | Can::SHADER_INT64_ATOMIC_MIN_MAX
            | Can::MULTISAMPLED_SHADING;
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), capabilities)
    };
    let splatting = &sward_core::wgsl::splatting::SPLATTING;
    let built_in = ShaderModules::built_in();
    translates_to_metal_and_dx12(
        splatting,
        int64,
        ((3, 1), naga::back::hlsl::ShaderModel::V6_6),
        &built_in,
    );
}

/// The splatting passes with 32-bit cells (`narrow_splats`: a device without 64-bit atomics)
/// are valid WGSL without 64-bit integers and translate to Metal and DX12 as WebGPU's own.
#[test]
fn the_narrow_splatting_pipelines_need_no_64_bit_integer() {
    let narrow = ShaderModules::built_in().with_narrow_splats(true);
    let splatting = &sward_core::wgsl::splatting::SPLATTING;
    for pipeline in splatting {
        let text = narrow.text(pipeline).unwrap_or_else(|e| panic!("{e}"));
        assert!(
            !text.contains("u64"),
            "{} with narrow cells still names u64",
            pipeline.name
        );
    }
    let webgpu = |_: &sward_wgpu::portable::PipelineSource| {
        use naga::valid::Capabilities as Can;
        // The resolve a sample at a time reads `sample_index` (WebGPU has it).
        let capabilities = Can::SHADER_FLOAT16_IN_FLOAT32 | Can::MULTISAMPLED_SHADING;
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), capabilities)
    };
    translates_to_metal_and_dx12(
        splatting,
        webgpu,
        ((2, 4), naga::back::hlsl::ShaderModel::V6_0),
        &narrow,
    );
}

/// Each of `pipelines`, valid by `validator`, written by naga as Metal of `msl` and HLSL of
/// `shader_model`, each stage an entry point.
fn translates_to_metal_and_dx12(
    pipelines: &[sward_wgpu::portable::PipelineSource],
    validator: impl Fn(&sward_wgpu::portable::PipelineSource) -> naga::valid::Validator,
    (msl, shader_model): ((u8, u8), naga::back::hlsl::ShaderModel),
    modules: &ShaderModules,
) {
    for pipeline in pipelines {
        let text = modules.text(pipeline).unwrap_or_else(|e| panic!("{e}"));
        let module = naga::front::wgsl::parse_str(&text).expect("parses");
        let info = validator(pipeline)
            .validate(&module)
            .unwrap_or_else(|e| panic!("{}: {}", pipeline.name, e.emit_to_string(&text)));
        for (stage, entry) in stages(pipeline) {
            // The overrides at their defaults, as wgpu resolves them before a backend writes.
            let (module, info) = naga::back::pipeline_constants::process_overrides(
                &module,
                &info,
                Some((stage, entry)),
                &Default::default(),
            )
            .unwrap_or_else(|e| panic!("{} {stage:?}: {e}", pipeline.name));
            let (module, info) = (module.as_ref(), info.as_ref());
            let entry = Some((stage, entry.to_string()));
            let msl = naga::back::msl::Options {
                lang_version: msl,
                ..Default::default()
            };
            let msl_pipeline = naga::back::msl::PipelineOptions {
                entry_point: entry.clone(),
                ..Default::default()
            };
            let (metal, _) = naga::back::msl::write_string(module, info, &msl, &msl_pipeline)
                .unwrap_or_else(|e| panic!("{} {stage:?} in Metal: {e}", pipeline.name));
            let keyword = match stage {
                naga::ShaderStage::Vertex => "vertex ",
                naga::ShaderStage::Fragment => "fragment ",
                _ => "kernel void",
            };
            assert!(
                metal.contains(keyword),
                "{}: no Metal {stage:?} function",
                pipeline.name
            );
            let hlsl = naga::back::hlsl::Options {
                shader_model,
                ..Default::default()
            };
            let hlsl_pipeline = naga::back::hlsl::PipelineOptions { entry_point: entry };
            let mut dx12 = String::new();
            let written = naga::back::hlsl::Writer::new(&mut dx12, &hlsl, &hlsl_pipeline)
                .write(module, info, None)
                .unwrap_or_else(|e| panic!("{} {stage:?} in HLSL: {e}", pipeline.name));
            assert_eq!(
                written.entry_point_names.len(),
                1,
                "{}: one HLSL {stage:?} entry point",
                pipeline.name
            );
            assert!(
                written.entry_point_names[0].is_ok(),
                "{} {stage:?} in HLSL: {:?}",
                pipeline.name,
                written.entry_point_names[0]
            );
        }
    }
}

/// wgpu's log lines of warnings and errors (the validation layer's, GL's debug output), with the
/// thread that logged them: the tests run side by side, and each checks its own.
static LOGGED: Mutex<Vec<(String, String)>> = Mutex::new(Vec::new());

struct Collect;

impl log::Log for Collect {
    fn enabled(&self, metadata: &log::Metadata) -> bool {
        // EGL's probing of the platforms it may run on (a DRI driver it finds no device for, here)
        // is the machine's, not the renderer's: wgpu goes on to the one that works.
        let target = metadata.target();
        metadata.level() <= log::Level::Warn && target.starts_with("wgpu") && !target.starts_with("wgpu_hal::gles::egl")
    }
    fn log(&self, record: &log::Record) {
        if self.enabled(record.metadata()) {
            let thread = std::thread::current().name().unwrap_or_default().to_string();
            let line = format!("{}: {}", record.target(), record.args());
            LOGGED.lock().unwrap().push((thread, line));
        }
    }
    fn flush(&self) {}
}

/// A device on wgpu's `backend` with its validation on (Vulkan's layer, GL's debug output),
/// WebGPU's default limits, and the optional features the portable renderer uses where the
/// adapter has them (`portable_features`) but the splats': lavapipe's subgroups and draws with a
/// count, none on llvmpipe's GL, so the tests that run on both run both paths.
fn portable_device(backend: wgpu::Backends) -> (wgpu::Adapter, wgpu::Device, wgpu::Queue) {
    portable_device_on((backend, false))
}

/// [`portable_device`], or (`splats`) one that splats the far field: every optional feature the
/// portable renderer uses, 64-bit atomic min/max among them (lavapipe has them), and the limits
/// it asks for then (`portable_limits`: the splatting passes bind more storage buffers than
/// WebGPU's defaults).
fn portable_device_on((backend, splats): (wgpu::Backends, bool)) -> (wgpu::Adapter, wgpu::Device, wgpu::Queue) {
    let _ = log::set_logger(&Collect).map(|()| log::set_max_level(log::LevelFilter::Warn));
    // Validation without wgpu's debug flag: with it, wgpu attaches the WGSL text to the SPIR-V
    // as source language WGSL, which Debian 12's validation layer rejects.
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
        backends: backend,
        flags: wgpu::InstanceFlags::VALIDATION,
        ..wgpu::InstanceDescriptor::new_without_display_handle()
    });
    let needs = match backend {
        wgpu::Backends::GL => "this test needs GL through EGL (Debian/Ubuntu: apt-get install libegl1 libegl-mesa0 libgles2 libgl1-mesa-dri)",
        _ => support::NEEDS,
    };
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default()))
        .unwrap_or_else(|e| panic!("{needs}: no wgpu adapter ({e})"));
    let offered = sward_wgpu::portable::portable_features(&adapter);
    let splatting = sward_wgpu::portable::SPLAT_FEATURES;
    assert!(
        !splats || offered.contains(splatting),
        "lavapipe should give the portable renderer 64-bit atomic min/max to splat with"
    );
    let (features, limits) = match splats {
        true => (offered, sward_wgpu::portable::portable_limits(&adapter)),
        false => (
            offered - splatting - wgpu::Features::PASSTHROUGH_SHADERS,
            wgpu::Limits::default(),
        ),
    };
    if backend == wgpu::Backends::VULKAN && !splats {
        let both = wgpu::Features::SUBGROUP | wgpu::Features::MULTI_DRAW_INDIRECT_COUNT;
        assert_eq!(
            features, both,
            "lavapipe should give the portable renderer both its optional features"
        );
    }
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("portable"),
        required_features: features,
        required_limits: limits,
        ..Default::default()
    }))
    .unwrap_or_else(|e| {
        panic!(
            "{needs}: no device with WebGPU's default limits on {:?} ({e})",
            adapter.get_info()
        )
    });
    (adapter, device, queue)
}

/// The portable renderer's pipelines on [`portable_device`]'s device for `backend`, with the
/// adapter named as a failure names it.
fn portable_renderer(backend: wgpu::Backends) -> (String, wgpu::Device, wgpu::Queue, PortableRenderer) {
    let (adapter, device, queue) = portable_device(backend);
    let on = format!("{:?} ({})", adapter.get_info().backend, adapter.get_info().name);
    let renderer = PortableRenderer::new(&adapter, &device).expect("the portable pipelines build");
    (on, device, queue, renderer)
}

/// A depth texture of `size` pixels and `samples` a pixel that can be drawn into and read, as
/// an engine's depth of its view.
fn callers_depth(device: &wgpu::Device, [width, height]: [u32; 2], samples: u32) -> wgpu::TextureView {
    device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some("the caller's depth"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: samples,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Depth32Float,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        })
        .create_view(&Default::default())
}

/// That wgpu warned of nothing on this test's thread.
fn assert_nothing_logged() {
    let thread = std::thread::current().name().unwrap_or_default().to_string();
    let logged: Vec<String> = LOGGED
        .lock()
        .unwrap()
        .iter()
        .filter(|(t, _)| *t == thread)
        .map(|(_, line)| line.clone())
        .collect();
    assert!(logged.is_empty(), "wgpu warned:\n{}", logged.join("\n"));
}

#[test]
fn the_portable_simulation_matches_the_cpu_reference_for_every_wind_on_vulkan() {
    simulation_matches_the_cpu_reference(wgpu::Backends::VULKAN);
}

#[test]
fn the_portable_simulation_matches_the_cpu_reference_for_every_wind_on_gl() {
    simulation_matches_the_cpu_reference(wgpu::Backends::GL);
}

/// 240 steps of random fields with 12 spheres, in frames of 24 steps, blown by every wind field
/// alone and by four summed, on `backend`, against the CPU reference.
fn simulation_matches_the_cpu_reference(backend: wgpu::Backends) {
    let (on, device, queue, mut renderer) = portable_renderer(backend);
    let only_simulate = PortablePasses::SIMULATE;
    let combined = [WindKind::Waves, WindKind::Radial, WindKind::Whirl, WindKind::Noise];
    let cases = WindKind::ALL.map(|k| vec![k]).into_iter().chain([combined.to_vec()]);
    for (case, kinds) in cases.enumerate() {
        let mut rng = Pcg32::new(700 + case as u64, 5);
        let scene = random_scene(&mut rng, &kinds);
        let start = random_blades(&mut rng, BLADES, 6.0);
        let mut field = PortableField::new(&device, &start).unwrap();
        let mut done = 0;
        while done < STEPS {
            let time = done as f32 * scene.simulation.step;
            let desc = FrameDesc::of_scene(&scene, Vec2::splat(30.0), (time, STEPS_PER_FRAME), [320, 240]);
            let mut encoder = device.create_command_encoder(&Default::default());
            renderer.record(&device, &queue, &mut encoder, &desc, &mut field, only_simulate);
            queue.submit([encoder.finish()]);
            done += STEPS_PER_FRAME;
        }
        let (gpu_blades, gpu_etas) = field.read(&device, &queue).unwrap();
        check_simulation(&start, (&gpu_blades, &gpu_etas), &scene, &format!("{on}, {kinds:?}"));
    }
    assert_nothing_logged();
}

/// `gpu` (blades and η) is what sward-core's CPU reference makes of `start` in STEPS steps of
/// `scene`, within TOLERANCE but for ill-conditioned trajectories; the spheres pressed some
/// blades and the forces moved most. `case` names the case in a failure.
fn check_simulation(start: &[Blade], (gpu_blades, gpu_etas): (&[Blade], &[f32]), scene: &Scene, case: &str) {
    let mut cpu_blades = start.to_vec();
    let mut cpu_etas = vec![0.0; start.len()];
    let sim = &scene.simulation;
    simulate(
        &mut cpu_blades,
        &mut cpu_etas,
        sim,
        &scene.colliders,
        &scene.wind,
        0.0,
        STEPS,
    );
    let chaotic = ill_conditioned(start, &cpu_blades, scene, STEPS);
    assert!(
        chaotic.len() < start.len() / 25,
        "{case}: {} trajectories ill-conditioned",
        chaotic.len()
    );
    let trampled = cpu_etas.iter().filter(|e| **e > 0.0).count();
    assert!(
        trampled > 20,
        "{case}: the spheres should press some blades, pressed {trampled}"
    );
    let moved = (0..start.len())
        .filter(|&i| cpu_blades[i].tip().distance(start[i].tip()) > 0.01)
        .count();
    assert!(moved > start.len() / 2, "{case}: forces should move most blades");
    let (err, i, what) = worst_error(gpu_blades, gpu_etas, &cpu_blades, &cpu_etas, &chaotic);
    assert!(
        err <= TOLERANCE,
        "{case}: blade {i} {what} differs by {err:e} (GPU {:?} η {} vs CPU {:?} η {})",
        gpu_blades[i],
        gpu_etas[i],
        cpu_blades[i],
        cpu_etas[i]
    );
}

#[test]
fn a_field_too_large_for_the_devices_bindings_says_how_many_blades_fit() {
    let (_adapter, device, _queue) = portable_device(wgpu::Backends::VULKAN);
    let limit = device.limits().max_storage_buffer_binding_size as usize;
    let blades = vec![<Blade as bytemuck::Zeroable>::zeroed(); limit / 64 + 1];
    match PortableField::new(&device, &blades) {
        Err(e @ PortableError::FieldTooLarge { fits, .. }) => {
            assert_eq!(fits as usize, limit / 64);
            let said = e.to_string();
            assert!(said.contains(&format!("at most {fits} blades fit")), "{said}");
        }
        Err(e) => panic!("the wrong error: {e}"),
        Ok(_) => panic!("a field over the binding limit was taken"),
    }
    // A device opened as the command line opens it binds as much as the adapter offers, and
    // no less than WebGPU's defaults (lavapipe offers the default 128 MiB; the H100 4 GiB).
    let (adapter, device, _queue) = sward_wgpu::portable::open_device(wgpu::Backends::VULKAN, true).unwrap();
    let (offered, opened) = (adapter.limits(), device.limits());
    let webgpu = wgpu::Limits::default();
    for (name, offered, opened, default) in [
        (
            "storage binding",
            offered.max_storage_buffer_binding_size,
            opened.max_storage_buffer_binding_size,
            webgpu.max_storage_buffer_binding_size,
        ),
        (
            "buffer",
            offered.max_buffer_size,
            opened.max_buffer_size,
            webgpu.max_buffer_size,
        ),
    ] {
        assert_eq!(opened, offered.max(default), "the largest {name}");
    }
    let said = sward_wgpu::portable::beyond_webgpu_defaults(blades.len()).expect("beyond the defaults");
    assert!(
        said.contains("128 MiB") && said.contains("not in every browser"),
        "{said}"
    );
    assert!(sward_wgpu::portable::beyond_webgpu_defaults(limit / 64).is_none());
    assert_nothing_logged();
}

#[test]
fn the_portable_cull_lists_the_cpu_references_visible_blades_by_distance_bucket_on_vulkan() {
    cull_matches_the_cpu_reference(wgpu::Backends::VULKAN);
}

#[test]
fn the_portable_cull_lists_the_cpu_references_visible_blades_by_distance_bucket_on_gl() {
    cull_matches_the_cpu_reference(wgpu::Backends::GL);
}

/// A field culled by more workgroups than the bucket scan takes in one round (2,048 of 64
/// blades: 140,000 random blades in 2,188), on lavapipe: the CPU reference's verdicts, each
/// bucket in draw order — the scan's rounds carry each bucket's count from one to the next, and
/// the sort takes the list in several runs.
#[test]
fn a_field_the_bucket_scan_takes_in_several_rounds_is_listed_in_draw_order() {
    let (_, device, queue, mut renderer) = portable_renderer(wgpu::Backends::VULKAN);
    let mut rng = Pcg32::new(931, 5);
    let blades = random_blades(&mut rng, 140_000, 12.0);
    let mut field = PortableField::new(&device, &blades).unwrap();
    for round in 0..2 {
        let mut scene = Scene {
            camera: random_camera(&mut rng),
            cull: random_cull(&mut rng),
            ..Scene::default()
        };
        scene.simulation.forces.wind = false;
        let desc = FrameDesc::of_scene(&scene, Vec2::splat(30.0), (0.0, 0), [320, 240]);
        let mut encoder = device.create_command_encoder(&Default::default());
        renderer.record(&device, &queue, &mut encoder, &desc, &mut field, PortablePasses::CULL);
        queue.submit([encoder.finish()]);
        let (listed, draws) = field.read_visible(&device, &queue, 0).unwrap();
        let case = format!("round {round}");
        let seen = check_cull(&listed, &draws, &blades, (&scene, &desc), &case);
        assert_in_draw_order((&listed, &draws), (&blades, &desc), u64::from, &case);
        assert!(seen > 1000 || round > 0, "the first camera should see blades ({seen})");
    }
    assert_nothing_logged();
}

/// Eight rounds of two random cameras and sets of tests over 5003 random blades on `backend`,
/// each camera culling into its own lists in the same frame: the same
/// verdicts as the CPU reference (but for blades within 1e-4 of a threshold), each listed blade
/// in its distance bucket.
fn cull_matches_the_cpu_reference(backend: wgpu::Backends) {
    let (_, device, queue, mut renderer) = portable_renderer(backend);
    let cull = PortablePasses::CULL;
    let mut rng = Pcg32::new(930, 5);
    let blades = random_blades(&mut rng, 5003, 12.0);
    let mut field = PortableField::new(&device, &blades).unwrap();
    for round in 0..8 {
        // Two cameras a frame, each culling into its own lists (as two cameras of an engine).
        let scenes = [0, 1].map(|_| {
            let mut scene = Scene {
                camera: random_camera(&mut rng),
                cull: random_cull(&mut rng),
                ..Scene::default()
            };
            scene.simulation.forces.wind = false;
            scene.blades.ridge = round % 2 == 0;
            scene
        });
        let descs = scenes
            .each_ref()
            .map(|scene| FrameDesc::of_scene(scene, Vec2::splat(30.0), (0.0, 0), [320, 240]));
        for (view, desc) in descs.iter().enumerate() {
            let mut encoder = device.create_command_encoder(&Default::default());
            renderer.record_view(&device, &queue, &mut encoder, (desc, view), &mut field, cull);
            queue.submit([encoder.finish()]);
        }
        for (view, (scene, desc)) in scenes.iter().zip(&descs).enumerate() {
            let (listed, draws) = field.read_visible(&device, &queue, view).unwrap();
            let case = format!("round {round}, view {view}");
            let seen = check_cull(&listed, &draws, &blades, (scene, desc), &case);
            assert_in_draw_order((&listed, &draws), (&blades, desc), u64::from, &case);
            // The draw with a count stops at the farthest bucket that holds a blade.
            let farthest = draws.iter().rposition(|d| d.instance_count > 0).map_or(0, |k| k + 1);
            let drawn = field.read_drawn_buckets(&device, &queue, view).unwrap();
            assert_eq!(drawn as usize, farthest, "{case}: buckets drawn");
            assert!(seen > 0 || round > 0, "the first cameras should see some blades");
        }
    }
    assert_nothing_logged();
}

/// The listed blades (`listed`, by the draw commands `draws`) are the CPU reference's visible ones
/// for `scene` seen as `desc` says (but for blades within 1e-4 of a threshold), each listed once
/// and in its distance bucket; `case` names the case in a failure. Returns how many the CPU sees.
fn check_cull(
    listed: &[u32],
    draws: &[DrawCommand],
    blades: &[Blade],
    (scene, desc): (&Scene, &FrameDesc),
    case: &str,
) -> usize {
    check_buckets(listed, draws, blades, desc);
    let mut gpu = listed.to_vec();
    gpu.sort_unstable();
    gpu.dedup();
    assert_eq!(gpu.len(), listed.len(), "{case}: a blade was listed twice");
    let eye = scene.camera.position;
    let view_proj = desc.camera.view_projection();
    let mut on_threshold = 0;
    let mut gpu_iter = gpu.iter().peekable();
    let mut seen = 0;
    for (id, blade) in blades.iter().enumerate() {
        let id = id as u32;
        let on_gpu = gpu_iter.next_if_eq(&&id).is_some();
        let visible =
            |slack| cull_blade_loosened(blade, id, eye, &view_proj, &scene.cull, slack) == CullVerdict::Visible;
        if visible(1e-4) != visible(-1e-4) {
            on_threshold += 1;
            continue;
        }
        let cpu = cull_blade(blade, id, eye, &view_proj, &scene.cull) == CullVerdict::Visible;
        seen += cpu as usize;
        assert_eq!(
            on_gpu, cpu,
            "{case}, blade {id}: GPU visible {on_gpu}, CPU {cpu} ({:?})",
            scene.cull
        );
    }
    assert!(
        on_threshold < blades.len() / 100,
        "{case}: {on_threshold} blades within 1e-4 of a threshold"
    );
    seen
}

/// Each bucket lists its blades in draw order: nearest first by exact distance (to within two
/// of a sort key's steps) within each run the sort takes (cull.wesl `sort_drawn`: 4,096 or
/// 8,192 entries of the list; pairs across a multiple of 4,096 are not compared), blades at
/// one distance in the cull's order (`rank`: a blade's index, or its tile's place in the run and
/// then its index), whatever order the workgroups ran in: the list is the same every run, and
/// with it the draw order, which decides depth ties. The frame splats
/// nothing (the list is sorted to its end).
fn assert_in_draw_order(
    (listed, draws): (&[u32], &[DrawCommand]),
    (blades, desc): (&[Blade], &FrameDesc),
    rank: impl Fn(u32) -> u64,
    case: &str,
) {
    let lod = FrameDecisions::of(desc, RendererCan::strips()).lod;
    let range = bucket_range(lod.far, desc.cull.distance_max);
    // The place within its bucket the sort keys quantize (exact_order.wesl `exact_key`).
    let within = |id: u32, k: usize| {
        let d = blades[id as usize].v0.truncate().distance(desc.camera.eye);
        let x = ((d / range).sqrt() * DISTANCE_BUCKETS as f32 - k as f32).max(0.0);
        if k + 1 < DISTANCE_BUCKETS as usize {
            x.min(1.0)
        } else {
            x / (1.0 + x)
        }
    };
    // The coarsest step of a key's fine bits (13 of them on a device that sorts 8,192).
    let step = 1.0 / 8191.0;
    for (k, d) in draws.iter().enumerate() {
        let first = d.first_instance as usize;
        for slot in first..(first + d.instance_count as usize).saturating_sub(1) {
            if (slot + 1) % 4096 == 0 {
                continue;
            }
            let (a, b) = (listed[slot], listed[slot + 1]);
            let (wa, wb) = (within(a, k), within(b, k));
            assert!(
                wa <= wb + 2.0 * step,
                "{case}: bucket {k} lists blade {a} ({wa}) before the nearer blade {b} ({wb})"
            );
            // At one distance (one key but for the run's order) the cull's order stays.
            assert!(
                wa != wb || rank(a) < rank(b),
                "{case}: bucket {k} lists blade {a} before blade {b} at the same distance"
            );
        }
    }
}

/// The buckets tile the list nearest first, each blade in its distance bucket's range (a blade
/// within 1e-4 of a boundary on either side), each bucket's strip as long as its segments ask.
fn check_buckets(listed: &[u32], draws: &[DrawCommand], blades: &[Blade], desc: &FrameDesc) {
    assert_eq!(draws.len(), DISTANCE_BUCKETS as usize);
    let columns = if desc.blades.ridge { 4 } else { 2 };
    let mut start = 0;
    for (k, d) in draws.iter().enumerate() {
        assert_eq!(
            d.first_instance, start,
            "bucket {k} does not start where the one before ends"
        );
        assert!(
            d.vertex_count >= 3 * columns && d.vertex_count % columns == 0,
            "bucket {k}: {d:?}"
        );
        start += d.instance_count;
    }
    assert_eq!(start as usize, listed.len());
    let lod = FrameDecisions::of(desc, RendererCan::strips()).lod;
    let range = bucket_range(lod.far, desc.cull.distance_max);
    for (slot, &id) in listed.iter().enumerate() {
        let dist = blades[id as usize].v0.truncate().distance(desc.camera.eye);
        let lo = distance_bucket(range, dist * (1.0 - 1e-4));
        let hi = distance_bucket(range, dist * (1.0 + 1e-4));
        let within = (lo..=hi).any(|k| {
            let d = draws[k as usize];
            (d.first_instance..d.first_instance + d.instance_count).contains(&(slot as u32))
        });
        assert!(
            within,
            "blade {id} at {dist} (bucket {lo}..={hi}) sits at slot {slot}, outside its bucket"
        );
    }
}

/// The picture tests' image size, and the steps simulated before the frame.
const PICTURE: [u32; 2] = [240, 180];
const PICTURE_STEPS: u32 = 30;
/// The picture tests' tolerance: at most one pixel in this many may differ from the Vulkan
/// renderer's by more than `PICTURE_LEVELS` of 255 in a channel (rounding where a blade's edge
/// crosses a sample; seen on lavapipe and llvmpipe GL: at most 3 pixels of 43,200).
const PICTURE_ONE_IN: usize = 2000;
const PICTURE_LEVELS: u8 = 8;
/// Where cutters mow, one pixel in this many: a texel whose centre lies on a cutter's rim is
/// mown or not by the last bit of a square root, and its blades stand full height or as stubs
/// (seen: none on wgpu's Vulkan backend, 31 pixels of 43,200 on llvmpipe's GL).
const MOWN_PICTURE_ONE_IN: usize = 1000;
/// Where colliders roll through the Bezier field, one pixel in this many: a blade they touch
/// keeps its collision strength η from step to step (SPEC §3.7), so a contact decided by the
/// last bit of a distance leaves it pushed down or recovering for the rest of the run (seen on
/// the trample scene: none on wgpu's Vulkan backend, 26 pixels of 43,200 on llvmpipe's GL
/// through wgpu 30, single pixels along the spheres' trails).
const ROLLED_PICTURE_ONE_IN: usize = 1000;
/// The generated grass along the trample map's trails, one pixel in this many: each blade leans
/// by the push at its root, which the trample pass sums as each compiler rounds it (seen: 4
/// pixels of 43,200 on wgpu's Vulkan backend, 96 on llvmpipe's GL; with the trails left out of
/// the frame that draws them, 1,121).
const TRAIL_PICTURE_ONE_IN: usize = 400;
/// A streamed field 850 units from the world's origin (the frame origin moves only past 1024),
/// one pixel in this many: there a 32-bit coordinate's step is 0.06 mm, the blades settle and
/// step as exactly as each compiler's contractions leave them (within 4 mm, the streaming test
/// says), and a dense field's thin edges that move a fraction of a pixel flip whole pixels
/// (seen: 12 pixels of 43,200 on wgpu's Vulkan backend, 49 on llvmpipe's GL).
const STREAMED_PICTURE_ONE_IN: usize = 500;

/// The shipped scenes whose Bezier blades the portable renderer draws (a field grown once), at
/// most 6,000 of them, the trample scene mown too, and the open world's window all Bezier.
fn drawable_scenes() -> Vec<(&'static str, Scene)> {
    let shipped = shipped_scenes();
    let named = |name: &str| shipped.iter().find(|(n, _)| *n == name).cloned().unwrap();
    let mut scenes: Vec<_> = ["meadow", "hills", "planet", "prairie", "trample"].map(named).into();
    scenes.push(mowing(named("trample")));
    scenes.push(streamed_bezier(named("openworld")));
    scenes.push(blade_shadows(named("meadow")));
    scenes
}

/// The open world's streamed window of 3 × 3 tiles over its terrain, every blade a Bezier blade
/// (the generated grass beyond is the Vulkan renderer's alone so far), seen from its path's
/// start above the ground.
fn streamed_bezier((_, mut scene): (&'static str, Scene)) -> (&'static str, Scene) {
    scene.technique = sward_core::instanced::Technique::Bezier;
    scene.field.blades = 9 * sward_core::tiles::TILE_BLADES;
    assert!(scene.stream_window().is_some());
    let ground = scene.grow_field().unwrap().ground.and_then(|m| m.height_grid());
    scene.camera = scene.camera_path.camera_over(&scene.camera, 0.0, ground.as_ref());
    ("openworld-bezier", scene)
}

/// The portable renderer's `picture` of `scene` holds the sun's shadows: drawn without them,
/// where the camera sees one (the colliders', the terrain's, the blades') more than one pixel
/// in a thousand is lighter.
fn assert_shadows_drawn(name: &str, scene: &Scene, picture: &[u8]) {
    let mut unshadowed = scene.clone();
    unshadowed.shading.shadows = false;
    let lit = portable_picture(&unshadowed, (wgpu::Backends::VULKAN, false));
    let darker = lit
        .chunks(4)
        .zip(picture.chunks(4))
        .filter(|(l, p)| (0..3).all(|c| l[c] >= p[c]) && (0..3).any(|c| l[c] > p[c] + PICTURE_LEVELS))
        .count();
    eprintln!("{name}: {darker} pixels in shadow");
    // Where the camera sees a shadow: the planet's own night side and its spheres', the trample
    // scene's balls', the blades'.
    let casts = ["planet", "trample", "trample-mown", "meadow-blade-shadows"].contains(&name);
    assert!(
        !casts || darker * 1000 > picture.len() / 4,
        "{name}: the shadows darken {darker} pixels"
    );
}

/// `scene` with the blades near the eye casting shadows too (the near cascade; as shipped, only
/// at `ultra`).
fn blade_shadows((_, mut scene): (&'static str, Scene)) -> (&'static str, Scene) {
    scene.shading.blade_shadows = sward_core::look::BladeShadows::On;
    ("meadow-blade-shadows", scene)
}

/// `scene` with every other collider a cutter: the trample map runs, and the blades it mows
/// are drawn as stubs.
fn mowing((_, mut scene): (&'static str, Scene)) -> (&'static str, Scene) {
    for collider in scene.colliders.iter_mut().step_by(2) {
        collider.cut = true;
    }
    assert!(scene.tramples());
    ("trample-mown", scene)
}

/// `scene` drawn by the Vulkan renderer's strip route after PICTURE_STEPS steps, with the
/// validation layer on.
fn vulkan_strips(scene: &Scene) -> Vec<u8> {
    vulkan_route(scene, sward_gpu::DrawRoute::Strips)
}

/// `scene` drawn by the Vulkan renderer as the portable renderer draws it where it splats: by
/// the compute route, its far Bezier buckets splatted and none rasterized by compute.
fn vulkan_splatting(scene: &Scene) -> Vec<u8> {
    let mut scene = scene.clone();
    scene.lod.compute_raster = false;
    vulkan_route(&scene, sward_gpu::DrawRoute::Compute)
}

/// `scene` drawn by the Vulkan renderer's `route` after PICTURE_STEPS steps, with the validation
/// layer on.
fn vulkan_route(scene: &Scene, route: sward_gpu::DrawRoute) -> Vec<u8> {
    let desc = sward_gpu::ContextDesc {
        validation: sward_gpu::Validation::Required,
        ..Default::default()
    };
    let ctx = sward_gpu::Context::new(&desc).unwrap_or_else(|e| panic!("{}: {e}", support::NEEDS));
    let field = scene.grow_field().unwrap();
    let [width, height] = PICTURE;
    let mut headless = sward_gpu::Headless::new(&ctx, width, height, None).unwrap();
    let mut scene = scene.clone();
    scene.quality.route = route;
    assert!(headless.renderer.set_route(scene.quality.route).is_none());
    headless.renderer.upload(&field).unwrap();
    headless.renderer.upload_ground(field.ground.as_ref()).unwrap();
    let pixels = headless.render_scene(&scene, field.size, PICTURE_STEPS).unwrap();
    drop(headless);
    let messages = ctx.take_validation_messages();
    assert!(messages.is_empty(), "Vulkan validation: {messages:?}");
    pixels
}

/// `scene` drawn by the portable renderer on `backend`, splatting the far field or not, after
/// PICTURE_STEPS steps.
fn portable_picture(scene: &Scene, on: (wgpu::Backends, bool)) -> Vec<u8> {
    portable_picture_of(scene, on, ShaderModules::built_in())
}

/// [`portable_picture`] with the renderer's pipelines made of `modules` (their far field drawn
/// where `on` does not splat, unless they ask for 32-bit cells).
fn portable_picture_of(scene: &Scene, on: (wgpu::Backends, bool), modules: ShaderModules) -> Vec<u8> {
    let samples = scene.quality.preset.msaa_samples();
    let modules = match (on.1, modules.narrow_splats()) {
        (false, None) => modules.with_narrow_splats(false),
        _ => modules,
    };
    let mut headless = PortableHeadless::made_of(portable_device_on(on), PICTURE, samples, modules).unwrap();
    let field = scene.grow_field().unwrap();
    headless.upload(&field).unwrap();
    headless.render_scene(scene, field.size, PICTURE_STEPS).unwrap()
}

/// A headless portable renderer of `size` and `samples` on [`portable_device_on`]'s device for
/// `on`: where it does not splat with 64-bit atomics, its far field drawn as geometry (not in
/// 32-bit cells: the tests of those ask for them).
fn headless_on(on: (wgpu::Backends, bool), size: [u32; 2], samples: u32) -> PortableHeadless {
    let modules = ShaderModules::built_in().with_narrow_splats(false);
    PortableHeadless::made_of(portable_device_on(on), size, samples, modules).unwrap()
}

/// Pixels of RGBA images `a` and `b` that differ by more than `levels` in a channel, and the
/// largest difference.
fn differing_pixels(a: &[u8], b: &[u8], levels: u8) -> (usize, u8) {
    assert_eq!(a.len(), b.len());
    let per_pixel = a
        .chunks(4)
        .zip(b.chunks(4))
        .map(|(p, q)| p.iter().zip(q).map(|(x, y)| x.abs_diff(*y)).max().unwrap_or(0));
    per_pixel.fold((0, 0), |(over, worst), d| (over + (d > levels) as usize, worst.max(d)))
}

/// Of two RGBA pictures `PICTURE` in size, the blocks of `BLOCK` × `BLOCK` pixels whose mean
/// colours differ by more than `levels` in a channel, of how many, and the most they differ by:
/// what two devices whose shader math differs in its last bits agree on (a blade a fraction of
/// a pixel over changes single pixels at its edges, not a block's mean).
fn differing_blocks(a: &[u8], b: &[u8], levels: u8) -> (usize, usize, u8) {
    const BLOCK: usize = 4;
    let [width, height] = PICTURE.map(|n| n as usize);
    let mean = |p: &[u8], bx: usize, by: usize, c: usize| {
        let rows = (by * BLOCK..(by + 1) * BLOCK).flat_map(|y| (bx * BLOCK..(bx + 1) * BLOCK).map(move |x| (x, y)));
        let sum: u32 = rows.map(|(x, y)| u32::from(p[(y * width + x) * 4 + c])).sum();
        (sum as f32 / (BLOCK * BLOCK) as f32).round() as u8
    };
    let blocks: Vec<u8> = (0..height / BLOCK)
        .flat_map(|by| (0..width / BLOCK).map(move |bx| (bx, by)))
        .map(|(bx, by)| {
            (0..3)
                .map(|c| mean(a, bx, by, c).abs_diff(mean(b, bx, by, c)))
                .max()
                .unwrap()
        })
        .collect();
    let over = blocks.iter().filter(|&&d| d > levels).count();
    (over, blocks.len(), blocks.iter().copied().max().unwrap_or(0))
}

/// Save `pixels` under the tests' scratch folder for a person to look at.
fn save_picture(name: &str, pixels: &[u8]) {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("portable-pictures");
    std::fs::create_dir_all(&dir).unwrap();
    let [width, height] = PICTURE;
    image::RgbaImage::from_raw(width, height, pixels.to_vec())
        .unwrap()
        .save(dir.join(name))
        .unwrap();
}

/// Every shipped scene as it ships (its Bezier field at most 6,000 blades; its generated grass,
/// billboards, streamed window and trample map as they are).
fn shipped_scenes() -> Vec<(&'static str, Scene)> {
    let load = |name: &'static str, text: &str| {
        let mut scene = Scene::from_toml(text, name).unwrap();
        scene.field.blades = scene.field.blades.min(6000);
        (name, scene)
    };
    vec![
        load("meadow", include_str!("../../../scenes/meadow.toml")),
        load("hills", include_str!("../../../scenes/hills.toml")),
        load("planet", include_str!("../../../scenes/planet.toml")),
        load("prairie", include_str!("../../../scenes/prairie.toml")),
        load("trample", include_str!("../../../scenes/trample.toml")),
        load("trail", include_str!("../../../scenes/trail.toml")),
        load("park", include_str!("../../../scenes/park.toml")),
        load("landscape", include_str!("../../../scenes/landscape.toml")),
        load("openworld", include_str!("../../../scenes/openworld.toml")),
    ]
}

/// The ways the picture tests run the portable renderer: on wgpu's Vulkan backend (lavapipe)
/// drawing the far field and splatting it, on its GL backend (llvmpipe) drawing it.
const PORTABLE_ROUTES: [(wgpu::Backends, bool); 3] = [
    (wgpu::Backends::VULKAN, false),
    (wgpu::Backends::VULKAN, true),
    (wgpu::Backends::GL, false),
];

/// Same scene, same bytes: every shipped scene drawn twice by the portable renderer, each time
/// on a device of its own, on wgpu's Vulkan backend (lavapipe, the far field drawn and splatted)
/// and GL backend (llvmpipe). What a
/// frame reads besides its scene (memory left as it was found, a list placed in the order the
/// GPU happened to run its workgroups — the cull's own order is held by
/// `assert_in_draw_order`) would show here.
#[test]
fn each_shipped_scene_drawn_twice_by_the_portable_renderer_gives_the_same_bytes() {
    for (name, scene) in shipped_scenes() {
        for on in PORTABLE_ROUTES {
            let first = portable_picture(&scene, on);
            let second = portable_picture(&scene, on);
            let (over, worst) = differing_pixels(&first, &second, 0);
            assert_eq!(
                over, 0,
                "{name} on {on:?}: {over} pixels differ (by up to {worst} levels)"
            );
            let sky = first.chunks(4).filter(|p| p[1] <= p[2]).count();
            assert!(sky < first.len() / 4, "{name} on {on:?}: only sky");
        }
    }
    assert_nothing_logged();
}

/// The passes compiled without WebGPU's runtime checks (the default: bounds on every index and
/// loop, workgroup memory zeroed) draw the bytes they draw with them, on each way the portable
/// renderer runs: no pass reads an index past its buffer or workgroup memory it did not write.
/// The trample scene each way (the cull's buckets, a trample map, the blades' shadows; the test
/// fails where the cull's workgroup counts are not cleared) and the landscape splatted (the
/// generated grass and the billboards).
#[test]
fn the_passes_without_webgpus_checks_draw_what_they_draw_with_them() {
    for (name, scene) in shipped_scenes() {
        let ways: &[_] = match name {
            "trample" => &PORTABLE_ROUTES,
            "landscape" => &[(wgpu::Backends::VULKAN, true)],
            _ => continue,
        };
        for &on in ways {
            let unchecked = portable_picture(&scene, on);
            let checked = portable_picture_of(&scene, on, ShaderModules::built_in().with_checks(true));
            let (over, worst) = differing_pixels(&unchecked, &checked, 0);
            assert_eq!(
                over, 0,
                "{name} on {on:?}: {over} pixels differ (by up to {worst} levels)"
            );
        }
    }
    assert_nothing_logged();
}

/// The far field splatted into 32-bit cells (`narrow_splats`: a 16-bit depth key above an RGB
/// 5-6-5 colour, the path of a device without 64-bit atomics) against the 64-bit cells, on
/// lavapipe (which has both), for the shipped scenes that splat: within
/// [`NARROW_LEVELS`] in one pixel in [`PICTURE_ONE_IN`] and no more than [`NARROW_WORST`] in
/// any, and the same bytes twice, bound once a pass (as a browser binds them) or through a plain
/// view too. Where the narrow cells splatted nothing, or dropped their colours' low bits
/// unrounded, or mis-ordered depths by their key, this fails.
#[test]
fn the_narrow_splat_cells_draw_what_the_wide_ones_draw() {
    let splats = (wgpu::Backends::VULKAN, true);
    for (name, scene) in shipped_scenes() {
        if !matches!(name, "landscape" | "trail" | "openworld") {
            continue;
        }
        let wide = portable_picture(&scene, splats);
        let narrow_modules = ShaderModules::built_in().with_narrow_splats(true);
        let narrow = portable_picture_of(&scene, splats, narrow_modules.clone());
        save_picture(&format!("{name}-portable-narrow-splats.png"), &narrow);
        let drawn = portable_picture(&scene, (wgpu::Backends::VULKAN, false));
        let (moved, _) = differing_pixels(&wide, &drawn, 0);
        let (over, worst) = differing_pixels(&narrow, &wide, NARROW_LEVELS);
        let (any, _) = differing_pixels(&narrow, &wide, 0);
        let pixels = wide.len() / 4;
        eprintln!("{name}: narrow against wide cells {any} pixels differ, {over} by more than {NARROW_LEVELS} levels (up to {worst}); the far field drawn differs in {moved}");
        assert!(any > 0 && moved > 0, "{name}: the narrow cells should differ from the wide ones in some pixels (the colour's low bits), as drawing the far field does");
        assert!(
            over * PICTURE_ONE_IN <= pixels && worst <= NARROW_WORST,
            "{name}: {over} pixels differ by more than {NARROW_LEVELS} levels, up to {worst}"
        );
        let again = portable_picture_of(&scene, splats, narrow_modules.clone());
        assert!(
            again == narrow,
            "{name}: the narrow cells gave other bytes the second time"
        );
        // Bound once a pass, as a browser binds them: their words read through the atomics.
        let single = portable_picture_of(&scene, splats, narrow_modules.clone().with_single_splat_binding(true));
        assert!(
            single == narrow,
            "{name}: the narrow cells bound once a pass gave other bytes than through their plain view"
        );
        // On llvmpipe's GL, which has no 64-bit atomics: the cells as a GL or WebGPU device
        // splats them, within WebGPU's default limits.
        let gl = (wgpu::Backends::GL, false);
        let on_gl = portable_picture_of(&scene, gl, narrow_modules.clone());
        save_picture(&format!("{name}-portable-gl-narrow-splats.png"), &on_gl);
        let (over, worst) = differing_pixels(&on_gl, &narrow, PICTURE_LEVELS);
        eprintln!("{name}: GL's narrow cells against lavapipe's: {over} pixels differ by more than {PICTURE_LEVELS} levels (up to {worst})");
        assert!(
            over * STREAMED_PICTURE_ONE_IN <= pixels,
            "{name}: GL's narrow cells differ from lavapipe's in {over} pixels"
        );
        let again = portable_picture_of(&scene, gl, narrow_modules);
        assert!(
            again == on_gl,
            "{name}: GL's narrow cells gave other bytes the second time"
        );
    }
    assert_nothing_logged();
}

/// The most storage buffers a splatting pass binds in a stage is what the portable renderer
/// asks of a device before it splats (`SPLAT_STORAGE_BUFFERS`): more, and a device that binds
/// that many would fail to make a pass; fewer, and one that binds enough would draw its far
/// field.
#[test]
fn a_device_splats_where_it_binds_the_storage_buffers_the_splatting_passes_bind() {
    let most_bound = |modules: &ShaderModules| {
        sward_core::wgsl::splatting::PORTABLE_SPLATTING
            .iter()
            .map(|pipeline| storage_buffers_bound(pipeline, modules))
            .max()
            .unwrap()
    };
    let narrow = ShaderModules::built_in().with_narrow_splats(true);
    assert_eq!(most_bound(&narrow), sward_wgpu::portable::SPLAT_STORAGE_BUFFERS);
    // A browser's: the cells bound once a pass.
    let single = narrow.with_single_splat_binding(true);
    assert_eq!(most_bound(&single), sward_wgpu::portable::SPLAT_STORAGE_BUFFERS - 1);
}

/// The most storage buffers a stage of `pipeline` composed of `modules` binds (naga's
/// reflection of the entry points' uses).
fn storage_buffers_bound(pipeline: &sward_wgpu::portable::PipelineSource, modules: &ShaderModules) -> u32 {
    let text = modules.text(pipeline).unwrap_or_else(|e| panic!("{e}"));
    let module = naga::front::wgsl::parse_str(&text).expect("parses");
    let capabilities = naga::valid::Capabilities::all();
    let info = naga::valid::Validator::new(naga::valid::ValidationFlags::all(), capabilities)
        .validate(&module)
        .unwrap_or_else(|e| panic!("{}: {e:?}", pipeline.name));
    stages(pipeline)
        .into_iter()
        .map(|(_, entry)| {
            let at = module.entry_points.iter().position(|e| e.name == entry).unwrap();
            let used = info.get_entry_point(at);
            module
                .global_variables
                .iter()
                .filter(|(handle, var)| {
                    matches!(var.space, naga::AddressSpace::Storage { .. }) && !used[*handle].is_empty()
                })
                .count() as u32
        })
        .max()
        .unwrap_or(0)
}

/// Levels (of 255) a pixel of the narrow splat cells may differ from the wide ones' by: the
/// colour's 5 and 6 bits in gamma 2 are 1/62 and 1/126 of the channel's square root, up to 8
/// levels of sRGB at mid grey after the resolve averages a pixel's cells.
const NARROW_LEVELS: u8 = 8;
/// The most a pixel of the narrow cells may differ by: where two blades' depths fall in one
/// key step, the one of the lesser colour wins the cell.
const NARROW_WORST: u8 = 32;

/// Each shipped scene the portable renderer draws, on wgpu's Vulkan backend (lavapipe: the far
/// field drawn, and splatted as the Vulkan renderer splats it) and GL backend (llvmpipe),
/// against the Vulkan renderer's strip route (where it splats, its compute route without the
/// compute rasterizer), the sun's shadows included
/// (the terrain's and the colliders'; the blades' too in one meadow). Both without
/// the Vulkan renderer's occlusion test (which leaves out a few blades it should not on the
/// hills and the planet: the difference is then the Vulkan renderer's).
#[test]
fn the_portable_renderer_draws_each_shipped_scene_as_the_vulkan_strip_route_does() {
    for (name, mut scene) in drawable_scenes() {
        scene.cull.occlusion = false;
        let reference = vulkan_strips(&scene);
        save_picture(&format!("{name}-vulkan-strips.png"), &reference);
        let splatted = vulkan_splatting(&scene);
        save_picture(&format!("{name}-vulkan-splatting.png"), &splatted);
        let sky = reference.chunks(4).filter(|p| p[1] <= p[2]).count();
        let pixels = reference.len() / 4;
        assert!(
            sky < pixels * 9 / 10,
            "{name}: the reference shows grass or ground, not only sky"
        );
        for on @ (backend, splats) in PORTABLE_ROUTES {
            let picture = portable_picture(&scene, on);
            save_picture(&format!("{name}-portable-{backend:?}-splats-{splats}.png"), &picture);
            let reference = if splats { &splatted } else { &reference };
            let (over, worst) = differing_pixels(&picture, reference, PICTURE_LEVELS);
            let one_in = if scene.tramples() {
                MOWN_PICTURE_ONE_IN
            } else if !scene.colliders.is_empty() {
                ROLLED_PICTURE_ONE_IN
            } else if scene.stream_window().is_some() {
                STREAMED_PICTURE_ONE_IN
            } else {
                PICTURE_ONE_IN
            };
            eprintln!("{name} on {on:?}: {over} pixels differ by more than {PICTURE_LEVELS} levels");
            if backend == wgpu::Backends::VULKAN {
                assert_shadows_drawn(name, &scene, &picture);
            }
            assert!(
                over * one_in <= pixels,
                "{name} on {on:?}: {over} of {pixels} pixels differ by more than {PICTURE_LEVELS} levels (at most {worst})"
            );
        }
    }
    assert_nothing_logged();
}

/// The shadow map's field cascade keeps its ground while what places it stays the same, as the
/// Vulkan renderer's: the first frame draws it into the cascade, the second keeps it apart and
/// copies it in, the third only copies it, each drawing the colliders over it. On wgpu's Vulkan
/// backend, the far field drawn and splatted: the planet's three frames give the same bytes, its
/// night side in shadow; the trample scene's second and third frames, its balls taken away
/// (the ground placed as before), give what a renderer that never drew the balls gives.
#[test]
fn the_kept_shadow_ground_draws_what_the_drawn_one_does() {
    let scenes = drawable_scenes();
    let scene = |name: &str| {
        let (_, mut scene) = scenes.iter().find(|(n, _)| *n == name).unwrap().clone();
        scene.cull.occlusion = false;
        scene
    };
    let (planet, trample) = (scene("planet"), scene("trample"));
    let mut unrolled = trample.clone();
    unrolled.colliders.clear();
    for on in [(wgpu::Backends::VULKAN, false), (wgpu::Backends::VULKAN, true)] {
        let frames = |scenes: &[&Scene]| -> Vec<Vec<u8>> {
            let samples = scenes[0].quality.preset.msaa_samples();
            let mut headless = headless_on(on, PICTURE, samples);
            let field = scenes[0].grow_field().unwrap();
            headless.upload(&field).unwrap();
            scenes
                .iter()
                .map(|scene| headless.render_scene(scene, field.size, 0).unwrap())
                .collect()
        };
        let same = |a: &[u8], b: &[u8], what: &str| {
            let (over, worst) = differing_pixels(a, b, 0);
            assert_eq!(over, 0, "{what} on {on:?}: {over} pixels differ (by up to {worst})");
        };
        let lit = frames(&[&planet, &planet, &planet]);
        same(&lit[0], &lit[1], "the planet's kept ground, kept anew");
        same(&lit[0], &lit[2], "the planet's kept ground");
        assert_shadows_drawn("planet", &planet, &lit[2]);
        let rolled = frames(&[&trample, &unrolled, &unrolled]);
        let never = frames(&[&unrolled]);
        same(&rolled[1], &never[0], "the trample scene's kept ground, kept anew");
        same(&rolled[2], &never[0], "the trample scene's kept ground");
    }
    assert_nothing_logged();
}

/// A JSON string of `text`.
fn json_string(text: &str) -> String {
    let mut out = String::from("\"");
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            c if (c as u32) < 0x20 => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// Blocks of 4 × 4 pixels (of one) the browser's picture may differ from lavapipe's in by more
/// than `PICTURE_LEVELS`. SwiftShader's shader math (its sine, cosine and powers) is not
/// llvmpipe's: the blades stand a fraction of a pixel apart, so 3–7 % of single pixels differ
/// at blades' edges (a level on average) while the blocks' means agree (seen: none of 2,700 by
/// more than 8 levels; the far field drawn in place of splatted: 8 and 73).
const BROWSER_BLOCKS_ONE_IN: usize = 500;

/// sward-web's page, built for the browser (`scripts/web-page.sh`), draws in headless Chromium's
/// WebGPU (SwiftShader) what the portable renderer draws on lavapipe, with no WebGPU error: the
/// far field in 32-bit splat cells (what a browser's device splats into) and drawn as geometry,
/// each within `BROWSER_BLOCKS_ONE_IN` of lavapipe's, the 32-bit cells the same bytes twice. The whole frame's passes run there, bound as the renderer binds them (a browser
/// refuses what naga and wgpu let by: one buffer bound twice to a pass where either is
/// writable).
#[test]
fn the_browser_page_draws_what_the_portable_renderer_draws_on_lavapipe() {
    let needs =
        "this test needs node, Chromium and the wasm32-unknown-unknown target (scripts/setup.sh --xvfb installs them)";
    let chromium = chromium().unwrap_or_else(|| panic!("{needs}: no Chromium found (SWARD_CHROMIUM names one)"));
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("web-page");
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let built = std::process::Command::new("bash")
        .args([&format!("{root}/scripts/web-page.sh"), dir.to_str().unwrap()])
        .output()
        .unwrap_or_else(|e| panic!("{needs}: bash does not run ({e})"));
    assert!(
        built.status.success(),
        "sward-web's page did not build: {}",
        String::from_utf8_lossy(&built.stderr)
    );
    let routes = [("splatted", true), ("drawn", false), ("splatted", true)];
    // The page reads a scene file, which holds a streamed field to its smallest budget: the
    // landscape (generated grass and billboards beyond streamed blades, a shot half a minute in
    // SwiftShader on two cores; the colliders' physics in the browser are the other test's).
    let scenes: Vec<(&str, Scene)> = shipped_scenes()
        .into_iter()
        .filter(|(name, _)| *name == "landscape")
        .map(|(name, mut scene)| {
            scene.field.blades = 1 << 16;
            (name, scene)
        })
        .collect();
    let shots: Vec<String> = scenes
        .iter()
        .flat_map(|(_, scene)| routes.map(|(route, _)| (scene.to_toml(), route)))
        .map(|(toml, route)| format!("{{\"toml\":{},\"route\":\"{route}\"}}", json_string(&toml)))
        .collect();
    let [width, height] = PICTURE;
    let plan = format!(
        "{{\"cases\":[],\"routes\":[],\"repeats\":0,\"width\":{width},\"height\":{height},\"shot_steps\":{PICTURE_STEPS},\"shots\":[{}]}}",
        shots.join(",")
    );
    std::fs::write(dir.join("plan.json"), plan).unwrap();
    run_page(&dir, &chromium, needs, false);
    let said = std::fs::read_to_string(dir.join("out-done")).unwrap();
    assert!(!said.contains("error:"), "the page said:\n{said}");
    let narrow = ShaderModules::built_in().with_narrow_splats(true);
    let mut wrong = Vec::new();
    for (k, (name, scene)) in scenes.iter().enumerate() {
        let shot = |r: usize| {
            let path = dir.join(format!("out-shot-{}.rgba", k * routes.len() + r));
            std::fs::read(&path).unwrap_or_else(|e| panic!("{name}: no picture from the page ({e}); it said:\n{said}"))
        };
        let lavapipe = [
            portable_picture_of(scene, (wgpu::Backends::VULKAN, true), narrow.clone()),
            portable_picture(scene, (wgpu::Backends::VULKAN, false)),
        ];
        for (r, (route, splatted)) in routes.iter().take(2).enumerate() {
            let browser = shot(r);
            save_picture(&format!("{name}-browser-{route}.png"), &browser);
            let reference = &lavapipe[usize::from(!splatted)];
            save_picture(&format!("{name}-lavapipe-{route}.png"), reference);
            let (pixels_over, _) = differing_pixels(&browser, reference, PICTURE_LEVELS);
            let (over, blocks, worst) = differing_blocks(&browser, reference, PICTURE_LEVELS);
            eprintln!("{name} {route} in the browser against lavapipe: {over} of {blocks} blocks differ by more than {PICTURE_LEVELS} levels (up to {worst}); {pixels_over} pixels");
            if over * BROWSER_BLOCKS_ONE_IN > blocks {
                wrong.push(format!("{name} {route}: the browser's picture differs from lavapipe's in {over} of {blocks} blocks of 4 × 4 pixels (up to {worst} levels)"));
            }
        }
        assert!(
            shot(2) == shot(0),
            "{name}: the browser's 32-bit cells gave other bytes the second time"
        );
        let (moved, _) = differing_pixels(&shot(0), &shot(1), 0);
        assert!(
            moved > 0,
            "{name}: the far field splatted should differ from it drawn in some pixels"
        );
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
    assert_nothing_logged();
}

/// The frame's uniforms for `desc` over a field of `blades`, as the portable renderer packs them.
fn packed(desc: &FrameDesc, blades: usize) -> Vec<u8> {
    let plan = sward_core::gpu::FramePlan {
        blade_count: blades as u32,
        ..sward_core::gpu::FramePlan::of(desc, RendererCan::strips())
    };
    sward_core::declared::frame_bytes(&FrameUniforms::pack(desc, &plan))
}

/// Headless Chromium's WebGPU (SwiftShader) compiles every portable pipeline's WGSL with no
/// error or warning and makes each pipeline (WebGPU's default limits), simulates a random field
/// with spheres and four winds summed 240 steps in frames of 24, and culls another for a random
/// camera: the results agree with sward-core's CPU reference as on wgpu's backends. Needs node
/// and Chromium (scripts/setup.sh installs both); without them it fails and says so.
#[test]
fn headless_chromiums_webgpu_compiles_every_pipeline_and_simulates_and_culls_as_the_cpu_reference() {
    let needs = "this test needs node and Chromium (scripts/setup.sh --xvfb installs them; Debian: apt-get install nodejs chromium)";
    let chromium = chromium().unwrap_or_else(|| panic!("{needs}: no Chromium found (SWARD_CHROMIUM names one)"));
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("browser-fixture");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    // Every portable pipeline, then the splatting passes in 32-bit cells (`narrow`), bound once
    // a pass as a browser's device binds them.
    let narrow = ShaderModules::built_in()
        .with_narrow_splats(true)
        .with_single_splat_binding(true);
    let listed = PIPELINES.iter().map(|p| (p, false));
    let splatting = sward_core::wgsl::splatting::PORTABLE_SPLATTING
        .iter()
        .map(|p| (p, true));
    let pipelines: Vec<String> = listed
        .chain(splatting)
        .map(|(p, narrowed)| {
            let fragment = p.fragment.map_or("null".to_string(), json_string);
            let modules = if narrowed { narrow.clone() } else { ShaderModules::built_in() };
            format!(
                "{{\"name\":{},\"entry\":{},\"fragment\":{fragment},\"vertex_only\":{},\"narrow\":{narrowed},\"code\":{},\"reads\":{:?}}}",
                json_string(p.name),
                json_string(p.entry),
                sward_wgpu::portable::vertex_only(p),
                json_string(&modules.browser_text(p).unwrap_or_else(|e| panic!("{e}"))),
                sward_portable::frame_blocks_read(p).unwrap_or_else(|e| panic!("{e}")),
            )
        })
        .collect();
    std::fs::write(dir.join("pipelines.json"), format!("[{}]", pipelines.join(","))).unwrap();
    // The binding numbers by name, as sward-core declares them for every shader.
    let bindings: Vec<String> = sward_core::declared::bindings::ALL
        .iter()
        .map(|(name, number)| format!("{}:{number}", json_string(name)))
        .collect();
    std::fs::write(dir.join("bindings.json"), format!("{{{}}}", bindings.join(","))).unwrap();
    let numbers: Vec<String> = sward_core::commands::ALL
        .iter()
        .map(|(name, number)| format!("{}:{number}", json_string(name)))
        .collect();
    std::fs::write(dir.join("numbers.json"), format!("{{{}}}", numbers.join(","))).unwrap();

    let mut rng = Pcg32::new(4242, 5);
    let kinds = [WindKind::Waves, WindKind::Radial, WindKind::Whirl, WindKind::Noise];
    let scene = random_scene(&mut rng, &kinds);
    let start = random_blades(&mut rng, BLADES, 6.0);
    let frames: Vec<u8> = (0..STEPS / STEPS_PER_FRAME)
        .flat_map(|k| {
            let time = (k * STEPS_PER_FRAME) as f32 * scene.simulation.step;
            packed(
                &FrameDesc::of_scene(&scene, Vec2::splat(30.0), (time, STEPS_PER_FRAME), [320, 240]),
                BLADES,
            )
        })
        .collect();
    std::fs::write(dir.join("simulate-blades.bin"), bytemuck::cast_slice(&start)).unwrap();
    std::fs::write(dir.join("simulate-frames.bin"), &frames).unwrap();
    std::fs::write(
        dir.join("frame-size.txt"),
        sward_core::declared::FRAME_BYTES.to_string(),
    )
    .unwrap();
    let blocks: Vec<String> = sward_core::declared::frame_blocks()
        .map(|(b, at, size)| format!("[{b},{at},{size}]"))
        .collect();
    std::fs::write(dir.join("frame-blocks.json"), format!("[{}]", blocks.join(","))).unwrap();

    let cull_blades = random_blades(&mut rng, 5003, 12.0);
    let mut cull_scene = Scene {
        camera: random_camera(&mut rng),
        cull: random_cull(&mut rng),
        ..Scene::default()
    };
    cull_scene.simulation.forces.wind = false;
    let cull_desc = FrameDesc::of_scene(&cull_scene, Vec2::splat(30.0), (0.0, 0), [320, 240]);
    std::fs::write(dir.join("cull-blades.bin"), bytemuck::cast_slice(&cull_blades)).unwrap();
    std::fs::write(dir.join("cull-frame.bin"), packed(&cull_desc, cull_blades.len())).unwrap();

    run_page(&dir, &chromium, needs, false);
    let read = |name: &str| {
        std::fs::read(dir.join(format!("out-{name}"))).unwrap_or_else(|e| panic!("no {name} from the page: {e}"))
    };
    let said = String::from_utf8(read("done")).unwrap();
    let (adapter, problems): (Vec<&str>, Vec<&str>) = said.lines().partition(|l| l.starts_with("adapter:"));
    let (narrow_made, problems): (Vec<&str>, Vec<&str>) = problems.into_iter().partition(|l| l.starts_with("narrow:"));
    let all = sward_core::wgsl::splatting::PORTABLE_SPLATTING.len();
    assert!(
        narrow_made.len() == 1 && narrow_made[0].starts_with(&format!("narrow: {all} of {all} ")),
        "the browser should make every splatting pipeline in 32-bit cells: {narrow_made:?}; it said:\n{said}"
    );
    assert_eq!(adapter.len(), 1, "the page found no WebGPU adapter: {said}");
    // SwiftShader's WebGPU has subgroups: the page culls with the passes that use them.
    assert!(
        adapter[0].ends_with("with subgroups"),
        "the browser's adapter has no subgroups: {}",
        adapter[0]
    );
    assert!(
        problems.is_empty(),
        "WebGPU ({}) said:\n{}",
        adapter[0],
        problems.join("\n")
    );

    let gpu_blades: Vec<Blade> = bytemuck::pod_collect_to_vec(&read("simulated-blades"));
    let gpu_etas: Vec<f32> = bytemuck::pod_collect_to_vec(&read("simulated-etas"));
    check_simulation(
        &start,
        (&gpu_blades, &gpu_etas),
        &scene,
        &format!("WebGPU ({})", adapter[0]),
    );

    let visible: Vec<u32> = bytemuck::pod_collect_to_vec(&read("visible"));
    let mut draws: Vec<DrawCommand> = bytemuck::pod_collect_to_vec(&read("draws"));
    draws.truncate(DISTANCE_BUCKETS as usize);
    let counters: Vec<u32> = bytemuck::pod_collect_to_vec(&read("counters"));
    let starts = &counters[sward_core::commands::counters::BUCKET_STARTS as usize..];
    for (draw, &start) in draws.iter_mut().zip(starts) {
        assert_eq!(
            draw.first_instance, 0,
            "a command's first instance needs a feature WebGPU lacks by default"
        );
        draw.first_instance = start;
    }
    let listed = draws.iter().map(|d| d.instance_count as usize).sum::<usize>();
    let seen = check_cull(
        &visible[..listed],
        &draws,
        &cull_blades,
        (&cull_scene, &cull_desc),
        "WebGPU",
    );
    let lists = (&visible[..listed], &draws[..]);
    assert_in_draw_order(lists, (&cull_blades, &cull_desc), u64::from, "WebGPU");
    assert!(seen > 0, "the camera should see some blades");
}

/// A dense field seen from among its blades, where the nearest blades hide most of the rest.
fn dense_field_seen_low() -> Scene {
    let mut scene = Scene::from_toml(include_str!("../../../scenes/meadow.toml"), "meadow").unwrap();
    scene.field.blades = 12_000;
    scene.field.size = Vec2::splat(6.0);
    scene.camera.position = glam::Vec3::new(0.0, 0.35, -3.2);
    scene.camera.target = glam::Vec3::new(0.0, 0.3, 0.0);
    scene.shading.shadows = false;
    scene
}

/// The bench's cis565 scene at its 2^24 blades' density (2^19 on a field 2.65 m square): a
/// plane seen from a metre up, where the nearest blades the last frame listed hide most of the
/// rest.
fn dense_cis565() -> Scene {
    let size = ("field.size".to_string(), "[2.65, 2.65]".to_string());
    Scene::cis565(1 << 19).with_overrides(&[size]).unwrap()
}

/// Both renderers hide the same blades behind the same occluders: the bench's cis565 field at
/// 2^24's density (2^19 blades on 2.65 m), frame by frame as the bench runs it (the last
/// frame's nearest blades into the depth pyramid, a step, the cull), on lavapipe: the same
/// blades listed every frame in the same order, and where both pyramids hold an occluder its
/// depth within a millimetre. (With the Vulkan renderer's blade occluders drawn depth-biased as
/// the sun's shadow casters are, its pyramid lay 1–10 cm deeper in a fifth of its texels and it
/// listed 1.7 % more; the picture showed nothing, the visible count did. With the portable
/// renderer's tiles sorted by exact distance, the Vulkan renderer's by its GPU's coarser key,
/// a bucket's blades came in another order, and a budget ending inside a bucket took other
/// occluders from it.)
#[test]
fn the_portable_renderer_hides_the_blades_the_vulkan_renderer_hides() {
    let scene = dense_cis565();
    let field = scene.grow_field().unwrap();
    let [width, height] = PICTURE;
    let ctx = sward_gpu::Context::new(&sward_gpu::ContextDesc {
        validation: sward_gpu::Validation::Required,
        ..Default::default()
    })
    .unwrap_or_else(|e| panic!("{}: {e}", support::NEEDS));
    let mut vulkan = sward_gpu::Headless::new(&ctx, width, height, None).unwrap();
    vulkan.renderer.upload(&field).unwrap();
    vulkan.renderer.upload_ground(field.ground.as_ref()).unwrap();
    let (adapter, device, queue) = portable_device_on((wgpu::Backends::VULKAN, true));
    let mut portable = PortableRenderer::new(&adapter, &device).unwrap();
    portable.upload_ground(&device, field.ground.as_ref());
    let mut blades = PortableField::with_tiles(&device, &field.blades, field.tiles.clone()).unwrap();
    let view_depth =
        |z: f32| scene.camera.near * scene.camera.far / (scene.camera.far - z * (scene.camera.far - scene.camera.near));
    for frame in 0..4 {
        let desc = vulkan.frame(&scene, field.size, (frame as f32 * scene.simulation.step, 1));
        let compute = sward_gpu::Passes {
            draw: false,
            ..sward_gpu::Passes::ALL
        };
        vulkan.renderer.run_compute(&desc, compute).unwrap();
        // Occluders, step, cull, in the order the Vulkan renderer runs them.
        let mut encoder = device.create_command_encoder(&Default::default());
        portable.record(&device, &queue, &mut encoder, &desc, &mut blades, PortablePasses::ALL);
        queue.submit([encoder.finish()]);
        let reference = vulkan.renderer.read_visible().unwrap().0;
        let ours = blades.read_visible(&device, &queue, 0).unwrap().0;
        let set = |list: &[u32]| list.iter().copied().collect::<std::collections::HashSet<u32>>();
        let apart = set(&reference).symmetric_difference(&set(&ours)).count();
        let order = reference.iter().zip(&ours).position(|(a, b)| a != b);
        eprintln!(
            "cis565 frame {frame}: the Vulkan renderer lists {}, the portable renderer {}, {apart} listed by one only, the order first differs at {order:?}",
            reference.len(),
            ours.len()
        );
        assert!(reference.len() > 10_000, "the camera should see many blades");
        assert_eq!(apart, 0, "frame {frame}: blades listed by one renderer only");
        assert_eq!(order, None, "frame {frame}: the lists' order");
        let theirs = &vulkan.renderer.read_depth_pyramid().unwrap()[0];
        let mine = portable.read_pyramid(&device, &queue, 0).unwrap();
        let both = theirs.iter().copied().zip(mine.iter().map(|&d| f32::from_bits(d)));
        let apart = both
            .filter(|&(a, b)| a < 1.0 && b < 1.0 && (view_depth(a) - view_depth(b)).abs() > 1e-3)
            .count();
        assert_eq!(
            apart, 0,
            "frame {frame}: pyramid texels whose occluders lie more than 1 mm apart"
        );
    }
    let messages = ctx.take_validation_messages();
    assert!(messages.is_empty(), "Vulkan validation: {messages:?}");
    assert_nothing_logged();
}

/// The occlusion test on wgpu's Vulkan and GL backends: the depth pyramid's every level holds
/// the farthest depth of the 2 × 2 texels under it; among dense blades seen low, the nearest
/// blades the last frame listed hide more than half of the rest; and no shipped scene's picture
/// changes for it. (With the pyramid in a mipmapped texture, lavapipe lost blades near the
/// planet's limb, 537 pixels at 320×240, and wgpu's GL backend lost the coarser levels: the
/// pyramid is in a storage buffer for that.)
#[test]
fn the_portable_occlusion_test_culls_what_is_hidden_and_keeps_the_picture() {
    for backend in [wgpu::Backends::VULKAN, wgpu::Backends::GL] {
        let scene = dense_field_seen_low();
        let count = |occlusion: bool| {
            let mut scene = scene.clone();
            scene.cull.occlusion = occlusion;
            let mut headless = headless_on((backend, false), PICTURE, 4);
            let field = scene.grow_field().unwrap();
            headless.upload(&field).unwrap();
            // The second frame's pyramid holds the nearest blades the first listed.
            headless.render_scene(&scene, field.size, 0).unwrap();
            let picture = headless.render_scene(&scene, field.size, 0).unwrap();
            (headless.visible_count().unwrap(), picture, headless)
        };
        let (without, open, _) = count(false);
        let (with, hidden, headless) = count(true);
        assert!(
            with * 2 < without,
            "{backend:?}: occlusion listed {with} blades of the {without} in view"
        );
        let (over, worst) = differing_pixels(&hidden, &open, PICTURE_LEVELS);
        assert!(
            over * PICTURE_ONE_IN <= open.len() / 4,
            "{backend:?}: occlusion changed {over} pixels (at most {worst} levels)"
        );
        check_pyramid_levels(&headless, backend);
        for (name, mut scene) in drawable_scenes() {
            scene.shading.shadows = false;
            let open = portable_picture(
                &Scene {
                    cull: sward_core::cull::CullParams {
                        occlusion: false,
                        ..scene.cull
                    },
                    ..scene.clone()
                },
                (backend, false),
            );
            let culled = portable_picture(&scene, (backend, false));
            let (over, worst) = differing_pixels(&culled, &open, PICTURE_LEVELS);
            assert!(
                over * PICTURE_ONE_IN <= open.len() / 4,
                "{name} on {backend:?}: occlusion changed {over} pixels (at most {worst} levels)"
            );
        }
    }
    assert_nothing_logged();
}

/// Fields placed around one camera, culled together (`record_fields_view`) or each alone:
/// each field's visible blades after two frames (the second's pyramid holds the nearest
/// blades the first listed), sorted.
fn placed_fields_listed(backend: wgpu::Backends, scene: &Scene, at: &[glam::Vec3], together: bool) -> Vec<Vec<u32>> {
    use sward_core::placement::Placement;
    use sward_wgpu::portable::FieldView;
    let (_, device, queue, first) = portable_renderer(backend);
    let grown = scene.grow_field().unwrap();
    let mut renderers: Vec<PortableRenderer> = at.iter().map(|_| first.sibling(&device)).collect();
    let mut fields: Vec<PortableField> = at
        .iter()
        .map(|_| PortableField::with_tiles(&device, &grown.blades, grown.tiles.clone()).unwrap())
        .collect();
    let world = FrameDesc::of_scene(scene, grown.size, (0.0, 0), [320, 240]);
    let descs: Vec<FrameDesc> = at
        .iter()
        .map(|&p| {
            let placement = Placement::from_scale_rotation_translation(glam::Vec3::ONE, glam::Quat::IDENTITY, p);
            world.clone().placed(placement, placement)
        })
        .collect();
    for _ in 0..2 {
        let mut encoder = device.create_command_encoder(&Default::default());
        let views = renderers.iter_mut().zip(fields.iter_mut()).zip(&descs);
        let mut views: Vec<FieldView> = views
            .map(|((renderer, field), desc)| FieldView {
                renderer,
                field,
                desc,
                passes: PortablePasses::CULL,
                view: 0,
            })
            .collect();
        match together {
            true => PortableRenderer::record_fields_view(&device, &queue, &mut encoder, &mut views),
            false => {
                for v in views {
                    v.renderer
                        .record_view(&device, &queue, &mut encoder, (v.desc, 0), v.field, v.passes);
                }
            }
        }
        queue.submit([encoder.finish()]);
    }
    fields
        .iter()
        .map(|field| {
            let (mut ids, _) = field.read_visible(&device, &queue, 0).unwrap();
            ids.sort_unstable();
            ids
        })
        .collect()
}

/// Several fields seen by one camera are culled against one depth pyramid holding all their
/// occluders, built once: a field under another's ground is hidden by it (each alone, it is
/// not); a field beside and below it is not (a plane hides no more than its own field's area:
/// reaching to the horizon, it would hide that field too); and the field on top lists exactly
/// what it lists alone.
#[test]
fn fields_culled_together_hide_each_other_behind_their_grounds_and_no_further_on_vulkan() {
    fields_culled_together(wgpu::Backends::VULKAN);
}

#[test]
fn fields_culled_together_hide_each_other_behind_their_grounds_and_no_further_on_gl() {
    fields_culled_together(wgpu::Backends::GL);
}

/// [`fields_culled_together_hide_each_other_behind_their_grounds_and_no_further_on_vulkan`] on
/// `backend`.
fn fields_culled_together(backend: wgpu::Backends) {
    use glam::Vec3;
    let mut scene = Scene::default();
    scene.field.blades = 4000;
    scene.field.size = Vec2::splat(6.0);
    scene.field.height = [0.25, 0.4];
    scene.camera.position = Vec3::new(0.0, 12.0, -3.0);
    scene.camera.target = Vec3::new(0.0, -1.0, 0.0);
    scene.cull.occlusion = true;
    // No blade shadows: a blade casting into the near cascade is kept, hidden or not.
    scene.shading.shadows = false;
    // On top; under it; beside it and lower.
    let at = [Vec3::ZERO, Vec3::new(0.0, -3.0, 0.0), Vec3::new(7.0, -1.0, 0.0)];
    let alone = placed_fields_listed(backend, &scene, &at, false);
    let together = placed_fields_listed(backend, &scene, &at, true);
    let counts = |lists: &[Vec<u32>]| lists.iter().map(Vec::len).collect::<Vec<_>>();
    let (alone_counts, together_counts) = (counts(&alone), counts(&together));
    assert!(
        alone_counts.iter().all(|&n| n > 200),
        "{backend:?}: each field alone should list blades: {alone_counts:?}"
    );
    // Those left stand near the edge of the other's ground on screen, where the pyramid's
    // coarse texels a blade's box is tested at reach past it (lavapipe: 163 of 3878).
    assert!(
        together_counts[1] * 10 < alone_counts[1],
        "{backend:?}: the field under the other's ground listed {} of its {} blades",
        together_counts[1],
        alone_counts[1]
    );
    assert_eq!(together[0], alone[0], "the field on top listed other blades together");
    assert_eq!(
        together[2], alone[2],
        "the field beside and below was hidden: {together_counts:?} against {alone_counts:?}"
    );
    assert_nothing_logged();
}

/// Each level of `headless`'s depth pyramid above the first is the farthest of the 2 × 2 below.
fn check_pyramid_levels(headless: &PortableHeadless, backend: wgpu::Backends) {
    let read = |level| {
        headless
            .renderer
            .read_pyramid(&headless.device, &headless.queue, level)
            .unwrap()
    };
    let mut below = read(0);
    let far = 1.0f32.to_bits();
    assert!(
        below.iter().any(|&d| d < far),
        "{backend:?}: nothing drawn into the pyramid"
    );
    for level in 1..10 {
        let level_now = read(level);
        let side = 512 >> level;
        for y in 0..side {
            for x in 0..side {
                let at = |dx, dy| below[(2 * y + dy) * 2 * side + 2 * x + dx];
                let farthest = [at(0, 0), at(1, 0), at(0, 1), at(1, 1)].into_iter().max().unwrap();
                assert_eq!(
                    level_now[y * side + x],
                    farthest,
                    "{backend:?}: level {level} texel ({x}, {y})"
                );
            }
        }
        below = level_now;
    }
}

#[test]
fn the_portable_trample_map_and_the_blades_it_holds_match_the_cpu_reference_on_vulkan() {
    trample_matches_the_cpu_reference(wgpu::Backends::VULKAN);
}

#[test]
fn the_portable_trample_map_and_the_blades_it_holds_match_the_cpu_reference_on_gl() {
    trample_matches_the_cpu_reference(wgpu::Backends::GL);
}

/// A field of Bezier blades with a ball pressing and a cutter mowing for five frames, then
/// neither as the eye walks on (the trails fade, the cut grows back), on `backend`: each frame
/// the portable trample map's texels are sward-core's `TrampleMap`'s, and the blades it holds
/// down and mows are what sward-core's `step_trampled_blade` makes of them with that map's
/// texel at each root — within the parity tolerance, for blades held and mown in numbers.
fn trample_matches_the_cpu_reference(backend: wgpu::Backends) {
    use glam::Vec3;
    use sward_core::physics::{step_trampled_blade, Collider};
    use sward_core::trample::{TrampleMap, TrampleParams};

    let (on, device, queue, mut renderer) = portable_renderer(backend);
    let ball = Collider::sphere(Vec3::new(1.2, 0.3, 1.0), 0.6);
    // Its underside 0.3 units above the ground, in grass about a unit tall.
    let cutter = Collider {
        cut: true,
        ..Collider::sphere(Vec3::new(-1.5, 1.1, -0.5), 0.8)
    };
    let mut scene = Scene::default();
    scene.field.blades = 3000;
    scene.field.size = Vec2::splat(8.0);
    scene.field.height = [0.8, 1.1];
    scene.trample = TrampleParams {
        enabled: true,
        resolution: 96,
        extent: 24.0,
        regrow: 0.5,
    };
    scene.simulation.eta_decay = 0.6;
    let field = scene.grow_field().unwrap();
    let mut gpu_field = PortableField::new(&device, &field.blades).unwrap();
    let mut cpu_blades = field.blades.clone();
    let mut cpu_etas = vec![0.0; cpu_blades.len()];
    let mut map = TrampleMap::new(scene.trample);
    let grass_top = scene.instanced.grid.height[1].max(scene.billboard.grid.height[1]);
    let steps = 6;
    let mut eye = Vec3::new(0.0, 1.7, -6.0);
    let (mut held, mut mown) = (0, 0);
    for frame in 0..10 {
        scene.colliders = if frame < 5 {
            vec![ball.clone(), cutter.clone()]
        } else {
            Vec::new()
        };
        scene.camera.position = eye;
        let time = (frame * steps) as f32 * scene.simulation.step;
        let mut desc = FrameDesc::of_scene(&scene, field.size, (time, steps), [320, 240]);
        // The map runs for a cutter in a Bezier field; on for the frames after it too.
        desc.trample = Some(scene.trample);
        let mut encoder = device.create_command_encoder(&Default::default());
        renderer.record(
            &device,
            &queue,
            &mut encoder,
            &desc,
            &mut gpu_field,
            PortablePasses::SIMULATE,
        );
        queue.submit([encoder.finish()]);

        let dt = steps as f32 * scene.simulation.step;
        map.step(eye, &scene.colliders, grass_top, scene.simulation.eta_decay, dt);
        let pushing: Vec<Collider> = scene.colliders.iter().filter(|c| !c.cut).cloned().collect();
        for (blade, eta) in cpu_blades.iter_mut().zip(&mut cpu_etas) {
            let root = Vec2::new(blade.v0.x, blade.v0.z);
            let (push, cut) = (map.push_at(root, eye), map.cut_at(root, eye));
            let cut = if cut > 0.0 { cut } else { f32::INFINITY };
            held += usize::from(push.length() > 0.2 && frame == 4);
            mown += usize::from(cut < blade.height() && frame == 4);
            for k in 0..steps {
                let t = time + k as f32 * scene.simulation.step;
                step_trampled_blade(blade, eta, &scene.simulation, (&pushing, &scene.wind), t, (cut, push));
            }
        }

        let texels = renderer.read_trample_map(&device, &queue).unwrap();
        assert_eq!(texels.len(), map.texels.len(), "{on}: texels");
        for (k, (cpu, gpu)) in map.texels.iter().zip(&texels).enumerate() {
            assert!(
                cpu.tag == gpu.tag && (cpu.push - gpu.push).length() < 1e-4 && (cpu.cut - gpu.cut).abs() < 1e-4,
                "{on}, frame {frame}, texel {k}: CPU {cpu:?}, GPU {gpu:?}"
            );
        }
        let (gpu_blades, gpu_etas) = gpu_field.read(&device, &queue).unwrap();
        let (err, i, what) = worst_error(&gpu_blades, &gpu_etas, &cpu_blades, &cpu_etas, &[]);
        assert!(
            err <= TOLERANCE,
            "{on}, frame {frame}: blade {i} {what} differs by {err:e} (GPU {:?} η {} vs CPU {:?} η {})",
            gpu_blades[i],
            gpu_etas[i],
            cpu_blades[i],
            cpu_etas[i]
        );
        eye += Vec3::new(0.4, 0.0, 0.3);
    }
    assert!(
        held > 40 && mown > 40,
        "{on}: the map held {held} blades and mowed {mown}"
    );
    assert_nothing_logged();
}

#[test]
fn the_portable_tiles_run_only_the_tiles_near_the_view_and_list_what_the_whole_field_would_on_vulkan() {
    tiles_cull_as_the_whole_field(wgpu::Backends::VULKAN);
}

#[test]
fn the_portable_tiles_run_only_the_tiles_near_the_view_and_list_what_the_whole_field_would_on_gl() {
    tiles_cull_as_the_whole_field(wgpu::Backends::GL);
}

/// A field grown in tiles (40,000 blades, 10 tiles) seen by a camera walking and turning over
/// it, on `backend`: each frame lists exactly the CPU reference's visible blades of the whole
/// field (a tile outside the view holds none), while the frames run only some of the tiles; and
/// a frame that steps the grass moves the blades of the tiles it runs and no other.
fn tiles_cull_as_the_whole_field(backend: wgpu::Backends) {
    use glam::Vec3;
    let (_, device, queue, mut renderer) = portable_renderer(backend);
    let mut scene = Scene::default();
    scene.field.blades = 40_000;
    scene.field.size = Vec2::splat(40.0);
    scene.cull.occlusion = false;
    scene.cull.distance_max = 60.0;
    let grown = scene.grow_field().unwrap();
    assert!(grown.tiles.len() >= 8, "{} tiles", grown.tiles.len());
    let mut field = PortableField::with_tiles(&device, &grown.blades, grown.tiles.clone()).unwrap();
    let mut fewest = usize::MAX;
    for frame in 0..6 {
        let angle = frame as f32 * 1.1;
        let eye = Vec3::new(-12.0 + 5.0 * frame as f32, 1.7, -8.0 + 3.0 * frame as f32);
        scene.camera.position = eye;
        scene.camera.target = eye + Vec3::new(angle.cos(), -0.25, angle.sin());
        let desc = FrameDesc::of_scene(&scene, grown.size, (0.0, 0), [320, 240]);
        let mut encoder = device.create_command_encoder(&Default::default());
        renderer.record(&device, &queue, &mut encoder, &desc, &mut field, PortablePasses::CULL);
        queue.submit([encoder.finish()]);
        let (listed, draws) = field.read_visible(&device, &queue, 0).unwrap();
        let seen = check_cull(
            &listed,
            &draws,
            &grown.blades,
            (&scene, &desc),
            &format!("frame {frame}"),
        );
        assert!(
            seen > 100,
            "frame {frame}: the camera should see the grass ({seen} blades)"
        );
        let run = field
            .read_tiles_run(&device, &queue, 0)
            .unwrap()
            .expect("the field has tiles");
        let tile_of = |id: u32| run.iter().position(|t| (t.first..t.first + t.count).contains(&id));
        let rank = |id: u32| ((tile_of(id).expect("a listed blade's tile ran") as u64) << 32) | u64::from(id);
        let case = format!("frame {frame}");
        assert_in_draw_order((&listed, &draws), (&grown.blades, &desc), rank, &case);
        fewest = fewest.min(run.len());
    }
    assert!(
        fewest < grown.tiles.len() * 3 / 4,
        "the walk should leave tiles out: at fewest {fewest} of {} run",
        grown.tiles.len()
    );

    // A frame that steps the wind: the blades of the tiles it ran move, the others stand.
    let desc = FrameDesc::of_scene(&scene, grown.size, (0.0, 12), [320, 240]);
    let mut encoder = device.create_command_encoder(&Default::default());
    renderer.record(&device, &queue, &mut encoder, &desc, &mut field, PortablePasses::ALL);
    queue.submit([encoder.finish()]);
    let run = field.read_tiles_run(&device, &queue, 0).unwrap().unwrap();
    let (blades, _) = field.read(&device, &queue).unwrap();
    let ran = |i: usize| run.iter().any(|t| (t.first..t.first + t.count).contains(&(i as u32)));
    let moved = |i: usize| blades[i].tip().distance(grown.blades[i].tip()) > 1e-6;
    let (mut stepped, mut stood) = (0, 0);
    for i in 0..blades.len() {
        assert_eq!(ran(i), moved(i), "blade {i}: ran {} moved {}", ran(i), moved(i));
        stepped += usize::from(ran(i));
        stood += usize::from(!ran(i));
    }
    assert!(
        stepped > 1000 && stood > 1000,
        "{stepped} blades stepped, {stood} stood"
    );
    assert_nothing_logged();
}

#[test]
fn the_callers_depth_hides_the_grass_behind_its_scene_on_vulkan() {
    for samples in [1, 4] {
        callers_depth_hides_the_grass_behind_it(wgpu::Backends::VULKAN, samples);
    }
}

/// wgpu's GL backend cannot read a depth texture in a compute shader (naga's GLSL): the
/// caller's depth is refused in one sentence, and the renderer culls on without it.
#[test]
fn the_callers_depth_is_refused_in_one_sentence_on_gl() {
    let (_, device, queue, mut renderer) = portable_renderer(wgpu::Backends::GL);
    let depth = callers_depth(&device, [64, 48], 1);
    let given = sward_wgpu::portable::CallerDepth {
        view: &depth,
        samples: 1,
    };
    let said = renderer
        .set_caller_depth(&device, 0, Some(given))
        .unwrap_err()
        .to_string();
    assert!(
        said.contains("GL backend") && said.contains("not folded") && !said.contains('\n'),
        "{said}"
    );
    let scene = dense_field_seen_low();
    let field = scene.grow_field().unwrap();
    let mut gpu_field = PortableField::with_tiles(&device, &field.blades, field.tiles.clone()).unwrap();
    let desc = FrameDesc::of_scene(&scene, field.size, (0.0, 0), [64, 48]);
    let mut encoder = device.create_command_encoder(&Default::default());
    renderer.record(
        &device,
        &queue,
        &mut encoder,
        &desc,
        &mut gpu_field,
        PortablePasses::CULL,
    );
    queue.submit([encoder.finish()]);
    assert!(gpu_field.visible_count(&device, &queue).unwrap() > 0);
    assert_nothing_logged();
}

/// An engine's depth of the view (`samples` per pixel), folded into the depth pyramid on
/// `backend`: a wall at the far plane hides nothing (the same list as without it); a wall at
/// 4 units hides the grass beyond it and none before it; a wall at the near plane hides it all.
fn callers_depth_hides_the_grass_behind_it(backend: wgpu::Backends, samples: u32) {
    use glam::Vec3;
    let (_, device, queue, mut renderer) = portable_renderer(backend);
    let mut scene = Scene::default();
    scene.field.blades = 12_000;
    scene.field.size = Vec2::splat(12.0);
    scene.field.height = [0.25, 0.4];
    scene.camera.position = Vec3::new(0.0, 2.0, -7.0);
    scene.camera.target = Vec3::new(0.0, 0.0, 0.0);
    scene.cull.occlusion = true;
    // No blade shadows: a blade casting into the near cascade is kept, hidden or not.
    scene.shading.shadows = false;
    let grown = scene.grow_field().unwrap();
    let mut field = PortableField::with_tiles(&device, &grown.blades, grown.tiles.clone()).unwrap();
    let [width, height] = [320, 240];
    let desc = FrameDesc::of_scene(&scene, grown.size, (0.0, 0), [width, height]);
    let depth = callers_depth(&device, [width, height], samples);
    let mut listed = |wall: Option<f32>| {
        let mut encoder = device.create_command_encoder(&Default::default());
        if let Some(at) = wall {
            // The engine's scene: a wall across the whole view at depth `at`.
            encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(at),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                ..Default::default()
            });
        }
        queue.submit([encoder.finish()]);
        let given = wall.map(|_| sward_wgpu::portable::CallerDepth { view: &depth, samples });
        renderer.set_caller_depth(&device, 0, given).unwrap();
        // The second frame's pyramid holds the nearest blades the first listed, as every frame's.
        for _ in 0..2 {
            let mut encoder = device.create_command_encoder(&Default::default());
            renderer.record(&device, &queue, &mut encoder, &desc, &mut field, PortablePasses::CULL);
            queue.submit([encoder.finish()]);
        }
        let (mut ids, _) = field.read_visible(&device, &queue, 0).unwrap();
        ids.sort_unstable();
        ids
    };
    let alone = listed(None);
    let case = format!("{backend:?}, {samples} samples");
    assert!(alone.len() > 300, "{case}: {} blades listed", alone.len());
    assert_eq!(listed(Some(1.0)), alone, "{case}: a wall at the far plane hid grass");
    // A wall at the near plane hides every blade wholly on screen (a blade reaching off it is
    // never hidden: the frustum test's business, as in the Vulkan renderer).
    let view_proj = desc.camera.view_projection();
    let eye = desc.camera.eye;
    let on_screen = |i: &u32| {
        let b = grown.blades[*i as usize];
        [b.root(), b.midpoint(), b.tip()].iter().all(|p| {
            let clip = view_proj * p.extend(1.0);
            clip.w > 0.0 && (clip.x / clip.w).abs() < 1.0 && (clip.y / clip.w).abs() < 1.0
        })
    };
    let seen = alone.iter().filter(|i| on_screen(i)).count();
    assert!(seen > 50, "{case}: {seen} blades wholly on screen");
    let left: Vec<u32> = listed(Some(0.0)).into_iter().filter(on_screen).collect();
    assert!(
        left.is_empty(),
        "{case}: a wall at the near plane left {} of the {seen} blades wholly on screen",
        left.len()
    );
    // A wall 4 units ahead: the grass nearer than 3 units stays, most beyond 5 goes.
    let ahead = (scene.camera.target - eye).normalize();
    let clip = view_proj * (eye + 4.0 * ahead).extend(1.0);
    let kept = listed(Some(clip.z / clip.w));
    let distance = |i: &u32| grown.blades[*i as usize].root().distance(eye);
    let near: Vec<u32> = alone.iter().copied().filter(|i| distance(i) < 3.0).collect();
    assert!(near.len() > 20, "{case}: {} blades near the eye", near.len());
    assert!(
        near.iter().all(|i| kept.binary_search(i).is_ok()),
        "{case}: the wall hid grass in front of it"
    );
    let far = |list: &[u32]| list.iter().filter(|i| distance(i) > 5.0).count();
    assert!(
        far(&kept) * 4 < far(&alone),
        "{case}: the wall left {} of the {} blades beyond it",
        far(&kept),
        far(&alone)
    );
    assert_nothing_logged();
}

#[test]
fn a_streamed_window_makes_each_entering_tile_as_the_cpu_reference_and_the_vulkan_renderer_on_vulkan() {
    streamed_window_matches(wgpu::Backends::VULKAN);
}

#[test]
fn a_streamed_window_makes_each_entering_tile_as_the_cpu_reference_and_the_vulkan_renderer_on_gl() {
    streamed_window_matches(wgpu::Backends::GL);
}

/// A streamed field of 3 × 3 tiles walked by the eye — a tile and a bit, a jump of a kilometre,
/// then a step over the frame origin's boundary that moves the origin with most tiles kept —
/// made by the portable renderer and by the Vulkan renderer: after each frame every slot holds
/// the blades of the world tile the window puts there, each blade's root, facing, height, width
/// and stiffness those of the CPU reference (`stream::tile_blades`) at the origin both renderers
/// report, and its settled shape the Vulkan renderer's within 1e-3; the tiles entering are
/// those the eye walked into.
fn streamed_window_matches(backend: wgpu::Backends) {
    use glam::Vec3;
    use sward_core::stream::tile_blades;
    use sward_core::tiles::TILE_BLADES;
    let (_, device, queue, mut renderer) = portable_renderer(backend);
    let mut scene = Scene::default();
    scene.field.stream = true;
    scene.field.blades = 9 * TILE_BLADES;
    let window = scene.stream_window().expect("the scene streams");
    assert_eq!(window.tiles, 3);
    let grown = scene.grow_field().unwrap();
    let mut field = PortableField::streamed(&device, window).unwrap();
    let ctx = sward_gpu::Context::new(&sward_gpu::ContextDesc {
        validation: sward_gpu::Validation::Required,
        ..Default::default()
    })
    .unwrap_or_else(|e| panic!("{}: {e}", support::NEEDS));
    let mut vulkan = sward_gpu::Headless::new(&ctx, 64, 64, None).unwrap();
    vulkan.renderer.upload(&grown).unwrap();
    let tile = window.tile_size();
    let walk = [(0.0, 9), (tile, 3), (1020.0, 9), (1020.0 + tile, 3)];
    let mut held = [None; 9];
    for (frame, (x, entering)) in walk.into_iter().enumerate() {
        let eye = Vec3::new(x, 1.7, 0.5);
        scene.camera.position = eye;
        scene.camera.target = eye + Vec3::new(1.0, -0.3, 0.2);
        let desc = FrameDesc::of_scene(&scene, grown.size, (0.5, 0), [64, 64]);
        let mut encoder = device.create_command_encoder(&Default::default());
        renderer.record(&device, &queue, &mut encoder, &desc, &mut field, PortablePasses::ALL);
        queue.submit([encoder.finish()]);
        let compute = sward_gpu::Passes {
            draw: false,
            ..sward_gpu::Passes::ALL
        };
        vulkan.renderer.run_compute(&desc, compute).unwrap();
        let (blades, _) = field.read(&device, &queue).unwrap();
        let origin = field.origin();
        assert_eq!(
            origin,
            vulkan.renderer.origin(),
            "frame {frame}: the frame origins differ"
        );
        let base = window.base(eye);
        let now: Vec<_> = (0..9).map(|slot| Some(window.tile_in(slot, base))).collect();
        let entered = held.iter().zip(&now).filter(|(was, is)| was != is).count();
        assert_eq!(
            entered, entering,
            "frame {frame}: the walk should bring {entering} tiles in"
        );
        held.copy_from_slice(&now);
        let from = Vec3::new(origin.x, 0.0, origin.y);
        for slot in 0..9u32 {
            let tile = window.tile_in(slot, base);
            let cpu = tile_blades(tile, &desc.instanced, desc.stiffness, None);
            let at = (slot * TILE_BLADES) as usize;
            for (k, want) in cpu.iter().enumerate() {
                let got = &blades[at + k];
                let case = format!("frame {frame}, slot {slot} (tile {tile}), blade {k}");
                assert!(
                    (got.root() + from).distance(want.root()) < 1e-3,
                    "{case}: root {} + {from} against {}",
                    got.root(),
                    want.root()
                );
                assert!(
                    (got.v0.w - want.v0.w).abs() < 1e-5,
                    "{case}: facing {} against {}",
                    got.v0.w,
                    want.v0.w
                );
                assert!(
                    (got.height() - want.height()).abs() < 1e-5,
                    "{case}: height {} against {}",
                    got.height(),
                    want.height()
                );
                assert!(
                    (got.width() - want.width()).abs() < 1e-6,
                    "{case}: width {} against {}",
                    got.width(),
                    want.width()
                );
                assert!(
                    (got.stiffness() - want.stiffness()).abs() < 1e-4,
                    "{case}: stiffness {} against {}",
                    got.stiffness(),
                    want.stiffness()
                );
            }
        }
        let theirs = vulkan.renderer.read_blades().unwrap();
        // Within a millimetre, and 4 more a kilometre from the world's origin, where a blade
        // made before the frame origin moved there was settled in coordinates whose 32-bit step
        // is 0.06 mm: the settle's differences of nearby points (and the waves' sines of
        // arguments near 800) are as exact as each compiler's contractions leave them.
        for (i, (a, b)) in blades.iter().zip(&theirs).enumerate() {
            let apart =
                a.v1.truncate()
                    .distance(b.v1.truncate())
                    .max(a.v2.truncate().distance(b.v2.truncate()));
            let within = 1e-3 + 4e-6 * (a.root() + from).length();
            assert!(
                apart < within,
                "frame {frame}, blade {i} at {}: its settled shape differs from the Vulkan renderer's by {apart}",
                a.root()
            );
        }
    }
    assert_eq!(
        field.origin(),
        glam::Vec2::new(1024.0, 0.0),
        "the last step moves the origin"
    );
    drop(vulkan);
    let messages = ctx.take_validation_messages();
    assert!(messages.is_empty(), "Vulkan validation: {messages:?}");
    assert_nothing_logged();
}

#[test]
fn a_stroke_on_a_streamed_field_makes_only_the_tile_under_it_anew_on_vulkan() {
    a_stroke_keeps_what_it_did_not_paint(wgpu::Backends::VULKAN);
}

#[test]
fn a_stroke_on_a_streamed_field_makes_only_the_tile_under_it_anew_on_gl() {
    a_stroke_keeps_what_it_did_not_paint(wgpu::Backends::GL);
}

/// A mow stroke painted over a streamed field (as the Bevy plugin paints a game's edits on the
/// portable passes): the one tile under it is made again from the new paint, its blades under
/// the stroke mowed, and every other blade — in that tile beyond the stroke's reach, or in any
/// other tile, a trail pressed into them — keeps its pose and collision strength to the bit
/// against the same steps with no stroke (the Vulkan renderer's `stream.rs` test, on the
/// portable renderer's own pass).
fn a_stroke_keeps_what_it_did_not_paint(backend: wgpu::Backends) {
    let scene = repaint::trailed();
    let grown = scene.grow_field().unwrap();
    let run = |painted: bool| {
        let (_, device, queue, mut renderer) = portable_renderer(backend);
        let mut field = PortableField::streamed(&device, scene.stream_window().unwrap()).unwrap();
        renderer.upload_paint(&device, grown.paint.as_ref());
        // Eight steps a submission, as the headless frames step a trampling scene.
        let simulate = |field: &mut PortableField, renderer: &mut PortableRenderer, first: u32, steps: u32| {
            for done in (0..steps).step_by(8) {
                let time = (first + done) as f32 * scene.simulation.step;
                let desc = FrameDesc::of_scene(&scene, grown.size, (time, 8.min(steps - done)), [64, 48]);
                let mut encoder = device.create_command_encoder(&Default::default());
                renderer.record(&device, &queue, &mut encoder, &desc, field, PortablePasses::SIMULATE);
                queue.submit([encoder.finish()]);
            }
        };
        simulate(&mut field, &mut renderer, 0, 60);
        let (before, _) = field.read(&device, &queue).unwrap();
        let mut remade = 0;
        if painted {
            let (paint, added, texel) = repaint::painted(&scene, &grown.paint);
            renderer.upload_paint(&device, paint.as_ref());
            remade = field.repaint_under(&added, texel);
        }
        simulate(&mut field, &mut renderer, 60, 2);
        let (after, etas) = field.read(&device, &queue).unwrap();
        assert_eq!(field.origin(), Vec2::ZERO, "the eye is at home");
        (before, after, etas, remade)
    };
    let (plain_before, plain, plain_etas, _) = run(false);
    let (before, after, etas, remade) = run(true);
    assert_eq!(remade, 1, "{backend:?}: the stroke lies within one tile");
    assert!(before == plain_before, "{backend:?}: the same steps gave other blades");
    repaint::assert_only_the_stroke_changed(&scene, (&plain, &plain_etas), (&after, &etas));
    assert_nothing_logged();
}

/// The meadow drawn by the whole chain (the landscape technique): 6,000 Bezier blades near the
/// eye, the generated grass to a 30-unit cut-off (some 30,000 blades in view, every level of
/// detail within it) settling in its wind, and the billboards beyond; without the occlusion test
/// (each renderer's depth pyramid is its own) and the shadows (not drawn by the portable
/// renderer yet).
fn generated_meadow() -> Scene {
    let mut scene = Scene::from_toml(include_str!("../../../scenes/meadow.toml"), "meadow").unwrap();
    scene.technique = sward_core::instanced::Technique::Landscape;
    scene.field.blades = 6000;
    scene.quality.route = sward_gpu::DrawRoute::Strips;
    scene.instanced.grid.radius = 30.0;
    scene.instanced.lod_distances = [4.0, 10.0, 20.0];
    scene.cull.occlusion = false;
    scene.shading.shadows = false;
    scene
}

/// The Vulkan renderer as a device without 64-bit atomics runs it, as the portable renderer
/// draws the generated grass: nothing splatted or rasterized by compute, every blade within the
/// cut-off listed at its level and drawn by the raster hardware.
fn vulkan_without_splats() -> std::sync::Arc<sward_gpu::Context> {
    let desc = sward_gpu::ContextDesc {
        validation: sward_gpu::Validation::Required,
        withheld: sward_gpu::Withheld {
            int64_atomics: true,
            ..Default::default()
        },
        ..Default::default()
    };
    sward_gpu::Context::new(&desc).unwrap_or_else(|e| panic!("{}: {e}", support::NEEDS))
}

#[test]
fn the_portable_generated_grass_lists_and_draws_the_vulkan_renderers_blades_on_vulkan() {
    generated_grass_matches(wgpu::Backends::VULKAN);
}

#[test]
fn the_portable_generated_grass_lists_and_draws_the_vulkan_renderers_blades_on_gl() {
    generated_grass_matches(wgpu::Backends::GL);
}

/// A listed blade's words (generated.wesl `place_generated`): root, height and half-width,
/// facing, lean (as fractions of the height), hash, outline.
struct Listed {
    root: glam::Vec3,
    size: glam::Vec2,
    facing: f32,
    lean: glam::Vec3,
    outline: u32,
}

impl Listed {
    fn of(w: &[u32; 8]) -> Listed {
        let half = |bits: u32| half::f16::from_bits(bits as u16).to_f32();
        let snorm = |bits: u32| (bits as u16 as i16) as f32 / 32767.0;
        Listed {
            root: glam::Vec3::new(f32::from_bits(w[0]), f32::from_bits(w[1]), f32::from_bits(w[2])),
            size: glam::Vec2::new(half(w[3]), half(w[3] >> 16)),
            facing: half(w[4]),
            lean: glam::Vec3::new(snorm(w[4] >> 16), snorm(w[5]), snorm(w[5] >> 16)),
            outline: w[7],
        }
    }
}

/// The portable renderer's generated grass on `backend` against the Vulkan renderer's without
/// splats: each level lists the same blades (by hash; a few may sit on the other side of a
/// level's boundary, the last bit of a distance), each placed, sized and leaning as the Vulkan
/// renderer's (the lean within 5e-3 of the height, 2.5 mm on a 0.5-unit blade: the settle's six
/// steps as each compiler contracts them; seen 1.7e-3 on wgpu's Vulkan backend, 2.7e-3 on GL,
/// at blades the wind lays on the ground); and the pictures agree as the Bezier scenes' do.
fn generated_grass_matches(backend: wgpu::Backends) {
    let scene = generated_meadow();
    let grown = scene.grow_field().unwrap();
    let desc = FrameDesc::of_scene(&scene, grown.size, (0.5, 0), PICTURE);
    let ctx = vulkan_without_splats();
    let [width, height] = PICTURE;
    let mut vulkan = sward_gpu::Headless::new(&ctx, width, height, None).unwrap();
    vulkan.renderer.upload(&grown).unwrap();
    vulkan.renderer.run_compute(&desc, sward_gpu::Passes::ALL).unwrap();
    let theirs = vulkan.renderer.read_generated_lists().unwrap();
    drop(vulkan);
    let messages = ctx.take_validation_messages();
    assert!(messages.is_empty(), "Vulkan validation: {messages:?}");

    let (on, device, queue, mut renderer) = portable_renderer(backend);
    let mut field = PortableField::with_tiles(&device, &grown.blades, grown.tiles.clone()).unwrap();
    let mut encoder = device.create_command_encoder(&Default::default());
    renderer.record(&device, &queue, &mut encoder, &desc, &mut field, PortablePasses::ALL);
    queue.submit([encoder.finish()]);
    let ours = renderer.read_generated(&device, &queue, 0).unwrap();
    let listed: usize = ours.iter().map(Vec::len).sum();
    assert!(
        listed > 10_000,
        "{on}: the view should list the meadow's blades, not {listed}"
    );
    assert!(
        ours.len() == 5 && ours.iter().all(|list| list.len() > 500),
        "{on}: every level and the billboards should hold blades: {:?}",
        ours.iter().map(Vec::len).collect::<Vec<_>>()
    );
    let mut worst_lean = 0.0f32;
    for (level, (ours, theirs)) in ours.iter().zip(&theirs).enumerate() {
        let by_hash: std::collections::HashMap<u32, &[u32; 8]> = theirs.iter().map(|w| (w[6], w)).collect();
        let unmatched = ours.iter().filter(|w| !by_hash.contains_key(&w[6])).count();
        let apart = unmatched + theirs.len().saturating_sub(ours.len() - unmatched);
        assert!(
            apart * 1000 <= ours.len().max(1000),
            "{on}, level {level}: {apart} of {} blades are not the Vulkan renderer's {}",
            ours.len(),
            theirs.len()
        );
        for words in ours {
            let Some(twin) = by_hash.get(&words[6]) else {
                continue;
            };
            let (a, b) = (Listed::of(words), Listed::of(twin));
            let case = format!("{on}, level {level}, blade {:#x} at {}", words[6], a.root);
            assert!(a.root.distance(b.root) < 1e-4, "{case}: root against {}", b.root);
            assert!(
                (a.size - b.size).abs().max_element() < 2e-3,
                "{case}: size {} against {}",
                a.size,
                b.size
            );
            assert!(
                (a.facing - b.facing).abs() < 4e-3,
                "{case}: facing {} against {}",
                a.facing,
                b.facing
            );
            worst_lean = worst_lean.max(a.lean.distance(b.lean));
            assert!(
                a.lean.distance(b.lean) < 5e-3,
                "{case}: lean {} against {}",
                a.lean,
                b.lean
            );
            assert_eq!(a.outline, b.outline, "{case}: outline");
        }
    }
    eprintln!("generated meadow on {on}: leaning at most {worst_lean} apart");

    // The whole chain, and each technique of it.
    use sward_core::instanced::Technique;
    for technique in [
        Technique::Landscape,
        Technique::Instanced,
        Technique::Billboard,
        Technique::Both,
    ] {
        generated_picture_matches(
            &Scene {
                technique,
                ..scene.clone()
            },
            &ctx,
            (backend, false),
            PICTURE_ONE_IN,
        );
    }
    // The open world whole, over its terrain: its streamed Bezier blades easing into their
    // instanced twins across the hand-over (without the easing a ring of blades there differs:
    // 642 pixels of 43,200; with it 24 on wgpu's Vulkan backend, 55 on GL), the generated grass
    // and the billboards.
    let world = Scene::from_toml(include_str!("../../../scenes/openworld.toml"), "openworld").unwrap();
    let (_, mut world) = streamed_bezier(("openworld", world));
    world.technique = Technique::Landscape;
    world.shading.shadows = false;
    world.cull.occlusion = false;
    generated_picture_matches(&world, &ctx, (backend, false), STREAMED_PICTURE_ONE_IN);
    // The generated grass laid along the trample map's trails by the walking colliders.
    let mut trail = Scene::from_toml(include_str!("../../../scenes/trample.toml"), "trample").unwrap();
    trail.technique = Technique::Instanced;
    trail.instanced.grid.radius = 30.0;
    trail.instanced.lod_distances = [4.0, 10.0, 20.0];
    trail.shading.shadows = false;
    trail.cull.occlusion = false;
    assert!(trail.tramples());
    generated_picture_matches(&trail, &ctx, (backend, false), TRAIL_PICTURE_ONE_IN);
    assert_nothing_logged();
}

/// `scene` drawn by the portable renderer on `backend`, splatting or not (`on`), against the
/// Vulkan renderer's on `ctx` (splatting as the portable renderer does), after PICTURE_STEPS
/// steps: grass where the reference shows it, and at most one pixel in `one_in` apart.
fn generated_picture_matches(
    scene: &Scene,
    ctx: &std::sync::Arc<sward_gpu::Context>,
    on: (wgpu::Backends, bool),
    one_in: usize,
) {
    let (backend, splats) = on;
    let name = scene.technique.name();
    let grown = scene.grow_field().unwrap();
    let [width, height] = PICTURE;
    let mut vulkan = sward_gpu::Headless::new(ctx, width, height, None).unwrap();
    vulkan.renderer.upload(&grown).unwrap();
    vulkan.renderer.upload_ground(grown.ground.as_ref()).unwrap();
    let reference = vulkan.render_scene(scene, grown.size, PICTURE_STEPS).unwrap();
    drop(vulkan);
    let messages = ctx.take_validation_messages();
    assert!(messages.is_empty(), "Vulkan validation: {messages:?}");
    let samples = scene.quality.preset.msaa_samples();
    let mut headless = headless_on(on, PICTURE, samples);
    headless.upload(&grown).unwrap();
    let picture = headless.render_scene(scene, grown.size, PICTURE_STEPS).unwrap();
    save_picture(
        &format!("generated-{name}-vulkan-{backend:?}-splats-{splats}.png"),
        &reference,
    );
    save_picture(
        &format!("generated-{name}-portable-{backend:?}-splats-{splats}.png"),
        &picture,
    );
    let grass = reference.chunks(4).filter(|p| p[1] > p[2]).count();
    let pixels = reference.len() / 4;
    assert!(
        grass > pixels / 3,
        "{name}: the reference shows the meadow's grass ({grass} of {pixels} pixels)"
    );
    let (over, worst) = differing_pixels(&picture, &reference, PICTURE_LEVELS);
    eprintln!("{name} meadow on {on:?}: {over} pixels differ by more than {PICTURE_LEVELS} levels");
    assert!(
        over * one_in <= pixels,
        "{name} on {on:?}: {over} of {pixels} pixels differ by more than {PICTURE_LEVELS} levels (at most {worst})"
    );
}

/// Where the device has 64-bit atomic min/max the portable renderer splats the far field with
/// the Vulkan renderer's passes: the meadow's chain with its instanced blades splatted from 12
/// units (and rasterized by compute from 8) and its billboards splatted from 45 (rasterized from
/// 35), each technique, and the open world as it ships, against the Vulkan renderer splatting
/// them, on lavapipe.
#[test]
fn the_portable_renderer_splats_the_far_field_as_the_vulkan_renderer_does() {
    use sward_core::instanced::Technique;
    let desc = sward_gpu::ContextDesc {
        validation: sward_gpu::Validation::Required,
        ..Default::default()
    };
    let ctx = sward_gpu::Context::new(&desc).unwrap_or_else(|e| panic!("{}: {e}", support::NEEDS));
    let mut scene = generated_meadow();
    scene.instanced.splat_distance = 12.0;
    scene.instanced.raster_distance = 8.0;
    scene.billboard.splat_distance = 45.0;
    scene.billboard.raster_distance = 35.0;
    for technique in [Technique::Landscape, Technique::Instanced, Technique::Billboard] {
        let scene = Scene {
            technique,
            ..scene.clone()
        };
        generated_picture_matches(&scene, &ctx, (wgpu::Backends::VULKAN, true), PICTURE_ONE_IN);
    }
    let world = Scene::from_toml(include_str!("../../../scenes/openworld.toml"), "openworld").unwrap();
    let (_, mut world) = streamed_bezier(("openworld", world));
    world.cull.occlusion = false;
    generated_picture_matches(&world, &ctx, (wgpu::Backends::VULKAN, true), STREAMED_PICTURE_ONE_IN);
    // A frame that splats nothing on a device that splats (the trample scene's Bezier blades
    // all strips): its balls' shadows drawn all the same.
    let mut trample = Scene::from_toml(include_str!("../../../scenes/trample.toml"), "trample").unwrap();
    trample.field.blades = trample.field.blades.min(6000);
    trample.cull.occlusion = false;
    trample.quality.route = sward_gpu::DrawRoute::Strips;
    let reference = vulkan_strips(&trample);
    let picture = portable_picture(&trample, (wgpu::Backends::VULKAN, true));
    assert_shadows_drawn("trample", &trample, &picture);
    let (over, worst) = differing_pixels(&picture, &reference, PICTURE_LEVELS);
    let pixels = picture.len() / 4;
    assert!(
        over * ROLLED_PICTURE_ONE_IN <= pixels,
        "trample as strips on a splatting device: {over} of {pixels} pixels differ (at most {worst} levels)"
    );
    assert_nothing_logged();
}

#[test]
fn the_portable_hand_overs_show_no_ring_as_the_camera_moves_on_vulkan() {
    hand_overs_in_motion((wgpu::Backends::VULKAN, false), false);
}

#[test]
fn the_portable_hand_overs_show_no_ring_as_the_camera_moves_on_gl() {
    hand_overs_in_motion((wgpu::Backends::GL, false), false);
}

/// The same where the portable renderer splats the far field: the splat band is a seam too.
#[test]
fn the_portable_splats_hand_over_with_no_ring_as_the_camera_moves_on_vulkan() {
    hand_overs_in_motion((wgpu::Backends::VULKAN, true), false);
}

/// The same with the far field splatted into 32-bit cells, on llvmpipe's GL (which has no 64-bit
/// atomics): the narrow cells' depth key moves the splat band no more than the wide cells do.
#[test]
fn the_portable_32_bit_splats_hand_over_with_no_ring_as_the_camera_moves_on_gl() {
    hand_overs_in_motion((wgpu::Backends::GL, false), true);
}

/// `scenes` drawn one after another by one portable renderer on `backend`, at the seam tests'
/// size: the first after `steps[0]` steps of its field's physics from time 0, each next one
/// after `steps[1]` more (the generated grass stands as the time says: 0 draws each at time 0).
fn frames_of(scenes: &[Scene], steps: [u32; 2], (on, narrow): ((wgpu::Backends, bool), bool)) -> Vec<Vec<u8>> {
    let first = &scenes[0];
    let samples = first.quality.preset.msaa_samples();
    let size = [seams::WIDTH, seams::HEIGHT];
    let mut headless = match narrow {
        true => {
            let modules = ShaderModules::built_in().with_narrow_splats(true);
            PortableHeadless::made_of(portable_device_on(on), size, samples, modules).unwrap()
        }
        false => headless_on(on, size, samples),
    };
    let field = first.grow_field().unwrap();
    headless.upload(&field).unwrap();
    let steps = std::iter::once(steps[0]).chain(std::iter::repeat(steps[1]));
    scenes
        .iter()
        .zip(steps)
        .map(|(scene, steps)| headless.render_scene(scene, field.size, steps).unwrap())
        .collect()
}

/// The portable renderer's hand-overs seen in motion, as lod_seams.rs sees the Vulkan
/// renderer's: a small step of the camera changes the image rows where the generated grass
/// changes level (the strips geomorph), and where the landscape chain hands Bezier blades to
/// instanced blades to billboards to the tinted ground, no more than the rows around them (where
/// only parallax moves things); and a streamed field walked three steps across its hand-over
/// (settled first, no wind), frame to frame, the same. Where it splats (`on`'s second), the
/// splat band is a seam as the levels' boundaries are, and moves out with them; `narrow`: it
/// splats into 32-bit cells.
fn hand_overs_in_motion(on: (wgpu::Backends, bool), narrow: bool) {
    let splats = on.1 || narrow;
    use glam::Vec3;
    use seams::*;
    let start = Vec3::new(0.0, 5.0, 0.0);
    let step = Vec3::new(0.0, 0.0, -0.05);
    let distances = row_distances(&scene(start).camera);
    let reached = |seams: &[(f32, f32)]| -> Vec<(f32, f32)> {
        let far = |&(_, hi): &(f32, f32)| distances.iter().any(|&d| d > hi);
        seams.iter().copied().filter(far).collect()
    };
    // The levels' boundaries are the seams, and where it splats the splat band (lod_seams.rs).
    let levels = match splats {
        true => seams(&scene(start).instanced),
        false => scene(start).instanced.lod_distances.map(|d| (0.8 * d, d)).to_vec(),
    };
    let seen = reached(&levels);
    assert!(
        seen.len() >= 2,
        "the view should cross the levels' boundaries: {seen:?}"
    );
    let frames = frames_of(&[scene(start), scene(start + step)], [0, 0], (on, narrow));
    assert_no_ring(&row_changes(&frames[0], &frames[1]), &distances, &seen, [0.3, 0.6, 3.0]);
    // The camera still, the boundaries moved out by 3 %: the blades between change level and
    // nothing else changes, so whatever differs is the seams' own change (lod_seams.rs
    // `moving_the_boundaries_past_blades_changes_almost_nothing`).
    let mut moved = scene(start);
    moved.instanced.lod_distances = moved.instanced.lod_distances.map(|d| d * 1.03);
    moved.instanced.splat_distance *= 1.03;
    let frames = frames_of(&[scene(start), moved], [0, 0], (on, narrow));
    let changes = row_changes(&frames[0], &frames[1]);
    for (lo, hi) in levels {
        let (at, rows) = mean_change(&changes, &distances, |d| d >= lo * 0.97 - 0.3 && d <= hi * 1.03 + 0.3);
        eprintln!("{on:?}: moving the boundary at {lo}..{hi} changes its {rows} rows by {at:.2}");
        assert!(
            at <= 4.0,
            "the level boundary at {lo}..{hi} pops: its {rows} rows change by {at:.2}"
        );
    }
    let whole = changes.iter().sum::<f32>() / HEIGHT as f32;
    assert!(
        whole <= 1.0,
        "moving the boundaries changed the image by {whole:.2} per pixel"
    );

    let seen = reached(&LANDSCAPE_SEAMS);
    assert_eq!(seen.len(), 3, "the view should cross every hand-over of the chain");
    let frames = frames_of(&[landscape(start), landscape(start + step)], [0, 0], (on, narrow));
    assert_no_ring(&row_changes(&frames[0], &frames[1]), &distances, &seen, [0.0, 1.0, 8.0]);

    let eye = Vec3::new(0.0, 2.0, 0.0);
    let walk: Vec<Scene> = (0..=3)
        .map(|k| streamed(eye + Vec3::new(0.0, 0.0, -0.05 * k as f32), 8.0))
        .collect();
    let hand_over = walk[0].hand_over();
    let seam = (along_ground(hand_over * 0.85, eye.y), along_ground(hand_over, eye.y));
    let distances = row_distances(&walk[0].camera);
    assert!(
        distances.iter().any(|&d| d > seam.1 + 8.0),
        "the view should reach past the hand-over"
    );
    let frames = frames_of(&walk, [120, 1], (on, narrow));
    for pair in frames.windows(2) {
        assert_no_ring(&row_changes(&pair[0], &pair[1]), &distances, &[seam], [0.0, 1.0, 4.0]);
    }
    assert_nothing_logged();
}

#[test]
fn the_portable_open_world_walked_run_and_flown_shows_no_bald_ground_near_the_eye() {
    open_world_in_motion(wgpu::Backends::VULKAN);
}

/// The open world on the portable renderer, its ground painted magenta (a colour no grass has),
/// walked (1.5 m/s), run (10) and flown (100) along its loop over the hills, a frame each
/// sixtieth of a second, the streamed window following the eye: every few frames the lower third
/// of the frame (the ground within a few metres of the eye) shows no more magenta than the same
/// view shows between the blades once the camera has stood there a few frames (the terrain
/// under the eye changes what a still camera sees).
fn open_world_in_motion(backend: wgpu::Backends) {
    let mut world = Scene::from_toml(include_str!("../../../scenes/openworld.toml"), "openworld").unwrap();
    world.shading.ground_color = glam::Vec3::new(1.0, 0.0, 1.0);
    world.shading.shadows = false;
    // The billboards but for a thin ring are left out (the scene keeps its techniques): they
    // stand past 58 metres, far above the lower third this reads, and were half of a frame's
    // work on a CPU device.
    world.billboard.grid.radius = world.billboard.grid.inner_radius + 1.0;
    let ground = match world.surface {
        sward_core::field::Surface::Terrain {
            size,
            height,
            resolution,
            seed,
        } => sward_core::mesh::Mesh::terrain(size, height, resolution, seed).height_grid(),
        _ => panic!("the open world stands on terrain"),
    };
    let samples = world.quality.preset.msaa_samples();
    let mut headless = headless_on((backend, false), PICTURE, samples);
    let field = world.grow_field().unwrap();
    headless.upload(&field).unwrap();
    // The lower third: magenta where the ground shows through.
    let bald = |image: &[u8]| -> f32 {
        let lower = &image[image.len() * 2 / 3..];
        let magenta = lower
            .as_chunks::<4>()
            .0
            .iter()
            .filter(|p| p[0] > p[1] + 40 && p[2] > p[1] + 40)
            .count();
        magenta as f32 / (lower.len() / 4) as f32
    };
    let mut along = 0.0;
    let path_speed = world.camera_path.speed;
    let mut frame_at = |along: f32| {
        let mut scene = world.clone();
        scene.camera = world.camera_path.camera_over(&world.camera, along, ground.as_ref());
        headless.render_scene(&scene, field.size, 1).unwrap()
    };
    // Flown 16 frames, 27 metres: each check (every 8 frames, 13 metres) finds a new row of
    // the streamed window's 9-metre tiles entered since the last.
    for (pace, speed, frames) in [("walked", 1.5, 8), ("run", 10.0, 8), ("flown", 100.0, 16)] {
        for k in 1..=frames {
            along += speed / 60.0 / path_speed;
            let moving = frame_at(along);
            if k % 8 != 0 {
                continue;
            }
            // The same view after the camera stood there: the window made around the eye.
            for _ in 0..3 {
                frame_at(along);
            }
            let settled = frame_at(along);
            let [seen, still] = [&moving, &settled].map(|image| bald(image));
            eprintln!("{backend:?}: {pace}, frame {k}: {seen:.4} of the lower third bald (standing there: {still:.4})");
            if k == frames {
                save_picture(&format!("open-world-{pace}.png"), &moving);
            }
            assert!(
                seen <= 1.5 * still + 0.01,
                "{pace} at {speed} m/s, frame {k}: {seen:.4} of the lower third shows bare ground (standing there: {still:.4})"
            );
        }
    }
    assert_nothing_logged();
}
