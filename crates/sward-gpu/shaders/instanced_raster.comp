#version 460
// The instanced grass's blades from the raster distance up to the splat distance
// (instanced::raster_from; instanced_pass.glsl lists them apart), rasterized by compute into the
// splat target splat.frag resolves, instead of queueing as strips on the few raster units of
// some GPUs. Each blade is cut into the very triangles of the strip instanced.vert would draw
// at its level (instanced.glsl `strip_vertex`, geomorphing included) and each covered sample
// shaded as blade.frag shades the strip's fragment there (attributes interpolated with
// perspective) — so the picture is the drawn one, up to which samples an edge takes. As the
// hardware shades a multisampled fragment, a pixel is shaded once, at its centre, for the
// samples the blade covers in it (per sample the shading costs four times as much, and the
// strips are not shaded so either). One blade per workgroup: its corners and its triangles'
// edge planes made once into shared memory, then a pixel row of its screen box per invocation,
// over the pixels its segments' outlines cross in that row (most of a leaning blade's box is
// empty), each pixel's samples tested against the segments whose box holds them. A sample
// already nearer is left (a plain read; a pixel with none left is not shaded), and the nearest
// is kept by the 64-bit atomicMin, order-independent. Dispatched chunk by chunk of the list,
// nearest first (generated_scan.wesl writes each chunk's size, in rows of 65535),
// splat_tiles.wesl taking the tiles' farthest depths between chunks: from the second chunk on,
// a row wholly behind them is left (the hardware's hierarchical depth test; exact: this frame's
// depths, strict comparison). Measured on the H100 (BENCHMARKS.md): faster than the strips at
// one sample per pixel, slower at four, where a near field hundreds of blades deep is rejected
// better by the hardware's early depth test in draw order than by workgroups side by side —
// hence off unless the scene asks (instanced.raster_distance). A blade per invocation, walking
// its own cells, was slower still: the nearest blades held their subgroups.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#define SWARD_SPLAT_WRITE
#include "common.glsl"
#include "instanced.glsl"
#include "blade_surface.glsl"
#include "shading.glsl"
#include "splat.glsl"

// Which chunk of the list this dispatch rasterizes.
layout(constant_id = CONSTANT_CHUNK) const uint CHUNK = 0u;

const uint LANES = 64u;
layout(local_size_x = 64) in;

// The finest strip: 8 segments, 17 corners, 15 triangles.
const uint MAX_SEGMENTS = 8u;
const uint MAX_CORNERS = 2u * MAX_SEGMENTS + 1u;
const uint MAX_TRIANGLES = 2u * MAX_SEGMENTS - 1u;

// The blade's corners: x, y in splat cells, depth, 1 / w (all zero behind the eye); and what
// shading reads.
shared vec4 corner_cell[MAX_CORNERS];
shared vec3 corner_position[MAX_CORNERS];
shared vec3 corner_normal[MAX_CORNERS];
shared vec2 corner_uv[MAX_CORNERS];
// The cells whose samples each segment may cover (xy first, zw last; empty where the segment
// reaches behind the eye, which raster_from keeps rasterized blades far from).
shared ivec4 segment_box[MAX_SEGMENTS];
// Triangle i of the strip, corners (i, i + 1, i + 2): its barycentric weights as three planes
// over cells relative to the blade box's first cell (near the blade: planes through far-off
// coordinates lose the precision a thin blade needs), so a sample is tested with three dot
// products.
shared vec3 triangle_weight[MAX_TRIANGLES][3];
shared ivec4 blade_box;
// The blade's nearest depth bits (its corners', which hold it on screen and in depth).
shared uint blade_nearest;

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

// Triangle i's weight planes relative to `origin` (zero where degenerate: it covers nothing).
void make_triangle(uint i, vec2 origin) {
    vec3 planes[3];
    bool covers = weight_planes(corner_cell[i].xy - origin, corner_cell[i + 1u].xy - origin, corner_cell[i + 2u].xy - origin, planes);
    for (int k = 0; k < 3; k++) {
        triangle_weight[i][k] = covers ? planes[k] : vec3(0.0, 0.0, -1.0);
    }
}

vec3 weights_of(uint i, vec3 p) {
    return vec3(dot(triangle_weight[i][0], p), dot(triangle_weight[i][1], p), dot(triangle_weight[i][2], p));
}

