#version 460
// A billboard (SPEC §7 [B]; its shape, sway and trampling in billboard.glsl): three textured quads
// crossing at 60°, 18 vertices per instance, the instance pulling its billboard (root, height,
// half-width, facing, hash) from the billboard list that generate_grid.wesl's billboard dispatch
// filled; far from the eye one quad turned to it. Outputs match billboard_shading.glsl.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shading.glsl"
#include "billboard.glsl"

layout(location = 0) out vec3 out_normal;
layout(location = 1) out vec3 out_position;
layout(location = 2) out vec2 out_uv;
layout(location = 3) out vec3 out_vary; // blade_fragment.wesl says why
layout(location = 4) flat out float out_layers;
layout(location = 5) flat out uvec2 out_look;

const uint CORNERS[6] = uint[](0u, 1u, 2u, 2u, 1u, 3u);
// Where a billboard's painted blades lie in its quad (u across, height up; billboard.rs
// BILLBOARD_OUTLINE): blades lean outward from roots crowded in the middle, and the top 5 % holds
// no tip, so the corners below the wide top are clear. Drawn as this trapezoid, a near billboard
// rasterizes a fifth fewer fragments. It holds every texel of mip levels 0 to 2 that
// alpha-to-coverage can draw; coarser levels spread wider.
const vec2 BILLBOARD_OUTLINE[4] =
    vec2[](vec2(0.22, 0.0), vec2(0.89, 0.0), vec2(0.02, 0.95), vec2(0.99, 0.95));
// Billboards at least this many pixels tall are seen through mip levels 0 to 2 (256 / 4).
const float OUTLINE_PIXELS = 64.0;

// How many pixels of the image a billboard of `height` standing at `root` spans (0 when the eye is
// below or behind it).
float pixels_tall(vec3 root, float height) {
    vec4 foot = frame.view_proj * vec4(root, 1.0);
    vec4 top = frame.view_proj * vec4(root + vec3(0.0, height, 0.0), 1.0);
    if (foot.w <= 0.0 || top.w <= 0.0) {
        return 0.0;
    }
    vec2 span = (top.xy / top.w - foot.xy / foot.w) * 0.5 * frame.viewport.xy;
    return length(span);
}

void main() {
    uint instance = uint(gl_InstanceIndex);
    if (billboards_rasterized()) {
        // Only the billboards billboard_raster.wesl left to the hardware, by their index in the
        // list.
        instance = instanced_blades[hardware_billboards_at() + instance / 4u][instance % 4u];
    }
    if (instance >= frame.billboard_meta.y) {
        gl_Position = vec4(0.0, 0.0, -1.0, 1.0); // past a full list: outside the clip volume
        return;
    }
    uint at = 2u * (frame.billboard_meta.x + instance);
    Billboard t = unpack_billboard(instanced_blades[at], instanced_blades[at + 1u]);
    uint quad = uint(gl_VertexIndex) / 6u;
    uint corner = CORNERS[uint(gl_VertexIndex) % 6u];
    float dist = length(t.root - frame.camera_position.xyz);
    if (one_quad(dist) && quad > 0u) {
        // Far: one quad, turned square to the eye; the other two make no triangle.
        gl_Position = vec4(0.0, 0.0, -1.0, 1.0);
        return;
    }
    BillboardQuad q = billboard_quad(t, quad, dist, one_quad(dist));
    if (billboard_quad_rasterized(t, q, dist)) {
        gl_Position = vec4(0.0, 0.0, -1.0, 1.0); // billboard_raster.wesl makes it
        return;
    }
    // The corner's place in the quad: the outline where the billboard is large on screen.
    vec2 place = vec2(corner & 1u, corner >> 1u);
    if (pixels_tall(t.root, t.height) >= OUTLINE_PIXELS) {
        place = BILLBOARD_OUTLINE[corner];
    }
    vec3 p = billboard_point(t, q, place);
    out_normal = q.normal;
    out_position = p;
    out_uv = vec2(place.x, 1.0 - place.y); // texture row 0 holds the tips
    out_look = blade_look(t.hash, world_xz(t.root.xz));
    out_vary = albedo_variation(p, t.hash, out_look);
    out_layers = q.layers;
    gl_Position = frame.view_proj * vec4(p, 1.0);
}
