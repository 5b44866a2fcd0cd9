// sward's grass in Bevy's main pass, lit by Bevy's PBR: its lights and their shadows, ambient
// light and environment maps, exposure, fog and tonemapping, as every Bevy mesh is. The
// blade's look is sward's: its colours (drawn_blades.comp), rounded normals, the fake ambient
// occlusion at the root and translucency as Bevy's diffuse transmission. GRASS_FAR draws the
// far grass (far_grass.wgsl: the generated levels, or with GRASS_BILLBOARDS the billboards,
// their painted texture's coverage by alpha-to-coverage where GRASS_COVERAGE, else cut at half).

#ifdef GRASS_FAR
#import sward::far_grass::{far_vertex, not_drawn}
#else ifdef SWARD_PORTABLE
#import sward::portable_blades::blade_vertex
#else
#import sward::blades::blade_vertex
#endif
#ifdef GRASS_BILLBOARDS
#import sward::portable::{billboard_painted, painted_detail}
#endif
#import sward::blade_pbr::blade_pbr_input
#import bevy_pbr::{
    mesh_view_bindings::view,
    pbr_functions::{apply_pbr_lighting, main_pass_post_lighting_processing},
    view_transformations::position_world_to_clip,
}

struct GrassVertexOutput {
    @builtin(position) position: vec4<f32>,
    @location(0) world_position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) @interpolate(flat) colour: vec3<u32>,
    @location(4) @interpolate(flat) layers: f32,
}

@vertex
fn vertex(@builtin(instance_index) instance: u32, @builtin(vertex_index) vertex: u32) -> GrassVertexOutput {
    var out: GrassVertexOutput;
#ifdef GRASS_FAR
    let point = far_vertex(instance, vertex);
    out.layers = point.layers;
    out.position = select(not_drawn(), position_world_to_clip(point.world_position), point.drawn);
#else
    let point = blade_vertex(instance, vertex);
    out.layers = 1.0;
    out.position = position_world_to_clip(point.world_position);
#endif
    out.world_position = point.world_position;
    out.normal = point.normal;
    out.uv = point.uv;
    out.colour = point.colour;
    return out;
}

@fragment
fn fragment(in: GrassVertexOutput) -> @location(0) vec4<f32> {
#ifdef GRASS_BILLBOARDS
    let painted = billboard_painted(in.uv, in.layers);
#ifndef GRASS_COVERAGE
    if (painted.a < 0.5) {
        discard;
    }
#endif
    // Lit as the blades beside it, at the height in the billboard the fragment stands.
    let uv = vec2(0.3, 1.0 - in.uv.y);
#else
    let uv = in.uv;
#endif
    var pbr = blade_pbr_input(in.position, in.world_position, in.normal, uv, in.colour, view.world_position.xyz, true);
#ifdef GRASS_BILLBOARDS
    pbr.material.base_color = vec4(pbr.material.base_color.rgb * painted_detail(painted), 1.0);
#endif
    pbr.is_orthographic = view.clip_from_view[3].w == 1.0;
    var color = apply_pbr_lighting(pbr);
    color = main_pass_post_lighting_processing(pbr, color);
#ifdef GRASS_COVERAGE
    color.a = painted.a;
#endif
    return color;
}
