#version 460
// After each pass of the compute rasterizer (raster_blades.comp): the farthest depth in each
// tile of 8 × 8 splat cells, kept after the cells in the splat buffer — after the first pass as
// this frame's tiles, which the second pass tests against; after the second as the last frame's,
// which the next frame's first pass tests against; and between the chunks of the instanced
// blades' rasterizer (GENERATED), as this frame's tiles. An empty cell is farthest of all: a tile with
// a hole hides nothing. After the first pass it also writes the second's dispatch size. Eight invocations per tile, one cell row each; eight tiles side by
// side per workgroup.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#define SWARD_WRITE
#define SWARD_SPLAT_WRITE
#include "common.glsl"
#include "blade_surface.glsl"
#include "shading.glsl"
#include "splat.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
// Which pass was just run: the first (this frame's tiles) or the second (the last frame's, for
// the next frame).
layout(constant_id = CONSTANT_SECOND_PASS) const bool SECOND_PASS = false;
// Between the chunks of the instanced blades' compute rasterizer (instanced_raster.comp): this
// frame's tiles, and no dispatch of raster_blades.comp to write.
layout(constant_id = CONSTANT_GENERATED) const bool GENERATED = false;

shared uint farthest[8];

void main() {
    uint slot = gl_LocalInvocationID.x;
    if (gl_LocalInvocationID.y == 0u) {
        farthest[slot] = 0u;
    }
    barrier();
    ivec2 size = splat_cells_size();
    ivec2 tile = ivec2(gl_WorkGroupID.x * 8u + slot, gl_WorkGroupID.y);
    int y = tile.y * SPLAT_TILE + int(gl_LocalInvocationID.y);
    // Cells past the screen's edge hold nothing that could be seen: they hide everything.
    if (y < size.y) {
        uint row_farthest = 0u;
        for (int x = tile.x * SPLAT_TILE; x < min(tile.x * SPLAT_TILE + SPLAT_TILE, size.x); x++) {
            row_farthest = max(row_farthest, splat_depth_at(y * size.x + x));
        }
        atomicMax(farthest[slot], row_farthest);
    }
    barrier();
    if (gl_LocalInvocationID.y == 0u && tile.x < splat_tiles_size().x) {
        splat_write[splat_tile_at(tile, SECOND_PASS)] = uint64_t(farthest[slot]);
    }
    if (!SECOND_PASS && !GENERATED && gl_LocalInvocationIndex == 0u && gl_WorkGroupID.x == 0u && gl_WorkGroupID.y == 0u) {
        uint left = draws[COMMAND_RASTER_LEFT].vertex_count;
        draws[COMMAND_RASTER_RETRY] = DrawCommand(min(left, 65535u), (left + 65534u) / 65535u, 1u, 0u);
    }
}
