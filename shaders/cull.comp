#version 460
// Per-blade culling of SPEC §4 (orientation → frustum → distance) and compaction: survivors append
// their 4-byte index to `visible`, and `draws[0].vertex_count` counts them (reset by
// vkCmdFillBuffer before this dispatch). With `modes.z` = P > 0 the draw is also split into
// commands `draws[1 + k]` of at most P patches each. Mirrors sward-core's cull.rs.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_ballot : require
#define SWARD_WRITE
#include "common.glsl"

layout(local_size_x = 256) in;
layout(constant_id = 0) const bool USE_SUBGROUPS = true;

bool seen_edge_on(Blade b, vec3 eye) {
    vec3 view_dir = normalize_or_zero(b.v0.xyz - eye);
    return abs(dot(view_dir, width_direction(b.up.xyz, b.v0.w))) > frame.cull.x;
}

bool outside_frustum(Blade b) {
    vec3 mid = 0.25 * b.v0.xyz + 0.5 * b.v1.xyz + 0.25 * b.v2.xyz;
    float t = frame.cull.y;
    return !inside_clip(frame.view_proj * vec4(b.v0.xyz, 1.0), t)
        && !inside_clip(frame.view_proj * vec4(mid, 1.0), t)
        && !inside_clip(frame.view_proj * vec4(b.v2.xyz, 1.0), t);
}

bool thinned_by_distance(Blade b, uint id, vec3 eye) {
    vec3 up = b.up.xyz;
    vec3 rel = b.v0.xyz - eye;
    float d_proj = length(rel - up * dot(rel, up));
    uint n = max(uint(frame.cull.w), 1u);
    float kept = ceil(float(n) * (1.0 - d_proj / frame.cull.z));
    return float(id % n) >= kept;
}

bool is_visible(uint id) {
    Blade b = blades[id];
    vec3 eye = frame.camera_position.xyz;
    uint tests = frame.modes.x;
    if ((tests & 1u) != 0u && seen_edge_on(b, eye)) return false;
    if ((tests & 2u) != 0u && outside_frustum(b)) return false;
    if ((tests & 4u) != 0u && thinned_by_distance(b, id, eye)) return false;
    return true;
}

// One atomic per subgroup instead of one per visible blade.
uint append_slot(bool keep) {
    if (!USE_SUBGROUPS) {
        return keep ? atomicAdd(draws[0].vertex_count, 1u) : 0u;
    }
    uvec4 ballot = subgroupBallot(keep);
    uint total = subgroupBallotBitCount(ballot);
    uint base = 0u;
    if (subgroupElect() && total > 0u) {
        base = atomicAdd(draws[0].vertex_count, total);
    }
    return subgroupBroadcastFirst(base) + subgroupBallotExclusiveBitCount(ballot);
}

void main() {
    uint id = gl_GlobalInvocationID.x;
    // No early return: every lane takes part in the subgroup vote.
    bool keep = id < frame.counts.x && is_visible(id);
    uint slot = append_slot(keep);
    if (!keep) {
        return;
    }
    visible[slot] = id;
    uint per_draw = frame.modes.z;
    if (per_draw != 0u) {
        uint k = slot / per_draw;
        atomicMax(draws[1u + k].vertex_count, slot - k * per_draw + 1u);
        if (slot == k * per_draw) {
            draws[1u + k].instance_count = 1u;
            draws[1u + k].first_vertex = k * per_draw;
        }
    }
}
