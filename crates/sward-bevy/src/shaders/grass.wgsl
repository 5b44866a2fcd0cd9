// sward's Bezier blades in Bevy's main pass, lit by Bevy's PBR: its lights and their shadows,
// ambient light and environment maps, exposure, fog and tonemapping, as every Bevy mesh is.
// The blade's look is sward's: its colours (drawn_blades.comp), rounded normals, the fake
// ambient occlusion at the root and translucency as Bevy's diffuse transmission.

#import sward::blades::{blade_vertex, blade_albedo, blade_occlusion, blade_transmission}
#import bevy_pbr::{
    mesh_view_bindings::view,
    pbr_types,
    pbr_functions::{apply_pbr_lighting, main_pass_post_lighting_processing},
    mesh_types::{MESH_FLAGS_SHADOW_RECEIVER_BIT, MESH_FLAGS_TRANSMITTED_SHADOW_RECEIVER_BIT},
    view_transformations::position_world_to_clip,
}

struct GrassVertexOutput {
    @builtin(position) position: vec4<f32>,
    @location(0) world_position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) @interpolate(flat) drawn: u32,
}

@vertex
fn vertex(@builtin(instance_index) instance: u32, @builtin(vertex_index) vertex: u32) -> GrassVertexOutput {
    let point = blade_vertex(instance, vertex);
    var out: GrassVertexOutput;
    out.position = position_world_to_clip(point.world_position);
    out.world_position = point.world_position;
    out.normal = point.normal;
    out.uv = point.uv;
    out.drawn = point.drawn;
    return out;
}

@fragment
fn fragment(in: GrassVertexOutput) -> @location(0) vec4<f32> {
    let V = normalize(view.world_position.xyz - in.world_position);
    // Two-sided: lit from the side the eye sees.
    var n = normalize(in.normal);
    n = select(-n, n, dot(n, V) >= 0.0);
    var pbr = pbr_types::pbr_input_new();
    pbr.material.base_color = vec4(blade_albedo(in.drawn, in.uv.y), 1.0);
    pbr.material.perceptual_roughness = 0.6;
    pbr.material.reflectance = vec3(0.25);
    // Light through the thin blade from behind, stronger toward the tip.
    pbr.material.diffuse_transmission = blade_transmission(in.uv.y);
    pbr.material.flags = pbr_types::STANDARD_MATERIAL_FLAGS_FOG_ENABLED_BIT
        | pbr_types::STANDARD_MATERIAL_FLAGS_DOUBLE_SIDED_BIT;
    pbr.diffuse_occlusion = vec3(blade_occlusion(in.uv));
    pbr.frag_coord = in.position;
    pbr.world_position = vec4(in.world_position, 1.0);
    pbr.world_normal = n;
    pbr.N = n;
    pbr.V = V;
    pbr.is_orthographic = view.clip_from_view[3].w == 1.0;
#ifdef GRASS_RECEIVES_SHADOWS
    pbr.flags = MESH_FLAGS_SHADOW_RECEIVER_BIT | MESH_FLAGS_TRANSMITTED_SHADOW_RECEIVER_BIT;
#endif
    var color = apply_pbr_lighting(pbr);
    color = main_pass_post_lighting_processing(pbr, color);
    return color;
}
