//! A wgpu application with sward's meadow: the application draws its ground and a cube with
//! wgpu, sward draws the responsive grass over them — depth-tested against the cube, culled
//! where the cube hides it — while the camera circles the cube. In a window where there is a
//! display (Esc closes it); without one, 240 frames headless and the last written to a PNG.
//!
//! `cargo run --release -p sward-wgpu --example meadow [-- --headless OUT.png]`
//!
//! `-- --bench FRAMES` draws FRAMES frames at 1920×1080 headless after a warm-up and prints
//! the median and 99th percentile of sward's GPU time per frame (its own timestamps, the same
//! passes `sward bench` times) and of the host time `GrassRenderer::encode` takes.

#[path = "../tests/support/cube.rs"]
mod cube;
#[path = "../tests/support/readback.rs"]
mod readback;

use std::error::Error;
use std::sync::Arc;
use std::time::{Duration, Instant};

use cube::Cube;
use glam::Vec3;
use sward_core::{Field, FrameDesc, Scene};
use sward_wgpu::{DepthDirection, FrameTarget, GrassRenderer, SwardDevice, TargetDesc};
use winit::application::ApplicationHandler;
use winit::event::{ElementState, KeyEvent, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::window::{Window, WindowId};

const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// The cube, standing in the grass where the camera looks.
const CUBE: (Vec3, f32) = (Vec3::new(0.0, 0.8, 0.0), 0.8);
/// The sky behind everything (linear).
const SKY: wgpu::Color = wgpu::Color {
    r: 0.36,
    g: 0.52,
    b: 0.78,
    a: 1.0,
};

fn main() -> Result<(), Box<dyn Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().is_some_and(|a| a == "--bench") {
        let frames = args
            .get(1)
            .and_then(|n| n.parse().ok())
            .ok_or("--bench needs a number of frames")?;
        return bench(frames);
    }
    let headless = args.first().is_some_and(|a| a == "--headless") || !has_display();
    if headless {
        let out = args.get(1).cloned().unwrap_or_else(|| "sward-wgpu-meadow.png".into());
        return render_headless(&out);
    }
    let event_loop = EventLoop::new()?;
    let mut app = App::default();
    event_loop.run_app(&mut app)?;
    app.error.map_or(Ok(()), Err)
}

fn has_display() -> bool {
    ["DISPLAY", "WAYLAND_DISPLAY"]
        .iter()
        .any(|v| std::env::var_os(v).is_some())
}

/// The meadow scene that ships with sward.
fn meadow() -> Result<Scene, Box<dyn Error>> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/meadow.toml");
    Ok(Scene::load(std::path::Path::new(path))?)
}

/// The application's frame: its world, sward's grass, and the camera that sees both.
struct Frame {
    grass: GrassRenderer,
    cube: Cube,
    scene: Scene,
    field: Field,
    depth: wgpu::TextureView,
    frame: u64,
    /// Seen as `sward bench` sees the meadow (the scene's camera, no cube).
    as_bench: bool,
    /// Last: sward's renderer goes before the device it draws on.
    sward: SwardDevice,
}

impl Frame {
    fn new(sward: SwardDevice, color: wgpu::TextureFormat, size: [u32; 2]) -> Result<Frame, Box<dyn Error>> {
        let scene = meadow()?;
        let mut grass = GrassRenderer::new(&sward, &TargetDesc::new(color, DEPTH_FORMAT), scene.quality.preset)?;
        let field = scene.grow_field()?;
        grass.upload(&field)?;
        let cube = Cube::new(&sward.device, color, DEPTH_FORMAT, 1, false);
        let depth = depth_view(&sward.device, size);
        Ok(Frame {
            grass,
            cube,
            scene,
            field,
            depth,
            frame: 0,
            as_bench: false,
            sward,
        })
    }

