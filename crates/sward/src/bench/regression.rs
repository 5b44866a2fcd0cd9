//! The regression set (`sward bench --regression-set`): the named cases where sward's cost grows
//! with scale — the generated grass at the counts its presets ship, the landscape chain, the
//! prairie, the Bezier presets, the billboards, and the streamed open world walked, run and
//! flown — each at quality `high`, every culling test on. Run it before and after a change to a
//! hot path, on one device, and compare the two folders (`sward bench --compare OLD NEW`).

use crate::args::{Preset, TechniqueArg};

/// One case of the set.
#[derive(Clone, Copy, Debug)]
pub struct RegressionCase {
    /// What the comparison calls it.
    pub name: &'static str,
    pub preset: Preset,
    /// The technique, where not the preset's own.
    pub technique: Option<TechniqueArg>,
    /// Blades (a generated technique's candidates within its radius; the open world's budget).
    pub count: u32,
    /// The camera's speed along the scene's path, units per second.
    pub speed: f32,
}

const fn case(name: &'static str, preset: Preset, technique: Option<TechniqueArg>, count: u32) -> RegressionCase {
    RegressionCase {
        name,
        preset,
        technique,
        count,
        speed: 0.0,
    }
}

const fn open_world(name: &'static str, speed: f32) -> RegressionCase {
    RegressionCase {
        name,
        preset: Preset::Openworld,
        technique: None,
        count: 65536,
        speed,
    }
}

/// The set, in the order it runs.
pub const REGRESSION_SET: [RegressionCase; 12] = [
    case("instanced 2^26", Preset::Meadow, Some(TechniqueArg::Instanced), 1 << 26),
    case("instanced 2^24", Preset::Meadow, Some(TechniqueArg::Instanced), 1 << 24),
    case("landscape 2^20", Preset::Meadow, Some(TechniqueArg::Landscape), 1 << 20),
    case("prairie 2^24", Preset::Prairie, None, 1 << 24),
    case("cis565 2^20", Preset::Cis565, None, 1 << 20),
    case("cis565 2^24", Preset::Cis565, None, 1 << 24),
    case("meadow 2^20", Preset::Meadow, None, 1 << 20),
    case(
        "billboards 2^22",
        Preset::Meadow,
        Some(TechniqueArg::Billboard),
        1 << 22,
    ),
    case(
        "billboards 2^24",
        Preset::Meadow,
        Some(TechniqueArg::Billboard),
        1 << 24,
    ),
    open_world("open world walking", 1.5),
    open_world("open world running", 10.0),
    open_world("open world flying", 100.0),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_set_names_each_case_once_and_covers_the_scales_presets_ship() {
        for (k, c) in REGRESSION_SET.iter().enumerate() {
            assert!(
                REGRESSION_SET[..k].iter().all(|o| o.name != c.name),
                "{} named twice",
                c.name
            );
        }
        let generated = |t: TechniqueArg| REGRESSION_SET.iter().filter(move |c| c.technique == Some(t));
        assert!(generated(TechniqueArg::Instanced).any(|c| c.count == 1 << 26));
        assert!(REGRESSION_SET
            .iter()
            .any(|c| c.preset == Preset::Openworld && c.speed > 0.0));
    }
}
