// The portable renderer's depth pyramid (Hi-Z; the Vulkan renderer's depth_pyramid.rs and
// hiz_reduce.comp): the occluders — ground, collider spheres, the nearest blades the last frame
// listed — are drawn from the camera into level 0 as the bits of their depth (blade.wgsl
// `occluder_depth`: a 32-bit integer target is renderable on every backend, a 32-bit float one
// is not, and a non-negative float's bits sort as the float does), then each level is reduced
// here from the one below it, a texel keeping the farthest depth of the 2 × 2 under it, so a
// test against it is conservative. The cull (cull.wgsl) tests blades against it. Stands alone.

// The level below, and the level this dispatch writes.
@group(0) @binding(0) var finer: texture_2d<u32>;
@group(0) @binding(1) var coarser: texture_storage_2d<r32uint, write>;

@compute @workgroup_size(8, 8)
fn reduce_level(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(coarser);
    if (any(id.xy >= size)) {
        return;
    }
    let below = vec2<i32>(textureDimensions(finer)) - 1;
    let at = vec2<i32>(id.xy) * 2;
    let a = textureLoad(finer, min(at, below), 0).r;
    let b = textureLoad(finer, min(at + vec2<i32>(1, 0), below), 0).r;
    let c = textureLoad(finer, min(at + vec2<i32>(0, 1), below), 0).r;
    let d = textureLoad(finer, min(at + vec2<i32>(1, 1), below), 0).r;
    textureStore(coarser, vec2<i32>(id.xy), vec4<u32>(max(max(a, b), max(c, d)), 0u, 0u, 1u));
}
