// The instanced grass (SPEC §7 [F]), one invocation per grid cell of the frame's patches: make the
// cell's blade from its hash (instanced.rs `blade_at`), cull it (bounding sphere against the
// frustum, distance cut-off, inner radius; `lod_of`), and list it at its level — in two passes
// (see main), so each blade's place in its list is the grid's, the same every run — counting
// into that level's draw command (reset by vkCmdFillBuffer before the first). Blades
// beyond the splat distance are not listed but splatted: walked from root to tip a pixel at a
// time, each pixel shaded and kept if nearest by a 64-bit atomicMin of (depth, colour) into the
// splat buffer, which splat.frag then resolves into the frame. Their count goes to the fifth
// draw command, which is never drawn (a workgroup of mostly splatted blades queues them by the
// shape of their walk first: `queue_splats`). Blades from the raster distance (instanced::raster_from) up
// to the splat distance are listed apart (RASTER_LEVEL), for instanced_raster.wesl to rasterize
// by compute, and counted with the splatted ones. The placing pass runs only over the patches
// that may hold listed blades (patch_cull.wesl's PLACE_DISPATCH), the nearest of the list.
// Included by instanced.comp (with splats: SWARD_SPLAT_WRITE and the int64 atomics) and by
// instanced_drawn.comp (without them, for devices that lack 64-bit atomics; the renderer sets no
// splat distance there, so no blade is ever at the splat level).
#define SWARD_WRITE
#include "common.glsl"
#include "instanced.glsl"
#include "blade_surface.glsl"
#include "shading.glsl"
#include "billboard.glsl"
#ifdef SWARD_SPLAT_WRITE
#include "splat.glsl"
#define BILLBOARD_COVERAGE_COMPUTE
#include "billboard_coverage.glsl"
#include "billboard_splat.glsl"
#endif

layout(local_size_x_id = CONSTANT_WORKGROUP) in;
// The billboards' dispatch (billboard.rs `as_grid`): the same generation and culling over the
// billboard grid, one list, counted in the sixth draw command; billboards beyond their splat
// distance splatted (billboard_splat.glsl) and counted with the splatted blades.
layout(constant_id = CONSTANT_BILLBOARDS) const bool BILLBOARDS = false;
// The second pass: place the blades the first counted (see main).
layout(constant_id = CONSTANT_PLACE) const bool PLACE = false;
layout(constant_id = CONSTANT_WORKGROUP) const uint WORKGROUP = 256u;

// What this dispatch generates: the instanced grass's grid or the billboards'.
struct Grid {
    float spacing;
    float radius;
    float inner_radius;
    float clump_scale;
    vec4 shape; // height min, max; half-width min, max
    float bend;
    float sway;
    uint seed;
    vec4 lod; // xyz level distances, w splat distance
    float raster_from; // rasterized by compute from here to the splat distance
};

Grid this_grid() {
    Grid g;
    if (BILLBOARDS) {
        g.spacing = frame.billboard_grid.x;
        g.radius = frame.billboard_grid.y;
        g.inner_radius = frame.billboard_grid.z;
        g.clump_scale = frame.billboard_grid.w;
        g.shape = frame.billboard_shape;
        g.bend = 0.0;
        g.sway = frame.billboard_motion.x;
        g.seed = frame.billboard_meta.w;
        g.lod = vec4(vec3(3.0e38), frame.billboard_far.y); // one level, far billboards splatted
        g.raster_from = 3.0e38; // billboard_raster.wesl rasterizes billboards from the listed ones
    } else {
        g.spacing = frame.instanced_grid.x;
        g.radius = frame.instanced_grid.y;
        g.inner_radius = frame.instanced_grid.z;
        g.clump_scale = frame.instanced_grid.w;
        g.shape = frame.instanced_shape;
        g.bend = frame.instanced_motion.x;
        g.sway = frame.instanced_motion.y;
        g.seed = frame.instanced_meta.x;
        g.lod = frame.instanced_lod;
        g.raster_from = frame.instanced_motion.z;
    }
    return g;
}

