#version 460
// The drawn blades' fragments (Bezier and instanced): shading.glsl's blade shading.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shading.glsl"

layout(location = 0) in vec3 in_normal;
layout(location = 1) in vec3 in_position;
layout(location = 2) in vec2 in_uv; // u across the blade, v from root to tip
// What the blade's colour varies by: a Bezier blade's colour key (common.glsl
// `blade_colour_key`, made by the vertex stage), a generated blade's hash.
layout(location = 3) flat in uint in_blade;
// What its colour comes from (common.glsl `blade_look`), found once per blade.
layout(location = 4) flat in uvec2 in_look;
layout(location = 0) out vec4 out_color;

void main() {
    out_color = guard_color(shade_blade_look(in_normal, in_position, in_uv, in_blade, in_look));
}
