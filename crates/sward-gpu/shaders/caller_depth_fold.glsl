// The caller's depth folded into the depth pyramid's level 0 (embedding: TargetViews::occlusion),
// by compute after sward's own occluders are drawn there and before the pyramid is reduced. A
// texel of level 0 stands for a block of the caller's image: it takes the farthest depth the
// caller drew anywhere in that block, every sample, so whatever lies behind it there is hidden
// by the caller's scene; the texel keeps the nearer of that and sward's own occluders — either
// hides what is behind it. Where the caller drew nothing (its far plane) sward's occluders stand.
//
// LANES invocations share a texel, each fetching every LANES-th of the block's samples, and
// reduce them in shared memory: a 1920 × 1080 caller with 4 samples has 60 samples under a
// texel of a 512 × 512 level, which one invocation fetching them in turn waits on one after
// another (0.8 ms on the H100 as a fragment pass; the fragments alone cost the raster floor).
// The includer defines CALLER_DEPTH_MULTISAMPLED for a multisampled image.
#include "common.glsl"

const uint LANES = 16u;
layout(local_size_x = 256) in;

#ifdef CALLER_DEPTH_MULTISAMPLED
layout(set = 0, binding = BINDING_CALLER_DEPTH) uniform sampler2DMS caller_depth;
#else
layout(set = 0, binding = BINDING_CALLER_DEPTH) uniform sampler2D caller_depth;
#endif
layout(set = 0, binding = BINDING_PYRAMID_BASE, r32f) uniform image2D pyramid_base;

shared float farthest[256];

ivec2 caller_size() {
#ifdef CALLER_DEPTH_MULTISAMPLED
    return textureSize(caller_depth);
#else
    return textureSize(caller_depth, 0);
#endif
}

int caller_samples() {
#ifdef CALLER_DEPTH_MULTISAMPLED
    return textureSamples(caller_depth);
#else
    return 1;
#endif
}

// Sample `s` of the caller's depth at `texel`, in sward's forward convention (target_depth: a
// reversed caller's mirrored).
float caller_depth_at(ivec2 texel, int s) {
#ifdef CALLER_DEPTH_MULTISAMPLED
    return target_depth(texelFetch(caller_depth, texel, s).r);
#else
    return target_depth(texelFetch(caller_depth, texel, 0).r);
#endif
}

// The farthest of this lane's share of the samples under level-0 texel `texel` of a level
// `side` wide: the caller's texels the pyramid texel covers, every one it touches at all.
float lane_farthest(ivec2 texel, int side, uint lane) {
    ivec2 size = caller_size();
    ivec2 first = texel * size / side;
    ivec2 last = min(max(((texel + 1) * size + side - 1) / side, first + 1), size);
    ivec2 extent = last - first;
    int samples = caller_samples();
    int count = extent.x * extent.y * samples;
    float far_depth = 0.0;
    for (int i = int(lane); i < count; i += int(LANES)) {
        int t = i / samples;
        far_depth = max(far_depth, caller_depth_at(first + ivec2(t % extent.x, t / extent.x), i % samples));
    }
    return far_depth;
}

void main() {
    uint local = gl_LocalInvocationID.x;
    uint lane = local % LANES;
    uint index = gl_GlobalInvocationID.x / LANES;
    int side = imageSize(pyramid_base).x;
    ivec2 texel = ivec2(int(index) % side, int(index) / side);
    bool inside = index < uint(side * side);
    farthest[local] = inside ? lane_farthest(texel, side, lane) : 0.0;
    barrier();
    for (uint step = LANES / 2u; step > 0u; step /= 2u) {
        if (lane < step) {
            farthest[local] = max(farthest[local], farthest[local + step]);
        }
        barrier();
    }
    if (inside && lane == 0u) {
        float own = imageLoad(pyramid_base, texel).r;
        imageStore(pyramid_base, texel, vec4(min(own, farthest[local])));
    }
}
