//! What the portable renderer asks of an adapter and makes of it: the optional features it uses,
//! the limits it asks for, and one sentence for `sward info`. Nothing here waits on the GPU.

/// The optional features the portable renderer uses where `adapter` has them: drawing the
/// blades' buckets with a count from the cull (`MULTI_DRAW_INDIRECT_COUNT`), subgroups in the
/// cull's compaction (`SUBGROUP`), 64-bit atomic min/max to splat the far field
/// (`SHADER_INT64_ATOMIC_MIN_MAX`), and on Vulkan the splats' resolve at the pixel's rate
/// handed over as SPIR-V (`PASSTHROUGH_SHADERS`). Without them it runs on WebGPU's core.
pub fn portable_features(adapter: &wgpu::Adapter) -> wgpu::Features {
    adapter.features() & USED_FEATURES
}

/// The optional features the portable renderer uses where it finds them.
const USED_FEATURES: wgpu::Features = wgpu::Features::MULTI_DRAW_INDIRECT_COUNT
    .union(wgpu::Features::SUBGROUP)
    .union(crate::passes::splats::SPLAT_FEATURES)
    .union(wgpu::Features::PASSTHROUGH_SHADERS);

/// The limits the portable renderer asks of `adapter`: WebGPU's defaults, which every backend
/// offers and the passes need no more than, with the adapter's larger textures (a big image)
/// and storage buffers (a big field's blades in one binding: WebGPU's default of 128 MiB holds
/// 2 million blades) where it has them; where it splats with 64-bit atomics (a native adapter),
/// the adapter's storage buffers a stage and its workgroups' size and memory (32-bit cells
/// splat within WebGPU's defaults, as a browser runs them).
pub fn portable_limits(adapter: &wgpu::Adapter) -> wgpu::Limits {
    let offered = adapter.limits();
    let webgpu = wgpu::Limits::default();
    let splats = adapter.features().contains(crate::passes::splats::SPLAT_FEATURES);
    // Where it splats (a native adapter), the adapter's own compute limits: the instanced
    // grass's counting pass then runs a patch to a workgroup, as the Vulkan renderer's.
    let native = |offered: u32, webgpu: u32| if splats { offered.max(webgpu) } else { webgpu };
    wgpu::Limits {
        max_storage_buffers_per_shader_stage: native(
            offered.max_storage_buffers_per_shader_stage,
            webgpu.max_storage_buffers_per_shader_stage,
        ),
        max_compute_invocations_per_workgroup: native(
            offered.max_compute_invocations_per_workgroup,
            webgpu.max_compute_invocations_per_workgroup,
        ),
        max_compute_workgroup_size_x: native(
            offered.max_compute_workgroup_size_x,
            webgpu.max_compute_workgroup_size_x,
        ),
        max_compute_workgroup_storage_size: native(
            offered.max_compute_workgroup_storage_size,
            webgpu.max_compute_workgroup_storage_size,
        ),
        max_storage_buffer_binding_size: offered
            .max_storage_buffer_binding_size
            .max(webgpu.max_storage_buffer_binding_size),
        max_buffer_size: offered.max_buffer_size.max(webgpu.max_buffer_size),
        ..webgpu.using_resolution(offered)
    }
}

