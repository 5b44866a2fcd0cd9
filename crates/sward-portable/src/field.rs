//! The Bezier field on the GPU for the portable passes: the blades (64 bytes each, sward-core's
//! `Blade`) and their collision strengths η, uploaded once, where motion vectors are drawn the
//! blades as the last frame drew them, and per view the lists its cull fills each frame (the
//! visible blades by distance bucket, a draw command per bucket, the tiles it runs); read back
//! for tests and tools. A field grown in tiles (sward-core's `tiles`) runs, each frame, only
//! the tiles in or near the view: the host decides them (`TileGroups::active`, the Vulkan
//! renderer's CPU decision) and the passes take a row of workgroups per tile. A streamed field
//! is a window of such tiles that follows the eye (sward-core's `WindowSlots`): each frame the
//! host lists the tiles entering it for `stream.wesl` to make, and moves every tile's box.

use sward_core::commands::{counters, DISTANCE_BUCKETS};
use sward_core::gpu::DrawCommand;
use sward_core::plan::FrameDecisions;
use sward_core::stream::{StreamWindow, WindowSlots};
use sward_core::tiles::{ActiveTile, Tile, TileGroups, TILE_BLADES};
use sward_core::{Blade, FrameDesc};
use wgpu::util::DeviceExt;

use crate::passes::{blade_groups, TILE_GROUPS};
use crate::PortableError;

/// Bytes of one blade on the GPU.
const BLADE_BYTES: u64 = std::mem::size_of::<Blade>() as u64;

/// A field's blades and collision strengths in storage buffers, and each view's cull lists.
pub struct PortableField {
    pub(crate) blades: wgpu::Buffer,
    pub(crate) etas: wgpu::Buffer,
    /// The blades as the last frame drew them, where motion vectors are asked for
    /// ([`PortableField::keep_previous`]): copied before each frame simulates.
    pub(crate) previous: Option<wgpu::Buffer>,
    /// Each view's lists (the first made with the field; a camera culls into its own).
    pub(crate) views: Vec<CullLists>,
    /// The field's tiles, where it was grown in them (where it streams, the window's slots).
    tiles: Option<TileGroups>,
    /// The window, where the field streams.
    pub(crate) stream: Option<FieldStream>,
    count: u32,
}

/// A streamed field's window and the tiles entering it in the last frame advanced.
pub(crate) struct FieldStream {
    slots: WindowSlots,
    /// The entering tiles as stream.wesl reads them (sward-core's `ActiveTile`): per tile its
    /// slot and world tile.
    pub entering: wgpu::Buffer,
    /// How many tiles entered in the last frame advanced.
    pub entered: u32,
    /// Whether the frame origin moved in it (every held blade is carried there).
    pub moved: bool,
    /// Whether a frame has placed the window yet.
    advanced: bool,
}

/// What one view's cull fills each frame: the visible blades by distance bucket, a draw command
/// per bucket.
pub struct CullLists {
    /// The visible blades' indices, bucket by bucket (cull.wesl `visible`).
    pub(crate) visible: wgpu::Buffer,
    /// Each blade's bucket this frame (cull.wesl `bucket_of`).
    pub(crate) bucket_of: wgpu::Buffer,
    /// A draw command per distance bucket, for the draw's indirect calls.
    pub(crate) draws: wgpu::Buffer,
    /// Each bucket's count, then where its list starts, then the buckets drawn and the
    /// workgroups counted (cleared each frame; sward-core `commands::counters`).
    pub(crate) counters: wgpu::Buffer,
    /// Each cull workgroup's blades per bucket, then where its run of each bucket starts within
    /// the bucket (bucket_runs.wesl `group_runs`): what keeps the list's order fixed.
    pub(crate) group_runs: wgpu::Buffer,
    /// The tiles the view's frame runs (sward-core's `ActiveTile`; tiles.wesl), nearest first.
    pub(crate) active_tiles: wgpu::Buffer,
    /// How many of them its last frame listed, and their blades.
    pub(crate) tiles_run: u32,
    blades_run: u32,
}

