#define_import_path sward::blades

// sward's Bezier blades as Bevy's passes draw them: each instance of a distance bucket's draw
// command one blade, a triangle strip up it as sward's strip route cuts it (shaders/
// blade_strip.vert and blade_surface.glsl, of which this is the WGSL), from the buffers sward's
// compute passes filled this frame: the blades, the drawn blades (shaders/drawn_blades.comp: id,
// outline, strip length and colours) and the frame's uniforms.

// The frame's uniforms (sward-core `FrameUniforms`, shaders/common.glsl `Frame`) up to the
// origin: the rest is not read here.
struct Frame {
    view_proj: mat4x4<f32>,
    inv_view_proj: mat4x4<f32>,
    sun_view_proj: mat4x4<f32>,
    sun_near_view_proj: mat4x4<f32>,
    camera_position: vec4<f32>,
    gravity: vec4<f32>,
    point_gravity: vec4<f32>,
    simulation: vec4<f32>,
    counts: vec4<u32>,
    cull: vec4<f32>,
    coarse_cull: vec4<f32>,
    modes: vec4<u32>,
    lod: vec4<f32>,
    blade_style: vec4<f32>,
    viewport: vec4<f32>,
    light_direction: vec4<f32>,
    light_color: vec4<f32>,
    root_color: vec4<f32>,
    tip_color: vec4<f32>,
    ground_color: vec4<f32>,
    sky_zenith: vec4<f32>,
    sky_horizon: vec4<f32>,
    shading_model: vec4<f32>,
    shading_extra: vec4<f32>,
    ground_extent: vec4<f32>,
    surface: vec4<f32>,
    instanced_grid: vec4<f32>,
    instanced_shape: vec4<f32>,
    instanced_motion: vec4<f32>,
    instanced_lod: vec4<f32>,
    instanced_lists: vec4<u32>,
    instanced_caps: vec4<u32>,
    instanced_meta: vec4<u32>,
    instanced_ground: vec4<f32>,
    instanced_ground_cells: vec4<u32>,
    billboard_grid: vec4<f32>,
    billboard_shape: vec4<f32>,
    billboard_motion: vec4<f32>,
    billboard_meta: vec4<u32>,
    routes: vec4<u32>,
    occlusion: vec4<u32>,
    patch_cull: vec4<u32>,
    patch_bounds: vec4<f32>,
    tiles: vec4<u32>,
    trample: vec4<u32>,
    mowing: vec4<u32>,
    billboard_far: vec4<f32>,
    instanced_raster: vec4<u32>,
    stream: vec4<u32>,
    stream_reach: vec4<f32>,
    origin: vec4<f32>,
}

struct Blade {
    root: vec4<f32>, // xyz root, w orientation (v0)
    guide: vec4<f32>, // xyz guide, w height (v1)
    tip: vec4<f32>, // xyz tip guide, w width (v2)
    up: vec4<f32>, // xyz surface normal, w stiffness
}

@group(2) @binding(0) var<uniform> frame: Frame;
@group(2) @binding(1) var<storage, read> blades: array<Blade>;
@group(2) @binding(2) var<storage, read> drawn_blades: array<vec4<u32>>;
// The blades as the last frame drew them (the motion vectors' other end).
@group(2) @binding(3) var<storage, read> previous_blades: array<Blade>;

const DRAW_BLADE_RIDGE: u32 = 4u;
const BLADE_QUAD: u32 = 0u;
const BLADE_TRIANGLE: u32 = 1u;
const BLADE_QUADRATIC: u32 = 2u;
const SEED_STALK: f32 = 0.14;
const SEED_HEAD_WIDTH: f32 = 0.5;
const BLADE_ROUNDING: f32 = 0.15;

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

fn normalize_or_zero(v: vec3<f32>) -> vec3<f32> {
    let len = length(v);
    return select(vec3(0.0), v / len, len > 0.0);
}

fn width_direction(up: vec3<f32>, orientation: f32) -> vec3<f32> {
    let s = select(-1.0, 1.0, up.z >= 0.0);
    let a = -1.0 / (s + up.z);
    let c = up.x * up.y * a;
    let t = vec3(1.0 + s * up.x * up.x * a, s * c, -s * up.x);
    let b = vec3(c, s + up.y * up.y * a, -up.y);
    return normalize_or_zero(t * cos(orientation) + b * sin(orientation));
}

fn seed_head_shape(head: f32, u: f32, v: f32) -> f32 {
    let s = clamp((v - (1.0 - head)) / head, 0.0, 1.0);
    let spindle = select(0.0, SEED_HEAD_WIDTH * pow(sin(3.14159265 * pow(s, 0.8)), 0.6), v > 1.0 - head);
    return 0.5 + (u - 0.5) * max(SEED_STALK * (1.0 - s), spindle);
}