InstancedBlade blade_at(ivec2 cell, Grid g) {
    InstancedBlade b = instanced_blade_of(cell, g.spacing, g.clump_scale, g.shape, g.bend, g.seed, !BILLBOARDS);
    // Mown (the trample map's cut, growing back): no taller than the cut.
    b.height = min(b.height, trample_cut(b.root.xz));
    return b;
}

const int SPLAT_LEVEL = 4;
// Rasterized by compute (instanced_raster.wesl): listed apart, counted with the splatted blades.
const int RASTER_LEVEL = 5;
const float SPLAT_BAND = 0.1; // instanced.rs SPLAT_BAND
// Bounds on a splatted blade's pixels: a blade this big should be drawn, not splatted.
const int MAX_SPLAT_STEPS = 256;
const int MAX_SPLAT_ACROSS = 16;

// instanced.rs `splatted`: beyond the splat distance, or within its dissolve band by a per-blade
// threshold that rises with distance.
bool splatted(float dist, uint hash, float splat_distance) {
    float band = SPLAT_BAND * splat_distance;
    float start = splat_distance - band;
    return dist >= splat_distance || (dist > start && hash_unit(hash_u32(hash ^ 0x2545f491u)) * band < dist - start);
}

// The blade's level of detail (SPLAT_LEVEL when splatted, RASTER_LEVEL when rasterized by
// compute), or -1 when culled.
int lod_of(InstancedBlade b, Grid g) {
    if (b.height <= 0.0) {
        return -1;
    }
    vec3 center = b.root + vec3(0.0, 0.5 * b.height, 0.0);
    // A blade settles anywhere its length reaches above the ground (gravity, wind, the trample
    // map laying it down); a billboard stands, swaying.
    float radius = BILLBOARDS ? 0.5 * b.height * (1.0 + g.sway) + b.width : 1.15 * b.height + b.width;
    if (frame.trample.x > 0u) {
        // A trampled billboard lies along the ground up to its height from its root.
        radius = max(radius, 1.15 * b.height + b.width);
    }
    for (int k = 0; k < 6; k++) {
        if (dot(frame.frustum[k].xyz, center) + frame.frustum[k].w < -radius) {
            return -1;
        }
    }
    float dist = length(b.root - frame.camera_position.xyz);
    if (dist >= g.radius || dist < g.inner_radius) {
        return -1;
    }
    vec4 lod = g.lod;
    if (splatted(dist, b.hash, lod.w)) {
        return SPLAT_LEVEL;
    }
    if (dist >= g.raster_from) {
        return RASTER_LEVEL;
    }
    return strip_level(dist, lod);
}

// Splat blade `b` in the scene's blade silhouette (as the drawn blades have it); or on the
// billboards' grid billboard `b` (billboard_splat.glsl).
void splat_instanced(InstancedBlade b, float dist) {
#ifdef SWARD_SPLAT_WRITE
    if (BILLBOARDS) {
        splat_billboard(Billboard(b.root, b.height, b.width, b.facing, b.hash), dist);
        return;
    }
    Shape sh = instanced_shape(b, dist);
    // As splat_blades.wesl splats the Bezier blades: as leaves.
    splat_blade(SplatBlade(sh.p0, sh.p1, sh.p2, sh.across, sh.width, blade_shape_code(), b.hash), MAX_SPLAT_STEPS, MAX_SPLAT_ACROSS);
#endif
}

// Write blade `b` at `slot` of the list starting at `list` (instanced.glsl `unpack_blade`).
void store_blade(uint list, uint slot, InstancedBlade b) {
    uint at = 2u * (list + slot);
    instanced_blades[at] = uvec4(floatBitsToUint(b.root), packHalf2x16(vec2(b.height, b.width)));
    instanced_blades[at + 1u] = uvec4(pack_facing_tip(b), b.hash, b.outline);
}

// Each workgroup's blades per level (the four, splatted, rasterized), then (placing) each
// invocation's level: a token slot in the counting pass, whose shared memory the queue needs.
shared uint level_counts[6];
shared int lane_levels[PLACE ? WORKGROUP : 1u];

