// The generated grass's listed blades as strips (SPEC §7 [F]; the Vulkan renderer's
// instanced.glsl): the draw of level k has 2·(8 >> k) + 1 vertices (17, 9, 5, 3: the last level
// is one triangle) from vertex k · STRIP_STRIDE, which says the level; the instance pulls its
// 32-byte blade from that level's list (posed: its tip where it settles this frame) and builds
// its curve and the strip's point, geomorphed near level boundaries so crossing one changes
// nothing on screen. sward's own draw (generated_strips.wgsl) and an engine's passes place the
// strips by it. Needs frame.wgsl, blade.wgsl, buckets.wgsl, outline.wgsl and listed.wgsl.

// A listed blade (generated.wgsl `place_generated`): root, height, half-width, facing, where
// its tip stands this frame, its hash and its outline.
struct ListedBlade {
    root: vec3<f32>,
    height: f32,
    width: f32,
    facing: f32,
    tip: vec3<f32>,
    hash: u32,
    outline: u32,
}

// Blade `slot` of the lists (instanced.glsl `unpack_blade`).
fn listed_blade(slot: u32) -> ListedBlade {
    let a = listed[2u * slot];
    let b = listed[2u * slot + 1u];
    let root = bitcast<vec3<f32>>(a.xyz);
    let size = unpack2x16float(a.w);
    let lean = vec3<f32>(unpack2x16snorm(b.x).y, unpack2x16snorm(b.y)) * LEAN_RANGE;
    return ListedBlade(root, size.x, size.y, unpack2x16float(b.x).x, root + lean * size.x, b.z, b.w);
}

// A blade as a quadratic curve from its root to its tip (guide between) with a half-width
// narrowing to its tip.
struct Shape {
    root: vec3<f32>,
    guide: vec3<f32>,
    tip: vec3<f32>,
    across: vec3<f32>,
    width: f32,
    outline: u32,
}

// A listed blade's shape `dist` from the eye (instanced.glsl `listed_shape`): the curve
// validation makes of its root, height and tip, its width across its face widened with distance
// so coarse levels keep their coverage.
fn listed_shape(b: ListedBlade, dist: f32) -> Shape {
    let curve = validated(b.root, max(b.height, 1e-4), b.tip);
    return Shape(b.root, curve.guide.xyz, curve.tip.xyz, blade_across(b.facing), widened(b.width, dist), b.outline);
}

fn curve_at(s: Shape, t: f32) -> vec3<f32> {
    return mix(mix(s.root, s.guide, vec3<f32>(t)), mix(s.guide, s.tip, vec3<f32>(t)), vec3<f32>(t));
}

// The edge point at height t on side `side` (-1, 0 the tip, 1) in the blade's outline.
fn edge(s: Shape, t: f32, side: f32) -> vec3<f32> {
    let tau = blade_shape_of(s.outline, side * 0.5 + 0.5, t);
    return curve_at(s, t) + s.across * (s.width * (2.0 * tau - 1.0));
}

// A point of a level's strip: where it is (in the frame's coordinates), its rounded normal,
// and u across the blade, v from root to tip.
struct LevelPoint {
    position: vec3<f32>,
    normal: vec3<f32>,
    uv: vec2<f32>,
}

// Vertex `v` of shape `s`'s strip at level `lod`, `dist` from the eye (instanced.glsl
// `strip_vertex`): row by row its left and right edge, then the tip; near a level boundary the
// odd rows slide onto the coarser strip's edges.
fn level_point(s: Shape, dist: f32, lod: u32, v: u32) -> LevelPoint {
    let segments = 8u >> lod;
    let row = min(v / 2u, segments);
    let side = select(select(1.0, -1.0, (v & 1u) == 0u), 0.0, v == 2u * segments);
    let t = f32(row) / f32(segments);
    var p = edge(s, t, side);
    if (lod < 3u && (row & 1u) == 1u) {
        let boundary = frame.instanced_lod[lod];
        if (dist > 0.8 * boundary) {
            let dt = 1.0 / f32(segments);
            let chord = 0.5 * (edge(s, t - dt, side) + edge(s, t + dt, side));
            p = mix(p, chord, vec3<f32>(smoothstep(0.8 * boundary, boundary, dist)));
        }
    }
    let tangent = normalize_or_zero(mix(s.guide - s.root, s.tip - s.guide, vec3<f32>(t)));
    let normal = rounded_normal(normalize_or_zero(cross(tangent, s.across)), s.across, side * 0.5 + 0.5);
    return LevelPoint(p, normal, vec2<f32>(side * 0.5 + 0.5, t));
}

// A vertex of a level's draw: whether it is drawn (not past a full list), its blade's root and
// hash, and the point.
struct GeneratedPoint {
    drawn: bool,
    root: vec3<f32>,
    hash: u32,
    point: LevelPoint,
}

// Vertex `vertex_index` of instance `instance` of the levels' draws (level k's from vertex
// k · STRIP_STRIDE): its listed blade's strip at that level, geomorphed by its distance from
// the eye.
fn generated_point(vertex_index: u32, instance: u32) -> GeneratedPoint {
    var out: GeneratedPoint;
    let lod = min(vertex_index / STRIP_STRIDE, 3u);
    if (instance >= frame.instanced_caps[lod]) {
        return out; // past a full list
    }
    let b = listed_blade(frame.instanced_lists[lod] + instance);
    let dist = distance(b.root, frame.camera_position.xyz);
    out.drawn = true;
    out.root = b.root;
    out.hash = b.hash;
    out.point = level_point(listed_shape(b, dist), dist, lod, vertex_index % STRIP_STRIDE);
    return out;
}
