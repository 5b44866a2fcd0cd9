// The fragment stage of every occluder drawn into the depth pyramid's level 0 (pyramid.wgsl): its
// depth, as the bits of the float (their order is the order of the depths).
@fragment
fn occluder_depth(@builtin(position) at: vec4<f32>) -> @location(0) u32 {
    return bitcast<u32>(at.z);
}
