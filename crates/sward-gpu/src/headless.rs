//! Headless rendering: a renderer and an offscreen target, one call per image.

use std::sync::Arc;

use ash::vk;
use sward_core::{FrameDesc, Scene};

use crate::buffer::Buffer;
use crate::context::{Context, FrameCommands};
use crate::error::{GpuError, Result};
use crate::pipelines::{ComputeOptions, TargetFormat};
use crate::renderer::{Passes, Renderer, RendererDesc};
use crate::target::{OffscreenTarget, OFFSCREEN_FORMAT};
use crate::timer::{DrawCounter, GpuTimer, Stamp};

/// Most fixed steps one GPU submission simulates, so a long warm-up is not one huge dispatch.
const STEPS_PER_SUBMIT: u32 = 120;
/// Steps per submission where colliders trample the generated grass: a ball rolling at 3 units
/// a second moves 0.2 units between stamps, so its trail is one band, not a row of discs.
const STEPS_PER_TRAMPLE: u32 = 8;

/// 4× MSAA, as the images sward writes use.
pub const HEADLESS_FORMAT: TargetFormat = TargetFormat {
    color: OFFSCREEN_FORMAT,
    depth: crate::pipelines::DEPTH_FORMAT,
    samples: vk::SampleCountFlags::TYPE_4,
    depth_direction: crate::pipelines::DepthDirection::Forward,
};

/// A renderer and an offscreen target of one size: frames drawn and read back.
pub struct Headless {
    /// The renderer: upload a field and ground to it, set its route.
    pub renderer: Renderer,
    /// The image the frames are drawn into.
    pub target: OffscreenTarget,
    commands: FrameCommands,
    ctx: Arc<Context>,
}

impl Headless {
    /// `patches_per_draw` as in [`RendererDesc`]: `None` picks per driver.
    pub fn new(ctx: &Arc<Context>, width: u32, height: u32, patches_per_draw: Option<u32>) -> Result<Headless> {
        let desc = RendererDesc {
            target: HEADLESS_FORMAT,
            frames_in_flight: 1,
            patches_per_draw,
            compute: ComputeOptions::default(),
            fused: true,
            shadow_map_size: crate::passes::shadows::SHADOW_SIZE,
        };
        Self::with_desc(ctx, width, height, &desc)
    }

    /// As [`Headless::new`] with every renderer option given (the bench varies them); the target's
    /// colour format is always the offscreen one, its depth format and sample count
    /// `desc.target`'s.
    pub fn with_desc(ctx: &Arc<Context>, width: u32, height: u32, desc: &RendererDesc) -> Result<Headless> {
        let format = TargetFormat {
            color: OFFSCREEN_FORMAT,
            ..desc.target
        };
        let renderer = Renderer::new(
            ctx,
            &RendererDesc {
                target: format,
                ..*desc
            },
        )?;
        check_image_fits(ctx, width, height, format.samples)?;
        let target = OffscreenTarget::new(ctx, width, height, format)?;
        let mut renderer = renderer;
        renderer.reserve_splats(width, height)?;
        Ok(Headless {
            renderer,
            target,
            commands: FrameCommands::new(ctx)?,
            ctx: ctx.clone(),
        })
    }

    /// Run the frame `desc` describes (whatever `passes` says) and return the image as RGBA8,
    /// top row first.
    pub fn render(&mut self, desc: &FrameDesc, passes: Passes) -> Result<Vec<u8>> {
        let ctx = self.ctx.clone();
        let d = &ctx.device;
        self.commands.submit_and_wait("rendering a frame", |cmd| {
            self.target.begin(d, cmd);
            let views = self.target.views();
            self.renderer
                .record_frame(cmd, 0, desc, Passes { draw: true, ..passes }, Some(&views), None);
            self.target.finish(d, cmd);
        })?;
        Ok(self.target.pixels())
    }

    /// Simulate `steps` fixed steps of `scene` from the uploaded field's current state, then cull
    /// and draw one frame: what `sward render` writes.
    pub fn render_scene(&mut self, scene: &Scene, field_size: glam::Vec2, steps: u32) -> Result<Vec<u8>> {
        self.render_after(scene, field_size, 0, steps)
    }