// The nearest of the strip's triangles covering the sample at `p` (cells relative to the box's
// first cell) among the segments whose box holds `cell`, and its depth (2 where none does: a
// blade bent over may cover a sample twice).
float nearest_at(ivec2 cell, vec2 p, uint segments, out uint nearest) {
    float depth = 2.0;
    nearest = 0u;
    uint triangles = 2u * segments - 1u;
    vec3 q = vec3(p, 1.0);
    for (uint s = 0u; s < segments; s++) {
        ivec4 box = segment_box[s];
        if (any(lessThan(cell, box.xy)) || any(greaterThan(cell, box.zw))) {
            continue;
        }
        for (uint i = 2u * s; i < min(2u * s + 2u, triangles); i++) {
            vec3 w = weights_of(i, q);
            if (min(w.x, min(w.y, w.z)) < 0.0) {
                continue;
            }
            float z = dot(w, vec3(corner_cell[i].z, corner_cell[i + 1u].z, corner_cell[i + 2u].z));
            if (z < depth) {
                depth = z;
                nearest = i;
            }
        }
    }
    return depth;
}

// Blade.frag's colour at `p` (cells relative to the box's first cell) on triangle i, its
// attributes interpolated with perspective (outside the triangle extrapolated, as the hardware
// does for a pixel centre), packed as the splat target holds it.
uint shade_at(uint i, vec2 p, uint blade) {
    vec3 w = weights_of(i, vec3(p, 1.0));
    vec3 persp = w * vec3(corner_cell[i].w, corner_cell[i + 1u].w, corner_cell[i + 2u].w);
    persp /= persp.x + persp.y + persp.z;
    vec3 position = mat3(corner_position[i], corner_position[i + 1u], corner_position[i + 2u]) * persp;
    vec3 normal = mat3(corner_normal[i], corner_normal[i + 1u], corner_normal[i + 2u]) * persp;
    vec2 uv = mat3x2(corner_uv[i], corner_uv[i + 1u], corner_uv[i + 2u]) * persp;
    vec3 colour = guard_color(shade_blade(normal, position, uv, blade)).rgb;
    return splat_colour(colour);
}

// Pixel `pixel`: its samples the blade covers and no nearer blade holds yet, shaded once at the
// pixel's centre (by the triangle of the first sample it covers) and kept where nearest.
void raster_pixel(ivec2 pixel, uint segments, uint blade) {
    int scale = int(frame.instanced_meta.z);
    ivec2 size = splat_cells_size();
    vec2 origin = vec2(blade_box.xy);
    uint depths[4];
    uint mask = 0u, shading = 0u;
    bool covered = false;
    for (int k = 0; k < scale * scale; k++) {
        ivec2 cell = pixel * scale + ivec2(k & 1, k >> 1);
        if (any(greaterThanEqual(cell, size))) {
            continue;
        }
        uint nearest;
        float depth = nearest_at(cell, sample_in(cell, scale) - origin, segments, nearest);
        if (depth < 0.0 || depth > 1.0) {
            continue;
        }
        // The pixel's colour comes from its first covered sample's triangle, whatever other
        // blades hold already (which depends on the order workgroups ran in): the frame's
        // bytes must not.
        if (!covered) {
            shading = nearest;
            covered = true;
        }
        depths[k] = floatBitsToUint(depth);
        if (splat_depth_at(uint(cell.y * size.x + cell.x)) < depths[k]) {
            continue; // a nearer blade is there already
        }
        mask |= 1u << k;
    }
    if (mask == 0u) {
        return;
    }
    uint packed = shade_at(shading, (vec2(pixel) + 0.5) * float(scale) - origin, blade);
    for (int k = 0; k < 4; k++) {
        if ((mask & (1u << k)) != 0u) {
            ivec2 cell = pixel * scale + ivec2(k & 1, k >> 1);
            atomicMin(splat_write[uint(cell.y * size.x + cell.x)], (uint64_t(depths[k]) << 32) | uint64_t(packed));
        }
    }
}

// Whether the cells `first` to `last` lie in splat tiles whose every cell is nearer than the
// blade (from the second chunk on: the tiles hold what the chunks before left).
bool hidden_cells(ivec2 first, ivec2 last) {
    if (CHUNK == 0u) {
        return false;
    }
    ivec2 tiles_last = splat_tiles_size() - 1;
    ivec2 t0 = min(first / SPLAT_TILE, tiles_last), t1 = min(last / SPLAT_TILE, tiles_last);
    for (int y = t0.y; y <= t1.y; y++) {
        for (int x = t0.x; x <= t1.x; x++) {
            if (uint(splat_write[splat_tile_at(ivec2(x, y), false)]) >= blade_nearest) {
                return false;
            }
        }
    }
    return true;
}

