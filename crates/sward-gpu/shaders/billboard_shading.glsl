// A billboard's fragment (billboard.frag; billboard_nearest.frag after a depth pre-pass):
// the painted grass texture's alpha drives alpha-to-coverage (MSAA edges, no shimmering alpha
// test), and its colour is lit by the blades' own shading
// (shading.glsl: gradient, clumps, Lambert or Blinn-Phong, translucency, root darkening, shadow,
// fog), so billboards match the blades they stand beside. The painted blades' own light and dark
// modulate the result.
#include "common.glsl"
#include "shading.glsl"
#include "billboard_coverage.glsl"

layout(location = 0) in vec3 in_normal;
layout(location = 1) in vec3 in_position;
layout(location = 2) in vec2 in_uv;
// Its colour variation, found at its vertices (blade_fragment.wesl says why).
layout(location = 3) in vec3 in_vary;
layout(location = 4) flat in float in_layers;
// What its colour comes from (common.glsl `blade_look`), found once per billboard.
layout(location = 5) flat in uvec2 in_look;
layout(location = 0) out vec4 out_color;

void main() {
    vec4 painted = texture(grass_texture, in_uv);
    painted.a = billboard_coverage(in_uv, in_layers);
    float v = 1.0 - in_uv.y; // height in the billboard
    vec3 lit = shade_blade_lit(in_normal, in_position, vec2(0.3, v),
                               in_look, in_vary, sunlight(in_position));
    out_color = vec4(guard_color(lit * painted_detail(painted)).rgb, painted.a);
}
