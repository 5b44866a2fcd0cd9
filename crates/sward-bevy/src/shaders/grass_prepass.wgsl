// sward's Bezier blades in Bevy's prepass and deferred G-buffer: depth; normals (SSAO reads
// them); motion vectors from each blade's pose in the last frame and now, with the camera's
// motion (TAA keeps the swaying grass sharp); on a deferred camera, the G-buffer of the same
// PBR input the forward pass lights.

#ifdef SWARD_PORTABLE
#import sward::portable_blades::moving_blade_vertex
#else
#import sward::blades::moving_blade_vertex
#endif
#import sward::blade_pbr::blade_pbr_input
#import bevy_pbr::{
    prepass_io::{VertexOutput, FragmentOutput},
    prepass_bindings::previous_view_uniforms,
    mesh_view_bindings::view,
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
    @location(4) @interpolate(flat) colour: vec3<u32>,
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
    out.colour = point.colour;
    return out;
}

#ifdef PREPASS_FRAGMENT
@fragment
fn fragment(in: GrassPrepassOutput) -> FragmentOutput {
    var out: FragmentOutput;
#ifdef DEFERRED_PREPASS
    let pbr = blade_pbr_input(in.position, in.world_position, in.normal, in.uv, in.colour, view.world_position.xyz, false);
    let n = pbr.N;
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
    // The side the eye sees, as the lighting turns it.
    let to_eye = view.world_position.xyz - in.world_position;
    let n = normalize(in.normal) * select(-1.0, 1.0, dot(in.normal, to_eye) >= 0.0);
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
