#version 460
// The instanced field's blades from the raster distance up to the splat distance
// (instanced::raster_from; instanced_pass.glsl lists them apart), rasterized by compute into the
// splat target splat.frag resolves, instead of queueing as strips on the few raster units of
// some GPUs. Each blade is cut into the very triangles of the strip instanced.vert would draw
// at its level (instanced.glsl `strip_vertex`, geomorphing included) and each covered sample
// shaded as blade.frag shades the strip's fragment there (attributes interpolated with
// perspective) — so the picture is the drawn one, up to which samples an edge takes. One blade
// per workgroup: its corners made once into shared memory, then its screen box an 8 × 32-cell
// tile at a time, an invocation per splat cell, each testing its sample against the segments
// whose box holds it. A sample already nearer skips its shading (a plain read), and the nearest
// is kept by the 64-bit atomicMin, order-independent. A blade per invocation, walking its own
// cells, measured 28 ms a frame for 2^26 candidates on the H100 where the strips took 9: the
// nearest blades are hundreds of cells and held their subgroups while the rest waited.
// Dispatched indirectly with the size generated_scan.comp wrote, in rows of 65535.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#define SWARD_SPLAT_WRITE
#include "common.glsl"
#include "instanced.glsl"
#include "blade_surface.glsl"
#include "shading.glsl"
#include "splat.glsl"

const uint LANES = 256u;
const int TILE_COLUMNS = 8;
const int TILE_ROWS = int(LANES) / TILE_COLUMNS;
layout(local_size_x = 256) in;

// The finest strip: 8 segments, 17 corners.
const uint MAX_SEGMENTS = 8u;
const uint MAX_CORNERS = 2u * MAX_SEGMENTS + 1u;

// The blade's corners: x, y in splat cells, depth, 1 / w (all zero behind the eye); and what
// shading reads.
shared vec4 corner_cell[MAX_CORNERS];
shared vec3 corner_position[MAX_CORNERS];
shared vec3 corner_normal[MAX_CORNERS];
shared vec2 corner_uv[MAX_CORNERS];
// The cells whose samples each segment may cover (xy first, zw last; empty where the segment
// reaches behind the eye, which raster_from keeps rasterized blades far from).
shared ivec4 segment_box[MAX_SEGMENTS];

// Barycentric weights of the triangle of corners `k` at `p` (cells), relative to its first
// corner (near it, so a thin sliver keeps its precision); negative outside or when degenerate.
vec3 weights_at(uvec3 k, vec2 p) {
    vec2 a = corner_cell[k.x].xy, b = corner_cell[k.y].xy - a, c = corner_cell[k.z].xy - a;
    vec2 q = p - a;
    float area = b.x * c.y - b.y * c.x;
    if (abs(area) < 1e-8) {
        return vec3(-1.0);
    }
    float wb = (q.x * c.y - q.y * c.x) / area;
    float wc = (b.x * q.y - b.y * q.x) / area;
    return vec3(1.0 - wb - wc, wb, wc);
}

// The cells segment `s` of `segments` may cover: its corners' box, shrunk to the cells whose
// sample (a quarter or three quarters in; the middle on a 1× target) can lie inside.
ivec4 box_of_segment(uint s, uint segments) {
    uint first = 2u * s, last = min(2u * s + 3u, 2u * segments);
    vec2 lo = vec2(1e30), hi = vec2(-1e30);
    for (uint k = first; k <= last; k++) {
        if (corner_cell[k].w == 0.0) {
            return ivec4(1, 1, 0, 0);
        }
        lo = min(lo, corner_cell[k].xy);
        hi = max(hi, corner_cell[k].xy);
    }
    ivec2 size = splat_cells_size();
    return ivec4(max(ivec2(ceil(lo - 0.75)), ivec2(0)), min(ivec2(floor(hi - 0.25)), size - 1));
}