// A workgroup whose blades are mostly splatted (three quarters or more: the dense far field)
// queues them by the shape of their walk before splatting them (`queue_splats`); one with fewer
// splats them as they are. On the H200 the queue took 0.29 ms off the instanced grass at 2^26
// candidates, where nearly every far workgroup is full, and queueing every workgroup with a
// splatted blade cost the landscape's generating passes 0.13 ms (its workgroups splat few, and
// would pay the queue's barriers for little): from half or from 200 of 256 up, the landscape
// read as without the queue (BENCHMARKS.md, "Each workgroup's splatted blades queued by their
// walk"). In workgroups of a whole patch the queue is worth 0.37 ms at 2^26; from half of 1024
// it reads the same, from any splatted blade the landscape's generating passes cost 0.11 ms more.
const uint QUEUE_FROM = WORKGROUP - WORKGROUP / 4u;
// Bins of the queue: cells across at the root (0 to 7 and more) by steps (octaves). On the
// H200 at 2^26 candidates these bins generated 0.10 ms faster than four widths by half
// octaves of steps, and 0.4 ms faster than steps first (BENCHMARKS.md).
const uint SPLAT_BINS = 64u;
// The queue's slots: one per invocation in the counting pass of the instanced grass's grid, a
// token one where nothing is queued — the shared memory a dispatch declares is the L1 cache it
// loses, and with the queue's first 10 KiB (256 slots of 40 bytes) the billboards' dispatch,
// which queues nothing, read 1.6 % slower at 2^24 on the H200.
#ifdef SWARD_SPLAT_WRITE
const uint QUEUE_SLOTS = BILLBOARDS || PLACE ? 1u : WORKGROUP;
#else
const uint QUEUE_SLOTS = 1u;
#endif
shared uint splat_bin_counts[SPLAT_BINS];
// A queued blade in 20 bytes (a workgroup of 1024 queues in 20 KiB): what its noise, paint and
// ground decided — its root's height, its height, width and hash — and its kind and cell in
// the patch; its hash makes the rest again (instanced.glsl `blade_xz` and the others).
shared uvec4 queued_size[QUEUE_SLOTS]; // root height, height, width, hash
shared uint queued_cell[QUEUE_SLOTS];  // cell in the patch | kind << 10

// The shape of splatted blade `b`'s walk, `dist` from the eye, as a bin of the queue: its cells
// across at the root and its steps, as it would stand upright unposed — an estimate (the walk
// is the posed blade's), which orders the queue and nothing else.
uint splat_walk_bin(InstancedBlade b, float dist) {
#ifdef SWARD_SPLAT_WRITE
    vec4 c0 = frame.view_proj * vec4(b.root, 1.0);
    if (c0.w <= 1e-3) {
        return 0u;
    }
    Shape s = shape_start(b, dist);
    vec4 up = frame.view_proj * vec4(0.0, b.height, 0.0, 0.0);
    vec4 across = frame.view_proj * vec4(s.across * s.width, 0.0);
    vec2 q0 = to_cells(c0);
    float steps = distance(to_cells(c0 + up), q0);
    float cells = 2.0 * distance(to_cells(c0 + across), q0);
    uint steps_bin = uint(clamp(log2(max(steps, 1.0)), 0.0, 7.0));
    return uint(clamp(cells, 0.0, 7.0)) * 8u + steps_bin;
#else
    return 0u;
#endif
}

// Queue blade `b` of grid cell `cell` in patch `patch_` at `slot`.
void queue_blade(uint slot, InstancedBlade b, ivec2 cell, ivec2 patch_) {
    uvec2 in_patch = uvec2(cell - patch_ * PATCH_CELLS);
    queued_size[slot] = uvec4(floatBitsToUint(vec3(b.root.y, b.height, b.width)), b.hash);
    queued_cell[slot] = (in_patch.y * uint(PATCH_CELLS) + in_patch.x) | (b.species << 10u);
}

// The blade queued at `slot` by a workgroup of patch `patch_`, as `blade_at` made it.
InstancedBlade queued_blade(uint slot, ivec2 patch_, Grid g) {
    uvec4 size = queued_size[slot];
    uint local = queued_cell[slot] & 1023u;
    ivec2 cell = patch_ * PATCH_CELLS + ivec2(local % uint(PATCH_CELLS), local / uint(PATCH_CELLS));
    InstancedBlade b;
    b.hash = size.w;
    b.species = queued_cell[slot] >> 10u;
    vec2 at = frame_xz(blade_xz(cell, b.hash, g.spacing));
    b.root = vec3(at.x, uintBitsToFloat(size.x), at.y);
    b.height = uintBitsToFloat(size.y);
    b.width = uintBitsToFloat(size.z);
    b.facing = blade_facing(b.hash);
    b.bend = blade_bend(width_lean_hash(b.hash), b.species, g.bend, true);
    b.outline = grown_outline(b.hash, b.species, true);
    b.tip = b.root;
    return b;
}

