//! Where the Bezier blades' draw commands sit in their buffer (in commands; the shaders name the
//! same slots through `declared.rs`): the tessellation route's one command over the whole
//! ordered list, the strip route's command per distance bucket (nearest first), the compute
//! passes' dispatch sizes, and from `COMMAND_SPLITS` on, where a driver needs it, the
//! tessellation draw split into commands.

/// The tessellation route's one command over the whole ordered list.
pub const COMMAND_ALL: u32 = 0;
/// The strip route's first command (one per distance bucket follows).
pub const COMMAND_BUCKETS: u32 = 1;
/// Distance buckets of the visible list (and strip commands).
pub const DISTANCE_BUCKETS: u32 = 64;
/// The compute route's splat pass: its dispatch size.
pub const COMMAND_SPLAT_DISPATCH: u32 = COMMAND_BUCKETS + DISTANCE_BUCKETS;
/// The mesh route's workgroups (x, y; `VkDrawMeshTasksIndirectCommandEXT`).
pub const COMMAND_MESH_DISPATCH: u32 = COMMAND_SPLAT_DISPATCH + 1;
/// The compute route's rasterizer, first pass: its workgroups (x, y; a blade each) and where
/// its blades start.
pub const COMMAND_RASTER_DISPATCH: u32 = COMMAND_MESH_DISPATCH + 1;
/// How many blades the rasterizer's first pass left to the second (x).
pub const COMMAND_RASTER_LEFT: u32 = COMMAND_RASTER_DISPATCH + 1;
/// The rasterizer's second pass: its workgroups (x, y), and in its last word (which a dispatch
/// does not read) the blades themselves, which the pass reads there.
pub const COMMAND_RASTER_RETRY: u32 = COMMAND_RASTER_LEFT + 1;
/// The blade occluders of the next frame's depth pyramid: per distance bucket its strip
/// command cut so that all of them together draw at most `cull.blade_occluders` of the
/// nearest visible blades.
pub const COMMAND_OCCLUDERS: u32 = COMMAND_RASTER_RETRY + 1;
/// The exact-distance sort of the drawn part of the ordered list: its workgroups (x; a run
/// of entries each) and where the drawn part ends.
pub const COMMAND_SORT_DISPATCH: u32 = COMMAND_OCCLUDERS + DISTANCE_BUCKETS;
/// The tiles this frame runs: the simulate and cull passes' dispatch size (x workgroups
/// per tile, y tiles; a row of workgroups each) and, in the last word, the blades they
/// simulate. Written by `tile_cull.wesl`, or by the host where it decides the tiles.
pub const COMMAND_TILE_DISPATCH: u32 = COMMAND_SORT_DISPATCH + 1;
/// The tessellation draw split into commands, where a driver needs it.
pub const COMMAND_SPLITS: u32 = COMMAND_TILE_DISPATCH + 1;
/// A visible-list entry before ordering: the blade id, its bucket from this bit up. All
/// bits set marks a slot whose blade is not visible: no field on a GPU reaches id 2^26 − 1
/// in bucket 63 (2^26 − 1 blades are 4 GiB, past every device's largest storage buffer).
pub const BUCKET_SHIFT: u32 = 26;
/// Rows of segments a blade occluder is drawn with at most (the strips that draw the nearest
/// visible blades into the next frame's depth pyramid).
pub const OCCLUDER_SEGMENTS: u32 = 4;
/// Vertex indices a strip command spans: more than any strip has. A command's first vertex is
/// its bucket (or generated level) times this, which tells its vertex stage which it draws: a
/// draw's first instance must be 0 on WebGPU without `indirect-first-instance`, its first
/// vertex need not, and a draw's index is not a WGSL built-in.
pub const STRIP_STRIDE: u32 = 1024;

/// The portable cull's counters (a buffer of `u32`s, cleared each frame): per distance bucket
/// its visible blades, then where its list starts, then how many buckets the draw issues (up to
/// the farthest that holds a blade; a draw with a count reads it), how many workgroups the cull
/// ran (its scan's length), and the bucket the blade occluders' budget cuts.
pub mod counters {
    use super::DISTANCE_BUCKETS;

