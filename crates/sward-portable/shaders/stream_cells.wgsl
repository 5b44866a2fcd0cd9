// The streamed field's cells (sward-core's `stream`, the Vulkan renderer's common.glsl): the hash
// of a grid cell, the world tile a window slot holds, a streamed blade's cell. The strips colour
// a streamed blade by its cell's hash; stream.wgsl makes the entering tiles' blades from it.
// Needs frame.wgsl and blade.wgsl.

fn cell_hash(cell: vec2<i32>, seed: u32) -> u32 {
    return hash_word((u32(cell.x) * 73856093u) ^ hash_word(u32(cell.y) ^ (seed * 19349663u)));
}

// The world tile window slot `slot` holds (stream.rs `StreamWindow::tile_in`).
fn stream_tile(slot: u32) -> vec2<i32> {
    let n = i32(frame.stream.x);
    let base = bitcast<vec2<i32>>(frame.stream.zw);
    let s = vec2<i32>(i32(slot % frame.stream.x), i32(slot / frame.stream.x));
    // (s - base) modulo n in unsigned numbers: naga writes WGSL's `%` as GLSL's, undefined for
    // a negative operand (trample_map.wgsl `trample_wrap`). Good for windows within n · 2^18
    // tiles of the world's origin.
    let bias = vec2<i32>(n << 18u);
    return base + vec2<i32>(vec2<u32>(s - base + bias) % u32(n));
}

// The grid cell of streamed blade `id`.
fn stream_cell(id: u32) -> vec2<i32> {
    let cells = frame.stream.y;
    let per_tile = cells * cells;
    let index = id % per_tile;
    return stream_tile(id / per_tile) * i32(cells) + vec2<i32>(i32(index % cells), i32(index / cells));
}


// The grid cell of blade `index` (row by row) of world tile `tile` (stream.rs
// `StreamWindow::cell_of`).
fn tile_cell(tile: vec2<i32>, index: u32) -> vec2<i32> {
    let cells = frame.stream.y;
    return tile * i32(cells) + vec2<i32>(i32(index % cells), i32(index / cells));
}

// How far a streamed blade has eased into its instanced twin (0 where nothing streams).
fn twin_ease(root: vec3<f32>) -> f32 {
    let start = frame.stream_reach.y;
    let end = frame.stream_reach.x;
    if (frame.stream.x == 0u || start >= end) {
        return 0.0;
    }
    return smoothstep(start, end, distance(root, frame.camera_position.xyz));
}
