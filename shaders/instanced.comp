#version 460
// The instanced field (SPEC §7 [F]), one invocation per grid cell of the frame's patches: make the
// cell's blade from its hash (instanced.rs `blade_at`), cull it (bounding sphere against the
// frustum, distance cut-off, inner radius; `lod_of`), and append it to its level's visible list,
// counting into that level's draw command (reset by vkCmdFillBuffer before this dispatch).
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_ballot : require
#define SWARD_WRITE
#include "common.glsl"

layout(local_size_x_id = 0) in;
layout(constant_id = 1) const bool USE_SUBGROUPS = true;

const int PATCH_CELLS = 32;

struct InstancedBlade {
    vec3 root;
    float facing;
    float height;
    float width;
    float pitch;
    float bend;
    float phase;
    uint hash;
};

uint cell_hash(ivec2 cell) {
    uint seed = frame.instanced_meta.x;
    return hash_u32((uint(cell.x) * 73856093u) ^ hash_u32(uint(cell.y) ^ (seed * 19349663u)));
}

// The height of the ground grid's triangles at xz (mesh.rs `HeightGrid::height_at`); false off it.
bool ground_height(vec2 xz, out float height) {
    uvec2 n = frame.instanced_ground_cells.xy;
    height = 0.0;
    if (n.x == 0u) {
        return true;
    }
    vec2 lo = frame.instanced_ground.xy;
    vec2 hi = frame.instanced_ground.zw;
    vec2 cells = vec2(n - 1u);
    vec2 q = (xz - lo) / (hi - lo) * cells;
    if (any(lessThan(q, vec2(0.0))) || any(greaterThan(q, cells))) {
        return false;
    }
    vec2 cell = min(floor(q), cells - 1.0);
    vec2 f = q - cell;
    uint i = uint(cell.x), j = uint(cell.y);
    float h00 = ground_vertices[j * n.x + i].position.y;
    float h10 = ground_vertices[j * n.x + i + 1u].position.y;
    float h01 = ground_vertices[(j + 1u) * n.x + i].position.y;
    float h11 = ground_vertices[(j + 1u) * n.x + i + 1u].position.y;
    height = f.x + f.y <= 1.0 ? h00 + f.x * (h10 - h00) + f.y * (h01 - h00)
                              : h11 + (1.0 - f.x) * (h01 - h11) + (1.0 - f.y) * (h10 - h11);
    return true;
}

InstancedBlade blade_at(ivec2 cell) {
    uint h = cell_hash(cell);
    uint h1 = hash_u32(h), h2 = hash_u32(h ^ 0x68e31da4u), h3 = hash_u32(h ^ 0xb5297a4du);
    uint h4 = hash_u32(h ^ 0x1b56c4e9u), h5 = hash_u32(h ^ 0x7f4a7c15u);
    float spacing = frame.instanced_grid.x;
    vec2 xz = (vec2(cell) + vec2(hash_unit(h1), hash_unit(h2))) * spacing;
    float y;
    bool on_ground = ground_height(xz, y);
    float clump = 0.5 + 0.5 * simplex2(xz * frame.instanced_grid.w);
    float tall = clamp(clump + 0.25 * (hash_unit(h3) - 0.5), 0.0, 1.0);
    vec4 shape = frame.instanced_shape;
    InstancedBlade b;
    b.root = vec3(xz.x, y, xz.y);
    b.facing = hash_unit(h4) * 6.2831855;
    b.height = on_ground ? shape.x + (shape.y - shape.x) * tall : 0.0;
    b.width = shape.z + (shape.w - shape.z) * (0.5 * tall + 0.5 * hash_unit(h5));
    b.pitch = 0.25 * (hash_unit(h3) - 0.5);
    b.bend = frame.instanced_motion.x * (0.5 + hash_unit(h5));
    b.phase = hash_unit(h2 ^ h4) * 6.2831855;
    b.hash = h;
    return b;
}

// The blade's level of detail, or -1 when culled.
int lod_of(InstancedBlade b) {
    if (b.height <= 0.0) {
        return -1;
    }
    vec3 center = b.root + vec3(0.0, 0.5 * b.height, 0.0);
    float radius = 0.5 * b.height * (1.0 + frame.instanced_motion.x + frame.instanced_motion.y) + b.width;
    for (int k = 0; k < 6; k++) {
        if (dot(frame.frustum[k].xyz, center) + frame.frustum[k].w < -radius) {
            return -1;
        }
    }
    float dist = length(b.root - frame.camera_position.xyz);
    if (dist >= frame.instanced_grid.y || dist < frame.instanced_grid.z) {
        return -1;
    }
    vec3 lod = frame.instanced_lod.xyz;
    return int(dist >= lod.x) + int(dist >= lod.y) + int(dist >= lod.z);
}

// Slot in level `lod`'s list: one atomic per subgroup and level.
uint append_slot(bool mine, uint lod) {
    if (!USE_SUBGROUPS) {
        return mine ? atomicAdd(instanced_draws[lod].instance_count, 1u) : 0u;
    }
    uvec4 ballot = subgroupBallot(mine);
    uint total = subgroupBallotBitCount(ballot);
    uint base = 0u;
    if (subgroupElect() && total > 0u) {
        base = atomicAdd(instanced_draws[lod].instance_count, total);
    }
    return subgroupBroadcastFirst(base) + subgroupBallotExclusiveBitCount(ballot);
}

void main() {
    ivec2 patch_ = instanced_patches[gl_WorkGroupID.y].xy;
    uint local = gl_GlobalInvocationID.x;
    bool inside = local < uint(PATCH_CELLS * PATCH_CELLS);
    ivec2 cell = patch_ * PATCH_CELLS + ivec2(local % uint(PATCH_CELLS), local / uint(PATCH_CELLS));
    InstancedBlade b = blade_at(cell);
    int lod = inside ? lod_of(b) : -1;
    for (uint k = 0u; k < 4u; k++) {
        // Every lane votes for every level.
        uint slot = append_slot(lod == int(k), k);
        if (lod == int(k) && slot < frame.instanced_caps[k]) {
            uint at = 2u * (frame.instanced_lists[k] + slot);
            instanced_blades[at] = uvec4(floatBitsToUint(b.root), packHalf2x16(vec2(b.height, b.width)));
            instanced_blades[at + 1u] = uvec4(
                packHalf2x16(vec2(b.facing, b.pitch)), packHalf2x16(vec2(b.bend, b.phase)), b.hash, 0u);
        }
    }
}
