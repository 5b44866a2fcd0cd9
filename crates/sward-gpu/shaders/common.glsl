// Shared by every sward shader: the struct layouts of sward-core's `gpu.rs` and `blade.rs`, and the
// maths that sward-core's CPU reference mirrors (hash, noise, tangent frame, wind, culling, LOD).

// Every named number the shaders share with the host (flags, codes, command slots, bindings,
// specialisation constant ids) and the frame block's members: written by sward-core declared.rs.
#include "declared.glsl"

struct Blade {
    vec4 v0; // xyz root, w orientation
    vec4 v1; // xyz guide, w height
    vec4 v2; // xyz tip guide, w width
    vec4 up; // xyz surface normal, w stiffness
};

// The frame's uniforms (sward-core gpu.rs `FrameUniforms`, whose members say what each means).
layout(set = 0, binding = BINDING_FRAME, std140) uniform Frame {
    FRAME_MEMBERS
} frame;

// The drawing stages only read the frame's buffers (the core's WGSL passes write them).
layout(set = 0, binding = BINDING_BLADES, std430) readonly buffer Blades { Blade blades[]; };
// Only for the bench's comparison variant (COPY_BLADES): whole culled blades instead of indices.
layout(set = 0, binding = BINDING_CULLED, std430) readonly buffer Culled { Blade culled[]; };
layout(constant_id = CONSTANT_COPY_BLADES) const bool COPY_BLADES = false;
// The visible blade ids in draw order: nearest distance bucket first (order.wesl `order_blades`).
layout(set = 0, binding = BINDING_ORDERED, std430) readonly buffer Ordered { uint ordered[]; };

// The sun's shadow map.
layout(set = 0, binding = BINDING_SHADOW_MAP) uniform sampler2DShadow shadow_map;

// The Bezier blades' silhouette (BLADE_*) and whether they have a ridge, the lighting model
// (SHADING_*).
uint blade_shape_code() {
    return uint(frame.blade_style.x);
}

// τ(u, v): where across the width (0 one edge, 1 the other) the point u of height v lies, for
// blade shape `shape` (look.rs BladeShape).
// A flowering stalk's outline (species.rs `SeedHeads`): a thin stalk, then over the top `head`
// of the blade a slim spindle (a seed head is narrower than a leaf), narrowing to the tip.
const float SEED_STALK = 0.14; // the stalk's width, of the leaf's
const float SEED_HEAD_WIDTH = 0.5; // the head's widest, of the leaf's
float seed_head_shape(float head, float u, float v) {
    float s = clamp((v - (1.0 - head)) / head, 0.0, 1.0);
    float spindle = v > 1.0 - head ? SEED_HEAD_WIDTH * pow(sin(3.14159265 * pow(s, 0.8)), 0.6)
                                   : 0.0;
    return 0.5 + (u - 0.5) * max(SEED_STALK * (1.0 - s), spindle);
}

// τ(u, v) of blade outline `shape` (`blade_outline`): the scene's blade shape in the low byte,
// above it a flowering stalk's head length in 255ths (0: a leaf).
float blade_shape_of(uint shape, float u, float v) {
    uint head = shape >> 8u;
    if (head != 0u) return seed_head_shape(float(head) / 255.0, u, v);
    if (shape == BLADE_QUAD) return u;
    if (shape == BLADE_TRIANGLE) return u + 0.5 * v - u * v;
    if (shape == BLADE_QUADRATIC) return u - u * v * v;
    float tip = frame.blade_style.y; // BLADE_TRIANGLE_TIP
    return 0.5 + (u - 0.5) * (1.0 - max(v - tip, 0.0) / (1.0 - tip));
}

bool blade_ridge() {
    return (frame.modes.w & DRAW_BLADE_RIDGE) != 0u;
}

// ------------------------------------------------- the frame origin (stream.rs `frame_origin`)

// Every position the frame holds (blades, eye, colliders, matrices) is world less frame.origin,
// so numbers near the eye stay fine however far the world goes. What depends on where in the
// world a point is — grid cells and their hashes, noise, wind — asks for its world place.
vec2 world_xz(vec2 xz) {
    return xz + frame.origin.xy;
}

// The blade a draw refers to: by index into the field, or the copy the cull pass made.
Blade drawn_blade(uint id) {
    return COPY_BLADES ? culled[id] : blades[id];
}

// ------------------------------------------------------------ hashing and noise (rng.rs, wind.rs)

