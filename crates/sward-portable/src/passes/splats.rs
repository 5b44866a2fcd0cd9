//! The far field splatted on the portable renderer (SPEC §7 \[F\], §10), where the device has
//! 64-bit atomic min/max and the renderer draws into a target of its own: the splat target — per
//! cell the nearest (depth, colour) as one 64-bit word, one cell per sample on a 4× target, then
//! the tiles' farthest depths — as the Vulkan renderer's (`sward-gpu` `passes/splats.rs`); the
//! generated grass made by the Vulkan renderer's passes (sward-core `wgsl::splatting`): both
//! grids' patches kept, each grid counted with its far blades and billboards splatted, scanned and
//! placed, the nearer far blades and billboards rasterized by compute; and the cells resolved
//! into the frame by a screen-covering triangle a sample at a time.
//!
//! Where the Vulkan renderer dispatches a pass from a size an earlier pass wrote into the
//! commands it also binds, wgpu may not read a dispatch's size from a buffer the dispatch
//! writes: the commands are copied (a few hundred bytes) after the passes that write sizes.

use sward_core::commands::generated::{
    self as commands, BILLBOARD_RASTER_DISPATCH, INSTANCED_LISTS, PATCH_DISPATCH, PLACE_DISPATCH, RASTER_CHUNK_DISPATCH,
};
use sward_core::declared::{bindings, constants};
use sward_core::wgsl::splatting::{
    patch_cull, BILLBOARD_RASTER_LAYERED, GENERATED_SCAN, GENERATE_PLACE, GENERATE_SPLATS_LAYERED,
    INSTANCED_RASTER_LAYERED, SPLAT_CLEAR, SPLAT_LISTED_BLADES, SPLAT_TILES,
};

use super::draw::{Attachments, DrawInputs};
use super::generated::{GeneratedDraws, GeneratedLists, GrassTexture};
use super::FrameParts;
use crate::shaders::ShaderModules;
use crate::{compute_pipeline_with, dispatch, Bindable, Bound, Dispatch, Groups, PortableError, Reading, FRAME};

/// Bytes of one splat cell: its depth bits above its colour (8), or its 16-bit depth key above
/// its 16-bit colour where cells are narrow (4).
const fn splat_bytes(narrow: bool) -> u64 {
    if narrow {
        4
    } else {
        8
    }
}
/// Side of a splat tile in cells (splat.wesl `SPLAT_TILE`).
const SPLAT_TILE: u32 = 8;
/// Chunks of the instanced blades' compute rasterizer.
const RASTER_CHUNKS: usize = commands::RASTER_CHUNKS as usize;
/// Invocations of the billboards' generating workgroups, and of the instanced grass's where
/// the device runs no more (WebGPU's most).
const GENERATE_WORKGROUP: u32 = 256;

/// Invocations of the instanced grass's generating workgroups on `device`: a patch's cells
/// (1,024) to a workgroup where the device runs that many and holds their splat queue (20
/// bytes each), as the Vulkan renderer does (`ComputeOptions::instanced_workgroup_on`: 4.5 %
/// of the frame at 2^26 blades on the H200), else [`GENERATE_WORKGROUP`].
pub(crate) fn instanced_workgroup(device: &wgpu::Device) -> u32 {
    let limits = device.limits();
    let patch = sward_core::instanced::PATCH_BLADES;
    let queue_bytes = 4 * 6 + 4 * 64 + 20 * patch;
    let runs = limits.max_compute_invocations_per_workgroup >= patch
        && limits.max_compute_workgroup_size_x >= patch
        && limits.max_compute_workgroup_storage_size >= queue_bytes;
    if runs {
        patch
    } else {
        GENERATE_WORKGROUP
    }
}
/// Words cleared by one workgroup of `clear_splats`.
const CLEAR_GROUP: u64 = 256;
/// Invocations of a workgroup splatting Bezier blades (buckets.wesl `SPLAT_LANES`).
const SPLAT_LANES: u32 = 256;
/// The cull's command holding the splatted buckets' dispatch size (buckets.wesl
/// `SPLAT_BLADES_COMMAND`: after the buckets' and the occluders').
const SPLAT_BLADES_COMMAND: u64 = sward_core::commands::DISTANCE_BUCKETS as u64 + 1;

/// The features a device splats with: 64-bit integers and their atomic min and max.
pub const SPLAT_FEATURES: wgpu::Features =
    wgpu::Features::SHADER_INT64.union(wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX);

