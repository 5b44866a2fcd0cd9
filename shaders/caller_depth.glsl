// The caller's depth folded into the depth pyramid's level 0 (embedding: TargetViews::occlusion),
// drawn over level 0 as a screen-covering triangle (sky.vert) after sward's own occluders. A
// texel of level 0 stands for a block of the caller's image: it takes the farthest depth the
// caller drew anywhere in that block, every sample, so whatever lies behind it there is hidden
// by the caller's scene. The depth test keeps the nearer of that and sward's own occluders —
// either hides what is behind it. Where the caller drew nothing (its far plane) the test fails
// and sward's occluders stand. The includer defines CALLER_DEPTH_MULTISAMPLED for a
// multisampled image.
#include "common.glsl"

#ifdef CALLER_DEPTH_MULTISAMPLED
layout(set = 0, binding = BINDING_CALLER_DEPTH) uniform sampler2DMS caller_depth;
#else
layout(set = 0, binding = BINDING_CALLER_DEPTH) uniform sampler2D caller_depth;
#endif

layout(location = 0) out float out_depth;

// The caller's depth at `texel` in sward's forward convention (target_depth: a reversed
// caller's mirrored), the farthest of its samples.
float caller_depth_at(ivec2 texel) {
#ifdef CALLER_DEPTH_MULTISAMPLED
    float farthest = 0.0;
    for (int s = 0; s < textureSamples(caller_depth); s++) {
        farthest = max(farthest, target_depth(texelFetch(caller_depth, texel, s).r));
    }
    return farthest;
#else
    return target_depth(texelFetch(caller_depth, texel, 0).r);
#endif
}

void main() {
#ifdef CALLER_DEPTH_MULTISAMPLED
    ivec2 size = textureSize(caller_depth);
#else
    ivec2 size = textureSize(caller_depth, 0);
#endif
    int side = int(frame.occlusion.y);
    ivec2 texel = ivec2(gl_FragCoord.xy);
    // The caller's texels this pyramid texel covers, every one it touches at all.
    ivec2 first = texel * size / side;
    ivec2 last = max(((texel + 1) * size + side - 1) / side, first + 1);
    float farthest = 0.0;
    for (int y = first.y; y < min(last.y, size.y); y++) {
        for (int x = first.x; x < min(last.x, size.x); x++) {
            farthest = max(farthest, caller_depth_at(ivec2(x, y)));
        }
    }
    out_depth = farthest;
    gl_FragDepth = farthest;
}
