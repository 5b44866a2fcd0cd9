//! Asking the grass about a place, on the CPU (footsteps, stealth, a grazing animal's AI): how
//! much grass grows there, how tall, of which kind and colour, and how far it is pressed down.
//! It answers by the rules every technique grows its blades by — the paint (`paint.rs`), the
//! kinds of grass (`species.rs`), the generated grass's clumps (`instanced.rs`) — so what it
//! says is what is drawn; and it keeps the presses of the colliders it is stepped with as the
//! GPU's trample map does (`trample.rs`: the same stamp, the same η recovery, the same regrowth
//! of mown grass), but only in the cells a collider touched. Nothing runs until asked.

use std::collections::HashMap;

use glam::{IVec2, Vec2, Vec3};

use crate::field::Surface;
use crate::mesh::{HeightGrid, Mesh, MeshError};
use crate::paint::{paint_at, GroundPaint, Stroke};
use crate::physics::Collider;
use crate::species::MAX_SPECIES;
use crate::trample::{cut, recovered, regrown, stamp, TrampleParams};
use crate::walk::Ground;
use crate::Scene;

/// What the grass is at one place of the ground.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GrassSample {
    /// The ground's height there (`None`: no ground to stand on: off a terrain, or on a
    /// sphere, which has no "down").
    pub ground: Option<f32>,
    /// How much of the grass grows there: 0 bare, 1 all of it.
    pub density: f32,
    /// How tall the grass there stands on average, in units above the ground, unpressed: its
    /// kinds' heights (clumped as the generated grass is), times the paint's length, no taller
    /// than a cutter mowed it. 0 where nothing grows.
    pub height: f32,
    /// The kind of grass most of it is there (an index into the scene's `[[species]]`); `None`
    /// where the scene lists none or nothing grows.
    pub species: Option<usize>,
    /// Each kind's share of the grass there (summing to 1 where the scene lists kinds).
    pub shares: [f32; MAX_SPECIES],
    /// What the grass's colour there is multiplied by (1: the scene's own colours).
    pub tint: Vec3,
    /// How far the grass there is pressed down: 0 standing, 1 flat on the ground.
    pub pressed: f32,
}

/// A kind of grass as the sampler weighs it: its weight and its height range.
#[derive(Clone, Copy, Debug)]
struct Kind {
    weight: f32,
    height: [f32; 2],
}

/// What colliders left in one cell of the ground: how flat they pressed it and how low they
/// mowed it (0: uncut), as of time `at`.
#[derive(Clone, Copy, Debug, Default)]
struct Press {
    push: f32,
    mown: f32,
    at: f32,
}

/// A scene's grass, asked on the CPU. Made from a scene ([`GrassSampler::new`]); told of the
/// colliders each frame where presses matter ([`GrassSampler::step`]); told of strokes a game
/// paints ([`GrassSampler::paint`]).
#[derive(Clone, Debug)]
pub struct GrassSampler {
    paint: Option<GroundPaint>,
    surface: Surface,
    mesh: Option<Mesh>,
    grid: Option<HeightGrid>,
    kinds: Vec<Kind>,
    /// Whether kinds are listed (else one kind of the field's own ranges).
    by_species: bool,
    /// The generated grass's clump scale, where heights clump; `None` for a fixed field of
    /// Bezier blades, whose heights are spread evenly over their range.
    clump_scale: Option<f32>,
    /// Where a fixed field on the plane ends (half its size), beyond which nothing grows.
    plane_reach: Option<Vec2>,
    /// How tall the generated grass grows at most: the depth a collider presses is measured
    /// against it, as the trample map's is.
    grass_top: f32,
    trample: TrampleParams,
    eta_decay: f32,
    presses: HashMap<IVec2, Press>,
    now: f32,
}

impl GrassSampler {
    /// The grass `scene` grows: its paint (maps read), ground (mesh files read) and kinds.
    /// Fails only where a map or mesh file cannot be used.
    pub fn new(scene: &Scene) -> Result<GrassSampler, MeshError> {
        let mesh = scene.surface.mesh(&scene.contents)?;
        let mut sampler = GrassSampler {
            paint: scene.paint_map()?,
            surface: scene.surface.clone(),
            grid: mesh.as_ref().and_then(Mesh::height_grid),
            mesh,
            kinds: Vec::new(),
            by_species: false,
            clump_scale: None,
            plane_reach: None,
            grass_top: 0.0,
            trample: scene.trample,
            eta_decay: 0.0,
            presses: HashMap::new(),
            now: 0.0,
        };
        sampler.tune(scene);
        Ok(sampler)
    }

