//! The trample map (SPEC §11): grass that keeps no state of its own — the instanced grass and the
//! billboards, made anew each frame — still remembers where it was walked on. A square window of
//! texels over the ground around the eye holds, per texel, which way and how far the grass there
//! is flattened; every collider stamps it each frame, and every texel recovers by the Bezier
//! blades' own η rule (SPEC §3.7: strength falls by `eta_decay` per second), so a trail fades at
//! their rate. The window follows the eye a texel at a time: texel (i, j) holds the world cell
//! congruent to it modulo the resolution that lies within the window, and a texel that changes
//! cell starts flat. This is the CPU reference of the trample pass (`shaders/trample.wesl`).

use glam::{IVec2, Vec2, Vec3};
use serde::{Deserialize, Serialize};

use crate::physics::Collider;
use crate::validate::{Checks, Validate};

/// The trample map's scene parameters (`[trample]`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(default, deny_unknown_fields)]
pub struct TrampleParams {
    /// Whether colliders flatten the generated grass (the Bezier blades respond either way).
    pub enabled: bool,
    /// Texels along each side of the window.
    pub resolution: u32,
    /// Units of ground along each side of the window (centred on the eye's cell).
    pub extent: f32,
    /// How fast mown grass grows back, units of height per second.
    pub regrow: f32,
}

impl Default for TrampleParams {
    fn default() -> Self {
        Self {
            enabled: true,
            // 0.25-unit texels over 192 units: a walker's trail of the last minute (96 units
            // behind at 1.4 units a second) is still in the window; 9 MiB.
            resolution: 768,
            extent: 192.0,
            regrow: 0.05,
        }
    }
}

impl TrampleParams {
    /// The most texels along a side (a 4096² map is 256 MiB).
    pub const MAX_RESOLUTION: u32 = 4096;

    /// Units of ground per texel.
    pub fn texel_size(&self) -> f32 {
        self.extent / self.resolution.max(1) as f32
    }

    /// The world cell that holds ground point `xz`.
    pub fn cell_of(&self, xz: Vec2) -> IVec2 {
        (xz / self.texel_size()).floor().as_ivec2()
    }

    /// The first cell of the window around `eye` (its lowest x and z).
    pub fn window_base(&self, eye: Vec3) -> IVec2 {
        self.cell_of(Vec2::new(eye.x, eye.z)) - IVec2::splat(self.resolution as i32 / 2)
    }

    /// The world cell texel `texel` holds in the window that starts at `base`.
    pub fn cell_at(&self, texel: IVec2, base: IVec2) -> IVec2 {
        let n = self.resolution as i32;
        base + (texel - base).rem_euclid(IVec2::splat(n))
    }
}

/// A cell's tag, kept with its texel: a texel whose tag is not its cell's holds an old cell.
pub fn cell_tag(cell: IVec2) -> u32 {
    (cell.x as u32 & 0xffff) | (cell.y as u32 & 0xffff) << 16
}

/// How high above the ground (at height `ground`) a collider's underside is over ground point
/// `xz`, where the collider is over it at all.
fn underside(collider: &Collider, xz: Vec2, ground: f32) -> Option<f32> {
    let away = xz - Vec2::new(collider.center.x, collider.center.z);
    let reach = collider.radius * collider.radius - away.length_squared();
    (reach > 0.0).then(|| collider.center.y - reach.sqrt() - ground)
}

/// How a collider flattens the grass at ground point `xz` (ground at height `ground`, grass
/// `grass_top` tall there): away from the collider's centre, by how deep its underside reaches
/// into the grass (1: down to the ground), or not at all where it does not reach down into it.
pub fn stamp(collider: &Collider, xz: Vec2, ground: f32, grass_top: f32) -> Vec2 {
    let Some(under) = underside(collider, xz, ground).filter(|_| grass_top > 0.0) else {
        return Vec2::ZERO;
    };
    let away = xz - Vec2::new(collider.center.x, collider.center.z);
    let depth = ((grass_top - under) / grass_top).clamp(0.0, 1.0);
    away.normalize_or(Vec2::X) * depth
}

/// The lowest a cutter mows grass, units above the ground (so a cut texel's height is never
/// 0, which marks uncut grass).
pub const STUBBLE: f32 = 0.02;
/// Mown grass that has grown back this tall is uncut again (taller than any grass grows).
pub const GROWN_BACK: f32 = 16.0;

/// How high cutter `collider` leaves the grass at ground point `xz` (ground at `ground`): its
/// underside there, no lower than [`STUBBLE`]; `None` where it does not reach down to below
/// `grass_top`.
pub fn cut(collider: &Collider, xz: Vec2, ground: f32, grass_top: f32) -> Option<f32> {
    let under = underside(collider, xz, ground)?;
    (under < grass_top).then_some(under.max(STUBBLE))
}