    /// Simulate `steps` fixed steps of `scene` from step `first` on (its time), then cull and
    /// draw one frame at the time they reach: one frame of an animation. A cull before it
    /// leaves the nearest blades as the frame's occluders (`cull.blade_occluders`), as the
    /// frame before it would in the viewer.
    pub fn render_after(&mut self, scene: &Scene, field_size: glam::Vec2, first: u64, steps: u32) -> Result<Vec<u8>> {
        self.simulate(scene, field_size, first, steps)?;
        let time = (first + steps as u64) as f32 * scene.simulation.step;
        let desc = self.frame(scene, field_size, (time, 0));
        if scene.cull.occlusion && scene.cull.blade_occluders.any() {
            self.renderer.run_compute(&desc, Passes::CULL)?;
        }
        self.render(
            &desc,
            Passes {
                simulate: false,
                cull: true,
                draw: true,
            },
        )
    }

    /// A frame of `scene` over a field `field_size` wide, at simulated time `clock.0` running
    /// `clock.1` steps, on this target.
    pub fn frame(&self, scene: &Scene, field_size: glam::Vec2, clock: (f32, u32)) -> FrameDesc {
        let viewport = [self.target.extent.width, self.target.extent.height];
        FrameDesc::of_scene(scene, field_size, clock, viewport)
    }

    /// Simulate `steps` fixed steps of `scene` from step `first` on (its time), in submissions of
    /// at most `STEPS_PER_SUBMIT` (`STEPS_PER_TRAMPLE` where colliders trample generated grass:
    /// a submission stamps them once, where its first step finds them), and wait for them.
    pub fn simulate(&mut self, scene: &Scene, field_size: glam::Vec2, first: u64, steps: u32) -> Result<()> {
        let trampling = scene.tramples() && !scene.colliders_at(0.0).is_empty();
        let per_submit = if trampling { STEPS_PER_TRAMPLE } else { STEPS_PER_SUBMIT };
        let mut done = 0;
        while done < steps {
            let chunk = (steps - done).min(per_submit);
            let time = (first + done as u64) as f32 * scene.simulation.step;
            let desc = self.frame(scene, field_size, (time, chunk));
            self.renderer.run_compute(&desc, Passes::SIMULATE)?;
            done += chunk;
        }
        Ok(())
    }

    /// One fully timed frame for benchmarks: every pass between timestamps, the visible count
    /// copied to `visible_count`, no image read-back. Returns the host's time from beginning the
    /// command buffer until its submission returned (recording, or replaying the kept passes,
    /// and submitting).
    pub fn timed_frame(
        &mut self,
        desc: &FrameDesc,
        timer: &mut GpuTimer,
        mut counter: Option<&mut DrawCounter>,
        visible_count: &Buffer,
    ) -> Result<std::time::Duration> {
        let ctx = self.ctx.clone();
        let d = &ctx.device;
        // The fragments are counted by a query open around the frame, which a replayed frame
        // may run inside only where the device has inheritedQueries.
        let keep = self.renderer.keep_recordings;
        self.renderer.keep_recordings &= counter.is_none() || ctx.info.inherited_queries;
        let submitted = self.commands.submit_and_wait("a timed frame", |cmd| {
            timer.begin(cmd);
            if let Some(counter) = counter.as_deref_mut() {
                counter.begin(cmd);
            }
            self.target.begin(d, cmd);
            let views = self.target.views();
            self.renderer
                .record_frame(cmd, 0, desc, Passes::ALL, Some(&views), Some(timer));
            if let Some(counter) = counter.as_deref() {
                counter.end(cmd);
            }
            self.renderer.record_copy_visible_count(cmd, visible_count);
            timer.stamp(cmd, Stamp::Ui);
        });
        self.renderer.keep_recordings = keep;
        submitted
    }
}

/// Fail if a `width` × `height` image with `samples` samples per pixel (its colour, depth,
/// resolve and read-back, and the splat cells a frame of it may need) does not fit the GPU
/// memory still free, naming the largest image of the same shape that does.
fn check_image_fits(ctx: &Context, width: u32, height: u32, samples: vk::SampleCountFlags) -> Result<()> {
    let per_pixel = crate::target::bytes_per_pixel(samples) + crate::passes::splats::bytes_per_pixel(samples);
    let pixels = width as u64 * height as u64;
    // Drivers pad images (rows, tiles, alignment): 2 % more than the texels, as measured on
    // lavapipe (1.2–1.6 %).
    let needs = pixels * per_pixel * 51 / 50;
    let free = ctx.memory.free();
    if needs <= free {
        return Ok(());
    }
    // Both sides shrink by the same factor, so the image keeps its shape.
    let scale = (free as f64 / needs as f64).sqrt();
    const MIB: u64 = 1 << 20;
    Err(GpuError::ImageOutOfMemory {
        width,
        height,
        needs_mib: needs.div_ceil(MIB),
        free_mib: free / MIB,
        max_width: (width as f64 * scale) as u32,
        max_height: (height as f64 * scale) as u32,
    })
}
