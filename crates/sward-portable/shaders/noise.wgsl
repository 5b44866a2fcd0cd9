// Hashing and noise for the portable renderer (sward-core rng.rs, wind.rs, instanced.rs; the
// Vulkan renderer's common.glsl): a hash to a unit number, value noise (the wind's gusts, the
// blades' clumps, the soil's mottle) and simplex noise (the paint's patches). Needs blade.wgsl
// (`hash_word`).

fn hash_unit(x: u32) -> f32 {
    return f32(hash_word(x) >> 8u) * (1.0 / 16777216.0);
}

fn noise_corner(cell: vec2<i32>) -> f32 {
    return f32(hash_word(u32(cell.x) + hash_word(u32(cell.y))) >> 8u) * (1.0 / 16777216.0);
}

fn value_noise(q: vec2<f32>) -> f32 {
    let cell = floor(q);
    let f = q - cell;
    let i = vec2<i32>(cell);
    let u = f * f * (vec2<f32>(3.0) - 2.0 * f);
    let bottom = noise_corner(i) + (noise_corner(i + vec2<i32>(1, 0)) - noise_corner(i)) * u.x;
    let top = noise_corner(i + vec2<i32>(0, 1)) + (noise_corner(i + vec2<i32>(1, 1)) - noise_corner(i + vec2<i32>(0, 1))) * u.x;
    return bottom + (top - bottom) * u.y;
}

// A corner of 2D simplex noise with hashed gradients (instanced.rs `simplex_noise`).
fn simplex_corner(c: vec2<f32>, x: vec2<f32>) -> f32 {
    let t = 0.5 - dot(x, x);
    if (t <= 0.0) {
        return 0.0;
    }
    let h = hash_word(u32(i32(c.x)) + hash_word(u32(i32(c.y))));
    let angle = hash_unit(h) * 6.2831855;
    return t * t * t * t * dot(vec2<f32>(cos(angle), sin(angle)), x);
}

// 2D simplex noise in [-1, 1].
fn simplex_noise(v: vec2<f32>) -> f32 {
    let SKEW = 0.36602542;
    let UNSKEW = 0.21132487;
    let i = floor(v + vec2<f32>((v.x + v.y) * SKEW));
    let near_corner = v - i + vec2<f32>((i.x + i.y) * UNSKEW);
    let step_ = select(vec2<f32>(0.0, 1.0), vec2<f32>(1.0, 0.0), near_corner.x > near_corner.y);
    let mid_corner = near_corner - step_ + vec2<f32>(UNSKEW);
    let far_corner = near_corner - vec2<f32>(1.0) + vec2<f32>(2.0 * UNSKEW);
    return 70.0 * (simplex_corner(i, near_corner) + simplex_corner(i + step_, mid_corner) + simplex_corner(i + vec2<f32>(1.0), far_corner));
}
