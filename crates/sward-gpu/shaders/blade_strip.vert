#version 460
// The strip route: each visible blade one instance of a triangle strip, its vertices evaluated
// from blade_surface.glsl at (u, v) picked by gl_VertexIndex — no tessellator. The draw command
// of distance bucket gl_DrawID gives the strip its length: 2 (or, with the ridge, 4) vertices
// per row, strip_segments rows of segments, as the tessellation route would cut the blade.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shading.glsl"
#include "blade_surface.glsl"

layout(location = 0) out vec3 out_normal;
layout(location = 1) out vec3 out_position;
layout(location = 2) out vec2 out_uv;
layout(location = 3) out vec3 out_vary; // blade_fragment.wesl says why
layout(location = 4) flat out uvec2 out_look;

// The blade as an occluder of the depth pyramid (VIEW_OCCLUDERS): shortened by a pyramid texel
// (occlusion.y across the viewport) and narrowed on each side by a texel and a tenth of its width,
// so that a texel it covers at its centre is wholly behind it and the sway before the next
// frame's cull does not uncover what it hides there. What is left of a thin blade is nothing, and
// a blade that may be a flowering stalk (`none`) has none.
// (On the H100 1.5 texels and a fifth each side, or 0.5 texels and nothing, culled within 3 %
// as many blades and drew the same picture, bit for bit, at cis565 2^20 and 2^24.)
vec3 occluder_point(Blade b, uint outline, float u, float v, bool none) {
    float texel = max(frame.viewport.x, frame.viewport.y) / float(frame.occlusion.y);
    vec3 n;
    vec2 top = to_pixels(blade_point(b, outline, 0.5, 1.0, n));
    float tall = length(top - to_pixels(blade_point(b, outline, 0.5, 0.0, n)));
    v *= max(0.0, 1.0 - texel / max(tall, 1e-3));
    vec2 right = to_pixels(blade_point(b, outline, 1.0, v, n));
    float across = length(right - to_pixels(blade_point(b, outline, 0.0, v, n)));
    float keep = none ? 0.0 : max(0.0, 1.0 - 2.0 * (texel + 0.1 * across) / max(across, 1e-3));
    vec3 p = blade_point(b, outline, 0.5 + (u - 0.5) * keep, v, n);
    // Drawn as one flat column (the ridge's fold between its edges left out): set back along
    // the view by the most the fold bulges, so the occluder does not stand in front of the blade.
    return p + normalize(p - frame.camera_position.xyz) * 0.5 * b.v2.w;
}

// The ordered list's entry this instance draws. An occluder command may draw fewer blades than
// its bucket holds (the budget ends there): they are spread over the whole bucket, which lies
// in tiles across the view, rather than taken from its start, which is a few tiles.
uint list_entry() {
    uint i = uint(gl_InstanceIndex);
    if (VIEW != VIEW_OCCLUDERS) {
        return i;
    }
    DrawCommand bucket = draws[COMMAND_BUCKETS + uint(gl_DrawID)];
    DrawCommand drawn = draws[COMMAND_OCCLUDERS + uint(gl_DrawID)];
    uint k = i - bucket.first_instance;
    float spread = float(bucket.instance_count) / float(max(drawn.instance_count, 1u));
    return bucket.first_instance + min(uint(float(k) * spread), bucket.instance_count - 1u);
}

void main() {
    uint id = ordered[list_entry()];
    uint segments = strip_segments(uint(gl_DrawID));
    uint i = uint(gl_VertexIndex);
    uint row;
    float u;
    if (VIEW == VIEW_OCCLUDERS) {
        // An occluder is flat and coarse: its depth only has to lie behind the blade's.
        segments = min(strip_segments(uint(gl_DrawID)), OCCLUDER_SEGMENTS);
    }
    if (!blade_ridge() || VIEW == VIEW_OCCLUDERS) {
        row = i >> 1u;
        u = float(i & 1u);
    } else if (i < 2u * (segments + 1u)) {
        // The ridge folds the blade at u = 0.5: up the left half, then down the right half (the
        // two turning triangles are degenerate).
        row = i >> 1u;
        u = 0.5 * float(i & 1u);
    } else {
        uint j = i - 2u * (segments + 1u);
        row = segments - (j >> 1u);
        u = 0.5 + 0.5 * float(j & 1u);
    }
    float v = float(row) / float(segments);
    vec3 n = vec3(0.0);
    uint key = blade_colour_key(id);
    vec2 root = world_xz(blades[id].v0.xz);
    // The camera's blades need their whole look, shadows only their outline; an occluder is a
    // leaf's, and none for a blade that may be a flowering stalk (its thin stalk hides little).
    uvec2 look = VIEW == VIEW_CAMERA ? blade_look(key, root) : uvec2(0u);
    uint outline = VIEW == VIEW_CAMERA      ? blade_outline(look)
                   : VIEW == VIEW_OCCLUDERS ? blade_shape_code()
                                            : blade_outline_at(key, root);
    vec3 p = VIEW == VIEW_OCCLUDERS ? occluder_point(blades[id], outline, u, v, may_flower(key))
                                    : blade_point(blades[id], outline, u, v, n);
    out_normal = n;
    out_position = p;
    out_uv = vec2(u, v);
    out_vary = albedo_variation(p, key, look);
    out_look = look;
    gl_Position = pass_view_proj() * vec4(p, 1.0);
}
