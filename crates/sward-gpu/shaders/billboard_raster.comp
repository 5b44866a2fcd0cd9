#version 460
// Billboards rasterized by compute (billboard.raster_distance on, up to their splat
// distance): the billboards the billboards' list holds at that distance or beyond are not drawn by
// the raster hardware (billboard.vert leaves them) but cut here into the two triangles per quad
// billboard.vert draws and rasterized per sample into the splat target that splat.frag
// resolves. Each sample tests the painted texture's coverage against an ordered threshold by
// its place, as alpha-to-coverage picks samples by alpha (billboard_splat.glsl), so a sample is kept
// or not whole: on this GPU the raster hardware writes depth by alpha-to-coverage at half the
// speed it writes it for whole pixels, and billboards seen through a field are tens deep. One quad
// per workgroup of 256, an 8 × 32-cell tile of its screen box at a time, an invocation per cell;
// a sample already nearer skips its shading (a plain read), and the nearest is kept by the
// 64-bit atomicMin, order-independent. Shading as the far billboards' splats: at root, middle and
// tip, interpolated, then the painted blades' light and dark. Dispatched indirectly with the
// size generated_scan.wesl wrote (three quads per listed billboard, in rows of 65535). The billboards with
// a quad it does not make (nearer than the raster distance, or reaching behind the eye) it
// lists for the raster hardware (HARDWARE_BILLBOARD_COMMAND), which then draws those alone instead
// of running its vertices for every billboard.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#define SWARD_WRITE
#define SWARD_SPLAT_WRITE
#include "common.glsl"
#include "blade_surface.glsl"
#include "shading.glsl"
#include "splat.glsl"
#include "billboard.glsl"
#define BILLBOARD_COVERAGE_COMPUTE
#include "billboard_coverage.glsl"
#include "billboard_splat.glsl"

// Invocations per quad, and the tile of cells they take at a time (TILE_COLUMNS across, the
// rest down). Measured on the H100 at 2^22 billboards: 32 invocations 12.4 ms a frame, 64 8.5, 128
// 6.6, 256 5.9 (16 × 16 cells 5.95): most quads are small, and a workgroup that covers one in
// a pass or two costs less than many that loop over it.
const uint LANES = 256u;
const int TILE_COLUMNS = 8;
const int TILE_ROWS = int(LANES) / TILE_COLUMNS;
layout(local_size_x = 256) in;

// The quad's corners (bottom left, bottom right, top left, top right): x, y in cells, depth,
// 1 / w; their texture coordinates follow from the corner.
shared vec4 corner_cell[4];
shared vec3 shade_at[3]; // root, middle, tip
// A corner reaches behind the eye: the raster hardware draws the quad.
shared bool behind_eye;

// The texture coordinates of corner k (row 0 of the texture holds the tips).
vec2 corner_uv(uint k) {
    return vec2(float(k & 1u), 1.0 - float(k >> 1u));
}

// Barycentric weights of the triangle of corners (a, b, c) at `p` (cells), as planes through
// the triangle's own first corner (near it, so a thin sliver keeps its precision); all zero
// when it is degenerate.
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

// The sample of `cell`: covered by either triangle of the quad, shaded and kept if nearest.
void raster_cell(ivec2 cell, int scale, float level, float layers) {
    vec2 p = sample_in(cell, scale);
    const uvec3 TRIANGLES[2] = uvec3[2](uvec3(0u, 1u, 2u), uvec3(2u, 1u, 3u));
    for (uint i = 0u; i < 2u; i++) {
        uvec3 k = TRIANGLES[i];
        vec3 w = weights_at(k, p);
        if (min(w.x, min(w.y, w.z)) < 0.0) {
            continue;
        }
        float depth = dot(w, vec3(corner_cell[k.x].z, corner_cell[k.y].z, corner_cell[k.z].z));
        if (depth < 0.0 || depth > 1.0) {
            return;
        }
        ivec2 size = splat_cells_size();
        uint at = uint(cell.y * size.x + cell.x);
        uint depth_bits = floatBitsToUint(depth);
        if (splat_depth_at(at) < depth_bits) {
            return; // a nearer billboard or blade is there already
        }
        vec3 persp = w * vec3(corner_cell[k.x].w, corner_cell[k.y].w, corner_cell[k.z].w);
        persp /= persp.x + persp.y + persp.z;
        vec2 uv = mat3x2(corner_uv(k.x), corner_uv(k.y), corner_uv(k.z)) * persp;
        vec4 painted = textureLod(grass_texture, uv, level);
        if (billboard_coverage_at(painted.a, level, layers) <= cell_threshold(cell)) {
            return;
        }
        float y = 1.0 - uv.y;
        vec3 colour = shade_at[0] * ((2.0 * y - 1.0) * (y - 1.0)) + shade_at[1] * (4.0 * y * (1.0 - y)) + shade_at[2] * (y * (2.0 * y - 1.0));
        vec3 lit = guard_color(colour * painted_detail(painted)).rgb;
        uint packed = splat_colour(lit);
        atomicMin(splat_write[at], (uint64_t(depth_bits) << 32) | uint64_t(packed));
        return;
    }
}

