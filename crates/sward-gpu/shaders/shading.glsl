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
