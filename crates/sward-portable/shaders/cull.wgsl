// The portable renderer's culling and compaction (SPEC §4–5): each blade tested by orientation,
// frustum (kept where its shadow falls in view) and distance (thinned by its id, or cut at the
// streamed field's hand-over), as the Vulkan renderer's culling.glsl and sward-core's cull.rs;
// the survivors listed by distance bucket, nearest first, each bucket a draw command of the
// strips its distance asks for. Three passes: count each bucket's blades, lay the buckets out
// (the commands and where each bucket's list starts), place each blade in its bucket's list.
// Blades behind the depth pyramid's occluders (pyramid.wgsl) are culled as the Vulkan
// renderer's are. Needs frame.wgsl, blade.wgsl, buckets.wgsl, pyramid_levels.wgsl, occlusion.wgsl,
// tiles.wgsl and a way for a blade to join its bucket's run: cull_join.wgsl, or with subgroups
// cull_join_subgroups.wgsl.

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
// The tiles this frame runs for the view (tiles.wgsl): the count and place passes take the
// same blades.
@group(0) @binding(10) var<storage, read> active_tiles: array<vec4<u32>>;

fn inside_clip(clip: vec4<f32>, tolerance: f32) -> bool {
    let limit = clip.w + tolerance;
    return clip.x >= -limit && clip.x <= limit && clip.y >= -limit && clip.y <= limit
        && clip.z >= -tolerance && clip.z <= limit;
}

fn seen_edge_on(b: Blade, eye: vec3<f32>) -> bool {
    let view_dir = normalize_or_zero(b.root.xyz - eye);
    return abs(dot(view_dir, width_direction(b.up.xyz, b.root.w))) > frame.cull.x;
}

// Where blades cast shadows (the sun's near cascade, shading_extra.w around the eye), whether
// the shadow of the blade's tip on the ground through its root lies in view: such a blade is
// kept though it is off screen, so it casts into the view (cull.rs `ShadowCasting`).
fn shadow_in_view(b: Blade, t: f32) -> bool {
    let reach = frame.shading_extra.w;
    if ((frame.modes.w & DRAW_BLADE_SHADOWS) == 0u || distance(b.root.xyz, frame.camera_position.xyz) >= reach) {
        return false;
    }
    let sun = frame.light_direction.xyz;
    let height = dot(b.tip.xyz - b.root.xyz, b.up.xyz);
    let shadow = b.tip.xyz - sun * (height / max(dot(sun, b.up.xyz), 0.2));
    return inside_clip(frame.view_proj * vec4<f32>(shadow, 1.0), t);
}

fn outside_frustum(b: Blade) -> bool {
    let mid = 0.25 * b.root.xyz + 0.5 * b.guide.xyz + 0.25 * b.tip.xyz;
    let t = frame.cull.y;
    return !inside_clip(frame.view_proj * vec4<f32>(b.root.xyz, 1.0), t)
        && !inside_clip(frame.view_proj * vec4<f32>(mid, 1.0), t)
        && !inside_clip(frame.view_proj * vec4<f32>(b.tip.xyz, 1.0), t)
        && !shadow_in_view(b, t);
}

fn thinned_by_distance(b: Blade, id: u32, eye: vec3<f32>) -> bool {
    let up = b.up.xyz;
    let rel = b.root.xyz - eye;
    let d_proj = length(rel - up * dot(rel, up));
    let n = max(u32(frame.cull.w), 1u);
    let kept = ceil(f32(n) * (1.0 - d_proj / frame.cull.z));
    return f32(id % n) >= kept;
}

// ---------------------------------------------------------------- occlusion (culling.glsl, hiz.glsl)

// The pyramid level the three-point test reads: texels of 2 × 2 occluder pixels, the farthest of
// the 2 × 2 texels around a point taken, so an occluder's edge a pixel off never hides what is
// beside it.
const HIZ_LEVEL: i32 = 1;

