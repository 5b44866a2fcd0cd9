// Blade shading (SPEC §8), shared by every technique: a root-to-tip colour gradient varied per
// blade and per clump; Lambert or Blinn-Phong with a highlight that grows toward the tip on the
// sunlit side, diffuse transmission on the other (and the lamps' light likewise); a sky/ground
// hemisphere ambient; a stronger back-scatter when looking into the sun; fake ambient occlusion at
// the root and along the midrib; the sun's shadow; distance fog. Two-sided: lit from the side the
// eye sees. The vertex stages find a blade's look and colour variation here; blade_fragment.wesl
// shades. Needs common.glsl. What blade `blade` of look `look` at `position` multiplies its kind's
// colours by: its own shade and hue (a hash of it), its clump's (value noise of position, shared by
// neighbouring blades), and the paint's tint there.
vec3 albedo_variation(vec3 position, uint blade, uvec2 look) {
    float jitter = frame.root_color.w;
    float variation = frame.shading_extra.y;
    vec2 xz = world_xz(position.xz) * frame.shading_extra.z;
    float clump = value_noise(xz) - 0.5;
    float clump_hue = value_noise(xz * 0.7 + vec2(31.7)) - 0.5;
    float shade = (hash_unit(blade) - 0.5) * jitter + clump * variation;
    float hue = (hash_unit(blade ^ 0x9e3779b9u) - 0.5) * jitter + clump_hue * 2.0 * variation;
    vec3 vary = vec3(1.0 + shade);
    vary.r *= 1.0 + 1.5 * hue; // some clumps drier, some lusher
    // As the paint tints the ground there (paint.rs): dry patches, lush hollows.
    if ((look.x & LOOK_TINTED) != 0u) {
        vary *= 4.0 * unpackUnorm4x8(look.y).rgb;
    }
    return vary;
}

// The root's and the tip's colour of a blade of look `look`: its kind of grass's (species.rs),
// or the scene's.
vec3 root_albedo(uvec2 look) {
    return species_count() > 0u ? frame.species[4u * (look.x & 0xffu) + 2u].rgb
                                : frame.root_color.rgb;
}
vec3 tip_albedo(uvec2 look) {
    return species_count() > 0u ? frame.species[4u * (look.x & 0xffu) + 3u].rgb
                                : frame.tip_color.rgb;
}

// A flowering stalk's head colour (its kind's), before the blade's variation.
vec3 seed_head_albedo(uvec2 look) {
    return frame.seed_heads[2u * (look.x & 0xffu) + 1u].rgb;
}

// The colour at height v of a blade of look `look` (common.glsl `blade_look`), its variation
// `vary` (`albedo_variation`): a root-to-tip gradient; a flowering stalk's head, in its own
// colour from where the spindle starts, with rows of spikelets, lighter and darker, up it.
vec3 blade_albedo(float v, uvec2 look, vec3 vary) {
    vec3 base = mix(root_albedo(look), tip_albedo(look), v);
    float head = seed_head_length(look);
    if (head > 0.0) {
        vec3 seeds = seed_head_albedo(look);
        float rows = sin(6.2831853 * v / head * 8.0);
        seeds *= 0.85 + 0.2 * rows;
        base = mix(base, seeds, smoothstep(1.0 - head - 0.02, 1.0 - head + 0.06, v));
    }
    return max(base * vary, vec3(0.0));
}

// Fake ambient occlusion: dark at the root where blades crowd, a faint groove along the midrib.
float occlusion(vec2 uv) {
    float strength = frame.shading_extra.x;
    float root = mix(1.0 - strength, 1.0, smoothstep(0.0, 0.7, uv.y));
    float midrib = 1.0 - 0.35 * strength * exp(-pow((uv.x - 0.5) / 0.06, 2.0));
    return root * midrib;
}

