#version 460
// The compute route's rasterizer (SPEC §10): the Bezier blades of the distance buckets from
// routes.y up to routes.x (the near and middle field; splat_blades.comp splats the rest) cut into
// the same triangles the strip route draws and rasterized by compute into the splat target, so
// big blades stop queueing on the few units that run fragment work. One blade per workgroup of
// 32 invocations: its corners are evaluated once into shared memory (blade_surface.glsl, as the
// strips do), then segment by segment and 8 × 8-cell tile by tile of the segment's screen box
// the invocations take one splat cell each (neighbours read neighbouring memory), testing the
// cell's sample against the segment's triangles. Per covered sample: the nearest-so-far read
// first, and only a sample that may win is shaded (shading.glsl, per sample) and kept by a
// 64-bit atomicMin of (depth, colour) — order-independent, so the picture does not depend on
// which blade ran first. Occlusion is tested per tile against the farthest depth in it
// (splat_tiles.comp), as the hardware's hierarchical depth test does — which is what makes a
// field hundreds of blades deep affordable — in two passes: the first draws the tiles where the
// last frame's depths show the segment (nearly all that will be seen, when the camera moved
// little) and leaves the blade's other tiles to the second, which tests them against this
// frame's depths as the first pass left them (so a wrong guess from the last frame costs time,
// never a blade). On a 4× target the cells are the standard sample positions, so the resolve
// (splat.frag) antialiases edges as 4× MSAA does. Dispatched indirectly with the size
// order.wesl `order_buckets` wrote, in rows of 65535 workgroups.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#define SWARD_WRITE
#define SWARD_SPLAT_WRITE
#include "common.glsl"
#include "blade_surface.glsl"
#include "shading.glsl"
#include "splat.glsl"

const uint LANES = 32u;
layout(local_size_x = 32) in;
// Which of the two passes this is.
layout(constant_id = CONSTANT_SECOND_PASS) const bool SECOND_PASS = false;

// Segments a blade is cut into here at most (the strip route's count, capped), and its columns:
// three when the ridge folds it at u = 0.5, else two.
const uint MAX_SEGMENTS = 16u;
const uint MAX_CORNERS = (MAX_SEGMENTS + 1u) * 3u;
// Triangles of one segment at most: two per column gap.
const uint MAX_TRIANGLES = 4u;

// The blade's corners: in splat cells with depth (z / w) and 1 / w, and what shading needs.
shared vec4 corner_cell[MAX_CORNERS]; // x, y in cells, z depth, w 1 / w (0: behind the eye)
shared vec3 corner_position[MAX_CORNERS];
shared vec3 corner_normal[MAX_CORNERS];
shared vec2 corner_uv[MAX_CORNERS];
// The tiles of a batch of 32 the workgroup draws (a bit each), and whether the first pass left
// any tile of the blade to the second.
shared uint tiles_drawn;
shared uint blade_left;

// One triangle as three plane equations over cell space: its barycentric weights (each ≥ 0
// inside), so a sample is tested and interpolated with three dot products.
struct Triangle {
    vec3 weight[3];
    uvec3 corner;
};

// The triangle's weights as planes over cells relative to `origin` (near the triangle: planes
// through far-off coordinates lose the precision a thin blade needs); false when degenerate.
bool make_triangle(uvec3 c, vec2 origin, out Triangle t) {
    t.corner = c;
    return weight_planes(corner_cell[c.x].xy - origin, corner_cell[c.y].xy - origin, corner_cell[c.z].xy - origin, t.weight);
}

// Shade the blade at the sample of `cell` on triangle `t` (weights `w`) and keep it if nearest.
void cover(ivec2 cell, int row, Triangle t, vec3 w, float depth, uint blade) {
    uint at = uint(cell.y * row + cell.x);
    uint depth_bits = floatBitsToUint(depth);
    if (splat_depth_at(at) < depth_bits) {
        return; // a nearer blade is already there: no shading (an equal one may lose by colour)
    }
    uvec3 c = t.corner;
    vec3 persp = w * vec3(corner_cell[c.x].w, corner_cell[c.y].w, corner_cell[c.z].w);
    persp /= persp.x + persp.y + persp.z;
    vec3 position = mat3(corner_position[c.x], corner_position[c.y], corner_position[c.z]) * persp;
    vec3 normal = mat3(corner_normal[c.x], corner_normal[c.y], corner_normal[c.z]) * persp;
    vec2 uv = mat3x2(corner_uv[c.x], corner_uv[c.y], corner_uv[c.z]) * persp;
    vec3 colour = shade_blade(normal, position, uv, blade_colour_key(blade));
    uint packed = splat_colour(colour);
    atomicMin(splat_write[at], (uint64_t(depth_bits) << 32) | uint64_t(packed));
}