// Widen [lo, hi] by the part of the edge p–q within the rows of cells y0–y1.
void span_edge(vec2 p, vec2 q, float y0, float y1, inout float lo, inout float hi) {
    float ya = max(min(p.y, q.y), y0), yb = min(max(p.y, q.y), y1);
    if (ya > yb) {
        return;
    }
    float dy = q.y - p.y;
    float xa = abs(dy) < 1e-6 ? p.x : mix(p.x, q.x, (ya - p.y) / dy);
    float xb = abs(dy) < 1e-6 ? q.x : mix(p.x, q.x, (yb - p.y) / dy);
    lo = min(lo, min(xa, xb));
    hi = max(hi, max(xa, xb));
}

// The pixels of row `y` whose samples the blade may cover: where its segments' outlines (the
// quad of corners 2s, 2s + 1, 2s + 3, 2s + 2; the tip's triangle) cross the row's sample rows.
// Empty (first > last) where none does.
ivec2 row_span(int y, uint segments, int scale) {
    // The row's samples lie a quarter to three quarters into its cells (the middle at 1×).
    float inset = scale == 1 ? 0.5 : 0.25;
    float y0 = float(y * scale) + inset, y1 = float(y * scale + scale) - inset;
    float lo = 1e30, hi = -1e30;
    for (uint s = 0u; s < segments; s++) {
        ivec4 box = segment_box[s];
        if (box.y > y * scale + scale - 1 || box.w < y * scale || box.x > box.z) {
            continue;
        }
        uint a = 2u * s, b = a + 1u, c = a + 2u, d = min(a + 3u, 2u * segments);
        vec2 pa = corner_cell[a].xy, pb = corner_cell[b].xy, pc = corner_cell[c].xy, pd = corner_cell[d].xy;
        span_edge(pa, pb, y0, y1, lo, hi);
        span_edge(pb, pd, y0, y1, lo, hi);
        span_edge(pd, pc, y0, y1, lo, hi);
        span_edge(pc, pa, y0, y1, lo, hi);
    }
    if (lo > hi) {
        return ivec2(1, 0);
    }
    // Cells whose sample may lie in [lo, hi], as pixels.
    return ivec2(int(ceil(lo - 0.75)), int(floor(hi - 0.25))) / scale;
}

void main() {
    uint lane = gl_LocalInvocationID.x;
    DrawCommand chunk = instanced_draws[RASTER_CHUNK_DISPATCH + CHUNK];
    uint listed = min(instanced_draws[RASTER_COMMAND].instance_count, frame.instanced_raster.y);
    uint end = CHUNK + 1u < RASTER_CHUNKS ? instanced_draws[RASTER_CHUNK_DISPATCH + CHUNK + 1u].first_instance : listed;
    uint index = chunk.first_instance + gl_WorkGroupID.y * 65535u + gl_WorkGroupID.x;
    if (index >= end) {
        return; // the whole workgroup
    }
    uint at = 2u * (frame.instanced_raster.x + index);
    InstancedBlade b = unpack_blade(instanced_blades[at], instanced_blades[at + 1u]);
    float dist = length(b.root - frame.camera_position.xyz);
    uint lod = uint(strip_level(dist, frame.instanced_lod));
    uint segments = 8u >> lod;
    if (lane <= 2u * segments) {
        Shape s = listed_shape(b, dist);
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
    if (lane == 0u) {
        ivec4 box = ivec4(1 << 30, 1 << 30, -1, -1);
        for (uint s = 0u; s < segments; s++) {
            ivec4 sb = segment_box[s];
            if (all(lessThanEqual(sb.xy, sb.zw))) {
                box = ivec4(min(box.xy, sb.xy), max(box.zw, sb.zw));
            }
        }
        blade_box = box;
        float nearest = 1.0;
        for (uint k = 0u; k <= 2u * segments; k++) {
            nearest = min(nearest, corner_cell[k].w > 0.0 ? corner_cell[k].z : 0.0);
        }
        blade_nearest = floatBitsToUint(max(nearest, 0.0));
    }
    barrier();
    ivec4 box = blade_box;
    if (lane < 2u * segments - 1u) {
        make_triangle(lane, vec2(box.xy));
    }
    barrier();
    // A pixel row of the box per invocation, over the pixels the blade's edges span in it.
    int scale = int(frame.instanced_meta.z);
    ivec2 first = box.xy / scale, last = box.zw / scale;
    for (int y = first.y + int(lane); y <= last.y; y += int(LANES)) {
        ivec2 span = row_span(y, segments, scale);
        int from = max(span.x, first.x), to = min(span.y, last.x);
        if (from > to || hidden_cells(ivec2(from, y) * scale, ivec2(to + 1, y + 1) * scale - 1)) {
            continue;
        }
        for (int x = from; x <= to; x++) {
            raster_pixel(ivec2(x, y), segments, b.hash);
        }
    }
}
