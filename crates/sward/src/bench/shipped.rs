//! The shipped set (`sward bench --shipped`): every scene in `scenes/` as it ships — its own
//! blades, technique, camera and paint — and the meadow drawn by each technique, every culling
//! test on; and its table of what to expect (`expect.md`): frame time median and p99, visible
//! blades, the host's frame and the GPU memory sward holds, one row per scene.

use std::fmt::Write as _;

use crate::args::{Preset, TechniqueArg};

use super::report::{quantile, Case};
use super::RunInfo;

/// One row of the set: a shipped scene, and the technique it is drawn with where not its own.
#[derive(Clone, Copy, Debug)]
pub struct ShippedCase {
    pub preset: Preset,
    pub technique: Option<TechniqueArg>,
    /// The camera's speed along the scene's path (the open world is walked), units per second.
    pub speed: f32,
}

const fn as_shipped(preset: Preset) -> ShippedCase {
    ShippedCase {
        preset,
        technique: None,
        speed: 0.0,
    }
}

const fn meadow_as(technique: TechniqueArg) -> ShippedCase {
    ShippedCase {
        preset: Preset::Meadow,
        technique: Some(technique),
        speed: 0.0,
    }
}

/// The set, in the order it runs: the scenes, then the meadow by the other techniques.
pub const SHIPPED_SET: [ShippedCase; 14] = [
    as_shipped(Preset::Meadow),
    as_shipped(Preset::Hills),
    as_shipped(Preset::Trample),
    as_shipped(Preset::Planet),
    as_shipped(Preset::Prairie),
    as_shipped(Preset::Landscape),
    as_shipped(Preset::Trail),
    as_shipped(Preset::Park),
    as_shipped(Preset::Openworld),
    ShippedCase {
        speed: 1.5,
        ..as_shipped(Preset::Openworld)
    },
    meadow_as(TechniqueArg::Instanced),
    meadow_as(TechniqueArg::Both),
    meadow_as(TechniqueArg::Billboard),
    meadow_as(TechniqueArg::Landscape),
];

impl ShippedCase {
    /// What the table calls it: the scene, with the technique where it is not the scene's own.
    pub fn label(&self) -> String {
        match self.technique {
            Some(t) => format!(
                "{} · {}",
                self.preset.name(),
                sward_core::instanced::Technique::from(t).name()
            ),
            None => self.preset.name().to_string(),
        }
    }

    /// The scene as it ships (its own blades and density), drawn by this case's technique.
    pub fn scene(&self) -> sward_core::Scene {
        let blades = crate::scenes::load(self.preset.name())
            .map(|s| s.field.blades)
            .unwrap_or_else(|e| panic!("the shipped {} is valid: {e}", self.preset.name()));
        let mut scene = self.preset.scene(blades);
        if let Some(technique) = self.technique {
            scene.technique = technique.into();
        }
        scene
    }
}

/// The table of what to expect: one row per case of the run, headed by the device, driver,
/// resolution, commit and the command that made it; below it, the scenes that did not fit.
pub fn expect_table(info: &RunInfo, cases: &[Case], stopped: &[String]) -> String {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "{} — driver {} — {}×{}, {}× MSAA — commit {}\n",
        info.device,
        info.driver,
        info.resolution[0],
        info.resolution[1],
        cases.first().map_or(1, |c| c.msaa),
        info.commit
    );
    let _ = writeln!(md, "`{}`\n", info.command);
    let _ = writeln!(
        md,
        "| scene | field.blades | visible blades | GPU frame median ms | GPU frame p99 ms | CPU frame median ms | GPU memory MiB |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|");
    for c in cases {
        let gpu = c.series(|s| s.gpu.frame());
        let name = c.label.clone().unwrap_or_else(|| c.preset.to_string());
        let moving = if c.speed > 0.0 {
            format!(", moving {} m/s", c.speed)
        } else {
            String::new()
        };
        let _ = writeln!(
            md,
            "| {name}{moving} | {} | {:.0} | {:.2} | {:.2} | {:.3} | {:.0} |",
            c.blades,
            c.visible(),
            quantile(&gpu, 0.5),
            quantile(&gpu, 0.99),
            c.median(|s| s.cpu_ms),
            c.memory_mib
        );
    }
    for line in stopped {
        let _ = writeln!(md, "\n- {line}");
    }
    md
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_shipped_scene_is_in_the_set_and_the_meadow_by_every_technique() {
        for (name, _) in crate::scenes::SHIPPED {
            assert!(
                SHIPPED_SET
                    .iter()
                    .any(|c| c.preset.name() == *name && c.technique.is_none()),
                "{name} is shipped but not in the set"
            );
        }
        for t in [
            TechniqueArg::Instanced,
            TechniqueArg::Both,
            TechniqueArg::Billboard,
            TechniqueArg::Landscape,
        ] {
            assert!(SHIPPED_SET.iter().any(|c| c.technique == Some(t)), "{t:?}");
        }
    }

    #[test]
    fn a_shipped_case_keeps_the_scene_s_own_blades_and_density() {
        let meadow = crate::scenes::load("meadow").unwrap();
        let as_instanced = meadow_as(TechniqueArg::Instanced).scene();
        assert_eq!(as_instanced.field.blades, meadow.field.blades);
        assert_eq!(as_instanced.instanced.grid.density, meadow.instanced.grid.density);
        assert_eq!(as_instanced.technique, sward_core::instanced::Technique::Instanced);
        let prairie = as_shipped(Preset::Prairie).scene();
        assert_eq!(prairie.field.blades, 1 << 24);
    }
}
