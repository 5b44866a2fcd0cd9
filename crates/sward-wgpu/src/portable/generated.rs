//! The generated grass on the portable renderer (SPEC §7 \[F\]; generated.wgsl,
//! generated_strips.wgsl): its four passes, and each view's buffers — the patch rows and the
//! ring order they are picked from, the counts, the levels' visible lists and their draw
//! commands. No blade is stored: each frame the GPU makes the blades of the grid around the eye,
//! culls them and lists each at its level of detail, posed; the draw pulls them from the lists.
//! The lists are laid out as the Vulkan renderer lays out its own (sward-core's
//! `GeneratedLayout`), so both list the same blades in the same places. Nothing is splatted here:
//! every blade within the cut-off is drawn by the raster hardware.

use sward_core::gpu::{GeneratedLayout, GeneratedRows};
use sward_core::instanced::{patch_order, LODS, PATCH_BLADES};
use sward_core::plan::FrameDecisions;
use sward_core::FrameDesc;
use wgpu::util::DeviceExt;

use super::shaders::GENERATED_SOURCES;
use super::{compute_pipeline, dispatch, BindGroups, Bound, Dispatch, Groups, PortableError};

/// Bytes of one listed blade.
const BLADE_BYTES: u64 = 32;
/// Invocations of a generating workgroup (generated.wgsl `GENERATE_GROUP`), and the workgroups
/// of a patch's row.
const GENERATE_GROUP: u64 = 256;
const GROUPS_ACROSS: u64 = PATCH_BLADES as u64 / GENERATE_GROUP;
/// The placing pass's dispatch size in the dispatch buffer (after the counting pass's).
const PLACE_DISPATCH_OFFSET: u64 = 12;

/// The generating passes: keep the patches, count, scan, place.
pub(crate) struct GeneratedPipelines([wgpu::ComputePipeline; 4]);

impl GeneratedPipelines {
    pub fn new(device: &wgpu::Device) -> Result<GeneratedPipelines, PortableError> {
        let [patches, count, scan, place] = &GENERATED_SOURCES;
        Ok(GeneratedPipelines([
            compute_pipeline(device, patches)?,
            compute_pipeline(device, count)?,
            compute_pipeline(device, scan)?,
            compute_pipeline(device, place)?,
        ]))
    }
}

/// What the generating passes read beside a view's own buffers.
pub(crate) struct GeneratingInputs<'a> {
    /// The view's uniforms.
    pub frame: &'a wgpu::Buffer,
    /// The ground's height grid (its vertices).
    pub ground: &'a wgpu::Buffer,
    /// The trample map's texels.
    pub trample: &'a wgpu::Buffer,
    /// The paint maps' texels.
    pub paint: &'a wgpu::Buffer,
    /// The view's depth pyramid.
    pub pyramid: &'a wgpu::Buffer,
}

/// One view's generated grass: where its patches, counts and lists are kept, as large as the
/// frames so far asked.
pub(crate) struct GeneratedLists {
    /// The patch rows (both grids', as sward-core lays them out), then the ring order.
    patches: wgpu::Buffer,
    rows: GeneratedRows,
    ring_len: u32,
    /// The levels' visible lists, one after another.
    listed: wgpu::Buffer,
    listed_entries: u64,
    /// One draw command per level (written by the patch pass each frame).
    draws: wgpu::Buffer,
    /// Per counting workgroup and level: its blades, then their place.
    counts: wgpu::Buffer,
    count_words: u64,
    /// The counting and placing passes' dispatch sizes.
    dispatches: wgpu::Buffer,
    /// The lists as the last frame prepared them, and whether it generated any.
    layout: GeneratedLayout,
    on: bool,
}

impl GeneratedLists {
    pub fn new(device: &wgpu::Device) -> GeneratedLists {
        let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_SRC;
        GeneratedLists {
            patches: patch_buffer(device, &GeneratedRows::default()).0,
            rows: GeneratedRows::default(),
            ring_len: 1,
            listed: storage(device, "sward generated blades", BLADE_BYTES),
            listed_entries: 1,
            draws: buffer(device, "sward generated draws", 16 * LODS as u64, usage),
            counts: storage(device, "sward generated counts", 4),
            count_words: 1,
            dispatches: buffer(device, "sward generated dispatches", 24, usage),
            layout: GeneratedLayout::default(),
            on: false,
        }
    }

    /// This frame's lists (as `desc`'s technique asks, drawn as `decided` says): where they
    /// start and what they hold, from the most patches each grid may keep. The buffers grow
    /// when the grids' reach or density asks for more than they hold, never from what a frame
    /// kept; returns whether one grew (the bind groups made of the old ones are stale).
    pub fn prepare(&mut self, device: &wgpu::Device, desc: &FrameDesc, decided: &FrameDecisions) -> bool {
        self.on = decided.generates && desc.technique.draws_instanced();
        if !self.on {
            self.layout = GeneratedLayout::default();
            return false;
        }
        let limits = device.limits();
        let kept = GeneratedRows::of(desc, decided, limits.max_compute_workgroups_per_dimension);
        let mut grown = false;
        if !self.rows.holds(&kept) {
            self.rows = self.rows.max(&kept);
            (self.patches, self.ring_len) = patch_buffer(device, &self.rows);
            grown = true;
        }
        let binding = (limits.max_storage_buffer_binding_size as u64).min(limits.max_buffer_size);
        let (layout, entries) = GeneratedLayout::of(decided, &kept, (&self.rows, self.ring_len), binding / BLADE_BYTES);
        if entries > self.listed_entries {
            self.listed_entries = (entries * 3 / 2).min(binding / BLADE_BYTES).max(entries);
            self.listed = storage(device, "sward generated blades", self.listed_entries * BLADE_BYTES);
            grown = true;
        }
        let words = 1 + LODS as u64 * self.rows.rows[0] as u64 * GROUPS_ACROSS;
        if words > self.count_words {
            self.count_words = words;
            self.counts = storage(device, "sward generated counts", 4 * words);
            grown = true;
        }
        self.layout = layout;
        grown
    }

