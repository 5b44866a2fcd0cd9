#version 460
// A billboard drawn in one pass: every quad shaded wherever it covers, overlap included.
#extension GL_GOOGLE_include_directive : require
#include "billboard_shading.glsl"
