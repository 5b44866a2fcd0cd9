#version 460
// A billboard's depth pre-pass: only the painted texture's alpha, which alpha-to-coverage
// turns into the samples whose depth this billboard writes (no colour is written). The shading pass
// (billboard_nearest.frag) then shades only where this pass's billboard won.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "billboard_coverage.glsl"

layout(location = 2) in vec2 in_uv;
layout(location = 4) flat in float in_layers;
layout(location = 0) out vec4 out_color;

void main() {
    out_color = vec4(0.0, 0.0, 0.0, billboard_coverage(in_uv, in_layers));
}
