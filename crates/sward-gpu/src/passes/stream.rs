//! The streamed field's window on the host (`sward_core::stream`): which world tile each slot of
//! the window holds, and, each frame, the tiles that enter it — listed, with a dispatch command,
//! after the frame's tile list and boxes, for `stream_tiles.comp` to make their blades before
//! the frame steps them — and every slot's box for `tile_cull.comp`. It also keeps the frame
//! origin the blades are held around (`sward_core::stream::frame_origin`), and in the frame it
//! moves sizes the dispatch that carries every blade there (`rebase_field.comp`). The host's
//! work is a comparison per slot and a few hundred bytes written; the blades are made on the GPU.

use glam::{IVec2, Vec2, Vec3};
use sward_core::frame::FrameDesc;
use sward_core::stream::StreamWindow;
use sward_core::tiles::{ActiveTile, Tile};

/// Bytes of a tile entry (an `ActiveTile`) in the list, the boxes and the entering tiles.
const ENTRY: usize = std::mem::size_of::<ActiveTile>();

/// The window's slots on the host.
pub(crate) struct StreamState {
    window: StreamWindow,
    /// The world tile each slot holds (`None`: none made yet).
    held: Vec<Option<IVec2>>,
    /// Invocations per workgroup of `stream_tiles.comp`.
    workgroup: u32,
    /// The frame origin (world x, z) the blades are held around, and how far it moved in the
    /// last prepared frame.
    origin: [Vec2; 2],
    /// The eye the window follows: the last stepping frame's (another camera's view of the
    /// same frame moves neither the window nor the origin).
    eye: Option<Vec3>,
}

impl StreamState {
    pub fn new(window: StreamWindow, workgroup: u32) -> StreamState {
        StreamState {
            window,
            held: vec![None; (window.tiles * window.tiles) as usize],
            workgroup,
            origin: [Vec2::ZERO; 2],
            eye: None,
        }
    }

    /// Where the frame's window has the same tiles on another grid (the instanced grass's density
    /// edited), every slot is made anew on it; a window of another size needs a field of its own
    /// (`Renderer::upload`), and until then the old one stays.
    fn follow_grid(&mut self, desc: &FrameDesc) {
        let Some(wanted) = desc.stream.map(|s| s.window) else {
            return;
        };
        if wanted != self.window && wanted.tiles == self.window.tiles {
            self.window = wanted;
            self.held.fill(None);
        }
    }

    /// The window the slots are on.
    pub fn window(&self) -> StreamWindow {
        self.window
    }

    /// The frame origin the blades are held around and how far it moved in the last prepared
    /// frame.
    pub fn origin(&self) -> [Vec2; 2] {
        self.origin
    }

    /// Bytes the per-frame tile buffer needs beyond the list and the boxes: the dispatch command,
    /// an entry per slot (the whole window enters at once after a jump) and the rebase's command.
    pub fn extra_bytes(window: &StreamWindow) -> usize {
        ENTRY * (2 + (window.tiles * window.tiles) as usize)
    }

    /// Where the dispatch command sits in the tile buffer: after the list and the boxes.
    pub fn command_offset(&self) -> u64 {
        (3 * self.held.len() * ENTRY) as u64
    }

    /// Where the rebase's dispatch command sits: after the entering tiles' room.
    pub fn rebase_offset(&self) -> u64 {
        self.command_offset() + ((1 + self.held.len()) * ENTRY) as u64
    }

    /// The window around this frame's eye: the tiles entering it written after the boxes of
    /// `buffer` (a frame slot's tile buffer, mapped) with their dispatch command, every slot's
    /// box rewritten; `ground` the ground's lowest and highest point. Returns the tiles entering.
    /// Where the frame `follows` (it steps the grass), the window moves to its eye; else (another
    /// camera's view of a frame) it stays where the last stepping frame put it.
    pub fn prepare(&mut self, desc: &FrameDesc, ground: [f32; 2], buffer: &mut [u8], follows: bool) -> u32 {
        if follows || self.eye.is_none() {
            self.follow_grid(desc);
            self.eye = Some(desc.camera.eye);
        }
        let eye = self.eye.unwrap_or(desc.camera.eye);
        let origin = sward_core::stream::frame_origin(self.origin[0], eye);
        self.origin = [origin, origin - self.origin[0]];
        let base = self.window.base(eye);
        let from = Vec3::new(origin.x, 0.0, origin.y);
        let grid = &desc.instanced;
        // A blade reaches as far from its root as its twin's shape: bent, swaying or lying down.
        let tallest = sward_core::instanced::patch_top(grid).max(1.15 * grid.grid.height[1]) + grid.grid.width[1];
        let slots = self.held.len();
        let mut entering = Vec::new();
        let mut boxes = Vec::with_capacity(2 * slots);
        for (slot, held) in self.held.iter_mut().enumerate() {
            let tile = self.window.tile_in(slot as u32, base);
            if *held != Some(tile) {
                *held = Some(tile);
                entering.push(ActiveTile {
                    first: slot as u32,
                    count: tile.x as u32,
                    drawn: tile.y as u32,
                    unused: 0,
                });
            }
            let mut tile_box = self.window.tile_box(tile, slot as u32, ground, tallest);
            (tile_box.min, tile_box.max) = (tile_box.min - from, tile_box.max - from);
            boxes.extend(box_words(&tile_box));
        }
        let command = ActiveTile {
            first: sward_core::stream::TILE_CELLS.pow(2).div_ceil(self.workgroup),
            count: entering.len() as u32,
            drawn: 1,
            unused: 0,
        };
        let rebase = ActiveTile {
            count: match self.origin[1] == Vec2::ZERO {
                true => 0,
                false => slots as u32,
            },
            ..command
        };
        let list_end = slots * ENTRY;
        write(buffer, list_end, &boxes);
        write(buffer, self.command_offset() as usize, &[command]);
        write(buffer, self.command_offset() as usize + ENTRY, &entering);
        write(buffer, self.rebase_offset() as usize, &[rebase]);
        entering.len() as u32
    }
}

