#version 460
// The blade's surface (SPEC §6): De Casteljau along the height, the blade shape across the width,
// the 3D ridge, and the minimum-width fix that keeps far blades from aliasing into holes.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(quads, fractional_even_spacing, ccw) in;
layout(location = 0) in uint in_blade[];
layout(location = 0) out vec3 out_normal;
layout(location = 1) out vec3 out_position;
layout(location = 2) out vec2 out_uv;
layout(location = 3) flat out uint out_blade;

float blade_shape(float u, float v) {
    uint shape = uint(frame.blade_style.x);
    if (shape == 0u) return u;                     // quad
    if (shape == 1u) return u + 0.5 * v - u * v;   // triangle
    if (shape == 2u) return u - u * v * v;         // quadratic
    float tip = frame.blade_style.y;               // triangle-tip
    return 0.5 + (u - 0.5) * (1.0 - max(v - tip, 0.0) / (1.0 - tip));
}

vec2 to_pixels(vec3 p) {
    vec4 clip = frame.view_proj * vec4(p, 1.0);
    return clip.xy / max(clip.w, 1e-4) * 0.5 * frame.viewport.xy;
}

void main() {
    float u = gl_TessCoord.x;
    float v = gl_TessCoord.y;
    uint id = in_blade[0];
    Blade b = drawn_blade(id);
    vec3 up = b.up.xyz;
    float w = b.v2.w;
    vec3 t1 = width_direction(up, b.v0.w);

    vec3 a = mix(b.v0.xyz, b.v1.xyz, v);
    vec3 bb = mix(b.v1.xyz, b.v2.xyz, v);
    vec3 c = mix(a, bb, v);
    vec3 t0 = bb - a;
    t0 = dot(t0, t0) > 1e-12 ? normalize(t0) : up;
    vec3 n = normalize(cross(t0, t1));
    vec3 c0 = c - w * t1;
    vec3 c1 = c + w * t1;

    float tau = blade_shape(u, v);
    float min_px = frame.blade_style.w;
    if (min_px > 0.0) {
        float px = length(to_pixels(c1) - to_pixels(c0));
        tau = mix(tau, u, clamp(1.0 - px / min_px, 0.0, 1.0));
    }
    vec3 p = mix(c0, c1, tau);
    if (frame.blade_style.z > 0.5) {
        p += n * w * (0.5 - abs(u - 0.5)) * (1.0 - v);
    }

    out_normal = n;
    out_position = p;
    out_uv = vec2(u, v);
    out_blade = id;
    gl_Position = frame.view_proj * vec4(p, 1.0);
}
