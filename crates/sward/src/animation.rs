//! `sward render --animation N`: the grass in motion — wind, trampling, recovery — as N frames
//! at a fixed frame rate, each advancing the simulation by 1/fps seconds, written as one
//! animated PNG (and, with `--sequence`, as numbered PNGs), the camera travelling the scene's
//! `[camera_path]` and turning about its target where `--orbit` asks.

use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

use anyhow::Context as _;
use glam::{Quat, Vec2};
use indicatif::{ProgressBar, ProgressStyle};
use sward_core::Scene;
use sward_gpu::Headless;

/// What to capture: `frames` frames at `fps`, after `warmup` fixed steps.
pub struct Capture<'a> {
    pub out: &'a Path,
    pub frames: u32,
    pub fps: u32,
    pub warmup: u32,
    /// Degrees per second the camera turns about its target (about its up axis).
    pub orbit: Option<f32>,
    /// Also write each frame as its own PNG.
    pub sequence: bool,
    /// The ground a camera path above the ground follows (none: the plane).
    pub ground: Option<&'a sward_core::mesh::HeightGrid>,
}

/// Render and write the animation; the field is already on the GPU.
pub fn capture(headless: &mut Headless, scene: &Scene, field_size: Vec2, c: &Capture) -> anyhow::Result<()> {
    let [width, height] = [headless.target.extent.width, headless.target.extent.height];
    let mut apng = AnimatedPng::create(c.out, [width, height], c.frames, c.fps)?;
    let step = scene.simulation.step;
    let progress = ProgressBar::new(c.frames as u64).with_style(
        ProgressStyle::with_template("{bar:40} frame {pos}/{len} {eta} left")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    // Frame k shows the field at warm-up + k / fps seconds: whole steps, none lost to rounding.
    let mut done = 0u64;
    for k in 0..c.frames {
        let seconds = k as f64 / c.fps as f64;
        let target = c.warmup as u64 + (seconds / step as f64).round() as u64;
        let frame_scene = orbited(
            &travelled(scene, seconds as f32, c.ground),
            c.orbit.unwrap_or(0.0) * seconds as f32,
        );
        let pixels = headless.render_after(&frame_scene, field_size, done, (target - done) as u32)?;
        done = target;
        apng.add(&pixels)?;
        if c.sequence {
            let path = numbered(c.out, k + 1);
            image::save_buffer(&path, &pixels, width, height, image::ExtendedColorType::Rgba8)
                .with_context(|| format!("cannot write {}", path.display()))?;
        }
        progress.inc(1);
    }
    progress.finish_and_clear();
    apng.finish()
}

/// `scene` with its camera where its `[camera_path]` takes it `seconds` in (over `ground`).
pub fn travelled(scene: &Scene, seconds: f32, ground: Option<&sward_core::mesh::HeightGrid>) -> Scene {
    let mut scene = scene.clone();
    scene.camera = scene.camera_path.camera_over(&scene.camera, seconds, ground);
    scene
}

/// `scene` with its camera turned by `degrees` about its target, around its up axis.
fn orbited(scene: &Scene, degrees: f32) -> Scene {
    let mut scene = scene.clone();
    if degrees != 0.0 {
        let cam = &mut scene.camera;
        let turn = Quat::from_axis_angle(cam.up.normalize(), degrees.to_radians());
        cam.position = cam.target + turn * (cam.position - cam.target);
    }
    scene
}

/// `out` with `-NNNN` before its extension: the `index`-th frame of a sequence.
pub fn numbered(out: &Path, index: u32) -> PathBuf {
    let stem = out
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    out.with_file_name(format!("{stem}-{index:04}.png"))
}

/// An animated PNG written frame by frame (RGB: the frames are opaque).
struct AnimatedPng {
    writer: png::Writer<BufWriter<File>>,
    path: PathBuf,
}

impl AnimatedPng {
    fn create(path: &Path, [width, height]: [u32; 2], frames: u32, fps: u32) -> anyhow::Result<AnimatedPng> {
        let cannot = || format!("cannot write {}", path.display());
        let file = File::create(path).with_context(cannot)?;
        let mut encoder = png::Encoder::new(BufWriter::new(file), width, height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        // Grass is fine detail everywhere: the strongest compression saves a tenth or more.
        encoder.set_compression(png::Compression::High);
        // Played in a loop, forever (0 plays).
        encoder.set_animated(frames, 0).with_context(cannot)?;
        encoder.set_frame_delay(1, fps as u16).with_context(cannot)?;
        Ok(AnimatedPng {
            writer: encoder.write_header().with_context(cannot)?,
            path: path.to_path_buf(),
        })
    }

    /// Add a frame given as RGBA8, top row first.
    fn add(&mut self, rgba: &[u8]) -> anyhow::Result<()> {
        let rgb: Vec<u8> = rgba
            .as_chunks::<4>()
            .0
            .iter()
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect();
        let path = self.path.display().to_string();
        self.writer
            .write_image_data(&rgb)
            .with_context(|| format!("cannot write {path}"))
    }

    fn finish(self) -> anyhow::Result<()> {
        let path = self.path.display().to_string();
        self.writer.finish().with_context(|| format!("cannot write {path}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sequence_numbers_its_frames_beside_the_animation() {
        assert_eq!(
            numbered(Path::new("out/trample.png"), 7),
            Path::new("out/trample-0007.png")
        );
    }

    #[test]
    fn an_orbit_keeps_the_distance_to_the_target_and_the_height() {
        let scene = Scene::default();
        let turned = orbited(&scene, 90.0);
        let (a, b) = (scene.camera, turned.camera);
        assert!((a.position.distance(a.target) - b.position.distance(b.target)).abs() < 1e-4);
        assert!((a.position.y - b.position.y).abs() < 1e-4);
        assert!(a.position.distance(b.position) > 0.1);
    }
}
