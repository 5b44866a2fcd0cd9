//! The streamed field (`[field] stream = true`): the Bezier blades are a window of tiles that
//! follows the eye over ground with no edge, at a fixed blade budget. The window is `tiles` ×
//! `tiles` square tiles of `TILE_CELLS` × `TILE_CELLS` cells of the instanced grass's grid; it
//! is toroidal — world tile `t` always lives in slot `t mod tiles`, so a tile leaving one side
//! hands its slot to the tile entering the other. A tile's blades are made on the GPU
//! (stream.wesl `make_entering_tiles`) from the very hash and rules that place the instanced grass
//! (`instanced::blade_at`): cell for cell the Bezier blade near the eye and the instanced blade
//! beyond the hand-over are the same blade, so nothing pops where one takes over from the other.
//! This module holds the window's arithmetic, the frame origin the GPU's numbers are measured
//! from (`frame_origin`) and the CPU reference of a tile's blades.

use glam::{IVec2, Vec2, Vec3};

use crate::blade::Blade;
use crate::instanced::{blade_at, InstancedParams};
use crate::mesh::HeightGrid;
use crate::rng::hash_unit;
use crate::tiles::{Tile, TILE_BLADES};

/// Grid cells along each side of a streamed tile: a tile holds `TILE_BLADES` blades.
pub const TILE_CELLS: u32 = 64;
const _: () = assert!(TILE_CELLS * TILE_CELLS == TILE_BLADES);

/// Where a streamed blade's stiffness comes from in its cell's hash.
const STIFFNESS_SALT: u32 = 0x3c6e_f372;

/// The most tiles a streamed window holds: the GPU decides which of them run each frame (in one
/// workgroup's shared memory, `tile_cull.wesl`); a larger window would leave that to a host that
/// does not know where the streamed tiles are. 90 × 90 tiles, 33 M blades.
pub const MAX_TILES: u32 = 8192;

/// How far (in world units, along x or z) the eye may walk from the frame origin before the
/// origin moves, and the step it moves by. A power of two: a blade `ORIGIN_STEP` multiples away
/// is moved by an exact subtraction, so a field carried over to a new origin keeps every bit.
pub const ORIGIN_STEP: f32 = 1024.0;

/// The frame origin for a streamed field's eye at `eye` when it was `origin` (xz; y is always 0):
/// the GPU holds every position as world less this point, so 32-bit floats keep a tenth of a
/// millimetre near the eye at any distance from the world's origin (at 10 km a world coordinate
/// alone would keep only one millimetre, and a physics step moves a blade less than that). The
/// origin stays put until the eye is more than `ORIGIN_STEP` from it, then moves to the nearest
/// multiple of the step: a walk along the boundary does not move it back and forth.
pub fn frame_origin(origin: Vec2, eye: Vec3) -> Vec2 {
    let eye = Vec2::new(eye.x, eye.z);
    match (eye - origin).abs().max_element() <= ORIGIN_STEP {
        true => origin,
        false => (eye / ORIGIN_STEP).round() * ORIGIN_STEP,
    }
}

/// The window of streamed tiles: its size and the grid its cells are cut from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StreamWindow {
    /// Tiles along each side of the window.
    pub tiles: u32,
    /// Distance between neighbouring grid cells (the instanced grass's spacing).
    pub spacing: f32,
}

impl StreamWindow {
    /// The largest window `budget` blades fill, on the grid of `grid`.
    pub fn for_budget(budget: u32, grid: &InstancedParams) -> StreamWindow {
        StreamWindow {
            tiles: ((budget / TILE_BLADES) as f32).sqrt().floor() as u32,
            spacing: grid.spacing(),
        }
    }

    /// Blades the window holds.
    pub fn blades(&self) -> u32 {
        self.tiles * self.tiles * TILE_BLADES
    }

    /// A tile's side in world units.
    pub fn tile_size(&self) -> f32 {
        TILE_CELLS as f32 * self.spacing
    }

    /// How far from the eye the window reaches at least, whichever way: the eye is never more
    /// than half a tile from the window's middle.
    pub fn reach(&self) -> f32 {
        (0.5 * self.tiles as f32 - 0.5) * self.tile_size()
    }

    /// The window's first tile (lowest x and z) around `eye`: the window centred on the eye to
    /// the nearest tile.
    pub fn base(&self, eye: Vec3) -> IVec2 {
        let at = Vec2::new(eye.x, eye.z) / self.tile_size() - Vec2::splat(0.5 * self.tiles as f32);
        at.round().as_ivec2()
    }

