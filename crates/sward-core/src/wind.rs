//! Wind fields w_i(p, τ) of SPEC §3.4 and the wind force on one blade. Every formula here is
//! mirrored line by line in the core's physics.wesl; the GPU-vs-CPU test holds them together.

use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};

use crate::rng::hash_u32;
use crate::validate::{Checks, Validate};

/// Which wind field blows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(rename_all = "snake_case")]
pub enum WindKind {
    /// No wind.
    None,
    /// \[D\]'s directional waves, with a gusting magnitude.
    #[default]
    Waves,
    /// Value-noise gusts scrolling along the wind direction.
    Noise,
    /// The course seed's analytic sum of sines.
    Analytic,
    /// \[D\]'s radial source: a travelling wave from `center`.
    Radial,
    /// A rotating whirl around `center`.
    Whirl,
}

impl WindKind {
    /// The number the shaders switch on.
    pub fn code(self) -> u32 {
        use crate::flags::*;
        match self {
            WindKind::None => WIND_NONE,
            WindKind::Waves => WIND_WAVES,
            WindKind::Noise => WIND_NOISE,
            WindKind::Analytic => WIND_ANALYTIC,
            WindKind::Radial => WIND_RADIAL,
            WindKind::Whirl => WIND_WHIRL,
        }
    }
    /// Every kind, in the order the panel lists them.
    pub const ALL: [WindKind; 6] = [
        WindKind::None,
        WindKind::Waves,
        WindKind::Noise,
        WindKind::Analytic,
        WindKind::Radial,
        WindKind::Whirl,
    ];
}

/// A wind field and its parameters, as the scene file's `[wind]` table holds them.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(default, deny_unknown_fields)]
pub struct Wind {
    /// The kind of wind (the scene file's `type`).
    #[serde(rename = "type")]
    pub kind: WindKind,
    /// Direction the wind blows toward (waves, noise, analytic).
    pub direction: Vec3,
    /// Magnitude (acceleration units, like gravity's 9.8).
    pub strength: f32,
    /// Gust amplitude in [0, 1]: magnitude varies by ±gust (waves).
    pub gust: f32,
    /// Gust frequency in rad/s (waves).
    pub gust_frequency: f32,
    /// Spatial frequency of the noise field, 1/units (noise).
    pub scale: f32,
    /// Speed the gusts travel at, units/s (noise).
    pub speed: f32,
    /// Source of the radial wave or centre of the whirl.
    pub center: Vec3,
}

impl Default for Wind {
    fn default() -> Self {
        Self {
            kind: WindKind::Waves,
            direction: Vec3::new(1.0, 0.0, 0.4),
            strength: 6.0,
            gust: 0.4,
            gust_frequency: 0.7,
            scale: 0.15,
            speed: 3.0,
            center: Vec3::ZERO,
        }
    }
}

impl Wind {
    /// The calm: no wind at all.
    pub fn calm() -> Self {
        Self {
            kind: WindKind::None,
            ..Self::default()
        }
    }

    /// The field's value w_i at point `p` and time `t`.
    pub fn at(&self, p: Vec3, t: f32) -> Vec3 {
        let dir = self.direction.normalize_or_zero();
        match self.kind {
            WindKind::None => Vec3::ZERO,
            WindKind::Waves => {
                let wave = (p.x + p.z) * 0.75 + t;
                let sum = wave.cos() + ((p.x + p.y) * 0.5 + t).sin() + ((p.y + p.z) * 0.25 + t).sin();
                let shape = 1.0 - (sum / 3.0).max(0.0);
                let gust = 1.0 + self.gust * (self.gust_frequency * t).sin();
                dir * (self.strength * shape * gust)
            }
            WindKind::Noise => {
                let q = Vec2::new(p.x, p.z) * self.scale - Vec2::new(dir.x, dir.z) * (self.speed * self.scale * t);
                let n = 0.65 * value_noise(q) + 0.35 * value_noise(q * 2.03 + Vec2::splat(17.1));
                dir * (self.strength * n)
            }
            WindKind::Analytic => {
                let s = 1.0
                    + (0.4 * t + 0.06 * p.x + 0.05 * p.z).sin()
                    + 0.4 * (1.7 * t + 0.4 * p.x).cos()
                    + 0.2 * (3.0 * t + 0.5 * p.z).sin();
                dir * (self.strength * s)
            }
            WindKind::Radial => {
                let d = p - self.center;
                let dist = d.length();
                let wave = 1.0 - (0.4 * dist - 4.0 * t).sin().max(0.0);
                d.normalize_or_zero() * (self.strength * attenuation(dist) * wave)
            }
            WindKind::Whirl => {
                let d = Vec3::new(p.x - self.center.x, 0.0, p.z - self.center.z);
                let radial = d.normalize_or_zero();
                let tangent = Vec3::Y.cross(radial);
                (tangent - 0.25 * radial) * (self.strength * attenuation(d.length()))
            }
        }
    }
}

/// The most wind fields one scene may combine.
pub const MAX_WINDS: usize = 4;

/// The wind fields of a scene, summed (SPEC §3.4: `w_i` may be combined). The scene file holds
/// one `[wind]` table or several `[[wind]]` tables; one field is written back as a table.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
pub struct Winds(pub Vec<Wind>);

impl Default for Winds {
    fn default() -> Self {
        Winds(vec![Wind::default()])
    }
}

impl std::ops::Deref for Winds {
    type Target = Vec<Wind>;
    fn deref(&self) -> &Vec<Wind> {
        &self.0
    }
}

