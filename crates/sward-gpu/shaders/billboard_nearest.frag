#version 460
// A billboard after the depth pre-pass (billboard_depth.frag): the depth test (equal: only
// the billboard nearest the eye at a sample passes) runs before shading, so each covered sample is
// shaded once however many quads overlap it. Safe to test early: this pass writes no depth.
#extension GL_GOOGLE_include_directive : require
layout(early_fragment_tests) in;
#include "billboard_shading.glsl"
