#version 460
// The ordering pass, part two: every visible blade moves from the cull pass's list (in the order
// the workgroups finished) to its distance bucket's range of the ordered list, nearest bucket
// first, so both routes draw roughly front to back and depth testing rejects hidden fragments
// before they are shaded. Dispatched indirectly with the size order_buckets.comp wrote.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_vote : require
#define SWARD_WRITE
#include "common.glsl"

layout(local_size_x_id = 0) in;
layout(constant_id = 1) const bool USE_SUBGROUPS = true;

// This blade's place within its bucket: one atomic per bucket the subgroup's blades fall in.
uint place_in_bucket(bool live, uint bucket) {
    if (!USE_SUBGROUPS) {
        return live ? atomicAdd(draws[COMMAND_BUCKETS + bucket].instance_count, 1u) : 0u;
    }
    bool pending = live;
    uint place = 0u;
    while (subgroupAny(pending)) {
        if (pending) {
            uint first = subgroupBroadcastFirst(bucket);
            if (bucket == first) {
                uvec4 ballot = subgroupBallot(true);
                uint base = 0u;
                if (subgroupElect()) {
                    base = atomicAdd(draws[COMMAND_BUCKETS + bucket].instance_count, subgroupBallotBitCount(ballot));
                }
                place = subgroupBroadcastFirst(base) + subgroupBallotExclusiveBitCount(ballot);
                pending = false;
            }
        }
    }
    return place;
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    bool live = i < draws[COMMAND_ALL].vertex_count;
    uint entry = live ? visible[i] : 0u;
    uint bucket = entry >> BUCKET_SHIFT;
    uint place = place_in_bucket(live, bucket);
    if (live) {
        ordered[draws[COMMAND_BUCKETS + bucket].first_instance + place] = entry & ((1u << BUCKET_SHIFT) - 1u);
    }
}
