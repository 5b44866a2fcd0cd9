// The portable renderer's culling and compaction (SPEC §4–5): each blade tested by orientation,
// frustum (kept where its shadow falls in view) and distance (thinned by its id, or cut at the
// streamed field's hand-over), as the Vulkan renderer's culling.glsl and sward-core's cull.rs;
// the survivors listed by distance bucket, nearest first, each bucket a draw command of the
// strips its distance asks for. Three passes: count each bucket's blades, lay the buckets out
// (the commands and where each bucket's list starts), place each blade in its bucket's list.
// The occlusion test (a depth pyramid) is the Vulkan renderer's alone for now: here a blade
// behind an occluder is drawn. Needs frame.wgsl, blade.wgsl and buckets.wgsl.

// The culling tests (`modes.x`; sward-core flags.rs).
const CULL_ORIENTATION: u32 = 1u;
const CULL_FRUSTUM: u32 = 2u;
const CULL_DISTANCE: u32 = 4u;

// A blade no bucket lists.
const NOT_DRAWN: u32 = 0xffffffffu;

@group(0) @binding(1) var<storage, read> blades: array<Blade>;
// The visible blades' indices, bucket by bucket.
@group(0) @binding(3) var<storage, read_write> visible: array<u32>;
// One draw command per distance bucket.
@group(0) @binding(4) var<storage, read_write> draws: array<DrawCommand>;
// Each blade's bucket this frame (NOT_DRAWN: culled).
@group(0) @binding(5) var<storage, read_write> bucket_of: array<u32>;
// Each bucket's count, then the next free place in its list, then where its list starts
// (cleared before the first pass).
@group(0) @binding(6) var<storage, read_write> counters: array<atomic<u32>>;

fn inside_clip(clip: vec4<f32>, tolerance: f32) -> bool {
    let limit = clip.w + tolerance;
    return clip.x >= -limit && clip.x <= limit && clip.y >= -limit && clip.y <= limit
        && clip.z >= -tolerance && clip.z <= limit;
}

fn seen_edge_on(b: Blade, eye: vec3<f32>) -> bool {
    let view_dir = normalize_or_zero(b.v0.xyz - eye);
    return abs(dot(view_dir, width_direction(b.up.xyz, b.v0.w))) > frame.cull.x;
}

// Where blades cast shadows (the sun's near cascade, shading_extra.w around the eye), whether
// the shadow of the blade's tip on the ground through its root lies in view: such a blade is
// kept though it is off screen, so it casts into the view (cull.rs `ShadowCasting`).
fn shadow_in_view(b: Blade, t: f32) -> bool {
    let reach = frame.shading_extra.w;
    if ((frame.modes.w & DRAW_BLADE_SHADOWS) == 0u || distance(b.v0.xyz, frame.camera_position.xyz) >= reach) {
        return false;
    }
    let sun = frame.light_direction.xyz;
    let height = dot(b.v2.xyz - b.v0.xyz, b.up.xyz);
    let shadow = b.v2.xyz - sun * (height / max(dot(sun, b.up.xyz), 0.2));
    return inside_clip(frame.view_proj * vec4<f32>(shadow, 1.0), t);
}

fn outside_frustum(b: Blade) -> bool {
    let mid = 0.25 * b.v0.xyz + 0.5 * b.v1.xyz + 0.25 * b.v2.xyz;
    let t = frame.cull.y;
    return !inside_clip(frame.view_proj * vec4<f32>(b.v0.xyz, 1.0), t)
        && !inside_clip(frame.view_proj * vec4<f32>(mid, 1.0), t)
        && !inside_clip(frame.view_proj * vec4<f32>(b.v2.xyz, 1.0), t)
        && !shadow_in_view(b, t);
}

fn thinned_by_distance(b: Blade, id: u32, eye: vec3<f32>) -> bool {
    let up = b.up.xyz;
    let rel = b.v0.xyz - eye;
    let d_proj = length(rel - up * dot(rel, up));
    let n = max(u32(frame.cull.w), 1u);
    let kept = ceil(f32(n) * (1.0 - d_proj / frame.cull.z));
    return f32(id % n) >= kept;
}

fn is_visible(b: Blade, id: u32) -> bool {
    let eye = frame.camera_position.xyz;
    let tests = frame.modes.x;
    if ((tests & CULL_ORIENTATION) != 0u && seen_edge_on(b, eye)) {
        return false;
    }
    if ((tests & CULL_FRUSTUM) != 0u && outside_frustum(b)) {
        return false;
    }
    if (frame.stream.x > 0u) {
        // The streamed field hands over cell for cell: no thinning, every blade nearer than the
        // hand-over drawn.
        return b.v1.w > 0.0 && distance(b.v0.xyz, eye) < frame.stream_reach.x;
    }
    return (tests & CULL_DISTANCE) == 0u || !thinned_by_distance(b, id, eye);
}

@compute @workgroup_size(64)
fn count_buckets(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = blade_index(id, groups);
    if (i >= frame.counts.x) {
        return;
    }
    let b = blades[i];
    var k = NOT_DRAWN;
    if (is_visible(b, i)) {
        k = distance_bucket(distance(b.v0.xyz, frame.camera_position.xyz));
        atomicAdd(&counters[k], 1u);
    }
    bucket_of[i] = k;
}

// One invocation lays the 64 buckets out: each one's command and where its list starts.
@compute @workgroup_size(1)
fn lay_out_buckets() {
    // Three columns when the ridge folds the blade at u = 0.5, else two.
    let columns = select(2u, 4u, (frame.modes.w & DRAW_BLADE_RIDGE) != 0u);
    var first = 0u;
    for (var k = 0u; k < DISTANCE_BUCKETS; k++) {
        let count = atomicLoad(&counters[k]);
        draws[k] = DrawCommand(columns * (strip_segments(k) + 1u), count, k * STRIP_STRIDE, 0u);
        atomicStore(&counters[DISTANCE_BUCKETS + k], first);
        atomicStore(&counters[BUCKET_STARTS + k], first);
        first += count;
    }
}

@compute @workgroup_size(64)
fn place_blades(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = blade_index(id, groups);
    if (i >= frame.counts.x) {
        return;
    }
    let k = bucket_of[i];
    if (k != NOT_DRAWN) {
        visible[atomicAdd(&counters[DISTANCE_BUCKETS + k], 1u)] = i;
    }
}
