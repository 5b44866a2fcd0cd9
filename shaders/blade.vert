#version 460
// One tessellation patch per visible blade: pull the blade's index from the compacted list.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(location = 0) out uint out_blade;

void main() {
    out_blade = COPY_BLADES ? uint(gl_VertexIndex) : visible[gl_VertexIndex];
}