// The workgroup's `splatted` blades (this invocation's `b` if `splat`), queued by the shape of
// their walk and splatted, the first `splatted` invocations taking one each: the 32 lanes of a
// subgroup walk together and take as long as their longest blade and widest step, so lanes
// with blades of one shape waste less of it, and the subgroups past the last queued blade end
// at once. Each cell keeps the nearest of what reaches it, whatever the order: the picture is
// the same. Called by every invocation of the workgroup (it holds barriers); `cell` is the
// invocation's grid cell, in patch `patch_`.
void queue_splats(bool splat, InstancedBlade b, ivec2 cell, ivec2 patch_, uint splatted) {
    uint lane = gl_LocalInvocationID.x;
    if (lane < SPLAT_BINS) {
        splat_bin_counts[lane] = 0u;
    }
    barrier();
    uint bin = 0u, rank = 0u;
    if (splat) {
        bin = splat_walk_bin(b, length(b.root - frame.camera_position.xyz));
        rank = atomicAdd(splat_bin_counts[bin], 1u);
    }
    barrier();
    if (splat) {
        uint slot = rank;
        for (uint k = 0u; k < bin; k++) {
            slot += splat_bin_counts[k];
        }
        queue_blade(slot, b, cell, patch_);
    }
    barrier();
    if (lane < splatted) {
        InstancedBlade queued = queued_blade(lane, patch_, this_grid());
        splat_instanced(queued, length(queued.root - frame.camera_position.xyz));
    }
}

// The lists a grid's blades are placed in: the instanced grass's four levels and its rasterized
// blades (list 4), or the billboards' one.
uint list_count() {
    return BILLBOARDS ? 1u : 5u;
}

// The level whose blades list `k` holds.
uint level_of_list(uint k) {
    return k < 4u ? k : uint(RASTER_LEVEL);
}

// The draw command counting list `k`'s blades.
uint command_of_list(uint k) {
    return BILLBOARDS ? BILLBOARD_COMMAND : (k < 4u ? k : RASTER_COMMAND);
}

// Counting: this workgroup's blades per list into its counts (and the lists' commands, sums, so
// in no particular order), then the splatted blades splatted (`cell`: this invocation's grid
// cell, in patch `patch_`).
void count_levels(int lod, InstancedBlade b, ivec2 cell, ivec2 patch_, uint base, uint group, uint groups) {
    uint lane = gl_LocalInvocationID.x;
    if (lane < 6u) {
        level_counts[lane] = 0u;
    }
    barrier();
    if (lod >= 0) {
        atomicAdd(level_counts[uint(lod)], 1u);
    }
    barrier();
    if (lane < list_count()) {
        uint n = level_counts[level_of_list(lane)];
        generated_counts[base + 1u + lane * groups + group] = n;
        atomicAdd(instanced_draws[command_of_list(lane)].instance_count, n);
    }
    if (lane == uint(SPLAT_LEVEL)) {
        // The blades drawn by compute, splatted and rasterized, are also counted together (the
        // fifth command, never drawn).
        uint n = level_counts[SPLAT_LEVEL] + level_counts[RASTER_LEVEL];
        atomicAdd(instanced_draws[SPLAT_LEVEL].instance_count, n);
    }
    // Last, past the barriers: a subgroup whose blades are splatted sooner ends, rather than
    // waiting at a barrier for the workgroup's longest blade (on the H100 0.3 ms less at 2^26).
    // The count is the workgroup's own, so every invocation takes the same branch; only the
    // dispatch with a slot per invocation queues (the instanced grass's, where it splats).
    uint splatted = level_counts[SPLAT_LEVEL];
    if (QUEUE_SLOTS == WORKGROUP && splatted >= QUEUE_FROM) {
        queue_splats(lod == SPLAT_LEVEL, b, cell, patch_, splatted);
    } else if (lod == SPLAT_LEVEL) {
        splat_instanced(b, length(b.root - frame.camera_position.xyz));
    }
}

