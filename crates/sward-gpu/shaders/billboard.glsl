// A billboard's shape, shared by its drawing (billboard.vert) and its splatting
// (generate_grid.wesl): three textured quads crossing at 60°, or far from the eye one quad turned
// to it. Wind as SPEC §7 [B] has it: the billboard's hash picks a fast or a slow sway, taller
// billboards sway slower, the top moves and the base does not, and a second hash varies the
// amplitude; direction and strength are the scene's first wind field's. Near the instanced field's
// edge (technique landscape) billboards grow in over the cross-fade band, and they sink into the
// ground over the last 10 % before the cut-off; where the trample map says so they lie down. Needs
// common.glsl.

const float BILLBOARD_PI = 3.14159265;
// How many of three crossed quads a line of sight through a billboard crosses, on average over the
// billboard's width: the coverage one quad turned to the eye is drawn with in their place.
const float CROSSED_LAYERS = 2.0;

// A billboard as its list holds it.
struct Billboard {
    vec3 root;
    float height; // as generated (before it sinks or grows in)
    float half_width;
    float facing;
    uint hash;
};

Billboard unpack_billboard(uvec4 a, uvec4 b) {
    vec2 size = unpackHalf2x16(a.w);
    return Billboard(uintBitsToFloat(a.xyz), size.x, size.y, unpackHalf2x16(b.x).x, b.z);
}

// One quad of a billboard as drawn this frame.
struct BillboardQuad {
    vec3 across; // unit direction of the quad's width
    vec3 normal; // the normal it is lit by
    float height; // standing height at this distance
    float half_width; // widened with distance
    float layers; // texture layers its coverage stands for
};

// How much of the billboard stands at `dist`: growing in past the inner radius, sinking at the
// edge.
float standing(float dist) {
    float inner = frame.billboard_grid.z;
    float fade = frame.billboard_motion.y;
    float radius = frame.billboard_grid.y;
    float grow = inner > 0.0 ? smoothstep(inner, inner + fade, dist) : 1.0;
    return grow * (1.0 - smoothstep(0.9 * radius, radius, dist));
}

// The sideways push of the billboard's top at time `time`.
vec3 sway(vec3 root, float height, uint hash, float time) {
    vec3 direction = vec3(1.0, 0.0, 0.0);
    float strength = 4.0;
    if (frame.modes.y > 0u) {
        direction = normalize_or_zero(vec3(frame.winds[0].x, 0.0, frame.winds[0].z));
        strength = frame.winds[0].w;
    }
    bool fast = (hash & 1u) != 0u;
    float frequency = (fast ? 2.6 : 1.3) / (0.6 + height);
    vec2 world = world_xz(root.xz);
    float phase = hash_unit(hash) * 2.0 * BILLBOARD_PI + 0.3 * (world.x + world.y);
    float amplitude = frame.billboard_motion.x * height * (0.6 + 0.8 * hash_unit(hash ^ 0x51ed27u));
    amplitude *= clamp(strength / 4.0, 0.0, 2.0);
    return direction * amplitude * cos(frequency * time + phase);
}

// Whether billboard `t` at `dist` is drawn as one quad turned to the eye.
bool one_quad(float dist) {
    return dist > frame.billboard_far.x;
}

// Quad `quad` (0 to 2) of billboard `t` at `dist`; where the billboard is `single`, the one quad
// turned to the eye, lit as one of the three (the billboard's hash picks which), so far billboards
// keep the mix of lit and shaded sides the crossed quads show.
BillboardQuad billboard_quad(Billboard t, uint quad, float dist, bool single) {
    float angle = t.facing + float(quad) * BILLBOARD_PI / 3.0;
    vec3 across = vec3(cos(angle), 0.0, -sin(angle));
    vec3 lit_across = across;
    float layers = 1.0;
    if (single) {
        float lit_angle = t.facing + float(t.hash % 3u) * BILLBOARD_PI / 3.0;
        lit_across = vec3(cos(lit_angle), 0.0, -sin(lit_angle));
        vec2 to_eye = frame.camera_position.xz - t.root.xz;
        across = normalize_or_zero(vec3(-to_eye.y, 0.0, to_eye.x));
        layers = CROSSED_LAYERS;
    }
    // Lit as grass, not as a flat card: the quad's normal leaning up.
    vec3 normal = normalize(cross(lit_across, vec3(0.0, 1.0, 0.0)) + vec3(0.0, 0.25, 0.0));
    // Wider with distance, as the instanced blades, so far billboards keep their coverage.
    float radius = frame.billboard_grid.y;
    float widen = 1.0 + 1.5 * smoothstep(0.05 * radius, radius, dist);
    return BillboardQuad(across, normal, t.height * standing(dist), t.half_width * widen, layers);
}

// The point of quad `q` of billboard `t` at `place` (x across from 0 to 1, y up from 0 to 1):
// swayed by the wind at the top, laid along the trample map's push where trampled.
vec3 billboard_point(Billboard t, BillboardQuad q, vec2 place) {
    float x = 2.0 * place.x - 1.0, y = place.y;
    vec3 p = t.root + q.across * (x * q.half_width) + vec3(0.0, y * q.height, 0.0);
    p += sway(t.root, q.height, t.hash, frame.camera_position.w) * (y * y);
    vec2 push = trample_push(t.root.xz);
    float flat_by = min(length(push), 1.0);
    if (flat_by > 0.0) {
        vec3 along = vec3(push.x, 0.0, push.y) / length(push);
        p += (along * 0.9 - vec3(0.0, 0.75, 0.0)) * (q.height * flat_by * y);
    }
    return p;
}

// Corner `k` of quad `q` of billboard `t` (bottom left, bottom right, top left, top right) in clip
// space.
vec4 billboard_corner_clip(Billboard t, BillboardQuad q, uint k) {
    return frame.view_proj * vec4(billboard_point(t, q, vec2(k & 1u, k >> 1u)), 1.0);
}

// A corner behind the eye (or too near it to divide by): the hardware clips such a quad, compute
// passes leave it.
bool behind_eye_at(vec4 clip) {
    return clip.w <= 1e-3;
}

// Whether a billboard at `dist` is within the compute rasterizer's reach
// (billboard.raster_distance).
bool within_raster_reach(float dist) {
    return dist >= frame.billboard_far.w;
}

// Whether quad `q` of billboard `t` at `dist` is rasterized by compute (billboard_raster.wesl)
// rather than drawn (billboard.vert): within the rasterizer's reach, every corner in front of the
// eye. Both ask this (billboard_raster.wesl from its corners as it projects them), so each quad is
// made exactly once.
bool billboard_quad_rasterized(Billboard t, BillboardQuad q, float dist) {
    if (!within_raster_reach(dist)) {
        return false;
    }
    for (uint k = 0u; k < 4u; k++) {
        if (behind_eye_at(billboard_corner_clip(t, q, k))) {
            return false;
        }
    }
    return true;
}