    /// Take what `scene` says of the grass beside its field — the generated grass's heights
    /// and clumps, the trample map's rates — for a scene that grows the field this sampler's
    /// grows ([`Scene::grows_as`]); its paint and ground stay as read.
    pub fn tune(&mut self, scene: &Scene) {
        let fixed = scene.bezier_blades() > 0 && !scene.field.stream;
        let own_range = if fixed {
            scene.field.height
        } else {
            scene.instanced.grid.height
        };
        self.kinds = if scene.species.is_empty() {
            vec![Kind {
                weight: 1.0,
                height: own_range,
            }]
        } else {
            let kinds = scene.species.iter().take(MAX_SPECIES);
            kinds
                .map(|s| Kind {
                    weight: s.weight,
                    height: s.height,
                })
                .collect()
        };
        self.by_species = !scene.species.is_empty();
        self.clump_scale = (!fixed).then_some(scene.instanced.grid.clump_scale);
        self.plane_reach = (fixed && scene.surface == Surface::Plane).then_some(scene.field.size / 2.0);
        let generated =
            crate::species::envelope(&scene.species).map_or(scene.instanced.grid.height[1], |e| e.height[1]);
        self.grass_top = generated.max(scene.billboard.grid.height[1]);
        self.trample = scene.trample;
        self.eta_decay = scene.simulation.eta_decay;
    }

    /// The grass at world ground point `xz`.
    pub fn at(&self, xz: Vec2) -> GrassSample {
        let ground = self.ground().height_at(xz);
        let paint = paint_at(self.paint.as_ref(), xz);
        let grows = ground.is_some() && self.plane_reach.is_none_or(|r| xz.abs().cmple(r).all());
        let weights: Vec<f32> = self
            .kinds
            .iter()
            .zip(paint.species)
            .map(|(k, m)| k.weight * m)
            .collect();
        let total: f32 = weights.iter().sum();
        // Where no kind weighs anything the first grows (`species.rs` `species_of`).
        let mut shares = [1.0, 0.0, 0.0, 0.0];
        if total > 0.0 {
            for (share, w) in shares.iter_mut().zip(&weights) {
                *share = w / total;
            }
        }
        let density = if grows { paint.density.clamp(0.0, 1.0) } else { 0.0 };
        let tall = self.tall_at(xz);
        let standing: f32 = self
            .kinds
            .iter()
            .zip(shares)
            .map(|(k, s)| s * (k.height[0] + (k.height[1] - k.height[0]) * tall))
            .sum();
        let press = self.press_at(xz);
        let mut height = if density > 0.0 { standing * paint.length } else { 0.0 };
        if press.mown > 0.0 {
            height = height.min(press.mown);
        }
        let dominant = (0..weights.len()).max_by(|&a, &b| shares[a].total_cmp(&shares[b]));
        GrassSample {
            ground,
            density,
            height,
            species: dominant.filter(|_| self.by_species && density > 0.0),
            shares: if self.by_species { shares } else { [0.0; MAX_SPECIES] },
            tint: paint.tint,
            pressed: if density > 0.0 { press.push } else { 0.0 },
        }
    }

    /// The colliders of one frame `dt` seconds long: each presses the cells under it flatter
    /// where it reaches deeper than they already lie, and each cutter mows them lower; every
    /// press recovers as the trample map's does. Costs the cells under the colliders only.
    pub fn step(&mut self, colliders: &[Collider], dt: f32) {
        self.now += dt.max(0.0);
        let size = self.trample.texel_size();
        for c in colliders {
            let reach = Vec2::splat(c.radius);
            let centre = Vec2::new(c.center.x, c.center.z);
            let (low, high) = (
                self.trample.cell_of(centre - reach),
                self.trample.cell_of(centre + reach),
            );
            for z in low.y..=high.y {
                for x in low.x..=high.x {
                    let cell = IVec2::new(x, z);
                    let xz = (cell.as_vec2() + 0.5) * size;
                    let ground = self.ground().height_at(xz).unwrap_or(0.0);
                    self.press(cell, c, xz, ground);
                }
            }
        }
    }

