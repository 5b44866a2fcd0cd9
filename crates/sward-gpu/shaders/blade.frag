#version 460
// The drawn blades' fragments (Bezier and instanced): shading.glsl's blade shading.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shading.glsl"

layout(location = 0) in vec3 in_normal;
layout(location = 1) in vec3 in_position;
layout(location = 2) in vec2 in_uv; // u across the blade, v from root to tip
// The blade's colour variation (shading.glsl `albedo_variation`: its own shade and hue, its
// clump's, the paint's tint) as the vertex stage finds it at its vertices, interpolated. The
// clumps' noise is smooth over a blade, so this draws what finding it at each fragment drew
// within 3 levels of 255, on a few pixels in ten thousand (render.rs
// `colour_variation_found_at_the_vertices_matches_the_fragments`), and a fragment no longer
// pays the noise's eight hashes. On the H200 at 1920×1080 the draw fell 0.79 ms for the
// landscape, 0.65 for the prairie and 0.35–0.48 for the instanced grass (BENCHMARKS.md).
layout(location = 3) in vec3 in_vary;
// What its colour comes from (common.glsl `blade_look`), found once per blade.
layout(location = 4) flat in uvec2 in_look;
layout(location = 0) out vec4 out_color;

void main() {
    out_color = guard_color(shade_blade_lit(in_normal, in_position, in_uv, in_look, in_vary, sunlight(in_position)));
}