    /// The lists as the last prepared frame lays them out.
    pub fn layout(&self) -> GeneratedLayout {
        self.layout
    }

    /// Record the frame's generating passes where it generates: the patches kept, each
    /// workgroup's blades counted per level (a row of workgroups per kept patch, as the patch
    /// pass sized it), the counts scanned (a workgroup per level), the blades placed.
    pub fn record(
        &self,
        (device, groups): (&wgpu::Device, &BindGroups),
        encoder: &mut wgpu::CommandEncoder,
        pipelines: &GeneratedPipelines,
        inputs: &GeneratingInputs,
    ) {
        if !self.on {
            return;
        }
        let b = Bound::Buffer;
        let [patches, count, scan, place] = &pipelines.0;
        let keeping = [
            (0, b(inputs.frame)),
            (8, b(inputs.pyramid)),
            (11, b(&self.patches)),
            (13, b(&self.draws)),
            (14, b(&self.counts)),
            (15, b(&self.dispatches)),
        ];
        let made_of = [
            (0, b(inputs.frame)),
            (7, b(inputs.ground)),
            (9, b(inputs.trample)),
            (11, b(&self.patches)),
            (14, b(&self.counts)),
            (20, b(inputs.paint)),
        ];
        let counting: Vec<(u32, Bound)> = made_of.iter().copied().chain([(13, b(&self.draws))]).collect();
        let placing: Vec<(u32, Bound)> = made_of.iter().copied().chain([(12, b(&self.listed))]).collect();
        let scanning = [(14, b(&self.counts))];
        let passes: [Dispatch; 4] = [
            (patches, &keeping[..], Groups::Direct([1, 1])),
            (count, &counting[..], Groups::Indirect(&self.dispatches, 0)),
            (scan, &scanning[..], Groups::Direct([LODS as u32, 1])),
            (
                place,
                &placing[..],
                Groups::Indirect(&self.dispatches, PLACE_DISPATCH_OFFSET),
            ),
        ];
        dispatch((device, groups), encoder, &passes);
    }

    /// Draw the levels' lists with the pipeline and bind group set (its group 0 binds
    /// [`GeneratedLists::listed`]), where the frame generated any.
    pub fn record_draw(&self, pass: &mut wgpu::RenderPass) {
        if self.on {
            pass.multi_draw_indirect(&self.draws, 0, LODS as u32);
        }
    }

    /// Whether the last prepared frame generates the instanced grass.
    pub fn generates(&self) -> bool {
        self.on
    }

    /// The levels' visible lists.
    pub fn listed(&self) -> &wgpu::Buffer {
        &self.listed
    }

    /// The draw commands (one per level) and the lists, as the GPU holds them now: each
    /// level's listed blades, 32 bytes each, in the order they are drawn.
    pub fn read(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<Vec<Vec<[u32; 8]>>, PortableError> {
        let draws: Vec<[u32; 4]> =
            bytemuck::pod_collect_to_vec(&super::field::read_buffer(device, queue, &self.draws)?);
        let blades: Vec<[u32; 8]> =
            bytemuck::pod_collect_to_vec(&super::field::read_buffer(device, queue, &self.listed)?);
        Ok(self
            .layout
            .levels
            .iter()
            .zip(&draws)
            .map(|(&[start, cap], draw)| {
                let count = draw[1].min(cap) as usize;
                blades[start as usize..start as usize + count].to_vec()
            })
            .collect())
    }

    /// How many blades the last frame listed at its levels (none where it generated none):
    /// the draw commands' instances, each within its list.
    pub fn count(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<u32, PortableError> {
        if !self.on {
            return Ok(0);
        }
        let draws: Vec<[u32; 4]> =
            bytemuck::pod_collect_to_vec(&super::field::read_buffer(device, queue, &self.draws)?);
        Ok(self
            .layout
            .levels
            .iter()
            .zip(&draws)
            .map(|(&[_, cap], d)| d[1].min(cap))
            .sum())
    }

    /// Bytes of GPU memory the view's generated grass holds.
    pub fn bytes(&self) -> u64 {
        [&self.patches, &self.listed, &self.draws, &self.counts, &self.dispatches]
            .iter()
            .map(|b| b.size())
            .sum()
    }
}

/// A patch buffer for `rows`: zeroed rows for both grids' lists, then the ring order for their
/// reach; and that order's length.
fn patch_buffer(device: &wgpu::Device, rows: &GeneratedRows) -> (wgpu::Buffer, u32) {
    let order = patch_order(rows.reach);
    let entries: Vec<glam::IVec4> = std::iter::repeat_n(glam::IVec4::ZERO, (rows.rows[0] + rows.rows[1]) as usize)
        .chain(order.iter().map(|o| o.extend(0).extend(0)))
        .collect();
    let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("sward generated patches"),
        contents: bytemuck::cast_slice(&entries),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
    });
    (buffer, order.len() as u32)
}

fn storage(device: &wgpu::Device, label: &str, bytes: u64) -> wgpu::Buffer {
    buffer(
        device,
        label,
        bytes,
        wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
    )
}

fn buffer(device: &wgpu::Device, label: &str, bytes: u64, usage: wgpu::BufferUsages) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes,
        usage,
        mapped_at_creation: false,
    })
}
