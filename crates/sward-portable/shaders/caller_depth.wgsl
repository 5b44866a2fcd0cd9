// The caller's depth folded into the depth pyramid's level 0 (the Vulkan renderer's
// caller_depth_fold.glsl): an engine that draws its own scene — houses, rocks, terrain — before
// the grass gives its depth of the view, and the grass behind that scene is culled as the grass
// behind sward's own occluders is. Each level-0 texel takes the farthest of the caller's depths
// over every pixel (every sample) it covers, and keeps the nearer of that and the occluders'
// farthest depth: both bound every surface seen there, so the nearer bound is conservative.
// The caller's depth runs forward (0 near), from the frame's camera, the view's whole image
// mapped onto the pyramid as clip space is. A depth texture's own binding per entry point:
// single-sampled, or multisampled (a MSAA target's depth).

// The pyramid's levels (pyramid.wgsl) and the step's uniform (y: level 0's side).
@group(0) @binding(1) var<storage, read_write> levels: array<u32>;
@group(0) @binding(2) var<uniform> step: vec4<u32>;
@group(0) @binding(3) var caller_depth: texture_depth_2d;
@group(0) @binding(4) var caller_depth_samples: texture_depth_multisampled_2d;

// The caller's pixels level-0 texel `texel` covers, wholly or in part, of an image `size`
// pixels: from xy up to zw (exclusive).
fn covered_pixels(texel: vec2<u32>, size: vec2<u32>) -> vec4<u32> {
    let side = step.y;
    let lo = texel * size / side;
    let hi = max(lo + 1u, ((texel + 1u) * size + side - 1u) / side);
    return vec4<u32>(lo, min(hi, size));
}

// Level-0 texel `texel` keeps the nearer of the occluders' farthest depth and the caller's
// (a non-negative float's bits sort as the float does).
fn fold_into(texel: vec2<u32>, farthest: f32) {
    let at = texel.y * step.y + texel.x;
    levels[at] = min(levels[at], bitcast<u32>(farthest));
}

@compute @workgroup_size(8, 8)
fn fold_caller_depth(@builtin(global_invocation_id) id: vec3<u32>) {
    if (any(id.xy >= vec2<u32>(step.y))) {
        return;
    }
    let pixels = covered_pixels(id.xy, textureDimensions(caller_depth));
    var farthest = 0.0;
    for (var y = pixels.y; y < pixels.w; y++) {
        for (var x = pixels.x; x < pixels.z; x++) {
            farthest = max(farthest, textureLoad(caller_depth, vec2<u32>(x, y), 0));
        }
    }
    fold_into(id.xy, farthest);
}

@compute @workgroup_size(8, 8)
fn fold_caller_depth_samples(@builtin(global_invocation_id) id: vec3<u32>) {
    if (any(id.xy >= vec2<u32>(step.y))) {
        return;
    }
    let pixels = covered_pixels(id.xy, textureDimensions(caller_depth_samples));
    let samples = textureNumSamples(caller_depth_samples);
    var farthest = 0.0;
    for (var y = pixels.y; y < pixels.w; y++) {
        for (var x = pixels.x; x < pixels.z; x++) {
            for (var s = 0u; s < samples; s++) {
                farthest = max(farthest, textureLoad(caller_depth_samples, vec2<u32>(x, y), s));
            }
        }
    }
    fold_into(id.xy, farthest);
}
