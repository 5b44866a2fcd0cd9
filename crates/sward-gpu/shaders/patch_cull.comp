#version 460
// The generated grass's patch lists, built on the GPU (SPEC §7 [F]): one workgroup per grid (0
// the instanced grass's, 1 the billboards'), over the grid patches around the eye in the ring
// order the host laid out once (nearest rings first, instanced.rs `patch_order`), keeps those
// that reach into the cut-off radius and out of the inner radius, touch the view frustum and,
// where this frame's depth pyramid holds the occluders, are not wholly behind them; and writes
// them, in that order, as the rows the generating passes (instanced.comp) are dispatched over,
// with the dispatch's size — and the placing pass's, up to the last kept patch within the reach
// of listed blades. sward-core's `instanced::patches` is the same rule on the CPU.
#extension GL_GOOGLE_include_directive : require
#define SWARD_WRITE
#include "common.glsl"
#include "hiz.glsl"

layout(local_size_x = 256) in;
// The billboards' grid's generating workgroup size (the instanced grass's: INSTANCED_WORKGROUP).
layout(constant_id = CONSTANT_WORKGROUP) const uint WORKGROUP = 256u;

shared uint kept_before[256];
// Rows up to the last kept patch that may hold a listed blade.
shared uint listed_rows;

struct Grid {
    float size;    // a patch's side
    float radius;  // cut-off
    float inner;   // inner radius
    float top;     // highest a blade reaches above the ground
    float listed;  // blades within this distance may be listed (drawn by the raster hardware)
    int reach;     // patches each way from the eye's
    uint first;    // first row of its list
    uint capacity; // rows it may fill
};

Grid grid_of(uint g) {
    Grid grid;
    vec4 p = g == 0u ? frame.instanced_grid : frame.billboard_grid;
    grid.size = float(PATCH_CELLS) * p.x;
    grid.radius = p.y;
    grid.inner = p.z;
    // The instanced grass lists blades short of the splats (those the compute rasterizer takes
    // too, apart); every billboard is listed.
    grid.listed = g == 0u ? frame.instanced_lod.w : 3.0e38;
    grid.top = g == 0u ? frame.patch_bounds.z : frame.patch_bounds.w;
    grid.reach = int(g == 0u ? frame.patch_cull.z : frame.patch_cull.w);
    grid.first = g == 0u ? 0u : frame.billboard_meta.z;
    grid.capacity = g == 0u ? frame.billboard_meta.z : frame.patch_cull.x - frame.billboard_meta.z;
    return grid;
}

// Whether the box lo–hi lies wholly behind this frame's occluders.
bool box_behind_occluders(vec3 lo, vec3 hi) {
    vec2 ndc_lo = vec2(1e30);
    vec2 ndc_hi = vec2(-1e30);
    float nearest = 1e30;
    for (int i = 0; i < 8; i++) {
        vec3 corner = vec3((i & 1) != 0 ? hi.x : lo.x, (i & 2) != 0 ? hi.y : lo.y, (i & 4) != 0 ? hi.z : lo.z);
        vec4 clip = frame.view_proj * vec4(corner, 1.0);
        if (clip.w <= frame.coarse_cull.z) {
            return false; // reaches the near plane
        }
        ndc_lo = min(ndc_lo, clip.xy / clip.w);
        ndc_hi = max(ndc_hi, clip.xy / clip.w);
        nearest = min(nearest, clip.w);
    }
    return screen_box_hidden(ndc_lo, ndc_hi, nearest);
}

// The patch at `offset` from the eye's, or no patch (off the grid's reach or culled); `listed`:
// whether it reaches within the distance where blades are listed.
bool kept(Grid grid, ivec2 offset, out ivec2 patch_, out bool listed) {
    listed = false;
    vec3 eye = frame.camera_position.xyz;
    // World patches (their cells' hashes are the world's), boxed in the frame's numbers.
    patch_ = ivec2(floor(world_xz(eye.xz) / grid.size)) + offset;
    if (max(abs(offset.x), abs(offset.y)) > grid.reach) {
        return false;
    }
    vec3 lo = vec3(frame_xz(vec2(patch_) * grid.size), frame.patch_bounds.x).xzy - vec3(grid.top);
    vec3 hi = vec3(frame_xz(vec2(patch_ + 1) * grid.size), frame.patch_bounds.y + grid.top).xzy + vec3(grid.top);
    vec3 nearest = clamp(eye, lo, hi);
    vec3 farthest = vec3(eye.x - lo.x > hi.x - eye.x ? lo.x : hi.x, eye.y, eye.z - lo.z > hi.z - eye.z ? lo.z : hi.z);
    if (distance(nearest, eye) > grid.radius || distance(farthest, eye) < grid.inner) {
        return false;
    }
    listed = distance(nearest, eye) < grid.listed;
    for (int k = 0; k < 6; k++) {
        vec4 plane = frame.frustum[k];
        vec3 corner = mix(lo, hi, greaterThanEqual(plane.xyz, vec3(0.0)));
        if (dot(plane.xyz, corner) + plane.w < 0.0) {
            return false;
        }
    }
    // The frame's occlusion bit is set only where its pyramid can hide grass (plan.rs).
    bool pyramid = (frame.modes.x & CULL_OCCLUSION) != 0u;
    return !(pyramid && box_behind_occluders(lo, hi));
}

void main() {
    uint g = gl_WorkGroupID.x;
    uint lane = gl_LocalInvocationID.x;
    Grid grid = grid_of(g);
    uint table = frame.patch_cull.x;
    uint count = 0u;
    if (lane == 0u) {
        listed_rows = 0u;
    }
    bool on = g == 0u ? draws_instanced() : draws_billboards();
    for (uint start = 0u; on && start < frame.patch_cull.y; start += 256u) {
        ivec2 patch_ = ivec2(0);
        bool listed = false;
        uint entry = start + lane;
        bool keep = entry < frame.patch_cull.y && kept(grid, instanced_patches[table + entry].xy, patch_, listed);
        // Rows in table order: an exclusive scan of the kept flags across the workgroup.
        kept_before[lane] = uint(keep);
        barrier();
        for (uint step = 1u; step < 256u; step <<= 1u) {
            uint add = lane >= step ? kept_before[lane - step] : 0u;
            barrier();
            kept_before[lane] += add;
            barrier();
        }
        uint row = count + kept_before[lane] - uint(keep);
        if (keep && row < grid.capacity) {
            instanced_patches[grid.first + row] = ivec4(patch_, 0, 0);
            if (listed) {
                atomicMax(listed_rows, row + 1u);
            }
        }
        count += kept_before[255];
        barrier();
    }
    if (lane == 0u) {
        // At most a row of workgroups per patch the device is sure to dispatch.
        uint rows = min(min(count, grid.capacity), 65535u);
        uint workgroup = g == 0u ? INSTANCED_WORKGROUP : WORKGROUP;
        uint across = (1024u + workgroup - 1u) / workgroup;
        instanced_draws[PATCH_DISPATCH + g] = DrawCommand(across, rows, 1u, 0u);
        instanced_draws[PLACE_DISPATCH + g] = DrawCommand(across, min(listed_rows, rows), 1u, 0u);
        // The placing counts are laid out by the workgroups of the whole list.
        generated_counts[generated_counts_base(g == 1u)] = across * rows;
    }
}
