//! The generated grass on the portable renderer (SPEC §7 \[F\] and \[B\]; generated.wesl,
//! generated_strips.wesl, billboards.wesl): its passes, each view's buffers — the patch rows
//! and the ring order they are picked from, the counts, the visible lists and their draw
//! commands — and the billboards' painted texture. No blade is stored: each frame the GPU makes
//! the blades of both grids around the eye (the instanced grass's, the billboards'), culls them
//! and lists each (a blade at its level of detail, posed; a billboard in one list); the draws
//! pull them from the lists.
//! The lists are laid out as the Vulkan renderer lays out its own (sward-core's
//! `GeneratedLayout`), so both list the same blades in the same places. Where the renderer
//! splats (`splats.rs`: a device with 64-bit atomic min/max, a target of its own) the lists are
//! the Vulkan renderer's own, made by its passes (`sward_core::wgsl::splatting`), with its draw
//! commands (`commands::generated`); elsewhere every blade within the cut-off is listed and drawn
//! by the raster hardware.

use sward_core::commands::generated as splatted;
use sward_core::declared::bindings;
use sward_core::gpu::{GeneratedLayout, GeneratedRows, LISTED_BLADE_BYTES as BLADE_BYTES};
use sward_core::instanced::{patch_order, SeenSector, LODS, PATCH_BLADES};
use sward_core::plan::FrameDecisions;
use wgpu::util::DeviceExt;

use super::FrameParts;
use crate::shaders::{ShaderModules, GENERATED_SOURCES};
use crate::{compute_pipeline, dispatch, Bound, Dispatch, Groups, PortableError, Reading, FRAME};

/// Invocations of a generating workgroup (generated.wesl `GENERATE_GROUP`), and the workgroups
/// of a patch's row.
const GENERATE_GROUP: u64 = 256;
const GROUPS_ACROSS: u64 = PATCH_BLADES as u64 / GENERATE_GROUP;
/// Bytes of a grid's dispatch sizes (counting, placing: x, y, z each), and the placing pass's
/// within them.
const GRID_DISPATCH_BYTES: u64 = 24;
const PLACE_DISPATCH_OFFSET: u64 = 12;
/// The draw commands: the instanced grass's levels, then the billboards'.
const COMMANDS: u64 = GeneratedDraws::COMMANDS as u64;
/// The grids: the instanced grass's, the billboards'.
const GRIDS: usize = 2;

/// The generating passes: both grids' patches kept; per grid its count, scan and place.
#[derive(Clone)]
pub(crate) struct GeneratedPipelines {
    patches: Reading<wgpu::ComputePipeline>,
    grids: [[Reading<wgpu::ComputePipeline>; 3]; GRIDS],
}

impl GeneratedPipelines {
    pub fn new(device: &wgpu::Device, modules: &ShaderModules) -> Result<GeneratedPipelines, PortableError> {
        let [patches, count, scan, place, count_billboards, scan_billboards, place_billboards] = &GENERATED_SOURCES;
        let make = |source| compute_pipeline(device, source, modules);
        Ok(GeneratedPipelines {
            patches: make(patches)?,
            grids: [
                [make(count)?, make(scan)?, make(place)?],
                [make(count_billboards)?, make(scan_billboards)?, make(place_billboards)?],
            ],
        })
    }
}

/// One view's generated grass as an engine's passes draw it: the lists (bound at
/// `engine_bindings::LISTED`), and their draw commands ([`GeneratedDraws::LEVEL_COMMANDS`] at
/// the start of `draws`, then the billboards' at `billboard_command`).
pub struct GeneratedDraws<'a> {
    /// The lists: each blade's 32 bytes (sward-core's `LISTED_BLADE_BYTES`).
    pub listed: &'a wgpu::Buffer,
    /// The draw commands (indirect).
    pub draws: &'a wgpu::Buffer,
    /// Whether the frame listed the instanced grass's levels.
    pub instanced: bool,
    /// Where the frame listed billboards, their painted texture and its sampler.
    pub billboards: Option<(&'a wgpu::TextureView, &'a wgpu::Sampler)>,
    /// How far from the eye each level's blades begin, then the billboards: a pass that draws
    /// only what lies nearer than some distance (a shadow map's reach) leaves out the draws
    /// that begin past it.
    pub starts: [f32; GeneratedDraws::COMMANDS],
    /// The billboards' draw command: [`GeneratedDraws::BILLBOARD_COMMAND`], or where the frame
    /// splatted, the splatting passes' command of the billboards left to the hardware.
    pub billboard_command: u32,
}

