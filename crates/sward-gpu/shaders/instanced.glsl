// A listed instanced blade and its shape (SPEC §7 [F]), as instanced.vert draws it: the blades
// generate_grid.wesl lists (posed), their curve and their strip's vertices. Needs common.glsl.

struct InstancedBlade {
    vec3 root;
    float facing;
    float height;
    float width;
    float bend;
    uint hash;
    // Its kind of grass (species.rs; 0 where the scene lists none).
    uint species;
    // How it is drawn (common.glsl `blade_outline`): a leaf, or a flowering stalk.
    uint outline;
    // Where its tip stands this frame (`posed`); the root until it is posed.
    vec3 tip;
};

// How far from its root, in heights, a listed blade's stored tip may lie (`pack_facing_tip`):
// `settle` gives the tip before validation, which may lie past the blade's length.
const float LEAN_RANGE = 4.0;

// A listed blade from its 32 bytes (generated.wesl `store_blade`): root; height and
// half-width (halves); facing (a half, where billboard.glsl reads it too) and the tip, posed,
// as three 16-bit fractions of LEAN_RANGE heights from the root; the hash; its outline.
InstancedBlade unpack_blade(uvec4 a, uvec4 b) {
    InstancedBlade blade;
    blade.root = uintBitsToFloat(a.xyz);
    vec2 size = unpackHalf2x16(a.w);
    blade.height = size.x;
    blade.width = size.y;
    blade.facing = unpackHalf2x16(b.x).x;
    blade.bend = 0.0;
    blade.hash = b.z;
    blade.outline = b.w;
    // Not kept in the list: posed blades need it no more, and shading draws it from the hash.
    blade.species = 0u;
    vec3 lean = vec3(unpackSnorm2x16(b.x).y, unpackSnorm2x16(b.y)) * LEAN_RANGE;
    blade.tip = blade.root + lean * blade.height;
    return blade;
}

// A blade as a quadratic curve p0 → p2 (guide p1) with a half-width narrowing to its tip.
struct Shape {
    vec3 p0, p1, p2;
    vec3 across;
    float width;
    uint outline; // common.glsl `blade_outline`: a leaf of the scene's shape or a flowering stalk
};

vec3 curve(Shape s, float t) {
    return mix(mix(s.p0, s.p1, t), mix(s.p1, s.p2, t), t);
}

// Edge point at height t on side `side` (-1, 0 tip, 1) in the scene's blade silhouette, as the
// Bezier blades have it (common.glsl `blade_shape_of`: τ across the width, 0 at side -1).
vec3 edge(Shape s, float t, float side) {
    float tau = blade_shape_of(s.outline, side * 0.5 + 0.5, t);
    return curve(s, t) + s.across * (s.width * (2.0 * tau - 1.0));
}

// The unit direction across the face of a blade facing `facing` (as common.glsl
// `width_direction` gives a Bezier blade of that orientation on flat ground).
vec3 blade_across(float facing) {
    return vec3(cos(facing), 0.0, -sin(facing));
}

// The start of blade `b`'s shape `dist` from the eye: root, width across its face (as a Bezier
// blade of facing `b.facing` has it), widened with distance so coarse levels keep their coverage.
Shape shape_start(InstancedBlade b, float dist) {
    float radius = frame.instanced_grid.y;
    Shape s;
    s.across = blade_across(b.facing);
    s.width = b.width * (1.0 + 1.5 * smoothstep(0.05 * radius, radius, dist));
    s.p0 = b.root;
    s.outline = b.outline;
    return s;
}

// A posed blade's shape: the curve validation makes of its root, height and tip. Every path
// builds it so — the listed blades from the tip they were stored with, the splatted ones, the
// Bezier blades easing into their twins — so they draw one curve.
Shape listed_shape(InstancedBlade b, float dist) {
    Shape s = shape_start(b, dist);
    validate_tip(b.root, vec3(0.0, 1.0, 0.0), max(b.height, 1e-4), b.tip, s.p1, s.p2);
    return s;
}

// Vertex `v` of blade shape `s`'s strip at level `lod` (2·(8 >> lod) + 1 vertices: row by row
// its left and right edge, then the tip), `dist` from the eye: its position, its normal (rounded
// across the blade) and (u across, v from root to tip). Near a level boundary the odd rows
// slide onto the coarser strip's edges (geomorphing), so crossing a boundary changes nothing on
// screen. instanced.vert draws these vertices; instanced_raster.wesl rasterizes them by compute.
vec3 strip_vertex(Shape s, float dist, uint lod, uint v, out vec3 normal, out vec2 uv) {
    uint segments = 8u >> lod;
    uint row = min(v / 2u, segments);
    float side = v == 2u * segments ? 0.0 : ((v & 1u) == 0u ? -1.0 : 1.0);
    float t = float(row) / float(segments);
    vec3 p = edge(s, t, side);
    float boundary = lod < 3u ? frame.instanced_lod[lod] : 0.0;
    // Only near a boundary (a whole blade's vertices are near one or not): elsewhere the chord
    // would be mixed in by nothing.
    if (lod < 3u && (row & 1u) == 1u && dist > 0.8 * boundary) {
        float morph = smoothstep(0.8 * boundary, boundary, dist);
        float dt = 1.0 / float(segments);
        vec3 chord = 0.5 * (edge(s, t - dt, side) + edge(s, t + dt, side));
        p = mix(p, chord, morph);
    }
    vec3 tangent = normalize_or_zero(mix(s.p1 - s.p0, s.p2 - s.p1, t));
    normal = rounded_normal(normalize_or_zero(cross(tangent, s.across)), s.across, side * 0.5 + 0.5);
    uv = vec2(side * 0.5 + 0.5, t);
    return p;
}
