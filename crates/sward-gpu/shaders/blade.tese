#version 460
// The tessellation route's blade surface: each vertex the tessellator asks for, at (u across, v
// along the height), placed and varied by the core (tessellation.wesl `tessellated_vertex`), as
// the strips and the mesh stage place theirs; blade_fragment.wesl shades it.
#extension GL_GOOGLE_include_directive : require
#include "declared.glsl"
#include "tessellation.glsl"

layout(constant_id = CONSTANT_COPY_BLADES) const bool COPY_BLADES = false;
layout(quads, fractional_even_spacing, ccw) in;
layout(location = 0) in uint in_blade[];
layout(location = 0) out vec3 out_normal;
layout(location = 1) out vec3 out_position;
layout(location = 2) out vec2 out_uv;
layout(location = 3) out vec3 out_vary;
layout(location = 4) flat out uvec2 out_look;

void main() {
    vec2 uv = gl_TessCoord.xy;
    BladeVertex vertex = tessellated_vertex(in_blade[0], COPY_BLADES, uv.x, uv.y);
    out_normal = vertex.normal;
    out_position = vertex.position;
    out_uv = vertex.uv;
    out_vary = vertex.vary;
    out_look = vertex.look;
    gl_Position = vertex.clip;
}
