// An instanced blade and its shape (SPEC §7 [F]): instanced.comp generates blades and splats the
// far ones, instanced.vert draws the others; both build the curve here. Needs common.glsl.

struct InstancedBlade {
    vec3 root;
    float facing;
    float height;
    float width;
    float pitch;
    float bend;
    float phase;
    uint hash;
};

// The strip level of detail of a blade at `dist` from the eye, with `lod` the distances where
// levels 1, 2 and 3 start (instanced::lod_at).
int strip_level(float dist, vec4 lod) {
    return int(dist >= lod.x) + int(dist >= lod.y) + int(dist >= lod.z);
}

// A listed blade from its 32 bytes (instanced_pass.glsl `store_blade`).
InstancedBlade unpack_blade(uvec4 a, uvec4 b) {
    InstancedBlade blade;
    blade.root = uintBitsToFloat(a.xyz);
    vec2 size = unpackHalf2x16(a.w);
    vec2 facing_pitch = unpackHalf2x16(b.x);
    vec2 bend_phase = unpackHalf2x16(b.y);
    blade.height = size.x;
    blade.width = size.y;
    blade.facing = facing_pitch.x;
    blade.pitch = facing_pitch.y;
    blade.bend = bend_phase.x;
    blade.phase = bend_phase.y;
    blade.hash = b.z;
    return blade;
}

// The height of the ground grid's triangles at world ground point xz (mesh.rs
// `HeightGrid::height_at`); false off it.
bool ground_height(vec2 xz, out float height) {
    uvec2 n = frame.instanced_ground_cells.xy;
    height = 0.0;
    if (n.x == 0u) {
        return true;
    }
    vec2 lo = frame.instanced_ground.xy;
    vec2 hi = frame.instanced_ground.zw;
    vec2 cells = vec2(n - 1u);
    vec2 q = (xz - lo) / (hi - lo) * cells;
    if (any(lessThan(q, vec2(0.0))) || any(greaterThan(q, cells))) {
        return false;
    }
    vec2 cell = min(floor(q), cells - 1.0);
    vec2 f = q - cell;
    uint i = uint(cell.x), j = uint(cell.y);
    float h00 = ground_vertices[j * n.x + i].position.y;
    float h10 = ground_vertices[j * n.x + i + 1u].position.y;
    float h01 = ground_vertices[(j + 1u) * n.x + i].position.y;
    float h11 = ground_vertices[(j + 1u) * n.x + i + 1u].position.y;
    height = f.x + f.y <= 1.0 ? h00 + f.x * (h10 - h00) + f.y * (h01 - h00)
                              : h11 + (1.0 - f.x) * (h01 - h11) + (1.0 - f.y) * (h10 - h11);
    return true;
}

// The blade of grid cell `cell` on a grid of `spacing` (instanced.rs `blade_at`): jittered
// position, clumped height and width (`shape`: height min, max; half-width min, max), facing,
// pitch, bend and wind phase, all from the cell's hash and simplex noise of its position; on
// the ground's height grid, and of no height off it. Uncut: the passes that draw it cut it.
InstancedBlade instanced_blade_of(ivec2 cell, float spacing, float clump_scale, vec4 shape, float bend, uint seed) {
    uint h = cell_hash(cell, seed);
    uint h1 = hash_u32(h), h2 = hash_u32(h ^ 0x68e31da4u), h3 = hash_u32(h ^ 0xb5297a4du);
    uint h4 = hash_u32(h ^ 0x1b56c4e9u), h5 = hash_u32(h ^ 0x7f4a7c15u);
    vec2 xz = (vec2(cell) + vec2(hash_unit(h1), hash_unit(h2))) * spacing;
    float y;
    bool on_ground = ground_height(xz, y);
    float clump = 0.5 + 0.5 * simplex2(xz * clump_scale);
    float tall = clamp(clump + 0.25 * (hash_unit(h3) - 0.5), 0.0, 1.0);
    InstancedBlade b;
    vec2 at = frame_xz(xz);
    b.root = vec3(at.x, y, at.y);
    b.facing = hash_unit(h4) * 6.2831855;
    b.height = on_ground ? shape.x + (shape.y - shape.x) * tall : 0.0;
    b.width = shape.z + (shape.w - shape.z) * (0.5 * tall + 0.5 * hash_unit(h5));
    b.pitch = 0.25 * (hash_unit(h3) - 0.5);
    b.bend = bend * (0.5 + hash_unit(h5));
    b.phase = hash_unit(h2 ^ h4) * 6.2831855;
    b.hash = h;
    return b;
}