/// Whether the portable renderer runs on `adapter` (or what it lacks), the largest field it
/// binds there, whether it folds a caller's depth, and which optional features the adapter has
/// that the portable renderer uses, and which it does without so far.
pub fn adapter_sentence(adapter: &wgpu::Adapter) -> String {
    let info = adapter.get_info();
    let name = format!("wgpu {:?} ({})", info.backend, info.name);
    let flags = adapter.get_downlevel_capabilities().flags;
    let storage = adapter.limits().max_storage_buffers_per_shader_stage;
    let lacks = if !flags.contains(wgpu::DownlevelFlags::COMPUTE_SHADERS) {
        Some("compute shaders".to_string())
    } else if !flags.contains(wgpu::DownlevelFlags::VERTEX_STORAGE) {
        Some("storage buffers in vertex shaders".to_string())
    } else if storage < crate::STORAGE_BUFFERS_PER_STAGE {
        Some(format!(
            "storage buffers: it binds {storage} a stage, the passes {}",
            crate::STORAGE_BUFFERS_PER_STAGE
        ))
    } else {
        None
    };
    if let Some(lacks) = lacks {
        return format!("{name}: the portable renderer does not run here (it lacks {lacks})");
    }
    let blade_bytes = std::mem::size_of::<sward_core::Blade>() as u64;
    let limits = portable_limits(adapter);
    let blades = limits.max_storage_buffer_binding_size.min(limits.max_buffer_size) / blade_bytes;
    let webgpu = wgpu::Limits::default().max_storage_buffer_binding_size / blade_bytes;
    let caller = match info.backend {
        wgpu::Backend::Gl => {
            "cannot fold a caller's depth into its depth pyramid (GL's compute reads no depth texture)"
        }
        _ => "folds a caller's depth into its depth pyramid",
    };
    let optional = [
        (wgpu::Features::MULTI_DRAW_INDIRECT_COUNT, "multi-draw-indirect-count"),
        (wgpu::Features::SUBGROUP, "subgroups"),
        (wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX, "64-bit atomic min and max"),
    ];
    let named = |used: bool| -> Vec<&str> {
        let has = |feature: wgpu::Features| adapter.features().contains(feature);
        optional
            .iter()
            .filter(|(feature, _)| has(*feature) && USED_FEATURES.contains(*feature) == used)
            .map(|(_, what)| *what)
            .collect()
    };
    let (used, unused) = (spoken_list(&named(true)), spoken_list(&named(false)));
    let extras = match (used.is_empty(), unused.is_empty()) {
        (true, true) => "it has none of the optional features sward could use".to_string(),
        (false, true) => format!("it uses {used}"),
        (true, false) => format!("it has {unused} and does without them so far"),
        (false, false) => format!("it uses {used}, and does without {unused} so far"),
    };
    // The far field's generated grass: splatted by compute into 64-bit cells where the adapter
    // has 64-bit atomic min/max, else into 32-bit cells where it binds enough storage buffers,
    // else drawn by indirect draws.
    let far = match crate::passes::splats::splat_cells(adapter.features(), &adapter.limits(), None) {
        Some(false) => "it splats the generated grass and billboards beyond their splat distances by compute, as the Vulkan renderer does",
        Some(true) => "it splats the generated grass and billboards beyond their splat distances by compute into 32-bit cells (it has no 64-bit atomic min and max)",
        None => "it draws the generated grass and billboards to the horizon as geometry by indirect draws",
    };
    format!("{name}: the portable renderer runs here, a field of up to {blades} blades (WebGPU's defaults hold {webgpu}); it {caller}; {far}; {extras}")
}

/// `items` as a sentence lists them: "a", "a and b", "a, b and c".
fn spoken_list(items: &[&str]) -> String {
    match items {
        [] => String::new(),
        [one] => one.to_string(),
        [rest @ .., last] => format!("{} and {last}", rest.join(", ")),
    }
}

/// Where a field of `blades` needs more storage than WebGPU's default limits bind (and so more
/// than every browser gives), one sentence saying so: the portable renderer then runs only
/// where the adapter gives larger bindings.
pub fn beyond_webgpu_defaults(blades: usize) -> Option<String> {
    let bytes = blades as u64 * std::mem::size_of::<sward_core::Blade>() as u64;
    let webgpu = wgpu::Limits::default().max_storage_buffer_binding_size;
    (bytes > webgpu).then(|| {
        format!(
            "a field of {blades} blades binds {} MiB of blades, more than WebGPU's default of {} MiB: it runs where the adapter gives larger storage bindings (this one does), not in every browser",
            bytes >> 20,
            webgpu >> 20
        )
    })
}
