// A drawn blade's vertex as its fragments read it, and their shading (shading.wgsl): the
// Bezier blades' strips and the generated grass's draw the same. Needs frame.wgsl, blade.wgsl,
// noise.wgsl and shading.wgsl.

struct BladeVertex {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) position: vec3<f32>,
    // u across the blade, v from root to tip.
    @location(2) uv: vec2<f32>,
    // Its colour variation (shading.wgsl `albedo_variation`) at the vertex, interpolated
    // (blade.frag says why).
    @location(3) vary: vec3<f32>,
    // Its look (found once, at its root).
    @location(4) @interpolate(flat) look: vec2<u32>,
}

@fragment
fn strip_fragment(in: BladeVertex) -> @location(0) vec4<f32> {
    return guard_color(shade_blade_lit(in.normal, in.position, in.uv, in.look, in.vary, sunlight(in.position)));
}