/// Mown height `height` (0: uncut) after growing back for `amount` units: uncut again once
/// past [`GROWN_BACK`].
pub fn regrown(height: f32, amount: f32) -> f32 {
    match height {
        h if h <= 0.0 => 0.0,
        h if h + amount >= GROWN_BACK => 0.0,
        h => h + amount,
    }
}

/// One texel: which way and how far its grass lies (length 1: flat), how high it was mown
/// (0: uncut), and its cell's tag.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Texel {
    /// Flattening direction times strength, in the ground's xz plane.
    pub push: Vec2,
    /// The grass's height above the ground where mown (growing back), 0 where uncut.
    pub cut: f32,
    /// `cell_tag` of the cell the texel holds.
    pub tag: u32,
}

impl Texel {
    /// A texel as the GPU holds it: the push's two floats, the mown height and the tag, as
    /// four words (their bits).
    pub fn from_words(words: [u32; 4]) -> Texel {
        Texel {
            push: Vec2::new(f32::from_bits(words[0]), f32::from_bits(words[1])),
            cut: f32::from_bits(words[2]),
            tag: words[3],
        }
    }
}

/// The trample map on the CPU (the GPU's reference, for tests).
#[derive(Clone, Debug)]
pub struct TrampleMap {
    /// The window's size and extent.
    pub params: TrampleParams,
    /// Texels row by row (z, then x), `resolution`² of them.
    pub texels: Vec<Texel>,
}

impl TrampleMap {
    /// A map with every texel flat-free.
    pub fn new(params: TrampleParams) -> TrampleMap {
        let n = params.resolution as usize;
        TrampleMap {
            params,
            texels: vec![Texel::default(); n * n],
        }
    }

    /// One frame of `dt` seconds with the window around `eye`: every texel recovers by
    /// `decay · dt` and grows back by `regrow · dt` (a texel that changed cell starts upright
    /// and uncut), then every collider stamps it where it flattens more than the texel already
    /// is, and every cutter mows it where it cuts lower. The ground is flat at height 0.
    pub fn step(&mut self, eye: Vec3, colliders: &[Collider], grass_top: f32, decay: f32, dt: f32) {
        let n = self.params.resolution as i32;
        let base = self.params.window_base(eye);
        let size = self.params.texel_size();
        for (i, texel) in self.texels.iter_mut().enumerate() {
            let cell = self.params.cell_at(IVec2::new(i as i32 % n, i as i32 / n), base);
            let tag = cell_tag(cell);
            let kept = if texel.tag == tag { *texel } else { Texel::default() };
            let mut push = kept.push * recovered(kept.push.length(), decay * dt);
            let mut mown = regrown(kept.cut, self.params.regrow * dt);
            let xz = (cell.as_vec2() + 0.5) * size;
            for c in colliders {
                if c.cut {
                    if let Some(h) = cut(c, xz, 0.0, grass_top) {
                        mown = if mown > 0.0 { mown.min(h) } else { h };
                    }
                    continue;
                }
                let pressed = stamp(c, xz, 0.0, grass_top);
                if pressed.length() > push.length() {
                    push = pressed;
                }
            }
            *texel = Texel { push, cut: mown, tag };
        }
    }

    /// How the grass at ground point `xz` lies: zero outside the window or where the texel
    /// holds another cell.
    pub fn push_at(&self, xz: Vec2, eye: Vec3) -> Vec2 {
        self.texel_at(xz, eye).push
    }

    /// How high the grass at ground point `xz` was mown (0: uncut, as off the window).
    pub fn cut_at(&self, xz: Vec2, eye: Vec3) -> f32 {
        self.texel_at(xz, eye).cut
    }

    /// The texel of ground point `xz` where it holds that point's cell, else an untouched one.
    fn texel_at(&self, xz: Vec2, eye: Vec3) -> Texel {
        let n = self.params.resolution as i32;
        let base = self.params.window_base(eye);
        let cell = self.params.cell_of(xz);
        let t = cell - base;
        if t.min_element() < 0 || t.max_element() >= n {
            return Texel::default();
        }
        let wrapped = cell.rem_euclid(IVec2::splat(n));
        let texel = self.texels[(wrapped.y * n + wrapped.x) as usize];
        if texel.tag == cell_tag(cell) {
            texel
        } else {
            Texel::default()
        }
    }
}

