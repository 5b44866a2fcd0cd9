// The portable renderer's simulation (SPEC §3): one invocation per blade of the field,
// `counts.y` fixed steps per dispatch, as the Vulkan renderer's simulate.comp; a streamed
// blade then eases into its instanced twin across the hand-over band. Needs frame.wgsl,
// blade.wgsl, noise.wgsl, shading.wgsl, trample_map.wgsl, physics.wgsl, ground_grid.wgsl,
// stream_cells.wgsl, outline.wgsl, twin.wgsl and tiles.wgsl. Dispatched a row of
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
    ease_into_twin(&b, i);
    // Only the guide and tip move; the root and up never change.
    blades[i].guide = b.guide;
    blades[i].tip = b.tip;
    etas[i] = eta;
}

// A streamed blade across the hand-over band, eased into its instanced twin as the frame poses
// it (physics.glsl `ease_into_twin`): none before the band, all of it at the hand-over, where
// the instanced grass draws the twin instead — so the hand-over shows no seam.
fn ease_into_twin(b: ptr<function, Blade>, id: u32) {
    let s = twin_ease((*b).root.xyz);
    if (s <= 0.0) {
        return;
    }
    let dist = distance((*b).root.xyz, frame.camera_position.xyz);
    let twin = instanced_twin(stream_cell(id));
    let shape = twin_shape(twin, dist);
    (*b).guide = vec4<f32>(mix((*b).guide.xyz, shape.guide.xyz, vec3<f32>(s)), (*b).guide.w);
    (*b).tip = vec4<f32>(mix((*b).tip.xyz, shape.tip.xyz, vec3<f32>(s)), mix(twin.width, widened(twin.width, dist), s));
}
