#version 460
// The trample map's frame (trample.rs `TrampleMap::step`, an invocation per texel): the texel
// takes the cell of the window around the eye it now holds (starting upright if that cell is
// new to it), recovers by the Bezier blades' η rule (SPEC §3.7: strength falls by
// simulation.y per second, over the frame's steps), then every collider presses it where it
// flattens the grass more than it already is — away from its centre, by how deep its underside
// reaches into the generated grass above the ground there; mown grass grows back by
// trample.regrow per second, and every cutter mows it down to its underside where that is lower.
#extension GL_GOOGLE_include_directive : require
#define SWARD_TRAMPLE_WRITE
#include "common.glsl"
#include "instanced.glsl"

layout(local_size_x = 16, local_size_y = 16) in;

// trample.rs `underside`: how high above the ground a sphere's underside is over xz; false
// where the sphere is not over it.
bool underside(vec4 sphere, vec2 xz, float ground, out float under) {
    vec2 away = xz - sphere.xz;
    float reach = sphere.w * sphere.w - dot(away, away);
    under = sphere.y - sqrt(max(reach, 0.0)) - ground;
    return reach > 0.0;
}

// trample.rs `stamp`.
vec2 stamp(vec4 collider, vec2 xz, float ground, float grass_top) {
    float under;
    if (!underside(collider, xz, ground, under) || grass_top <= 0.0) {
        return vec2(0.0);
    }
    vec2 away = xz - collider.xz;
    float depth = clamp((grass_top - under) / grass_top, 0.0, 1.0);
    return (dot(away, away) > 0.0 ? normalize(away) : vec2(1.0, 0.0)) * depth;
}

const float STUBBLE = 0.02; // trample.rs
const float GROWN_BACK = 16.0; // trample.rs

// trample.rs `cut`: how high a cutter leaves the grass at xz, 0 where it does not reach into it.
float cut(vec4 cutter, vec2 xz, float ground, float grass_top) {
    float under;
    if (!underside(cutter, xz, ground, under)) {
        return 0.0;
    }
    return under < grass_top ? max(under, STUBBLE) : 0.0;
}

// trample.rs `regrown`.
float regrown(float height, float amount) {
    return height <= 0.0 || height + amount >= GROWN_BACK ? 0.0 : height + amount;
}

void main() {
    int n = int(frame.trample.x);
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(t, ivec2(n)))) {
        return;
    }
    ivec2 base = ivec2(frame.trample.zw);
    ivec2 cell = base + (((t - base) % n) + n) % n;
    uint tag = trample_tag(cell);
    uint i = uint(t.y * n + t.x);
    uvec4 texel = trample_texels[i];
    uvec4 kept = texel.w == tag ? texel : uvec4(0u);
    vec2 push = uintBitsToFloat(kept.xy);
    float strength = length(push);
    float seconds = frame.simulation.x * float(frame.counts.y);
    float amount = frame.simulation.y * seconds;
    push *= strength > 0.0 ? max(strength - amount, 0.0) / strength : 0.0;
    float mown = regrown(uintBitsToFloat(kept.z), uintBitsToFloat(frame.mowing.y) * seconds);
    vec2 world = (vec2(cell) + 0.5) * uintBitsToFloat(frame.trample.y);
    float ground;
    ground_height(world, ground);
    // The colliders are in the frame's numbers.
    vec2 xz = frame_xz(world);
    // As tall as the generated grass grows.
    float grass_top = max(frame.instanced_shape.y, frame.billboard_shape.y);
    uint colliders = (frame.counts.w & FORCE_COLLISIONS) != 0u ? frame.counts.z : 0u;
    for (uint k = 0u; k < colliders; k++) {
        vec2 pressed = stamp(frame.colliders[k], xz, ground, grass_top);
        if (length(pressed) > length(push)) {
            push = pressed;
        }
    }
    // The cutters, after the pushing colliders.
    uint cutters = (frame.counts.w & FORCE_COLLISIONS) != 0u ? frame.mowing.x : 0u;
    for (uint k = frame.counts.z; k < frame.counts.z + cutters; k++) {
        float h = cut(frame.colliders[k], xz, ground, grass_top);
        if (h > 0.0) {
            mown = mown > 0.0 ? min(mown, h) : h;
        }
    }
    trample_texels[i] = uvec4(floatBitsToUint(push), floatBitsToUint(mown), tag);
}
