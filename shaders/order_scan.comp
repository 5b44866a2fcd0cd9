#version 460
// The ordering pass, part three (a workgroup per distance bucket): each cull workgroup's count
// in the bucket becomes how many of the bucket's blades the workgroups before it hold — an
// exclusive prefix sum over the routes.w workgroups, in their fixed order.
#extension GL_GOOGLE_include_directive : require
#define SWARD_WRITE
#define SWARD_GROUP_COUNTS
#include "common.glsl"

const uint LANES = 256u;
layout(local_size_x = 256) in;

shared uint partial[LANES];

void main() {
    uint lane = gl_LocalInvocationID.x;
    uint groups = frame.routes.w;
    uint base = gl_WorkGroupID.x * groups;
    // Each invocation a run of workgroups: its sum, the sums scanned across the workgroup, then
    // the run rewritten from where the runs before it end.
    uint run = (groups + LANES - 1u) / LANES;
    uint first = min(lane * run, groups), last = min(first + run, groups);
    uint sum = 0u;
    for (uint g = first; g < last; g++) {
        sum += group_counts[base + g];
    }
    partial[lane] = sum;
    barrier();
    for (uint offset = 1u; offset < LANES; offset <<= 1u) {
        uint add = lane >= offset ? partial[lane - offset] : 0u;
        barrier();
        partial[lane] += add;
        barrier();
    }
    uint before = partial[lane] - sum;
    for (uint g = first; g < last; g++) {
        uint n = group_counts[base + g];
        group_counts[base + g] = before;
        before += n;
    }
}
