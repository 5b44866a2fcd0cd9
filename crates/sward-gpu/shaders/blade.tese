#version 460
// The tessellation route's blade surface: blade_surface.glsl evaluated at the tessellator's
// (u across, v along the height) coordinates.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shading.glsl"
#include "blade_surface.glsl"

layout(quads, fractional_even_spacing, ccw) in;
layout(location = 0) in uint in_blade[];
layout(location = 0) out vec3 out_normal;
layout(location = 1) out vec3 out_position;
layout(location = 2) out vec2 out_uv;
layout(location = 3) out vec3 out_vary; // blade_fragment.wesl says why
layout(location = 4) flat out uvec2 out_look;

void main() {
    float u = gl_TessCoord.x;
    float v = gl_TessCoord.y;
    uint id = in_blade[0];
    vec3 n;
    Blade b = drawn_blade(id);
    uint key = blade_colour_key(id);
    uvec2 look = blade_look(key, world_xz(b.v0.xz));
    vec3 p = blade_point(b, blade_outline(look), u, v, n);
    out_normal = n;
    out_position = p;
    out_uv = vec2(u, v);
    out_vary = albedo_variation(p, key, look);
    out_look = look;
    gl_Position = frame.view_proj * vec4(p, 1.0);
}
