// The generated grass on the portable renderer (SPEC §7 [F]; the Vulkan renderer's
// patch_cull.comp, instanced_pass.glsl and generated_scan.comp where it splats nothing): no
// blade is stored; each frame makes the instanced grass's blade of every grid cell around the
// eye from the cell's hash (twin.wgsl `instanced_twin`), culls it and lists it at its level of
// detail, posed, for the draw (generated_strips.wgsl). Four passes:
//   cull_patches      one workgroup: the grid patches around the eye, in the ring order the
//                     host laid out once (nearest rings first), kept where they reach into the
//                     cut-off radius and out of the inner radius, touch the view frustum and are
//                     not wholly behind the depth pyramid's occluders; written as the rows the
//                     next passes run over, with their dispatch sizes. Also resets the draws.
//   count_generated   a row of workgroups per kept patch, an invocation per cell: each
//                     workgroup's blades per level, summed into the levels' draw commands.
//   scan_generated    a workgroup per level: each workgroup's count becomes how many of the
//                     level's blades the workgroups before it hold.
//   place_generated   the blades made again, each at its level's list after those of the
//                     workgroups and invocations before it — a place the grid decides, not the
//                     order workgroups ran in, so the lists are the same every run (and the
//                     Vulkan renderer's).
// Needs frame.wgsl, blade.wgsl, noise.wgsl, buckets.wgsl, shading.wgsl, trample_map.wgsl,
// physics.wgsl, ground_grid.wgsl, stream_cells.wgsl (a cell's hash), outline.wgsl, twin.wgsl,
// pyramid_levels.wgsl and occlusion.wgsl.

// The trample map (trample_map.wgsl), as this frame's trample pass left it.
@group(0) @binding(9) var<storage, read> trample_texels: array<vec4<u32>>;
// The patch rows the counting and placing passes run over (cull_patches writes them), then
// from `patch_cull.x` the ring order of offsets around the eye's patch (the host's, once).
@group(0) @binding(11) var<storage, read_write> patches: array<vec4<i32>>;
// The levels' visible lists, one after another (`instanced_lists`), 32 bytes a blade.
@group(0) @binding(12) var<storage, read_write> listed: array<vec4<u32>>;
// One draw command per level: vertices, instances, first vertex, first instance.
@group(0) @binding(13) var<storage, read_write> level_draws: array<atomic<u32>>;
// Word 0 the counting pass's workgroups; then per level, per workgroup its blades (counting),
// then where they start in the level's list (scanned).
@group(0) @binding(14) var<storage, read_write> group_counts: array<u32>;
// The counting and placing passes' dispatch sizes (x, y, z each).
@group(0) @binding(15) var<storage, read_write> generated_dispatch: array<u32>;

// Cells along a patch's side, and in a patch (instanced.rs).
const PATCH_CELLS: i32 = 32;
const PATCH_BLADES: u32 = 1024u;
// Invocations of a generating workgroup, and its workgroups across a patch's row.
const GENERATE_GROUP: u32 = 256u;
const GROUPS_ACROSS: u32 = 4u;
// The instanced grass's levels of detail (instanced.rs `LOD_SEGMENTS`: 8, 4, 2, 1 rows).
const LEVELS: u32 = 4u;
// Patches at most in a dispatch's rows (WebGPU's default limit).
const MAX_ROWS: u32 = 65535u;

// ---------------------------------------------------------------- the patches

// Whether the box lo–hi lies wholly behind this frame's occluders (patch_cull.comp).
fn box_behind_occluders(lo: vec3<f32>, hi: vec3<f32>) -> bool {
    var ndc_lo = vec2<f32>(1e30);
    var ndc_hi = vec2<f32>(-1e30);
    var nearest = 1e30;
    for (var i = 0u; i < 8u; i++) {
        let corner = select(lo, hi, vec3<bool>((i & 1u) != 0u, (i & 2u) != 0u, (i & 4u) != 0u));
        let clip = frame.view_proj * vec4<f32>(corner, 1.0);
        if (clip.w <= frame.coarse_cull.z) {
            return false; // reaches the near plane
        }
        ndc_lo = min(ndc_lo, clip.xy / clip.w);
        ndc_hi = max(ndc_hi, clip.xy / clip.w);
        nearest = min(nearest, clip.w);
    }
    return screen_box_hidden(ndc_lo, ndc_hi, nearest);
}

// A patch of the ring: kept this frame or not, whether any of its blades may be listed, and
// which world patch it is.
struct RingPatch {
    kept: bool,
    listed: bool,
    at: vec2<i32>,
}

