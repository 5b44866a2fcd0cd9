// The portable renderer's depth pyramid (Hi-Z; the Vulkan renderer's depth_pyramid.rs and
// hiz_reduce.comp): the occluders — ground, collider spheres, the nearest blades the last frame
// listed — are drawn from the camera into an image as the bits of their depth (blade.wgsl
// `occluder_depth`: a 32-bit integer target is renderable on every backend, a 32-bit float one
// is not, and a non-negative float's bits sort as the float does), copied here into level 0 of
// the pyramid, and each level is reduced from the one below it, a texel keeping the farthest
// depth of the 2 × 2 under it, so a test against it is conservative. The levels lie one after
// another in a storage buffer (`pyramid_start`): a buffer is read and written alike on every
// backend, where a texture's levels are not (wgpu's GL backend binds a sampled level as the
// texture's only level, and the level written beside it is lost). The cull (cull.wgsl) tests
// blades against it. Needs pyramid_levels.wgsl.

// The occluders as drawn (level 0's texels).
@group(0) @binding(0) var occluders: texture_2d<u32>;
@group(0) @binding(1) var<storage, read_write> levels: array<u32>;
// x: the level this dispatch writes (0: copied from the occluders), y: level 0's side.
@group(0) @binding(2) var<uniform> step: vec4<u32>;

@compute @workgroup_size(8, 8)
fn reduce_level(@builtin(global_invocation_id) id: vec3<u32>) {
    let level = step.x;
    let side = max(step.y >> level, 1u);
    if (any(id.xy >= vec2<u32>(side))) {
        return;
    }
    let at = pyramid_start(step.y, level) + id.y * side + id.x;
    if (level == 0u) {
        levels[at] = textureLoad(occluders, vec2<i32>(id.xy), 0).r;
        return;
    }
    let below = pyramid_start(step.y, level - 1u);
    let wide = side * 2u;
    let corner = below + id.y * 2u * wide + id.x * 2u;
    levels[at] = max(max(levels[corner], levels[corner + 1u]), max(levels[corner + wide], levels[corner + wide + 1u]));
}