/// A tile's box as `tile_cull.comp` reads it: (min, first), (max, count).
pub(crate) fn box_words(t: &Tile) -> [ActiveTile; 2] {
    let word = |v: glam::Vec3, last: u32| ActiveTile {
        first: v.x.to_bits(),
        count: v.y.to_bits(),
        drawn: v.z.to_bits(),
        unused: last,
    };
    [word(t.min, t.first), word(t.max, t.count)]
}

fn write(buffer: &mut [u8], at: usize, entries: &[ActiveTile]) {
    let bytes: &[u8] = bytemuck::cast_slice(entries);
    buffer[at..at + bytes.len()].copy_from_slice(bytes);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn desc_at(eye: glam::Vec3) -> FrameDesc {
        let mut scene = sward_core::Scene::default();
        scene.camera.position = eye;
        FrameDesc::of_scene(&scene, glam::Vec2::splat(10.0), (0.0, 1), [64, 64])
    }

    /// A window of 4×4 tiles, none made yet, and a frame slot's tile buffer for it.
    fn four_by_four() -> (StreamState, Vec<u8>) {
        let window = StreamWindow {
            tiles: 4,
            spacing: 0.125,
        };
        let buffer = vec![0u8; 3 * 16 * ENTRY + StreamState::extra_bytes(&window)];
        (StreamState::new(window, 256), buffer)
    }

    #[test]
    fn the_whole_window_enters_first_then_only_the_tiles_walked_into() {
        let (mut state, mut buffer) = four_by_four();
        assert_eq!(
            state.prepare(&desc_at(glam::Vec3::ZERO), [0.0, 0.0], &mut buffer, true),
            16
        );
        assert_eq!(
            state.prepare(&desc_at(glam::Vec3::new(0.5, 0.0, 0.0)), [0.0, 0.0], &mut buffer, true),
            0
        );
        // One tile (8 units) along x: a column of 4 tiles enters, reusing the column that left.
        assert_eq!(
            state.prepare(&desc_at(glam::Vec3::new(8.0, 0.0, 0.0)), [0.0, 0.0], &mut buffer, true),
            4
        );
        let at = state.command_offset() as usize;
        let command: ActiveTile = bytemuck::pod_read_unaligned(&buffer[at..at + ENTRY]);
        assert_eq!((command.first, command.count, command.drawn), (16, 4, 1));
        // Back again: the column comes back (it was reused), nothing else.
        assert_eq!(
            state.prepare(&desc_at(glam::Vec3::ZERO), [0.0, 0.0], &mut buffer, true),
            4
        );
        // A jump: everything anew.
        assert_eq!(
            state.prepare(
                &desc_at(glam::Vec3::new(500.0, 0.0, 0.0)),
                [0.0, 0.0],
                &mut buffer,
                true
            ),
            16
        );
    }

    #[test]
    fn another_camera_s_view_of_a_frame_moves_neither_the_window_nor_the_origin() {
        let (mut state, mut buffer) = four_by_four();
        assert_eq!(
            state.prepare(&desc_at(glam::Vec3::ZERO), [0.0, 0.0], &mut buffer, true),
            16
        );
        let origin = state.origin()[0];
        // A minimap's camera far away: nothing enters, nothing is carried to another origin.
        let far = desc_at(glam::Vec3::new(500.0, 0.0, 0.0));
        assert_eq!(state.prepare(&far, [0.0, 0.0], &mut buffer, false), 0);
        assert_eq!(state.origin(), [origin, glam::Vec2::ZERO]);
        let at = state.rebase_offset() as usize;
        let rebase: ActiveTile = bytemuck::pod_read_unaligned(&buffer[at..at + ENTRY]);
        assert_eq!(rebase.count, 0, "no rebase dispatched");
        // The stepping camera moves it.
        assert_eq!(state.prepare(&far, [0.0, 0.0], &mut buffer, true), 16);
    }

    #[test]
    fn a_window_on_another_grid_is_made_anew_and_another_size_is_not_taken() {
        let mut state = StreamState::new(
            StreamWindow {
                tiles: 4,
                spacing: 0.125,
            },
            256,
        );
        let mut buffer = vec![0u8; 3 * 16 * ENTRY + StreamState::extra_bytes(&state.window())];
        let mut desc = desc_at(glam::Vec3::ZERO);
        let stream = |tiles, spacing| sward_core::frame::FrameStream {
            window: StreamWindow { tiles, spacing },
            hand_over: 5.0,
            twins: true,
        };
        desc.stream = Some(stream(4, 0.125));
        assert_eq!(state.prepare(&desc, [0.0, 0.0], &mut buffer, true), 16);
        assert_eq!(state.prepare(&desc, [0.0, 0.0], &mut buffer, true), 0);
        // The instanced grass's density edited: the same tiles on another grid.
        desc.stream = Some(stream(4, 0.2));
        assert_eq!(state.prepare(&desc, [0.0, 0.0], &mut buffer, true), 16);
        assert_eq!(state.window().spacing, 0.2);
        // A window of another size needs a field of its own: the held one stays.
        desc.stream = Some(stream(5, 0.2));
        assert_eq!(state.prepare(&desc, [0.0, 0.0], &mut buffer, true), 0);
        assert_eq!(state.window().tiles, 4);
    }
}
