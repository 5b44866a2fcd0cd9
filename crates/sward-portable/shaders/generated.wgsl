// The generated grass on the portable renderer (SPEC §7 [F]; the Vulkan renderer's
// patch_cull.comp, instanced_pass.glsl and generated_scan.comp where it splats nothing): no
// blade is stored; each frame makes the blade of every grid cell around the eye from the cell's
// hash (twin.wgsl `grid_blade`), culls it and lists it — on the instanced grass's grid at its
// level of detail, posed, for generated_strips.wgsl; on the billboards' grid in one list, for
// billboards.wgsl. Four passes, the last three per grid (`_generated`: the instanced grass's,
// `_billboards`: the billboards'):
//   cull_patches      a workgroup per grid: the grid patches around the eye, in the ring order
//                     the host laid out once (nearest rings first), kept where they reach into
//                     the cut-off radius and out of the inner radius, touch the view frustum and
//                     are not wholly behind the depth pyramid's occluders; written as the rows
//                     the next passes run over, with their dispatch sizes. Also resets the
//                     grid's draw commands.
//   count_*           a row of workgroups per kept patch, an invocation per cell: each
//                     workgroup's blades per list, summed into the lists' draw commands.
//   scan_*            a workgroup per list: each workgroup's count becomes how many of the
//                     list's blades the workgroups before it hold.
//   place_*           the blades made again, each at its list after those of the workgroups
//                     and invocations before it — a place the grid decides, not the order
//                     workgroups ran in, so the lists are the same every run (and the Vulkan
//                     renderer's).
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
// One draw command per level, then the billboards': vertices, instances, first vertex, first
// instance.
@group(0) @binding(13) var<storage, read_write> level_draws: array<atomic<u32>>;
// Per grid (`counts_base`): a word for its counting pass's workgroups; then per list, per
// workgroup its blades (counting), then where they start in the list (scanned).
@group(0) @binding(14) var<storage, read_write> group_counts: array<u32>;
// Per grid, its counting and placing passes' dispatch sizes (x, y, z each).
@group(0) @binding(15) var<storage, read_write> generated_dispatch: array<u32>;

// Cells along a patch's side, and in a patch (instanced.rs).
const PATCH_CELLS: i32 = 32;
const PATCH_BLADES: u32 = 1024u;
// Invocations of a generating workgroup, and its workgroups across a patch's row.
const GENERATE_GROUP: u32 = 256u;
const GROUPS_ACROSS: u32 = 4u;
// The instanced grass's levels of detail (instanced.rs `LOD_SEGMENTS`: 8, 4, 2, 1 rows).
const LEVELS: u32 = 4u;
// The grids: the instanced grass's, the billboards'.
const GRID_BLADES: u32 = 0u;
const GRID_BILLBOARDS: u32 = 1u;
// The billboards' draw command (after the levels').
const BILLBOARD_COMMAND: u32 = 4u;

// The lists grid `g` places blades in: the levels, or the billboards' one.
fn lists_of(g: u32) -> u32 {
    return select(LEVELS, 1u, g == GRID_BILLBOARDS);
}

// The draw command counting list `k` of grid `g`.
fn command_of(g: u32, k: u32) -> u32 {
    return select(k, BILLBOARD_COMMAND, g == GRID_BILLBOARDS);
}

// Where grid `g`'s counts start: the instanced grass's at 0, the billboards' after the most
// the instanced grass's kept patches may take.
fn counts_base(g: u32) -> u32 {
    return select(0u, 1u + LEVELS * GROUPS_ACROSS * frame.billboard_meta.z, g == GRID_BILLBOARDS);
}

// The first patch row of grid `g`'s list.
fn first_row(g: u32) -> u32 {
    return select(0u, frame.billboard_meta.z, g == GRID_BILLBOARDS);
}
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

// What a grid's patches are culled by (patch_cull.comp `Grid`).
struct PatchGrid {
    // A patch's side, the cut-off and inner radius.
    size: f32,
    radius: f32,
    inner: f32,
    // The highest a blade reaches above the ground.
    top: f32,
    // Blades within this distance may be listed (the Vulkan renderer splats the rest).
    listed: f32,
    // Patches each way from the eye's.
    reach: i32,
}

fn patch_grid(g: u32) -> PatchGrid {
    if (g == GRID_BILLBOARDS) {
        let p = frame.billboard_grid;
        return PatchGrid(f32(PATCH_CELLS) * p.x, p.y, p.z, frame.patch_bounds.w, 3.0e38, i32(frame.patch_cull.w));
    }
    let p = frame.instanced_grid;
    return PatchGrid(f32(PATCH_CELLS) * p.x, p.y, p.z, frame.patch_bounds.z, frame.instanced_lod.w, i32(frame.patch_cull.z));
}

