// The drawn Bezier blade's surface (SPEC §6), shared by every route that draws it (blade.tese's
// patches, blade_strip.vert's strips): De Casteljau along the height, the blade shape across the
// width, the 3D ridge, and the minimum-width fix that keeps far blades from aliasing into holes.
// Needs common.glsl.

vec2 to_pixels(vec3 p) {
    vec4 clip = frame.view_proj * vec4(p, 1.0);
    return clip.xy / max(clip.w, 1e-4) * 0.5 * frame.viewport.xy;
}

// The point of blade `b`, drawn with outline `outline` (common.glsl `blade_outline`: a leaf of
// the scene's shape or a flowering stalk), at (u across, v from root to tip) and the blade's
// normal there (rounded across the width).
vec3 blade_point(Blade b, uint outline, float u, float v, out vec3 n) {
    vec3 up = b.up.xyz;
    float w = b.v2.w;
    vec3 t1 = width_direction(up, b.v0.w);

    vec3 a = mix(b.v0.xyz, b.v1.xyz, v);
    vec3 bb = mix(b.v1.xyz, b.v2.xyz, v);
    vec3 c = mix(a, bb, v);
    vec3 t0 = bb - a;
    t0 = dot(t0, t0) > 1e-12 ? normalize(t0) : up;
    n = normalize(cross(t0, t1));
    vec3 c0 = c - w * t1;
    vec3 c1 = c + w * t1;

    // Streamed: the blade eases with the pose into the twin's shape (the same silhouette, no
    // ridge), all the way at the hand-over.
    float like = twin_ease(b.v0.xyz);
    float tau = blade_shape_of(outline, u, v);
    float min_px = frame.blade_style.w;
    if (min_px > 0.0) {
        float px = length(to_pixels(c1) - to_pixels(c0));
        // The twin keeps its coverage by widening instead (outline.wesl `widened`).
        tau = mix(tau, u, clamp(1.0 - px / min_px, 0.0, 1.0) * (1.0 - like));
    }
    vec3 p = mix(c0, c1, tau);
    if (blade_ridge()) {
        // A flowering stalk folds as little as it is wide.
        float fold = (outline >> 8u) != 0u ? SEED_STALK : 1.0;
        p += n * (w * fold) * (0.5 - abs(u - 0.5)) * (1.0 - v) * (1.0 - like);
    }
    n = rounded_normal(n, t1, u);
    return p;
}