    /// Where each bucket's list starts in the visible list (one word per bucket).
    pub const BUCKET_STARTS: u32 = DISTANCE_BUCKETS;
    /// How many buckets the draw issues.
    pub const DRAWN_BUCKETS: u32 = 2 * DISTANCE_BUCKETS;
    /// How many workgroups the cull ran this frame.
    pub const COUNTED_GROUPS: u32 = DRAWN_BUCKETS + 1;
    /// Where the bucket the next frame's blade occluders' budget ends in starts in the list,
    /// then its blades (0: the budget holds every listed blade): the occluders drawn of it are
    /// spread over the whole bucket, as the Vulkan renderer's (bezier_strips.wesl `list_entry`).
    pub const OCCLUDER_CUT: u32 = COUNTED_GROUPS + 1;
    /// Words of the counters.
    pub const WORDS: u32 = OCCLUDER_CUT + 2;
}

/// The generated grass's draw commands and dispatch sizes, in the Vulkan renderer's buffer of
/// them (`DrawCommand`s, four words each; the shaders name them through `declared.rs`): the
/// levels' draws (`instanced::LODS`) and the splatted blades' count first.
pub mod generated {
    use crate::instanced::SPLAT_LEVEL;

    /// The blades drawn by compute, splatted and rasterized, counted (a command never drawn:
    /// the levels' draws come before it).
    pub const SPLAT_COMMAND: u32 = SPLAT_LEVEL as u32;
    /// The billboards' draw command.
    pub const BILLBOARD_COMMAND: u32 = SPLAT_COMMAND + 1;
    /// The generating passes' dispatch sizes, the instanced grass's then the billboards'
    /// (written by the patch cull).
    pub const PATCH_DISPATCH: u32 = BILLBOARD_COMMAND + 1;
    /// The compute billboard rasterizer's dispatch size (the billboards' scan writes it: a
    /// workgroup a quad), and in its last word how many quads it rasterizes.
    pub const BILLBOARD_RASTER_DISPATCH: u32 = PATCH_DISPATCH + 2;
    /// The billboards the raster hardware draws where the rest are rasterized by compute: their
    /// draw command (the billboard rasterizer counts them).
    pub const HARDWARE_BILLBOARD_COMMAND: u32 = BILLBOARD_RASTER_DISPATCH + 1;
    /// The placing passes' dispatch sizes, the instanced grass's (over the patches that may hold
    /// listed blades) then the billboards' (written by the patch cull).
    pub const PLACE_DISPATCH: u32 = HARDWARE_BILLBOARD_COMMAND + 1;
    /// The count of the instanced blades rasterized by compute.
    pub const RASTER_COMMAND: u32 = PLACE_DISPATCH + 2;
    /// The instanced blades' rasterizer runs chunk by chunk of their list, nearest first: each
    /// chunk's dispatch size and first blade from here (the scan writes them).
    pub const RASTER_CHUNK_DISPATCH: u32 = RASTER_COMMAND + 1;
    /// Chunks of the rasterized blades' list.
    pub const RASTER_CHUNKS: u32 = 5;
    /// The commands in all.
    pub const COMMANDS: u32 = RASTER_CHUNK_DISPATCH + RASTER_CHUNKS;
    /// The lists the instanced grass's generating workgroups count their blades into: one a
    /// level of detail, and the blades rasterized by compute (the billboards' grid has one).
    pub const INSTANCED_LISTS: u32 = SPLAT_LEVEL as u32 + 1;

    /// Every slot with its name, as the shaders spell it.
    pub const ALL: [(&str, u32); 10] = [
        ("SPLAT_COMMAND", SPLAT_COMMAND),
        ("BILLBOARD_COMMAND", BILLBOARD_COMMAND),
        ("PATCH_DISPATCH", PATCH_DISPATCH),
        ("BILLBOARD_RASTER_DISPATCH", BILLBOARD_RASTER_DISPATCH),
        ("HARDWARE_BILLBOARD_COMMAND", HARDWARE_BILLBOARD_COMMAND),
        ("PLACE_DISPATCH", PLACE_DISPATCH),
        ("RASTER_COMMAND", RASTER_COMMAND),
        ("RASTER_CHUNK_DISPATCH", RASTER_CHUNK_DISPATCH),
        ("RASTER_CHUNKS", RASTER_CHUNKS),
        ("INSTANCED_LISTS", INSTANCED_LISTS),
    ];