uint hash_u32(uint x) {
    uint state = x * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

float hash_unit(uint x) {
    return float(hash_u32(x) >> 8u) * (1.0 / 16777216.0);
}

// The hash of grid cell `cell` of a grid seeded `seed` (instanced.rs `cell_hash`).
uint cell_hash(ivec2 cell, uint seed) {
    return hash_u32((uint(cell.x) * 73856093u) ^ hash_u32(uint(cell.y) ^ (seed * 19349663u)));
}

// ---------------------------------------------------------------- the streamed field (stream.rs)

// Whether the Bezier field is a window of tiles that follows the eye.
bool streamed() {
    return frame.stream.x > 0u;
}

// The world tile window slot `slot` holds (stream.rs `StreamWindow::tile_in`).
ivec2 stream_tile(uint slot) {
    int n = int(frame.stream.x);
    ivec2 base = ivec2(frame.stream.zw);
    ivec2 s = ivec2(int(slot % frame.stream.x), int(slot / frame.stream.x));
    return base + (((s - base) % n) + n) % n;
}

// The grid cell of blade `index` (row by row) of world tile `tile` (stream.rs
// `StreamWindow::cell_of`).
ivec2 tile_cell(ivec2 tile, uint index) {
    uint cells = frame.stream.y;
    return tile * int(cells) + ivec2(int(index % cells), int(index / cells));
}

// The grid cell of streamed blade `id`.
ivec2 stream_cell(uint id) {
    uint blades = frame.stream.y * frame.stream.y;
    return tile_cell(stream_tile(id / blades), id % blades);
}

// How far a streamed Bezier blade rooted at `root` has eased into its instanced twin: 0 before the
// hand-over band, 1 at the hand-over (stream.rs; twin.wesl `ease_into_twin` eases its pose by it,
// blade_surface.glsl its silhouette). 0 where the field does not stream or has no twins.
float twin_ease(vec3 root) {
    float start = frame.stream_reach.y;
    float end = frame.stream_reach.x;
    if (!streamed() || start >= end) {
        return 0.0;
    }
    return smoothstep(start, end, distance(root, frame.camera_position.xyz));
}

// What a Bezier blade's colour varies by (shading.glsl `blade_albedo`): its id, or where the
// field streams its cell's hash, as the instanced blade of that cell is varied.
uint blade_colour_key(uint id) {
    return streamed() ? cell_hash(stream_cell(id), frame.instanced_meta.x) : id;
}

float noise_corner(ivec2 cell) {
    return float(hash_u32(uint(cell.x) + hash_u32(uint(cell.y))) >> 8u) * (1.0 / 16777216.0);
}

float value_noise(vec2 q) {
    vec2 cell = floor(q);
    vec2 f = q - cell;
    ivec2 i = ivec2(cell);
    vec2 u = f * f * (vec2(3.0) - 2.0 * f);
    float bottom = noise_corner(i) + (noise_corner(i + ivec2(1, 0)) - noise_corner(i)) * u.x;
    float top_left = noise_corner(i + ivec2(0, 1));
    float top = top_left + (noise_corner(i + ivec2(1, 1)) - top_left) * u.x;
    return bottom + (top - bottom) * u.y;
}

// 2D simplex noise in [-1, 1] with hashed gradients (instanced.rs `simplex2`).
float simplex_corner(vec2 c, vec2 x) {
    float t = 0.5 - dot(x, x);
    if (t <= 0.0) {
        return 0.0;
    }
    uint h = hash_u32(uint(int(c.x)) + hash_u32(uint(int(c.y))));
    float angle = hash_unit(h) * 6.2831855;
    return t * t * t * t * dot(vec2(cos(angle), sin(angle)), x);
}

float simplex2(vec2 v) {
    const float F2 = 0.36602542;
    const float G2 = 0.21132487;
    vec2 i = floor(v + vec2((v.x + v.y) * F2));
    vec2 x0 = v - i + vec2((i.x + i.y) * G2);
    vec2 step_ = x0.x > x0.y ? vec2(1.0, 0.0) : vec2(0.0, 1.0);
    vec2 x1 = x0 - step_ + vec2(G2);
    vec2 x2 = x0 - vec2(1.0) + vec2(2.0 * G2);
    float corners = simplex_corner(i, x0) + simplex_corner(i + step_, x1);
    return 70.0 * (corners + simplex_corner(i + vec2(1.0), x2));
}

// The paint maps (paint.rs `PaintMap`): per texel two words — the density's byte lowest, then
// the length's; the tint's red, green and blue bytes (128: the scene's own colour).
layout(set = 0, binding = BINDING_PAINT, std430) readonly buffer PaintTexels {
    uvec4 paint_texels[];
};

// What the paint says at a place: how much grass grows and how tall (fractions), what its
// colour is multiplied by, and each species' weight map there.
struct PaintSample {
    vec2 amounts;
    vec3 tint;
    vec4 species;
};

// paint.rs `unpack_texel`: texel t's paint.
PaintSample paint_texel(uvec2 t) {
    uvec4 w = paint_texels[t.y * frame.paint_size.x + t.x];
    vec2 amounts = vec2(float(w.x & 0xffu), float((w.x >> 8u) & 0xffu)) * (1.0 / 255.0);
    vec3 tint = vec3(float(w.y & 0xffu), float((w.y >> 8u) & 0xffu), float((w.y >> 16u) & 0xffu))
                * (1.0 / 128.0);
    vec4 species = vec4(float(w.z & 0xffu), float((w.z >> 8u) & 0xffu), float((w.z >> 16u) & 0xffu),
                        float(w.z >> 24u)) * (1.0 / 255.0);
    return PaintSample(amounts, tint, species);
}

PaintSample mix_paint(PaintSample a, PaintSample b, float t) {
    return PaintSample(mix(a.amounts, b.amounts, t), mix(a.tint, b.tint, t),
                       mix(a.species, b.species, t));
}

// paint.rs `PaintMap::at`: the four nearest texels blended, the edge carrying on beyond them.
PaintSample paint_map_at(vec2 world) {
    vec2 limit = vec2(frame.paint_size.xy) - 1.0;
    vec2 at = clamp((world - frame.paint_area.xy) * frame.paint_area.zw - 0.5, vec2(0.0), limit);
    vec2 low = floor(at);
    vec2 f = at - low;
    uvec2 t0 = uvec2(low);
    uvec2 t1 = min(t0 + 1u, frame.paint_size.xy - 1u);
    PaintSample near = mix_paint(paint_texel(t0), paint_texel(uvec2(t1.x, t0.y)), f.x);
    PaintSample far = mix_paint(paint_texel(uvec2(t0.x, t1.y)), paint_texel(t1), f.x);
    return mix_paint(near, far, f.y);
}

// paint.rs `noise_patch`: how much of a noise patch (`noise`: x patches per unit, y cover, z
// softness) covers world ground point `world`, the noise shifted by `offset`.
float noise_patch(vec2 world, vec4 noise, vec2 offset) {
    float n = 0.5 + 0.5 * simplex2(world * noise.x + offset);
    float threshold = 1.0 - noise.y;
    float soft = noise.z;
    return soft > 0.0 ? smoothstep(threshold - soft, threshold + soft, n) : step(threshold, n);
}

// The maps' paint at world ground point `world` (read once), or the full paint where no map is
// painted: all the grass, full height, untinted, every species at its weight.
PaintSample paint_map_or_full(vec2 world) {
    return frame.paint_size.x == 0u ? PaintSample(vec2(1.0), vec3(1.0), vec4(1.0))
                                    : paint_map_at(world);
}

// paint.rs `GroundPaint::at`: what the grass's colour is multiplied by at world ground point
// `world` — the colour map's tint `p` says, times the tint noise's.
vec3 painted_tint(PaintSample p, vec2 world) {
    vec3 tint = p.tint;
    if (frame.paint_tint_noise.x > 0.0) {
        float patch_amount = noise_patch(world, frame.paint_tint_noise, vec2(-211.7, 93.1));
        tint *= mix(vec3(1.0), frame.paint_tint_color.rgb, patch_amount);
    }
    return tint;
}

// species.rs: the kinds of grass a scene grows (0: one, from its own ranges and colours).
uint species_count() {
    return frame.species_meta.x;
}

// Species k's weight at world ground point `world` (its weight times its map there).
float species_weight(uint k, vec4 maps) {
    return frame.species[4u * k + 1u].w * maps[k];
}

// species.rs `species_of`: the species of the blade with hash `hash` where the species' weight
// maps read `maps` — its draw falls in that species' share of their weights' sum there.
const uint SPECIES_SALT = 0x5bd1e995u;
uint species_drawn(uint hash, vec4 maps) {
    uint n = species_count();
    if (n <= 1u) {
        return 0u;
    }
    float total = 0.0;
    for (uint k = 0u; k < n; k++) {
        total += species_weight(k, maps);
    }
    if (total <= 0.0) {
        return 0u;
    }
    float draw = hash_unit(hash ^ SPECIES_SALT) * total;
    for (uint k = 0u; k < n; k++) {
        float w = species_weight(k, maps);
        if (draw < w) {
            return k;
        }
        draw -= w;
    }
    return n - 1u;
}

// species.rs `seed_head_drawn`: whether the blade with hash `key`, of species `k`, is a
// flowering stalk.
const uint SEED_HEAD_SALT = 0x27d4eb2fu;
bool seed_head_drawn(uint key, uint k) {
    return frame.species_meta.y != 0u
           && hash_unit(key ^ SEED_HEAD_SALT) < frame.seed_heads[2u * k].x;
}

// What a blade's colour comes from, found once per blade (at its root) by the stage that makes
// its vertices rather than per fragment: x its species (low byte) and whether it is tinted
// (LOOK_TINTED), y its tint (packUnorm4x8 of a quarter of it).
const uint LOOK_TINTED = 0x80000000u;
const uint LOOK_SEED_HEAD = 0x40000000u;
uvec2 blade_look(uint key, vec2 world_root) {
    if (frame.paint_size.x == 0u && frame.paint_tint_noise.x <= 0.0 && species_count() == 0u) {
        return uvec2(0u);
    }
    PaintSample p = paint_map_or_full(world_root);
    vec3 tint = painted_tint(p, world_root);
    uint k = species_drawn(key, p.species);
    uint head = seed_head_drawn(key, k) ? LOOK_SEED_HEAD : 0u;
    return uvec2(k | head | LOOK_TINTED, packUnorm4x8(vec4(0.25 * tint, 0.0)));
}

// The part of its blade a seed head takes, for a blade of look `look` (0: a leaf).
float seed_head_length(uvec2 look) {
    return (look.x & LOOK_SEED_HEAD) != 0u ? frame.seed_heads[2u * (look.x & 0xffu)].y : 0.0;
}

// The outline (`blade_shape_of`) a blade of species `k` is drawn with: a flowering stalk with
// the species' head where `flowering`, else a leaf of the scene's shape.
uint outline_of(uint k, bool flowering) {
    uint head = flowering ? uint(round(frame.seed_heads[2u * k].y * 255.0)) : 0u;
    return blade_shape_code() | (head << 8u);
}

// The outline a blade of look `look` is drawn with.
uint blade_outline(uvec2 look) {
    return outline_of(look.x & 0xffu, (look.x & LOOK_SEED_HEAD) != 0u);
}

vec3 normalize_or_zero(vec3 v) {
    float len = length(v);
    return len > 0.0 ? v / len : vec3(0.0);
}

// ---------------------------------------------------------------- blade frame (blade.rs)

void surface_tangent(vec3 up, out vec3 t, out vec3 b) {
    float s = up.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + up.z);
    float c = up.x * up.y * a;
    t = vec3(1.0 + s * up.x * up.x * a, s * c, -s * up.x);
    b = vec3(c, s + up.y * up.y * a, -up.y);
}