/// The most storage buffers a splatting pass binds in one stage: WebGPU's default, so a
/// browser's device splats with its default limits (there, 32-bit cells bound once a pass, one
/// fewer: `single_splat_binding`). A device without 64-bit atomics that binds fewer draws its
/// far field.
pub const SPLAT_STORAGE_BUFFERS: u32 = 8;

/// `modules` as the splatting passes of a device on `backend` compile them, in 32-bit cells
/// where `narrow`: bound once a pass on a browser's WebGPU, which refuses a buffer bound twice
/// where either binding is writable (or where `modules` ask for it); elsewhere through a second,
/// plain view of the cells for their plain reads, faster (docs/benchmarks-history.md).
pub(crate) fn splat_modules(modules: &ShaderModules, narrow: bool, backend: wgpu::Backend) -> ShaderModules {
    let single = modules.single_splat_binding() || backend == wgpu::Backend::BrowserWebGpu;
    modules
        .clone()
        .with_narrow_splats(narrow)
        .with_single_splat_binding(narrow && single)
}

/// How a device of `features` and `limits` splats, as `asked` (`ShaderModules::narrow_splats`):
/// `Some(false)` into 64-bit cells (it has 64-bit atomic min and max), `Some(true)` into 32-bit
/// ones (it has not — the rule: on the H100 and lavapipe they beat drawing the far field as
/// geometry wherever generated grass is drawn, docs/benchmarks-history.md — or they are asked for:
/// `--narrow-splats`), `None` not at all: its far field drawn as geometry (it binds too few
/// storage buffers in a stage, or no narrow cells are asked for: `--without
/// int64-atomics,narrow-splats`).
pub(crate) fn splat_cells(features: wgpu::Features, limits: &wgpu::Limits, asked: Option<bool>) -> Option<bool> {
    let wide = features.contains(SPLAT_FEATURES);
    let binds = limits.max_storage_buffers_per_shader_stage >= SPLAT_STORAGE_BUFFERS;
    match (wide, asked) {
        (true, None | Some(false)) => Some(false),
        (_, Some(true)) | (false, None) => binds.then_some(true),
        (false, Some(false)) => None,
    }
}

/// The splatting passes and the resolve.
#[derive(Clone)]
pub(crate) struct SplatPipelines {
    patches: Reading<wgpu::ComputePipeline>,
    /// Per grid (the instanced grass's, the billboards'): count with splats, scan, place.
    grids: [[Reading<wgpu::ComputePipeline>; 3]; 2],
    /// The instanced blades' compute rasterizer, chunk by chunk.
    chunks: [Reading<wgpu::ComputePipeline>; RASTER_CHUNKS],
    /// The splat tiles' farthest depths between the chunks.
    tiles: Reading<wgpu::ComputePipeline>,
    /// The billboards' compute rasterizer.
    billboards: Reading<wgpu::ComputePipeline>,
    /// The far Bezier blades, over the cull's list.
    bezier: Reading<wgpu::ComputePipeline>,
    clear: Reading<wgpu::ComputePipeline>,
    /// The resolve into the renderer's own draw; none where an engine resolves the cells
    /// ([`crate::PortableRenderer::for_engine`]).
    resolve: Option<Reading<wgpu::RenderPipeline>>,
}

impl SplatPipelines {
    /// The passes, the resolve made for attachments like `target` (none without one).
    pub fn new(
        (device, backend): (&wgpu::Device, wgpu::Backend),
        target: Option<&Attachments>,
        modules: &ShaderModules,
    ) -> Result<SplatPipelines, PortableError> {
        let make = |source, overrides: &[(u32, u32)]| compute_pipeline_with(device, source, modules, overrides);
        // Every pass's workgroup size and the instanced grass's (which lay out the counts), as
        // the Vulkan renderer gives every pass.
        let instanced = instanced_workgroup(device);
        let sized = [
            (constants::WORKGROUP, GENERATE_WORKGROUP),
            (constants::INSTANCED_WORKGROUP, instanced),
        ];
        let grid = |billboards: bool| -> Result<[Reading<wgpu::ComputePipeline>; 3], PortableError> {
            let this_grid = (constants::BILLBOARDS, billboards as u32);
            let generating = match billboards {
                true => [sized[0], sized[1], this_grid],
                false => [(constants::WORKGROUP, instanced), sized[1], this_grid],
            };
            Ok([
                make(&GENERATE_SPLATS_LAYERED[billboards as usize], &generating)?,
                make(&GENERATED_SCAN, &[sized[0], sized[1], this_grid])?,
                make(&GENERATE_PLACE, &generating)?,
            ])
        };
        let chunk = |k: u32| make(&INSTANCED_RASTER_LAYERED, &[sized[0], sized[1], (constants::CHUNK, k)]);
        Ok(SplatPipelines {
            patches: make(&patch_cull(&[]), &sized)?,
            grids: [grid(false)?, grid(true)?],
            chunks: [chunk(0)?, chunk(1)?, chunk(2)?, chunk(3)?, chunk(4)?],
            tiles: make(&SPLAT_TILES, &[(constants::GENERATED, 1)])?,
            billboards: make(&BILLBOARD_RASTER_LAYERED, &sized)?,
            bezier: make(&SPLAT_LISTED_BLADES, &[(constants::WORKGROUP, SPLAT_LANES)])?,
            clear: make(&SPLAT_CLEAR, &[])?,
            resolve: target
                .map(|t| super::resolve::resolve_pipeline(device, backend, t, modules))
                .transpose()?,
        })
    }
}