// Placing: the blade at its list, after the list's blades of the workgroups before this one
// (generated_scan.wesl) and of the invocations before it in this one — a place the grid
// decides, not the order workgroups ran in, so the draw order is the same every run.
void place(int lod, InstancedBlade b, uint base, uint group, uint groups) {
    uint lane = gl_LocalInvocationID.x;
    lane_levels[lane] = lod;
    barrier();
    bool listed = lod >= 0 && (BILLBOARDS ? lod < 1 : (lod < 4 || lod == RASTER_LEVEL));
    if (!listed) {
        return;
    }
    uint rank = 0u;
    for (uint j = 0u; j < lane; j++) {
        rank += uint(lane_levels[j] == lod);
    }
    uint k = lod == RASTER_LEVEL ? 4u : uint(lod);
    uint slot = generated_counts[base + 1u + k * groups + group] + rank;
    if (!BILLBOARDS) {
        // Settled once here, not at each of its strip's vertices.
        b = posed(b, length(b.root - frame.camera_position.xyz));
    }
    if (BILLBOARDS) {
        if (slot < frame.billboard_meta.y) {
            store_blade(frame.billboard_meta.x, slot, b);
        }
    } else if (k == 4u) {
        if (slot < frame.instanced_raster.y) {
            store_blade(frame.instanced_raster.x, slot, b);
        }
    } else if (slot < frame.instanced_caps[k]) {
        store_blade(frame.instanced_lists[k], slot, b);
    }
}

// The grid cell of patch `patch_` that its `local`th invocation makes: the patch walked in rows
// across the line from the eye to it, from the side nearest the eye. Blades are listed, and so
// drawn, in this order, so each patch is drawn front to back and the depth test rejects what
// nearer blades hide before it is shaded: on the H200, the instanced grass's patches drawn in
// the reverse of their rows made its draw at 2^26 candidates 2.45 ms slower (fragments shaded
// 5.3 → 8.4 M), as a fixed order of rows did wherever the eye looked the other way.
ivec2 cell_of(uint local, ivec2 patch_, float spacing) {
    vec2 away = (vec2(patch_) + 0.5) * float(PATCH_CELLS) * spacing - world_xz(frame.camera_position.xz);
    uint across = local % uint(PATCH_CELLS), along = local / uint(PATCH_CELLS);
    uvec2 at = abs(away.y) >= abs(away.x) ? uvec2(across, along) : uvec2(along, across);
    uint last = uint(PATCH_CELLS) - 1u;
    at.x = away.x < 0.0 ? last - at.x : at.x;
    at.y = away.y < 0.0 ? last - at.y : at.y;
    return patch_ * PATCH_CELLS + ivec2(at);
}

// Two passes over the same grid: the first counts each workgroup's blades per level (and
// splats the far ones), generated_scan.wesl sums the counts over the workgroups before each,
// and the second makes the blades again and puts each at its place.
void main() {
    uint local_row = gl_WorkGroupID.y;
    uint row = local_row + (BILLBOARDS ? frame.billboard_meta.z : 0u);
    ivec2 patch_ = instanced_patches[row].xy;
    uint local = gl_LocalInvocationID.x + gl_WorkGroupID.x * gl_WorkGroupSize.x;
    bool inside = local < uint(PATCH_CELLS * PATCH_CELLS);
    Grid g = this_grid();
    ivec2 cell = cell_of(local, patch_, g.spacing);
    InstancedBlade b = blade_at(cell, g);
    int lod = inside ? lod_of(b, g) : -1;
    uint base = generated_counts_base(BILLBOARDS);
    // The counts are laid out by the workgroups of the whole list (patch_cull.wesl writes how
    // many), also where the placing pass runs over its nearer rows only.
    uint groups = generated_counts[base];
    uint group = local_row * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    if (PLACE) {
        place(lod, b, base, group, groups);
    } else {
        count_levels(lod, b, cell, patch_, base, group, groups);
    }
}