/// Where the counters hold how many buckets the draw issues (buckets.wesl `DRAWN_BUCKETS`).
pub const DRAWN_BUCKETS_OFFSET: u64 = 4 * counters::DRAWN_BUCKETS as u64;

/// Bytes of one active tile (sward-core's `ActiveTile`).
const TILE_BYTES: u64 = std::mem::size_of::<ActiveTile>() as u64;

/// The usage of the field's buffers: bound for storage, copied to and from.
const FIELD_USAGE: wgpu::BufferUsages = wgpu::BufferUsages::STORAGE
    .union(wgpu::BufferUsages::COPY_SRC)
    .union(wgpu::BufferUsages::COPY_DST);

impl CullLists {
    /// Lists for a field of `blades` in `tiles` tiles (0: grown without them) on `device`, for
    /// as many workgroups as its cull runs at most: a row of them per tile run, or as many rows
    /// as a blade an invocation takes.
    fn for_field(device: &wgpu::Device, blades: u64, tiles: u64) -> CullLists {
        let [across, down] = blade_groups(blades as u32, device.limits().max_compute_workgroups_per_dimension);
        let groups = (across as u64 * down as u64).max(TILE_GROUPS as u64 * tiles);
        CullLists::new(device, (blades, tiles), groups)
    }

    /// Lists for a field of `blades` (at least one) in `tiles` tiles, culled by at most
    /// `groups` workgroups.
    fn new(device: &wgpu::Device, (blades, tiles): (u64, u64), groups: u64) -> CullLists {
        let lists = |label, size| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: FIELD_USAGE,
                mapped_at_creation: false,
            })
        };
        let per_blade = 4 * blades.max(1);
        let buckets = DISTANCE_BUCKETS as u64;
        CullLists {
            visible: lists("sward visible blades", per_blade),
            bucket_of: lists("sward blade buckets", per_blade),
            draws: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("sward draw commands"),
                // A command per bucket, the blade occluders', the far buckets' splat dispatch and
                // the exact-distance sort's (buckets.wesl OCCLUDER_COMMAND, SPLAT_BLADES_COMMAND,
                // SORT_DRAWN_COMMAND).
                size: (buckets + 3) * std::mem::size_of::<DrawCommand>() as u64,
                usage: FIELD_USAGE | wgpu::BufferUsages::INDIRECT,
                mapped_at_creation: false,
            }),
            // Per bucket its count and its start, then the buckets drawn, which a draw with a
            // count reads, and the workgroups counted.
            counters: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("sward bucket counters"),
                size: 4 * counters::WORDS as u64,
                usage: FIELD_USAGE | wgpu::BufferUsages::INDIRECT,
                mapped_at_creation: false,
            }),
            group_runs: lists("sward bucket runs", 4 * buckets * groups.max(1)),
            active_tiles: lists("sward active tiles", TILE_BYTES * tiles.max(1)),
            tiles_run: 0,
            blades_run: 0,
        }
    }

    fn bytes(&self) -> u64 {
        [
            &self.visible,
            &self.bucket_of,
            &self.draws,
            &self.counters,
            &self.group_runs,
            &self.active_tiles,
        ]
        .iter()
        .map(|b| b.size())
        .sum()
    }

    /// The visible blades' indices, bucket by bucket: bucket `k`'s from
    /// `counters[BUCKET_STARTS + k]` (buckets.wesl), `draws[k].instance_count` of them.
    pub fn visible(&self) -> &wgpu::Buffer {
        &self.visible
    }

    /// The draw commands: a distance bucket's each (its first vertex `k × STRIP_STRIDE` says
    /// which bucket it is, its first instance is 0), then the blade occluders'.
    pub fn draws(&self) -> &wgpu::Buffer {
        &self.draws
    }

    /// The cull's counters, where each bucket's list starts (buckets.wesl `BUCKET_STARTS`), and
    /// how many buckets the draw issues: up to the farthest that holds a blade (at byte
    /// [`DRAWN_BUCKETS_OFFSET`]).
    pub fn counters(&self) -> &wgpu::Buffer {
        &self.counters
    }
}

