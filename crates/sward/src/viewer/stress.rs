//! `view --stress SEED`: what a restless user does to a running viewer, one act per drawn frame
//! — resizing the window (to nothing, to one pixel, 16384 pixels wide, to ordinary sizes),
//! minimising and restoring it, and editing the panel (blade count, technique, draw route,
//! quality preset and with it the MSAA) — so a storm of them can run under the validation layer.
//! The storm runs twice, acts for acts the same; each time it ends with the scene and window as
//! they began and the GPU memory in use measured, so a leak shows as a second figure larger
//! than the first.

use sward_core::instanced::Technique;
use sward_core::quality::{DrawRoute, QualityPreset};
use sward_core::rng::Pcg32;

/// Frames at the end of each storm spent back at the start's scene and size, settling.
const SETTLE_FRAMES: u32 = 8;

/// Window sizes a user (or a window system) may ask for: nothing, a pixel, the widest a GPU
/// image may be, and ordinary ones.
const SIZES: [[u32; 2]; 8] = [
    [0, 0],
    [1, 1],
    [16384, 16],
    [16, 16384],
    [160, 120],
    [133, 91],
    [64, 48],
    [97, 141],
];

/// One thing the user does.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Act {
    Resize([u32; 2]),
    Minimise,
    Blades(u32),
    Technique(Technique),
    Route(DrawRoute),
    Quality(QualityPreset),
    /// Leave the scene as it is for a frame.
    Wait,
    /// Put the scene and window back as they were at the start.
    Settle,
    /// Settled: measure the GPU memory in use.
    Measure,
}

/// The storm's schedule over `frames` drawn frames.
pub struct Stress {
    seed: u64,
    rng: Pcg32,
    /// Drawn frames per storm (two storms in all).
    storm_frames: u32,
    /// Bezier blades the user may ask for at most (kept small: a CPU driver draws this).
    max_blades: u32,
    /// When each storm had settled: sward's GPU bytes in use and the allocator's allocations.
    pub measured: Vec<(u64, usize)>,
    pub resizes: u32,
    pub edits: u32,
}

impl Stress {
    pub fn new(seed: u64, frames: u32, max_blades: u32) -> Stress {
        Stress {
            seed,
            rng: Pcg32::new(seed, 7),
            storm_frames: (frames / 2).max(SETTLE_FRAMES + 2),
            max_blades: max_blades.max(1),
            measured: Vec::new(),
            resizes: 0,
            edits: 0,
        }
    }

    /// The act for drawn frame `frame`.
    pub fn act(&mut self, frame: u32) -> Act {
        let at = frame % self.storm_frames;
        if at == 0 {
            // Each storm the same acts.
            self.rng = Pcg32::new(self.seed, 7);
        }
        let left = self.storm_frames - at;
        if left == 1 {
            return Act::Measure;
        }
        if left <= SETTLE_FRAMES {
            return Act::Settle;
        }
        // Per thousand frames: 185 resizes, 30 minimises, 80 blade counts, 60 techniques, 80
        // routes, 10 quality presets (each builds a new renderer: seconds on a CPU driver), and
        // in the other frames the scene left as it is.
        let act = match self.rng.below(1000) {
            0..185 => Act::Resize(pick(&mut self.rng, &SIZES)),
            185..215 => Act::Minimise,
            215..295 => Act::Blades(self.rng.below(self.max_blades + 1)),
            295..355 => Act::Technique(pick(&mut self.rng, &Technique::ALL)),
            355..435 => Act::Route(pick(&mut self.rng, &DrawRoute::ALL)),
            435..445 => Act::Quality(pick(&mut self.rng, &QualityPreset::ALL)),
            _ => return Act::Wait,
        };
        match act {
            Act::Resize(_) | Act::Minimise => self.resizes += 1,
            _ => self.edits += 1,
        }
        act
    }

    /// The closing line: what the storms did and the memory each left in use.
    pub fn report(&self) -> String {
        let measured: Vec<String> = self
            .measured
            .iter()
            .map(|(bytes, allocations)| format!("{bytes} bytes in {allocations} allocations"))
            .collect();
        format!(
            "stress: {} resizes and minimises, {} panel edits; GPU memory in use after each storm: {}",
            self.resizes,
            self.edits,
            measured.join(", then ")
        )
    }
}

fn pick<T: Copy>(rng: &mut Pcg32, items: &[T]) -> T {
    items[rng.below(items.len() as u32) as usize]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_storms_act_alike_and_end_settled_then_measured() {
        let mut stress = Stress::new(3, 1000, 5000);
        let acts: Vec<Act> = (0..1000).map(|f| stress.act(f)).collect();
        assert_eq!(acts[..500], acts[500..]);
        assert_eq!(acts[499], Act::Measure);
        assert!(acts[492..499].iter().all(|a| *a == Act::Settle));
        let storm = &acts[..492];
        assert!(storm.iter().any(|a| matches!(a, Act::Resize([0, 0]))));
        assert!(storm.iter().any(|a| matches!(a, Act::Resize([16384, _]))));
        assert!(storm.iter().any(|a| matches!(a, Act::Minimise)));
        assert!(storm.iter().any(|a| matches!(a, Act::Quality(_))));
        assert!(stress.resizes >= 200, "{}", stress.resizes);
    }
}