// Shade the sample of splat cell `at` on the triangle of corners `k` (weights `w`, depth
// `depth`) as blade.frag shades the fragment there, and keep it if nearest.
void cover(uint at, uvec3 k, vec3 w, float depth, uint blade) {
    uint depth_bits = floatBitsToUint(depth);
    if (uint(splat_write[at] >> 32) < depth_bits) {
        return; // a nearer blade is there already: no shading
    }
    vec3 persp = w * vec3(corner_cell[k.x].w, corner_cell[k.y].w, corner_cell[k.z].w);
    persp /= persp.x + persp.y + persp.z;
    vec3 position = mat3(corner_position[k.x], corner_position[k.y], corner_position[k.z]) * persp;
    vec3 normal = mat3(corner_normal[k.x], corner_normal[k.y], corner_normal[k.z]) * persp;
    vec2 uv = mat3x2(corner_uv[k.x], corner_uv[k.y], corner_uv[k.z]) * persp;
    vec3 colour = guard_color(shade_blade(normal, position, uv, blade)).rgb;
    uint packed = packUnorm4x8(vec4(sqrt(clamp(colour, 0.0, 1.0)), 1.0));
    atomicMin(splat_write[at], (uint64_t(depth_bits) << 32) | uint64_t(packed));
}

// The sample of `cell` against the triangles of the segments whose box holds it (the strip's
// triangles, in its order: (2s, 2s + 1, 2s + 2) and (2s + 1, 2s + 2, 2s + 3)); the nearest
// covering one (a blade bent over may cover a sample twice) shades it.
void raster_cell(ivec2 cell, uint segments, uint blade) {
    int scale = int(frame.instanced_meta.z);
    vec2 p = sample_in(cell, scale);
    float depth = 2.0;
    vec3 weights = vec3(0.0);
    uvec3 nearest = uvec3(0u);
    uint triangles = 2u * segments - 1u;
    for (uint s = 0u; s < segments; s++) {
        ivec4 box = segment_box[s];
        if (any(lessThan(cell, box.xy)) || any(greaterThan(cell, box.zw))) {
            continue;
        }
        for (uint i = 2u * s; i < min(2u * s + 2u, triangles); i++) {
            uvec3 k = uvec3(i, i + 1u, i + 2u);
            vec3 w = weights_at(k, p);
            if (min(w.x, min(w.y, w.z)) < 0.0) {
                continue;
            }
            float z = dot(w, vec3(corner_cell[k.x].z, corner_cell[k.y].z, corner_cell[k.z].z));
            if (z < depth) {
                depth = z;
                weights = w;
                nearest = k;
            }
        }
    }
    if (depth >= 0.0 && depth <= 1.0) {
        ivec2 size = splat_cells_size();
        cover(uint(cell.y * size.x + cell.x), nearest, weights, depth, blade);
    }
}

void main() {
    uint lane = gl_LocalInvocationID.x;
    uint index = gl_WorkGroupID.y * 65535u + gl_WorkGroupID.x;
    uint listed = min(instanced_draws[RASTER_COMMAND].instance_count, frame.instanced_raster.y);
    if (index >= listed) {
        return; // the whole workgroup
    }
    uint at = 2u * (frame.instanced_raster.x + index);
    InstancedBlade b = unpack_blade(instanced_blades[at], instanced_blades[at + 1u]);
    float dist = length(b.root - frame.camera_position.xyz);
    uint lod = uint(strip_level(dist, frame.instanced_lod));
    uint segments = 8u >> lod;
    if (lane <= 2u * segments) {
        Shape s = instanced_shape(b, dist);
        vec3 normal;
        vec2 uv;
        vec3 p = strip_vertex(s, dist, lod, lane, normal, uv);
        vec4 clip = frame.view_proj * vec4(p, 1.0);
        corner_cell[lane] = clip.w > 1e-3 ? vec4(to_cells(clip), clip.z / clip.w, 1.0 / clip.w) : vec4(0.0);
        corner_position[lane] = p;
        corner_normal[lane] = normal;
        corner_uv[lane] = uv;
    }
    barrier();
    if (lane < segments) {
        segment_box[lane] = box_of_segment(lane, segments);
    }
    barrier();
    ivec4 box = ivec4(1 << 30, 1 << 30, -1, -1);
    for (uint s = 0u; s < segments; s++) {
        ivec4 sb = segment_box[s];
        if (all(lessThanEqual(sb.xy, sb.zw))) {
            box = ivec4(min(box.xy, sb.xy), max(box.zw, sb.zw));
        }
    }
    ivec2 cell_in_tile = ivec2(int(lane) % TILE_COLUMNS, int(lane) / TILE_COLUMNS);
    for (int y = box.y; y <= box.w; y += TILE_ROWS) {
        for (int x = box.x; x <= box.z; x += TILE_COLUMNS) {
            ivec2 cell = ivec2(x, y) + cell_in_tile;
            if (cell.x <= box.z && cell.y <= box.w) {
                raster_cell(cell, segments, b.hash);
            }
        }
    }
}
