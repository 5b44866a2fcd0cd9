#version 460
// Level of detail per blade (SPEC §6): subdivide along the height only, smoothly in distance.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(vertices = 1) out;
layout(location = 0) in uint in_blade[];
layout(location = 0) out uint out_blade[];

void main() {
    uint id = in_blade[0];
    out_blade[gl_InvocationID] = id;
    float level = lod_level(distance(drawn_blade(id).v0.xyz, frame.camera_position.xyz));
    // Two segments across the width: the 3D ridge folds at u = 0.5.
    gl_TessLevelInner[0] = 2.0;
    gl_TessLevelInner[1] = level;
    gl_TessLevelOuter[0] = level;
    gl_TessLevelOuter[1] = 2.0;
    gl_TessLevelOuter[2] = level;
    gl_TessLevelOuter[3] = 2.0;
}
