#version 460
// One tessellation patch per visible blade: pull the blade's index from the ordered list (or,
// in the bench's copy variant, the copy's own index).
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(location = 0) out uint out_blade;

void main() {
    out_blade = COPY_BLADES ? uint(gl_VertexIndex) : ordered[gl_VertexIndex];
}
