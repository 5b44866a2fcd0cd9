// How much of a billboard's quad its painted blades cover: `billboard_coverage` for fragment
// stages (the mip level is the fragment's); compute stages (the billboard splat) define
// BILLBOARD_COVERAGE_COMPUTE and pick the level themselves. Needs common.glsl's grass_texture.

// The share of a billboard's quad at `uv` covered by its painted blades, as `layers` quads crossing
// it would cover it (a far billboard drawn as one quad stands for three crossed ones). Where the
// texture is seen near full size its blades are opaque or clear and crossed quads add up as
// layers; where it is seen through coarse mip levels (a few pixels a billboard) alpha is a mean and
// alpha-to-coverage gives quads of equal alpha at one pixel the same samples, so crossed quads
// cover no more than one (levels 3.8 and 5.7: fitted, tests/lod_seams.rs).
const float BILLBOARD_GAIN = 1.17;

float billboard_coverage_at(float alpha, float level, float layers) {
    float overlap = mix(layers, 1.0, smoothstep(3.8, 5.7, level));
    return 1.0 - pow(1.0 - alpha, overlap);
}

// How the painted blades' own light and dark modulate a billboard's shaded colour: about their
// mean green (0.55 in linear terms), which the mip levels keep as they average, times a gain.
// A painted billboard shows the ground between its clumps where a field of blades would not,
// and its blades stand upright where the generated blades lean in gravity and wind, their faces
// turned up to the light: the gain (measured against the instanced grass, tests/lod_seams.rs)
// evens the two out. Every path that paints a billboard (drawn, rasterized, splatted) uses it.
float painted_detail(vec4 painted) {
    return clamp(painted.g / 0.55, 0.6, 1.4) * BILLBOARD_GAIN;
}

#ifndef BILLBOARD_COVERAGE_COMPUTE
float billboard_coverage(vec2 uv, float layers) {
    float level = textureQueryLod(grass_texture, uv).y;
    return billboard_coverage_at(texture(grass_texture, uv).a, level, layers);
}
#endif
