// sward's Bezier blades into Bevy's shadow maps: the same strips as the main pass draws, seen
// from the light (Bevy's shadow views: the sun's cascades, point and spot lights), depth only.

#import sward::blades::blade_vertex
#import bevy_render::view::View

@group(0) @binding(0) var<uniform> view: View;

@vertex
fn vertex(@builtin(instance_index) instance: u32, @builtin(vertex_index) vertex: u32) -> @builtin(position) vec4<f32> {
    let point = blade_vertex(instance, vertex);
    return view.clip_from_world * vec4(point.world_position, 1.0);
}