    /// The commands as a renderer uploads them before its first frame: each level's strip (its
    /// vertices, and its level as its first vertex, `STRIP_STRIDE` apart: the strips' vertex
    /// stage reads it), the billboards' three quads (both their commands), every count and
    /// dispatch size zero. A frame resets the counts; the patch cull and the scans write the
    /// dispatch sizes.
    pub fn initial() -> Vec<crate::gpu::DrawCommand> {
        use crate::gpu::DrawCommand;
        let mut commands = vec![DrawCommand::default(); COMMANDS as usize];
        for (level, segments) in (0..).zip(crate::instanced::LOD_SEGMENTS) {
            commands[level as usize] = DrawCommand {
                vertex_count: 2 * segments + 1,
                first_vertex: level * super::STRIP_STRIDE,
                ..DrawCommand::default()
            };
        }
        // Three quads of two triangles a billboard.
        for k in [BILLBOARD_COMMAND, HARDWARE_BILLBOARD_COMMAND] {
            commands[k as usize].vertex_count = 18;
        }
        commands
    }
}

/// How far the buckets reach (buckets.wesl `bucket_range`): to the distance test's cut-off
/// `distance_max`, or eight times the level-of-detail far distance `lod_far` if nearer.
pub fn bucket_range(lod_far: f32, distance_max: f32) -> f32 {
    (lod_far * 8.0).min(distance_max).max(1.0)
}

/// A visible blade's distance bucket (buckets.wesl `distance_bucket`): square-root spaced
/// over `range`.
pub fn distance_bucket(range: f32, dist: f32) -> u32 {
    let f = (dist.max(0.0) / range).sqrt();
    ((f * DISTANCE_BUCKETS as f32) as u32).min(DISTANCE_BUCKETS - 1)
}

/// The first bucket whose blades all lie at least `dist` from the eye (`DISTANCE_BUCKETS`
/// where none does).
pub fn first_bucket_beyond(range: f32, dist: f32) -> u32 {
    let f = (dist.max(0.0) / range).sqrt();
    ((f * DISTANCE_BUCKETS as f32).ceil() as u32).min(DISTANCE_BUCKETS)
}

/// Every slot constant with its name, as the shaders spell it.
pub const ALL: [(&str, u32); 21] = [
    ("COMMAND_ALL", COMMAND_ALL),
    ("COMMAND_BUCKETS", COMMAND_BUCKETS),
    ("DISTANCE_BUCKETS", DISTANCE_BUCKETS),
    ("COMMAND_SPLAT_DISPATCH", COMMAND_SPLAT_DISPATCH),
    ("COMMAND_MESH_DISPATCH", COMMAND_MESH_DISPATCH),
    ("COMMAND_RASTER_DISPATCH", COMMAND_RASTER_DISPATCH),
    ("COMMAND_RASTER_LEFT", COMMAND_RASTER_LEFT),
    ("COMMAND_RASTER_RETRY", COMMAND_RASTER_RETRY),
    ("COMMAND_OCCLUDERS", COMMAND_OCCLUDERS),
    ("COMMAND_SORT_DISPATCH", COMMAND_SORT_DISPATCH),
    ("COMMAND_TILE_DISPATCH", COMMAND_TILE_DISPATCH),
    ("COMMAND_SPLITS", COMMAND_SPLITS),
    ("BUCKET_SHIFT", BUCKET_SHIFT),
    ("OCCLUDER_SEGMENTS", OCCLUDER_SEGMENTS),
    ("STRIP_STRIDE", STRIP_STRIDE),
    ("BUCKET_STARTS", counters::BUCKET_STARTS),
    ("DRAWN_BUCKETS", counters::DRAWN_BUCKETS),
    ("COUNTED_GROUPS", counters::COUNTED_GROUPS),
    ("OCCLUDER_CUT", counters::OCCLUDER_CUT),
    ("TILE_KEY_STEPS", crate::tiles::TILE_KEY_STEPS),
    ("TILE_INDEX_BITS", crate::tiles::TILE_INDEX_BITS),
];

const _: () = assert!(1u64 << BUCKET_SHIFT >= crate::validate::MAX_BLADES as u64);
const _: () = assert!(DISTANCE_BUCKETS <= 1 << (32 - BUCKET_SHIFT));
