#define_import_path sward::portable_blades

// sward's Bezier blades as Bevy's passes draw them on any device Bevy opened: each instance of
// a distance bucket's draw command one visible blade of the portable cull's lists, a triangle
// strip up it, from the WGSL the portable renderer draws its own strips with (sward-wgpu's
// `engine_library`, imported as sward::portable: strip_surface.wgsl and the shading's looks).
// The same functions as blades.wgsl, which reads the Vulkan renderer's drawn-blade records.

#import sward::portable::{
    frame, Blade, blades, visible, counters, StripPlace, strip_place, blade_point, blade_colour_key,
    blade_look, blade_outline, world_xz, placed_point, placed_before_point, placed_normal, albedo_variation, occlusion,
    strip_segments, BUCKET_STARTS, STRIP_STRIDE, blade_albedo as look_albedo, may_flower,
}

// The blades as the last frame drew them (the motion vectors' other end).
@group(2) @binding(21) var<storage, read> previous_blades: array<Blade>;

// A point of the drawn blade, in Bevy's world.
struct BladePoint {
    world_position: vec3<f32>,
    // Rounded across the width; either side's (the fragment stage turns it to the eye).
    normal: vec3<f32>,
    // u across, v from root to tip.
    uv: vec2<f32>,
    // What its colour comes from: the blade's colour key (x) and its look (y, z).
    colour: vec3<u32>,
    // Where the point was in the last frame (the blade's pose then, in Bevy's world).
    previous_world_position: vec3<f32>,
}

// The outline the blade is drawn with and its look, found once at its root.
fn look_of(id: u32, b: Blade) -> vec3<u32> {
    let key = blade_colour_key(id);
    return vec3(key, blade_look(key, world_xz(b.root.xz)));
}

// The point of blade `b` of look `colour` at strip place `at`, in Bevy's world as the last
// frame had the field.
fn point_before(b: Blade, colour: vec3<u32>, at: StripPlace) -> vec3<f32> {
    return placed_before_point(blade_point(b, blade_outline(colour.yz), at.u, at.v).position);
}

// Vertex `vertex` of instance `instance` of a bucket's command, where it is now.
fn blade_vertex(instance: u32, vertex: u32) -> BladePoint {
    let at = strip_place(vertex, instance);
    let b = blades[at.id];
    let colour = look_of(at.id, b);
    let surface = blade_point(b, blade_outline(colour.yz), at.u, at.v);
    var out: BladePoint;
    out.world_position = placed_point(surface.position);
    out.previous_world_position = placed_before_point(surface.position);
    out.normal = placed_normal(surface.normal);
    out.uv = vec2(at.u, at.v);
    out.colour = colour;
    return out;
}

// The same vertex, and where it was in the last frame (the blade's pose then: its own motion,
// wind and collisions, as well as the camera's, make the motion vectors).
fn moving_blade_vertex(instance: u32, vertex: u32) -> BladePoint {
    var out = blade_vertex(instance, vertex);
    let at = strip_place(vertex, instance);
    out.previous_world_position = point_before(previous_blades[at.id], out.colour, at);
    return out;
}

// Rows of a blade's strip in a shadow map at most: a shadow needs the blade's outline, not its
// curve's every row (as blades.wgsl).
const SHADOW_SEGMENTS: u32 = 4u;

// Vertex `vertex` of instance `instance` as a shadow map draws it: a flat strip of at most
// SHADOW_SEGMENTS rows up the blade's edges; the command's vertices past it fall on the tip.
fn shadow_blade_vertex(instance: u32, vertex: u32) -> vec3<f32> {
    let k = vertex / STRIP_STRIDE;
    let segments = min(strip_segments(k), SHADOW_SEGMENTS);
    let i = min(vertex % STRIP_STRIDE, 2u * segments + 1u);
    let id = visible[counters[BUCKET_STARTS + k] + instance];
    let b = blades[id];
    let at = StripPlace(id, f32(i & 1u), f32(i >> 1u) / f32(segments));
    // Only a flowering stalk's outline differs from the scene's leaf: its look (the paint and
    // species at its root) is found only where the blade may flower.
    let key = blade_colour_key(id);
    var outline = u32(frame.blade_style.x);
    if may_flower(key) {
        outline = blade_outline(blade_look(key, world_xz(b.root.xz)));
    }
    return placed_point(blade_point(b, outline, at.u, at.v).position);
}

// The blade's colour at height v where it is at `world_position` (shading.wgsl `blade_albedo`).
fn blade_albedo(colour: vec3<u32>, v: f32, world_position: vec3<f32>) -> vec3<f32> {
    let position = vec3(world_position.x - frame.origin.x, world_position.y, world_position.z - frame.origin.y);
    return look_albedo(v, colour.yz, albedo_variation(position, colour.x, colour.yz));
}

// Fake ambient occlusion (shading.wgsl `occlusion`).
fn blade_occlusion(uv: vec2<f32>) -> f32 {
    return occlusion(uv);
}

// The share of the light on a blade at height v that passes through it (as blades.wgsl).
fn blade_transmission(v: f32) -> f32 {
    return clamp(frame.shading_model.w * (0.5 + v) * 0.5, 0.0, 0.9);
}
