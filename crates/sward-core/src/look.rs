//! How blades, ground and sky look: blade shape (SPEC §6) and shading model and parameters (SPEC §8).

use crate::validate::{finite_non_negative, Checks, Validate};
use glam::Vec3;
use serde::{Deserialize, Serialize};

/// The blade silhouettes of the paper.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(rename_all = "snake_case")]
pub enum BladeShape {
    /// The same width from root to tip.
    Quad,
    /// Narrowing linearly to a point.
    Triangle,
    /// Narrowing along a parabola (the paper's default).
    #[default]
    Quadratic,
    /// Full width, then a triangular tip from `tip_threshold` on.
    TriangleTip,
}

impl BladeShape {
    /// The shape's number as the shaders read it.
    pub fn code(self) -> u32 {
        use crate::flags::*;
        match self {
            BladeShape::Quad => BLADE_QUAD,
            BladeShape::Triangle => BLADE_TRIANGLE,
            BladeShape::Quadratic => BLADE_QUADRATIC,
            BladeShape::TriangleTip => BLADE_TRIANGLE_TIP,
        }
    }
}

/// Shape of the tessellated blade.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(default, deny_unknown_fields)]
pub struct BladeStyle {
    /// The blade's silhouette.
    pub shape: BladeShape,
    /// Where the triangle-tip shape starts narrowing, in [0, 1) along the height.
    pub tip_threshold: f32,
    /// Fold the blade along its midrib (the 3D ridge).
    pub ridge: bool,
    /// Blades narrower than this on screen blend toward a quad so they do not alias into holes
    /// (0 turns the fix off).
    pub min_width_pixels: f32,
}

impl Default for BladeStyle {
    fn default() -> Self {
        Self {
            shape: BladeShape::Quadratic,
            tip_threshold: 0.5,
            ridge: true,
            min_width_pixels: 1.5,
        }
    }
}

/// How blades catch the sun (SPEC §8).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(rename_all = "snake_case")]
pub enum ShadingModel {
    /// Diffuse only.
    Lambert,
    /// Diffuse plus a specular highlight that grows toward the tip.
    #[default]
    BlinnPhong,
}

impl ShadingModel {
    /// The model's number as the shaders read it.
    pub fn code(self) -> u32 {
        match self {
            ShadingModel::Lambert => crate::flags::SHADING_LAMBERT,
            ShadingModel::BlinnPhong => crate::flags::SHADING_BLINN_PHONG,
        }
    }
}

/// Whether blades cast shadows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(rename_all = "snake_case")]
pub enum BladeShadows {
    /// As the quality preset says (`QualityPreset::blade_shadows`: at `ultra`).
    #[default]
    Preset,
    /// At every preset.
    On,
    /// At none.
    Off,
}

impl BladeShadows {
    /// Every choice, in the order the panel lists them.
    pub const ALL: [BladeShadows; 3] = [Self::Preset, Self::On, Self::Off];

    /// The choice as the scene file spells it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Preset => "preset",
            Self::On => "on",
            Self::Off => "off",
        }
    }

    /// Whether blades cast shadows at `preset`.
    pub fn at(self, preset: crate::quality::QualityPreset) -> bool {
        match self {
            Self::Preset => preset.blade_shadows(),
            Self::On => true,
            Self::Off => false,
        }
    }
}

/// Colours and light. Colours are linear RGB.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(default, deny_unknown_fields)]
pub struct Shading {
    /// Direction toward the sun.
    pub light_direction: Vec3,
    /// Sunlight colour.
    pub light_color: Vec3,
    /// Share of sky light in [0, 1].
    pub ambient: f32,
    /// Blade colour at the root.
    pub root_color: Vec3,
    /// Blade colour at the tip.
    pub tip_color: Vec3,
    /// Per-blade colour variation in [0, 1].
    pub color_jitter: f32,
    /// Colour of the ground.
    pub ground_color: Vec3,
    /// How wet the ground is, in [0, 1]: where it is bare (painted clear, or between noise
    /// patches) it is standing water to this share, mirroring the sky, and the soil under the
    /// grass is darker with it (a marsh); 0 is dry soil.
    pub ground_water: f32,
    /// Sky colour overhead.
    pub sky_zenith: Vec3,
    /// Sky colour at the horizon (and of the fog).
    pub sky_horizon: Vec3,
    /// Exponential fog density per unit of distance (0 = none).
    pub fog_density: f32,
    /// The lighting model: Lambert or Blinn-Phong.
    pub model: ShadingModel,
    /// Strength of the Blinn-Phong highlight at the tip (it fades to nothing at the root).
    pub specular: f32,
    /// Blinn-Phong exponent: larger is a tighter highlight.
    pub shininess: f32,
    /// Sunlight scattered through the blade toward a viewer looking into the sun (0 = none).
    pub translucency: f32,
    /// Fake ambient occlusion darkening roots and the midrib, in [0, 1] (0 = none).
    pub ambient_occlusion: f32,
    /// Colour variation between clumps of grass, in [0, 1].
    pub clump_variation: f32,
    /// Spatial frequency of the clumps, 1/units.
    pub clump_scale: f32,
    /// Grass and ground receive the shadows of the terrain and the colliders.
    pub shadows: bool,
    /// Whether blades near the eye cast shadows too (with `shadows` on): "preset" (at `ultra`),
    /// "on" or "off".
    pub blade_shadows: BladeShadows,
    /// How far from the eye blades cast shadows (units): the reach of the sun's near cascade.
    /// Blade shadows fade out over its last fifth. 0 turns them off.
    pub blade_shadow_distance: f32,
}

