// The billboards drawn by the portable renderer (the Vulkan renderer's billboard.vert and
// billboard.frag): each vertex placed by billboard_quads.wgsl; the painted texture's alpha
// drives alpha-to-coverage, its colour lit by the blades' own shading. Needs
// billboard_quads.wgsl.

struct BillboardVertex {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) position: vec3<f32>,
    // The texture's coordinates (row 0 holds the tips).
    @location(2) uv: vec2<f32>,
    // Its colour variation at the vertex (blade.frag says why).
    @location(3) vary: vec3<f32>,
    @location(4) @interpolate(flat) layers: f32,
    // What its colour comes from (shading.wgsl `blade_look`), found once per billboard.
    @location(5) @interpolate(flat) look: vec2<u32>,
}

@vertex
fn billboard_vertex(@builtin(vertex_index) vertex_index: u32, @builtin(instance_index) instance: u32) -> BillboardVertex {
    let b = billboard_corner(vertex_index, instance);
    var out: BillboardVertex;
    if (!b.drawn) {
        out.clip = vec4<f32>(0.0, 0.0, -1.0, 1.0); // a triangle the billboard does not make
        return out;
    }
    out.clip = target_clip(frame.view_proj * vec4<f32>(b.position, 1.0));
    out.normal = b.normal;
    out.position = b.position;
    out.uv = b.uv;
    out.layers = b.layers;
    out.look = blade_look(b.hash, world_xz(b.root.xz));
    out.vary = albedo_variation(b.position, b.hash, out.look);
    return out;
}

@fragment
fn billboard_fragment(in: BillboardVertex) -> @location(0) vec4<f32> {
    let painted = billboard_painted(in.uv, in.layers);
    let lit = shade_blade_lit(in.normal, in.position, vec2<f32>(0.3, 1.0 - in.uv.y), in.look, in.vary, sunlight(in.position));
    return vec4<f32>(guard_color(lit * painted_detail(painted)).rgb, painted.a);
}
