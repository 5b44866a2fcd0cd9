#version 460
// Per-blade culling of the drawn tiles' blades and compaction: survivors append their 4-byte index to `visible`, and
// `draws[0].vertex_count` counts them (reset by vkCmdFillBuffer before this dispatch). With
// `modes.z` = P > 0 the draw is also split into commands `draws[1 + k]` of at most P patches.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_vote : require
#define SWARD_WRITE
#include "common.glsl"

layout(local_size_x_id = CONSTANT_WORKGROUP) in;
layout(constant_id = CONSTANT_USE_SUBGROUPS) const bool USE_SUBGROUPS = true;

#include "culling.glsl"

void main() {
    bool inside, drawn;
    uint id = tile_blade(inside, drawn);
    // No early return: every lane takes part in the subgroup vote.
    Blade b = blades[id];
    bool keep = inside && drawn && is_visible(b, id);
    append_visible(keep, id, b);
}