vec3 width_direction(vec3 up, float orientation) {
    vec3 t, b;
    surface_tangent(up, t, b);
    return normalize_or_zero(t * cos(orientation) + b * sin(orientation));
}

// A blade is rounded across its width, as if folded along its midrib: the normal at u (0 one
// edge, 1 the other) tilts toward that edge, so light varies across each blade instead of
// shading it as one flat card (SPEC §8).
const float BLADE_ROUNDING = 0.15;

vec3 rounded_normal(vec3 n, vec3 across, float u) {
    return normalize_or_zero(n + across * ((2.0 * u - 1.0) * BLADE_ROUNDING));
}

// ---------------------------------------------------------------- wind (wind.rs)

// Validation's guide `v1` for a blade rooted at `v0` along `up`, `h` long, its tip at `v2` (above
// the ground), placed by how far the tip leans; and the length of the curve through them, which
// validation brings back to `h` by scaling the curve about its root (`validate_tip`).
float guided_length(vec3 v0, vec3 up, float h, vec3 v2, out vec3 v1) {
    vec3 rel = v2 - v0;
    float l_proj = length(rel - up * dot(rel, up));
    v1 = v0 + up * (h * max(1.0 - l_proj / h, 0.05 * max(l_proj / h, 1.0)));
    float l0 = length(v2 - v0);
    float l1 = length(v1 - v0) + length(v2 - v1);
    return (2.0 * l0 + l1) / 3.0;
}