    /// Paint `strokes` of `scene` (the strokes a game added since the sampler was made) into
    /// the paint it reads, as the renderer paints them.
    pub fn paint(&mut self, scene: &Scene, strokes: &[Stroke]) {
        scene.paint_strokes(&mut self.paint, strokes);
    }

    /// Forget every press (a new world, a teleport the trails should not follow).
    pub fn forget_presses(&mut self) {
        self.presses.clear();
    }

    /// Keep the presses of `other` (a sampler of the same scene made anew: its paint or ground
    /// changed, its trails did not).
    pub fn keep_presses_of(&mut self, other: GrassSampler) {
        self.presses = other.presses;
        self.now = other.now;
    }

    /// Collider `c` over cell `cell` (centre `xz`, ground at `ground`).
    fn press(&mut self, cell: IVec2, c: &Collider, xz: Vec2, ground: f32) {
        let now = self.now;
        let mut kept = self.press_at_cell(cell);
        if c.cut {
            if let Some(h) = cut(c, xz, ground, self.grass_top) {
                kept.mown = if kept.mown > 0.0 { kept.mown.min(h) } else { h };
            }
        } else {
            kept.push = kept.push.max(stamp(c, xz, ground, self.grass_top).length());
        }
        if kept.push > 0.0 || kept.mown > 0.0 {
            self.presses.insert(cell, Press { at: now, ..kept });
        }
    }

    /// The press of cell `cell` now: recovered and regrown since it was last pressed.
    fn press_at_cell(&self, cell: IVec2) -> Press {
        let Some(p) = self.presses.get(&cell) else {
            return Press::default();
        };
        let seconds = self.now - p.at;
        Press {
            push: p.push * recovered(p.push, self.eta_decay * seconds),
            mown: regrown(p.mown, self.trample.regrow * seconds),
            at: self.now,
        }
    }

    /// The press at world ground point `xz` (its cell's).
    fn press_at(&self, xz: Vec2) -> Press {
        self.press_at_cell(self.trample.cell_of(xz))
    }

    /// How far up its kinds' ranges the grass at `xz` stands on average, 0 to 1: the generated
    /// grass's clump there, each blade's own draw of a quarter either way averaged (clamped as
    /// `instanced.rs` `blade_at` clamps it); the middle of the range for a fixed field.
    fn tall_at(&self, xz: Vec2) -> f32 {
        let Some(scale) = self.clump_scale else {
            return 0.5;
        };
        let clump = 0.5 + 0.5 * crate::instanced::simplex2(xz * scale);
        const DRAWS: usize = 16;
        let drawn = (0..DRAWS).map(|i| (clump + 0.25 * ((i as f32 + 0.5) / DRAWS as f32 - 0.5)).clamp(0.0, 1.0));
        drawn.sum::<f32>() / DRAWS as f32
    }

    /// The ground the grass stands on.
    fn ground(&self) -> Ground<'_> {
        Ground::of(&self.surface, self.mesh.as_ref(), self.grid.as_ref())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::instanced::{blade_at, InstancedParams};
    use crate::paint::painted_height;
    use crate::species::species_of;
    use crate::trample::TrampleMap;

    fn park() -> Scene {
        Scene::from_toml(include_str!("../../../scenes/park.toml"), "park.toml").unwrap()
    }

    /// A generated blade of cell `cell` as the GPU's `instanced_blade_of` grows it (its kind,
    /// its shape from its kind, its height as the paint lets it): where it stands, how tall,
    /// which kind.
    fn drawn(cell: IVec2, scene: &Scene, paint: Option<&GroundPaint>, grid: Option<&HeightGrid>) -> (Vec2, f32, usize) {
        // Heights 0 to 1: the blade's place in its range.
        let mut unit = scene.instanced;
        unit.grid.height = [0.0, 1.0];
        let b = blade_at(cell, &unit, grid);
        let xz = Vec2::new(b.root.x, b.root.z);
        let p = paint_at(paint, xz);
        let weights: Vec<f32> = scene.species.iter().zip(p.species).map(|(s, m)| s.weight * m).collect();
        let kind = species_of(b.hash, &weights);
        let range = scene
            .species
            .get(kind)
            .map_or(scene.instanced.grid.height, |s| s.height);
        (
            xz,
            painted_height(b.hash, range[0] + (range[1] - range[0]) * b.height, p),
            kind,
        )
    }

