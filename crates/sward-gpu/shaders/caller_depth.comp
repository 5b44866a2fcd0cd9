#version 460
// The caller's single-sample depth into the depth pyramid (caller_depth_fold.glsl).
#extension GL_GOOGLE_include_directive : require
#include "caller_depth_fold.glsl"
