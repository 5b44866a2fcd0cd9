//! The streamed field's window for the Vulkan renderer: sward-core's `WindowSlots` (which world
//! tile each slot holds, the frame origin) written each frame into a frame slot's tile buffer —
//! the tiles entering the window, listed with a dispatch command after the frame's tile list and
//! boxes for `make_entering_tiles` (stream.wesl) to make their blades before the frame steps them; every slot's
//! box for `tile_cull.wesl`; and, in the frame the origin moves, the dispatch that carries every
//! blade there (the core's `stream.wesl` `rebase_field`). A few hundred bytes a frame; the blades are made on the GPU.

use sward_core::frame::FrameDesc;
use sward_core::stream::{StreamWindow, WindowSlots};
use sward_core::tiles::{ActiveTile, Tile};

/// Bytes of a tile entry (an `ActiveTile`) in the list, the boxes and the entering tiles.
const ENTRY: usize = std::mem::size_of::<ActiveTile>();

/// The window's slots, and the workgroup the dispatches are sized for.
pub(crate) struct StreamState {
    slots: WindowSlots,
    /// Invocations per workgroup of `make_entering_tiles` (stream.wesl).
    workgroup: u32,
}

impl StreamState {
    pub fn new(window: StreamWindow, workgroup: u32) -> StreamState {
        StreamState {
            slots: WindowSlots::new(window),
            workgroup,
        }
    }

    /// The window the slots are on.
    pub fn window(&self) -> StreamWindow {
        self.slots.window()
    }

    /// Make the tiles under `strokes` anew next frame (`WindowSlots::remake_under`).
    pub fn remake_under(&mut self, strokes: &[sward_core::paint::Stroke], texel: f32) -> usize {
        self.slots.remake_under(strokes, texel)
    }

    /// The frame origin the blades are held around and how far it moved in the last prepared
    /// frame.
    pub fn origin(&self) -> [glam::Vec2; 2] {
        self.slots.origin()
    }

    /// Bytes the per-frame tile buffer needs beyond the list and the boxes: the dispatch command,
    /// an entry per slot (the whole window enters at once after a jump) and the rebase's command.
    pub fn extra_bytes(window: &StreamWindow) -> usize {
        ENTRY * (2 + (window.tiles * window.tiles) as usize)
    }

    /// Where the dispatch command sits in the tile buffer: after the list and the boxes.
    pub fn command_offset(&self) -> u64 {
        (3 * self.slots.slots() * ENTRY) as u64
    }

    /// Where the rebase's dispatch command sits: after the entering tiles' room.
    pub fn rebase_offset(&self) -> u64 {
        self.command_offset() + ((1 + self.slots.slots()) * ENTRY) as u64
    }

    /// The window around this frame's eye (`WindowSlots::advance`) written into `buffer` (a frame
    /// slot's tile buffer, mapped): every slot's box after the list, the entering tiles with
    /// their dispatch command, the rebase's command; `ground` the ground's lowest and highest
    /// point. Returns the tiles entering.
    pub fn prepare(&mut self, desc: &FrameDesc, ground: [f32; 2], buffer: &mut [u8], follows: bool) -> u32 {
        let frame = self.slots.advance(desc, ground, follows);
        let boxes: Vec<ActiveTile> = frame.boxes.iter().flat_map(box_words).collect();
        let entering = frame.entering_words();
        let command = ActiveTile {
            first: sward_core::stream::TILE_CELLS.pow(2).div_ceil(self.workgroup),
            count: entering.len() as u32,
            drawn: 1,
            unused: 0,
        };
        let rebase = ActiveTile {
            count: match self.slots.origin()[1] == glam::Vec2::ZERO {
                true => 0,
                false => self.slots.slots() as u32,
            },
            ..command
        };
        write(buffer, self.slots.slots() * ENTRY, &boxes);
        write(buffer, self.command_offset() as usize, &[command]);
        write(buffer, self.command_offset() as usize + ENTRY, &entering);
        write(buffer, self.rebase_offset() as usize, &[rebase]);
        entering.len() as u32
    }
}

/// A tile's box as `tile_cull.wesl` reads it: (min, first), (max, count).
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

    fn read(buffer: &[u8], at: u64) -> ActiveTile {
        bytemuck::pod_read_unaligned(&buffer[at as usize..at as usize + ENTRY])
    }

    /// The window's frame as `make_entering_tiles` (stream.wesl) and `rebase_field` (stream.wesl) read it: the entering
    /// tiles' dispatch (workgroups per tile, tiles) and their slots and world tiles after it, the
    /// rebase's dispatch a row per slot only in the frame the origin moves.
    #[test]
    fn the_entering_tiles_and_the_rebase_are_written_where_the_shaders_read_them() {
        let window = StreamWindow {
            tiles: 4,
            spacing: 0.125,
        };
        let mut state = StreamState::new(window, 256);
        let mut buffer = vec![0u8; 3 * 16 * ENTRY + StreamState::extra_bytes(&window)];
        assert_eq!(
            state.prepare(&desc_at(glam::Vec3::ZERO), [0.0, 0.0], &mut buffer, true),
            16
        );
        assert_eq!(
            state.prepare(&desc_at(glam::Vec3::new(8.0, 0.0, 0.0)), [0.0, 0.0], &mut buffer, true),
            4
        );
        let command = read(&buffer, state.command_offset());
        assert_eq!((command.first, command.count, command.drawn), (16, 4, 1));
        let first = read(&buffer, state.command_offset() + ENTRY as u64);
        let tile = glam::IVec2::new(first.count as i32, first.drawn as i32);
        assert_eq!(window.slot_of(tile), first.first);
        assert_eq!(
            read(&buffer, state.rebase_offset()).count,
            0,
            "no rebase while the origin stays"
        );
        state.prepare(
            &desc_at(glam::Vec3::new(3000.0, 0.0, 0.0)),
            [0.0, 0.0],
            &mut buffer,
            true,
        );
        assert_eq!(
            read(&buffer, state.rebase_offset()).count,
            16,
            "a row per slot when it moves"
        );
    }
}
