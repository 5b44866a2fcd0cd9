// Splatting (SPEC §10): a blade rasterized by compute into the splat target (splat.rs) instead of
// by the hardware. The blade is walked from root to tip one splat cell at a time and its
// projected width covered at each step; each cell keeps the nearest (depth, colour) by a 64-bit
// atomicMin, and splat.frag resolves the cells into the frame. Used by instanced.comp (the
// instanced grass's far blades); the passes written in WGSL have the same in splat.wesl.
// Needs common.glsl, blade_surface.glsl and shading.glsl; the includer enables the int64
// extensions and defines SWARD_SPLAT_WRITE before common.glsl.

// The splat target as the splatting passes write it: per cell, view depth bits above colour.
layout(set = 0, binding = BINDING_SPLAT_CELLS, std430) buffer SplatWrite { uint64_t splat_write[]; };
// The same cells as 32-bit words, cell k's depth bits at 2k + 1 (as splat.frag's `splat_pixels`
// reads them), for the plain reads that need only a cell's depth: a 32-bit read and compare
// where a 64-bit one cost the instanced grass's generating 0.15 ms more of 6.65 at 2^26
// candidates on the H200 (measured on 1396952's walk).
layout(set = 0, binding = BINDING_SPLAT_CELLS, std430) buffer SplatDepths { uint splat_depth_words[]; };

// The depth bits splat cell `at` holds now.
uint splat_depth_at(uint at) {
    return splat_depth_words[2u * at + 1u];
}

// A blade to splat: a quadratic centre curve p0 → p2 (guide p1), the unit width direction and the
// half-width at the root; `shape` is the blade shape (blade_surface.glsl) that narrows it toward
// the tip; `blade` picks its colour variation.
struct SplatBlade {
    vec3 p0, p1, p2;
    vec3 across;
    float width;
    uint shape;
    uint blade;
};

vec3 splat_curve(SplatBlade s, float t) {
    return mix(mix(s.p0, s.p1, t), mix(s.p1, s.p2, t), t);
}

// Splat cells: a pixel on a 1-sample target, a quarter of it (one per sample) on a 4× one.
vec2 to_cells(vec4 clip) {
    return (clip.xy / clip.w * 0.5 + 0.5) * frame.viewport.xy * float(frame.instanced_meta.z);
}

// The splat target in cells.
ivec2 splat_cells_size() {
    return ivec2(frame.viewport.xy) * int(frame.instanced_meta.z);
}

// A colour as a splat cell holds it, below its depth: gamma-2 RGB8 (splat.frag squares it back).
uint splat_colour(vec3 colour) {
    return packUnorm4x8(vec4(sqrt(clamp(colour, 0.0, 1.0)), 1.0));
}

// Keep (depth, colour) in splat cell `px`, if it is on the target and the nearest there so far.
// The plain read first skips most atomics: blades are splatted roughly nearest first, so a far
// blade usually finds a nearer one there. It reads the depth alone; at an equal depth the atomic
// decides by colour, as it always did, so the cells are the same. A cell off the target takes no
// branch of its own (one unsigned compare per axis finds it: a cell left of or above the target
// wraps past its size); it reads cell 0 and writes nothing. On the H200 at 2^26 candidates the
// instanced grass's generating took 6.89 ms returning early for it, 6.76 offering the nearest
// edge cell the farthest value, 6.58 this way; offering cell 0 the farthest value took 44 ms,
// every atomic of the frame's off-target cells on one address where the sky leaves it empty.
void splat_cell(ivec2 px, uint64_t depth_colour) {
    ivec2 size = splat_cells_size();
    bool on_target = all(lessThan(uvec2(px), uvec2(size)));
    uint at = on_target ? uint(px.y * size.x + px.x) : 0u;
    uint held = splat_depth_at(at);
    if (on_target && uint(depth_colour >> 32) <= held) {
        atomicMin(splat_write[at], depth_colour);
    }
}

// What a splatted blade's shading takes once per blade rather than at each point it is shaded
// at (a blade a few cells across shows no change of them along it): its look (common.glsl
// `blade_look`) at its root, as the drawn blades find it; its colour variation and its share of
// sunlight at its middle.
struct SplatLight {
    uvec2 look;
    vec3 vary;
    float sunlit;
};

SplatLight splat_light_of(SplatBlade s) {
    vec3 middle = splat_curve(s, 0.5);
    uvec2 look = blade_look(s.blade, world_xz(s.p0.xz));
    return SplatLight(look, albedo_variation(middle, s.blade, look), sunlight(middle));
}

// The blade's shaded colour at height t along it (u = 0.3: off the midrib groove, which a blade a
// few cells wide cannot show).
vec3 splat_shade(SplatBlade s, SplatLight light, float t) {
    vec3 tangent = mix(s.p1 - s.p0, s.p2 - s.p1, t);
    vec3 normal = cross(tangent, s.across);
    return shade_blade_lit(normal, splat_curve(s, t), vec2(0.3, t), light.look, light.vary, light.sunlit);
}