impl Default for Shading {
    fn default() -> Self {
        Self {
            light_direction: Vec3::new(0.4, 0.8, 0.35),
            light_color: Vec3::new(1.0, 0.95, 0.85),
            ambient: 0.35,
            root_color: Vec3::new(0.03, 0.09, 0.01),
            tip_color: Vec3::new(0.22, 0.42, 0.06),
            color_jitter: 0.25,
            ground_color: Vec3::new(0.07, 0.06, 0.025),
            ground_water: 0.0,
            sky_zenith: Vec3::new(0.15, 0.32, 0.75),
            sky_horizon: Vec3::new(0.65, 0.75, 0.85),
            fog_density: 0.01,
            model: ShadingModel::BlinnPhong,
            specular: 0.25,
            shininess: 24.0,
            translucency: 0.5,
            ambient_occlusion: 0.6,
            clump_variation: 0.3,
            clump_scale: 0.12,
            shadows: true,
            blade_shadows: BladeShadows::Preset,
            blade_shadow_distance: 12.0,
        }
    }
}

impl Validate for Shading {
    fn validate(&self, c: &mut Checks) {
        c.non_negative("shading.specular", self.specular);
        c.non_negative("shading.translucency", self.translucency);
        for (key, value) in [
            ("shading.ambient_occlusion", self.ambient_occlusion),
            ("shading.clump_variation", self.clump_variation),
        ] {
            c.check((0.0..=1.0).contains(&value), key, value, "a value in [0, 1]");
        }
        c.check(
            self.shininess >= 1.0 && self.shininess.is_finite(),
            "shading.shininess",
            self.shininess,
            "an exponent ≥ 1",
        );
        c.check(
            self.clump_scale > 0.0 && self.clump_scale.is_finite(),
            "shading.clump_scale",
            self.clump_scale,
            "a positive spatial frequency",
        );
        c.check(
            self.light_direction.length() > 1e-6,
            "shading.light_direction",
            self.light_direction,
            "a non-zero direction",
        );
        for (key, value) in [
            ("shading.ambient", self.ambient),
            ("shading.color_jitter", self.color_jitter),
            ("shading.ground_water", self.ground_water),
        ] {
            c.check((0.0..=1.0).contains(&value), key, value, "a share in [0, 1]");
        }
        c.check(
            finite_non_negative(self.fog_density),
            "shading.fog_density",
            self.fog_density,
            "a finite density ≥ 0",
        );
        c.check(
            finite_non_negative(self.blade_shadow_distance) && self.blade_shadow_distance <= 1000.0,
            "shading.blade_shadow_distance",
            self.blade_shadow_distance,
            "a distance in [0, 1000] units (0: blades cast no shadows)",
        );
        let colors = [
            self.light_color,
            self.root_color,
            self.tip_color,
            self.ground_color,
            self.sky_zenith,
            self.sky_horizon,
        ];
        c.check(
            colors.iter().all(|v| v.is_finite() && v.min_element() >= 0.0),
            "shading",
            "colour",
            "colours with finite components ≥ 0",
        );
    }
}

impl Validate for BladeStyle {
    fn validate(&self, c: &mut Checks) {
        c.check(
            (0.0..1.0).contains(&self.tip_threshold),
            "blades.tip_threshold",
            self.tip_threshold,
            "a value in [0, 1)",
        );
        c.check(
            (0.0..=16.0).contains(&self.min_width_pixels),
            "blades.min_width_pixels",
            self.min_width_pixels,
            "0 (off) to 16 pixels",
        );
    }
}

/// The most lamps a frame lights the grass with.
pub const MAX_LAMPS: usize = 8;

/// A light near the grass besides the sun (`FrameDesc::lamps`): a point light, or a spot light
/// where it has a cone. The Bevy plugin makes them of Bevy's point and spot lights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lamp {
    /// Where it is (world).
    pub position: Vec3,
    /// Its light on a surface one unit away that faces it, in the sun's units
    /// (`Shading::light_color`): it falls off with the square of the distance.
    pub color: Vec3,
    /// Where its light ends (units): it fades to nothing there.
    pub range: f32,
    /// A spot light's cone; `None`: it shines all round.
    pub spot: Option<Spot>,
}

/// A spot light's cone.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spot {
    /// Where it points (a unit vector).
    pub direction: Vec3,
    /// The cosine of the angle within which it shines fully.
    pub inner_cos: f32,
    /// The cosine of the angle beyond which it does not shine.
    pub outer_cos: f32,
}

impl Lamp {
    /// Its light where the eye at `eye` is: how much it can matter (frames keep the
    /// `MAX_LAMPS` that matter most).
    pub fn at_eye(&self, eye: Vec3) -> f32 {
        self.color.max_element() / self.position.distance_squared(eye).max(1e-4)
    }
}

/// The `MAX_LAMPS` of `lamps` that matter most to an eye at `eye` (`Lamp::at_eye`), brightest first.
pub fn nearest_lamps(lamps: &[Lamp], eye: Vec3) -> Vec<Lamp> {
    let mut kept = lamps.to_vec();
    kept.sort_by(|a, b| b.at_eye(eye).total_cmp(&a.at_eye(eye)));
    kept.truncate(MAX_LAMPS);
    kept
}