// State validation a–c (paper §5.2) of a blade rooted at `v0` along `up`, `h` long, whose tip
// would move to `v2`: the tip kept above the ground, the guide placed by how far the tip leans,
// the curve brought back to its length. Each physics step ends with it (physics.wesl); the
// generated blades settle with it (twin.wesl `settle`).
void validate_tip(vec3 v0, vec3 up, float h, vec3 v2, out vec3 v1_out, out vec3 v2_out) {
    v2 -= up * min(dot(up, v2 - v0), 0.0);
    vec3 v1;
    float len = guided_length(v0, up, h, v2, v1);
    float ratio = len > 1e-12 ? h / len : 1.0;
    v1_out = v0 + (v1 - v0) * ratio;
    v2_out = v1_out + (v2 - v1) * ratio;
}

// ---------------------------------------------------------------- culling and LOD (cull.rs)

float lod_level(float dist) {
    float t = clamp((dist - frame.lod.z) / (frame.lod.w - frame.lod.z), 0.0, 1.0);
    return frame.lod.x + (frame.lod.y - frame.lod.x) * (1.0 - t);
}

// ---------------------------------------------------------------- shading

// The shadow map holds two cascades side by side, each a square: on the left the near cascade
// (the ball of radius shading_extra.w around the eye: the blades there), on the right the field
// cascade (the whole field: terrain and colliders). Share of sunlight reaching p in cascade
// `half_index` (0 near, 1 field) seen through `sun`: 4 taps of the hardware-filtered comparison
// (so shadow edges are soft), kept inside the cascade's half so no tap reads the other; -1 where
// p lies outside the cascade.
float cascade_sunlight(vec3 p, mat4 sun, float half_index, float receiver_bias) {
    vec4 clip = sun * vec4(p, 1.0);
    vec3 ndc = clip.xyz / clip.w;
    if (any(greaterThan(abs(ndc.xy), vec2(1.0))) || ndc.z > 1.0 || ndc.z < 0.0) {
        return -1.0;
    }
    vec2 size = vec2(textureSize(shadow_map, 0));
    vec2 texel = 1.0 / size;
    vec2 uv = ndc.xy * 0.5 + 0.5;
    // Taps reach 1.5 texels out and filter one more: keep them 3 texels inside the half.
    vec2 lo = vec2(half_index * 0.5, 0.0) + 3.0 * texel;
    vec2 hi = vec2(half_index * 0.5 + 0.5, 1.0) - 3.0 * texel;
    uv.x = uv.x * 0.5 + half_index * 0.5;
    float depth = ndc.z - receiver_bias;
    float lit = 0.0;
    for (int i = 0; i < 4; i++) {
        vec2 offset = (vec2(i & 1, i >> 1) - 0.5) * 1.5 * texel;
        lit += textureLod(shadow_map, vec3(clamp(uv + offset, lo, hi), depth), 0.0);
    }
    return lit * 0.25;
}