impl PortableField {
    /// Upload `blades` (each at collision strength 0), or say how many fit where the device's
    /// storage bindings are too small for them.
    pub fn new(device: &wgpu::Device, blades: &[Blade]) -> Result<PortableField, PortableError> {
        PortableField::with_tiles(device, blades, Vec::new())
    }

    /// Upload `blades` grown in `tiles` (sward-core's `Field::tiles`: runs of `TILE_BLADES`
    /// blades with their boxes, in the blades' order; empty: one run of everything), so that a
    /// frame runs only the tiles in or near its view.
    pub fn with_tiles(
        device: &wgpu::Device,
        blades: &[Blade],
        tiles: Vec<Tile>,
    ) -> Result<PortableField, PortableError> {
        let limit = device.limits().max_storage_buffer_binding_size;
        let bytes = blades.len() as u64 * BLADE_BYTES;
        if bytes > limit || blades.len() > u32::MAX as usize {
            return Err(PortableError::FieldTooLarge {
                blades: blades.len(),
                bytes,
                limit,
                fits: limit / BLADE_BYTES,
            });
        }
        // A binding is never empty: an empty field holds one unused blade.
        let first = [<Blade as bytemuck::Zeroable>::zeroed()];
        let contents = if blades.is_empty() { &first[..] } else { blades };
        let etas = vec![0.0f32; contents.len()];
        let init = |label, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: FIELD_USAGE,
            })
        };
        Ok(PortableField {
            blades: init("sward blades", bytemuck::cast_slice(contents)),
            etas: init("sward collision strengths", bytemuck::cast_slice(&etas)),
            previous: None,
            views: vec![CullLists::for_field(device, blades.len() as u64, tiles.len() as u64)],
            tiles: (!tiles.is_empty()).then(|| TileGroups::new(tiles)),
            stream: None,
            count: blades.len() as u32,
        })
    }

    /// A streamed field: the window `window` of tiles that follows the eye, every blade made on
    /// the GPU as its tile enters (the first frame makes them all).
    pub fn streamed(device: &wgpu::Device, window: StreamWindow) -> Result<PortableField, PortableError> {
        let blades = vec![<Blade as bytemuck::Zeroable>::zeroed(); window.blades() as usize];
        let mut field = PortableField::with_tiles(device, &blades, window.empty_tiles())?;
        let slots = WindowSlots::new(window);
        field.stream = Some(FieldStream {
            entering: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("sward entering tiles"),
                size: TILE_BYTES * slots.slots() as u64,
                usage: FIELD_USAGE,
                mapped_at_creation: false,
            }),
            slots,
            entered: 0,
            moved: false,
            advanced: false,
        });
        Ok(field)
    }

    /// Where the field streams, move its window around the frame `desc`'s eye (where the frame
    /// `follows`: it steps the grass; else it stays where the last stepping frame put it) over
    /// ground from `ground[0]` to `ground[1]`: the tiles entering it listed for stream.wesl and
    /// their collision strengths cleared, every slot's box moved. The window and the frame
    /// origin (and how far it moved), or None where the field does not stream.
    pub(crate) fn advance_window(
        &mut self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        desc: &FrameDesc,
        (ground, follows): ([f32; 2], bool),
    ) -> Option<(StreamWindow, [glam::Vec2; 2])> {
        let stream = self.stream.as_mut()?;
        if !follows && stream.advanced {
            // Another record of the frame (a pass of it, or another camera's view): the window
            // and the origin stay as the frame that stepped left them, and so do its uniforms'.
            (stream.entered, stream.moved) = (0, false);
            return Some((stream.slots.window(), stream.slots.origin()));
        }
        stream.advanced = true;
        let frame = stream.slots.advance(desc, ground, follows);
        let entering = frame.entering_words();
        if !entering.is_empty() {
            queue.write_buffer(&stream.entering, 0, bytemuck::cast_slice(&entering));
        }
        // A slot's new blades start free of any collision.
        let per_tile = TILE_BLADES as u64 * 4;
        for tile in &entering {
            encoder.clear_buffer(&self.etas, tile.first as u64 * per_tile, Some(per_tile));
        }
        stream.entered = entering.len() as u32;
        stream.moved = stream.slots.origin()[1] != glam::Vec2::ZERO;
        self.tiles = Some(TileGroups::new(frame.boxes));
        Some((stream.slots.window(), stream.slots.origin()))
    }

    /// Strokes painted into the paint uploaded last: where the field streams, the tiles under
    /// them are made anew next frame from the new paint (standing as their twins stand), every
    /// other tile's blades keeping their poses and trails; a field that does not stream keeps
    /// all its blades. `texel` is the side of a texel of that paint. Returns how many tiles
    /// will be made.
    pub fn repaint_under(&mut self, strokes: &[sward_core::paint::Stroke], texel: f32) -> usize {
        self.stream.as_mut().map_or(0, |s| s.slots.remake_under(strokes, texel))
    }

    /// The frame origin (world x and z) the blades are held around: zero unless the field
    /// streams ([`PortableField::read`] gives positions less it).
    pub fn origin(&self) -> glam::Vec2 {
        self.stream.as_ref().map_or(glam::Vec2::ZERO, |s| s.slots.origin()[0])
    }

    /// Tiles the field holds (0: grown without them).
    pub(crate) fn tiles_len(&self) -> u32 {
        self.tiles.as_ref().map_or(0, |t| t.tiles().len() as u32)
    }

    /// Lists for `views` views at least (a camera culls into its own).
    pub fn reserve_views(&mut self, device: &wgpu::Device, views: usize) {
        while self.views.len() < views {
            let tiles = self.tiles.as_ref().map_or(0, |t| t.tiles().len());
            self.views
                .push(CullLists::for_field(device, self.count as u64, tiles as u64));
        }
    }

    /// View `view`'s lists, where it has them ([`PortableField::reserve_views`]).
    pub fn lists(&self, view: usize) -> Option<&CullLists> {
        self.views.get(view)
    }

    /// Keep the blades as each frame found them before it simulated (from the next frame on),
    /// for motion vectors: [`PortableField::previous_blades`].
    pub fn keep_previous(&mut self, device: &wgpu::Device) {
        if self.previous.is_none() {
            self.previous = Some(device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("sward blades last drawn"),
                size: self.blades.size(),
                usage: FIELD_USAGE,
                mapped_at_creation: false,
            }));
        }
    }

    /// The blades (sward-core's `Blade`, 64 bytes each), positions from the frame's origin.
    pub fn blades(&self) -> &wgpu::Buffer {
        &self.blades
    }

    /// The blades as the last frame drew them, where kept ([`PortableField::keep_previous`]).
    pub fn previous_blades(&self) -> Option<&wgpu::Buffer> {
        self.previous.as_ref()
    }

    /// Write the tiles view `view`'s frame `desc` (as `decided`) runs into its list, nearest
    /// first: those in or near its view (a tile just outside it is simulated, not drawn, and one
    /// that may cast a blade shadow into it is kept), or where `every_tile`
    /// (the first view of several, which simulates for all), every tile, those out of its view
    /// simulated only. The tiles it runs, or None where the field has no tiles (every blade
    /// runs).
    pub(crate) fn write_tiles(
        &mut self,
        queue: &wgpu::Queue,
        (desc, decided, view): (&FrameDesc, &FrameDecisions, usize),
        every_tile: bool,
    ) -> Option<u32> {
        let groups = self.tiles.as_ref()?;
        let toward_sun = decided.toward_sun(desc);
        // The tiles' boxes are measured from the frame origin, where the field streams.
        let camera = match self.stream.as_ref().map(|s| s.slots.origin()[0]) {
            Some(origin) => desc.camera.relative_to(glam::Vec3::new(origin.x, 0.0, origin.y)),
            None => desc.camera,
        };
        let view_proj = camera.view_projection();
        let mut run = groups.active(
            &view_proj,
            camera.eye,
            desc.cull.tile_margin,
            desc.cull.tiles,
            toward_sun,
        );
        if every_tile && run.len() < groups.tiles().len() {
            let listed: std::collections::HashSet<u32> = run.iter().map(|t| t.first).collect();
            let rest = groups.tiles().iter().filter(|t| !listed.contains(&t.first));
            run.extend(rest.map(|t| ActiveTile {
                first: t.first,
                count: t.count,
                drawn: 0,
                unused: 0,
            }));
        }
        let lists = &mut self.views[view];
        queue.write_buffer(&lists.active_tiles, 0, bytemuck::cast_slice(&run));
        lists.tiles_run = run.len() as u32;
        lists.blades_run = run.iter().map(|t| t.count).sum();
        Some(lists.tiles_run)
    }

    #[cfg(feature = "blocking")]
    /// The tiles view `view`'s last frame ran, nearest first, as its list holds them (None
    /// where the field has no tiles: every blade runs), once the work submitted so far has
    /// finished.
    pub fn read_tiles_run(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        view: usize,
    ) -> Result<Option<Vec<ActiveTile>>, PortableError> {
        if self.tiles.is_none() {
            return Ok(None);
        }
        let lists = &self.views[view];
        let tiles: Vec<ActiveTile> = bytemuck::pod_collect_to_vec(&read_buffer(device, queue, &lists.active_tiles)?);
        Ok(Some(tiles[..lists.tiles_run as usize].to_vec()))
    }

    /// The blades view `view`'s last frame ran: those of its tiles, or every blade where the
    /// field has no tiles.
    pub fn blades_run(&self, view: usize) -> u32 {
        match &self.tiles {
            Some(_) => self.views.get(view).map_or(0, |l| l.blades_run),
            None => self.count,
        }
    }

    /// Blades in the field.
    pub fn count(&self) -> u32 {
        self.count
    }

    /// Bytes of GPU memory the field's buffers hold.
    pub fn bytes(&self) -> u64 {
        let previous = self.previous.as_ref().map_or(0, wgpu::Buffer::size);
        let lists: u64 = self.views.iter().map(CullLists::bytes).sum();
        self.blades.size() + self.etas.size() + previous + lists
    }

    #[cfg(feature = "blocking")]
    /// The blades the last culled frame listed for the first view, once the work submitted so far has finished.
    pub fn visible_count(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<u32, PortableError> {
        let draws: Vec<DrawCommand> = bytemuck::pod_collect_to_vec(&read_buffer(device, queue, &self.views[0].draws)?);
        Ok(draws[..DISTANCE_BUCKETS as usize]
            .iter()
            .map(|d| d.instance_count)
            .sum())
    }

    #[cfg(feature = "blocking")]
    /// The blades and their collision strengths as the GPU holds them, once the work submitted
    /// so far has finished (native backends: this waits for the device).
    pub fn read(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<(Vec<Blade>, Vec<f32>), PortableError> {
        let n = self.count as usize;
        let blades: Vec<Blade> = bytemuck::pod_collect_to_vec(&read_buffer(device, queue, &self.blades)?);
        let etas: Vec<f32> = bytemuck::pod_collect_to_vec(&read_buffer(device, queue, &self.etas)?);
        Ok((blades[..n].to_vec(), etas[..n].to_vec()))
    }

    #[cfg(feature = "blocking")]
    /// How many buckets view `view`'s last draw issues (up to the farthest that held a blade:
    /// the count a draw with a count reads), once the work submitted so far has finished.
    pub fn read_drawn_buckets(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        view: usize,
    ) -> Result<u32, PortableError> {
        let lists = self.views.get(view).ok_or(PortableError::NoField)?;
        let counters: Vec<u32> = bytemuck::pod_collect_to_vec(&read_buffer(device, queue, &lists.counters)?);
        Ok(counters[(DRAWN_BUCKETS_OFFSET / 4) as usize])
    }

    #[cfg(feature = "blocking")]
    /// View `view`'s visible blades in draw order and its draw command per distance bucket
    /// (`instance_count` blades from `first_instance` of the list: on the GPU the command's first
    /// instance is 0, its bucket's start kept apart), once the work submitted so far has finished.
    pub fn read_visible(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        view: usize,
    ) -> Result<(Vec<u32>, Vec<DrawCommand>), PortableError> {
        let lists = self.views.get(view).ok_or(PortableError::NoField)?;
        let mut draws: Vec<DrawCommand> = bytemuck::pod_collect_to_vec(&read_buffer(device, queue, &lists.draws)?);
        draws.truncate(DISTANCE_BUCKETS as usize);
        let counters: Vec<u32> = bytemuck::pod_collect_to_vec(&read_buffer(device, queue, &lists.counters)?);
        let starts = &counters[counters::BUCKET_STARTS as usize..];
        for (draw, &start) in draws.iter_mut().zip(starts) {
            draw.first_instance = start;
        }
        let listed = draws.iter().map(|d| d.instance_count as usize).sum::<usize>();
        let visible: Vec<u32> = bytemuck::pod_collect_to_vec(&read_buffer(device, queue, &lists.visible)?);
        Ok((visible[..listed.min(visible.len())].to_vec(), draws))
    }
}

#[cfg(feature = "blocking")]
/// The bytes of `buffer`, copied into a mappable buffer and mapped.
pub(crate) fn read_buffer(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    buffer: &wgpu::Buffer,
) -> Result<Vec<u8>, PortableError> {
    read_range(device, queue, buffer, 0..buffer.size())
}

#[cfg(feature = "blocking")]
/// The bytes `range` of `buffer` (4-byte aligned), copied into a mappable buffer and mapped.
pub(crate) fn read_range(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    buffer: &wgpu::Buffer,
    range: std::ops::Range<u64>,
) -> Result<Vec<u8>, PortableError> {
    let size = range.end - range.start;
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("sward read-back"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    encoder.copy_buffer_to_buffer(buffer, range.start, &staging, 0, size);
    queue.submit([encoder.finish()]);
    map_read(device, &staging)
}

#[cfg(feature = "blocking")]
/// The bytes of mappable `staging`, once the work submitted so far has finished.
#[allow(clippy::disallowed_methods)] // A read-back waits by its nature; built only for `blocking`.
pub(crate) fn map_read(device: &wgpu::Device, staging: &wgpu::Buffer) -> Result<Vec<u8>, PortableError> {
    let (sender, receiver) = std::sync::mpsc::channel();
    staging.slice(..).map_async(wgpu::MapMode::Read, move |r| {
        let _ = sender.send(r);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| PortableError::Readback(e.to_string()))?;
    match receiver.try_recv() {
        Ok(Ok(())) => {}
        Ok(Err(e)) => return Err(PortableError::Readback(e.to_string())),
        Err(_) => {
            return Err(PortableError::Readback(
                "the buffer was not mapped after the device went idle".into(),
            ))
        }
    }
    let bytes = staging
        .slice(..)
        .get_mapped_range()
        .map_err(|e| PortableError::Readback(e.to_string()))?
        .to_vec();
    staging.unmap();
    Ok(bytes)
}
