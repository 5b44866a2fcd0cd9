#version 460
// An instanced blade as a triangle strip (SPEC §7 [F]): the draw of level k (gl_DrawID) has
// 2·(8 >> k) + 1 vertices (17, 9, 5, 3: the last level is one triangle); the instance pulls its
// 32-byte blade from that level's list (posed: its tip where it settles this frame) and builds
// its curve and the strip's vertex (instanced.glsl `listed_shape`, `strip_vertex`, geomorphed
// near level boundaries). Outputs match blade_fragment.wesl `BladeVertex`.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shading.glsl"
#include "instanced.glsl"

layout(location = 0) out vec3 out_normal;
layout(location = 1) out vec3 out_position;
layout(location = 2) out vec2 out_uv;
layout(location = 3) out vec3 out_vary; // blade_fragment.wesl says why
layout(location = 4) flat out uvec2 out_look;

void main() {
    uint lod = uint(gl_DrawID);
    uint instance = uint(gl_InstanceIndex);
    if (instance >= frame.instanced_caps[lod]) {
        gl_Position = vec4(0.0, 0.0, -1.0, 1.0); // past a full list: outside the clip volume
        return;
    }
    uint at = 2u * (frame.instanced_lists[lod] + instance);
    InstancedBlade blade = unpack_blade(instanced_blades[at], instanced_blades[at + 1u]);
    float dist = length(blade.root - frame.camera_position.xyz);
    Shape s = listed_shape(blade, dist);

    vec3 p = strip_vertex(s, dist, lod, uint(gl_VertexIndex), out_normal, out_uv);
    out_position = p;
    out_look = VIEW == VIEW_CAMERA ? blade_look(blade.hash, world_xz(blade.root.xz)) : uvec2(0u);
    out_vary = albedo_variation(p, blade.hash, out_look);
    gl_Position = pass_view_proj() * vec4(p, 1.0);
}