// The patch at `offset` from the eye's on `grid` (instanced.rs `patches`, which the tests hold
// the Vulkan renderer's to).
fn ring_patch(offset: vec2<i32>, grid: PatchGrid) -> RingPatch {
    var found = RingPatch(false, false, vec2<i32>(0));
    let eye = frame.camera_position.xyz;
    let size = grid.size;
    // World patches (their cells' hashes are the world's), boxed in the frame's numbers.
    found.at = vec2<i32>(floor(world_xz(eye.xz) / size)) + offset;
    if (max(abs(offset.x), abs(offset.y)) > grid.reach) {
        return found;
    }
    let top = grid.top;
    let lo = vec3<f32>(frame_xz(vec2<f32>(found.at) * size), frame.patch_bounds.x).xzy - vec3<f32>(top);
    let hi = vec3<f32>(frame_xz(vec2<f32>(found.at + 1) * size), frame.patch_bounds.y + top).xzy + vec3<f32>(top);
    let nearest = clamp(eye, lo, hi);
    let farthest = vec3<f32>(
        select(hi.x, lo.x, eye.x - lo.x > hi.x - eye.x),
        eye.y,
        select(hi.z, lo.z, eye.z - lo.z > hi.z - eye.z),
    );
    if (distance(nearest, eye) > grid.radius || distance(farthest, eye) < grid.inner) {
        return found;
    }
    for (var k = 0u; k < 6u; k++) {
        let plane = frame.frustum[k];
        let corner = select(lo, hi, plane.xyz >= vec3<f32>(0.0));
        if (dot(plane.xyz, corner) + plane.w < 0.0) {
            return found;
        }
    }
    // The frame's occlusion bit is set only where its pyramid can hide grass (plan.rs).
    let pyramid = (frame.modes.x & CULL_OCCLUSION) != 0u;
    found.kept = !(pyramid && box_behind_occluders(lo, hi));
    // Blades are listed short of the splats (the Vulkan renderer's; none here).
    found.listed = distance(nearest, eye) < grid.listed;
    return found;
}

// One value per invocation, summed across the workgroup by `scan_lanes`.
var<workgroup> lanes: array<u32, GENERATE_GROUP>;

// `lanes[lane]` becomes the sum of `lanes[0..=lane]`, in log2 steps across the workgroup (all
// of it calls this, each invocation with its own lane). Ends past a barrier.
fn scan_lanes(lane: u32) {
    workgroupBarrier();
    for (var step = 1u; step < GENERATE_GROUP; step <<= 1u) {
        var add = 0u;
        if (lane >= step) {
            add = lanes[lane - step];
        }
        workgroupBarrier();
        lanes[lane] += add;
        workgroupBarrier();
    }
}

// Rows up to the last kept patch that may hold a listed blade.
var<workgroup> listed_rows: atomic<u32>;

// Grid `g`'s draw commands as a frame starts, no instances yet: level k's strip of 2·(8 >> k) + 1
// vertices from vertex k · STRIP_STRIDE (the vertex stage finds the level so); the billboards'
// three quads.
fn reset_draws(g: u32) {
    for (var k = 0u; k < lists_of(g); k++) {
        let command = 4u * command_of(g, k);
        let strip = g == GRID_BLADES;
        atomicStore(&level_draws[command], select(18u, 2u * (8u >> k) + 1u, strip));
        atomicStore(&level_draws[command + 1u], 0u);
        atomicStore(&level_draws[command + 2u], select(0u, k * STRIP_STRIDE, strip));
        atomicStore(&level_draws[command + 3u], 0u);
    }
}

@compute @workgroup_size(256)
fn cull_patches(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    let g = group.x;
    let grid = patch_grid(g);
    if (lane == 0u) {
        atomicStore(&listed_rows, 0u);
        reset_draws(g);
    }
    let ring = frame.patch_cull.x;
    let first = first_row(g);
    let capacity = select(frame.billboard_meta.z, frame.patch_cull.x - frame.billboard_meta.z, g == GRID_BILLBOARDS);
    // A grid the frame does not draw has no rows.
    let ring_len = select(frame.patch_cull.y, 0u, capacity == 0u);
    var count = 0u;
    for (var start = 0u; start < ring_len; start += GENERATE_GROUP) {
        let entry = start + lane;
        var here = RingPatch(false, false, vec2<i32>(0));
        if (entry < ring_len) {
            here = ring_patch(patches[ring + entry].xy, grid);
        }
        // Rows in ring order: the kept flags summed across the workgroup.
        lanes[lane] = u32(here.kept);
        scan_lanes(lane);
        let row = count + lanes[lane] - u32(here.kept);
        if (here.kept && row < capacity) {
            patches[first + row] = vec4<i32>(here.at, 0, 0);
            if (here.listed) {
                atomicMax(&listed_rows, row + 1u);
            }
        }
        count += lanes[GENERATE_GROUP - 1u];
        workgroupBarrier();
    }
    let listed = atomicLoad(&listed_rows);
    if (lane == 0u) {
        let rows = min(min(count, capacity), MAX_ROWS);
        let at = 6u * g;
        generated_dispatch[at] = GROUPS_ACROSS;
        generated_dispatch[at + 1u] = rows;
        generated_dispatch[at + 2u] = 1u;
        generated_dispatch[at + 3u] = GROUPS_ACROSS;
        generated_dispatch[at + 4u] = min(listed, rows);
        generated_dispatch[at + 5u] = 1u;
        group_counts[counts_base(g)] = GROUPS_ACROSS * rows;
    }
}

