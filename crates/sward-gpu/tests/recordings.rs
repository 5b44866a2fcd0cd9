//! The kept-recording key, on a real device: frames that differ only in what the shaders read
//! from the frame's uniforms (the camera, the time, the winds, the colliders' places) replay
//! the recording of the frame before; frames that differ in what shapes the commands (the
//! technique, the route, the quality, the counts, the target's size) are recorded anew.

mod common;

use glam::{Vec2, Vec3};
use sward_core::instanced::Technique;
use sward_core::quality::{DrawRoute, QualityPreset};
use sward_core::{Collider, FrameDesc, Scene};
use sward_gpu::headless::HEADLESS_FORMAT;
use sward_gpu::target::OffscreenTarget;
use sward_gpu::{Context, Passes, Renderer};

use common::{assert_validation_clean, context, renderer};

const FIELD: Vec2 = Vec2::splat(12.0);

/// A small landscape (Bezier blades, the instanced grass and billboards) with two balls.
fn scene() -> Scene {
    let mut scene = Scene {
        technique: Technique::Landscape,
        colliders: vec![
            Collider::sphere(Vec3::new(1.0, 0.3, 0.0), 0.4),
            Collider::sphere(Vec3::new(-1.0, 0.3, 1.0), 0.4),
        ],
        ..Scene::default()
    };
    scene.field.blades = 2000;
    scene.field.size = FIELD;
    scene.instanced.grid.density = 200.0;
    scene.instanced.grid.radius = 30.0;
    scene.billboard.grid.radius = 60.0;
    scene.quality.route = DrawRoute::Compute;
    scene
}

/// A renderer with `scene`'s field, and targets of two sizes.
struct Frames {
    renderer: Renderer,
    targets: [OffscreenTarget; 2],
    ctx: std::sync::Arc<Context>,
}

impl Frames {
    fn new(scene: &Scene) -> Frames {
        let ctx = context();
        let mut renderer = renderer(&ctx, 0, true);
        let field = scene.grow_field().unwrap();
        renderer.upload(&field).unwrap();
        let target = |w, h| OffscreenTarget::new(&ctx, w, h, HEADLESS_FORMAT).unwrap();
        Frames {
            renderer,
            targets: [target(160, 120), target(200, 120)],
            ctx,
        }
    }

    /// Draw `desc` into target `which` (its size is the description's viewport); whether the
    /// frame was recorded anew (not replayed).
    fn recorded(&mut self, desc: &FrameDesc, which: usize) -> bool {
        let before = self.renderer.frames_recorded();
        let target = &self.targets[which];
        let extent = target.extent;
        assert_eq!(desc.viewport, [extent.width, extent.height]);
        let renderer = &mut self.renderer;
        let d = &self.ctx.device;
        self.ctx
            .submit_and_wait("a frame", |cmd| {
                target.begin(d, cmd);
                renderer.record_frame(cmd, 0, desc, Passes::ALL, Some(&target.views()), None);
                target.finish(d, cmd);
            })
            .unwrap();
        self.renderer.frames_recorded() > before
    }
}

fn frame(scene: &Scene, time: f32) -> FrameDesc {
    FrameDesc::of_scene(scene, FIELD, (time, 1), [160, 120])
}

#[test]
fn frames_differing_only_in_what_shaders_read_replay_and_the_rest_record_anew() {
    let base = scene();
    let mut frames = Frames::new(&base);
    // The first frames record: new splat cells and trample map are cleared whole once.
    for k in 0..3 {
        frames.recorded(&frame(&base, k as f32 * 0.1), 0);
    }
    assert!(
        !frames.recorded(&frame(&base, 0.3), 0),
        "the same frame a step later replays"
    );

    // What only the shaders read: the camera, the time, the winds, the colliders' places.
    let mut moved = base.clone();
    moved.camera.position += Vec3::new(0.7, 0.2, -0.4);
    moved.camera.target += Vec3::new(0.3, 0.0, 0.1);
    moved.wind.0[0].strength *= 2.0;
    moved.wind.0[0].direction = Vec3::new(0.3, 0.0, 1.0);
    for c in &mut moved.colliders {
        c.center += Vec3::new(0.5, 0.0, 0.25);
    }
    let replayed = frame(&moved, 7.5);
    assert!(
        !frames.recorded(&replayed, 0),
        "camera, time, wind and colliders moved: replayed"
    );
    let mut own_eye = replayed.clone();
    own_eye.camera.eye += Vec3::new(0.0, 0.1, 0.0);
    own_eye.time += 1.0;
    assert!(
        !frames.recorded(&own_eye, 0),
        "a description changed in place: replayed"
    );

    // What shapes the commands, each recorded anew and then replayed.
    let mut changes: Vec<(&str, FrameDesc, usize)> = Vec::new();
    let mut technique = base.clone();
    technique.technique = Technique::Both;
    changes.push(("technique", frame(&technique, 0.0), 0));
    let mut route = base.clone();
    route.quality.route = DrawRoute::Tessellation;
    changes.push(("route", frame(&route, 0.0), 0));
    let mut quality = base.clone();
    quality.quality.preset = QualityPreset::Ultra;
    changes.push(("quality", frame(&quality, 0.0), 0));
    let mut colliders = base.clone();
    colliders
        .colliders
        .push(Collider::sphere(Vec3::new(0.0, 0.3, -2.0), 0.4));
    changes.push(("collider count", frame(&colliders, 0.0), 0));
    let mut density = base.clone();
    density.instanced.grid.density *= 2.0;
    changes.push(("instanced density", frame(&density, 0.0), 0));
    let mut steps = frame(&base, 0.0);
    steps.steps = 0;
    changes.push(("no physics step", steps, 0));
    let resized = FrameDesc::of_scene(&base, FIELD, (0.0, 1), [200, 120]);
    changes.push(("resolution", resized, 1));
    for (what, desc, target) in &changes {
        // A kept recording of the base frame must not be taken for it, nor it for the next.
        frames.recorded(&frame(&base, 0.0), 0);
        assert!(frames.recorded(desc, *target), "{what} changed: recorded anew");
    }
    let Frames { renderer, ctx, .. } = frames;
    drop(renderer);
    assert_validation_clean(&ctx);
}
