// A far billboard splatted by compute (beyond billboard.splat_distance): its one quad turned
// to the eye, walked a splat cell at a time (a sample of a 4× target), each cell covered where the
// painted texture's coverage at the quad's mip level beats the cell's threshold — what
// alpha-to-coverage does with a sample mask — and kept if nearest by splat.glsl's atomicMin.
// Shading runs at root, middle and tip of the quad and is interpolated, then the painted blades'
// light and dark modulate it as billboard_shading.glsl does. Needs common.glsl, shading.glsl,
// splat.glsl, billboard.glsl and billboard_coverage.glsl (with BILLBOARD_COVERAGE_COMPUTE).

// Cells a splatted billboard walks along each side at most: a billboard this big should be drawn.
const int MAX_BILLBOARD_CELLS = 64;

// The coverage a cell needs to be drawn: an ordered (Bayer) threshold by the cell's place on
// screen, as alpha-to-coverage picks samples by their place and alpha alone — so billboards of equal
// coverage over one pixel cover the same samples, as drawn ones do (billboard_coverage.glsl's layers
// rest on that), and coverage spreads evenly instead of in random clumps.
float cell_threshold(ivec2 cell) {
    const uint BAYER[16] = uint[](0u, 8u, 2u, 10u, 12u, 4u, 14u, 6u, 3u, 11u, 1u, 9u, 15u, 7u, 13u, 5u);
    return (float(BAYER[(cell.y & 3) * 4 + (cell.x & 3)]) + 0.5) / 16.0;
}

// The colour of quad `q` of billboard `t` at height `y` (0 root, 1 tip), before the painted detail.
vec3 billboard_shade(Billboard t, BillboardQuad q, float y) {
    return shade_blade(q.normal, billboard_point(t, q, vec2(0.5, y)), vec2(0.3, y), t.hash);
}

void splat_billboard(Billboard t, float dist) {
    BillboardQuad q = billboard_quad(t, 0u, dist, true);
    // Corners bottom left, bottom right, top left, top right, in clip space: the quad is
    // bilinear between them there too (projection is linear before the divide).
    vec4 c[4];
    for (uint k = 0u; k < 4u; k++) {
        c[k] = billboard_corner_clip(t, q, k);
        if (behind_eye_at(c[k])) {
            return;
        }
    }
    vec2 q0 = to_cells(c[0]), q1 = to_cells(c[1]), q2 = to_cells(c[2]), q3 = to_cells(c[3]);
    float tall = max(distance(q0, q2), distance(q1, q3));
    float wide = max(distance(q0, q1), distance(q2, q3));
    // Rounded up or down by a per-billboard dither, so the cells walked match the quad's area on
    // average (rounded up, small far billboards covered half as much again as drawn ones).
    int rows = min(int(tall + hash_unit(hash_u32(t.hash ^ 0x68e31da4u))), MAX_BILLBOARD_CELLS);
    int cols = min(int(wide + hash_unit(hash_u32(t.hash ^ 0xb5297a4du))), MAX_BILLBOARD_CELLS);
    // The mip level the hardware would pick: texels per pixel along the quad's shorter side.
    float texels = float(textureSize(grass_texture, 0).x);
    float per_pixel = float(frame.instanced_meta.z);
    float level = log2(max(texels * per_pixel / max(min(tall, wide), 1e-3), 1.0));
    vec3 root = billboard_shade(t, q, 0.0);
    vec3 middle = billboard_shade(t, q, 0.5);
    vec3 tip = billboard_shade(t, q, 1.0);
    for (int i = 0; i < rows; i++) {
        float y = (float(i) + 0.5) / float(rows);
        vec3 colour = root * ((2.0 * y - 1.0) * (y - 1.0)) + middle * (4.0 * y * (1.0 - y)) + tip * (y * (2.0 * y - 1.0));
        vec4 left = mix(c[0], c[2], y), right = mix(c[1], c[3], y);
        for (int j = 0; j < cols; j++) {
            float x = (float(j) + 0.5) / float(cols);
            vec4 clip = mix(left, right, x);
            ivec2 cell = ivec2(floor(to_cells(clip)));
            vec4 painted = textureLod(grass_texture, vec2(x, 1.0 - y), level);
            if (billboard_coverage_at(painted.a, level, q.layers) <= cell_threshold(cell)) {
                continue;
            }
            vec3 lit = guard_color(colour * painted_detail(painted)).rgb;
            uint packed = splat_colour(lit);
            uint64_t depth_colour = (uint64_t(floatBitsToUint(clip.z / clip.w)) << 32) | uint64_t(packed);
            splat_cell(cell, depth_colour);
        }
    }
}
