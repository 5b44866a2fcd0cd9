#version 460
// An instanced blade as a triangle strip (SPEC §7 [F]): the draw of level k (gl_DrawID) has
// 2·(8 >> k) + 1 vertices (17, 9, 5, 3: the last level is one triangle); the instance pulls its
// 32-byte blade from that level's list and builds its curve (instanced.glsl). Near a level boundary the odd vertices of the finer strip slide onto the coarser strip's edges
// (geomorphing), so crossing a boundary changes nothing on screen. Outputs match blade.frag.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "instanced.glsl"

layout(location = 0) out vec3 out_normal;
layout(location = 1) out vec3 out_position;
layout(location = 2) out vec2 out_uv;
layout(location = 3) flat out uint out_blade;

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
    float dist = length(blade.root - frame.camera_position.xyz);
    Shape s = instanced_shape(blade, dist);

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
    out_normal = rounded_normal(normalize_or_zero(cross(tangent, s.across)), s.across, side * 0.5 + 0.5);
    out_position = p;
    out_uv = vec2(side * 0.5 + 0.5, t);
    out_blade = b.z;
    gl_Position = pass_view_proj() * vec4(p, 1.0);
}