// ---------------------------------------------------------------- the blades

// The strip level of detail of a blade `dist` from the eye (instanced.rs `lod_at`).
fn strip_level(dist: f32) -> i32 {
    let lod = frame.instanced_lod;
    return i32(dist >= lod.x) + i32(dist >= lod.y) + i32(dist >= lod.z);
}

// Blade `b`'s list on grid `g` — its level of detail, or the billboards' one list — or -1 where
// it is culled (instanced.rs `lod_of`): its bounding sphere against the frustum, the cut-off and
// inner radius. A blade settles anywhere its length reaches above the ground (gravity, wind,
// the trample map laying it down); a billboard stands, swaying, or lies trampled.
fn list_of(b: Twin, g: u32) -> i32 {
    if (b.height <= 0.0) {
        return -1;
    }
    let billboards = g == GRID_BILLBOARDS;
    let center = b.root + vec3<f32>(0.0, 0.5 * b.height, 0.0);
    var radius = 1.15 * b.height + b.width;
    if (billboards && frame.trample.x == 0u) {
        radius = 0.5 * b.height * (1.0 + frame.billboard_motion.x) + b.width;
    } else if (billboards) {
        radius = max(0.5 * b.height * (1.0 + frame.billboard_motion.x) + b.width, radius);
    }
    for (var k = 0u; k < 6u; k++) {
        if (dot(frame.frustum[k].xyz, center) + frame.frustum[k].w < -radius) {
            return -1;
        }
    }
    let dist = distance(b.root, frame.camera_position.xyz);
    let grid = patch_grid(g);
    if (dist >= grid.radius || dist < grid.inner) {
        return -1;
    }
    return select(strip_level(dist), 0, billboards);
}

// The blade of an invocation of a generating pass and its list (-1: none).
struct Generated {
    blade: Twin,
    list: i32,
}

// The grid cell of patch `at` that its `local`th invocation makes: the patch walked in rows across
// the line from the eye to it, from the side nearest the eye, so each patch is listed and drawn
// front to back whatever way the eye looks (instanced_pass.glsl `cell_of` says what it saves).
fn cell_of(local: u32, at: vec2<i32>, spacing: f32) -> vec2<i32> {
    let away = (vec2<f32>(at) + 0.5) * f32(PATCH_CELLS) * spacing - world_xz(frame.camera_position.xz);
    let across = local % u32(PATCH_CELLS);
    let along = local / u32(PATCH_CELLS);
    var cell = select(vec2<u32>(along, across), vec2<u32>(across, along), abs(away.y) >= abs(away.x));
    let last = u32(PATCH_CELLS) - 1u;
    cell.x = select(cell.x, last - cell.x, away.x < 0.0);
    cell.y = select(cell.y, last - cell.y, away.y < 0.0);
    return at * PATCH_CELLS + vec2<i32>(cell);
}

// The blade of invocation `lane` of workgroup `group` (a row of workgroups per kept patch of
// grid `g`): its cell's blade, mown where the trample map says.
fn generated_at(group: vec3<u32>, lane: u32, g: u32) -> Generated {
    let at = patches[first_row(g) + group.y].xy;
    let local = lane + group.x * GENERATE_GROUP;
    var grid = instanced_grid();
    if (g == GRID_BILLBOARDS) {
        grid = billboard_grid();
    }
    let cell = cell_of(local, at, grid.spacing);
    let b = cut(grid_blade(cell, grid));
    return Generated(b, select(-1, list_of(b, g), local < PATCH_BLADES));
}

// The counting and placing passes' workgroup index (both have GROUPS_ACROSS across).
fn workgroup_index(group: vec3<u32>) -> u32 {
    return group.y * GROUPS_ACROSS + group.x;
}

var<workgroup> list_counts: array<atomic<u32>, LEVELS>;

