#version 460
// The ordering pass, part three (a workgroup per distance bucket): each cull workgroup's count
// in the bucket becomes how many of the bucket's blades the workgroups before it hold — an
// exclusive prefix sum over the cull's workgroups, in their fixed order.
#extension GL_GOOGLE_include_directive : require
#define SWARD_WRITE
#define SWARD_GROUP_COUNTS
#include "common.glsl"

#define SCAN_LANES 256u
#define SCAN_BUFFER group_counts
layout(local_size_x = 256) in;
shared uint scan_partial[SCAN_LANES];
#include "scan.glsl"

void main() {
    uint groups = cull_groups();
    exclusive_scan(gl_WorkGroupID.x * groups, groups);
}
