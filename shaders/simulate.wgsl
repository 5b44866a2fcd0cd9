// The portable renderer's simulation (SPEC §3): one invocation per blade of the field,
// `counts.y` fixed steps per dispatch, as the Vulkan renderer's simulate.comp. Needs frame.wgsl,
// blade.wgsl, noise.wgsl, trample_map.wgsl, physics.wgsl and tiles.wgsl. Dispatched a row of
// workgroups per tile the frame runs, or (a field without tiles) over rows of workgroups where
// the field has more blades than one row of the device's dispatch holds.

@group(0) @binding(1) var<storage, read_write> blades: array<Blade>;
@group(0) @binding(2) var<storage, read_write> etas: array<f32>;
// The trample map (trample_map.wgsl), as this frame's trample pass left it.
@group(0) @binding(9) var<storage, read> trample_texels: array<vec4<u32>>;

// The tiles this frame runs (tiles.wgsl).
@group(0) @binding(10) var<storage, read> active_tiles: array<vec4<u32>>;

@compute @workgroup_size(64)
fn simulate(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let taken = tiled_blade(id, groups);
    if (!taken.taken) {
        return;
    }
    let i = taken.index;
    var b = blades[i];
    var eta = etas[i];
    simulate_blade(&b, &eta);
    // Only the guide and tip move; the root and up never change.
    blades[i].guide = b.guide;
    blades[i].tip = b.tip;
    etas[i] = eta;
}
