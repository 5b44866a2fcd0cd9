#version 460
// The caller's multisampled depth into the depth pyramid (caller_depth_fold.glsl).
#define CALLER_DEPTH_MULTISAMPLED
#extension GL_GOOGLE_include_directive : require
#include "caller_depth_fold.glsl"
