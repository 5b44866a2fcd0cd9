#version 460
// Level of detail per blade (SPEC §6): subdivided along the height only, smoothly in distance
// (tessellation.wesl `patch_level`); two segments across the width, as the ridge folds at u = 0.5.
#extension GL_GOOGLE_include_directive : require
#include "declared.glsl"
#include "tessellation.glsl"

layout(constant_id = CONSTANT_COPY_BLADES) const bool COPY_BLADES = false;
layout(vertices = 1) out;
layout(location = 0) in uint in_blade[];
layout(location = 0) out uint out_blade[];

void main() {
    uint id = in_blade[0];
    out_blade[gl_InvocationID] = id;
    float level = patch_level(id, COPY_BLADES);
    gl_TessLevelInner[0] = 2.0;
    gl_TessLevelInner[1] = level;
    gl_TessLevelOuter[0] = level;
    gl_TessLevelOuter[1] = 2.0;
    gl_TessLevelOuter[2] = level;
    gl_TessLevelOuter[3] = 2.0;
}