// The instanced grass's blade of grid cell `cell` (the streamed field's twin of a Bezier blade).
InstancedBlade instanced_twin(ivec2 cell) {
    return instanced_blade_of(cell, frame.instanced_grid.x, frame.instanced_grid.w, frame.instanced_shape,
                              frame.instanced_motion.x, frame.instanced_meta.x);
}

// A blade as a quadratic curve p0 → p2 (guide p1) with a half-width narrowing to its tip.
struct Shape {
    vec3 p0, p1, p2;
    vec3 across;
    float width;
};

vec3 curve(Shape s, float t) {
    return mix(mix(s.p0, s.p1, t), mix(s.p1, s.p2, t), t);
}

// Edge point at height t on side `side` (-1, 0 tip, 1): the blade narrows to its tip.
vec3 edge(Shape s, float t, float side) {
    return curve(s, t) + s.across * (side * s.width * (1.0 - t));
}

// The blade `b`, `dist` from the eye, as the frame shows it: leaning by its pitch and bend,
// swaying with the wind by its phase (the tip moves, the root does not), widened with distance
// so coarse levels keep their coverage, and sinking into the ground over the last 15 % before
// the cut-off so the field has no hard edge.
Shape instanced_shape(InstancedBlade b, float dist) {
    float radius = frame.instanced_grid.y;
    float height = b.height * (1.0 - smoothstep(0.85 * radius, radius, dist));
    float widen = 1.0 + 1.5 * smoothstep(0.05 * radius, radius, dist);
    vec3 front = vec3(sin(b.facing), 0.0, cos(b.facing));
    Shape s;
    s.across = vec3(front.z, 0.0, -front.x);
    s.width = b.width * widen;
    s.p0 = b.root;
    s.p1 = b.root + height * (vec3(0.0, cos(b.pitch), 0.0) + front * sin(b.pitch));
    float time = frame.camera_position.w;
    vec3 wind = frame.modes.y > 0u ? frame.winds[0].xyz : vec3(1.0, 0.0, 0.0);
    vec2 world = world_xz(b.root.xz);
    float sway = frame.instanced_motion.y * sin(b.phase + 1.7 * time + 0.35 * (world.x + world.y));
    s.p2 = s.p1 + height * (front * b.bend + wind * sway - vec3(0.0, 0.5 * b.bend, 0.0));
    // Trampled (trample.rs): laid along the push, down to lying flat at full strength.
    vec2 push = trample_push(b.root.xz);
    float flat_by = min(length(push), 1.0);
    if (flat_by > 0.0) {
        vec3 along = vec3(push.x, 0.0, push.y) / length(push);
        s.p1 = mix(s.p1, b.root + height * (0.55 * along + vec3(0.0, 0.2, 0.0)), flat_by);
        s.p2 = mix(s.p2, b.root + height * (along + vec3(0.0, 0.08, 0.0)), flat_by);
    }
    return s;
}

// The streamed field's twin of a Bezier blade as the instanced grass draws it `dist` from the
// eye: no taller than the trample map's cut there (instanced_pass.glsl `blade_at` cuts it so).
Shape twin_shape(InstancedBlade twin, float dist) {
    twin.height = min(twin.height, trample_cut(twin.root.xz));
    return instanced_shape(twin, dist);
}

// Vertex `v` of blade shape `s`'s strip at level `lod` (2·(8 >> lod) + 1 vertices: row by row
// its left and right edge, then the tip), `dist` from the eye: its position, its normal (rounded
// across the blade) and (u across, v from root to tip). Near a level boundary the odd rows
// slide onto the coarser strip's edges (geomorphing), so crossing a boundary changes nothing on
// screen. instanced.vert draws these vertices; instanced_pass.glsl rasterizes them by compute.
vec3 strip_vertex(Shape s, float dist, uint lod, uint v, out vec3 normal, out vec2 uv) {
    uint segments = 8u >> lod;
    uint row = min(v / 2u, segments);
    float side = v == 2u * segments ? 0.0 : ((v & 1u) == 0u ? -1.0 : 1.0);
    float t = float(row) / float(segments);
    vec3 p = edge(s, t, side);
    if (lod < 3u && (row & 1u) == 1u) {
        float boundary = frame.instanced_lod[lod];
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
