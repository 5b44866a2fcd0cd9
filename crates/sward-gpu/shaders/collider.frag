#version 460
// Collider spheres: weathered stone under the same sun, sky light and fog as the grass.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 0) out vec4 out_color;

void main() {
    vec3 n = normalize(in_normal);
    float mottle = 0.7 + 0.3 * value_noise(vec2(in_position.x + in_position.y, in_position.z) * 3.0);
    vec3 albedo = vec3(0.32, 0.29, 0.25) * mottle;
    float lambert = max(dot(n, frame.light_direction.xyz), 0.0);
    float sky = frame.light_direction.w * (0.6 + 0.4 * n.y);
    vec3 color = albedo * (frame.light_color.rgb * lambert + frame.sky_zenith.rgb * sky * 2.0);
    out_color = guard_color(apply_fog(color, distance(frame.camera_position.xyz, in_position)));
}
