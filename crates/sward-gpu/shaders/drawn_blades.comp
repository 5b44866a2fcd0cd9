#version 460
// The listed blades for a renderer that draws them itself (sward-bevy draws them in Bevy's own
// passes, lit by Bevy): each entry of the ordered list, after the ordering, as two words of four
// — what that renderer's vertex and fragment stages need which only sward's shaders know:
//   x: the blade's id; y: its outline (common.glsl `blade_outline`) | its strip's segments
//   (its distance bucket's, `strip_segments`) << 16; z, w and the second word: its root's, tip's
//   and seed head's colour (shading.glsl `blade_albedo`: varied by blade, clump and paint, taken
//   at its root) as half floats, and the head's part of the blade.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shading.glsl"

layout(local_size_x_id = CONSTANT_WORKGROUP) in;

layout(set = 0, binding = BINDING_DRAWN_BLADES, std430) writeonly buffer DrawnBlades { uvec4 drawn_blades[]; };

// The distance bucket whose entries hold ordered entry `i`, or none (DISTANCE_BUCKETS): each
// bucket's command says where its entries start and how many there are (an empty bucket's start
// may be anything).
uint bucket_of(uint i) {
    for (uint k = 0u; k < DISTANCE_BUCKETS; k++) {
        DrawCommand bucket = draws[COMMAND_BUCKETS + k];
        if (i >= bucket.first_instance && i < bucket.first_instance + bucket.instance_count) {
            return k;
        }
    }
    return DISTANCE_BUCKETS;
}

void main() {
    uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    uint bucket = bucket_of(i);
    if (bucket == DISTANCE_BUCKETS) {
        return;
    }
    uint id = ordered[i];
    uint key = blade_colour_key(id);
    vec3 root = blades[id].v0.xyz;
    uvec2 look = blade_look(key, world_xz(root.xz));
    vec3 vary = albedo_variation(root, key, look);
    vec3 lower = max(root_albedo(look) * vary, vec3(0.0));
    vec3 upper = max(tip_albedo(look) * vary, vec3(0.0));
    vec3 seeds = max(seed_head_albedo(look) * vary, vec3(0.0));
    uint shape = blade_outline(look) | (strip_segments(bucket) << 16u);
    drawn_blades[2u * i] = uvec4(id, shape, packHalf2x16(lower.rg), packHalf2x16(vec2(lower.b, seed_head_length(look))));
    drawn_blades[2u * i + 1u] = uvec4(packHalf2x16(upper.rg), packHalf2x16(vec2(upper.b, 0.0)), packHalf2x16(seeds.rg), packHalf2x16(vec2(seeds.b, 0.0)));
}
