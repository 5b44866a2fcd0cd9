// The instanced field (SPEC §7 [F]), one invocation per grid cell of the frame's patches: make the
// cell's blade from its hash (instanced.rs `blade_at`), cull it (bounding sphere against the
// frustum, distance cut-off, inner radius; `lod_of`), and list it at its level — in two passes
// (see main), so each blade's place in its list is the grid's, the same every run — counting
// into that level's draw command (reset by vkCmdFillBuffer before the first). Blades
// beyond the splat distance are not listed but splatted: walked from root to tip a pixel at a
// time, each pixel shaded and kept if nearest by a 64-bit atomicMin of (depth, colour) into the
// splat buffer, which splat.frag then resolves into the frame. Their count goes to the fifth
// draw command, which is never drawn. Blades from the raster distance (instanced::raster_from) up
// to the splat distance are not listed either but rasterized here by compute, one invocation
// per blade (raster_blade): cut into the triangles of the strip instanced.vert would draw and
// shaded per sample as blade.frag shades, into the same splat buffer; they are counted with the
// splatted ones. The placing pass runs only over the patches that may hold listed blades
// (patch_cull.comp's PLACE_DISPATCH), the nearest of the list.
// Included by instanced.comp (with splats: SWARD_SPLAT_WRITE and the int64 atomics) and by
// instanced_drawn.comp (without them, for devices that lack 64-bit atomics; the renderer sets no
// splat distance there, so no blade is ever at the splat level).
#define SWARD_WRITE
#include "common.glsl"
#include "instanced.glsl"
#include "blade_surface.glsl"
#include "shading.glsl"
#include "tuft.glsl"
#ifdef SWARD_SPLAT_WRITE
#include "splat.glsl"
#define TUFT_COVERAGE_COMPUTE
#include "tuft_coverage.glsl"
#include "tuft_splat.glsl"
#endif

layout(local_size_x_id = 0) in;
// The billboards' dispatch (billboard.rs `as_grid`): the same generation and culling over the
// billboard grid, one list, counted in the sixth draw command; tufts beyond their splat
// distance splatted (tuft_splat.glsl) and counted with the splatted blades.
layout(constant_id = 4) const bool BILLBOARDS = false;
// The second pass: place the blades the first counted (see main).
layout(constant_id = 5) const bool PLACE = false;
layout(constant_id = 0) const uint WORKGROUP = 256u;

// What this dispatch generates: the instanced field's grid or the billboards'.
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
        g.lod = vec4(vec3(3.0e38), frame.billboard_far.y); // one level, far tufts splatted
        g.raster_from = 3.0e38; // tuft_raster.comp rasterizes tufts from the listed ones
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

uint cell_hash(ivec2 cell, uint seed) {
    return hash_u32((uint(cell.x) * 73856093u) ^ hash_u32(uint(cell.y) ^ (seed * 19349663u)));
}

InstancedBlade blade_at(ivec2 cell, Grid g) {
    uint h = cell_hash(cell, g.seed);
    uint h1 = hash_u32(h), h2 = hash_u32(h ^ 0x68e31da4u), h3 = hash_u32(h ^ 0xb5297a4du);
    uint h4 = hash_u32(h ^ 0x1b56c4e9u), h5 = hash_u32(h ^ 0x7f4a7c15u);
    vec2 xz = (vec2(cell) + vec2(hash_unit(h1), hash_unit(h2))) * g.spacing;
    float y;
    bool on_ground = ground_height(xz, y);
    float clump = 0.5 + 0.5 * simplex2(xz * g.clump_scale);
    float tall = clamp(clump + 0.25 * (hash_unit(h3) - 0.5), 0.0, 1.0);
    vec4 shape = g.shape;
    InstancedBlade b;
    b.root = vec3(xz.x, y, xz.y);
    b.facing = hash_unit(h4) * 6.2831855;
    b.height = on_ground ? shape.x + (shape.y - shape.x) * tall : 0.0;
    // Mown (the trample map's cut, growing back): no taller than the cut.
    b.height = min(b.height, trample_cut(xz));
    b.width = shape.z + (shape.w - shape.z) * (0.5 * tall + 0.5 * hash_unit(h5));
    b.pitch = 0.25 * (hash_unit(h3) - 0.5);
    b.bend = g.bend * (0.5 + hash_unit(h5));
    b.phase = hash_unit(h2 ^ h4) * 6.2831855;
    b.hash = h;
    return b;
}