// The blade's corners into shared memory: (segments + 1) rows of `columns`, as blade_strip.vert
// places its vertices.
void make_corners(uint lane, Blade b, uint outline, uint segments, uint columns) {
    for (uint i = lane; i < (segments + 1u) * columns; i += LANES) {
        uint row = i / columns;
        float u = float(i % columns) / float(columns - 1u);
        float v = float(row) / float(segments);
        vec3 n;
        vec3 p = blade_point(b, outline, u, v, n);
        vec4 clip = frame.view_proj * vec4(p, 1.0);
        // A corner behind the eye (w ≤ 0) leaves its segment out, as splat_blade leaves such
        // blades: marked by 1 / w = 0.
        corner_cell[i] = clip.w > 1e-3 ? vec4(to_cells(clip), clip.z / clip.w, 1.0 / clip.w) : vec4(0.0);
        corner_position[i] = p;
        corner_normal[i] = n;
        corner_uv[i] = vec2(u, v);
    }
}

// The splat tile's farthest depth bits: this frame's (after the first pass) or the last frame's.
uint tile_farthest(ivec2 tile, bool previous) {
    return uint(splat_write[splat_tile_at(tile, previous)]);
}

// The sample of `cell` against the segment's triangles (planes relative to `origin`): the
// nearest one there (the folded halves may overlap) covers it.
void raster_cell(ivec2 cell, int row, int scale, vec2 origin, Triangle triangles[MAX_TRIANGLES], uint count, uint blade) {
    vec3 p = vec3(sample_in(cell, scale) - origin, 1.0);
    float depth = 2.0;
    vec3 weights = vec3(0.0);
    uint which = 0u;
    for (uint i = 0u; i < count; i++) {
        vec3 w = vec3(dot(triangles[i].weight[0], p), dot(triangles[i].weight[1], p), dot(triangles[i].weight[2], p));
        if (min(w.x, min(w.y, w.z)) >= 0.0) {
            uvec3 c = triangles[i].corner;
            float z = dot(w, vec3(corner_cell[c.x].z, corner_cell[c.y].z, corner_cell[c.z].z));
            if (z < depth) {
                depth = z;
                weights = w;
                which = i;
            }
        }
    }
    if (depth >= 0.0 && depth <= 1.0) {
        cover(cell, row, triangles[which], weights, depth, blade);
    }
}

