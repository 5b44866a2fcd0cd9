#version 460
// The generated grass's placing, part two (a workgroup per list: the instanced grass's four
// levels and its rasterized blades, or the billboards' one): each generating workgroup's count
// in the list becomes how many of the list's blades the workgroups before it hold
// (instanced.comp counts, then places).
#extension GL_GOOGLE_include_directive : require
#define SWARD_WRITE
#include "common.glsl"
#include "instanced.glsl"

#define SCAN_LANES 256u
#define SCAN_BUFFER generated_counts
layout(local_size_x = 256) in;
layout(constant_id = CONSTANT_BILLBOARDS) const bool BILLBOARDS = false;
shared uint scan_partial[SCAN_LANES];
#include "scan.glsl"

void main() {
    uint base = generated_counts_base(BILLBOARDS);
    uint groups = generated_counts[base];
    exclusive_scan(base + 1u + gl_WorkGroupID.x * groups, groups);
    if (BILLBOARDS && gl_LocalInvocationID.x == 0u) {
        // The counting pass is done: the billboards listed are known, and so is the compute billboard
        // rasterizer's dispatch, three quads each, in rows of 65535 workgroups.
        uint quads = 3u * min(instanced_draws[BILLBOARD_COMMAND].instance_count, frame.billboard_meta.y);
        instanced_draws[BILLBOARD_RASTER_DISPATCH] = DrawCommand(min(quads, 65535u), (quads + 65534u) / 65535u, 1u, 0u);
    }
    if (!BILLBOARDS && gl_WorkGroupID.x == 4u && gl_LocalInvocationID.x < RASTER_CHUNKS) {
        // Likewise the instanced blades rasterized by compute, a workgroup each, chunk by chunk
        // of their list: the first sixteenth (the nearest), the next, then each chunk twice the
        // one before.
        uint blades = min(instanced_draws[RASTER_COMMAND].instance_count, frame.instanced_raster.y);
        uint k = gl_LocalInvocationID.x;
        uint first = k == 0u ? 0u : (blades >> (RASTER_CHUNKS - k));
        uint end = k + 1u == RASTER_CHUNKS ? blades : (blades >> (RASTER_CHUNKS - 1u - k));
        uint n = end - first;
        instanced_draws[RASTER_CHUNK_DISPATCH + k] = DrawCommand(min(n, 65535u), (n + 65534u) / 65535u, 1u, first);
    }
}
