// A blade's outline across its width (SPEC §6; common.glsl `blade_shape_of`): the scene's
// blade shape, or a flowering stalk with its seed head, and the normal rounded across the
// width. The Bezier blades' strips and the generated blades draw the same outlines. Needs
// frame.wgsl and blade.wgsl.

// The blade shapes (`blade_style.x`; look.rs `BladeShape::code`).
const BLADE_QUAD: u32 = 0u;
const BLADE_TRIANGLE: u32 = 1u;
const BLADE_QUADRATIC: u32 = 2u;
// A flowering stalk's outline: a thin stalk, then a slim spindle over its head.
const SEED_STALK: f32 = 0.14;
const SEED_HEAD_WIDTH: f32 = 0.5;
// How far a blade's normal tilts toward its edges (rounded across its width).
const BLADE_ROUNDING: f32 = 0.15;

fn seed_head_shape(head: f32, u: f32, v: f32) -> f32 {
    let s = clamp((v - (1.0 - head)) / head, 0.0, 1.0);
    let spindle = select(0.0, SEED_HEAD_WIDTH * pow(sin(3.14159265 * pow(s, 0.8)), 0.6), v > 1.0 - head);
    return 0.5 + (u - 0.5) * max(SEED_STALK * (1.0 - s), spindle);
}

// τ(u, v): where across the width point u of height v lies, for outline `shape` (the scene's
// blade shape in the low byte, a flowering stalk's head length in 255ths above it).
fn blade_shape_of(shape: u32, u: f32, v: f32) -> f32 {
    let head = shape >> 8u;
    if (head != 0u) {
        return seed_head_shape(f32(head) / 255.0, u, v);
    }
    if (shape == BLADE_QUAD) {
        return u;
    }
    if (shape == BLADE_TRIANGLE) {
        return u + 0.5 * v - u * v;
    }
    if (shape == BLADE_QUADRATIC) {
        return u - u * v * v;
    }
    let tip = frame.blade_style.y;
    return 0.5 + (u - 0.5) * (1.0 - max(v - tip, 0.0) / (1.0 - tip));
}

// Normal `n` of a blade whose face runs along `across`, tilted toward the edge at `u` (0 and 1
// the edges) so the blade looks rounded.
fn rounded_normal(n: vec3<f32>, across: vec3<f32>, u: f32) -> vec3<f32> {
    return normalize_or_zero(n + across * ((2.0 * u - 1.0) * BLADE_ROUNDING));
}

// The unit direction across the face of a blade facing `facing`.
fn blade_across(facing: f32) -> vec3<f32> {
    return vec3<f32>(cos(facing), 0.0, -sin(facing));
}

// A generated blade's half-width `width` as drawn `dist` from the eye: widened with distance so
// coarse levels keep their coverage (instanced.glsl `shape_start`).
fn widened(width: f32, dist: f32) -> f32 {
    let radius = frame.instanced_grid.y;
    return width * (1.0 + 1.5 * smoothstep(0.05 * radius, radius, dist));
}
