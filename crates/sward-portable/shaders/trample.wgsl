// The trample map's frame (sward-core trample.rs `TrampleMap::step`, an invocation per texel;
// the Vulkan renderer's trample.comp): the texel takes the cell of the window around the eye
// it now holds (starting upright and uncut if that cell is new to it), recovers by the Bezier
// blades' η rule (SPEC §3.7: strength falls by simulation.y per second, over the frame's
// steps) and grows back by trample.regrow per second where mown; then every pushing collider
// presses it where it flattens the grass more than it already is — away from its centre, by
// how deep its underside reaches into the grass above the ground there — and every cutter mows
// it down to its underside where that is lower. Needs frame.wgsl, blade.wgsl,
// trample_map.wgsl and ground_grid.wgsl.

@group(0) @binding(9) var<storage, read_write> trample_texels: array<vec4<u32>>;

// The forces that act (`counts.w`; sward-core flags.rs): colliders press only with collisions on.
const TRAMPLE_COLLISIONS: u32 = 8u;
// trample.rs `STUBBLE` and `GROWN_BACK`.
const STUBBLE: f32 = 0.02;
const GROWN_BACK: f32 = 16.0;

// trample.rs `underside`: how high above the ground a sphere's underside is over `xz` (x), and
// whether the sphere is over it at all (y > 0).
fn underside(sphere: vec4<f32>, xz: vec2<f32>, ground: f32) -> vec2<f32> {
    let away = xz - sphere.xz;
    let reach = sphere.w * sphere.w - dot(away, away);
    return vec2<f32>(sphere.y - sqrt(max(reach, 0.0)) - ground, reach);
}

// trample.rs `stamp`.
fn stamp(collider: vec4<f32>, xz: vec2<f32>, ground: f32, grass_top: f32) -> vec2<f32> {
    let under = underside(collider, xz, ground);
    if (under.y <= 0.0 || grass_top <= 0.0) {
        return vec2<f32>(0.0);
    }
    let away = xz - collider.xz;
    let depth = clamp((grass_top - under.x) / grass_top, 0.0, 1.0);
    return select(vec2<f32>(1.0, 0.0), normalize(away), dot(away, away) > 0.0) * depth;
}

// trample.rs `cut`: how high a cutter leaves the grass at `xz`, 0 where it does not reach
// into it.
fn cut(cutter: vec4<f32>, xz: vec2<f32>, ground: f32, grass_top: f32) -> f32 {
    let under = underside(cutter, xz, ground);
    if (under.y <= 0.0 || under.x >= grass_top) {
        return 0.0;
    }
    return max(under.x, STUBBLE);
}

// trample.rs `regrown`.
fn regrown(height: f32, amount: f32) -> f32 {
    if (height <= 0.0 || height + amount >= GROWN_BACK) {
        return 0.0;
    }
    return height + amount;
}

@compute @workgroup_size(16, 16)
fn trample(@builtin(global_invocation_id) id: vec3<u32>) {
    let n = i32(frame.trample.x);
    let t = vec2<i32>(id.xy);
    if (any(t >= vec2<i32>(n))) {
        return;
    }
    let base = bitcast<vec2<i32>>(frame.trample.zw);
    let cell = base + trample_wrap(t - base, n);
    let tag = trample_tag(cell);
    let i = u32(t.y * n + t.x);
    let texel = trample_texels[i];
    let kept = select(vec4<u32>(0u), texel, texel.w == tag);
    var push = bitcast<vec2<f32>>(kept.xy);
    let strength = length(push);
    let seconds = frame.simulation.x * f32(frame.counts.y);
    let amount = frame.simulation.y * seconds;
    push *= select(0.0, max(strength - amount, 0.0) / strength, strength > 0.0);
    var mown = regrown(bitcast<f32>(kept.z), bitcast<f32>(frame.mowing.y) * seconds);
    let world = (vec2<f32>(cell) + 0.5) * bitcast<f32>(frame.trample.y);
    let ground = grid_height(world);
    // The colliders are in the frame's numbers.
    let xz = frame_xz(world);
    // As tall as the generated grass grows.
    let grass_top = max(frame.instanced_shape.y, frame.billboard_shape.y);
    let colliding = (frame.counts.w & TRAMPLE_COLLISIONS) != 0u;
    let pushing = select(0u, frame.counts.z, colliding);
    for (var k = 0u; k < pushing; k++) {
        let pressed = stamp(frame.colliders[k], xz, ground, grass_top);
        if (length(pressed) > length(push)) {
            push = pressed;
        }
    }
    // The cutters, after the pushing colliders.
    let cutters = select(0u, frame.mowing.x, colliding);
    for (var k = frame.counts.z; k < frame.counts.z + cutters; k++) {
        let h = cut(frame.colliders[k], xz, ground, grass_top);
        if (h > 0.0) {
            mown = select(h, min(mown, h), mown > 0.0);
        }
    }
    trample_texels[i] = vec4<u32>(bitcast<vec2<u32>>(push), bitcast<u32>(mown), tag);
}
