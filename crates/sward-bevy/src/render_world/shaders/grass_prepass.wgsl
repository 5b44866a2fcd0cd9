// sward's grass in Bevy's prepass and deferred G-buffer: depth; normals (SSAO reads them);
// motion vectors from each Bezier blade's pose in the last frame and now, with the camera's
// motion (TAA keeps the swaying grass sharp), the far grass's (GRASS_FAR) from the camera's
// alone; on a deferred camera, the G-buffer of the same PBR input the forward pass lights. A
// billboard's fragment is drawn where its painted blades cover half of it.

#ifdef GRASS_FAR
#import sward::far_grass::{far_vertex, not_drawn}
#else ifdef SWARD_PORTABLE
#import sward::portable_blades::moving_blade_vertex
#else
#import sward::blades::moving_blade_vertex
#endif
#ifdef GRASS_BILLBOARDS
#import sward::portable::{billboard_painted, painted_detail}
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
#ifndef GRASS_FAR
    // The far grass stood where it stands (its motion vectors are the camera's).
    @location(1) previous_world_position: vec3<f32>,
#endif
    @location(2) normal: vec3<f32>,
    @location(3) uv: vec2<f32>,
    @location(4) @interpolate(flat) colour: vec3<u32>,
    @location(5) @interpolate(flat) layers: f32,
}

@vertex
fn vertex(@builtin(instance_index) instance: u32, @builtin(vertex_index) vertex: u32) -> GrassPrepassOutput {
    var out: GrassPrepassOutput;
#ifdef GRASS_FAR
    let point = far_vertex(instance, vertex);
    out.position = select(not_drawn(), view.clip_from_world * vec4(point.world_position, 1.0), point.drawn);
    out.layers = point.layers;
#else
    let point = moving_blade_vertex(instance, vertex);
    out.position = view.clip_from_world * vec4(point.world_position, 1.0);
    out.previous_world_position = point.previous_world_position;
    out.layers = 1.0;
#endif
    out.world_position = point.world_position;
    out.normal = point.normal;
    out.uv = point.uv;
    out.colour = point.colour;
    return out;
}

// Where the fragment's point was in the last frame.
fn previous_position(in: GrassPrepassOutput) -> vec3<f32> {
#ifdef GRASS_FAR
    return in.world_position;
#else
    return in.previous_world_position;
#endif
}

#ifdef GRASS_BILLBOARDS
// Depth alone (no prepass targets): a billboard where its painted blades cover half the
// fragment.
@fragment
fn coverage_fragment(in: GrassPrepassOutput) {
    if (billboard_painted(in.uv, in.layers).a < 0.5) {
        discard;
    }
}
#endif

#ifdef PREPASS_FRAGMENT
@fragment
fn fragment(in: GrassPrepassOutput) -> FragmentOutput {
    var out: FragmentOutput;
#ifdef GRASS_BILLBOARDS
    let painted = billboard_painted(in.uv, in.layers);
    if (painted.a < 0.5) {
        discard;
    }
    // Lit as the blades beside it, at the height in the billboard the fragment stands.
    let uv = vec2(0.3, 1.0 - in.uv.y);
#else
    let uv = in.uv;
#endif
#ifdef DEFERRED_PREPASS
    var pbr = blade_pbr_input(in.position, in.world_position, in.normal, uv, in.colour, view.world_position.xyz, false);
#ifdef GRASS_BILLBOARDS
    pbr.material.base_color = vec4(pbr.material.base_color.rgb * painted_detail(painted), 1.0);
#endif
    let n = pbr.N;
    var io: VertexOutput;
    io.position = in.position;
    io.world_position = vec4(in.world_position, 1.0);
    io.world_normal = n;
#ifdef MOTION_VECTOR_PREPASS
    io.previous_world_position = vec4(previous_position(in), 1.0);
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
    let before = previous_view_uniforms.clip_from_world * vec4(previous_position(in), 1.0);
    // As Bevy's prepass writes them: a UV offset, y down.
    out.motion_vector = (now.xy / now.w - before.xy / before.w) * vec2(0.5, -0.5);
#endif
#endif
    return out;
}
#endif
