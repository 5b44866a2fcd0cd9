//! The grass's quality tier, for a game's settings menu ([`GrassQuality`]): one resource that
//! thins, shortens and simplifies every field's grass at run time, from the scenes as they were
//! authored (`High`) and without changing them.

use bevy::ecs::prelude::*;
use bevy::prelude::ReflectDefault;
use sward_core::quality::QualityPreset;
use sward_core::{Scene, SceneError};

/// How much grass every field draws, switched at run time (a settings menu's "grass quality"):
/// `High` draws each scene as authored; the others scale from it. The Bezier blades near the
/// eye keep their reach (the hand-over) and budget ([`GrassBudget`](crate::GrassBudget) sets
/// that); a streamed field's Bezier blades are made from the generated grass's grid, so they
/// thin with it.
///
/// | tier | blades a m² | reach past the hand-over | far grass shadows | blade segments | far field under 4× MSAA |
/// |---|---|---|---|---|---|
/// | `Low` | ½ | ½ | none | low | a cell a pixel |
/// | `Medium` | ¾ | ¾ | ½ the distance | medium | a cell a pixel |
/// | `High` | as authored | as authored | as set | as authored | a cell a sample |
/// | `Ultra` | as authored | 1½ | twice the distance | as authored | a cell a sample |
/// | `HighRefresh` | ½ | 0.6 | none | low | a cell a pixel |
///
/// A cell a pixel under MSAA splats the far field at the pixel's resolution (its compute 0.9 ms
/// shorter than a cell a sample on the H100 at 1920×1080, docs/benchmarks-history.md) and shows it a little
/// darker and grainier near the horizon.
/// Changing the tier grows the fields again where their Bezier blades thin.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Eq, Hash, bevy::reflect::Reflect)]
#[reflect(Resource, Default, Debug, PartialEq, Hash)]
pub enum GrassQuality {
    /// Half the blades to half the distance, no far grass shadows.
    Low,
    /// Three quarters of the blades to three quarters of the distance.
    Medium,
    /// Each scene as authored.
    #[default]
    High,
    /// Grass half as far again, casting twice as far.
    Ultra,
    /// For games at 144 Hz and more: `Low`'s thinning to a little further, no far grass
    /// shadows.
    HighRefresh,
}

/// What a tier scales.
struct Tier {
    density: f32,
    reach: f32,
    shadows: f32,
    segments: Option<QualityPreset>,
    pixel_cells: bool,
}

impl GrassQuality {
    /// Every tier, lowest first.
    pub const ALL: [GrassQuality; 5] = [
        GrassQuality::HighRefresh,
        GrassQuality::Low,
        GrassQuality::Medium,
        GrassQuality::High,
        GrassQuality::Ultra,
    ];

    fn tier(self) -> Tier {
        let tier = |density, reach, shadows, segments, pixel_cells| Tier {
            density,
            reach,
            shadows,
            segments,
            pixel_cells,
        };
        match self {
            GrassQuality::Low => tier(0.5, 0.5, 0.0, Some(QualityPreset::Low), true),
            GrassQuality::Medium => tier(0.75, 0.75, 0.5, Some(QualityPreset::Medium), true),
            GrassQuality::High => tier(1.0, 1.0, 1.0, None, false),
            GrassQuality::Ultra => tier(1.0, 1.5, 2.0, None, false),
            GrassQuality::HighRefresh => tier(0.5, 0.6, 0.0, Some(QualityPreset::Low), true),
        }
    }

    /// `scene` (as authored) at this tier: its generated grass and billboards thinned, every
    /// distance past the Bezier blades' hand-over brought nearer (or further) to it, its blade
    /// segments; or why that scene fails its checks.
    pub fn applied(self, scene: &Scene) -> Result<Scene, SceneError> {
        if self == GrassQuality::High {
            return Ok(scene.clone());
        }
        let tier = self.tier();
        let mut scene = scene.clone();
        let hand_over = scene.hand_over();
        // A distance at or past the largest a scene holds stays there ("never", as a raster
        // distance's default says).
        let far = |d: &mut f32| {
            if *d > hand_over {
                *d = (hand_over + (*d - hand_over) * tier.reach).min((sward_core::MAX_MAGNITUDE as f32).max(*d));
            }
        };
        let instanced = &mut scene.instanced;
        instanced.grid.density *= tier.density;
        far(&mut instanced.grid.radius);
        instanced.lod_distances.iter_mut().for_each(far);
        far(&mut instanced.splat_distance);
        far(&mut instanced.raster_distance);
        let billboard = &mut scene.billboard;
        billboard.grid.density *= tier.density;
        far(&mut billboard.grid.inner_radius);
        far(&mut billboard.grid.radius);
        billboard.fade *= tier.reach;
        far(&mut billboard.one_quad_distance);
        far(&mut billboard.splat_distance);
        far(&mut billboard.raster_distance);
        if let Some(segments) = tier.segments {
            scene.quality.preset = segments;
        }
        scene.validate(&format!("GrassQuality::{self:?}"))?;
        Ok(scene)
    }

    /// A field's far grass shadow distance at this tier.
    pub fn shadow_distance(self, distance: f32) -> f32 {
        distance * self.tier().shadows
    }

    /// Whether the far field is splatted a cell a pixel under MSAA (else a cell a sample).
    pub fn pixel_cells(self) -> bool {
        self.tier().pixel_cells
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::GrassPreset;

    /// Every shipped preset and scene file passes its checks at every tier, the lower tiers
    /// drawing fewer blades to a shorter reach and `Ultra` further.
    #[test]
    #[allow(clippy::disallowed_methods)] // It reads the shipped scene files, natively.
    fn every_preset_at_every_tier_is_valid_and_scales_its_grass() {
        let mut scenes: Vec<(String, Scene)> = GrassPreset::ALL.iter().map(|p| (format!("{p:?}"), p.scene())).collect();
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes");
        for entry in std::fs::read_dir(dir).expect("the scenes folder") {
            let path = entry.expect("a scene file").path();
            if path.extension().is_some_and(|e| e == "toml") {
                // Read here: the plugin itself reads no file (a scene's own checks read none).
                let text = std::fs::read_to_string(&path).expect("a shipped scene file");
                let scene = Scene::from_toml_in(&text, &path.display().to_string(), path.parent())
                    .expect("a shipped scene loads");
                scenes.push((path.display().to_string(), scene));
            }
        }
        assert!(scenes.len() > 20, "{} scenes", scenes.len());
        for (name, scene) in &scenes {
            for tier in GrassQuality::ALL {
                let applied = tier
                    .applied(scene)
                    .unwrap_or_else(|e| panic!("{name} at {tier:?}: {e}"));
                let [a, b] = [scene, &applied].map(|s| (s.instanced.grid.density, s.billboard.grid.radius));
                match tier {
                    GrassQuality::High => assert_eq!(&applied, scene),
                    GrassQuality::Ultra => assert!(b.0 == a.0 && b.1 >= a.1, "{name} {tier:?}: {a:?} → {b:?}"),
                    _ => assert!(b.0 < a.0 && b.1 <= a.1, "{name} {tier:?}: {a:?} → {b:?}"),
                }
                assert_eq!(applied.hand_over(), scene.hand_over(), "{name} {tier:?}");
            }
        }
        assert_eq!(GrassQuality::Low.shadow_distance(40.0), 0.0);
        assert_eq!(GrassQuality::Ultra.shadow_distance(40.0), 80.0);
        assert!(GrassQuality::HighRefresh.pixel_cells() && !GrassQuality::High.pixel_cells());
    }
}