    /// The slot (index into the window's tiles) world tile `tile` lives in.
    pub fn slot_of(&self, tile: IVec2) -> u32 {
        let s = tile.rem_euclid(IVec2::splat(self.tiles as i32));
        s.y as u32 * self.tiles + s.x as u32
    }

    /// The world tile slot `slot` holds in the window that starts at `base`.
    pub fn tile_in(&self, slot: u32, base: IVec2) -> IVec2 {
        let n = self.tiles as i32;
        let s = IVec2::new((slot % self.tiles) as i32, (slot / self.tiles) as i32);
        base + (s - base).rem_euclid(IVec2::splat(n))
    }

    /// The grid cell of blade `index` (0..TILE_BLADES, row by row) of world tile `tile`.
    pub fn cell_of(tile: IVec2, index: u32) -> IVec2 {
        tile * TILE_CELLS as i32 + IVec2::new((index % TILE_CELLS) as i32, (index / TILE_CELLS) as i32)
    }

    /// The box that holds every shape of world tile `tile`'s blades: the tile's square grown by
    /// the tallest blade, over ground between `low` and `high`.
    pub fn tile_box(&self, tile: IVec2, slot: u32, [low, high]: [f32; 2], tallest: f32) -> Tile {
        let size = self.tile_size();
        let corner = tile.as_vec2() * size;
        Tile {
            first: slot * TILE_BLADES,
            count: TILE_BLADES,
            min: Vec3::new(corner.x, low, corner.y) - Vec3::splat(tallest),
            max: Vec3::new(corner.x + size, high, corner.y + size) + Vec3::splat(tallest),
        }
    }

    /// The window's tiles as the field first holds them: every slot a full run of blades, with
    /// boxes that hold nothing until their tile is made.
    pub fn empty_tiles(&self) -> Vec<Tile> {
        (0..self.tiles * self.tiles)
            .map(|slot| Tile {
                first: slot * TILE_BLADES,
                count: TILE_BLADES,
                min: Vec3::splat(f32::MAX),
                max: Vec3::splat(f32::MIN),
            })
            .collect()
    }
}

/// The window's slots as the host keeps them: which world tile each slot holds, the frame origin
/// the blades are held around, and the eye the window follows. Each frame it says which tiles
/// enter and where every slot's box lies ([`WindowSlots::advance`]); the renderers make the
/// entering tiles' blades on the GPU. The host's work is a comparison per slot.
#[derive(Clone, Debug)]
pub struct WindowSlots {
    window: StreamWindow,
    /// What each slot holds.
    held: Vec<Slot>,
    /// The frame origin (world x, z) the blades are held around, and how far it moved in the
    /// last frame advanced.
    origin: [Vec2; 2],
    /// The eye the window follows: the last stepping frame's (another camera's view of the same
    /// frame moves neither the window nor the origin).
    eye: Option<Vec3>,
}

/// What a slot of the window holds.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Slot {
    /// No tile: none made yet, or the window moved onto another grid.
    Empty,
    /// The blades of a world tile.
    Holds(IVec2),
    /// A world tile's blades, to be made again under a stroke (`remake_under`): those the
    /// stroke left as they were keep their poses.
    Repaint(IVec2),
}

/// What a frame changes in the window.
#[derive(Clone, Debug, PartialEq)]
pub struct WindowFrame {
    /// The tiles entering the window: (slot, world tile, made again under a stroke), for their
    /// blades to be made; a tile made again keeps the blades the stroke left as they were.
    pub entering: Vec<(u32, IVec2, bool)>,
    /// Every slot's box this frame, in slot order, measured from the frame origin.
    pub boxes: Vec<Tile>,
}

impl WindowFrame {
    /// The entering tiles as the pass that makes them reads them (stream.wesl
    /// `make_entering_tiles`): per tile its slot, then its world tile's x and z as two's complement
    /// words, then 1 where it is made again under a stroke.
    pub fn entering_words(&self) -> Vec<crate::tiles::ActiveTile> {
        self.entering
            .iter()
            .map(|&(slot, tile, repainted)| crate::tiles::ActiveTile {
                first: slot,
                count: tile.x as u32,
                drawn: tile.y as u32,
                unused: u32::from(repainted),
            })
            .collect()
    }
}

impl WindowSlots {
    /// A window none of whose slots holds a tile yet.
    pub fn new(window: StreamWindow) -> WindowSlots {
        WindowSlots {
            window,
            held: vec![Slot::Empty; (window.tiles * window.tiles) as usize],
            origin: [Vec2::ZERO; 2],
            eye: None,
        }
    }

