// The streamed field on the portable renderer (sward-core's `stream`; the Vulkan renderer's
// stream_tiles.comp and rebase_field.comp, line for line): every held blade carried to a moved
// frame origin, then the blades of the tiles entering the window made — each the instanced
// grass's blade of its cell (instanced.glsl `instanced_blade_of`: the same hash, clumps, paint
// and kinds), standing as that twin stands this frame (bent, swaying, laid down where the
// trample map says it was walked on), with a stiffness from its cell's hash. Physics takes it
// from there. Needs frame.wgsl, blade.wgsl, noise.wgsl, shading.wgsl, trample_map.wgsl,
// physics.wgsl, ground_grid.wgsl, twin.wgsl and stream_cells.wgsl.

@group(0) @binding(1) var<storage, read_write> blades: array<Blade>;
// The trample map (trample_map.wgsl), as the last frame left it.
@group(0) @binding(9) var<storage, read> trample_texels: array<vec4<u32>>;
// The tiles entering the window (sward-core's `ActiveTile`): per tile its slot and world tile.
@group(0) @binding(10) var<storage, read> entering: array<vec4<u32>>;

// The blades of the tiles entering the window: one row of workgroups per entering tile, an
// invocation per blade.
@compute @workgroup_size(64)
fn make_entering_tiles(@builtin(global_invocation_id) id: vec3<u32>, @builtin(workgroup_id) group: vec3<u32>) {
    let cells = frame.stream.y;
    let index = id.x;
    if (index >= cells * cells) {
        return;
    }
    let tile = entering[group.y];
    let twin = instanced_twin(tile_cell(bitcast<vec2<i32>>(tile.yz), index));
    let stiffness = grid_stiffness(twin.hash, twin.species);
    let dist = distance(twin.root, frame.camera_position.xyz);
    var b: Blade;
    b.root = vec4<f32>(twin.root, twin.facing);
    b.up = vec4<f32>(0.0, 1.0, 0.0, stiffness);
    if (twin.height > 0.0) {
        let shape = twin_shape(twin, dist);
        b.guide = vec4<f32>(shape.guide.xyz, twin.height);
        b.tip = vec4<f32>(shape.tip.xyz, twin.width);
    } else {
        // Off the ground's height grid: a blade of no height, never drawn.
        b.guide = vec4<f32>(twin.root, 0.0);
        b.tip = vec4<f32>(twin.root, twin.width);
    }
    blades[tile.x * cells * cells + index] = b;
}

// Every held blade carried to the moved frame origin, by frame.origin.zw (whole multiples of a
// power of two: exact). One row of workgroups per slot of the window.
@compute @workgroup_size(64)
fn rebase_field(@builtin(global_invocation_id) id: vec3<u32>, @builtin(workgroup_id) group: vec3<u32>) {
    let per_tile = frame.stream.y * frame.stream.y;
    if (id.x >= per_tile) {
        return;
    }
    let at = group.y * per_tile + id.x;
    let shift = vec3<f32>(frame.origin.z, 0.0, frame.origin.w);
    blades[at].root = vec4<f32>(blades[at].root.xyz - shift, blades[at].root.w);
    blades[at].guide = vec4<f32>(blades[at].guide.xyz - shift, blades[at].guide.w);
    blades[at].tip = vec4<f32>(blades[at].tip.xyz - shift, blades[at].tip.w);
}
