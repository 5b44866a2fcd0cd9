// sward's grass into Bevy's shadow maps, seen from the light (Bevy's shadow views: the sun's
// cascades, point and spot lights), depth only: the Bezier blades' outlines in coarser strips
// than the camera's (blades.wgsl `shadow_blade_vertex`); the far grass (GRASS_FAR) within the
// grass's shadow distance of the camera, a billboard where its painted blades cover half the
// fragment.

#ifdef GRASS_FAR
#import sward::far_grass::{far_vertex, casts, not_drawn}
#else ifdef SWARD_PORTABLE
#import sward::portable_blades::shadow_blade_vertex
#else
#import sward::blades::shadow_blade_vertex
#endif
#ifdef GRASS_BILLBOARDS
#import sward::portable::billboard_painted
#endif
#import bevy_render::view::View

@group(0) @binding(0) var<uniform> view: View;

struct ShadowVertex {
    @builtin(position) position: vec4<f32>,
    // A billboard's texture coordinates and layers.
    @location(0) uv: vec2<f32>,
    @location(1) @interpolate(flat) layers: f32,
}

@vertex
fn vertex(@builtin(instance_index) instance: u32, @builtin(vertex_index) vertex: u32) -> ShadowVertex {
    var out: ShadowVertex;
#ifdef GRASS_FAR
    let point = far_vertex(instance, vertex);
    out.position = select(not_drawn(), view.clip_from_world * vec4(point.world_position, 1.0), casts(point));
    out.uv = point.uv;
    out.layers = point.layers;
#else
    out.position = view.clip_from_world * vec4(shadow_blade_vertex(instance, vertex), 1.0);
#endif
    return out;
}

#ifdef GRASS_BILLBOARDS
// A billboard's fragment is in the shadow map where its painted blades cover half of it.
@fragment
fn coverage_fragment(in: ShadowVertex) {
    if (billboard_painted(in.uv, in.layers).a < 0.5) {
        discard;
    }
}
#endif