/// The map as a picture, `side`² RGBA pixels over the window around `eye` (row 0 at the window's
/// far z edge, so the picture is the map seen from above with +z up): grass green, pressed
/// grass towards yellow by how flat it lies, mown grass towards brown by how short it is (as
/// tall as `grass_top` again: green). Each pixel shows the most trampled and lowest-mown texel
/// of its block. For the viewer's overlay.
pub fn overlay(params: &TrampleParams, texels: &[Texel], eye: Vec3, grass_top: f32, side: u32) -> Vec<[u8; 4]> {
    let n = params.resolution as i32;
    let base = params.window_base(eye);
    let block = (n / side.max(1) as i32).max(1);
    let mut pixels = Vec::with_capacity((side * side) as usize);
    for row in 0..side as i32 {
        for col in 0..side as i32 {
            let (mut flat, mut short) = (0.0f32, 0.0f32);
            for dz in 0..block {
                for dx in 0..block {
                    let offset = IVec2::new(col * block + dx, n - 1 - (row * block + dz));
                    let cell = base + offset;
                    let wrapped = cell.rem_euclid(IVec2::splat(n));
                    let Some(texel) = texels.get((wrapped.y * n + wrapped.x) as usize) else {
                        continue;
                    };
                    if texel.tag != cell_tag(cell) {
                        continue;
                    }
                    flat = flat.max(texel.push.length().min(1.0));
                    if texel.cut > 0.0 {
                        short = short.max((1.0 - texel.cut / grass_top.max(1e-3)).clamp(0.0, 1.0));
                    }
                }
            }
            let grass = Vec3::new(40.0, 90.0, 30.0);
            let colour = grass
                .lerp(Vec3::new(250.0, 220.0, 70.0), flat)
                .lerp(Vec3::new(150.0, 90.0, 40.0), short);
            pixels.push([colour.x as u8, colour.y as u8, colour.z as u8, 255]);
        }
    }
    pixels
}

/// The factor a push of length `strength` keeps after recovering by `amount` (the η rule).
pub fn recovered(strength: f32, amount: f32) -> f32 {
    if strength > 0.0 {
        (strength - amount).max(0.0) / strength
    } else {
        0.0
    }
}