    /// The window the slots are on.
    pub fn window(&self) -> StreamWindow {
        self.window
    }

    /// Slots in the window.
    pub fn slots(&self) -> usize {
        self.held.len()
    }

    /// The frame origin the blades are held around and how far it moved in the last frame
    /// advanced.
    pub fn origin(&self) -> [Vec2; 2] {
        self.origin
    }

    /// Where the frame's window (`wanted`) has the same tiles on another grid (the instanced
    /// grass's density edited), every slot is made anew on it; a window of another size needs a
    /// field of its own, and until then the old one stays.
    fn follow_grid(&mut self, wanted: Option<StreamWindow>) {
        let Some(wanted) = wanted else {
            return;
        };
        if wanted != self.window && wanted.tiles == self.window.tiles {
            self.window = wanted;
            self.held.fill(Slot::Empty);
        }
    }

    /// Make again, next frame, the tiles held under `strokes` (painted over the ground, the field's
    /// x and z): their blades the strokes changed take the paint the strokes left, standing as
    /// their twins stand (trails the trample map holds and all), while every other blade keeps
    /// its pose: one the stroke left as it was (same root, facing, height, stiffness), in these
    /// tiles or any other.
    /// `texel` is the side of a texel of the paint they were painted into: a stroke changes the
    /// texels within its reach and one beyond, which a blade samples between. Returns how many
    /// tiles will be made.
    pub fn remake_under(&mut self, strokes: &[crate::paint::Stroke], texel: f32) -> usize {
        let size = self.window.tile_size();
        // A blade stands within a cell of its own (the tile's square grown by a cell) and reads
        // the paint two texels beyond what a stroke reaches.
        let margin = self.window.spacing + 2.0 * texel;
        let reached: Vec<(Vec2, Vec2)> = strokes.iter().filter_map(|s| s.reach()).collect();
        let mut remade = 0;
        for held in &mut self.held {
            let Slot::Holds(tile) = *held else { continue };
            let low = tile.as_vec2() * size - Vec2::splat(margin);
            let high = low + Vec2::splat(size + 2.0 * margin);
            if reached.iter().any(|&(a, b)| a.cmple(high).all() && b.cmpge(low).all()) {
                *held = Slot::Repaint(tile);
                remade += 1;
            }
        }
        remade
    }

    /// The window around the frame `desc`'s eye, over ground from `ground[0]` to `ground[1]`:
    /// the tiles entering it and every slot's box. Where the frame `follows` (it steps the
    /// grass) the window and the origin move to its eye; else (another camera's view of a
    /// frame) they stay where the last stepping frame put them.
    pub fn advance(&mut self, desc: &crate::frame::FrameDesc, ground: [f32; 2], follows: bool) -> WindowFrame {
        if follows || self.eye.is_none() {
            self.follow_grid(desc.stream.map(|s| s.window));
            self.eye = Some(desc.camera.eye);
        }
        let eye = self.eye.unwrap_or(desc.camera.eye);
        let origin = frame_origin(self.origin[0], eye);
        self.origin = [origin, origin - self.origin[0]];
        let base = self.window.base(eye);
        let from = Vec3::new(origin.x, 0.0, origin.y);
        let grid = &desc.instanced;
        // A blade reaches as far from its root as its twin's shape: bent, swaying or lying down.
        let tallest = crate::instanced::patch_top(grid).max(1.15 * grid.grid.height[1]) + grid.grid.width[1];
        let mut frame = WindowFrame {
            entering: Vec::new(),
            boxes: Vec::with_capacity(self.held.len()),
        };
        for (slot, held) in self.held.iter_mut().enumerate() {
            let tile = self.window.tile_in(slot as u32, base);
            if *held != Slot::Holds(tile) {
                // Another tile entering the slot, or its own made again under a stroke (where
                // the eye moved on as it was painted, another tile: made whole).
                let repainted = *held == Slot::Repaint(tile);
                *held = Slot::Holds(tile);
                frame.entering.push((slot as u32, tile, repainted));
            }
            let mut tile_box = self.window.tile_box(tile, slot as u32, ground, tallest);
            (tile_box.min, tile_box.max) = (tile_box.min - from, tile_box.max - from);
            frame.boxes.push(tile_box);
        }
        frame
    }
}

