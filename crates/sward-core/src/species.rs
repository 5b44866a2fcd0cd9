//! Grass types (`[[species]]`): a scene may grow up to four kinds of grass — each with its own
//! height, width, stiffness, lean and colours — mixed by weights that are constants or painted
//! maps. Which kind a blade is comes from its hash and the weights where it grows, by the rule
//! here and the core's WGSL (shading.wesl `species_drawn`), so a generated blade, the Bezier blade it
//! becomes and the billboard of its place are the same kind. A scene without species grows
//! one kind from its `[field]`, `[instanced]` and `[shading]` values.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::rng::hash_unit;
use crate::validate::{Checks, Validate};

/// The most species a scene may list.
pub const MAX_SPECIES: usize = 4;

/// Mixed into a blade's hash for its species draw.
pub const SPECIES_SALT: u32 = 0x5bd1_e995;

/// One kind of grass (`[[species]]`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(default, deny_unknown_fields)]
pub struct Species {
    /// What it is called (the viewer's brush lists it by name).
    pub name: String,
    /// How much of it grows beside the others (their weights are summed).
    pub weight: f32,
    /// A PNG read as grey: its weight there, times `weight` (black: none of it). Shares the
    /// `[paint]` maps' area and size.
    pub weight_map: Option<String>,
    /// It grows only where painted (by its weight map or a `[[paint.stroke]]` naming it), not
    /// everywhere else.
    pub painted_only: bool,
    /// Blade height range [min, max], units.
    pub height: [f32; 2],
    /// Blade half-width range [min, max] at the root, units.
    pub width: [f32; 2],
    /// Stiffness range [min, max]: how strongly its blades stand back up.
    pub stiffness: [f32; 2],
    /// How far its generated blades lean at rest before gravity and wind (`instanced.bend`).
    pub bend: f32,
    /// Colour at the root (linear RGB).
    pub root_color: Vec3,
    /// Colour at the tip (linear RGB).
    pub tip_color: Vec3,
    /// Flowering stalks among its blades (`[species.seed_heads]`; none without).
    pub seed_heads: Option<SeedHeads>,
}

/// A species' flowering stalks: a share of its blades are a thin stalk carrying a seed head —
/// a spindle of its own colour over the top of the blade — instead of a leaf. Which blades comes
/// from the hash (`seed_head_drawn` and its GLSL twin), so every technique draws the same ones.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(default, deny_unknown_fields)]
pub struct SeedHeads {
    /// The share of the species' blades that carry a head, 0 to 1.
    pub share: f32,
    /// How much of the blade's height the head takes, from the tip, 0.05 to 0.6.
    pub length: f32,
    /// How wide the head opens, as a share of the blade's width: 0.5 a grass's slim spike, 2 to
    /// 4 a flower's blossom or a plume (the stalk under it stays thin), 0.25 to 7.75 in quarters.
    pub width: f32,
    /// The head's outline: a spindle widest in its middle (a grass's spike, a plume) or a
    /// blossom opening to its widest at the top (a flower).
    pub shape: HeadShape,
    /// The head's colour (linear RGB).
    pub color: Vec3,
}

impl Default for SeedHeads {
    /// Ripening meadow heads: a quarter of the blades, the top quarter of each, straw-purple.
    fn default() -> Self {
        Self {
            share: 0.25,
            length: 0.25,
            width: 0.5,
            shape: HeadShape::Spike,
            color: Vec3::new(0.42, 0.33, 0.22),
        }
    }
}

/// The outline of a flowering stalk's head.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(rename_all = "snake_case")]
pub enum HeadShape {
    /// Widest in its middle, narrowing to the tip: a grass's seed head, a plume.
    #[default]
    Spike,
    /// Opening from the stalk to its widest at the top: a flower.
    Blossom,
}

/// Mixed into a blade's hash for its seed-head draw.
pub const SEED_HEAD_SALT: u32 = 0x27d4_eb2f;

/// Whether the blade with hash `hash`, of a species with `heads`, is a flowering stalk.
pub fn seed_head_drawn(hash: u32, heads: Option<&SeedHeads>) -> bool {
    heads.is_some_and(|h| hash_unit(hash ^ SEED_HEAD_SALT) < h.share)
}

impl Default for Species {
    /// Meadow grass, as the default scene grows it.
    fn default() -> Self {
        Self {
            name: "meadow".into(),
            weight: 1.0,
            weight_map: None,
            painted_only: false,
            height: [0.45, 1.1],
            width: [0.02, 0.045],
            stiffness: [14.0, 28.0],
            bend: 0.0,
            root_color: Vec3::new(0.05, 0.2, 0.03),
            tip_color: Vec3::new(0.35, 0.55, 0.15),
            seed_heads: None,
        }
    }
}

