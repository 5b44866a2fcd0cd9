// sward's Bezier blades in Bevy's main pass, lit by Bevy's PBR: its lights and their shadows,
// ambient light and environment maps, exposure, fog and tonemapping, as every Bevy mesh is.
// The blade's look is sward's: its colours (drawn_blades.comp), rounded normals, the fake
// ambient occlusion at the root and translucency as Bevy's diffuse transmission.

#ifdef SWARD_PORTABLE
#import sward::portable_blades::blade_vertex
#else
#import sward::blades::blade_vertex
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
}

@vertex
fn vertex(@builtin(instance_index) instance: u32, @builtin(vertex_index) vertex: u32) -> GrassVertexOutput {
    let point = blade_vertex(instance, vertex);
    var out: GrassVertexOutput;
    out.position = position_world_to_clip(point.world_position);
    out.world_position = point.world_position;
    out.normal = point.normal;
    out.uv = point.uv;
    out.colour = point.colour;
    return out;
}

@fragment
fn fragment(in: GrassVertexOutput) -> @location(0) vec4<f32> {
    var pbr = blade_pbr_input(in.position, in.world_position, in.normal, in.uv, in.colour, view.world_position.xyz, true);
    pbr.is_orthographic = view.clip_from_view[3].w == 1.0;
    var color = apply_pbr_lighting(pbr);
    color = main_pass_post_lighting_processing(pbr, color);
    return color;
}
