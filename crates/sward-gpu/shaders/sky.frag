#version 460
// Sky gradient from the horizon colour to the zenith colour along each view ray, with a soft glow
// around the sun.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(location = 0) in vec2 in_ndc;
layout(location = 0) out vec4 out_color;

void main() {
    vec4 far_point = frame.inv_view_proj * vec4(in_ndc, 1.0, 1.0);
    vec3 ray = normalize(far_point.xyz / far_point.w - frame.camera_position.xyz);
    float elevation = clamp(ray.y, 0.0, 1.0);
    vec3 color = mix(frame.sky_horizon.rgb, frame.sky_zenith.rgb, pow(elevation, 0.6));
    float sun = max(dot(ray, frame.light_direction.xyz), 0.0);
    color += frame.light_color.rgb * (0.25 * pow(sun, 8.0) + 0.6 * pow(sun, 256.0));
    out_color = guard_color(color);
}
