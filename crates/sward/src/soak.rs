//! `sward soak`: a scene's simulation run for a long time on the GPU, its blades read back and
//! checked every so many steps — every number finite, every tip above its ground, every blade
//! as long as it is tall (state validation's length estimate within 1 %), every collision
//! strength finite and ≥ 0 — optionally at extreme parameters. The camera walks the scene's
//! camera path (a streamed field's window follows it, tiles made anew as it goes), and the GPU
//! memory in use must stay what it was after the first check. The first broken blade ends the
//! run in one sentence naming the step, the blade and what broke.

use anyhow::bail;
use sward_core::physics::estimated_length;
use sward_core::{Blade, Scene};
use sward_gpu::{Context, Headless};

use crate::args::{GpuArgs, SoakArgs};
use crate::render::check_validation;

/// How far a tip may sit below its ground plane, and a blade's length stray from its height, as
/// shares of its height (the GPU's float rounding; SPEC §3.6 restores both every step).
const BELOW_GROUND: f32 = 1e-4;
const LENGTH_ERROR: f32 = 0.01;

pub fn soak(args: &SoakArgs, gpu: &GpuArgs) -> anyhow::Result<()> {
    let mut scene = args.scene.load()?;
    if args.extreme {
        make_extreme(&mut scene);
        scene.validate("--extreme")?;
    }
    let ctx = Context::new(&gpu.context_desc())?;
    sward_gpu::renderer::check_field_fits(&ctx, scene.bezier_blades() as u64)?;
    let field = scene.grow_field()?;
    if field.blades.is_empty() {
        bail!(
            "{} grows no Bezier blades (its technique draws only generated grass): nothing to simulate; soak a scene whose technique is bezier, both or landscape",
            scene.name
        );
    }
    // No frame is drawn: a small target is enough.
    let mut headless = Headless::new(&ctx, 64, 64, None)?;
    headless.renderer.upload(&field)?;
    if let Some(speed) = args.speed {
        scene.camera_path.speed = speed;
    }
    let ground = field.ground.as_ref().and_then(|m| m.height_grid());
    let mut walked = scene.clone();
    let mut worst = Worst::default();
    let mut memory = None;
    let mut done = 0u64;
    while done < args.steps {
        let chunk = (args.steps - done).min(args.check_every as u64) as u32;
        // The camera moves every few steps, as a frame's would.
        let mut stepped = 0;
        while stepped < chunk {
            let steps = (chunk - stepped).min(WALK_STEPS);
            let t = (done + stepped as u64) as f32 * scene.simulation.step;
            walked.camera = scene.camera_path.camera_over(&scene.camera, t, ground.as_ref());
            headless.simulate(&walked, field.size, done + stepped as u64, steps)?;
            stepped += steps;
        }
        done += chunk as u64;
        let blades = headless.renderer.read_blades()?;
        let etas = headless.renderer.read_etas()?;
        let posed = posed_by_twins(&walked);
        if let Some(fault) = check(&blades, &etas, &mut worst, &|b| !posed(b)) {
            bail!("after {done} steps of {}, blade {fault}", scene.name);
        }
        let used = ctx.memory.used();
        if *memory.get_or_insert(used) != used {
            bail!(
                "after {done} steps of {}, the GPU memory in use grew from {} to {used} bytes",
                scene.name,
                memory.unwrap_or(0)
            );
        }
        log::info!("{done} steps: sound");
    }
    check_validation(&ctx)?;
    let eye = walked.camera.position;
    println!(
        "{} steps of {} ({} blades{}) on {}, checked every {}: every blade finite, above its ground and as long as it is tall — at least {} stepped free in each check, the rest in their instanced twins' pose — (tips moved up to {:.2} of their height from rest; worst length error {:.3} %, deepest tip {:.1e} of its height below ground); the camera walked {:.0} units to ({:.0}, {:.0}, {:.0}), GPU memory in use flat at {:.1} MiB",
        args.steps,
        scene.name,
        field.blades.len(),
        if args.extreme { ", extreme parameters" } else { "" },
        ctx.info.name,
        args.check_every,
        worst.fewest_stepped.unwrap_or(0),
        worst.moved,
        100.0 * worst.length_error,
        worst.below_ground,
        walked_distance(&scene, args.steps),
        eye.x,
        eye.y,
        eye.z,
        memory.unwrap_or(0) as f64 / (1 << 20) as f64,
    );
    Ok(())
}

/// Where the field streams, whether a blade is held in its instanced twin's pose rather than
/// stepped free: from where the blades ease into their twins on, and so longer than their
/// height as the twin's bent curve is (`twin.wesl` `ease_into_twin`).
fn posed_by_twins(scene: &Scene) -> impl Fn(&Blade) -> bool {
    let eye = scene.camera.position;
    let start = sward_core::frame::FrameStream::of_scene(scene).map_or(f32::INFINITY, |s| s.band_start());
    move |b: &Blade| b.root().distance(eye) > start
}

