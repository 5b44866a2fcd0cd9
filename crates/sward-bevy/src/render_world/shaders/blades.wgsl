#define_import_path sward::blades

// sward's Bezier blades as Bevy's passes draw them: each instance of a distance bucket's draw
// command one blade, a triangle strip up it as sward's strip route cuts it (shaders/
// blade_strip.vert and blade_surface.glsl, of which this is the WGSL), from the buffers sward's
// compute passes filled this frame: the blades, the drawn blades (shaders/drawn_blades.comp: id,
// outline, strip length and colours) and the frame's uniforms. The frame, the blade and the
// blade's surface are the portable renderer's WGSL (sward::portable, as portable_blades.wgsl
// draws from): one source of the blade's shape for both.

#import sward::portable::{
    frame, Blade, blades, blade_point, placed_point, placed_before_point, placed_normal, strip_walk,
}

@group(2) @binding(2) var<storage, read> drawn_blades: array<vec4<u32>>;
// The blades as the last frame drew them (the motion vectors' other end): the binding the
// portable route has them at (the library holds its own lists at 3 and 6).
@group(2) @binding(21) var<storage, read> previous_blades: array<Blade>;

// A point of the drawn blade, in Bevy's world.
struct BladePoint {
    world_position: vec3<f32>,
    // Rounded across the width; either side's (the fragment stage turns it to the eye).
    normal: vec3<f32>,
    // u across, v from root to tip.
    uv: vec2<f32>,
    // What its colour comes from: here x the drawn blade (shaders/drawn_blades.comp) it is of
    // (portable_blades.wgsl: the blade's colour key and look).
    colour: vec3<u32>,
    // Where the point was in the last frame (the blade's pose then, in Bevy's world).
    previous_world_position: vec3<f32>,
}

// Where vertex `vertex` of the strip of drawn blade `drawn` lies on its blade: blade_strip.vert's
// walk up the blade — two vertices a row, or with the ridge up the left half and down the
// right. (u, v, the blade's id, its outline.)
struct StripPlace {
    u: f32,
    v: f32,
    blade: u32,
    outline: u32,
}

fn strip_place(drawn: u32, vertex: u32) -> StripPlace {
    let record = drawn_blades[2u * drawn];
    let at = strip_walk(vertex, record.y >> 16u);
    return StripPlace(at.x, at.y, record.x, record.y & 0xffffu);
}

// Vertex `vertex` of the strip of drawn blade `drawn`, where it is now.
fn blade_vertex(drawn: u32, vertex: u32) -> BladePoint {
    return strip_vertex(drawn, strip_place(drawn, vertex));
}

// The same vertex, and where it was in the last frame (the blade's pose then: its own motion,
// wind and collisions, as well as the camera's, make the motion vectors).
fn moving_blade_vertex(drawn: u32, vertex: u32) -> BladePoint {
    let at = strip_place(drawn, vertex);
    var out = strip_vertex(drawn, at);
    out.previous_world_position = placed_before_point(blade_point(previous_blades[at.blade], at.outline, at.u, at.v).position);
    return out;
}

// The point of drawn blade `drawn` at strip place `at`, where it is now.
fn strip_vertex(drawn: u32, at: StripPlace) -> BladePoint {
    let surface = blade_point(blades[at.blade], at.outline, at.u, at.v);
    var out: BladePoint;
    out.world_position = placed_point(surface.position);
    out.previous_world_position = placed_before_point(surface.position);
    out.normal = placed_normal(surface.normal);
    out.uv = vec2(at.u, at.v);
    out.colour = vec3(drawn, 0u, 0u);
    return out;
}

// Rows of a blade's strip in a shadow map at most: a shadow needs the blade's outline, not its
// curve's every row (the H100 drew the meadow's shadows in 3.0 ms with the camera's strips).
const SHADOW_SEGMENTS: u32 = 4u;

// Vertex `vertex` of drawn blade `drawn` as a shadow map draws it: a flat strip of at most
// SHADOW_SEGMENTS rows up the blade's edges (no ridge: its fold does not change the outline);
// the command's vertices past it fall on the tip, drawing nothing.
fn shadow_blade_vertex(drawn: u32, vertex: u32) -> vec3<f32> {
    let record = drawn_blades[2u * drawn];
    let segments = min(record.y >> 16u, SHADOW_SEGMENTS);
    let i = min(vertex, 2u * segments + 1u);
    let p = blade_point(blades[record.x], record.y & 0xffffu, f32(i & 1u), f32(i >> 1u) / f32(segments));
    return placed_point(p.position);
}

// The blade's colour at height v (shading.glsl `blade_albedo`, its variation taken at the root
// by drawn_blades.comp, whatever `world_position`).
fn blade_albedo(colour: vec3<u32>, v: f32, world_position: vec3<f32>) -> vec3<f32> {
    let drawn = colour.x;
    let a = drawn_blades[2u * drawn];
    let b = drawn_blades[2u * drawn + 1u];
    let root_rg = unpack2x16float(a.z);
    let root_b_head = unpack2x16float(a.w);
    let tip_rg = unpack2x16float(b.x);
    let tip_b = unpack2x16float(b.y).x;
    let root = vec3(root_rg, root_b_head.x);
    let tip = vec3(tip_rg, tip_b);
    var base = mix(root, tip, v);
    let head = root_b_head.y;
    if head > 0.0 {
        var seeds = vec3(unpack2x16float(b.z), unpack2x16float(b.w).x);
        let rows = sin(6.2831853 * v / head * 8.0);
        seeds *= 0.85 + 0.2 * rows;
        base = mix(base, seeds, smoothstep(1.0 - head - 0.02, 1.0 - head + 0.06, v));
    }
    return base;
}

// Fake ambient occlusion (shading.glsl `occlusion`): dark at the root where blades crowd, a
// faint groove along the midrib.
fn blade_occlusion(uv: vec2<f32>) -> f32 {
    let strength = frame.shading_extra.x;
    let root = mix(1.0 - strength, 1.0, smoothstep(0.0, 0.7, uv.y));
    let midrib = 1.0 - 0.35 * strength * exp(-pow((uv.x - 0.5) / 0.06, 2.0));
    return root * midrib;
}

// The share of the light on a blade at height v that passes through it (Bevy's diffuse
// transmission): the scene's translucency, stronger toward the thin tip (shading.glsl
// `sun_on_side`), halved because Bevy takes it from the diffuse light the blade reflects.
fn blade_transmission(v: f32) -> f32 {
    return clamp(frame.shading_model.w * (0.5 + v) * 0.5, 0.0, 0.9);
}