fn blade_shape_of(shape: u32, u: f32, v: f32) -> f32 {
    let head = shape >> 8u;
    if head != 0u {
        return seed_head_shape(f32(head) / 255.0, u, v);
    }
    if shape == BLADE_QUAD {
        return u;
    }
    if shape == BLADE_TRIANGLE {
        return u + 0.5 * v - u * v;
    }
    if shape == BLADE_QUADRATIC {
        return u - u * v * v;
    }
    let tip = frame.blade_style.y;
    return 0.5 + (u - 0.5) * (1.0 - max(v - tip, 0.0) / (1.0 - tip));
}

fn to_pixels(p: vec3<f32>) -> vec2<f32> {
    let clip = frame.view_proj * vec4(p, 1.0);
    return clip.xy / max(clip.w, 1e-4) * 0.5 * frame.viewport.xy;
}

fn twin_ease(root: vec3<f32>) -> f32 {
    let start = frame.stream_reach.y;
    let end = frame.stream_reach.x;
    if frame.stream.x == 0u || start >= end {
        return 0.0;
    }
    return smoothstep(start, end, distance(root, frame.camera_position.xyz));
}

fn blade_ridge() -> bool {
    return (frame.modes.w & DRAW_BLADE_RIDGE) != 0u;
}

// The blade's point at (u, v) in the frame's space and its rounded normal: blade_surface.glsl
// `blade_point`.
fn blade_point(b: Blade, outline: u32, u: f32, v: f32, n: ptr<function, vec3<f32>>) -> vec3<f32> {
    let up = b.up.xyz;
    let w = b.tip.w;
    let across = width_direction(up, b.root.w);
    let a = mix(b.root.xyz, b.guide.xyz, v);
    let bb = mix(b.guide.xyz, b.tip.xyz, v);
    let c = mix(a, bb, v);
    var along = bb - a;
    along = select(up, normalize(along), dot(along, along) > 1e-12);
    let flat_normal = normalize(cross(along, across));
    let edge_a = c - w * across;
    let edge_b = c + w * across;
    let like = twin_ease(b.root.xyz);
    var tau = blade_shape_of(outline, u, v);
    let min_px = frame.blade_style.w;
    if min_px > 0.0 {
        let px = length(to_pixels(edge_b) - to_pixels(edge_a));
        tau = mix(tau, u, clamp(1.0 - px / min_px, 0.0, 1.0) * (1.0 - like));
    }
    var p = mix(edge_a, edge_b, tau);
    if blade_ridge() {
        let fold = select(1.0, SEED_STALK, (outline >> 8u) != 0u);
        p += flat_normal * (w * fold) * (0.5 - abs(u - 0.5)) * (1.0 - v) * (1.0 - like);
    }
    *n = normalize_or_zero(flat_normal + across * ((2.0 * u - 1.0) * BLADE_ROUNDING));
    return p;
}

// A point of the frame's space in Bevy's world (common.glsl `world_point`).
fn world_of(p: vec3<f32>) -> vec3<f32> {
    return vec3(p.x + frame.origin.x, p.y, p.z + frame.origin.y);
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
    let segments = record.y >> 16u;
    var row: u32;
    var u: f32;
    if !blade_ridge() {
        row = vertex >> 1u;
        u = f32(vertex & 1u);
    } else if vertex < 2u * (segments + 1u) {
        row = vertex >> 1u;
        u = 0.5 * f32(vertex & 1u);
    } else {
        let j = vertex - 2u * (segments + 1u);
        row = segments - (j >> 1u);
        u = 0.5 + 0.5 * f32(j & 1u);
    }
    return StripPlace(u, f32(row) / f32(segments), record.x, record.y & 0xffffu);
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
    var n: vec3<f32>;
    out.previous_world_position = world_of(blade_point(previous_blades[at.blade], at.outline, at.u, at.v, &n));
    return out;
}

// The point of drawn blade `drawn` at strip place `at`, where it is now.
fn strip_vertex(drawn: u32, at: StripPlace) -> BladePoint {
    var n: vec3<f32>;
    let p = blade_point(blades[at.blade], at.outline, at.u, at.v, &n);
    var out: BladePoint;
    out.world_position = world_of(p);
    out.previous_world_position = out.world_position;
    out.normal = n;
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
    var n: vec3<f32>;
    let p = blade_point(blades[record.x], record.y & 0xffffu, f32(i & 1u), f32(i >> 1u) / f32(segments), &n);
    return world_of(p);
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
