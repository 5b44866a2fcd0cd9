// Distance buckets for the portable renderer (sward-core commands.rs; the Vulkan renderer's
// common.glsl): the cull lists each visible blade in the bucket of its distance, nearest first,
// and each bucket is one draw command of strips cut as finely as its distance asks. Where each
// bucket's list starts is kept apart from its command (`BUCKET_STARTS` in the counters), and
// the command's first vertex says which bucket it is (`STRIP_STRIDE` vertices a bucket): a
// draw's first instance must be 0 on WebGPU without `indirect-first-instance`, its first vertex
// need not. Needs frame.wgsl.

// Distance buckets (sward-core commands.rs DISTANCE_BUCKETS).
const DISTANCE_BUCKETS: u32 = 64u;
// Where the counters hold each bucket's start in the visible list (after its count and its
// next free place).
const BUCKET_STARTS: u32 = 128u;
// Where the counters hold how many buckets the draw issues: up to the farthest that holds a
// blade (read as the draw's count where the device draws indirect with a count).
const DRAWN_BUCKETS: u32 = 192u;
// Vertex indices a bucket's command spans: more than any strip has (4 × (segments + 1)).
const STRIP_STRIDE: u32 = 1024u;
// After the buckets' commands, the command that draws the nearest listed blades into the next
// frame's depth pyramid (`occlusion.x` of them at most), each a flat strip of OCCLUDER_SEGMENTS
// rows.
const COMMAND_OCCLUDERS: u32 = 64u;
const OCCLUDER_SEGMENTS: u32 = 4u;

// A draw command as the GPU reads it (sward-core gpu.rs `DrawCommand`).
struct DrawCommand {
    vertex_count: u32,
    instance_count: u32,
    first_vertex: u32,
    first_instance: u32,
}

fn lod_level(dist: f32) -> f32 {
    let t = clamp((dist - frame.lod.z) / (frame.lod.w - frame.lod.z), 0.0, 1.0);
    return frame.lod.x + (frame.lod.y - frame.lod.x) * (1.0 - t);
}

// Square-root spaced out to where the grass ends (commands.rs `bucket_range`).
fn bucket_range() -> f32 {
    return max(min(frame.lod.w * 8.0, frame.cull.z), 1.0);
}

fn distance_bucket(dist: f32) -> u32 {
    let f = sqrt(max(dist, 0.0) / bucket_range());
    return min(u32(f * f32(DISTANCE_BUCKETS)), DISTANCE_BUCKETS - 1u);
}

// Segments along a strip of bucket k: the tessellator's at the bucket's nearest distance.
fn strip_segments(k: u32) -> u32 {
    let f = f32(k) / f32(DISTANCE_BUCKETS);
    let level = lod_level(bucket_range() * f * f);
    return max(2u, 2u * u32(ceil(level * 0.5 - 1e-4)));
}