/// The splat cells and tiles, as large as the frames so far asked.
pub(crate) struct SplatTarget {
    buffer: wgpu::Buffer,
    /// Cells of 32 bits (`narrow_splats`), else 64.
    narrow: bool,
    /// Samples per pixel of the attachments it is resolved into.
    samples: u32,
    /// Splat cells per pixel side: 2 on a 4× target (one cell per sample), else 1.
    scale: u32,
    /// Tiles across and down, as of the last `prepare`.
    tiles: [u32; 2],
    /// Whether the frame being recorded splats.
    in_use: bool,
}

impl SplatTarget {
    /// An empty target for attachments of `samples` per pixel, its cells 32 bits wide where
    /// `narrow`.
    pub fn new(device: &wgpu::Device, samples: u32, narrow: bool) -> SplatTarget {
        SplatTarget {
            buffer: cell_buffer(device, splat_bytes(narrow)),
            narrow,
            samples,
            scale: if samples == 4 { 2 } else { 1 },
            tiles: [0, 0],
            in_use: false,
        }
    }

    /// An empty target for another field's renderer, for the same attachments.
    pub fn sibling(&self, device: &wgpu::Device) -> SplatTarget {
        SplatTarget::new(device, self.samples, self.narrow)
    }

    /// Splat cells per pixel side.
    pub fn scale(&self) -> u32 {
        self.scale
    }

    /// Get ready for a frame of `viewport` pixels that splats (`splatting`) or not: the cells
    /// grown to the viewport where they are smaller. Returns whether they grew (the bind groups
    /// made of the old ones are stale).
    pub fn prepare(&mut self, device: &wgpu::Device, viewport: [u32; 2], splatting: bool) -> bool {
        self.in_use = splatting;
        let size = viewport.map(|n| n * self.scale);
        self.tiles = size.map(|n| n.div_ceil(SPLAT_TILE));
        let cells = size[0] as u64 * size[1] as u64 + 2 * self.tiles[0] as u64 * self.tiles[1] as u64;
        let bytes = cells * splat_bytes(self.narrow);
        if !splatting || bytes <= self.buffer.size() {
            return false;
        }
        self.buffer = cell_buffer(device, bytes);
        true
    }

    /// Whether the frame being recorded splats.
    pub fn in_use(&self) -> bool {
        self.in_use
    }

    /// Bytes the target holds.
    pub fn bytes(&self) -> u64 {
        self.buffer.size()
    }

    /// Resolve into attachments of `samples` per pixel from the next frame on: one cell per
    /// sample on a 4× target, else one per pixel (an engine's camera may change its MSAA).
    pub fn set_samples(&mut self, samples: u32) {
        self.samples = samples;
        self.scale = if samples == 4 { 2 } else { 1 };
    }

    /// The cells, as the frame last recorded left them.
    pub fn cells(&self) -> &wgpu::Buffer {
        &self.buffer
    }
}

/// The splat buffer of `bytes`: its cells, then this frame's and the last frame's tiles (a
/// cell's size each).
fn cell_buffer(device: &wgpu::Device, bytes: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("sward splat cells"),
        size: bytes,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    })
}

/// How the frame draws its generated grass by compute, as its plan decided.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SplatShape {
    /// The instanced blades between the raster distance and the splat distance are rasterized
    /// by compute.
    pub blades_rasterized: bool,
    /// Billboards short of their splat distance are rasterized by compute.
    pub billboards_rasterized: bool,
    /// The far Bezier blades are splatted: the distance buckets from `first_splatted` on
    /// (`DISTANCE_BUCKETS`: none), which the strips leave out.
    pub bezier: bool,
    pub first_splatted: u32,
}

