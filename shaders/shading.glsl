// Blade shading (SPEC §8), shared by every technique: a root-to-tip colour gradient varied per
// blade and per clump; Lambert or Blinn-Phong with a highlight that grows toward the tip;
// sunlight scattered through the blade when looking into the sun; fake ambient occlusion at the
// root and along the midrib; the sun's shadow; distance fog. Two-sided: the normal faces the
// viewer. blade.frag shades the drawn blades with it, instanced.comp the splatted ones.
// Needs common.glsl.
vec3 blade_albedo(vec3 position, float v, uint blade) {
    float jitter = frame.root_color.w;
    float variation = frame.shading_extra.y;
    vec2 xz = position.xz * frame.shading_extra.z;
    // Clumps: value noise of position, shared by neighbouring blades; per blade: a hash of its id.
    float clump = value_noise(xz) - 0.5;
    float clump_hue = value_noise(xz * 0.7 + vec2(31.7)) - 0.5;
    float shade = (hash_unit(blade) - 0.5) * jitter + clump * variation;
    float hue = (hash_unit(blade ^ 0x9e3779b9u) - 0.5) * jitter + clump_hue * 2.0 * variation;
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

// The colour of blade `blade` at `position` with normal `normal` and blade coordinates `uv` (u
// across, v from root to tip), fogged.
vec3 shade_blade(vec3 normal, vec3 position, vec2 uv, uint blade) {
    vec3 to_eye = frame.camera_position.xyz - position;
    float dist = length(to_eye);
    vec3 view = to_eye / max(dist, 1e-6);
    vec3 n = normalize_or_zero(normal);
    if (dot(n, view) < 0.0) {
        n = -n;
    }
    vec3 l = frame.light_direction.xyz;
    vec3 sun = frame.light_color.rgb * sunlight(position);
    vec3 albedo = blade_albedo(position, uv.y, blade);
    float ao = occlusion(uv);
    vec3 color = albedo * frame.sky_zenith.rgb * frame.light_direction.w * 2.0 * ao;
    color += albedo * sun * max(dot(n, l), 0.0);
    if (frame.shading_model.x == 1.0) {
        vec3 h = normalize(l + view);
        float tip = uv.y * uv.y;
        color += sun * frame.shading_model.y * tip * pow(max(dot(n, h), 0.0), frame.shading_model.z);
    }
    // Back-scatter: sunlight through the blade toward an eye that looks into the sun.
    float into_sun = pow(max(dot(-view, l), 0.0), 4.0);
    color += albedo * sun * frame.shading_model.w * into_sun * (0.3 + 0.7 * uv.y) * 1.5;
    return apply_fog(color, dist);
}
