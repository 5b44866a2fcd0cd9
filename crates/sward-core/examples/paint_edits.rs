//! What a game's edits cost as they pile up: a meadow's scene painted with 1, 1,000 and 100,000
//! strokes as a game paints them (merged into the paint every `MERGE_AFTER`), against the same
//! strokes kept as a list (a scene file's `[[paint.stroke]]`). For each: the strokes the scene
//! holds, the time to clone and compare it (what a renderer and the sampler do when it changes)
//! and to make its paint again (what a renderer does when it grows the field anew); and what a
//! merge costs.
//!
//! `cargo run --release -p sward-core --example paint_edits`

use std::time::Instant;

use glam::Vec2;
use sward_core::paint::Stroke;
use sward_core::paint_edits::MERGE_AFTER;
use sward_core::Scene;

/// The `k`th stroke of a game mowing a lawn row by row over the paint area.
fn stroke(k: usize) -> Stroke {
    let at = Vec2::new((k % 200) as f32 * 0.3 - 30.0, (k / 200 % 200) as f32 * 0.3 - 30.0);
    Stroke::circle(at, 0.8).mow(0.3)
}

/// The median of `runs` timings of `f`, in milliseconds.
fn median_ms(runs: usize, mut f: impl FnMut()) -> f64 {
    let mut times: Vec<f64> = (0..runs)
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[runs / 2]
}

fn report(how: &str, count: usize, scene: &Scene) {
    let held = scene.paint.strokes.len() + scene.edits.pending().len();
    let clone = median_ms(51, || {
        let copy = scene.clone();
        assert!(copy == *scene);
    });
    let paint = median_ms(5, || {
        scene.paint_map().expect("the paint is made");
    });
    println!(
        "{how:>7} {count:>7} strokes: {held:>6} held, clone + compare {clone:>8.3} ms, paint made {paint:>8.2} ms"
    );
}

fn main() {
    println!(
        "a {}-unit paint area at 4 texels a unit; merged every {MERGE_AFTER}",
        64
    );
    for count in [1, 1000, 100_000] {
        let mut merged = Scene::default();
        for k in 0..count {
            // As the Bevy plugin does at each frame's start: merge once enough wait.
            if merged.edits.wants_merging() {
                merged.merge_edits().expect("a default scene's paint merges");
            }
            merged.edits.paint(stroke(k));
        }
        report("merged", count, &merged);
        if count == 100_000 {
            // What the plugin does every 32 strokes: the waiting ones painted into a copy of
            // the merged map (a frame's start; the renderers keep the one they hold).
            let mut waiting = merged.clone();
            (0..MERGE_AFTER).for_each(|k| waiting.edits.paint(stroke(k)));
            let merge = median_ms(11, || waiting.clone().merge_edits().expect("it merges"));
            println!("  a merge of {MERGE_AFTER} strokes over the merged map: {merge:.2} ms");
        }
        if count <= 1000 {
            let mut listed = Scene::default();
            listed.paint.strokes.extend((0..count).map(stroke));
            report("listed", count, &listed);
        }
    }
}
