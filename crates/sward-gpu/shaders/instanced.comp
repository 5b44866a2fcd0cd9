#version 460
// The instanced grass's pass (instanced_pass.glsl), its far blades splatted.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#define SWARD_SPLAT_WRITE
#include "instanced_pass.glsl"
