#version 460
// The instanced grass's pass (instanced_pass.glsl) for a device without 64-bit atomics: nothing
// is splatted, every blade within the cut-off is listed at its level and drawn.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "instanced_pass.glsl"