// Counting grid `g`: this workgroup's blades per list into its counts, and into the lists'
// draw commands (sums, so in no particular order).
fn count_grid(group: vec3<u32>, lane: u32, g: u32) {
    if (lane < LEVELS) {
        atomicStore(&list_counts[lane], 0u);
    }
    let made = generated_at(group, lane, g);
    workgroupBarrier();
    if (made.list >= 0) {
        atomicAdd(&list_counts[u32(made.list)], 1u);
    }
    workgroupBarrier();
    if (lane < lists_of(g)) {
        let n = atomicLoad(&list_counts[lane]);
        let base = counts_base(g);
        group_counts[base + 1u + lane * group_counts[base] + workgroup_index(group)] = n;
        atomicAdd(&level_draws[4u * command_of(g, lane) + 1u], n);
    }
}

@compute @workgroup_size(256)
fn count_generated(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    count_grid(group, lane, GRID_BLADES);
}

@compute @workgroup_size(256)
fn count_billboards(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    count_grid(group, lane, GRID_BILLBOARDS);
}

// An exclusive prefix sum over list `k` of grid `g`'s counts, in place (scan.glsl): each
// invocation takes a run of them, the runs' sums are scanned across the workgroup, then each run
// is rewritten from where the runs before it end. In a fixed order, so the same every run.
fn scan_list(lane: u32, g: u32, k: u32) {
    let header = counts_base(g);
    let groups = group_counts[header];
    let base = header + 1u + k * groups;
    let run = (groups + GENERATE_GROUP - 1u) / GENERATE_GROUP;
    let first = min(lane * run, groups);
    let last = min(first + run, groups);
    var sum = 0u;
    for (var i = first; i < last; i++) {
        sum += group_counts[base + i];
    }
    lanes[lane] = sum;
    scan_lanes(lane);
    var before = lanes[lane] - sum;
    for (var i = first; i < last; i++) {
        let n = group_counts[base + i];
        group_counts[base + i] = before;
        before += n;
    }
}

// A workgroup per level.
@compute @workgroup_size(256)
fn scan_generated(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    scan_list(lane, GRID_BLADES, group.x);
}

@compute @workgroup_size(256)
fn scan_billboards(@builtin(local_invocation_index) lane: u32) {
    scan_list(lane, GRID_BILLBOARDS, 0u);
}

// The 64 bits of a listed blade that hold its facing (a half) and its tip, posed, as three
// 16-bit fractions of LEAN_RANGE heights from the root (instanced.glsl `pack_facing_tip`).
fn pack_facing_tip(b: Twin) -> vec2<u32> {
    let lean = clamp((b.tip - b.root) / (LEAN_RANGE * max(b.height, 1e-6)), vec3<f32>(-1.0), vec3<f32>(1.0));
    let facing = pack2x16float(vec2<f32>(b.facing, 0.0)) & 0xffffu;
    return vec2<u32>(facing | (pack2x16snorm(vec2<f32>(0.0, lean.x)) & 0xffff0000u), pack2x16snorm(lean.yz));
}

// Each invocation's list, for the ranks within the workgroup.
var<workgroup> lane_lists: array<i32, GENERATE_GROUP>;

// Placing grid `g`: the blade at its list, after the list's blades of the workgroups before this
// one (scanned) and of the invocations before it in this one; a blade settled once here, not at
// each of its strip's vertices (a billboard sways as it is drawn).
fn place_grid(group: vec3<u32>, lane: u32, g: u32) {
    let made = generated_at(group, lane, g);
    lane_lists[lane] = made.list;
    workgroupBarrier();
    if (made.list < 0) {
        return;
    }
    var rank = 0u;
    for (var j = 0u; j < lane; j++) {
        rank += u32(lane_lists[j] == made.list);
    }
    let k = u32(made.list);
    let base = counts_base(g);
    let slot = group_counts[base + 1u + k * group_counts[base] + workgroup_index(group)] + rank;
    var b = made.blade;
    var at = 0u;
    if (g == GRID_BILLBOARDS) {
        if (slot >= frame.billboard_meta.y) {
            return;
        }
        at = 2u * (frame.billboard_meta.x + slot);
    } else {
        if (slot >= frame.instanced_caps[k]) {
            return;
        }
        b = posed(b, distance(b.root, frame.camera_position.xyz));
        at = 2u * (frame.instanced_lists[k] + slot);
    }
    listed[at] = vec4<u32>(bitcast<vec3<u32>>(b.root), pack2x16float(vec2<f32>(b.height, b.width)));
    listed[at + 1u] = vec4<u32>(pack_facing_tip(b), b.hash, b.outline);
}

@compute @workgroup_size(256)
fn place_generated(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    place_grid(group, lane, GRID_BLADES);
}

@compute @workgroup_size(256)
fn place_billboards(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    place_grid(group, lane, GRID_BILLBOARDS);
}
