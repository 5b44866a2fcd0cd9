// An instanced blade and its shape (SPEC §7 [F]): instanced.comp generates blades and splats the
// far ones, instanced.vert draws the others; both build the curve here. Needs common.glsl.

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

const uint STIFFNESS_SALT = 0x3c6ef372u; // stream.rs

// The strip level of detail of a blade at `dist` from the eye, with `lod` the distances where
// levels 1, 2 and 3 start (instanced::lod_at).
int strip_level(float dist, vec4 lod) {
    return int(dist >= lod.x) + int(dist >= lod.y) + int(dist >= lod.z);
}

// How far from its root, in heights, a listed blade's stored tip may lie (`pack_facing_tip`):
// `settle` gives the tip before validation, which may lie past the blade's length.
const float LEAN_RANGE = 4.0;

// A listed blade from its 32 bytes (instanced_pass.glsl `store_blade`): root; height and
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

// The 64 bits of `unpack_blade` that hold facing and tip.
uvec2 pack_facing_tip(InstancedBlade blade) {
    vec3 lean = clamp((blade.tip - blade.root) / (LEAN_RANGE * max(blade.height, 1e-6)), -1.0, 1.0);
    uint facing = packHalf2x16(vec2(blade.facing, 0.0)) & 0xffffu;
    return uvec2(facing | (packSnorm2x16(vec2(0.0, lean.x)) & 0xffff0000u), packSnorm2x16(lean.yz));
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

// What a blade's hash alone decides, apart from its size (`instanced_blade_of`), so a blade
// passed on with only its size and hash is made whole again the same (instanced_pass.glsl
// `queued_blade`): where in its cell it grows, its facing, its lean and its outline.
vec2 blade_xz(ivec2 cell, uint h, float spacing) {
    uint h1 = hash_u32(h), h2 = hash_u32(h ^ 0x68e31da4u);
    return (vec2(cell) + vec2(hash_unit(h1), hash_unit(h2))) * spacing;
}

float blade_facing(uint h) {
    return hash_unit(hash_u32(h ^ 0x1b56c4e9u)) * 6.2831855;
}

// The hash a blade's width and lean share.
uint width_lean_hash(uint h) {
    return hash_u32(h ^ 0x7f4a7c15u);
}

// The lean of a blade of kind `species` (the grid's `bend` where the scene lists no kinds), by
// its `width_lean_hash`.
float blade_bend(uint width_lean, uint species, float bend, bool by_species) {
    float kind_bend = by_species && species_count() > 0u ? frame.species[4u * species + 1u].z : bend;
    return kind_bend * (0.5 + hash_unit(width_lean));
}

uint grown_outline(uint h, uint species, bool by_species) {
    return outline_of(species, by_species && seed_head_drawn(h, species));
}

// The blade of grid cell `cell` on a grid of `spacing` (instanced.rs `blade_at`): jittered
// position, clumped height and width (`shape`: height min, max; half-width min, max), facing,
// pitch, bend and wind phase, all from the cell's hash and simplex noise of its position; on
// the ground's height grid, and of no height off it. Uncut: the passes that draw it cut it.
InstancedBlade instanced_blade_of(ivec2 cell, float spacing, float clump_scale, vec4 shape, float bend, uint seed,
                                  bool by_species) {
    uint h = cell_hash(cell, seed);
    uint h3 = hash_u32(h ^ 0xb5297a4du), h5 = width_lean_hash(h);
    vec2 xz = blade_xz(cell, h, spacing);
    // The paint there (read once), and its kind of grass where the scene lists kinds: their
    // shape ranges and lean.
    PaintSample paint = paint_map_or_full(xz);
    uint species = species_drawn(h, paint.species);
    if (by_species && species_count() > 0u) {
        shape = frame.species[4u * species];
    } else if (species_count() > 0u) {
        // A billboard is of a kind too (its colour, by its hash): the tallest kind's
        // billboards stand as tall as the scene's billboards, the others as much shorter as their
        // blades are (so the billboards' bounds hold).
        float tallest = 0.0;
        for (uint k = 0u; k < species_count(); k++) {
            tallest = max(tallest, dot(frame.species[4u * k].xy, vec2(1.0)));
        }
        float kind = dot(frame.species[4u * species].xy, vec2(1.0));
        shape.xy *= kind / max(tallest, 1e-6);
    }
    float y;
    bool on_ground = ground_height(xz, y);
    float clump = 0.5 + 0.5 * simplex2(xz * clump_scale);
    float tall = clamp(clump + 0.25 * (hash_unit(h3) - 0.5), 0.0, 1.0);
    InstancedBlade b;
    vec2 at = frame_xz(xz);
    b.root = vec3(at.x, y, at.y);
    b.facing = blade_facing(h);
    // As the paint says (paint.rs): a blade whose draw falls above the density does not grow.
    vec2 painted = vec2(painted_density(paint, xz), paint.amounts.y);
    b.height = on_ground ? painted_height(h, shape.x + (shape.y - shape.x) * tall, painted) : 0.0;
    b.width = shape.z + (shape.w - shape.z) * (0.5 * tall + 0.5 * hash_unit(h5));
    b.bend = blade_bend(h5, species, bend, by_species);
    b.hash = h;
    b.species = by_species ? species : 0u;
    // A flowering stalk where its kind has them and its hash says, as its Bezier twin is drawn.
    b.outline = grown_outline(h, species, by_species);
    b.tip = b.root;
    return b;
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

// The stiffness of the blade of a cell with hash `hash`, of species `species` (stream.rs
// `blade_of_cell`): the streamed Bezier blade of that cell has it too.
float grid_stiffness(uint hash, uint species) {
    vec2 range = species_count() > 0u ? frame.species[4u * species + 1u].xy : frame.stream_reach.zw;
    return mix(range.x, range.y, hash_unit(hash ^ STIFFNESS_SALT));
}

// Steps `settle` takes toward the wind's part of the rest (the wind's force depends on how the
// blade leans), and the steps toward the curve's length within each.
const int SETTLE_STEPS = 6;
const int CHORD_STEPS = 2;

// Where a blade rooted at `root`, `h` long, its face toward `front`, `k` stiff, leaning `bend`
// at rest, comes to rest in the frame's gravity and wind: the steady state of the Bezier blades'
// physics (physics.wesl `step_blade`). A physics step moves the tip the share k·dt of the way
// to the balance point (where recovery would balance gravity and wind), then validation scales
// the curve about its root to its length; at rest the tip therefore lies on the ray from the
// root to the balance point (on the ground where the balance point is below it), at the one
// distance a step moves it away from and validation brings it back to. That distance is found
// by CHORD_STEPS fixed-point steps, and where the wind depends on the lean, SETTLE_STEPS damped
// steps find the balance point. Returns the tip before the step's validation (which every path
// that draws the blade applies, `listed_shape`), so the curve drawn is the physics' own: on
// the CPU within 0.1 % of the height of the Bezier blade simulated to rest, for heights
// 0.06–1.1, stiffness 14–100, gravity 2–9.8 and winds 0–7 (where six steps of moving the tip
// toward the balance point missed by up to 80 %, a short blade lying flat as a straight line
// where the physics arches it).
vec3 settle(vec3 root, float h, vec3 front, float k, float bend) {
    const vec3 up = vec3(0.0, 1.0, 0.0);
    vec3 rest = root + h * normalize(up + bend * front);
    uint forces = frame.counts.w;
    // Nothing holds a blade up without recovery: it lies down.
    float stiffness = (forces & FORCE_RECOVERY) != 0u ? max(k, 1e-3) : 1e-3;
    float share = min(stiffness * frame.simulation.x, 1.0);
    vec3 wind = (forces & FORCE_WIND) != 0u ? wind_at(root, frame.camera_position.w) : vec3(0.0);
    vec3 wind_way = normalize_or_zero(wind);
    // Gravity depends on the tip only where it pulls toward a point: else found once.
    bool gravity = (forces & FORCE_GRAVITY) != 0u;
    bool toward_point = frame.simulation.z != 0.0;
    vec3 steady_gravity = gravity && !toward_point ? gravity_force(root, front) : vec3(0.0);
    vec3 tip = rest; // validated: where the forces act
    vec3 way = up;
    float balance_reach = h, chord = h;
    for (int i = 0; i < SETTLE_STEPS; i++) {
        vec3 force = wind_force_along(wind, wind_way, root, tip, up, h) + steady_gravity;
        if (gravity && toward_point) {
            force += gravity_force(tip, front);
        }
        vec3 balance = rest + force / stiffness;
        balance -= up * min(dot(up, balance - root), 0.0);
        balance_reach = length(balance - root);
        way = balance_reach > 1e-9 ? (balance - root) / balance_reach : up;
        for (int j = 0; j < CHORD_STEPS; j++) {
            float reach = mix(chord, balance_reach, share);
            vec3 guide;
            chord = reach * h / max(guided_length(root, up, h, root + way * reach, guide), 1e-12);
        }
        // Damped: a wind that tips the blade further as it leans would swing it past its rest.
        tip = mix(tip, root + way * chord, 0.7);
    }
    // Where the step moves it, within the stored range: validation scales the curve to its
    // length, so a tip farther out along the ray draws the same blade once it leans past level
    // (the guide's height then grows with the lean).
    return root + way * min(mix(chord, balance_reach, share), LEAN_RANGE * h);
}

// How much of blade `b` stands at `dist`: all of it, sinking into the ground over the last 15 %
// before the cut-off so the field has no hard edge.
float standing_height(InstancedBlade b, float dist) {
    float radius = frame.instanced_grid.y;
    return b.height * (1.0 - smoothstep(0.85 * radius, radius, dist));
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

// Blade `b` posed `dist` from the eye: its standing height, and its tip where it settles as a
// Bezier blade of its height and stiffness settles in the frame's gravity and wind (`settle`),
// laid down where the trample map says it was walked on.
InstancedBlade posed(InstancedBlade b, float dist) {
    b.height = standing_height(b, dist);
    vec3 front = normalize_or_zero(cross(vec3(0.0, 1.0, 0.0), blade_across(b.facing)));
    b.tip = settle(b.root, max(b.height, 1e-4), front, grid_stiffness(b.hash, b.species), b.bend);
    // Trampled (trample.rs): laid along the push, down to lying flat at full strength.
    vec2 push = trample_push(b.root.xz);
    float flat_by = min(length(push), 1.0);
    if (flat_by > 0.0) {
        vec3 along = vec3(push.x, 0.0, push.y) / length(push);
        b.tip = mix(b.tip, b.root + b.height * (along + vec3(0.0, 0.08, 0.0)), flat_by);
    }
    return b;
}

// A posed blade's shape: the curve validation makes of its root, height and tip. Every path
// builds it so — the listed blades from the tip they were stored with, the splatted ones, the
// Bezier blades easing into their twins — so they draw one curve.
Shape listed_shape(InstancedBlade b, float dist) {
    Shape s = shape_start(b, dist);
    validate_tip(b.root, vec3(0.0, 1.0, 0.0), max(b.height, 1e-4), b.tip, s.p1, s.p2);
    return s;
}

// The blade `b`, `dist` from the eye, as the frame shows it: posed, sinking at the cut-off.
Shape instanced_shape(InstancedBlade b, float dist) {
    return listed_shape(posed(b, dist), dist);
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