// Splat blade `s`, at most `max_steps` cells along and `max_across` cells across. A splatted blade
// is far enough that its depth hardly changes along it, so it is walked on the screen: its
// centre curve and depth as the quadratic through its projected root, middle and tip (exact
// there), its width's direction on the screen linear from root to tip. A step is then a few
// multiply-adds, no division or square root: on the H200 at 2^26 candidates the walk cost
// 0.28 ms less than stepping the curve in clip space and dividing twice a step, for pictures
// that differ by 0.02 of 255 on average. Shading runs at root, middle and tip and is
// interpolated in the cells' gamma-2 colour space (0.18 ms less than a square root per channel
// a step; 0.2 of 255 darker on average where blades are splatted). The step loop is most of a
// splatting pass.
// A blade reaching behind the eye is not splatted.
void splat_blade(SplatBlade s, int max_steps, int max_across) {
    vec4 c0 = frame.view_proj * vec4(s.p0, 1.0);
    vec4 c1 = frame.view_proj * vec4(s.p1, 1.0);
    vec4 c2 = frame.view_proj * vec4(s.p2, 1.0);
    vec4 across = frame.view_proj * vec4(s.across * s.width, 0.0);
    if (min(c0.w, min(c1.w, c2.w)) <= 1e-3) {
        return;
    }
    vec2 q0 = to_cells(c0), q1 = to_cells(c1), q2 = to_cells(c2);
    // The curve's screen length, between its chord and its control polygon: one step per cell,
    // each at the middle of its stretch, so steps do not pile onto the same cells.
    float reach = 0.5 * (distance(q0, q2) + distance(q0, q1) + distance(q1, q2));
    int steps = clamp(int(round(reach)), 1, max_steps);
    // colour(t) = root + t (colour_b + t colour_a) through root, middle and tip, in gamma 2.
    SplatLight light = splat_light_of(s);
    vec3 root = sqrt(clamp(splat_shade(s, light, 0.0), 0.0, 1.0));
    vec3 middle = sqrt(clamp(splat_shade(s, light, 0.5), 0.0, 1.0));
    vec3 tip = sqrt(clamp(splat_shade(s, light, 1.0), 0.0, 1.0));
    vec3 colour_b = 4.0 * middle - 3.0 * root - tip, colour_a = 2.0 * (root + tip) - 4.0 * middle;
    // The centre curve on the screen with its depth: e(t) = e0 + t (eb + t ea), through the
    // projected root, middle (the curve's own, not p1) and tip.
    vec4 c_middle = 0.25 * (c0 + c2) + 0.5 * c1;
    vec3 e0 = vec3(q0, c0.z / c0.w);
    vec3 e1 = vec3(to_cells(c_middle), c_middle.z / c_middle.w);
    vec3 e2 = vec3(q2, c2.z / c2.w);
    vec3 eb = 4.0 * e1 - 3.0 * e0 - e2, ea = 2.0 * (e0 + e2) - 4.0 * e1;
    // The width on the screen (root to its edge, in cells) at root and tip, and its length.
    vec2 width_root = to_cells(c0 + across) - q0;
    vec2 width_tip = to_cells(c2 + across) - q2;
    float cells_root = 2.0 * length(width_root), cells_tip = 2.0 * length(width_tip);
    float dt = 1.0 / float(steps);
    // Cells across: the projected width rounded up or down by a dither that runs along the blade
    // from a per-blade phase by the golden ratio (evenly spread), so the cells a blade covers
    // match its area on average (a sub-cell tip covers some steps only).
    float dither = hash_unit(s.blade);
    for (int i = 0; i < steps; i++) {
        float t = (float(i) + 0.5) * dt;
        vec3 e = e0 + t * (eb + t * ea);
        vec2 width = mix(width_root, width_tip, t);
        // The blade shape's edges at this height: u = 0 and u = 1 map to τ0 and τ1 across the
        // width (p = c + w (2τ - 1) across): the middle between them, and half the span.
        vec2 span = outline_span(s.shape, t);
        vec2 centre = e.xy + width * (span.x + span.y - 1.0);
        vec2 half_across = width * (span.y - span.x);
        dither = fract(dither + 0.618034);
        int cells = min(int(mix(cells_root, cells_tip, t) * (span.y - span.x) + dither), max_across);
        if (cells <= 0) {
            continue;
        }
        vec3 colour = root + t * (colour_b + t * colour_a);
        uint packed = packUnorm4x8(vec4(colour, 1.0));
        uint64_t depth_colour = (uint64_t(floatBitsToUint(e.z)) << 32) | uint64_t(packed);
        // The step's cells at u = (j + 0.5) / cells · 2 - 1 across: the first written by every
        // lane at once, then the rest. The 32 lanes of a subgroup walk together, and a far blade
        // is one cell wide at some steps and two at others (the dither): a step of one cell
        // taken apart from the loop ran as a third pass of the lanes beside the two of a
        // two-cell step (on the H200 at 2^26 candidates 0.37 ms more of the instanced grass's
        // generating; the cells the same, but for the few that float rounding moves by one).
        // Walking a blade wholly on the target without the bounds test at each cell saved the
        // instanced grass 0.4 ms more at 2^26, but cost the Bezier blades' splats 0.28 ms at
        // 2^20 and, in the instanced pass alone, the landscape 2^20's generating 0.42 ms
        // (BENCHMARKS.md, the regression set): not done.
        float per_cell = 1.0 / float(cells);
        vec2 first = centre + half_across * (per_cell - 1.0);
        vec2 stride = (2.0 * per_cell) * half_across;
        splat_cell(ivec2(floor(first)), depth_colour);
        for (int j = 1; j < cells; j++) {
            splat_cell(ivec2(floor(first + stride * float(j))), depth_colour);
        }
    }
}