    /// The generated blades rooted within `r` of `xz`: how many grow, their mean height, and
    /// how many of each kind.
    fn blades_near(scene: &Scene, sampler: &GrassSampler, xz: Vec2, r: f32) -> (f32, f32, [usize; MAX_SPECIES]) {
        let p: &InstancedParams = &scene.instanced;
        let s = p.spacing();
        let (low, high) = (
            ((xz - r) / s).floor().as_ivec2() - 1,
            ((xz + r) / s).ceil().as_ivec2() + 1,
        );
        let (mut near, mut grown, mut sum, mut kinds) = (0, 0, 0.0, [0; MAX_SPECIES]);
        for z in low.y..=high.y {
            for x in low.x..=high.x {
                let (root, height, kind) =
                    drawn(IVec2::new(x, z), scene, sampler.paint.as_ref(), sampler.grid.as_ref());
                if root.distance(xz) > r {
                    continue;
                }
                near += 1;
                if height > 0.0 {
                    grown += 1;
                    sum += height;
                    kinds[kind] += 1;
                }
            }
        }
        (grown as f32 / near as f32, sum / grown.max(1) as f32, kinds)
    }

    #[test]
    fn the_sampler_says_what_the_generated_blades_are() {
        let scene = park();
        let sampler = GrassSampler::new(&scene).unwrap();
        // On a gravel path, on a lawn beside it, in the meadow, under the boulder, and in the
        // meadow far off (other clumps).
        let places = [
            (0.0, -20.0),
            (4.0, -20.0),
            (40.0, -30.0),
            (14.0, -6.0),
            (-120.0, 150.0),
            (90.0, -200.0),
        ];
        let mut kinds_seen = std::collections::HashSet::new();
        for (x, z) in places {
            let xz = Vec2::new(x, z);
            let said = sampler.at(xz);
            let (grown, height, kinds) = blades_near(&scene, &sampler, xz, 0.7);
            let n: usize = kinds.iter().sum();
            assert!(said.ground.is_some(), "the terrain is under {xz}");
            // Some 75 blades are near: a share within 0.12 is within about two of its spreads.
            assert!(
                (said.density - grown).abs() < 0.12,
                "at {xz}: the sampler says density {}, {grown} of the blades grow",
                said.density
            );
            if n > 20 {
                let off = (said.height - height).abs() / height;
                assert!(
                    off < 0.1,
                    "at {xz}: the sampler says {} tall, the blades are {height} on average",
                    said.height
                );
                let most = (0..MAX_SPECIES).max_by_key(|&k| kinds[k]).unwrap();
                assert_eq!(
                    said.species,
                    Some(most),
                    "at {xz}: kinds {kinds:?}, shares said {:?}",
                    said.shares
                );
                kinds_seen.insert(most);
            } else {
                assert_eq!(said.height, 0.0, "at {xz}: bare ground has no height");
                assert_eq!(said.species, None);
            }
        }
        assert!(
            kinds_seen.len() >= 2,
            "the places hold more than one kind: {kinds_seen:?}"
        );
    }