// The patch at `offset` from the eye's (instanced.rs `patches`, which the tests hold this to).
fn ring_patch(offset: vec2<i32>) -> RingPatch {
    var found = RingPatch(false, false, vec2<i32>(0));
    let eye = frame.camera_position.xyz;
    let size = f32(PATCH_CELLS) * frame.instanced_grid.x;
    // World patches (their cells' hashes are the world's), boxed in the frame's numbers.
    found.at = vec2<i32>(floor(world_xz(eye.xz) / size)) + offset;
    if (max(abs(offset.x), abs(offset.y)) > i32(frame.patch_cull.z)) {
        return found;
    }
    let top = frame.patch_bounds.z;
    let lo = vec3<f32>(frame_xz(vec2<f32>(found.at) * size), frame.patch_bounds.x).xzy - vec3<f32>(top);
    let hi = vec3<f32>(frame_xz(vec2<f32>(found.at + 1) * size), frame.patch_bounds.y + top).xzy + vec3<f32>(top);
    let nearest = clamp(eye, lo, hi);
    let farthest = vec3<f32>(
        select(hi.x, lo.x, eye.x - lo.x > hi.x - eye.x),
        eye.y,
        select(hi.z, lo.z, eye.z - lo.z > hi.z - eye.z),
    );
    if (distance(nearest, eye) > frame.instanced_grid.y || distance(farthest, eye) < frame.instanced_grid.z) {
        return found;
    }
    for (var k = 0u; k < 6u; k++) {
        let plane = frame.frustum[k];
        let corner = select(lo, hi, plane.xyz >= vec3<f32>(0.0));
        if (dot(plane.xyz, corner) + plane.w < 0.0) {
            return found;
        }
    }
    let pyramid = frame.instanced_meta.w != 0u && (frame.modes.x & CULL_OCCLUSION) != 0u;
    found.kept = !(pyramid && box_behind_occluders(lo, hi));
    // Blades are listed short of the splats (the Vulkan renderer's; none here).
    found.listed = distance(nearest, eye) < frame.instanced_lod.w;
    return found;
}

var<workgroup> kept_before: array<u32, GENERATE_GROUP>;
// Rows up to the last kept patch that may hold a listed blade.
var<workgroup> listed_rows: atomic<u32>;

// The levels' draw commands as a frame starts: level k's strip of 2·(8 >> k) + 1 vertices from
// vertex k · STRIP_STRIDE (the vertex stage finds the level so), no instances yet.
fn reset_level_draw(k: u32) {
    atomicStore(&level_draws[4u * k], 2u * (8u >> k) + 1u);
    atomicStore(&level_draws[4u * k + 1u], 0u);
    atomicStore(&level_draws[4u * k + 2u], k * STRIP_STRIDE);
    atomicStore(&level_draws[4u * k + 3u], 0u);
}

@compute @workgroup_size(256)
fn cull_patches(@builtin(local_invocation_index) lane: u32) {
    if (lane == 0u) {
        atomicStore(&listed_rows, 0u);
    }
    if (lane < LEVELS) {
        reset_level_draw(lane);
    }
    let ring = frame.patch_cull.x;
    let ring_len = frame.patch_cull.y;
    let capacity = frame.billboard_meta.z;
    var count = 0u;
    for (var start = 0u; start < ring_len; start += GENERATE_GROUP) {
        let entry = start + lane;
        var here = RingPatch(false, false, vec2<i32>(0));
        if (entry < ring_len) {
            here = ring_patch(patches[ring + entry].xy);
        }
        // Rows in ring order: an exclusive scan of the kept flags across the workgroup.
        kept_before[lane] = u32(here.kept);
        workgroupBarrier();
        for (var step = 1u; step < GENERATE_GROUP; step <<= 1u) {
            var add = 0u;
            if (lane >= step) {
                add = kept_before[lane - step];
            }
            workgroupBarrier();
            kept_before[lane] += add;
            workgroupBarrier();
        }
        let row = count + kept_before[lane] - u32(here.kept);
        if (here.kept && row < capacity) {
            patches[row] = vec4<i32>(here.at, 0, 0);
            if (here.listed) {
                atomicMax(&listed_rows, row + 1u);
            }
        }
        count += kept_before[GENERATE_GROUP - 1u];
        workgroupBarrier();
    }
    let listed = atomicLoad(&listed_rows);
    if (lane == 0u) {
        let rows = min(min(count, capacity), MAX_ROWS);
        generated_dispatch[0] = GROUPS_ACROSS;
        generated_dispatch[1] = rows;
        generated_dispatch[2] = 1u;
        generated_dispatch[3] = GROUPS_ACROSS;
        generated_dispatch[4] = min(listed, rows);
        generated_dispatch[5] = 1u;
        group_counts[0] = GROUPS_ACROSS * rows;
    }
}

// ---------------------------------------------------------------- the blades

// The strip level of detail of a blade `dist` from the eye (instanced.rs `lod_at`).
fn strip_level(dist: f32) -> i32 {
    let lod = frame.instanced_lod;
    return i32(dist >= lod.x) + i32(dist >= lod.y) + i32(dist >= lod.z);
}

// Blade `b`'s level of detail, or -1 where it is culled (instanced.rs `lod_of`): its bounding
// sphere against the frustum, the cut-off and inner radius. A blade settles anywhere its length
// reaches above the ground (gravity, wind, the trample map laying it down).
fn level_of(b: Twin) -> i32 {
    if (b.height <= 0.0) {
        return -1;
    }
    let center = b.root + vec3<f32>(0.0, 0.5 * b.height, 0.0);
    let radius = 1.15 * b.height + b.width;
    for (var k = 0u; k < 6u; k++) {
        if (dot(frame.frustum[k].xyz, center) + frame.frustum[k].w < -radius) {
            return -1;
        }
    }
    let dist = distance(b.root, frame.camera_position.xyz);
    if (dist >= frame.instanced_grid.y || dist < frame.instanced_grid.z) {
        return -1;
    }
    return strip_level(dist);
}