impl std::ops::DerefMut for Winds {
    fn deref_mut(&mut self) -> &mut Vec<Wind> {
        &mut self.0
    }
}

impl Winds {
    /// The summed field at point `p` and time `t`.
    pub fn at(&self, p: Vec3, t: f32) -> Vec3 {
        sum_at(&self.0, p, t)
    }
}

/// The sum of `winds` at point `p` and time `t`: the wind a blade there feels.
pub fn sum_at(winds: &[Wind], p: Vec3, t: f32) -> Vec3 {
    winds.iter().map(|w| w.at(p, t)).sum()
}

impl Serialize for Winds {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self.0.as_slice() {
            [one] => one.serialize(s),
            many => many.serialize(s),
        }
    }
}

impl<'de> Deserialize<'de> for Winds {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(WindsVisitor)
    }
}

/// Reads a table as one field and an array of tables as several, handing each to the file's own
/// deserializer so that errors keep their line and column.
struct WindsVisitor;

impl<'de> serde::de::Visitor<'de> for WindsVisitor {
    type Value = Winds;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a [wind] table or [[wind]] tables")
    }

    fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> Result<Winds, A::Error> {
        Wind::deserialize(serde::de::value::MapAccessDeserializer::new(map)).map(|w| Winds(vec![w]))
    }

    fn visit_seq<A: serde::de::SeqAccess<'de>>(self, seq: A) -> Result<Winds, A::Error> {
        Vec::<Wind>::deserialize(serde::de::value::SeqAccessDeserializer::new(seq)).map(Winds)
    }
}

/// [D]'s fall-off with distance from a wind source: `max(1 − log2(0.2·dist + 1)/4, 0)`.
fn attenuation(dist: f32) -> f32 {
    (1.0 - (0.2 * dist + 1.0).log2() / 4.0).max(0.0)
}

/// Smooth 2D value noise in [0, 1), from the shared integer hash.
pub fn value_noise(q: Vec2) -> f32 {
    let cell = q.floor();
    let f = q - cell;
    let (ix, iy) = (cell.x as i32, cell.y as i32);
    let corner = |dx: i32, dy: i32| {
        let h = hash_u32((ix.wrapping_add(dx) as u32).wrapping_add(hash_u32(iy.wrapping_add(dy) as u32)));
        (h >> 8) as f32 * (1.0 / 16_777_216.0)
    };
    let u = f * f * (Vec2::splat(3.0) - 2.0 * f);
    let bottom = corner(0, 0) + (corner(1, 0) - corner(0, 0)) * u.x;
    let top = corner(0, 1) + (corner(1, 1) - corner(0, 1)) * u.x;
    bottom + (top - bottom) * u.y
}

/// Wind force on a blade: `w_i · f_d · f_r` (SPEC §3.4). Blades already bent along the wind
/// (f_d → 0) or lying flat (f_r → 0) catch less of it.
pub fn wind_force(wind: Vec3, root: Vec3, tip: Vec3, up: Vec3, height: f32) -> Vec3 {
    let alignment = 1.0 - wind.normalize_or_zero().dot((tip - root).normalize_or_zero()).abs();
    let height_ratio = (tip - root).dot(up) / height;
    wind * (alignment * height_ratio)
}

impl Validate for Winds {
    fn validate(&self, c: &mut Checks) {
        c.check(
            (1..=MAX_WINDS).contains(&self.len()),
            "wind",
            self.len(),
            "one to four wind fields ([wind] or [[wind]] tables; type = \"none\" for calm)",
        );
        self.iter().for_each(|w| w.validate(c));
    }
}

impl Validate for Wind {
    fn validate(&self, c: &mut Checks) {
        c.non_negative("wind.strength", self.strength);
        c.check(
            (0.0..=1.0).contains(&self.gust),
            "wind.gust",
            self.gust,
            "an amplitude in [0, 1]",
        );
        c.check(
            self.scale > 0.0 && self.scale.is_finite(),
            "wind.scale",
            self.scale,
            "a positive spatial frequency",
        );
        c.check(
            self.direction.is_finite() && self.center.is_finite() && self.speed.is_finite(),
            "wind",
            "…",
            "finite direction, centre and speed",
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_field_is_finite_and_calm_is_zero() {
        for kind in WindKind::ALL {
            let wind = Wind {
                kind,
                ..Wind::default()
            };
            for i in 0..50 {
                let p = Vec3::new(i as f32 * 1.3 - 30.0, 0.2, i as f32 * -0.7);
                assert!(wind.at(p, i as f32 * 0.1).is_finite(), "{kind:?}");
            }
        }
        assert_eq!(Wind::calm().at(Vec3::ONE, 1.0), Vec3::ZERO);
        // The source itself of the radial field is a degenerate point: guarded, not NaN.
        let radial = Wind {
            kind: WindKind::Radial,
            ..Wind::default()
        };
        assert!(radial.at(radial.center, 0.0).is_finite());
    }

    #[test]
    fn value_noise_is_continuous_across_cells() {
        let a = value_noise(Vec2::new(2.999_99, 5.5));
        let b = value_noise(Vec2::new(3.000_01, 5.5));
        assert!((a - b).abs() < 1e-3);
    }

    #[test]
    fn wind_along_the_blade_does_nothing() {
        let f = wind_force(Vec3::Y * 5.0, Vec3::ZERO, Vec3::Y, Vec3::Y, 1.0);
        assert!(f.length() < 1e-6);
        let g = wind_force(Vec3::X * 5.0, Vec3::ZERO, Vec3::Y, Vec3::Y, 1.0);
        assert!((g - Vec3::X * 5.0).length() < 1e-5);
    }
}
