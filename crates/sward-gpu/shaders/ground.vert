#version 460
// The ground, made from the vertex index alone: one large quad at y = 0 (around the eye under a streamed field), or a UV sphere of
// SPHERE_RINGS × SPHERE_SEGMENTS quads (keep in step with renderer.rs's GROUND_SPHERE_VERTICES).
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(location = 0) out vec3 out_position;
layout(location = 1) out vec3 out_normal;

const vec2 CORNERS[6] = vec2[](vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 0), vec2(1, 1), vec2(0, 1));
const uint SPHERE_RINGS = 96u;
const uint SPHERE_SEGMENTS = 192u;

void main() {
    vec2 corner = CORNERS[gl_VertexIndex % 6];
    if (ground_kind() == GROUND_MESH) {
        GroundVertex v = ground_vertices[gl_VertexIndex];
        out_normal = v.normal.xyz;
        // A hair below the triangles the blades stand on, so roots never float.
        vec3 world = v.position.xyz - v.normal.xyz * 0.002;
        out_position = vec3(frame_xz(world.xz), world.y).xzy;
    } else if (ground_kind() == GROUND_SPHERE) {
        uint quad = uint(gl_VertexIndex) / 6u;
        vec2 grid = (vec2(quad % SPHERE_SEGMENTS, quad / SPHERE_SEGMENTS) + corner) / vec2(SPHERE_SEGMENTS, SPHERE_RINGS);
        float phi = 3.14159265 * grid.y;
        float theta = 6.28318531 * grid.x;
        out_normal = vec3(sin(phi) * cos(theta), cos(phi), sin(phi) * sin(theta));
        // Slightly inside the facets the blades stand on, so roots never float.
        out_position = frame.surface.xyz + out_normal * frame.surface.w * 0.999;
    } else {
        // Under a streamed field the plane goes where the eye goes.
        vec2 middle = streamed() ? frame.camera_position.xz : vec2(0.0);
        vec2 xz = middle + (corner * 2.0 - 1.0) * frame.ground_extent.xy;
        out_normal = vec3(0.0, 1.0, 0.0);
        out_position = vec3(xz.x, 0.0, xz.y);
    }
    gl_Position = pass_view_proj() * vec4(out_position, 1.0);
}
