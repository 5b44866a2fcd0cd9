#version 460
// Ground shading: Lambert under the same light and shadow as the blades, soil mottled by value noise, tinted
// toward the grass's root colour where the field grows (everywhere when generated grass covers
// it) as densely as the paint lets grass grow there, wearing the grass's own colour past the
// billboards' reach (bare where the paint leaves it bare), fogged with distance.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 0) out vec4 out_color;

void main() {
    vec3 n = normalize(in_normal);
    vec2 xz = ground_kind() == GROUND_SPHERE ? vec2(in_position.x + in_position.y, in_position.z) : world_xz(in_position.xz);
    float mottle = 0.6 * value_noise(xz * 0.9) + 0.4 * value_noise(xz * 4.1 + vec2(3.7));
    vec2 field = frame.ground_extent.zw;
    vec2 outside = max(abs(xz) - field, vec2(0.0));
    float in_field = ground_kind() != GROUND_PLANE ? 1.0 : 1.0 - smoothstep(0.0, 2.0, length(outside));
    if (draws_generated_grass()) {
        in_field = 1.0; // generated grass covers the ground far beyond the grown field
    }
    // A path painted bare shows its soil at every distance, as bare as the grass beside it is thin.
    PaintSample paint = paint_map_or_full(xz);
    float density = painted_density(paint, xz);
    in_field *= density;
    // The grass's colour on the ground, tinted as the paint tints the blades there.
    vec3 tint = painted_tint(paint, xz);
    vec3 root, tip;
    ground_grass_colours(paint.species, root, tip);
    vec3 albedo = frame.ground_color.rgb * (0.7 + 0.6 * mottle);
    albedo = mix(albedo, root * tint * (0.8 + 0.4 * mottle), 0.6 * in_field);
    float dist = distance(frame.camera_position.xyz, in_position);
    if (draws_billboards()) {
        // Past the billboards' reach the ground itself wears the grass's colour to the horizon,
        // fading in as the billboards sink into it.
        float radius = frame.billboard_grid.y;
        vec3 turf = mix(root, tip, 0.45) * tint * (0.9 + 0.2 * mottle);
        albedo = mix(albedo, turf, density * smoothstep(0.75 * radius, radius, dist));
    }
    float lambert = max(dot(n, frame.light_direction.xyz), 0.0) * sunlight(in_position);
    vec3 color = albedo * (frame.light_color.rgb * lambert + frame.sky_zenith.rgb * frame.light_direction.w * 2.0);
    for (uint k = 0u; k < frame.lamp_meta.x; k++) {
        vec3 to_lamp;
        vec3 lamp = lamp_light(k, in_position, to_lamp);
        color += albedo * lamp * max(dot(n, to_lamp), 0.0);
    }
    out_color = guard_color(apply_fog(color, dist));
}
