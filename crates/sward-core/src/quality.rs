//! Quality presets: how much work the renderer spends per pixel and per blade, chosen by the user
//! (`--quality`, the scene file's `[quality]` table, the viewer's panel). `high` is the reference
//! picture; lower presets trade samples, shadow detail and blade segments for speed.

use serde::{Deserialize, Serialize};

/// One of the four presets.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(rename_all = "snake_case")]
pub enum QualityPreset {
    /// One sample per pixel, fewer blade segments, a small shadow map.
    Low,
    /// Two samples per pixel.
    Medium,
    /// Four samples per pixel: the reference picture.
    #[default]
    High,
    /// Eight samples per pixel, a large shadow map, blades casting shadows.
    Ultra,
}

/// How the Bezier blades reach the screen (SPEC §10); the picture is the same on every route,
/// only its cost differs. sward-gpu resolves `Auto` per device and refuses a route the device
/// lacks (mesh shaders).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(rename_all = "snake_case")]
pub enum DrawRoute {
    /// The fastest route the device has.
    #[default]
    Auto,
    /// One tessellated patch per blade: the paper's route and the reference picture.
    Tessellation,
    /// One vertex-pulled triangle strip per blade, its length from its distance bucket.
    Strips,
    /// Strips up to `lod.splat_distance`, splatted by compute beyond it; with
    /// `lod.compute_raster`, blades from `lod.strip_distance` on rasterized by compute.
    Compute,
    /// Mesh shaders (VK_EXT_mesh_shader), two blades per workgroup; not on every device.
    Mesh,
}

impl DrawRoute {
    /// Every route a user may ask for.
    pub const ALL: [DrawRoute; 5] = [Self::Auto, Self::Tessellation, Self::Strips, Self::Compute, Self::Mesh];

    /// The route's name as the scene file, the command line and the tables spell it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::Tessellation => "tessellation",
            Self::Strips => "strips",
            Self::Compute => "compute",
            Self::Mesh => "mesh",
        }
    }
}

/// The scene file's `[quality]` table.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(default, deny_unknown_fields)]
pub struct Quality {
    /// The quality preset.
    pub preset: QualityPreset,
    /// The Bezier blades' draw route.
    pub route: DrawRoute,
}

impl QualityPreset {
    /// Every preset, lowest first.
    pub const ALL: [QualityPreset; 4] = [Self::Low, Self::Medium, Self::High, Self::Ultra];

    /// The preset's name as the scene file and the command line spell it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Low => "low",
            Self::Medium => "medium",
            Self::High => "high",
            Self::Ultra => "ultra",
        }
    }

    /// Samples per pixel (MSAA); a device that lacks them renders with the most it has below.
    pub fn msaa_samples(self) -> u32 {
        match self {
            Self::Low => 1,
            Self::Medium => 2,
            Self::High => 4,
            Self::Ultra => 8,
        }
    }

    /// Side of the sun's shadow map in texels.
    pub fn shadow_map_size(self) -> u32 {
        match self {
            Self::Low => 1024,
            Self::Medium | Self::High => 2048,
            Self::Ultra => 4096,
        }
    }

    /// Whether blades cast shadows (into the sun's near cascade, `shading.blade_shadow_distance`
    /// around the eye). Only `ultra`: measured on the H100 (docs/benchmarks-history.md, "Blade shadows") they
    /// cost more than the tenth of a `high` frame they may take there.
    pub fn blade_shadows(self) -> bool {
        self == Self::Ultra
    }

    /// Factor on the scene's level-of-detail levels (segments along a blade's height).
    pub fn segment_scale(self) -> f32 {
        match self {
            Self::Low => 0.5,
            Self::Medium => 0.75,
            Self::High => 1.0,
            Self::Ultra => 1.5,
        }
    }

    /// Factor on the scene's level-of-detail distances: below 1, blades coarsen nearer the eye.
    pub fn lod_distance_scale(self) -> f32 {
        match self {
            Self::Low => 0.5,
            Self::Medium => 0.75,
            Self::High | Self::Ultra => 1.0,
        }
    }

    /// The scene's levels of detail as this preset draws them. Levels stay at least 1 (and the
    /// tessellator's even spacing draws at least 2 segments), distances keep their order.
    pub fn apply_to_lod(self, lod: &crate::cull::LodParams) -> crate::cull::LodParams {
        let levels = self.segment_scale();
        let distances = self.lod_distance_scale();
        crate::cull::LodParams {
            min_level: (lod.min_level * levels).max(1.0),
            max_level: (lod.max_level * levels).max(1.0),
            near: lod.near * distances,
            far: lod.far * distances,
            splat_distance: lod.splat_distance,
            compute_raster: lod.compute_raster,
            strip_distance: lod.strip_distance,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cull::LodParams;

    #[test]
    fn high_is_the_scene_as_written() {
        let lod = LodParams::default();
        assert_eq!(QualityPreset::High.apply_to_lod(&lod), lod);
        assert_eq!(QualityPreset::default(), QualityPreset::High);
    }

    #[test]
    fn presets_order_their_cost() {
        let lod = LodParams::default();
        let levels: Vec<f32> = QualityPreset::ALL
            .iter()
            .map(|q| q.apply_to_lod(&lod).max_level)
            .collect();
        assert!(levels.windows(2).all(|w| w[0] < w[1]), "{levels:?}");
        let samples: Vec<u32> = QualityPreset::ALL.iter().map(|q| q.msaa_samples()).collect();
        assert!(samples.windows(2).all(|w| w[0] < w[1]), "{samples:?}");
        let low = QualityPreset::Low.apply_to_lod(&lod);
        assert!(low.min_level >= 1.0 && low.near < low.far);
    }
}
