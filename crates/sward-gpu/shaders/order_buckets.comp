#version 460
// The ordering pass, part one (one workgroup): from the cull pass's per-bucket counts, where each
// distance bucket starts in the ordered list, each bucket's strip draw command (and the next
// frame's blade occluders among them: the nearest, up to frame.occlusion.x), the dispatch
// sizes of the compute route's raster_blades.comp and splat_blades.comp, of the exact-distance
// sort (order_sort.comp) and, where the driver
// needs it (modes.z > 0), the tessellation route's draw split into commands of modes.z patches.
#extension GL_GOOGLE_include_directive : require
#define SWARD_WRITE
#include "common.glsl"

layout(local_size_x = 64) in;
layout(constant_id = CONSTANT_WORKGROUP) const uint ORDER_WORKGROUP = 256u;

shared uint bucket_counts[DISTANCE_BUCKETS];

void main() {
    uint k = gl_LocalInvocationID.x;
    if (k < DISTANCE_BUCKETS) {
        bucket_counts[k] = draws[COMMAND_BUCKETS + k].instance_count;
    }
    barrier();
    uint total = draws[COMMAND_ALL].vertex_count;
    if (k < DISTANCE_BUCKETS) {
        uint start = 0u;
        for (uint j = 0u; j < k; j++) {
            start += bucket_counts[j];
        }
        // Three columns when the ridge folds the blade at u = 0.5, else two.
        uint columns = blade_ridge() ? 4u : 2u;
        uint vertices = columns * (strip_segments(k) + 1u);
        draws[COMMAND_BUCKETS + k] = DrawCommand(vertices, bucket_counts[k], 0u, start);
        // The next frame's blade occluders: the nearest frame.occlusion.x of these blades.
        uint budget = frame.occlusion.x;
        uint occluders = min(bucket_counts[k], budget - min(start, budget));
        uint occluder_vertices = 2u * (min(strip_segments(k), OCCLUDER_SEGMENTS) + 1u);
        draws[COMMAND_OCCLUDERS + k] = DrawCommand(occluder_vertices, occluders, 0u, start);
    }
    if (k == 0u) {
        // The compute route splats the buckets from routes.x on: its dispatch size, and (in the
        // command's last word) where those blades start in the ordered list.
        uint first_splatted = 0u;
        for (uint j = 0u; j < min(frame.routes.x, DISTANCE_BUCKETS); j++) {
            first_splatted += bucket_counts[j];
        }
        uint splatted = total - first_splatted;
        draws[COMMAND_SPLAT_DISPATCH] = DrawCommand((splatted + ORDER_WORKGROUP - 1u) / ORDER_WORKGROUP, 1u, 1u, first_splatted);
        // Its rasterizer the buckets from routes.y up to those: the first pass's workgroups (a
        // blade each, rows of 65535 groups; raster_blades.comp) and where its blades start; it
        // has left nothing to the second pass yet.
        uint first_rasterized = 0u;
        for (uint j = 0u; j < min(frame.routes.y, DISTANCE_BUCKETS); j++) {
            first_rasterized += bucket_counts[j];
        }
        uint rasterized = first_splatted - min(first_rasterized, first_splatted);
        draws[COMMAND_RASTER_DISPATCH] = DrawCommand(min(rasterized, 65535u), (rasterized + 65534u) / 65535u, 1u, first_rasterized);
        draws[COMMAND_RASTER_LEFT] = DrawCommand(0u, 0u, 0u, 0u);
        // The exact-distance sort: runs of 8192 entries (order_sort.comp) of what is drawn by
        // a rasterizer, hardware or compute; the splats need no order.
        draws[COMMAND_SORT_DISPATCH] = DrawCommand((first_splatted + 8191u) / 8192u, 1u, 1u, first_splatted);
        // The mesh route: two blades per workgroup, rows of 65535 groups (blade.mesh).
        uint groups = (total + 1u) / 2u;
        draws[COMMAND_MESH_DISPATCH] = DrawCommand(min(groups, 65535u), max((groups + 65534u) / 65535u, 1u), 1u, 0u);
    }
    uint per_draw = frame.modes.z;
    if (per_draw != 0u) {
        uint splits = (frame.counts.x + per_draw - 1u) / per_draw;
        for (uint s = k; s < splits; s += gl_WorkGroupSize.x) {
            uint first = s * per_draw;
            uint n = first < total ? min(per_draw, total - first) : 0u;
            draws[COMMAND_SPLITS + s] = DrawCommand(n, n > 0u ? 1u : 0u, first, 0u);
        }
    }
}