impl GeneratedDraws<'_> {
    /// The levels' commands, one a level from the first (each `COMMAND_BYTES` long): level k's
    /// first vertex is k × `STRIP_STRIDE`, which tells its vertex stage the level.
    pub const LEVEL_COMMANDS: u32 = LODS as u32;
    /// The billboards' command, after the levels'.
    pub const BILLBOARD_COMMAND: u32 = LODS as u32;
    /// Bytes of one draw command.
    pub const COMMAND_BYTES: u64 = 16;
    /// The draw commands: the levels', then the billboards'.
    pub const COMMANDS: usize = LODS + 1;

    /// Bytes into `draws` where the billboards' command is.
    pub const fn billboard_offset() -> u64 {
        Self::BILLBOARD_COMMAND as u64 * Self::COMMAND_BYTES
    }
}

/// One view's generated grass: where its patches, counts and lists are kept, as large as the
/// frames so far asked.
pub(crate) struct GeneratedLists {
    /// Whether the lists are the splatting passes' (`splats.rs`), with their commands.
    pub(crate) splats: bool,
    /// The patch rows (both grids', as sward-core lays them out), then the ring order.
    patches: wgpu::Buffer,
    rows: GeneratedRows,
    ring_len: u32,
    /// The levels' visible lists, one after another.
    listed: wgpu::Buffer,
    listed_entries: u64,
    /// One draw command per level, then the billboards' (written by the patch pass each frame);
    /// where the lists are the splatting passes', the Vulkan renderer's commands (reset each
    /// frame from `initial`).
    pub(crate) draws: wgpu::Buffer,
    pub(crate) initial: Option<wgpu::Buffer>,
    /// Per counting workgroup and level: its blades, then their place.
    pub(crate) counts: wgpu::Buffer,
    count_words: u64,
    /// Per grid, its counting and placing passes' dispatch sizes (where the lists are the
    /// splatting passes', a copy of their commands: a dispatch may not read its size from a
    /// buffer it writes).
    pub(crate) dispatches: wgpu::Buffer,
    /// The lists as the last frame prepared them, which grids it generated, and how far from
    /// the eye each list's blades begin.
    layout: GeneratedLayout,
    on: [bool; GRIDS],
    starts: [f32; GeneratedDraws::COMMANDS],
}