// Quad `quad` of billboard `t` is not rasterized here: list the billboard for the raster hardware, once —
// by the first of its quads that is not (the rare quads that reach behind the eye are asked
// about again; nearer than the raster distance every quad is left, the first lists it).
void list_for_hardware(Billboard t, float dist, uint quad, uint index) {
    for (uint k = 0u; k < quad; k++) {
        if (!billboard_quad_rasterized(t, billboard_quad(t, k, dist, false), dist)) {
            return;
        }
    }
    uint slot = atomicAdd(instanced_draws[HARDWARE_BILLBOARD_COMMAND].instance_count, 1u);
    instanced_blades[hardware_billboards_at() + slot / 4u][slot % 4u] = index;
}

void main() {
    uint lane = gl_LocalInvocationID.x;
    uint index = gl_WorkGroupID.y * 65535u + gl_WorkGroupID.x;
    uint listed = min(instanced_draws[BILLBOARD_COMMAND].instance_count, frame.billboard_meta.y);
    uint billboard_index = index / 3u, quad = index % 3u;
    if (billboard_index >= listed) {
        return;
    }
    uint at = 2u * (frame.billboard_meta.x + billboard_index);
    Billboard t = unpack_billboard(instanced_blades[at], instanced_blades[at + 1u]);
    float dist = length(t.root - frame.camera_position.xyz);
    bool single = one_quad(dist);
    if (single && quad > 0u) {
        return;
    }
    BillboardQuad q = billboard_quad(t, quad, dist, single);
    if (lane == 0u) {
        behind_eye = false;
    }
    barrier();
    // The corners once, and from them billboard_quad_rasterized's answer (billboard.vert asks it).
    if (lane < 4u) {
        vec4 clip = billboard_corner_clip(t, q, lane);
        corner_cell[lane] = vec4(to_cells(clip), clip.z / clip.w, 1.0 / clip.w);
        if (behind_eye_at(clip)) {
            behind_eye = true;
        }
    } else if (lane < 7u) {
        shade_at[lane - 4u] = billboard_shade(t, q, 0.5 * float(lane - 4u));
    }
    barrier();
    if (behind_eye || !within_raster_reach(dist)) {
        if (lane == 0u) {
            list_for_hardware(t, dist, quad, billboard_index); // billboard.vert draws it
        }
        return;
    }
    vec2 lo = min(min(corner_cell[0].xy, corner_cell[1].xy), min(corner_cell[2].xy, corner_cell[3].xy));
    vec2 hi = max(max(corner_cell[0].xy, corner_cell[1].xy), max(corner_cell[2].xy, corner_cell[3].xy));
    ivec2 size = splat_cells_size();
    ivec2 box_lo = max(ivec2(floor(lo)), ivec2(0));
    ivec2 box_hi = min(ivec2(ceil(hi)), size - 1);
    if (any(greaterThan(box_lo, box_hi))) {
        return; // the same for every invocation
    }
    int scale = int(frame.instanced_meta.z);
    // The mip level the hardware would pick: texels per pixel along the quad's shorter side.
    float tall = max(distance(corner_cell[0].xy, corner_cell[2].xy), distance(corner_cell[1].xy, corner_cell[3].xy));
    float wide = max(distance(corner_cell[0].xy, corner_cell[1].xy), distance(corner_cell[2].xy, corner_cell[3].xy));
    float texels = float(textureSize(grass_texture, 0).x);
    float level = log2(max(texels * float(scale) / max(min(tall, wide), 1e-3), 1.0));
    ivec2 cell_in_tile = ivec2(int(lane) % TILE_COLUMNS, int(lane) / TILE_COLUMNS);
    for (int ty = box_lo.y / TILE_ROWS; ty <= box_hi.y / TILE_ROWS; ty++) {
        for (int tx = box_lo.x / TILE_COLUMNS; tx <= box_hi.x / TILE_COLUMNS; tx++) {
            ivec2 cell = ivec2(tx * TILE_COLUMNS, ty * TILE_ROWS) + cell_in_tile;
            if (all(greaterThanEqual(cell, box_lo)) && all(lessThanEqual(cell, box_hi))) {
                raster_cell(cell, scale, level, q.layers);
            }
        }
    }
}
