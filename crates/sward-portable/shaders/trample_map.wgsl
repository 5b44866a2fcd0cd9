// The trample map as the portable passes read it (sward-core trample.rs; the Vulkan renderer's
// common.glsl): a square window of texels over the ground around the eye, each the push that
// flattens its grass (xy, float bits), how high it was mown (z, float bits; 0: uncut) and its
// cell's tag (w). The pass that binds `trample_texels` declares it (trample.wgsl writes it,
// simulate.wgsl reads it). Needs frame.wgsl and blade.wgsl.

// trample.rs `cell_tag`.
fn trample_tag(cell: vec2<i32>) -> u32 {
    return (u32(cell.x) & 0xffffu) | ((u32(cell.y) & 0xffffu) << 16u);
}

// `a` modulo `n` in [0, n) (Rust's `rem_euclid`), in unsigned numbers: naga writes WGSL's `%`
// as GLSL's, which is undefined for a negative operand (llvmpipe's GL gets it wrong). Good for
// cells down to -n · 2^18 (a million cells at least).
fn trample_wrap(a: vec2<i32>, n: i32) -> vec2<i32> {
    let bias = vec2<i32>(n << 18u);
    return vec2<i32>(vec2<u32>(a + bias) % u32(n));
}

// The texel of world cell `cell`: the cell modulo the resolution.
fn trample_texel(cell: vec2<i32>) -> u32 {
    let n = i32(frame.trample.x);
    let t = trample_wrap(cell, n);
    return u32(t.y * n + t.x);
}

// trample.rs `texel_at`: the texel of frame ground point `xz` where it holds that point's cell,
// else an untouched one (zeros: upright and uncut), as off the window or with the map off.
fn trample_texel_at(xz: vec2<f32>) -> vec4<u32> {
    let n = i32(frame.trample.x);
    if (n == 0) {
        return vec4<u32>(0u);
    }
    let cell = vec2<i32>(floor(world_xz(xz) / bitcast<f32>(frame.trample.y)));
    let t = cell - bitcast<vec2<i32>>(frame.trample.zw);
    if (any(t < vec2<i32>(0)) || any(t >= vec2<i32>(n))) {
        return vec4<u32>(0u);
    }
    let texel = trample_texels[trample_texel(cell)];
    return select(vec4<u32>(0u), texel, texel.w == trample_tag(cell));
}

// trample.rs `push_at`: which way and how far the grass at frame ground point `xz` lies
// (length 1: flat).
fn trample_push(xz: vec2<f32>) -> vec2<f32> {
    return bitcast<vec2<f32>>(trample_texel_at(xz).xy);
}

// How tall grass may stand at frame ground point `xz`: as mown there (trample.rs `cut_at`,
// growing back), else no limit.
fn trample_cut(xz: vec2<f32>) -> f32 {
    let mown = bitcast<f32>(trample_texel_at(xz).z);
    return select(3.0e38, mown, mown > 0.0);
}
