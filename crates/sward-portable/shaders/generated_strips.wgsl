// The generated grass's levels drawn by the portable renderer (the Vulkan renderer's
// instanced.vert): each vertex placed by generated_blades.wgsl, its fragments shaded as the
// Bezier blades' (blade_fragment.wgsl). Needs generated_blades.wgsl, shading.wgsl and
// blade_fragment.wgsl.

@vertex
fn generated_vertex(@builtin(vertex_index) vertex_index: u32, @builtin(instance_index) instance: u32) -> BladeVertex {
    let g = generated_point(vertex_index, instance);
    var out: BladeVertex;
    if (!g.drawn) {
        out.clip = vec4<f32>(0.0, 0.0, -1.0, 1.0); // past a full list: outside the clip volume
        return out;
    }
    out.clip = target_clip(frame.view_proj * vec4<f32>(g.point.position, 1.0));
    out.normal = g.point.normal;
    out.position = g.point.position;
    out.uv = g.point.uv;
    out.look = blade_look(g.hash, world_xz(g.root.xz));
    out.vary = albedo_variation(g.point.position, g.hash, out.look);
    return out;
}