impl Validate for Species {
    fn validate(&self, c: &mut Checks) {
        let key = |k: &str| format!("species.{}.{k}", self.name);
        c.check(
            self.weight.is_finite() && self.weight >= 0.0 && self.weight <= 1000.0,
            key("weight"),
            self.weight,
            "a weight from 0 to 1000",
        );
        c.range(key("height"), self.height);
        c.range(key("width"), self.width);
        c.range(key("stiffness"), self.stiffness);
        c.check(
            self.bend.is_finite() && (0.0..=1.0).contains(&self.bend),
            key("bend"),
            self.bend,
            "0 to 1",
        );
        for (name, colour) in [("root_color", self.root_color), ("tip_color", self.tip_color)] {
            c.check(
                colour.is_finite() && colour.min_element() >= 0.0 && colour.max_element() <= 16.0,
                key(name),
                colour,
                "three linear RGB values from 0 to 16",
            );
        }
        if let Some(h) = &self.seed_heads {
            c.check(
                h.share.is_finite() && (0.0..=1.0).contains(&h.share),
                key("seed_heads.share"),
                h.share,
                "a share from 0 to 1",
            );
            c.check(
                h.length.is_finite() && (0.05..=0.6).contains(&h.length),
                key("seed_heads.length"),
                h.length,
                "a part of the blade from 0.05 to 0.6",
            );
            c.check(
                h.width.is_finite() && (0.25..=7.75).contains(&h.width),
                key("seed_heads.width"),
                h.width,
                "a share of the blade's width from 0.25 to 7.75",
            );
            c.check(
                h.color.is_finite() && h.color.min_element() >= 0.0 && h.color.max_element() <= 16.0,
                key("seed_heads.color"),
                h.color,
                "three linear RGB values from 0 to 16",
            );
        }
    }
}

/// Which species (an index into `weights`) the blade with hash `hash` is where the species
/// weigh `weights`: its draw falls in that species' share of their sum (the first where all
/// weigh nothing).
pub fn species_of(hash: u32, weights: &[f32]) -> usize {
    let total: f32 = weights.iter().sum();
    if weights.is_empty() || total <= 0.0 {
        return 0;
    }
    let mut draw = hash_unit(hash ^ SPECIES_SALT) * total;
    for (i, &w) in weights.iter().enumerate() {
        if draw < w {
            return i;
        }
        draw -= w;
    }
    weights.len() - 1
}

/// The ranges every species falls within (`envelope`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Envelope {
    /// Blade heights.
    pub height: [f32; 2],
    /// Blade half-widths.
    pub width: [f32; 2],
    /// Stiffnesses.
    pub stiffness: [f32; 2],
    /// The most bend.
    pub bend: f32,
}

/// The ranges every species falls within (`None` without species). A frame's bounds on
/// generated grass (its patches' tops, its lists' sizes) are taken over these.
pub fn envelope(species: &[Species]) -> Option<Envelope> {
    let first = species.first()?;
    let widen = |r: [f32; 2], s: [f32; 2]| [r[0].min(s[0]), r[1].max(s[1])];
    let start = Envelope {
        height: first.height,
        width: first.width,
        stiffness: first.stiffness,
        bend: first.bend,
    };
    Some(species.iter().fold(start, |e, s| Envelope {
        height: widen(e.height, s.height),
        width: widen(e.width, s.width),
        stiffness: widen(e.stiffness, s.stiffness),
        bend: e.bend.max(s.bend),
    }))
}

/// `value`'s place in range `from`, carried to the same place in range `to` (a blade grown
/// within the field's ranges, given its species').
pub fn carried(value: f32, from: [f32; 2], to: [f32; 2]) -> f32 {
    let t = if from[1] > from[0] {
        ((value - from[0]) / (from[1] - from[0])).clamp(0.0, 1.0)
    } else {
        0.5
    };
    to[0] + (to[1] - to[0]) * t
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::hash_u32;

    #[test]
    fn each_species_gets_its_share_of_the_blades() {
        let weights = [1.0, 3.0, 0.0, 4.0];
        let mut counts = [0usize; 4];
        let n = 40_000u32;
        for i in 0..n {
            counts[species_of(hash_u32(i), &weights)] += 1;
        }
        for (k, &w) in weights.iter().enumerate() {
            let share = counts[k] as f32 / n as f32;
            assert!((share - w / 8.0).abs() < 0.01, "species {k}: {share}");
        }
        assert_eq!(species_of(7, &[0.0, 0.0]), 0);
        assert_eq!(species_of(7, &[]), 0);
    }

    #[test]
    fn a_share_of_the_blades_carry_seed_heads() {
        let heads = SeedHeads {
            share: 0.3,
            ..SeedHeads::default()
        };
        let n = 20_000u32;
        let drawn = (0..n).filter(|&i| seed_head_drawn(hash_u32(i), Some(&heads))).count();
        assert!((drawn as f32 / n as f32 - 0.3).abs() < 0.01, "{drawn}");
        assert!(!seed_head_drawn(hash_u32(1), None));
    }

    #[test]
    fn a_blade_keeps_its_place_in_its_range() {
        assert_eq!(carried(0.5, [0.0, 1.0], [2.0, 4.0]), 3.0);
        assert_eq!(carried(9.0, [0.0, 1.0], [2.0, 4.0]), 4.0);
        assert_eq!(carried(0.3, [0.3, 0.3], [2.0, 4.0]), 3.0);
    }
}
