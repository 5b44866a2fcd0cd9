// sward's Bezier blades in Bevy's prepass and deferred G-buffer: depth; normals (SSAO reads
// them); motion vectors from each blade's pose in the last frame and now, with the camera's
// motion (TAA keeps the swaying grass sharp); on a deferred camera, the G-buffer of the same
// PBR input the forward pass lights.

#import sward::blades::{moving_blade_vertex, blade_albedo, blade_occlusion, blade_transmission, frame}
#import bevy_pbr::{
    prepass_io::{VertexOutput, FragmentOutput},
    prepass_bindings::previous_view_uniforms,
    mesh_view_bindings::view,
    pbr_types,
    mesh_types::{MESH_FLAGS_SHADOW_RECEIVER_BIT, MESH_FLAGS_TRANSMITTED_SHADOW_RECEIVER_BIT},
}
#ifdef DEFERRED_PREPASS
#import bevy_pbr::pbr_deferred_functions::deferred_output
#endif

struct GrassPrepassOutput {
    @builtin(position) position: vec4<f32>,
    @location(0) world_position: vec3<f32>,
    @location(1) previous_world_position: vec3<f32>,
    @location(2) normal: vec3<f32>,
    @location(3) uv: vec2<f32>,
    @location(4) @interpolate(flat) drawn: u32,
}

@vertex
fn vertex(@builtin(instance_index) instance: u32, @builtin(vertex_index) vertex: u32) -> GrassPrepassOutput {
    let point = moving_blade_vertex(instance, vertex);
    var out: GrassPrepassOutput;
    out.position = view.clip_from_world * vec4(point.world_position, 1.0);
    out.world_position = point.world_position;
    out.previous_world_position = point.previous_world_position;
    out.normal = point.normal;
    out.uv = point.uv;
    out.drawn = point.drawn;
    return out;
}

#ifdef PREPASS_FRAGMENT
@fragment
fn fragment(in: GrassPrepassOutput) -> FragmentOutput {
    let V = normalize(view.world_position.xyz - in.world_position);
    var n = normalize(in.normal);
    n = select(-n, n, dot(n, V) >= 0.0);
    var out: FragmentOutput;
#ifdef DEFERRED_PREPASS
    var pbr = pbr_types::pbr_input_new();
    // The G-buffer holds no diffuse transmission: the blade's diffuse colour keeps the share the
    // forward pass leaves it (grass.wgsl), and light through it from behind is lost.
    pbr.material.base_color = vec4(blade_albedo(in.drawn, in.uv.y) * (1.0 - blade_transmission(in.uv.y)), 1.0);
    pbr.material.perceptual_roughness = 0.6;
    pbr.material.reflectance = vec3(0.25);
    pbr.material.flags = pbr_types::STANDARD_MATERIAL_FLAGS_FOG_ENABLED_BIT
        | pbr_types::STANDARD_MATERIAL_FLAGS_DOUBLE_SIDED_BIT;
    pbr.diffuse_occlusion = vec3(blade_occlusion(in.uv));
    pbr.frag_coord = in.position;
    pbr.world_position = vec4(in.world_position, 1.0);
    pbr.world_normal = n;
    pbr.N = n;
    pbr.V = V;
#ifdef GRASS_RECEIVES_SHADOWS
    pbr.flags = MESH_FLAGS_SHADOW_RECEIVER_BIT | MESH_FLAGS_TRANSMITTED_SHADOW_RECEIVER_BIT;
#endif
    var io: VertexOutput;
    io.position = in.position;
    io.world_position = vec4(in.world_position, 1.0);
    io.world_normal = n;
#ifdef MOTION_VECTOR_PREPASS
    io.previous_world_position = vec4(in.previous_world_position, 1.0);
#endif
    out = deferred_output(io, pbr);
#else
#ifdef NORMAL_PREPASS
    out.normal = vec4(n * 0.5 + vec3(0.5), 1.0);
#endif
#ifdef MOTION_VECTOR_PREPASS
    let now = view.unjittered_clip_from_world * vec4(in.world_position, 1.0);
    let before = previous_view_uniforms.clip_from_world * vec4(in.previous_world_position, 1.0);
    // As Bevy's prepass writes them: a UV offset, y down.
    out.motion_vector = (now.xy / now.w - before.xy / before.w) * vec2(0.5, -0.5);
#endif
#endif
    return out;
}
#endif