/// Steps between two moves of the walking camera.
const WALK_STEPS: u32 = 8;

/// How far the camera walks along the scene's path in `steps` steps.
fn walked_distance(scene: &Scene, steps: u64) -> f32 {
    match scene.camera_path.is_still() {
        true => 0.0,
        false => scene.camera_path.speed * steps as f32 * scene.simulation.step,
    }
}

/// The scene at the edges of what it allows: stiffness from nearly none to the most the step
/// integrates stably, every wind at strength 100, every collider rolling along the ground.
fn make_extreme(scene: &mut Scene) {
    let stiffest = 0.95 / scene.simulation.step;
    scene.field.stiffness = [0.05, stiffest];
    for wind in scene.wind.iter_mut() {
        wind.strength = 100.0;
    }
    for collider in &mut scene.colliders {
        collider.center.y = 0.0;
        for point in &mut collider.path {
            point.y = 0.0;
        }
    }
}

/// The worst a run has seen of what it checks (shares of a blade's height).
#[derive(Default, Debug)]
struct Worst {
    length_error: f32,
    below_ground: f32,
    /// How far a tip has moved from where it rests: that the run did bend the blades.
    moved: f32,
    /// The fewest blades one check held to their height (the rest in their twins' pose).
    fewest_stepped: Option<usize>,
}

/// The first blade of `blades` (with its collision strength in `etas`) that is broken, described
/// ("12 has a NaN or infinite point"); updates `worst` with the rest. Only blades physics
/// steps free (`stepped`) must be as long as they are tall.
fn check(blades: &[Blade], etas: &[f32], worst: &mut Worst, stepped: &dyn Fn(&Blade) -> bool) -> Option<String> {
    let mut held = 0;
    for (id, (b, &eta)) in blades.iter().zip(etas).enumerate() {
        let finite = [b.v0, b.v1, b.v2, b.up].iter().all(|v| v.is_finite());
        if !finite {
            return Some(format!("{id} has a NaN or infinite point: {b:?}"));
        }
        if !(eta.is_finite() && eta >= 0.0) {
            return Some(format!("{id} has collision strength {eta}, where it is finite and ≥ 0"));
        }
        let h = b.height();
        worst.moved = worst.moved.max(b.tip().distance(b.rest_tip()) / h);
        let below = -b.up().dot(b.tip() - b.root()) / h;
        worst.below_ground = worst.below_ground.max(below);
        if below > BELOW_GROUND {
            return Some(format!("{id} has its tip {:.3} of its height below its ground", below));
        }
        if !stepped(b) {
            continue;
        }
        held += 1;
        let error = (estimated_length(b.root(), b.guide(), b.tip()) - h).abs() / h;
        worst.length_error = worst.length_error.max(error);
        if error > LENGTH_ERROR {
            return Some(format!(
                "{id} is {:.1} % longer or shorter than its height",
                100.0 * error
            ));
        }
    }
    worst.fewest_stepped = Some(worst.fewest_stepped.map_or(held, |f| f.min(held)));
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec3, Vec4};

    fn upright() -> Blade {
        Blade::at_rest(Vec3::ZERO, Vec3::Y, 0.0, 1.0, 0.05, 10.0)
    }

    #[test]
    fn a_sound_field_passes_and_each_kind_of_break_is_named() {
        let mut worst = Worst::default();
        assert_eq!(check(&[upright(), upright()], &[0.0, 0.3], &mut worst, &|_| true), None);
        let mut nan = upright();
        nan.v2.x = f32::NAN;
        let found = check(&[upright(), nan], &[0.0, 0.0], &mut worst, &|_| true).unwrap();
        assert!(found.starts_with("1 has a NaN"), "{found}");
        let mut sunk = upright();
        sunk.v2 = Vec4::new(0.0, -0.5, 0.8, 0.05);
        assert!(check(&[sunk], &[0.0], &mut worst, &|_| true)
            .unwrap()
            .contains("below its ground"));
        let mut stretched = upright();
        stretched.v2.y = 1.5;
        stretched.v1.y = 1.5;
        assert!(check(&[stretched], &[0.0], &mut worst, &|_| true)
            .unwrap()
            .contains("longer or shorter"));
        // A blade held in its instanced twin's pose is not physics' to keep at its height.
        assert_eq!(check(&[stretched], &[0.0], &mut worst, &|_| false), None);
        assert!(check(&[upright()], &[f32::INFINITY], &mut worst, &|_| true)
            .unwrap()
            .contains("collision strength"));
    }
}
