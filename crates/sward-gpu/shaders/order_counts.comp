#version 460
// The ordering pass, part two (the cull's grid, invocation for invocation): how many visible
// blades each cull workgroup holds in each distance bucket, into group_counts bucket by bucket
// (cull_groups() workgroups in all). Sums, so the same whatever order the workgroups run in.
#extension GL_GOOGLE_include_directive : require
#define SWARD_WRITE
#define SWARD_GROUP_COUNTS
#include "common.glsl"

layout(local_size_x_id = CONSTANT_WORKGROUP) in;

shared uint counts[DISTANCE_BUCKETS];

void main() {
    uint lane = gl_LocalInvocationID.x;
    for (uint k = lane; k < DISTANCE_BUCKETS; k += gl_WorkGroupSize.x) {
        counts[k] = 0u;
    }
    barrier();
    uint entry = visible[CULL_SLOT()];
    if (entry != NOT_VISIBLE) {
        atomicAdd(counts[entry >> BUCKET_SHIFT], 1u);
    }
    barrier();
    uint group = CULL_GROUP();
    for (uint k = lane; k < DISTANCE_BUCKETS; k += gl_WorkGroupSize.x) {
        group_counts[k * cull_groups() + group] = counts[k];
    }
}
