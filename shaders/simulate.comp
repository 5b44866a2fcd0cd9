#version 460
// The physical model of SPEC §3, one invocation per blade, `counts.y` fixed steps per dispatch.
#extension GL_GOOGLE_include_directive : require
#define SWARD_WRITE
#include "common.glsl"
#include "physics.glsl"

layout(local_size_x_id = 0) in;

void main() {
    uint id = gl_GlobalInvocationID.x;
    if (id >= frame.counts.x) {
        return;
    }
    Blade b = blades[id];
    float eta = etas[id];
    simulate_blade(b, eta);
    // Only the guide and tip move; the root and up never change.
    blades[id].v1 = b.v1;
    blades[id].v2 = b.v2;
    etas[id] = eta;
}