    /// Draw the next frame (1/60 s later) into `color`; returns the host time sward's part took.
    fn draw(&mut self, color: &wgpu::TextureView, size: [u32; 2]) -> Result<Duration, Box<dyn Error>> {
        let step = self.scene.simulation.step;
        // 1/60 s a frame; as `sward bench` runs, one fixed step a frame.
        let frame_time = if self.as_bench { step } else { 1.0 / 60.0 };
        let t = self.frame as f32 * frame_time;
        let steps = (frame_time / step).round() as u32;
        // Circling the cube at a person's eye height.
        let angle = 0.15 * t;
        let eye = Vec3::new(7.0 * angle.sin(), 1.7, -7.0 * angle.cos());
        let (view, cube) = match self.as_bench {
            // `sward bench`'s meadow: the scene's own camera, nothing of the application's in
            // the field (the cube sunk below the ground).
            true => (self.scene.camera.view(), (Vec3::new(0.0, -100.0, 0.0), 0.01)),
            false => (glam::camera::rh::view::look_at_mat4(eye, CUBE.0, Vec3::Y), CUBE),
        };
        let cam = &self.scene.camera;
        let aspect = size[0] as f32 / size[1] as f32;
        let projection =
            glam::camera::rh::proj::directx::perspective(cam.fov_y_degrees.to_radians(), aspect, cam.near, cam.far);
        let mut world = self.sward.device.create_command_encoder(&Default::default());
        let attachments = (color, None, &self.depth);
        self.cube.draw(
            &self.sward.queue,
            &mut world,
            attachments,
            projection * view,
            cube,
            (SKY, true),
        );
        let desc = FrameDesc::of_scene(&self.scene, self.field.size, (t, steps), size)
            .with_view_projection(view, sward_wgpu::sward_projection(projection, DepthDirection::Forward));
        let started = Instant::now();
        let grass = self.grass.encode(&desc, &FrameTarget::new(color, &self.depth))?;
        let encoded = started.elapsed();
        self.sward.queue.submit(std::iter::once(world.finish()).chain(grass));
        self.frame += 1;
        Ok(encoded)
    }

    fn resize(&mut self, size: [u32; 2]) {
        self.depth = depth_view(&self.sward.device, size);
    }
}

/// The application's depth: read by sward's cull as well as tested (`TEXTURE_BINDING`).
fn depth_view(device: &wgpu::Device, [width, height]: [u32; 2]) -> wgpu::TextureView {
    device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some("depth"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        })
        .create_view(&Default::default())
}

fn instance(display: Option<Box<dyn wgpu::wgt::WgpuHasDisplayHandle>>) -> wgpu::Instance {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    desc.backends = wgpu::Backends::VULKAN;
    desc.display = display;
    wgpu::Instance::new(desc)
}

fn open(instance: &wgpu::Instance, surface: Option<&wgpu::Surface>) -> Result<SwardDevice, Box<dyn Error>> {
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        compatible_surface: surface,
        ..Default::default()
    }))?;
    Ok(sward_wgpu::open(
        &adapter,
        &wgpu::DeviceDescriptor::default(),
        &Default::default(),
    )?)
}

/// 240 frames into an offscreen texture; the last written to `out`.
fn render_headless(out: &str) -> Result<(), Box<dyn Error>> {
    let size = [960, 540];
    let (mut frame, texture, color) = offscreen(size)?;
    for _ in 0..240 {
        frame.draw(&color, size)?;
    }
    let pixels = readback::texels(&frame.sward.device, &frame.sward.queue, &texture);
    image::RgbaImage::from_raw(size[0], size[1], pixels)
        .ok_or("the frame has the wrong size")?
        .save(out)?;
    println!(
        "wrote {out}: a wgpu cube in sward's meadow, {} blades",
        frame.field.blades.len()
    );
    Ok(())
}

/// `frames` timed frames at 1920×1080 after 300 of warm-up: sward's GPU time per frame and the
/// host time of its encoding, median and 99th percentile.
fn bench(frames: usize) -> Result<(), Box<dyn Error>> {
    let size = [1920, 1080];
    let (mut frame, _texture, color) = offscreen(size)?;
    frame.grass.set_timing(true);
    frame.as_bench = true;
    let (mut passes, mut host, mut waits) = (Vec::new(), Vec::new(), Vec::new());
    for k in 0..300 + frames {
        let encoded = frame.draw(&color, size)?;
        if k >= 300 {
            let wait = frame.grass.gpu_wait();
            host.push(encoded.saturating_sub(wait).as_secs_f64() * 1e3);
            waits.push(wait.as_secs_f64() * 1e3);
            passes.extend(frame.grass.pass_times().copied());
        }
    }
    frame.grass.wait_idle();
    let info = &frame.sward.context.info;
    println!(
        "sward in wgpu: meadow ({} blades) at 1920×1080, 1 sample, the scene's camera, on {}",
        frame.field.blades.len(),
        info.name
    );
    let pass = |f: fn(&sward_gpu::timer::PassTimes) -> f64| passes.iter().map(f).collect::<Vec<_>>();
    let rows: [(&str, Vec<f64>); 7] = [
        ("GPU frame (sward's passes)", pass(|t| t.frame())),
        ("  occluders", pass(|t| t.occluders)),
        ("  simulate", pass(|t| t.simulate)),
        ("  cull", pass(|t| t.cull)),
        ("  draw", pass(|t| t.draw)),
        ("host: GrassRenderer::encode, less the wait", host),
        ("  waiting for the GPU", waits),
    ];
    for (what, mut ms) in rows {
        ms.sort_by(f64::total_cmp);
        let at = |q: f64| ms[((ms.len() - 1) as f64 * q) as usize];
        println!(
            "{what}: median {:.3} ms, p99 {:.3} ms ({} frames)",
            at(0.5),
            at(0.99),
            ms.len()
        );
    }
    Ok(())
}