impl GeneratedLists {
    /// Lists drawn by the raster hardware alone, or (`splats`) the splatting passes'.
    pub fn new(device: &wgpu::Device, splats: bool) -> GeneratedLists {
        let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_SRC;
        let initial = splats.then(|| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("sward generated commands"),
                contents: bytemuck::cast_slice(&splatted::initial()),
                usage: wgpu::BufferUsages::COPY_SRC,
            })
        });
        let [draw_bytes, dispatch_bytes] = match splats {
            true => [GeneratedDraws::COMMAND_BYTES * splatted::COMMANDS as u64; 2],
            false => [
                GeneratedDraws::COMMAND_BYTES * COMMANDS,
                GRID_DISPATCH_BYTES * GRIDS as u64,
            ],
        };
        GeneratedLists {
            splats,
            patches: patch_buffer(device, &GeneratedRows::default()).0,
            rows: GeneratedRows::default(),
            ring_len: 1,
            listed: storage(device, "sward generated blades", BLADE_BYTES),
            listed_entries: 1,
            draws: buffer(
                device,
                "sward generated draws",
                draw_bytes,
                usage | wgpu::BufferUsages::COPY_DST,
            ),
            initial,
            counts: storage(device, "sward generated counts", 4),
            count_words: 1,
            dispatches: buffer(
                device,
                "sward generated dispatches",
                dispatch_bytes,
                usage | wgpu::BufferUsages::COPY_DST,
            ),
            layout: GeneratedLayout::default(),
            on: [false; GRIDS],
            starts: [0.0; GeneratedDraws::COMMANDS],
        }
    }

    /// This frame's lists (on the grids `decided` generates, drawn as it says): where they
    /// start and what they hold, from the most patches each grid may keep in the sector its
    /// camera sees (`seen`; the whole disk around the eye where it sees every direction). The
    /// buffers grow when the grids' reach or density, or a wider view, asks for more than they
    /// hold, never from what a frame kept; returns whether one grew (the bind groups made of the
    /// old ones are stale).
    pub fn prepare(&mut self, device: &wgpu::Device, decided: &FrameDecisions, seen: Option<&SeenSector>) -> bool {
        self.on = decided.grids;
        let (instanced, billboards) = (&decided.instanced, &decided.billboards);
        let [near, middle, far] = instanced.lod_distances;
        self.starts = [
            instanced.grid.inner_radius,
            near,
            middle,
            far,
            billboards.grid.inner_radius,
        ];
        if self.on == [false; GRIDS] {
            self.layout = GeneratedLayout::default();
            return false;
        }
        let limits = device.limits();
        let kept = GeneratedRows::of(decided, limits.max_compute_workgroups_per_dimension);
        let mut grown = false;
        if !self.rows.holds(&kept) {
            self.rows = self.rows.max(&kept);
            (self.patches, self.ring_len) = patch_buffer(device, &self.rows);
            grown = true;
        }
        let binding = limits.max_storage_buffer_binding_size.min(limits.max_buffer_size);
        let (layout, entries) = GeneratedLayout::of(decided, &kept, (&self.rows, self.ring_len), (binding, seen));
        // Exactly as many as the lists may hold: their capacities are already the most the
        // grids' reach can list in the sector seen (not what a frame kept), so they change only
        // with the scene and the camera's view.
        if entries > self.listed_entries {
            self.listed_entries = entries;
            self.listed = storage(device, "sward generated blades", self.listed_entries * BLADE_BYTES);
            grown = true;
        }
        // Per grid a header word, then per list its workgroups' counts (the splatting passes'
        // instanced grass has a list for its blades rasterized by compute).
        let lists = if self.splats {
            splatted::INSTANCED_LISTS as u64
        } else {
            LODS as u64
        };
        let words = 2 + (lists * self.rows.rows[0] as u64 + self.rows.rows[1] as u64) * GROUPS_ACROSS;
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

    /// Record the frame's generating passes where it generates: both grids' patches kept, then
    /// for each grid it draws each workgroup's blades counted per list (a row of workgroups per
    /// kept patch, as the patch pass sized it), the counts scanned (a workgroup per list), the
    /// blades placed; the patches tested against the view's depth pyramid's `levels`.
    pub fn record(
        &self,
        (parts, levels): (&FrameParts, &wgpu::Buffer),
        encoder: &mut wgpu::CommandEncoder,
        pipelines: &GeneratedPipelines,
    ) {
        if self.on == [false; GRIDS] {
            return;
        }
        let b = Bound::Buffer;
        let keeping = [
            (FRAME, b(parts.frame)),
            (bindings::DEPTH_PYRAMID, b(levels)),
            (bindings::PATCHES, b(&self.patches)),
            (bindings::GENERATED_DRAWS, b(&self.draws)),
            (bindings::GENERATED_COUNTS, b(&self.counts)),
            (bindings::GENERATED_DISPATCH, b(&self.dispatches)),
        ];
        let made_of = [
            (FRAME, b(parts.frame)),
            (bindings::GROUND, b(parts.ground)),
            (bindings::TRAMPLE, b(parts.trample)),
            (bindings::PATCHES, b(&self.patches)),
            (bindings::GENERATED_COUNTS, b(&self.counts)),
            (bindings::PAINT, b(parts.paint)),
        ];
        let counting: Vec<(u32, Bound)> = made_of
            .iter()
            .copied()
            .chain([(bindings::GENERATED_DRAWS, b(&self.draws))])
            .collect();
        let placing: Vec<(u32, Bound)> = made_of
            .iter()
            .copied()
            .chain([(bindings::GENERATED_BLADES, b(&self.listed))])
            .collect();
        let scanning = [(FRAME, b(parts.frame)), (bindings::GENERATED_COUNTS, b(&self.counts))];
        let mut passes: Vec<Dispatch> = vec![(&pipelines.patches, &keeping[..], Groups::Direct([GRIDS as u32, 1]))];
        let grids = pipelines.grids.iter().zip(self.on).enumerate();
        for (g, ([count, scan, place], _)) in grids.filter(|(_, (_, on))| *on) {
            let at = g as u64 * GRID_DISPATCH_BYTES;
            let lists = if g == 0 { LODS as u32 } else { 1 };
            passes.extend([
                (count, &counting[..], Groups::Indirect(&self.dispatches, at)),
                (scan, &scanning[..], Groups::Direct([lists, 1])),
                (
                    place,
                    &placing[..],
                    Groups::Indirect(&self.dispatches, at + PLACE_DISPATCH_OFFSET),
                ),
            ]);
        }
        dispatch((parts.device, parts.groups), encoder, &passes);
    }

    /// Draw the instanced grass's levels with the pipeline and bind group set (its group 0
    /// binds [`GeneratedLists::listed`]), where the frame generated them.
    pub fn record_draw(&self, pass: &mut wgpu::RenderPass) {
        if self.on[0] {
            pass.multi_draw_indirect(&self.draws, 0, LODS as u32);
        }
    }

    /// Draw the billboards with the pipeline and bind group set, where the frame generated
    /// them: those the compute rasterizer left (`rasterized`), else every listed one.
    pub fn record_billboards(&self, pass: &mut wgpu::RenderPass, rasterized: bool) {
        if self.on[1] {
            let command = self.billboard_command(rasterized);
            pass.draw_indirect(&self.draws, u64::from(command) * GeneratedDraws::COMMAND_BYTES);
        }
    }

    /// The draw command of the billboards the hardware draws, where the frame rasterized the
    /// others by compute (`rasterized`) or not.
    pub fn billboard_command(&self, rasterized: bool) -> u32 {
        match (self.splats, rasterized) {
            (true, true) => splatted::HARDWARE_BILLBOARD_COMMAND,
            (true, false) => splatted::BILLBOARD_COMMAND,
            (false, _) => GeneratedDraws::BILLBOARD_COMMAND,
        }
    }

    /// The lists' patch rows, visible blades and counts (what the splatting passes bind).
    pub(crate) fn buffers(&self) -> [&wgpu::Buffer; 3] {
        [&self.patches, &self.listed, &self.counts]
    }

    /// Whether the last prepared frame generates the instanced grass, the billboards.
    pub fn generates(&self) -> [bool; GRIDS] {
        self.on
    }

    /// How far from the eye the last prepared frame's levels begin, then its billboards.
    pub fn starts(&self) -> [f32; GeneratedDraws::COMMANDS] {
        self.starts
    }

    /// The levels' visible lists.
    pub fn listed(&self) -> &wgpu::Buffer {
        &self.listed
    }

    /// The draw commands: the four levels', then the billboards'.
    pub fn draws(&self) -> &wgpu::Buffer {
        &self.draws
    }

    #[cfg(feature = "blocking")]
    /// The lists as the GPU holds them now, each as its draw command counts it: the instanced
    /// grass's four levels, then the billboards; each blade's 32 bytes, in the order they are
    /// drawn.
    pub fn read(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<Vec<Vec<[u32; 8]>>, PortableError> {
        let draws: Vec<[u32; 4]> =
            bytemuck::pod_collect_to_vec(&crate::field::read_buffer(device, queue, &self.draws)?);
        let blades: Vec<[u32; 8]> =
            bytemuck::pod_collect_to_vec(&crate::field::read_buffer(device, queue, &self.listed)?);
        let starts = self.layout.levels.iter().chain([&self.layout.billboards]).map(|l| l[0]);
        Ok(starts
            .zip(self.listed_lists())
            .zip(self.listed_commands().map(|k| &draws[k]))
            .map(|((start, (cap, on)), draw)| {
                let count = if on { draw[1].min(cap) as usize } else { 0 };
                blades[start as usize..start as usize + count].to_vec()
            })
            .collect())
    }

    #[cfg(feature = "blocking")]
    /// How many blades and billboards the last frame made visible (none where it generated
    /// none), and of them how many it splatted or rasterized by compute (counted, never
    /// listed for a draw) — as the Vulkan renderer's bench counts them.
    pub fn count(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<[u32; 2], PortableError> {
        if self.on == [false; GRIDS] {
            return Ok([0, 0]);
        }
        let draws: Vec<[u32; 4]> =
            bytemuck::pod_collect_to_vec(&crate::field::read_buffer(device, queue, &self.draws)?);
        let lists = self.listed_lists();
        let listed: u32 = lists
            .iter()
            .zip(self.listed_commands().map(|k| &draws[k]))
            .map(|(&(cap, on), d)| if on { d[1].min(cap) } else { 0 })
            .sum();
        let splatted = match self.splats {
            true => draws[splatted::SPLAT_COMMAND as usize][1],
            false => 0,
        };
        Ok([listed + splatted, splatted])
    }

    /// The draw command counting each list: the levels, the billboards.
    #[cfg(feature = "blocking")]
    fn listed_commands(&self) -> [usize; COMMANDS as usize] {
        let billboards = match self.splats {
            true => splatted::BILLBOARD_COMMAND as usize,
            false => GeneratedDraws::BILLBOARD_COMMAND as usize,
        };
        [0, 1, 2, 3, billboards]
    }

    /// Each list's capacity and whether the last frame generated it: the levels, the billboards.
    #[cfg(feature = "blocking")]
    fn listed_lists(&self) -> [(u32, bool); COMMANDS as usize] {
        let [l0, l1, l2, l3] = self.layout.levels.map(|[_, cap]| (cap, self.on[0]));
        [l0, l1, l2, l3, (self.layout.billboards[1], self.on[1])]
    }

    /// Bytes of GPU memory the view's generated grass holds.
    pub fn bytes(&self) -> u64 {
        [&self.patches, &self.listed, &self.draws, &self.counts, &self.dispatches]
            .into_iter()
            .chain(&self.initial)
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

/// The billboards' painted grass (sward-core's `shipped_grass_texture`, the Vulkan renderer's
/// too) with its coverage-keeping mip chain, sampled trilinearly and clamped at its edges.
pub(crate) struct GrassTexture {
    pub view: wgpu::TextureView,
    pub sampler: wgpu::Sampler,
}

impl GrassTexture {
    /// Paint the texture and upload every level.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> GrassTexture {
        let painted = sward_core::billboard::shipped_grass_texture();
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("sward grass texture"),
            size: wgpu::Extent3d {
                width: painted.size,
                height: painted.size,
                depth_or_array_layers: 1,
            },
            mip_level_count: painted.levels.len() as u32,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8UnormSrgb,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        for (level, texels) in painted.levels.iter().enumerate() {
            let side = painted.level_size(level);
            queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &texture,
                    mip_level: level as u32,
                    origin: wgpu::Origin3d::ZERO,
                    aspect: wgpu::TextureAspect::All,
                },
                bytemuck::cast_slice(texels),
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(4 * side),
                    rows_per_image: Some(side),
                },
                wgpu::Extent3d {
                    width: side,
                    height: side,
                    depth_or_array_layers: 1,
                },
            );
        }
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("sward grass sampler"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        GrassTexture {
            view: texture.create_view(&Default::default()),
            sampler,
        }
    }
}
