// Tests against the depth pyramid (the occluders' farthest depth per texel, level 0 of
// occlusion.y texels across the view, occluders.rs): shared by the Bezier cull (visibility.wesl's twin) and
// the generated grass's patch cull (patch_cull.comp). Needs common.glsl.

// View depth (distance along the view axis) of a depth-buffer value, for camera near/far.
float view_depth(float z) {
    float near = frame.coarse_cull.z;
    float far = frame.coarse_cull.w;
    return near * far / (far - z * (far - near));
}

// How many pyramid texels a box may span at the level it is tested at. Measured on the H100
// (cis565 2^20): a span of 16 culled a few per cent more blades than 8, and cost more in the
// cull than it saved in the draw; 4 culled fewer.
const float HIZ_SPAN = 8.0;

// Whether the screen box lo–hi (normalized device coordinates) whose nearest point lies
// `nearest` deep (view depth) is wholly behind the pyramid's occluders, by more than the
// occlusion tolerance: tested against the farthest depth of the texels under the box, at the
// level where it spans at most HIZ_SPAN of them. A box off screen is never hidden.
bool screen_box_hidden(vec2 lo, vec2 hi, float nearest) {
    vec2 size = vec2(frame.occlusion.y);
    vec2 low = (lo * 0.5 + 0.5) * size;
    vec2 high = (hi * 0.5 + 0.5) * size;
    if (any(lessThanEqual(high, vec2(0.0))) || any(greaterThanEqual(low, size))) {
        return false; // off screen: the frustum test's business
    }
    // A texel holds its centre's depth: an occluder's edge that covers the centre may leave the
    // rest of it open, so the box reaches a texel further (as the point test's 2 × 2 do).
    low = clamp(low - 1.0, vec2(0.0), size);
    high = clamp(high + 1.0, vec2(0.0), size);
    float extent = max(high.x - low.x, high.y - low.y);
    int level = clamp(int(ceil(log2(max(extent / HIZ_SPAN, 1.0)))), 0, textureQueryLevels(hiz) - 1);
    ivec2 last_texel = textureSize(hiz, level) - 1;
    ivec2 first = min(ivec2(floor(low)) >> level, last_texel);
    ivec2 last = min(max(ivec2(ceil(high)) - 1, ivec2(0)) >> level, last_texel);
    for (int y = first.y; y <= last.y; y++) {
        for (int x = first.x; x <= last.x; x++) {
            if (view_depth(texelFetch(hiz, ivec2(x, y), level).r) + frame.coarse_cull.y >= nearest) {
                return false;
            }
        }
    }
    return true;
}
