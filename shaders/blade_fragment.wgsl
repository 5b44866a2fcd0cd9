// A drawn blade's vertex as its fragments read it, and their shading (shading.wgsl): the
// Bezier blades' strips and the generated grass's draw the same. Needs frame.wgsl, blade.wgsl,
// noise.wgsl and shading.wgsl.

struct BladeVertex {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) position: vec3<f32>,
    // u across the blade, v from root to tip.
    @location(2) uv: vec2<f32>,
    // What the blade's colour varies by, and its look (found once, at its root).
    @location(3) @interpolate(flat) blade: u32,
    @location(4) @interpolate(flat) look: vec2<u32>,
}

@fragment
fn strip_fragment(in: BladeVertex) -> @location(0) vec4<f32> {
    return guard_color(shade_blade_look(in.normal, in.position, in.uv, in.blade, in.look));
}
