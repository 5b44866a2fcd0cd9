#version 460
// The ground: one large quad at y = 0, two triangles from the vertex index.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(location = 0) out vec3 out_position;

const vec2 CORNERS[6] = vec2[](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));

void main() {
    vec2 corner = CORNERS[gl_VertexIndex] * frame.ground_extent.xy;
    out_position = vec3(corner.x, 0.0, corner.y);
    gl_Position = frame.view_proj * vec4(out_position, 1.0);
}
