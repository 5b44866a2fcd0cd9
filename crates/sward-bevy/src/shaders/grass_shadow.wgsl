// sward's Bezier blades into Bevy's shadow maps, seen from the light (Bevy's shadow views: the
// sun's cascades, point and spot lights), depth only: the blades' outlines in coarser strips
// than the camera's (blades.wgsl `shadow_blade_vertex`).

#ifdef SWARD_PORTABLE
#import sward::portable_blades::shadow_blade_vertex
#else
#import sward::blades::shadow_blade_vertex
#endif
#import bevy_render::view::View

@group(0) @binding(0) var<uniform> view: View;

@vertex
fn vertex(@builtin(instance_index) instance: u32, @builtin(vertex_index) vertex: u32) -> @builtin(position) vec4<f32> {
    return view.clip_from_world * vec4(shadow_blade_vertex(instance, vertex), 1.0);
}
