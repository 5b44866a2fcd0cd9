#version 460
// Simulate and cull fused: each invocation steps its blade, writes it back and culls it while it
// is still in registers, so the blade is read from memory once per frame instead of twice.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_vote : require
#define SWARD_WRITE
#include "common.glsl"
#include "instanced.glsl"
#include "physics.glsl"

layout(local_size_x_id = CONSTANT_WORKGROUP) in;
layout(constant_id = CONSTANT_USE_SUBGROUPS) const bool USE_SUBGROUPS = true;

#include "culling.glsl"

void main() {
    bool inside, drawn;
    uint id = tile_blade(inside, drawn);
    bool keep = false;
    Blade b;
    if (inside) {
        b = blades[id];
        float eta = etas[id];
        simulate_blade(b, eta);
        ease_into_twin(b, id);
        blades[id].v1 = b.v1;
        blades[id].v2 = b.v2;
        etas[id] = eta;
        // Tiles just outside the view are simulated but not drawn.
        keep = drawn && is_visible(b, id);
    }
    append_visible(keep, id, b);
}