// Segment `s` of the blade (between corner rows s and s + 1), tile by tile of its screen box:
// the first pass draws the tiles where the last frame's farthest depth may show
// the segment and leaves the rest; the second draws those of the rest where this frame's tiles
// (as the first pass left them) show it. Within a tile the invocations take one cell each
// (neighbours read neighbouring memory), testing the cell's sample against the segment's
// triangles. Every invocation of the workgroup takes the same tiles (their depths are one
// value). Marks the blade when the first pass leaves a tile of it to the second.
void raster_segment(uint lane, uint s, uint columns, uint blade) {
    int scale = int(frame.instanced_meta.z);
    ivec2 size = splat_cells_size();
    uint first_corner = s * columns, corners = 2u * columns;
    vec2 lo = vec2(1e30), hi = vec2(-1e30);
    float nearest = 1.0;
    bool behind = false;
    for (uint i = first_corner; i < first_corner + corners; i++) {
        vec4 c = corner_cell[i];
        behind = behind || c.w == 0.0;
        lo = min(lo, c.xy);
        hi = max(hi, c.xy);
        nearest = min(nearest, c.z);
    }
    ivec2 box_lo = max(ivec2(floor(lo)), ivec2(0));
    ivec2 box_hi = min(ivec2(ceil(hi)), size - 1);
    if (behind || any(greaterThan(box_lo, box_hi))) {
        return; // the same for every invocation: no barrier is skipped by some only
    }
    uint nearest_bits = floatBitsToUint(max(nearest, 0.0));
    // The segment's triangles: each column gap a quad split along its diagonal.
    vec2 origin = vec2(box_lo);
    Triangle triangles[MAX_TRIANGLES];
    uint count = 0u;
    for (uint g = 0u; g + 1u < columns; g++) {
        uint a = first_corner + g, b = a + 1u, c = a + columns, d = c + 1u;
        if (make_triangle(uvec3(a, b, c), origin, triangles[count])) count++;
        if (make_triangle(uvec3(b, d, c), origin, triangles[count])) count++;
    }
    // The box's tiles 32 at a time: each invocation decides one (a read of its depths), the
    // workgroup gathers the decisions, then shares the drawn tiles' cells.
    ivec2 first_tile = box_lo / SPLAT_TILE, last_tile = box_hi / SPLAT_TILE;
    int across = last_tile.x - first_tile.x + 1;
    int tiles = across * (last_tile.y - first_tile.y + 1);
    for (int base = 0; base < tiles; base += int(LANES)) {
        if (lane == 0u) {
            tiles_drawn = 0u;
        }
        barrier();
        int k = base + int(lane);
        if (k < tiles) {
            ivec2 tile = first_tile + ivec2(k % across, k / across);
            // Ties count as shown: an equal depth may still win by colour, and the picture must
            // not depend on which pass drew what.
            bool shown_before = nearest_bits <= tile_farthest(tile, true);
            bool shown_now = !shown_before && nearest_bits <= tile_farthest(tile, false);
            if (SECOND_PASS ? shown_now : shown_before) {
                atomicOr(tiles_drawn, 1u << lane);
            }
            if (!shown_before) {
                blade_left = 1u;
            }
        }
        barrier();
        uint drawn = tiles_drawn;
        barrier();
        while (drawn != 0u) {
            int bit = findLSB(drawn);
            drawn &= drawn - 1u;
            ivec2 tile = first_tile + ivec2((base + bit) % across, (base + bit) / across);
            for (uint c = lane; c < uint(SPLAT_TILE * SPLAT_TILE); c += LANES) {
                ivec2 cell = tile * SPLAT_TILE + ivec2(c % uint(SPLAT_TILE), c / uint(SPLAT_TILE));
                if (all(greaterThanEqual(cell, box_lo)) && all(lessThanEqual(cell, box_hi))) {
                    raster_cell(cell, size.x, scale, origin, triangles, count, blade);
                }
            }
        }
    }
}

void main() {
    // The first pass takes the ordered list's range, the second the blades the first left.
    uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    uint i;
    if (SECOND_PASS) {
        if (group >= draws[COMMAND_RASTER_LEFT].vertex_count) {
            return; // the whole workgroup
        }
        i = visible[group];
    } else {
        i = draws[COMMAND_RASTER_DISPATCH].first_instance + group;
        if (i >= draws[COMMAND_SPLAT_DISPATCH].first_instance) {
            return;
        }
    }
    uint lane = gl_LocalInvocationID.x;
    uint id = ordered[i];
    Blade b = blades[id];
    uint bucket = distance_bucket(distance(b.v0.xyz, frame.camera_position.xyz));
    uint segments = min(strip_segments(bucket), MAX_SEGMENTS);
    uint columns = blade_ridge() ? 3u : 2u;
    if (lane == 0u) {
        blade_left = 0u;
    }
    make_corners(lane, b, blade_outline_at(blade_colour_key(id), world_xz(b.v0.xz)), segments, columns);
    barrier();
    for (uint s = 0u; s < segments; s++) {
        raster_segment(lane, s, columns, id);
    }
    barrier();
    // The visible list is free once ordered: it holds the second pass's blades.
    if (!SECOND_PASS && blade_left != 0u && lane == 0u) {
        visible[atomicAdd(draws[COMMAND_RASTER_LEFT].vertex_count, 1u)] = i;
    }
}
