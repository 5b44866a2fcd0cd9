// The depth pyramid as the culls test against it (the Vulkan renderer's hiz.glsl): each
// texel the farthest depth of the occluders it covers, and whether a screen box lies wholly
// behind them. The Bezier blades' cull and the generated grass's patches read it. Needs
// frame.wgsl and pyramid_levels.wgsl.

// The occlusion test (`modes.x`; sward-core flags.rs).
const CULL_OCCLUSION: u32 = 16u;

// The depth pyramid: the occluders' farthest depth per texel (a float's bits), level 0
// `occlusion.y` texels across the view, the levels one after another (pyramid.wgsl).
@group(0) @binding(8) var<storage, read> hiz: array<u32>;

// Texels along a side of the pyramid's level `level`.
fn pyramid_side(level: i32) -> i32 {
    return max(i32(frame.occlusion.y) >> u32(level), 1);
}

// The farthest depth the pyramid holds at `texel` of `level`.
fn pyramid_depth(texel: vec2<i32>, level: i32) -> f32 {
    let at = pyramid_start(frame.occlusion.y, u32(level)) + u32(texel.y * pyramid_side(level) + texel.x);
    return bitcast<f32>(hiz[at]);
}

// View depth (distance along the view axis) of a depth value, for the camera's near and far.
fn view_depth(z: f32) -> f32 {
    let near = frame.coarse_cull.z;
    let far = frame.coarse_cull.w;
    return near * far / (far - z * (far - near));
}

// How many pyramid texels a box may span at the level it is tested at (hiz.glsl).
const HIZ_SPAN: f32 = 8.0;

// Whether the screen box lo–hi (sward's normalized device coordinates) whose nearest point lies
// `nearest` deep is wholly behind the pyramid's occluders by more than the tolerance.
fn screen_box_hidden(lo_ndc: vec2<f32>, hi_ndc: vec2<f32>, nearest: f32) -> bool {
    let size = vec2<f32>(f32(frame.occlusion.y));
    var low = (lo_ndc * 0.5 + 0.5) * size;
    var high = (hi_ndc * 0.5 + 0.5) * size;
    if (any(high <= vec2<f32>(0.0)) || any(low >= size)) {
        return false; // off screen: the frustum test's business
    }
    // A texel holds its centre's depth: the box reaches a texel further.
    low = clamp(low - 1.0, vec2<f32>(0.0), size);
    high = clamp(high + 1.0, vec2<f32>(0.0), size);
    let extent = max(high.x - low.x, high.y - low.y);
    let levels = i32(pyramid_levels(frame.occlusion.y));
    let level = clamp(i32(ceil(log2(max(extent / HIZ_SPAN, 1.0)))), 0, levels - 1);
    let last_texel = vec2<i32>(pyramid_side(level) - 1);
    let first = min(vec2<i32>(floor(low)) >> vec2<u32>(u32(level)), last_texel);
    let last = min(max(vec2<i32>(ceil(high)) - 1, vec2<i32>(0)) >> vec2<u32>(u32(level)), last_texel);
    for (var y = first.y; y <= last.y; y++) {
        for (var x = first.x; x <= last.x; x++) {
            if (view_depth(pyramid_depth(vec2<i32>(x, y), level)) + frame.coarse_cull.y >= nearest) {
                return false;
            }
        }
    }
    return true;
}