// Whether point p lies behind the occluders by more than the tolerance (never off screen).
fn hidden(p: vec3<f32>) -> bool {
    let clip = frame.view_proj * vec4<f32>(p, 1.0);
    if (clip.w <= 0.0) {
        return false;
    }
    let ndc = clip.xyz / clip.w;
    if (any(abs(ndc.xy) > vec2<f32>(1.0)) || ndc.z < 0.0 || ndc.z > 1.0) {
        return false;
    }
    let size = vec2<i32>(pyramid_side(HIZ_LEVEL));
    let corner = clamp(vec2<i32>(floor((ndc.xy * 0.5 + 0.5) * vec2<f32>(size) - 0.5)), vec2<i32>(0), size - 2);
    let farthest = max(
        max(pyramid_depth(corner, HIZ_LEVEL), pyramid_depth(corner + vec2<i32>(1, 0), HIZ_LEVEL)),
        max(pyramid_depth(corner + vec2<i32>(0, 1), HIZ_LEVEL), pyramid_depth(corner + vec2<i32>(1, 1), HIZ_LEVEL)));
    return view_depth(ndc.z) > view_depth(farthest) + frame.coarse_cull.y;
}

// Pieces of the curve blade_hidden tests one by one.
const BLADE_PIECES: i32 = 4;

// Whether a ball of radius r swept along a–b lies wholly behind what the pyramid holds: its
// screen box and nearest depth bounded from the view-projection's rows.
fn capsule_hidden(a: vec3<f32>, b: vec3<f32>, r: f32) -> bool {
    let m = frame.view_proj;
    let pad = r * vec3<f32>(
        length(vec3<f32>(m[0][0], m[1][0], m[2][0])),
        length(vec3<f32>(m[0][1], m[1][1], m[2][1])),
        length(vec3<f32>(m[0][3], m[1][3], m[2][3])));
    var lo = vec2<f32>(1e30);
    var hi = vec2<f32>(-1e30);
    var nearest = 1e30;
    let ends = array<vec4<f32>, 2>(m * vec4<f32>(a, 1.0), m * vec4<f32>(b, 1.0));
    for (var i = 0; i < 2; i++) {
        let clip = ends[i];
        let w_near = clip.w - pad.z;
        if (w_near <= frame.coarse_cull.z) {
            return false; // reaches the near plane
        }
        let w_far = clip.w + pad.z;
        let corners = vec4<f32>(clip.xy - pad.xy, clip.xy + pad.xy);
        lo = min(lo, min(corners.xy / w_near, corners.xy / w_far));
        hi = max(hi, max(corners.zw / w_near, corners.zw / w_far));
        nearest = min(nearest, w_near);
    }
    return screen_box_hidden(lo, hi, nearest);
}

fn curve_point(b: Blade, t: f32) -> vec3<f32> {
    let s = 1.0 - t;
    return s * s * b.root.xyz + 2.0 * s * t * b.guide.xyz + t * t * b.tip.xyz;
}

// Whether the whole blade lies behind the pyramid (with blade occluders, whose gaps a test of
// three points would see through): the curve in pieces, each chord carrying a ball of 1.2 w
// plus how far the curve strays from it.
fn blade_hidden(b: Blade) -> bool {
    let dt = 1.0 / f32(BLADE_PIECES);
    let r = 1.2 * b.tip.w + length(b.root.xyz - 2.0 * b.guide.xyz + b.tip.xyz) * dt * dt * 0.25;
    var a = b.root.xyz;
    for (var i = 1; i <= BLADE_PIECES; i++) {
        let next = curve_point(b, f32(i) * dt);
        if (!capsule_hidden(a, next, r)) {
            return false;
        }
        a = next;
    }
    return true;
}