/// The Bezier blade of grid cell `cell`: the instanced blade there (root, height, half-width,
/// facing — the Bezier blade's orientation about +y is the instanced facing, so its width runs
/// the same way —), standing upright at rest, with a stiffness from the cell's hash within
/// `stiffness`. Off a height grid the blade has no height (and is never drawn).
pub fn blade_of_cell(cell: IVec2, grid: &InstancedParams, stiffness: [f32; 2], ground: Option<&HeightGrid>) -> Blade {
    let twin = blade_at(cell, grid, ground);
    let s = stiffness[0] + (stiffness[1] - stiffness[0]) * hash_unit(twin.hash ^ STIFFNESS_SALT);
    let mut blade = Blade::at_rest(twin.root, Vec3::Y, twin.facing, twin.height.max(0.0), twin.width, s);
    if twin.height <= 0.0 {
        blade.v1.w = 0.0;
    }
    blade
}

/// Every blade of world tile `tile`, in the order the window holds them (the CPU reference of
/// `make_entering_tiles`' attributes: root, orientation, height, width, up, stiffness).
pub fn tile_blades(
    tile: IVec2,
    grid: &InstancedParams,
    stiffness: [f32; 2],
    ground: Option<&HeightGrid>,
) -> Vec<Blade> {
    (0..TILE_BLADES)
        .map(|i| blade_of_cell(StreamWindow::cell_of(tile, i), grid, stiffness, ground))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn window() -> StreamWindow {
        StreamWindow::for_budget(9 * TILE_BLADES + 100, &InstancedParams::default())
    }

    #[test]
    fn the_origin_moves_by_whole_steps_only_when_the_eye_is_far_from_it() {
        let at = |x: f32, z: f32| Vec3::new(x, 1.7, z);
        assert_eq!(frame_origin(Vec2::ZERO, at(1000.0, -1000.0)), Vec2::ZERO);
        assert_eq!(frame_origin(Vec2::ZERO, at(10000.0, 10000.0)), Vec2::splat(10240.0));
        // Back and forth across the boundary between two steps: it stays where it went.
        let o = frame_origin(Vec2::ZERO, at(1030.0, 0.0));
        assert_eq!(o, Vec2::new(1024.0, 0.0));
        assert_eq!(frame_origin(o, at(500.0, 0.0)), o);
        assert_eq!(frame_origin(o, at(1600.0, 0.0)), o);
        // Moving a blade by whole steps keeps every bit of it.
        let x = 1023.3771_f32;
        assert_eq!((x - ORIGIN_STEP) + ORIGIN_STEP, x);
    }

    #[test]
    fn the_budget_sets_the_largest_square_window() {
        let w = window();
        assert_eq!(w.tiles, 3);
        assert_eq!(w.blades(), 9 * TILE_BLADES);
        assert!(w.blades() <= 9 * TILE_BLADES + 100);
    }

    #[test]
    fn every_slot_holds_one_tile_of_the_window_and_tiles_keep_their_slot() {
        let w = StreamWindow { tiles: 4, spacing: 0.1 };
        for base in [IVec2::new(0, 0), IVec2::new(-7, 3), IVec2::new(1001, -2002)] {
            let mut seen: Vec<IVec2> = (0..16).map(|s| w.tile_in(s, base)).collect();
            for (s, t) in seen.iter().enumerate() {
                assert_eq!(w.slot_of(*t), s as u32);
                assert!((*t - base).min_element() >= 0 && (*t - base).max_element() < 4);
            }
            seen.sort_by_key(|t| (t.x, t.y));
            seen.dedup();
            assert_eq!(seen.len(), 16);
        }
    }

    #[test]
    fn the_window_reaches_its_radius_around_any_eye() {
        let w = StreamWindow {
            tiles: 5,
            spacing: 0.13,
        };
        let size = w.tile_size();
        for k in 0..200 {
            let eye = Vec3::new(k as f32 * 0.37 - 30.0, 2.0, k as f32 * -0.61 + 11.0);
            let base = w.base(eye);
            let lo = base.as_vec2() * size;
            let hi = lo + Vec2::splat(5.0 * size);
            let reach = [eye.x - lo.x, hi.x - eye.x, eye.z - lo.y, hi.y - eye.z];
            assert!(reach.iter().all(|&r| r >= w.reach() - 1e-3), "{eye}: {reach:?}");
        }
    }

    fn desc_at(eye: Vec3) -> crate::frame::FrameDesc {
        let mut scene = crate::Scene::default();
        scene.camera.position = eye;
        crate::frame::FrameDesc::of_scene(&scene, Vec2::splat(10.0), (0.0, 1), [64, 64])
    }

    fn four_by_four() -> WindowSlots {
        WindowSlots::new(StreamWindow {
            tiles: 4,
            spacing: 0.125,
        })
    }

    #[test]
    fn the_whole_window_enters_first_then_only_the_tiles_walked_into() {
        let mut slots = four_by_four();
        let mut entering = |x: f32| {
            slots
                .advance(&desc_at(Vec3::new(x, 0.0, 0.0)), [0.0, 0.0], true)
                .entering
                .len()
        };
        assert_eq!(entering(0.0), 16);
        assert_eq!(entering(0.5), 0);
        // One tile (8 units) along x: a column of 4 tiles enters, reusing the column that left.
        assert_eq!(entering(8.0), 4);
        // Back again: the column comes back (it was reused), nothing else.
        assert_eq!(entering(0.0), 4);
        // A jump: everything anew.
        assert_eq!(entering(500.0), 16);
    }

    #[test]
    fn every_box_holds_its_slot_s_tile_around_the_frame_origin() {
        let mut slots = four_by_four();
        let eye = Vec3::new(1500.0, 0.0, -20.0);
        let frame = slots.advance(&desc_at(eye), [-1.0, 2.0], true);
        let [origin, moved] = slots.origin();
        assert_eq!(origin, Vec2::new(1024.0, 0.0));
        assert_eq!(moved, origin);
        for (slot, tile, _) in frame.entering {
            let b = frame.boxes[slot as usize];
            assert_eq!((b.first, b.count), (slot * TILE_BLADES, TILE_BLADES));
            let corner = tile.as_vec2() * slots.window().tile_size() - origin;
            assert!(b.min.x < corner.x && b.max.x > corner.x + slots.window().tile_size());
            assert!(b.min.z < corner.y && b.max.z > corner.y + slots.window().tile_size());
            assert!(b.min.y < -1.0 && b.max.y > 2.0);
        }
    }

    #[test]
    fn another_camera_s_view_of_a_frame_moves_neither_the_window_nor_the_origin() {
        let mut slots = four_by_four();
        assert_eq!(slots.advance(&desc_at(Vec3::ZERO), [0.0, 0.0], true).entering.len(), 16);
        let origin = slots.origin()[0];
        // A minimap's camera far away: nothing enters, nothing is carried to another origin.
        let far = desc_at(Vec3::new(5000.0, 0.0, 0.0));
        assert!(slots.advance(&far, [0.0, 0.0], false).entering.is_empty());
        assert_eq!(slots.origin(), [origin, Vec2::ZERO]);
        // The stepping camera moves it.
        assert_eq!(slots.advance(&far, [0.0, 0.0], true).entering.len(), 16);
        assert_ne!(slots.origin()[1], Vec2::ZERO);
    }

    #[test]
    fn a_window_on_another_grid_is_made_anew_and_another_size_is_not_taken() {
        let mut slots = four_by_four();
        let mut desc = desc_at(Vec3::ZERO);
        let stream = |tiles, spacing| crate::frame::FrameStream {
            window: StreamWindow { tiles, spacing },
            hand_over: 5.0,
            twins: true,
        };
        desc.stream = Some(stream(4, 0.125));
        assert_eq!(slots.advance(&desc, [0.0, 0.0], true).entering.len(), 16);
        assert_eq!(slots.advance(&desc, [0.0, 0.0], true).entering.len(), 0);
        // The instanced grass's density edited: the same tiles on another grid.
        desc.stream = Some(stream(4, 0.2));
        assert_eq!(slots.advance(&desc, [0.0, 0.0], true).entering.len(), 16);
        assert_eq!(slots.window().spacing, 0.2);
        // A window of another size needs a field of its own: the held one stays.
        desc.stream = Some(stream(5, 0.2));
        assert_eq!(slots.advance(&desc, [0.0, 0.0], true).entering.len(), 0);
        assert_eq!(slots.window().tiles, 4);
    }

    #[test]
    fn a_streamed_blade_is_the_instanced_blade_of_its_cell() {
        let grid = InstancedParams::default();
        for cell in [IVec2::new(0, 0), IVec2::new(-5, 9), IVec2::new(70000, -12)] {
            let b = blade_of_cell(cell, &grid, [7.0, 13.0], None);
            let twin = blade_at(cell, &grid, None);
            assert_eq!(b.root(), twin.root);
            assert_eq!(b.height(), twin.height);
            assert_eq!(b.width(), twin.width);
            // The width runs across the instanced blade's face: (cos f, 0, −sin f).
            let across = Vec3::new(twin.facing.cos(), 0.0, -twin.facing.sin());
            assert!(b.width_dir().distance(across) < 1e-5);
            assert!((7.0..13.0).contains(&b.stiffness()));
        }
    }
}