// Share of sunlight reaching p past the shadow casters: the terrain's and the colliders' (the
// field cascade) everywhere, and near the eye the blades' too (the near cascade), fading out
// over the last fifth of its reach so blade shadows end softly rather than at a circle. Each
// cascade holds its own casters, so the light is the darker of the two.
// 1 where shadows are off or p lies outside both.
float sunlight(vec3 p) {
    if ((frame.modes.w & DRAW_SHADOWS) == 0u) {
        return 1.0;
    }
    // A small receiver bias keeps the roots, which touch the casting ground, out of its shadow.
    float field = cascade_sunlight(p, frame.sun_view_proj, 1.0, 0.0005);
    field = field < 0.0 ? 1.0 : field;
    float reach = frame.shading_extra.w;
    if ((frame.modes.w & DRAW_BLADE_SHADOWS) == 0u || reach <= 0.0) {
        return field;
    }
    float dist = distance(p, frame.camera_position.xyz);
    float near_weight = 1.0 - smoothstep(0.8 * reach, reach, dist);
    if (near_weight <= 0.0) {
        return field;
    }
    // Its receiver bias is 5 cm, as depth: the map's depth gradient is 1 / its depth span.
    mat4 sun = frame.sun_near_view_proj;
    float per_unit = length(vec3(sun[0][2], sun[1][2], sun[2][2]));
    float blades = cascade_sunlight(p, sun, 0.0, 0.05 * per_unit);
    return blades < 0.0 ? field : min(field, mix(1.0, blades, near_weight));
}
