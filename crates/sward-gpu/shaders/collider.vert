#version 460
// The collider spheres, one instance each, built from the vertex index (a coarse UV sphere of
// COLLIDER_RINGS × COLLIDER_SEGMENTS quads; keep in step with renderer.rs's COLLIDER_VERTICES).
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(location = 0) out vec3 out_position;
layout(location = 1) out vec3 out_normal;

const vec2 CORNERS[6] = vec2[](vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 0), vec2(1, 1), vec2(0, 1));
const uint COLLIDER_RINGS = 16u;
const uint COLLIDER_SEGMENTS = 32u;

void main() {
    vec4 sphere = frame.colliders[gl_InstanceIndex];
    uint quad = uint(gl_VertexIndex) / 6u;
    vec2 grid = (vec2(quad % COLLIDER_SEGMENTS, quad / COLLIDER_SEGMENTS) + CORNERS[gl_VertexIndex % 6])
        / vec2(COLLIDER_SEGMENTS, COLLIDER_RINGS);
    float phi = 3.14159265 * grid.y;
    float theta = 6.28318531 * grid.x;
    out_normal = vec3(sin(phi) * cos(theta), cos(phi), sin(phi) * sin(theta));
    out_position = sphere.xyz + out_normal * sphere.w;
    gl_Position = pass_view_proj() * vec4(out_position, 1.0);
}
