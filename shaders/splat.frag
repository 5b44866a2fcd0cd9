#version 460
// The splatted far field into the frame (drawn over a screen-covering triangle, sky.vert), run per
// sample: each sample whose splat cell instanced.comp splatted a blade into takes its colour and
// depth, so the depth test sorts splatted blades against everything drawn, the sky fills in
// behind, and the MSAA resolve averages splats just as it averages drawn blades. On a 4× target
// the cells are the pixel's quarters: the standard sample i lies in quarter (i & 1, i >> 1).
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(location = 0) out vec4 out_color;

void main() {
    int scale = int(frame.instanced_meta.z);
    ivec2 cell = ivec2(gl_FragCoord.xy) * scale;
    if (scale == 2) {
        cell += ivec2(gl_SampleID & 1, gl_SampleID >> 1);
    }
    uvec2 splat = splat_pixels[cell.y * int(frame.viewport.x) * scale + cell.x];
    if (splat.y == 0xffffffffu) {
        discard;
    }
    vec3 colour = unpackUnorm4x8(splat.x).rgb;
    out_color = vec4(colour * colour, 1.0);
    gl_FragDepth = uintBitsToFloat(splat.y);
}