// Sunlight on a thin blade per unit of sunlight, seen from the side whose normal is `n`:
// reflected where the sun is on that side, and where it is on the far side transmitted through
// the blade — diffusely, so whatever the eye–sun angle — stronger toward the thin tip.
float sun_on_side(vec3 n, vec3 l, float v) {
    float n_dot_l = dot(n, l);
    float transmission = frame.shading_model.w * (0.5 + v);
    return n_dot_l >= 0.0 ? n_dot_l : -n_dot_l * transmission;
}

// Ambient light by normal: the sky above, the sunlit ground's bounce below.
vec3 hemisphere_ambient(vec3 n) {
    vec3 sky = frame.sky_zenith.rgb * frame.light_direction.w * 2.0;
    vec3 sunlit_ground = frame.light_color.rgb * max(frame.light_direction.y, 0.0);
    vec3 bounce = frame.ground_color.rgb * (sunlit_ground + sky);
    return mix(bounce, sky, 0.5 + 0.5 * n.y);
}

// All the light (per unit of albedo) on the blade's side whose normal is `n`: ambient, dimmed
// by `ao`, and the sun `sun` from `l`, reflected or transmitted.
vec3 light_on_side(vec3 n, vec3 l, vec3 sun, vec2 uv, float ao) {
    return hemisphere_ambient(n) * ao + sun * sun_on_side(n, l, uv.y);
}

// The colour at `position` with (geometric, either side's) normal `normal` and blade coordinates
// `uv` (u across, v from root to tip) of a blade of look `look` (common.glsl `blade_look`) whose
// colour varies by `vary` (`albedo_variation`), in `sunlit` of the sunlight (common.glsl
// `sunlight`), fogged.
vec3 shade_blade_lit(vec3 normal, vec3 position, vec2 uv, uvec2 look, vec3 vary, float sunlit) {
    vec3 to_eye = frame.camera_position.xyz - position;
    float dist = length(to_eye);
    vec3 view = to_eye / max(dist, 1e-6);
    vec3 n = normalize_or_zero(normal);
    // The side the eye sees, blended over a narrow band of angles: where a curved blade turns
    // edge-on to the eye the seen side changes, and switching at once drew a hard line across
    // every blade bending away from the eye — lit above it, flat ambient-only dark below, which
    // overlapping blades turned into stair-stepped dark masses.
    float front = smoothstep(-0.2, 0.2, dot(n, view));
    vec3 l = frame.light_direction.xyz;
    vec3 sun = frame.light_color.rgb * sunlit;
    vec3 albedo = blade_albedo(uv.y, look, vary);
    float ao = occlusion(uv);
    vec3 color =
        albedo * mix(light_on_side(-n, l, sun, uv, ao), light_on_side(n, l, sun, uv, ao), front);
    // The lamps, reflected or shining through the blade as the sun does.
    for (uint k = 0u; k < frame.lamp_meta.x; k++) {
        vec3 to_lamp;
        vec3 lamp = lamp_light(k, position, to_lamp);
        float sides = mix(sun_on_side(-n, to_lamp, uv.y), sun_on_side(n, to_lamp, uv.y), front);
        color += albedo * lamp * sides;
    }
    if (shading_model() == SHADING_BLINN_PHONG) {
        vec3 h = normalize(l + view);
        float tip = uv.y * uv.y;
        // Of the two sides' highlights one is 0 (the half vector lies on one side): one power,
        // weighted by how much of its side is seen.
        float n_dot_h = dot(n, h);
        float seen = n_dot_h >= 0.0 ? front : 1.0 - front;
        float highlight = pow(abs(n_dot_h), frame.shading_model.z) * seen;
        color += sun * frame.shading_model.y * tip * highlight;
    }
    // Back-scatter: a highlight of sunlight through the blade toward an eye that looks into the
    // sun.
    float into_sun = pow(max(dot(-view, l), 0.0), 4.0);
    color += albedo * sun * frame.shading_model.w * into_sun * (0.3 + 0.7 * uv.y) * 1.5;
    return apply_fog(color, dist);
}