const int SPLAT_LEVEL = 4;
// Rasterized by compute: counted with the splatted blades, never listed.
const int RASTER_LEVEL = 5;
// The most splat cells a rasterized blade spans (instanced.rs RASTER_MAX_CELLS): a bound on one
// invocation's loops, which raster_from keeps blades within.
const float RASTER_MAX_CELLS = 1024.0;
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

// The strip level of detail of a blade at `dist` (instanced::lod_at).
int strip_level(float dist, vec4 lod) {
    return int(dist >= lod.x) + int(dist >= lod.y) + int(dist >= lod.z);
}

// The blade's level of detail (SPLAT_LEVEL when splatted, RASTER_LEVEL when rasterized by
// compute), or -1 when culled.
int lod_of(InstancedBlade b, Grid g) {
    if (b.height <= 0.0) {
        return -1;
    }
    vec3 center = b.root + vec3(0.0, 0.5 * b.height, 0.0);
    float radius = 0.5 * b.height * (1.0 + g.bend + g.sway) + b.width;
    if (frame.trample.x > 0u) {
        // A trampled blade lies along the ground up to its height from its root.
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

// Splat blade `b`: its shape narrows linearly to the tip, the triangle of blade_surface.glsl; or
// on the billboards' grid tuft `b` (tuft_splat.glsl).
void splat_instanced(InstancedBlade b, float dist) {
#ifdef SWARD_SPLAT_WRITE
    if (BILLBOARDS) {
        splat_tuft(Tuft(b.root, b.height, b.width, b.facing, b.hash), dist);
        return;
    }
    Shape sh = instanced_shape(b, dist);
    const uint TRIANGLE = 1u;
    splat_blade(SplatBlade(sh.p0, sh.p1, sh.p2, sh.across, sh.width, TRIANGLE, b.hash), MAX_SPLAT_STEPS, MAX_SPLAT_ACROSS);
#endif
}

// Blade `b` as a list holds it (store_blade: shape and phase as half floats), so a blade
// rasterized by compute takes the very shape the raster hardware would draw from the list.
InstancedBlade as_listed(InstancedBlade b) {
    vec2 size = unpackHalf2x16(packHalf2x16(vec2(b.height, b.width)));
    vec2 facing_pitch = unpackHalf2x16(packHalf2x16(vec2(b.facing, b.pitch)));
    vec2 bend_phase = unpackHalf2x16(packHalf2x16(vec2(b.bend, b.phase)));
    b.height = size.x;
    b.width = size.y;
    b.facing = facing_pitch.x;
    b.pitch = facing_pitch.y;
    b.bend = bend_phase.x;
    b.phase = bend_phase.y;
    return b;
}

#ifdef SWARD_SPLAT_WRITE
// A vertex of a strip rasterized by compute: x, y in splat cells, depth, 1 / w (all zero behind
// the eye), and what blade.frag's shading reads.
struct StripCorner {
    vec4 cell;
    vec3 position;
    vec3 normal;
    vec2 uv;
};

StripCorner strip_corner(Shape s, float dist, uint lod, uint v) {
    StripCorner c;
    c.position = strip_vertex(s, dist, lod, v, c.normal, c.uv);
    vec4 clip = frame.view_proj * vec4(c.position, 1.0);
    c.cell = clip.w > 1e-3 ? vec4(to_cells(clip), clip.z / clip.w, 1.0 / clip.w) : vec4(0.0);
    return c;
}

// Barycentric weights of the triangle (a, b, c) at `p` (cells), relative to its first corner
// (near it, so a thin sliver keeps its precision); negative outside or when degenerate.
vec3 triangle_weights(vec2 a, vec2 b, vec2 c, vec2 p) {
    b -= a;
    c -= a;
    vec2 q = p - a;
    float area = b.x * c.y - b.y * c.x;
    if (abs(area) < 1e-8) {
        return vec3(-1.0);
    }
    float wb = (q.x * c.y - q.y * c.x) / area;
    float wc = (b.x * q.y - b.y * q.x) / area;
    return vec3(1.0 - wb - wc, wb, wc);
}

// The sample of splat cell `at` covered by triangle (a, b, c) with weights `w`: shaded as
// blade.frag shades the strip's fragment there (attributes interpolated with perspective) and
// kept if nearest — unless a nearer blade is there already (a plain read, no shading).
void cover_sample(uint at, StripCorner a, StripCorner b, StripCorner c, vec3 w, uint blade) {
    float depth = dot(w, vec3(a.cell.z, b.cell.z, c.cell.z));
    if (depth < 0.0 || depth > 1.0) {
        return;
    }
    uint depth_bits = floatBitsToUint(depth);
    if (uint(splat_write[at] >> 32) < depth_bits) {
        return;
    }
    vec3 persp = w * vec3(a.cell.w, b.cell.w, c.cell.w);
    persp /= persp.x + persp.y + persp.z;
    vec3 position = mat3(a.position, b.position, c.position) * persp;
    vec3 normal = mat3(a.normal, b.normal, c.normal) * persp;
    vec2 uv = mat3x2(a.uv, b.uv, c.uv) * persp;
    vec3 colour = guard_color(shade_blade(normal, position, uv, blade)).rgb;
    uint packed = packUnorm4x8(vec4(sqrt(clamp(colour, 0.0, 1.0)), 1.0));
    atomicMin(splat_write[at], (uint64_t(depth_bits) << 32) | uint64_t(packed));
}

// One segment of the strip: the triangles (a, b, c) and, unless it ends at the tip, (b, c, d),
// as the triangle strip orders them; every splat cell whose sample may fall in them is tested.
// A segment reaching behind the eye is left out (raster_from keeps rasterized blades far from
// the eye, where none does).
void raster_segment(StripCorner a, StripCorner b, StripCorner c, StripCorner d, bool tip, uint blade) {
    if (a.cell.w == 0.0 || b.cell.w == 0.0 || c.cell.w == 0.0 || d.cell.w == 0.0) {
        return;
    }
    vec2 lo = min(min(a.cell.xy, b.cell.xy), min(c.cell.xy, d.cell.xy));
    vec2 hi = max(max(a.cell.xy, b.cell.xy), max(c.cell.xy, d.cell.xy));
    ivec2 size = splat_cells_size();
    int scale = int(frame.instanced_meta.z);
    // Samples lie a quarter or three quarters into their cell (the middle on a 1× target).
    ivec2 first = max(ivec2(ceil(lo - 0.75)), ivec2(0));
    ivec2 last = min(ivec2(floor(hi - 0.25)), min(size - 1, first + int(RASTER_MAX_CELLS)));
    for (int y = first.y; y <= last.y; y++) {
        for (int x = first.x; x <= last.x; x++) {
            ivec2 cell = ivec2(x, y);
            vec2 p = sample_in(cell, scale);
            uint at = uint(y * size.x + x);
            vec3 w = triangle_weights(a.cell.xy, b.cell.xy, c.cell.xy, p);
            if (min(w.x, min(w.y, w.z)) >= 0.0) {
                cover_sample(at, a, b, c, w, blade);
            } else if (!tip) {
                w = triangle_weights(b.cell.xy, c.cell.xy, d.cell.xy, p);
                if (min(w.x, min(w.y, w.z)) >= 0.0) {
                    cover_sample(at, b, c, d, w, blade);
                }
            }
        }
    }
}

// Rasterize blade `b` as the strip of its level instanced.vert would draw, segment by segment,
// each row of corners made once.
void raster_blade(InstancedBlade b, float dist, uint lod) {
    Shape s = instanced_shape(b, dist);
    uint segments = 8u >> lod;
    StripCorner left = strip_corner(s, dist, lod, 0u);
    StripCorner right = strip_corner(s, dist, lod, 1u);
    for (uint row = 1u; row <= segments; row++) {
        bool tip = row == segments;
        StripCorner next_left = strip_corner(s, dist, lod, 2u * row);
        StripCorner next_right = tip ? next_left : strip_corner(s, dist, lod, 2u * row + 1u);
        raster_segment(left, right, next_left, next_right, tip, b.hash);
        left = next_left;
        right = next_right;
    }
}
#endif

// Rasterize instanced blade `b` by compute (RASTER_LEVEL), as listed and drawn at its level.
void raster_instanced(InstancedBlade b, float dist) {
#ifdef SWARD_SPLAT_WRITE
    raster_blade(as_listed(b), dist, uint(strip_level(dist, frame.instanced_lod)));
#endif
}

// Write blade `b` at `slot` of the list starting at `list`.
void store_blade(uint list, uint slot, InstancedBlade b) {
    uint at = 2u * (list + slot);
    instanced_blades[at] = uvec4(floatBitsToUint(b.root), packHalf2x16(vec2(b.height, b.width)));
    instanced_blades[at + 1u] = uvec4(
        packHalf2x16(vec2(b.facing, b.pitch)), packHalf2x16(vec2(b.bend, b.phase)), b.hash, 0u);
}

// Each workgroup's blades per level, then (placing) each invocation's level.
shared uint level_counts[5];
shared int lane_levels[1024];

// Counting: this workgroup's blades per level into its counts (and the levels' draw commands,
// sums, so in no particular order), and the splatted blades splatted.
void count_levels(int lod, InstancedBlade b, uint base, uint group, uint groups) {
    uint lane = gl_LocalInvocationID.x;
    if (lane < 5u) {
        level_counts[lane] = 0u;
    }
    barrier();
    if (lod >= 0) {
        atomicAdd(level_counts[min(uint(lod), uint(SPLAT_LEVEL))], 1u);
    }
    float dist = length(b.root - frame.camera_position.xyz);
    if (lod == SPLAT_LEVEL) {
        splat_instanced(b, dist);
    } else if (lod == RASTER_LEVEL) {
        raster_instanced(b, dist);
    }
    barrier();
    if (group == 0u && lane == 0u) {
        generated_counts[base] = groups;
    }
    uint levels = BILLBOARDS ? 1u : 4u;
    if (lane < levels) {
        generated_counts[base + 1u + lane * groups + group] = level_counts[lane];
        atomicAdd(instanced_draws[BILLBOARDS ? BILLBOARD_COMMAND : lane].instance_count, level_counts[lane]);
    }
    if (lane == uint(SPLAT_LEVEL)) {
        // The splatted blades and tufts are only counted (the fifth command).
        atomicAdd(instanced_draws[SPLAT_LEVEL].instance_count, level_counts[SPLAT_LEVEL]);
    }
}

// Placing: the blade at its level's list, after the level's blades of the workgroups before
// this one (generated_scan.comp) and of the invocations before it in this one — a place the
// grid decides, not the order workgroups ran in, so the draw order is the same every run.
void place(int lod, InstancedBlade b, uint base, uint group, uint groups) {
    uint lane = gl_LocalInvocationID.x;
    lane_levels[lane] = lod;
    barrier();
    bool listed = lod >= 0 && lod < (BILLBOARDS ? 1 : 4);
    if (!listed) {
        return;
    }
    uint rank = 0u;
    for (uint j = 0u; j < lane; j++) {
        rank += uint(lane_levels[j] == lod);
    }
    uint slot = generated_counts[base + 1u + uint(lod) * groups + group] + rank;
    if (BILLBOARDS) {
        if (slot < frame.billboard_meta.y) {
            store_blade(frame.billboard_meta.x, slot, b);
        }
    } else if (slot < frame.instanced_caps[lod]) {
        store_blade(frame.instanced_lists[lod], slot, b);
    }
}

// Two passes over the same grid: the first counts each workgroup's blades per level (and
// splats the far ones), generated_scan.comp sums the counts over the workgroups before each,
// and the second makes the blades again and puts each at its place.
void main() {
    uint row = gl_WorkGroupID.y + (BILLBOARDS ? frame.billboard_meta.z : 0u);
    ivec2 patch_ = instanced_patches[row].xy;
    uint local = gl_GlobalInvocationID.x;
    bool inside = local < uint(PATCH_CELLS * PATCH_CELLS);
    ivec2 cell = patch_ * PATCH_CELLS + ivec2(local % uint(PATCH_CELLS), local / uint(PATCH_CELLS));
    Grid g = this_grid();
    InstancedBlade b = blade_at(cell, g);
    int lod = inside ? lod_of(b, g) : -1;
    uint base = generated_counts_base(BILLBOARDS, WORKGROUP);
    // The placing pass may run over fewer rows than the counting pass did (PLACE_DISPATCH):
    // the counts are laid out by the counting pass's workgroups.
    uint groups = PLACE ? generated_counts[base] : gl_NumWorkGroups.x * gl_NumWorkGroups.y;
    uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    if (PLACE) {
        place(lod, b, base, group, groups);
    } else {
        count_levels(lod, b, base, group, groups);
    }
}