/// What the splatting passes read beside the lists: the view's depth pyramid, the shadow map,
/// the billboards' painted texture (both grids' counting pass binds it: the grid is an
/// override).
pub(crate) struct SplatReads<'a> {
    pub levels: &'a wgpu::Buffer,
    pub shadow_map: [(u32, Bound<'a>); 2],
    pub grass_texture: Option<&'a GrassTexture>,
}

impl Default for SplatShape {
    /// Nothing drawn by compute: every bucket drawn as strips.
    fn default() -> SplatShape {
        SplatShape {
            blades_rasterized: false,
            billboards_rasterized: false,
            bezier: false,
            first_splatted: sward_core::commands::DISTANCE_BUCKETS,
        }
    }
}

/// Record every word of the splat buffer set to all ones, before the frame's passes splat into
/// it.
pub(crate) fn record_clear(
    parts: &FrameParts,
    encoder: &mut wgpu::CommandEncoder,
    (pipelines, target): (&SplatPipelines, &SplatTarget),
) {
    let words = target.buffer.size() / 4;
    let most = u64::from(parts.device.limits().max_compute_workgroups_per_dimension);
    let across = words.div_ceil(CLEAR_GROUP).min(most);
    let down = words.div_ceil(CLEAR_GROUP * across);
    // The clear binds the buffer as words (wide cells) or as the cells themselves (narrow).
    let cells = [
        (bindings::SPLAT_WORDS, Bound::Buffer(&target.buffer)),
        (bindings::SPLAT_CELLS, Bound::Buffer(&target.buffer)),
    ];
    let clear: [Dispatch; 1] = [(
        &pipelines.clear,
        &cells[..],
        Groups::Direct([across as u32, down as u32]),
    )];
    dispatch((parts.device, parts.groups), encoder, &clear);
}

/// The cull's list and commands a frame splats the far Bezier blades from.
pub(crate) struct ListedBlades<'a> {
    pub blades: &'a wgpu::Buffer,
    pub visible: &'a wgpu::Buffer,
    pub draws: &'a wgpu::Buffer,
    pub counters: &'a wgpu::Buffer,
}

/// Record the far Bezier blades splatted: the buckets from the frame's hand-over on, a blade an
/// invocation, dispatched with the size the cull wrote (cull.wesl `lay_out_buckets`).
pub(crate) fn record_bezier_splats(
    parts: &FrameParts,
    encoder: &mut wgpu::CommandEncoder,
    (pipelines, target): (&SplatPipelines, &SplatTarget),
    (listed, shadow_map): (&ListedBlades, [(u32, Bound); 2]),
) {
    let b = Bound::Buffer;
    let [map, sampler] = shadow_map;
    let read = [
        (FRAME, b(parts.frame)),
        (bindings::BLADES, b(listed.blades)),
        (bindings::ORDERED, b(listed.visible)),
        (bindings::DRAWS, b(listed.draws)),
        (bindings::CULL_COUNTERS, b(listed.counters)),
        (bindings::PAINT, b(parts.paint)),
        (bindings::TRAMPLE, b(parts.trample)),
        (bindings::SPLAT_CELLS, b(&target.buffer)),
        (bindings::SPLAT_WORDS, b(&target.buffer)),
        map,
        sampler,
    ];
    let at = SPLAT_BLADES_COMMAND * GeneratedDraws::COMMAND_BYTES;
    let splats: [Dispatch; 1] = [(&pipelines.bezier, &read[..], Groups::Indirect(listed.draws, at))];
    dispatch((parts.device, parts.groups), encoder, &splats);
}

