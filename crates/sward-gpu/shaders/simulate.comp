#version 460
// The physical model of SPEC §3, one invocation per blade of the frame's active tiles,
// `counts.y` fixed steps per dispatch.
#extension GL_GOOGLE_include_directive : require
#define SWARD_WRITE
#include "common.glsl"
#include "instanced.glsl"
#include "physics.glsl"

layout(local_size_x_id = CONSTANT_WORKGROUP) in;

void main() {
    bool inside, drawn;
    uint id = tile_blade(inside, drawn);
    if (!inside) {
        return;
    }
    Blade b = blades[id];
    float eta = etas[id];
    simulate_blade(b, eta);
    ease_into_twin(b, id);
    // Only the guide and tip move; the root and up never change.
    blades[id].v1 = b.v1;
    blades[id].v2 = b.v2;
    etas[id] = eta;
}
