#version 460
// An instanced blade as a triangle strip (SPEC §7 [F]): the draw of level k (gl_DrawID) has
// 2·(8 >> k) + 1 vertices (17, 9, 5, 3: the last level is one triangle); the instance pulls its 32-byte blade from that level's list. The blade
// is a quadratic curve leaning by its pitch and bend, swaying with the wind by its phase (the tip
// moves, the root does not). Blades widen with distance so coarse levels keep their coverage, and
// near a level boundary the odd vertices of the finer strip slide onto the coarser strip's edges
// (geomorphing), so crossing a boundary changes nothing on screen. Outputs match blade.frag.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(location = 0) out vec3 out_normal;
layout(location = 1) out vec3 out_position;
layout(location = 2) out vec2 out_uv;
layout(location = 3) flat out uint out_blade;

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

void main() {
    uint lod = uint(gl_DrawID);
    uint segments = 8u >> lod;
    uint instance = uint(gl_InstanceIndex);
    if (instance >= frame.instanced_caps[lod]) {
        gl_Position = vec4(0.0, 0.0, -1.0, 1.0); // past a full list: outside the clip volume
        return;
    }
    uint at = 2u * (frame.instanced_lists[lod] + instance);
    uvec4 a = instanced_blades[at];
    uvec4 b = instanced_blades[at + 1u];
    vec3 root = uintBitsToFloat(a.xyz);
    vec2 size = unpackHalf2x16(a.w);
    vec2 facing_pitch = unpackHalf2x16(b.x);
    vec2 bend_phase = unpackHalf2x16(b.y);

    float dist = length(root - frame.camera_position.xyz);
    float radius = frame.instanced_grid.y;
    // Shrink into the ground over the last 15 % before the cut-off: no hard edge.
    float height = size.x * (1.0 - smoothstep(0.85 * radius, radius, dist));
    // Wider with distance, continuously, so coarse levels do not thin out.
    float widen = 1.0 + 1.5 * smoothstep(frame.instanced_lod.x * 0.5, radius, dist);
    vec3 front = vec3(sin(facing_pitch.x), 0.0, cos(facing_pitch.x));
    Shape s;
    s.across = vec3(front.z, 0.0, -front.x);
    s.width = size.y * widen;
    s.p0 = root;
    s.p1 = root + height * (vec3(0.0, cos(facing_pitch.y), 0.0) + front * sin(facing_pitch.y));
    float time = frame.camera_position.w;
    vec3 wind = frame.modes.y > 0u ? frame.winds[0].xyz : vec3(1.0, 0.0, 0.0);
    float sway = frame.instanced_motion.y * sin(bend_phase.y + 1.7 * time + 0.35 * (root.x + root.z));
    s.p2 = s.p1 + height * (front * bend_phase.x + wind * sway - vec3(0.0, 0.5 * bend_phase.x, 0.0));

    uint v = uint(gl_VertexIndex);
    uint row = min(v / 2u, segments);
    float side = v == 2u * segments ? 0.0 : ((v & 1u) == 0u ? -1.0 : 1.0);
    float t = float(row) / float(segments);
    vec3 p = edge(s, t, side);
    // Geomorph: odd rows move onto the chord of the coarser level as its distance nears.
    if (lod < 3u && (row & 1u) == 1u) {
        float boundary = frame.instanced_lod[lod];
        float morph = smoothstep(0.8 * boundary, boundary, dist);
        float dt = 1.0 / float(segments);
        vec3 chord = 0.5 * (edge(s, t - dt, side) + edge(s, t + dt, side));
        p = mix(p, chord, morph);
    }
    vec3 tangent = normalize_or_zero(mix(s.p1 - s.p0, s.p2 - s.p1, t));
    out_normal = normalize_or_zero(cross(tangent, s.across));
    out_position = p;
    out_uv = vec2(side * 0.5 + 0.5, t);
    out_blade = b.z;
    gl_Position = frame.view_proj * vec4(p, 1.0);
}
