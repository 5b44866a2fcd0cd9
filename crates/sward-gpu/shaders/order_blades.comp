#version 460
// The ordering pass, part four (the cull's grid, invocation for invocation): each visible blade
// into its place in the ordered list — its bucket's start, plus the bucket's blades in earlier
// cull workgroups (order_scan.comp), plus those before it in its own workgroup. Every place is
// decided by the cull's fixed slots, never by which workgroup ran first, so the ordered list —
// and with it the order blades are drawn in, which decides depth ties — is the same every run:
// nearest bucket first, and within a bucket in the field's order.
#extension GL_GOOGLE_include_directive : require
#define SWARD_WRITE
#define SWARD_GROUP_COUNTS
#include "common.glsl"

layout(local_size_x_id = CONSTANT_WORKGROUP) in;

// The workgroup's verdicts (at most 1024 invocations a workgroup).
shared uint entries[1024];

void main() {
    uint lane = gl_LocalInvocationID.x;
    uint entry = visible[CULL_SLOT()];
    entries[lane] = entry;
    barrier();
    if (entry == NOT_VISIBLE) {
        return;
    }
    uint bucket = entry >> BUCKET_SHIFT;
    uint rank = 0u;
    for (uint j = 0u; j < lane; j++) {
        rank += uint(entries[j] != NOT_VISIBLE && (entries[j] >> BUCKET_SHIFT) == bucket);
    }
    uint group = CULL_GROUP();
    uint place = draws[COMMAND_BUCKETS + bucket].first_instance + group_counts[bucket * cull_groups() + group] + rank;
    ordered[place] = entry & ((1u << BUCKET_SHIFT) - 1u);
}