impl Validate for TrampleParams {
    fn validate(&self, c: &mut Checks) {
        c.check(
            (16..=TrampleParams::MAX_RESOLUTION).contains(&self.resolution),
            "trample.resolution",
            self.resolution,
            "16 to 4096 texels along a side",
        );
        c.check(
            self.extent > 0.0 && self.extent <= 100_000.0,
            "trample.extent",
            self.extent,
            "0 < extent ≤ 100000 units of ground",
        );
        c.check(
            self.regrow.is_finite() && (0.0..=100.0).contains(&self.regrow),
            "trample.regrow",
            self.regrow,
            "0 ≤ regrow ≤ 100 units of height per second",
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn small() -> TrampleParams {
        TrampleParams {
            enabled: true,
            resolution: 64,
            extent: 16.0,
            regrow: 0.1,
        }
    }

    #[test]
    fn a_cutter_mows_to_its_underside_and_the_grass_grows_back() {
        let mut map = TrampleMap::new(small());
        let eye = Vec3::new(0.0, 1.7, 0.0);
        let mower = Collider {
            cut: true,
            ..Collider::sphere(Vec3::new(1.0, 0.7, 1.0), 0.5)
        };
        map.step(eye, std::slice::from_ref(&mower), 0.8, 0.5, 1.0 / 60.0);
        let under = Vec2::new(1.05, 1.05);
        let mown = map.cut_at(under, eye);
        assert!((0.2..0.25).contains(&mown), "mown to {mown}, its underside is 0.2");
        assert_eq!(map.push_at(under, eye), Vec2::ZERO, "a cutter presses nothing");
        assert_eq!(map.cut_at(Vec2::new(2.0, 1.0), eye), 0.0, "beyond its reach");
        // A cutter above the grass cuts nothing.
        let high = Collider {
            center: Vec3::new(-2.0, 1.5, 1.0),
            ..mower.clone()
        };
        map.step(eye, &[high], 0.8, 0.5, 0.0);
        assert_eq!(map.cut_at(Vec2::new(-2.0, 1.0), eye), 0.0);
        // Ten seconds at 0.1 units a second: a unit taller.
        for _ in 0..600 {
            map.step(eye, &[], 0.8, 0.5, 1.0 / 60.0);
        }
        let grown = map.cut_at(under, eye);
        assert!((grown - mown - 1.0).abs() < 1e-3, "{mown} → {grown}");
        // Cut again, lower: the lower cut holds.
        map.step(eye, &[mower], 0.8, 0.5, 0.0);
        assert!((map.cut_at(under, eye) - mown).abs() < 1e-6);
        assert_eq!(
            regrown(GROWN_BACK - 0.5, 1.0),
            0.0,
            "grown back past every blade: uncut"
        );
        assert_eq!(regrown(0.0, 1.0), 0.0, "uncut stays uncut");
    }

    #[test]
    fn a_ball_on_the_ground_flattens_the_grass_away_from_it_and_none_beyond_its_reach() {
        let b = Collider::sphere(Vec3::new(2.0, 0.5, 3.0), 0.5);
        let under = stamp(&b, Vec2::new(2.2, 3.0), 0.0, 1.0);
        assert!(under.x > 0.5 && under.y.abs() < 1e-6, "{under}");
        assert_eq!(stamp(&b, Vec2::new(2.6, 3.0), 0.0, 1.0), Vec2::ZERO, "outside the ball");
        let high = Collider::sphere(Vec3::new(2.0, 3.0, 3.0), 0.5);
        assert_eq!(
            stamp(&high, Vec2::new(2.0, 3.0), 0.0, 1.0),
            Vec2::ZERO,
            "above the grass"
        );
        // Its lowest point at the ground flattens fully.
        assert!((stamp(&b, Vec2::new(2.0, 3.0), 0.0, 1.0).length() - 1.0).abs() < 1e-6);
    }

    #[test]
    fn a_trail_fades_at_the_blades_rate_and_stays_where_it_was_made() {
        let mut map = TrampleMap::new(small());
        let eye = Vec3::new(0.0, 1.7, 0.0);
        map.step(
            eye,
            &[Collider::sphere(Vec3::new(1.0, 0.3, 1.0), 0.4)],
            0.8,
            0.5,
            1.0 / 60.0,
        );
        let at = Vec2::new(1.05, 1.0);
        let pressed = map.push_at(at, eye).length();
        assert!(pressed > 0.5, "{pressed}");
        // The ball is gone: half a unit of strength recovers per second.
        for _ in 0..30 {
            map.step(eye, &[], 0.8, 0.5, 1.0 / 60.0);
        }
        let later = map.push_at(at, eye).length();
        assert!((pressed - later - 0.25).abs() < 1e-4, "{pressed} → {later}");
        // The eye walks a few units: the trail stays where it was, in the window.
        let walked = Vec3::new(3.0, 1.7, -2.0);
        map.step(walked, &[], 0.8, 0.5, 0.0);
        assert_eq!(map.push_at(at, walked).length(), later);
        // Far enough that its texel holds another cell: the trail is forgotten.
        let away = Vec3::new(13.0, 1.7, 0.0);
        map.step(away, &[], 0.8, 0.5, 0.0);
        assert_eq!(map.push_at(at, away), Vec2::ZERO);
        let back = Vec3::new(0.0, 1.7, 0.0);
        map.step(back, &[], 0.8, 0.5, 0.0);
        assert_eq!(map.push_at(at, back), Vec2::ZERO, "a reused texel starts upright");
    }

    #[test]
    fn the_overlay_shows_trails_and_mown_grass_where_they_are() {
        let mut map = TrampleMap::new(small());
        let eye = Vec3::new(0.0, 1.7, 0.0);
        let ball = Collider::sphere(Vec3::new(-4.0, 0.3, 4.0), 0.5);
        let mower = Collider {
            cut: true,
            ..Collider::sphere(Vec3::new(4.0, 0.6, -4.0), 0.6)
        };
        map.step(eye, &[ball, mower], 0.8, 0.5, 0.0);
        let side = 16;
        let picture = overlay(&map.params, &map.texels, eye, 0.8, side);
        assert_eq!(picture.len(), 256);
        // 16 units over 16 pixels, the window from -8 to 8: the ball at x -4, z 4 is column 4,
        // row 3 (rows run from the far z edge); the mower at column 12, row 11.
        let at = |col: usize, row: usize| picture[row * side as usize + col];
        let (pressed, mown, untouched) = (at(4, 3), at(12, 11), at(8, 8));
        assert!(pressed[0] > 150 && pressed[1] > 150, "a trail is yellow: {pressed:?}");
        assert!(mown[0] > mown[1], "mown grass is brown: {mown:?}");
        assert_eq!(untouched, [40, 90, 30, 255], "untouched grass is green");
    }

    #[test]
    fn every_texel_of_the_window_holds_one_cell_of_it() {
        let p = small();
        let base = p.window_base(Vec3::new(-37.3, 0.0, 91.8));
        let mut seen = std::collections::HashSet::new();
        for j in 0..64 {
            for i in 0..64 {
                let cell = p.cell_at(IVec2::new(i, j), base);
                let t = cell - base;
                assert!(
                    t.min_element() >= 0 && t.max_element() < 64,
                    "{cell} outside the window"
                );
                assert_eq!(cell.rem_euclid(IVec2::splat(64)), IVec2::new(i, j));
                assert!(seen.insert(cell));
            }
        }
    }
}
