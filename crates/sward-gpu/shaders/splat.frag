#version 460
// The splatted far field into the frame (drawn over a screen-covering triangle, scenery.wesl
// `sky_vertex`): each pixel takes the splat cells generate_grid.wesl, splat_blades.wesl and
// raster_blades.wesl wrote into, so the depth test sorts splatted blades against everything drawn
// and the sky fills in behind. On a 4× target the cells are the pixel's quarters, one per sample
// (the standard sample i lies in quarter (i & 1, i >> 1)): the fragment covers the samples whose
// cells hold a blade (gl_SampleMask) with their mean colour and nearest depth, so the MSAA resolve
// blends splats with what lies behind as it does drawn blades, at one invocation per pixel instead
// of per sample.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(location = 0) out vec4 out_color;

const uint EMPTY = 0xffffffffu;

void main() {
    int scale = int(frame.instanced_meta.z);
    ivec2 base = ivec2(gl_FragCoord.xy) * scale;
    int row = int(frame.viewport.x) * scale;
    vec3 sum = vec3(0.0);
    float depth = 1.0;
    int mask = 0;
    int cells = scale * scale;
    for (int i = 0; i < cells; i++) {
        ivec2 cell = base + ivec2(i & 1, i >> 1);
        uvec2 splat = splat_pixels[cell.y * row + cell.x];
        if (splat.y != EMPTY) {
            vec3 colour = unpackUnorm4x8(splat.x).rgb;
            sum += colour * colour;
            depth = min(depth, uintBitsToFloat(splat.y));
            mask |= 1 << i;
        }
    }
    if (mask == 0) {
        discard;
    }
    out_color = vec4(sum / float(bitCount(mask)), 1.0);
    // One sample (scale 1) takes the pixel's only cell.
    gl_SampleMask[0] = scale == 1 ? -1 : mask;
    // Written past the viewport's mirror: a reversed target takes its own depth.
    gl_FragDepth = target_depth(depth);
}
