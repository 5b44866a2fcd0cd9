// The surface of a visible Bezier blade drawn as a triangle strip (SPEC §6–8), as the Vulkan
// renderer's strip route evaluates it (blade_strip.vert, blade_surface.glsl): which blade and
// which (u, v) on it a vertex of a distance bucket's command stands for, and the point there —
// De Casteljau along the height, the blade's outline across the width, the ridge, and the
// minimum width that keeps far blades from aliasing into holes. The portable renderer's strips
// (strips.wgsl) and an engine's own passes (sward-bevy) draw from it. No entry points. Needs
// frame.wgsl, blade.wgsl, noise.wgsl, buckets.wgsl, shading.wgsl, stream_cells.wgsl and
// outline.wgsl.

@group(0) @binding(1) var<storage, read> blades: array<Blade>;
// The visible blades' indices, bucket by bucket (cull.wgsl).
@group(0) @binding(3) var<storage, read> visible: array<u32>;
// The cull's counters: where each bucket's list starts at BUCKET_STARTS.
@group(0) @binding(6) var<storage, read> counters: array<u32>;

fn to_pixels(p: vec3<f32>) -> vec2<f32> {
    let clip = frame.view_proj * vec4<f32>(p, 1.0);
    return clip.xy / max(clip.w, 1e-4) * 0.5 * frame.viewport.xy;
}

// What a blade's colour varies by: its id, or where the field streams its cell's hash (as the
// instanced blade of that cell is varied).
fn blade_colour_key(id: u32) -> u32 {
    if (frame.stream.x > 0u) {
        return cell_hash(stream_cell(id), frame.instanced_meta.x);
    }
    return id;
}

// ---------------------------------------------------------------- the blade's surface

// A point of a blade's surface and its normal (rounded across the width).
struct SurfacePoint {
    position: vec3<f32>,
    normal: vec3<f32>,
}

// The point of blade `b`, drawn with outline `outline`, at (u across, v from root to tip).
fn blade_point(b: Blade, outline: u32, u: f32, v: f32) -> SurfacePoint {
    let up = b.up.xyz;
    let w = b.tip.w;
    let across = width_direction(up, b.root.w);
    let a = mix(b.root.xyz, b.guide.xyz, vec3<f32>(v));
    let bb = mix(b.guide.xyz, b.tip.xyz, vec3<f32>(v));
    let c = mix(a, bb, vec3<f32>(v));
    var along = bb - a;
    along = select(up, normalize(along), dot(along, along) > 1e-12);
    let n = normalize(cross(along, across));
    let edge_a = c - w * across;
    let edge_b = c + w * across;
    // Streamed: the blade eases with the pose into the twin's shape, all the way at the
    // hand-over.
    let like = twin_ease(b.root.xyz);
    var tau = blade_shape_of(outline, u, v);
    let min_px = frame.blade_style.w;
    if (min_px > 0.0) {
        let px = length(to_pixels(edge_b) - to_pixels(edge_a));
        tau = mix(tau, u, clamp(1.0 - px / min_px, 0.0, 1.0) * (1.0 - like));
    }
    var p = mix(edge_a, edge_b, vec3<f32>(tau));
    if ((frame.modes.w & DRAW_BLADE_RIDGE) != 0u) {
        // A flowering stalk folds as little as it is wide.
        let fold = select(1.0, SEED_STALK, (outline >> 8u) != 0u);
        p += n * (w * fold) * (0.5 - abs(u - 0.5)) * (1.0 - v) * (1.0 - like);
    }
    return SurfacePoint(p, rounded_normal(n, across, u));
}

// ---------------------------------------------------------------- where a vertex lies

// The blade a strip's vertex is of, and where on it: u across, v from root to tip.
struct StripPlace {
    id: u32,
    u: f32,
    v: f32,
}

// Vertex `vertex_index` of instance `instance` of a distance bucket's command: the command's
// first vertex says which bucket (STRIP_STRIDE vertices a bucket, since WebGPU draws every
// command from instance 0), the instance which of its visible blades, the vertex a place up
// the strip — two vertices a row, or with the ridge up the left half and down the right.
fn strip_place(vertex_index: u32, instance: u32) -> StripPlace {
    let k = vertex_index / STRIP_STRIDE;
    let i = vertex_index % STRIP_STRIDE;
    let id = visible[counters[BUCKET_STARTS + k] + instance];
    let at = strip_walk(i, strip_segments(k));
    return StripPlace(id, at.x, at.y);
}

// Where vertex `i` of a strip of `segments` rows lies on its blade, (u, v): two vertices a row,
// or with the ridge up the left half and down the right (blade_strip.vert's walk).
fn strip_walk(i: u32, segments: u32) -> vec2<f32> {
    var row: u32;
    var u: f32;
    if ((frame.modes.w & DRAW_BLADE_RIDGE) == 0u) {
        row = i >> 1u;
        u = f32(i & 1u);
    } else if (i < 2u * (segments + 1u)) {
        // The ridge folds the blade at u = 0.5: up the left half, then down the right half (the
        // two turning triangles are degenerate).
        row = i >> 1u;
        u = 0.5 * f32(i & 1u);
    } else {
        let j = i - 2u * (segments + 1u);
        row = segments - (j >> 1u);
        u = 0.5 + 0.5 * f32(j & 1u);
    }
    return vec2<f32>(u, f32(row) / f32(segments));
}
