#version 460
// Three levels of the depth pyramid (Hi-Z) in one dispatch: each texel keeps the farthest depth
// of the 2 × 2 texels it covers one level down, so a test against it is conservative. A
// workgroup reads 16 × 16 texels of `finer`, writes 8 × 8 of the next level, then 4 × 4 and
// 2 × 2 of the two after it from shared memory — a third of the dispatches (and the barriers
// between them) of a level at a time, which is what the host pays for per frame. The pyramid is
// square with a power-of-two side (occluders.rs), so every level halves exactly; a level past
// 1 × 1 (the last dispatch's, where the levels run out) is not written.
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, r32f) uniform readonly image2D finer;
layout(set = 0, binding = 1, r32f) uniform writeonly image2D coarser1;
layout(set = 0, binding = 2, r32f) uniform writeonly image2D coarser2;
layout(set = 0, binding = 3, r32f) uniform writeonly image2D coarser3;

shared float farthest[8][8];

// The farthest of texel `t`'s 2 × 2 children in `farthest` (texels of the level below, in the
// workgroup's corner), at the step where children are `span` cells apart.
float children(uvec2 t, uint span) {
    uvec2 c = t * 2u * span;
    return max(max(farthest[c.x][c.y], farthest[c.x + span][c.y]),
               max(farthest[c.x][c.y + span], farthest[c.x + span][c.y + span]));
}

void main() {
    uvec2 local = gl_LocalInvocationID.xy;
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
    int side = imageSize(finer).x / 2;
    float depth = 0.0;
    if (all(lessThan(texel, ivec2(side)))) {
        ivec2 start = texel * 2;
        depth = max(max(imageLoad(finer, start).r, imageLoad(finer, start + ivec2(1, 0)).r),
                    max(imageLoad(finer, start + ivec2(0, 1)).r, imageLoad(finer, start + ivec2(1, 1)).r));
        imageStore(coarser1, texel, vec4(depth));
    }
    farthest[local.x][local.y] = depth;
    barrier();
    // Level two: a texel per 2 × 2 cells, kept in its cells' corner.
    ivec2 origin = ivec2(gl_WorkGroupID.xy) * 4;
    if (all(lessThan(local, uvec2(4u)))) {
        depth = children(local, 1u);
    }
    barrier();
    if (all(lessThan(local, uvec2(4u)))) {
        farthest[local.x * 2u][local.y * 2u] = depth;
        if (all(lessThan(origin + ivec2(local), ivec2(side / 2)))) {
            imageStore(coarser2, origin + ivec2(local), vec4(depth));
        }
    }
    barrier();
    // Level three: a texel per 4 × 4 cells.
    if (all(lessThan(local, uvec2(2u))) && all(lessThan(origin / 2 + ivec2(local), ivec2(side / 4)))) {
        imageStore(coarser3, origin / 2 + ivec2(local), vec4(children(local, 2u)));
    }
}