// The blade of an invocation of a generating pass and its level (-1: none).
struct Generated {
    blade: Twin,
    level: i32,
}

// The blade of invocation `lane` of workgroup `group` (a row of workgroups per kept patch):
// its cell's blade, mown where the trample map says.
fn generated_at(group: vec3<u32>, lane: u32) -> Generated {
    let at = patches[group.y].xy;
    let local = lane + group.x * GENERATE_GROUP;
    let cell = at * PATCH_CELLS + vec2<i32>(i32(local % u32(PATCH_CELLS)), i32(local / u32(PATCH_CELLS)));
    let b = cut(instanced_twin(cell));
    return Generated(b, select(-1, level_of(b), local < PATCH_BLADES));
}

// The counting and placing passes' workgroup index (both have GROUPS_ACROSS across).
fn workgroup_index(group: vec3<u32>) -> u32 {
    return group.y * GROUPS_ACROSS + group.x;
}

var<workgroup> level_counts: array<atomic<u32>, LEVELS>;

@compute @workgroup_size(256)
fn count_generated(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    if (lane < LEVELS) {
        atomicStore(&level_counts[lane], 0u);
    }
    let made = generated_at(group, lane);
    workgroupBarrier();
    if (made.level >= 0) {
        atomicAdd(&level_counts[u32(made.level)], 1u);
    }
    workgroupBarrier();
    if (lane < LEVELS) {
        let n = atomicLoad(&level_counts[lane]);
        group_counts[1u + lane * group_counts[0] + workgroup_index(group)] = n;
        atomicAdd(&level_draws[4u * lane + 1u], n);
    }
}

var<workgroup> scan_partial: array<u32, GENERATE_GROUP>;

// An exclusive prefix sum over level `group.x`'s counts, in place (scan.glsl): each invocation
// takes a run of them, the runs' sums are scanned across the workgroup, then each run is
// rewritten from where the runs before it end. In a fixed order, so the same every run.
@compute @workgroup_size(256)
fn scan_generated(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    let groups = group_counts[0];
    let base = 1u + group.x * groups;
    let run = (groups + GENERATE_GROUP - 1u) / GENERATE_GROUP;
    let first = min(lane * run, groups);
    let last = min(first + run, groups);
    var sum = 0u;
    for (var g = first; g < last; g++) {
        sum += group_counts[base + g];
    }
    scan_partial[lane] = sum;
    workgroupBarrier();
    for (var offset = 1u; offset < GENERATE_GROUP; offset <<= 1u) {
        var add = 0u;
        if (lane >= offset) {
            add = scan_partial[lane - offset];
        }
        workgroupBarrier();
        scan_partial[lane] += add;
        workgroupBarrier();
    }
    var before = scan_partial[lane] - sum;
    for (var g = first; g < last; g++) {
        let n = group_counts[base + g];
        group_counts[base + g] = before;
        before += n;
    }
}

// The 64 bits of a listed blade that hold its facing (a half) and its tip, posed, as three
// 16-bit fractions of its height from the root (instanced.glsl `pack_facing_tip`).
fn pack_facing_tip(b: Twin) -> vec2<u32> {
    let lean = clamp((b.tip - b.root) / max(b.height, 1e-6), vec3<f32>(-1.0), vec3<f32>(1.0));
    let facing = pack2x16float(vec2<f32>(b.facing, 0.0)) & 0xffffu;
    return vec2<u32>(facing | (pack2x16snorm(vec2<f32>(0.0, lean.x)) & 0xffff0000u), pack2x16snorm(lean.yz));
}

// Each invocation's level, for the ranks within the workgroup.
var<workgroup> lane_levels: array<i32, GENERATE_GROUP>;

@compute @workgroup_size(256)
fn place_generated(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    let made = generated_at(group, lane);
    lane_levels[lane] = made.level;
    workgroupBarrier();
    if (made.level < 0) {
        return;
    }
    var rank = 0u;
    for (var j = 0u; j < lane; j++) {
        rank += u32(lane_levels[j] == made.level);
    }
    let k = u32(made.level);
    let slot = group_counts[1u + k * group_counts[0] + workgroup_index(group)] + rank;
    if (slot >= frame.instanced_caps[k]) {
        return;
    }
    // Posed once here, not at each of its strip's vertices.
    let b = posed(made.blade, distance(made.blade.root, frame.camera_position.xyz));
    let at = 2u * (frame.instanced_lists[k] + slot);
    listed[at] = vec4<u32>(bitcast<vec3<u32>>(b.root), pack2x16float(vec2<f32>(b.height, b.width)));
    listed[at + 1u] = vec4<u32>(pack_facing_tip(b), b.hash, b.outline);
}
