#version 460
// The tiles this frame runs, decided on the GPU so the host does nothing per tile (one
// workgroup; tiles.rs `active` is the CPU reference, for fields of at most MAX_TILES tiles):
// each tile's box — stretched along the sun's rays where blades cast shadows — against the view
// frustum: drawn where it meets the frustum, simulated where it lies within the margin of it,
// else skipped. The tiles that run are sorted nearest first (a bitonic sort of keys made of the
// distance, coarsely, and the tile's index, so ties keep the field's order and every run is the
// same) and written as the list the simulate and cull passes run a row of workgroups each of,
// with their dispatch size and the blades simulated (COMMAND_TILE_DISPATCH). The boxes follow
// the list in the same buffer: per tile (min, first), (max, count).
#extension GL_GOOGLE_include_directive : require
#define SWARD_WRITE
#define SWARD_TILE_CULL
#include "common.glsl"

layout(local_size_x = 1024) in;

// 32 KiB of keys, what every device gives a workgroup (field.rs `TILES_ON_GPU`: larger fields
// have the host decide).
const uint MAX_TILES = 8192u;
const uint INDEX_BITS = 13u;
shared uint keys[MAX_TILES];
#define SORT_KEYS keys
#include "bitonic.glsl"

struct TileBox {
    vec3 lo;
    vec3 hi;
    uint first;
    uint count;
};

TileBox tile_box(uint i) {
    uint at = frame.tiles.x + 2u * i;
    ActiveTile a = active_tiles[at];
    ActiveTile b = active_tiles[at + 1u];
    return TileBox(uintBitsToFloat(uvec3(a.first, a.count, a.drawn)), uintBitsToFloat(uvec3(b.first, b.count, b.drawn)), a.unused, b.unused);
}

// tiles.rs `outside`: the box wholly on the outer side of some plane by more than `margin`.
bool outside(vec3 lo, vec3 hi, float margin) {
    for (int k = 0; k < 6; k++) {
        vec3 n = frame.frustum[k].xyz;
        vec3 corner = mix(lo, hi, greaterThanEqual(n, vec3(0.0)));
        if (dot(n, corner) + frame.frustum[k].w < -margin) {
            return true;
        }
    }
    return false;
}

// tiles.rs `TileFate`: 0 skipped, 1 simulated, 2 drawn.
uint tile_fate(TileBox t) {
    if ((frame.modes.x & CULL_TILES) == 0u) {
        return 2u;
    }
    vec3 lo = t.lo;
    vec3 hi = t.hi;
    if ((frame.modes.w & DRAW_BLADE_SHADOWS) != 0u) {
        // tiles.rs `with_shadow`: moved away from the sun by its height's shadow, at most five
        // heights long.
        vec3 sun = normalize_or_zero(frame.light_direction.xyz);
        vec3 offset = -sun * (hi.y - lo.y) / max(sun.y, 0.2);
        lo = min(lo, lo + offset);
        hi = max(hi, hi + offset);
    }
    float margin = frame.coarse_cull.x;
    return !outside(lo, hi, 0.0) ? 2u : (!outside(lo, hi, margin) ? 1u : 0u);
}

// The sort key of tile i: its distance from the eye (to its box, as tiles.rs), log-spaced into
// the top bits, then its index.
uint tile_key(uint i, TileBox t) {
    vec3 eye = frame.camera_position.xyz;
    float d = distance(clamp(eye, t.lo, t.hi), eye);
    uint near = uint(clamp(log2(1.0 + d) * 16384.0, 0.0, float((1u << (32u - INDEX_BITS)) - 1u)));
    return (near << INDEX_BITS) | i;
}

// How many keys before the first skipped tile's (all ones) in the sorted keys.
uint kept_tiles(uint n) {
    uint lo = 0u;
    uint hi = n;
    while (lo < hi) {
        uint mid = (lo + hi) / 2u;
        if (keys[mid] == 0xffffffffu) {
            hi = mid;
        } else {
            lo = mid + 1u;
        }
    }
    return lo;
}

void main() {
    uint lane = gl_LocalInvocationID.x;
    uint tiles = frame.tiles.x;
    // Every word of shared memory holds keys, so the blades simulated are summed in the command.
    if (lane == 0u) {
        draws[COMMAND_TILE_DISPATCH] = DrawCommand(frame.tiles.y, 0u, 1u, 0u);
    }
    memoryBarrierBuffer();
    barrier();
    uint n = bitonic_size(tiles);
    for (uint i = lane; i < n; i += gl_WorkGroupSize.x) {
        uint key = 0xffffffffu;
        if (i < tiles) {
            TileBox t = tile_box(i);
            if (tile_fate(t) != 0u) {
                key = tile_key(i, t);
                atomicAdd(draws[COMMAND_TILE_DISPATCH].first_instance, t.count);
            }
        }
        keys[i] = key;
    }
    barrier();
    bitonic_sort(n);
    uint kept = kept_tiles(n);
    for (uint r = lane; r < kept; r += gl_WorkGroupSize.x) {
        uint i = keys[r] & ((1u << INDEX_BITS) - 1u);
        TileBox t = tile_box(i);
        active_tiles[r] = ActiveTile(t.first, t.count, uint(tile_fate(t) == 2u), 0u);
    }
    if (lane == 0u) {
        draws[COMMAND_TILE_DISPATCH].instance_count = kept;
    }
}
