#version 460
// The strip route: each visible blade one instance of a triangle strip, its vertices evaluated
// from blade_surface.glsl at (u, v) picked by gl_VertexIndex — no tessellator. The draw command
// of distance bucket gl_DrawID gives the strip its length: 2 (or, with the ridge, 4) vertices
// per row, strip_segments rows of segments, as the tessellation route would cut the blade.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "blade_surface.glsl"

layout(location = 0) out vec3 out_normal;
layout(location = 1) out vec3 out_position;
layout(location = 2) out vec2 out_uv;
layout(location = 3) flat out uint out_blade;

void main() {
    uint id = ordered[gl_InstanceIndex];
    uint segments = strip_segments(uint(gl_DrawID));
    uint i = uint(gl_VertexIndex);
    uint row;
    float u;
    if (frame.blade_style.z <= 0.5) {
        row = i >> 1u;
        u = float(i & 1u);
    } else if (i < 2u * (segments + 1u)) {
        // The ridge folds the blade at u = 0.5: up the left half, then down the right half (the
        // two turning triangles are degenerate).
        row = i >> 1u;
        u = 0.5 * float(i & 1u);
    } else {
        uint j = i - 2u * (segments + 1u);
        row = segments - (j >> 1u);
        u = 0.5 + 0.5 * float(j & 1u);
    }
    float v = float(row) / float(segments);
    vec3 n;
    vec3 p = blade_point(blades[id], u, v, n);
    out_normal = n;
    out_position = p;
    out_uv = vec2(u, v);
    out_blade = id;
    gl_Position = pass_view_proj() * vec4(p, 1.0);
}
