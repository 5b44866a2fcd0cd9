#version 460
// Blade shading: two-sided Lambert, a root-to-tip colour gradient with per-blade jitter, sky
// ambient darkening toward the root, distance fog.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(location = 0) in vec3 in_normal;
layout(location = 1) in vec3 in_position;
layout(location = 2) in vec2 in_uv;
layout(location = 3) flat in uint in_blade;
layout(location = 0) out vec4 out_color;

void main() {
    vec3 to_eye = frame.camera_position.xyz - in_position;
    float dist = length(to_eye);
    vec3 n = normalize(in_normal);
    if (dot(n, to_eye) < 0.0) {
        n = -n;
    }
    float jitter = (hash_unit(in_blade) - 0.5) * frame.root_color.w;
    float hue = (hash_unit(in_blade ^ 0x9e3779b9u) - 0.5) * frame.root_color.w;
    vec3 albedo = mix(frame.root_color.rgb, frame.tip_color.rgb, in_uv.y);
    albedo *= 1.0 + jitter;
    albedo.r *= 1.0 + 1.5 * hue; // some blades drier, some lusher
    vec3 l = frame.light_direction.xyz;
    float lambert = max(dot(n, l), 0.0);
    float sky_light = frame.light_direction.w * mix(0.35, 1.0, in_uv.y);
    vec3 color = albedo * (frame.light_color.rgb * lambert + frame.sky_zenith.rgb * sky_light * 2.0);
    out_color = guard_color(apply_fog(color, dist));
}