/// Record the frame's generated grass by the splatting passes, into `lists`, after the splat
/// buffer was cleared: the commands reset; both grids' patches kept; per grid its counting
/// (splatting its far blades), scan and placing passes; the instanced blades' compute
/// rasterizer chunk by chunk with the tiles' farthest depths between chunks, and the
/// billboards'.
pub(crate) fn record_splatting(
    parts: &FrameParts,
    encoder: &mut wgpu::CommandEncoder,
    (pipelines, target): (&SplatPipelines, &SplatTarget),
    (lists, reads): (&GeneratedLists, &SplatReads),
    shape: SplatShape,
) {
    let on = lists.generates();
    if on == [false; 2] {
        return;
    }
    let b = Bound::Buffer;
    let [patches, listed, counts] = lists.buffers();
    let [map, sampler] = reads.shadow_map;
    let mut read = vec![
        (FRAME, b(parts.frame)),
        (bindings::DEPTH_PYRAMID, b(reads.levels)),
        (bindings::PATCHES, b(patches)),
        (bindings::GENERATED_BLADES, b(listed)),
        (bindings::GENERATED_DRAWS, b(&lists.draws)),
        (bindings::GENERATED_COUNTS, b(counts)),
        (bindings::GROUND, b(parts.ground)),
        (bindings::TRAMPLE, b(parts.trample)),
        (bindings::PAINT, b(parts.paint)),
        (bindings::SPLAT_CELLS, b(&target.buffer)),
        (bindings::SPLAT_WORDS, b(&target.buffer)),
        // The tiles' pass names the Bezier cull's commands, which it writes only after the
        // Bezier rasterizer's first pass, never between the instanced rasterizer's chunks.
        (bindings::DRAWS, b(&lists.draws)),
        map,
        sampler,
    ];
    if let Some(texture) = reads.grass_texture {
        read.extend([
            (bindings::GRASS_TEXTURE, Bound::View(&texture.view)),
            (bindings::GRASS_SAMPLER, Bound::Sampler(&texture.sampler)),
        ]);
    }
    let device_groups = (parts.device, parts.groups);
    let initial = lists
        .initial
        .as_ref()
        .expect("splatting lists hold their first commands");
    encoder.copy_buffer_to_buffer(initial, 0, &lists.draws, 0, initial.size());
    dispatch(
        device_groups,
        encoder,
        &[(&pipelines.patches, &read[..], Groups::Direct([2, 1]))],
    );
    let sizes = &lists.dispatches;
    encoder.copy_buffer_to_buffer(&lists.draws, 0, sizes, 0, sizes.size());
    let command = |k: u32| u64::from(k) * GeneratedDraws::COMMAND_BYTES;
    let mut passes: Vec<Dispatch> = Vec::new();
    for (g, [count, scan, place]) in pipelines.grids.iter().enumerate().filter(|(g, _)| on[*g]) {
        let lists_of = if g == 0 { INSTANCED_LISTS } else { 1 };
        let g = g as u32;
        passes.extend([
            (count, &read[..], Groups::Indirect(sizes, command(PATCH_DISPATCH + g))),
            (scan, &read[..], Groups::Direct([lists_of, 1])),
            (place, &read[..], Groups::Indirect(sizes, command(PLACE_DISPATCH + g))),
        ]);
    }
    dispatch(device_groups, encoder, &passes);
    let blades = on[0] && shape.blades_rasterized;
    let billboards = on[1] && shape.billboards_rasterized;
    if !(blades || billboards) {
        return;
    }
    // The scans wrote the rasterizers' sizes.
    encoder.copy_buffer_to_buffer(&lists.draws, 0, sizes, 0, sizes.size());
    let mut rasters: Vec<Dispatch> = Vec::new();
    if blades {
        let [across, down] = target.tiles;
        for (k, chunk) in (0..).zip(&pipelines.chunks) {
            if k > 0 {
                rasters.push((&pipelines.tiles, &read[..], Groups::Direct([across.div_ceil(8), down])));
            }
            rasters.push((
                chunk,
                &read[..],
                Groups::Indirect(sizes, command(RASTER_CHUNK_DISPATCH + k)),
            ));
        }
    }
    if billboards {
        rasters.push((
            &pipelines.billboards,
            &read[..],
            Groups::Indirect(sizes, command(BILLBOARD_RASTER_DISPATCH)),
        ));
    }
    dispatch(device_groups, encoder, &rasters);
}

/// Draw the splat cells into the frame (inside the camera's draw, after the drawn grass), where
/// the frame splats.
pub(crate) fn record_resolve(
    (device, pass): (&wgpu::Device, &mut wgpu::RenderPass),
    (pipelines, target): (&SplatPipelines, &SplatTarget),
    inputs: &DrawInputs,
) {
    let (true, Some(resolve)) = (target.in_use, &pipelines.resolve) else {
        return;
    };
    let read = [
        (FRAME, Bound::Buffer(inputs.frame)),
        (bindings::SPLAT_WORDS, Bound::Buffer(&target.buffer)),
    ];
    let group = inputs.groups.of(device, Bindable::Render(resolve), &read);
    pass.set_pipeline(resolve);
    pass.set_bind_group(0, &group, &[]);
    pass.draw(0..3, 0..1);
}
