#version 460
// A billboard tuft (SPEC §7 [B]): three textured quads crossing at 60°, 18 vertices per instance,
// the instance pulling its tuft (root, height, half-width, facing, hash) from the billboard list
// that instanced.comp's billboard dispatch filled. Wind as [B] has it: the tuft's hash picks a
// fast or a slow sway, taller tufts sway slower, the top moves and the base does not, and a
// second hash varies the amplitude; direction and strength are the scene's first wind field's.
// Near the instanced field's edge (technique landscape) tufts grow in over the cross-fade band,
// and they sink into the ground over the last 10 % before the cut-off; where the trample map
// says so they lie down. Outputs match
// billboard.frag.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(location = 0) out vec3 out_normal;
layout(location = 1) out vec3 out_position;
layout(location = 2) out vec2 out_uv;
layout(location = 3) flat out uint out_tuft;
layout(location = 4) flat out float out_layers;

const float PI = 3.14159265;
const uint CORNERS[6] = uint[](0u, 1u, 2u, 2u, 1u, 3u);
// How many of three crossed quads a line of sight through a tuft crosses, on average over the
// tuft's width: the coverage one quad turned to the eye is drawn with in their place.
const float CROSSED_LAYERS = 2.0;
// Where a tuft's painted blades lie in its quad (u across, height up; billboard.rs
// TUFT_OUTLINE): blades lean outward from roots crowded in the middle, and the top 5 % holds no
// tip, so the corners below the wide top are clear. Drawn as this trapezoid, a near tuft
// rasterizes a fifth fewer fragments. It holds every texel of mip levels 0 to 2 that
// alpha-to-coverage can draw; coarser levels spread wider.
const vec2 TUFT_OUTLINE[4] = vec2[](vec2(0.22, 0.0), vec2(0.89, 0.0), vec2(0.02, 0.95), vec2(0.99, 0.95));
// Tufts at least this many pixels tall are seen through mip levels 0 to 2 (256 / 4).
const float OUTLINE_PIXELS = 64.0;

// How much of the tuft stands at `dist`: growing in past the inner radius, sinking at the edge.
float standing(float dist) {
    float inner = frame.billboard_grid.z;
    float fade = frame.billboard_motion.y;
    float radius = frame.billboard_grid.y;
    float grow = inner > 0.0 ? smoothstep(inner, inner + fade, dist) : 1.0;
    return grow * (1.0 - smoothstep(0.9 * radius, radius, dist));
}

// The sideways push of the tuft's top at time `time`.
vec3 sway(vec3 root, float height, uint hash, float time) {
    vec3 direction = vec3(1.0, 0.0, 0.0);
    float strength = 4.0;
    if (frame.modes.y > 0u) {
        direction = normalize_or_zero(vec3(frame.winds[0].x, 0.0, frame.winds[0].z));
        strength = frame.winds[0].w;
    }
    bool fast = (hash & 1u) != 0u;
    float frequency = (fast ? 2.6 : 1.3) / (0.6 + height);
    float phase = hash_unit(hash) * 2.0 * PI + 0.3 * (root.x + root.z);
    float amplitude = frame.billboard_motion.x * height * (0.6 + 0.8 * hash_unit(hash ^ 0x51ed27u));
    amplitude *= clamp(strength / 4.0, 0.0, 2.0);
    return direction * amplitude * cos(frequency * time + phase);
}

// How many pixels of the image a tuft of `height` standing at `root` spans (0 when the eye is
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
    if (instance >= frame.billboard_meta.y) {
        gl_Position = vec4(0.0, 0.0, -1.0, 1.0); // past a full list: outside the clip volume
        return;
    }
    uint at = 2u * (frame.billboard_meta.x + instance);
    uvec4 a = instanced_blades[at];
    uvec4 b = instanced_blades[at + 1u];
    vec3 root = uintBitsToFloat(a.xyz);
    vec2 size = unpackHalf2x16(a.w); // height, half-width
    float facing = unpackHalf2x16(b.x).x;
    uint hash = b.z;

    uint quad = uint(gl_VertexIndex) / 6u;
    uint corner = CORNERS[uint(gl_VertexIndex) % 6u];
    float dist = length(root - frame.camera_position.xyz);
    // The corner's place in the quad: the outline where the tuft is large on screen.
    vec2 place = vec2(corner & 1u, corner >> 1u);
    if (pixels_tall(root, size.x) >= OUTLINE_PIXELS) {
        place = TUFT_OUTLINE[corner];
    }
    float x = 2.0 * place.x - 1.0;
    float y = place.y;
    float angle = facing + float(quad) * PI / 3.0;
    vec3 across = vec3(cos(angle), 0.0, -sin(angle));
    // Lit as one of the crossed quads, whichever way the drawn quad turns.
    vec3 lit_across = across;
    out_layers = 1.0;
    if (dist > frame.billboard_motion.w) {
        // Far: one quad, turned square to the eye; the other two make no triangle.
        if (quad > 0u) {
            gl_Position = vec4(0.0, 0.0, -1.0, 1.0);
            return;
        }
        // Lit as one of the three (the tuft's hash picks which), so far tufts keep the mix of
        // lit and shaded sides the crossed quads show.
        float lit_angle = facing + float(hash % 3u) * PI / 3.0;
        lit_across = vec3(cos(lit_angle), 0.0, -sin(lit_angle));
        vec2 to_eye = frame.camera_position.xz - root.xz;
        across = normalize_or_zero(vec3(-to_eye.y, 0.0, to_eye.x));
        out_layers = CROSSED_LAYERS;
    }
    float height = size.x * standing(dist);
    // Wider with distance, as the instanced blades, so far tufts keep their coverage.
    float widen = 1.0 + 1.5 * smoothstep(0.05 * frame.billboard_grid.y, frame.billboard_grid.y, dist);
    vec3 p = root + across * (x * size.y * widen) + vec3(0.0, y * height, 0.0);
    p += sway(root, height, hash, frame.camera_position.w) * (y * y);
    // Trampled (trample.rs): the tuft's top laid along the push, down towards the ground.
    vec2 push = trample_push(root.xz);
    float flat_by = min(length(push), 1.0);
    if (flat_by > 0.0) {
        vec3 along = vec3(push.x, 0.0, push.y) / length(push);
        p += (along * 0.9 - vec3(0.0, 0.75, 0.0)) * (height * flat_by * y);
    }
    // Lit as grass, not as a flat card: the quad's normal leaning up.
    vec3 facing_normal = cross(lit_across, vec3(0.0, 1.0, 0.0));
    out_normal = normalize(facing_normal + vec3(0.0, 0.25, 0.0));
    out_position = p;
    out_uv = vec2(place.x, 1.0 - place.y); // texture row 0 holds the tips
    out_tuft = hash;
    gl_Position = frame.view_proj * vec4(p, 1.0);
}