// SPEC §4 occlusion: hidden at t = 0.1, 0.5 and 1, or with blade occluders wholly hidden. A
// blade that casts into the near shadow cascade is kept: its shadow may fall where it is seen.
fn occluded(b: Blade) -> bool {
    if (frame.occlusion.x > 0u) {
        let casts = (frame.modes.w & DRAW_BLADE_SHADOWS) != 0u
            && distance(b.root.xyz, frame.camera_position.xyz) < frame.shading_extra.w;
        return !casts && blade_hidden(b);
    }
    return hidden(curve_point(b, 0.1)) && hidden(curve_point(b, 0.5)) && hidden(curve_point(b, 1.0));
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
        if (b.guide.w <= 0.0 || distance(b.root.xyz, eye) >= frame.stream_reach.x) {
            return false;
        }
    } else if ((tests & CULL_DISTANCE) != 0u && thinned_by_distance(b, id, eye)) {
        return false;
    }
    return (tests & CULL_OCCLUSION) == 0u || !occluded(b);
}

// A workgroup's blades per distance bucket, then (placing) where its run of each bucket starts
// in the list: the workgroup adds to the global counters once per bucket, not once per blade,
// since the atomics of every blade on 64 counters were the pass's cost.
var<workgroup> group_counts: array<atomic<u32>, DISTANCE_BUCKETS>;
var<workgroup> group_starts: array<u32, DISTANCE_BUCKETS>;

@compute @workgroup_size(64)
fn count_buckets(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    let taken = tiled_blade(id, groups);
    var k = NOT_DRAWN;
    if (taken.taken) {
        let i = taken.index;
        let b = blades[i];
        if (taken.drawn && is_visible(b, i)) {
            k = distance_bucket(distance(b.root.xyz, frame.camera_position.xyz));
        }
        bucket_of[i] = k;
    }
    // Every invocation, in uniform control flow (cull_join*.wgsl).
    _ = join_bucket(k, lane);
    workgroupBarrier();
    for (var k = lane; k < DISTANCE_BUCKETS; k += WORKGROUP) {
        let n = atomicLoad(&group_counts[k]);
        if (n > 0u) {
            atomicAdd(&counters[k], n);
        }
    }
}

// One invocation lays the 64 buckets out: each one's command and where its list starts.
@compute @workgroup_size(1)
fn lay_out_buckets() {
    // Three columns when the ridge folds the blade at u = 0.5, else two.
    let columns = select(2u, 4u, (frame.modes.w & DRAW_BLADE_RIDGE) != 0u);
    var first = 0u;
    var drawn = 0u;
    for (var k = 0u; k < DISTANCE_BUCKETS; k++) {
        let count = atomicLoad(&counters[k]);
        draws[k] = DrawCommand(columns * (strip_segments(k) + 1u), count, k * STRIP_STRIDE, 0u);
        atomicStore(&counters[DISTANCE_BUCKETS + k], first);
        atomicStore(&counters[BUCKET_STARTS + k], first);
        first += count;
        drawn = select(drawn, k + 1u, count > 0u);
    }
    atomicStore(&counters[DRAWN_BUCKETS], drawn);
    // The list is nearest bucket first: its start is the nearest blades.
    draws[COMMAND_OCCLUDERS] = DrawCommand(2u * (OCCLUDER_SEGMENTS + 1u), min(first, frame.occlusion.x), 0u, 0u);
}

// Each listed blade at its place: the workgroup takes a run of each bucket's list for its
// blades of that bucket (one atomic per bucket), each blade its place in the run.
@compute @workgroup_size(64)
fn place_blades(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    let taken = tiled_blade(id, groups);
    var k = NOT_DRAWN;
    if (taken.taken) {
        k = bucket_of[taken.index];
    }
    let place = join_bucket(k, lane);
    workgroupBarrier();
    for (var bucket = lane; bucket < DISTANCE_BUCKETS; bucket += WORKGROUP) {
        let n = atomicLoad(&group_counts[bucket]);
        if (n > 0u) {
            group_starts[bucket] = atomicAdd(&counters[DISTANCE_BUCKETS + bucket], n);
        }
    }
    workgroupBarrier();
    if (k != NOT_DRAWN) {
        visible[group_starts[k] + place] = taken.index;
    }
}
