#version 460
// The generated grass's placing, part two (a workgroup per level: the instanced field's four,
// or the billboards' one): each generating workgroup's count at the level becomes how many of
// the level's blades the workgroups before it hold (instanced.comp counts, then places).
#extension GL_GOOGLE_include_directive : require
#define SWARD_WRITE
#include "common.glsl"
#include "instanced.glsl"

#define SCAN_LANES 256u
#define SCAN_BUFFER generated_counts
layout(local_size_x = 256) in;
layout(constant_id = 0) const uint WORKGROUP = 256u;
layout(constant_id = 4) const bool BILLBOARDS = false;
shared uint scan_partial[SCAN_LANES];
#include "scan.glsl"

void main() {
    uint base = generated_counts_base(BILLBOARDS, WORKGROUP);
    uint groups = generated_counts[base];
    exclusive_scan(base + 1u + gl_WorkGroupID.x * groups, groups);
}