/// The frame drawing into an offscreen colour texture of `size`.
fn offscreen(size: [u32; 2]) -> Result<(Frame, wgpu::Texture, wgpu::TextureView), Box<dyn Error>> {
    let color_format = wgpu::TextureFormat::Rgba8UnormSrgb;
    let sward = open(&instance(None), None)?;
    let texture = sward.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("frame"),
        size: wgpu::Extent3d {
            width: size[0],
            height: size[1],
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: color_format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let color = texture.create_view(&Default::default());
    let frame = Frame::new(sward, color_format, size)?;
    Ok((frame, texture, color))
}

/// The windowed application: a surface, and the frame drawn into it at the display's pace.
#[derive(Default)]
struct App {
    window: Option<Arc<Window>>,
    surface: Option<(wgpu::Surface<'static>, wgpu::SurfaceConfiguration)>,
    frame: Option<Frame>,
    error: Option<Box<dyn Error>>,
}

impl App {
    fn start(&mut self, event_loop: &ActiveEventLoop) -> Result<(), Box<dyn Error>> {
        let window = Arc::new(event_loop.create_window(Window::default_attributes().with_title("sward in wgpu"))?);
        let instance = instance(Some(Box::new(event_loop.owned_display_handle())));
        let surface = instance.create_surface(window.clone())?;
        let sward = open(&instance, Some(&surface))?;
        let size = window.inner_size();
        let caps = surface.get_capabilities(&sward.adapter);
        let format = caps
            .formats
            .iter()
            .copied()
            .find(|f| f.is_srgb())
            .ok_or("the surface offers no sRGB format")?;
        let config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            format,
            width: size.width.max(1),
            height: size.height.max(1),
            present_mode: wgpu::PresentMode::AutoVsync,
            desired_maximum_frame_latency: 2,
            alpha_mode: caps.alpha_modes[0],
            view_formats: vec![],
            color_space: Default::default(),
        };
        surface.configure(&sward.device, &config);
        self.frame = Some(Frame::new(sward, format, [config.width, config.height])?);
        self.surface = Some((surface, config));
        self.window = Some(window);
        Ok(())
    }

    fn redraw(&mut self) -> Result<(), Box<dyn Error>> {
        let (Some((surface, config)), Some(frame)) = (&self.surface, &mut self.frame) else {
            return Ok(());
        };
        let texture = match surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t) | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            _ => {
                surface.configure(&frame.sward.device, config);
                return Ok(());
            }
        };
        let view = texture.texture.create_view(&Default::default());
        frame.draw(&view, [config.width, config.height])?;
        frame.sward.queue.present(texture);
        Ok(())
    }

    fn resize(&mut self, width: u32, height: u32) {
        if let (Some((surface, config)), Some(frame)) = (&mut self.surface, &mut self.frame) {
            config.width = width.max(1);
            config.height = height.max(1);
            surface.configure(&frame.sward.device, config);
            frame.resize([config.width, config.height]);
        }
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, e: Box<dyn Error>) {
        self.error = Some(e);
        event_loop.exit();
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_none() {
            if let Err(e) = self.start(event_loop) {
                self.fail(event_loop, e);
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested
            | WindowEvent::KeyboardInput {
                event:
                    KeyEvent {
                        logical_key: Key::Named(NamedKey::Escape),
                        state: ElementState::Pressed,
                        ..
                    },
                ..
            } => event_loop.exit(),
            WindowEvent::Resized(size) => self.resize(size.width, size.height),
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.redraw() {
                    self.fail(event_loop, e);
                }
                if let Some(window) = &self.window {
                    window.request_redraw();
                }
            }
            _ => {}
        }
    }

    fn exiting(&mut self, _: &ActiveEventLoop) {
        // sward's renderer before the device and the surface it draws into.
        self.frame = None;
        self.surface = None;
    }
}