    #[test]
    fn a_game_s_strokes_change_what_the_sampler_says_as_they_change_the_field() {
        let mut scene = park();
        let mut sampler = GrassSampler::new(&scene).unwrap();
        let (meadow, lawn) = (Vec2::new(40.0, -30.0), Vec2::new(4.0, -20.0));
        let before = (sampler.at(meadow), sampler.at(lawn));
        let unburnt = sampler.at(meadow + Vec2::new(10.0, 0.0));
        let strokes = [
            Stroke::circle(meadow, 2.0).clear(),
            Stroke::path(&[lawn, lawn + Vec2::new(0.0, 3.0)], 1.0).mow(0.5),
            Stroke::circle(meadow + Vec2::new(10.0, 0.0), 2.0).burn(),
            Stroke::circle(meadow + Vec2::new(20.0, 0.0), 2.0)
                .species("dry")
                .strength(0.5),
        ];
        let old = scene.clone();
        scene.paint.strokes.extend(strokes.iter().cloned());
        let added = scene.strokes_added_to(&old).expect("only strokes were added");
        assert_eq!(added, &strokes[..]);
        sampler.paint(&scene, added);
        assert_eq!(sampler.at(meadow).density, 0.0, "cleared");
        assert_eq!(sampler.at(meadow).height, 0.0);
        let mown = sampler.at(lawn).height / before.1.height;
        assert!((mown - 0.5).abs() < 0.01, "mown to half: {mown}");
        let burnt = sampler.at(meadow + Vec2::new(10.0, 0.0));
        // The park's dry patches tint it too: burnt is that tint times BURNT.
        let tint = burnt.tint / unburnt.tint;
        assert!(tint.distance(crate::paint::BURNT) < 0.02, "burnt tint {tint}");
        let stubble = burnt.height / unburnt.height;
        assert!(
            (stubble - crate::paint::BURNT_LENGTH).abs() < 0.01,
            "burnt to {stubble} of its height"
        );
        // Half-way to only dry grass: the meadow grass's weight there halves (1 → 0.5), so the
        // dry grass (weight 0.35) grows from 0.35 / 1.35 of it to 0.35 / 0.85.
        let dry = sampler.at(meadow + Vec2::new(20.0, 0.0)).shares[1];
        assert!(
            (before.0.shares[1] - 0.35 / 1.35).abs() < 0.01,
            "dry before {}",
            before.0.shares[1]
        );
        assert!((dry - 0.35 / 0.85).abs() < 0.01, "dry {dry}");
        // Painted as the renderer paints them: a sampler made from the edited scene agrees.
        let made = GrassSampler::new(&scene).unwrap();
        for p in [
            meadow,
            lawn,
            meadow + Vec2::new(10.0, 1.0),
            meadow + Vec2::new(21.0, 0.5),
            Vec2::new(0.0, -20.0),
        ] {
            assert_eq!(sampler.at(p), made.at(p), "at {p}");
        }
        // Grown back.
        let regrow = Stroke::circle(meadow, 3.0).regrow();
        sampler.paint(&scene, std::slice::from_ref(&regrow));
        assert_eq!(sampler.at(meadow).density, 1.0);
        assert!((sampler.at(meadow).height - before.0.height).abs() < 0.01);
    }

    #[test]
    fn presses_and_mowing_recover_as_the_trample_map_s() {
        let mut scene = Scene {
            technique: crate::instanced::Technique::Instanced,
            ..Scene::default()
        };
        scene.trample.resolution = 128;
        scene.trample.extent = 32.0;
        let mut sampler = GrassSampler::new(&scene).unwrap();
        let mut map = TrampleMap::new(scene.trample);
        let top = sampler.grass_top;
        let eye = Vec3::new(0.0, 1.7, 0.0);
        let dt = 1.0 / 60.0;
        for frame in 0..240 {
            // A ball rolls across for two seconds, a mower passes after it; then both are gone.
            let t = frame as f32 * dt;
            let colliders: Vec<Collider> = if t < 2.0 {
                let ball = Collider::sphere(Vec3::new(-6.0 + 6.0 * t, 0.3, 1.0), 0.5);
                let mower = Collider {
                    cut: true,
                    ..Collider::sphere(Vec3::new(-6.0 + 6.0 * t, 0.55, -3.0), 0.5)
                };
                vec![ball, mower]
            } else {
                Vec::new()
            };
            sampler.step(&colliders, dt);
            map.step(eye, &colliders, top, scene.simulation.eta_decay, dt);
            if frame % 40 != 39 {
                continue;
            }
            let mut pressed = 0;
            for x in -28..28 {
                for (z, row) in [(1.0, "ball"), (-3.0, "mower")] {
                    let xz = Vec2::new(x as f32 * 0.25 + 0.1, z);
                    let said = sampler.at(xz);
                    let push = map.push_at(xz, eye).length();
                    assert!(
                        (said.pressed - push).abs() < 1e-4,
                        "frame {frame}, {row} at {xz}: {} against {push}",
                        said.pressed
                    );
                    let mown = map.cut_at(xz, eye);
                    if mown > 0.0 {
                        assert!(
                            said.height <= mown + 1e-5,
                            "frame {frame}: mown to {mown}, said {}",
                            said.height
                        );
                    }
                    pressed += (said.pressed > 0.0) as u32;
                }
            }
            assert!(frame >= 200 || pressed > 0, "frame {frame}: the ball pressed the grass");
        }
    }
}
