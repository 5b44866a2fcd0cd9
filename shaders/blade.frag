#version 460
// Blade shading (SPEC §8): a root-to-tip colour gradient varied per blade and per clump; Lambert
// or Blinn-Phong with a highlight that grows toward the tip; sunlight scattered through the blade
// when looking into the sun; fake ambient occlusion at the root and along the midrib; the sun's
// shadow; distance fog. Two-sided: the normal faces the viewer.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(location = 0) in vec3 in_normal;
layout(location = 1) in vec3 in_position;
layout(location = 2) in vec2 in_uv; // u across the blade, v from root to tip
layout(location = 3) flat in uint in_blade;
layout(location = 0) out vec4 out_color;

vec3 blade_albedo(float v) {
    float jitter = frame.root_color.w;
    float variation = frame.shading_extra.y;
    vec2 xz = in_position.xz * frame.shading_extra.z;
    // Clumps: value noise of position, shared by neighbouring blades; per blade: a hash of its id.
    float clump = value_noise(xz) - 0.5;
    float clump_hue = value_noise(xz * 0.7 + vec2(31.7)) - 0.5;
    float shade = (hash_unit(in_blade) - 0.5) * jitter + clump * variation;
    float hue = (hash_unit(in_blade ^ 0x9e3779b9u) - 0.5) * jitter + clump_hue * 2.0 * variation;
    vec3 albedo = mix(frame.root_color.rgb, frame.tip_color.rgb, v) * (1.0 + shade);
    albedo.r *= 1.0 + 1.5 * hue; // some clumps drier, some lusher
    return max(albedo, vec3(0.0));
}

// Fake ambient occlusion: dark at the root where blades crowd, a faint groove along the midrib.
float occlusion(vec2 uv) {
    float strength = frame.shading_extra.x;
    float root = mix(1.0 - strength, 1.0, smoothstep(0.0, 0.7, uv.y));
    float midrib = 1.0 - 0.35 * strength * exp(-pow((uv.x - 0.5) / 0.06, 2.0));
    return root * midrib;
}

void main() {
    vec3 to_eye = frame.camera_position.xyz - in_position;
    float dist = length(to_eye);
    vec3 view = to_eye / max(dist, 1e-6);
    vec3 n = normalize(in_normal);
    if (dot(n, view) < 0.0) {
        n = -n;
    }
    vec3 l = frame.light_direction.xyz;
    vec3 sun = frame.light_color.rgb * sunlight(in_position);
    vec3 albedo = blade_albedo(in_uv.y);
    float ao = occlusion(in_uv);
    vec3 color = albedo * frame.sky_zenith.rgb * frame.light_direction.w * 2.0 * ao;
    color += albedo * sun * max(dot(n, l), 0.0);
    if (frame.shading_model.x == 1.0) {
        vec3 h = normalize(l + view);
        float tip = in_uv.y * in_uv.y;
        color += sun * frame.shading_model.y * tip * pow(max(dot(n, h), 0.0), frame.shading_model.z);
    }
    // Back-scatter: sunlight through the blade toward an eye that looks into the sun.
    float into_sun = pow(max(dot(-view, l), 0.0), 4.0);
    color += albedo * sun * frame.shading_model.w * into_sun * (0.3 + 0.7 * in_uv.y) * 1.5;
    out_color = guard_color(apply_fog(color, dist));
}
