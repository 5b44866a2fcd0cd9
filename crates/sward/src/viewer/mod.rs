//! `sward view`: the interactive viewer. A winit window, the grass frame drawn into its swapchain
//! by the same renderer `sward render` uses, an egui panel that edits every scene value live,
//! orbit and fly cameras, colliders to push through the grass, frame statistics, screenshots and
//! shader hot reload.

mod brush;
mod camera_control;
mod hot_reload;
mod panel;
mod presenter;
mod stress;

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use anyhow::{anyhow, bail, Context as _};
use ash::vk;
use glam::{Vec2, Vec3, Vec4};
use raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use sward_core::mesh::{HeightGrid, Mesh};
use sward_core::physics::{SimClock, MAX_COLLIDERS};
use sward_core::walk::Ground;
use sward_core::FrameDesc;
use sward_core::{Field, Scene};
use sward_gpu::swapchain::Surface;
use sward_gpu::{Context, ContextDesc};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{KeyCode, ModifiersState, PhysicalKey};
use winit::window::{Window, WindowId};

use crate::args::{GpuArgs, PresentMode, ViewArgs};
use crate::scenes;
use camera_control::{CameraControl, Mode};
use panel::{Action, Controls, Panel, Stats};
use presenter::{Presenter, UiFrame};
use stress::{Act, Stress};

/// Run the viewer until its window closes (or `--frames` frames have been drawn).
pub fn run(args: &ViewArgs, gpu: &GpuArgs) -> anyhow::Result<()> {
    let scene = args.scene.load()?;
    let event_loop = EventLoop::new().map_err(|e| anyhow!("cannot open a window ({e}); is there a display?"))?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = App {
        args: args.clone(),
        gpu: gpu.clone(),
        scene: Some(scene),
        view: None,
        result: Ok(()),
    };
    event_loop
        .run_app(&mut app)
        .map_err(|e| anyhow!("the window system failed: {e}"))?;
    app.result
}

struct App {
    args: ViewArgs,
    gpu: GpuArgs,
    scene: Option<Scene>,
    view: Option<View>,
    result: anyhow::Result<()>,
}

impl App {
    fn fail(&mut self, event_loop: &ActiveEventLoop, error: anyhow::Error) {
        self.result = Err(error);
        self.view = None;
        event_loop.exit();
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        let Some(scene) = self.scene.take() else { return };
        match View::new(event_loop, &self.args, &self.gpu, scene) {
            Ok(view) => self.view = Some(view),
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(view) = self.view.as_mut() else { return };
        match view.on_event(&event) {
            Ok(Flow::Continue) => {}
            Ok(Flow::Exit) => {
                let outcome = view.finish();
                self.view = None;
                self.result = outcome;
                event_loop.exit();
            }
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(view) = &self.view {
            view.window.request_redraw();
        }
    }
}

enum Flow {
    Continue,
    Exit,
}

/// Everything the open window needs. Field order is drop order: GPU objects before the window.
struct View {
    presenter: Presenter,
    egui_state: egui_winit::State,
    egui: egui::Context,
    window: Arc<Window>,
    scene: Scene,
    field: Field,
    /// The field's ground as a height grid, where it is one (walking follows it).
    ground_grid: Option<HeightGrid>,
    panel: Panel,
    controls: Controls,
    camera: CameraControl,
    clock: SimClock,
    stats: Stats,
    shaders: Option<hot_reload::ShaderWatch>,
    input: Input,
    last_frame: Instant,
    /// When the panel's trample map picture was last read back.
    overlay_read: Option<Instant>,
    frames_drawn: u32,
    screenshot_count: u32,
    pending_screenshot: Option<PathBuf>,
    single_step: bool,
    resize_pending: bool,
    /// A brush drag ended over a fixed field: regrow it once the panel's scene is the view's.
    regrow_after_paint: bool,
    validate: bool,
    /// `--stress`: the storm, the scene and window size it returns to, the frame it last
    /// acted on, and whether it minimised the window.
    stress: Option<StressRun>,
    args: ViewArgs,
}

/// What the grown field and the paint the renderer holds depend on: the field's description,
/// the surface, whether the technique grows Bezier blades at all, the kinds of grass, the
/// paint but its strokes (a brush drag adds those; its end regrows) and the standing spheres
/// that clear the ground. A change of any of them grows the field again.
#[derive(PartialEq)]
struct GrownFrom {
    field: sward_core::field::FieldDesc,
    surface: sward_core::scene::Surface,
    bezier_blades: u32,
    species: Vec<sward_core::species::Species>,
    paint: sward_core::paint::PaintParams,
    clearing: Vec<(Vec3, f32)>,
}

impl GrownFrom {
    fn of(scene: &Scene) -> GrownFrom {
        let clearing = scene.colliders.iter().filter(|c| c.clear).map(|c| (c.center, c.radius));
        let bodies = scene.bodies.iter().filter(|b| b.clear).map(|b| (b.center, 0.0));
        GrownFrom {
            field: scene.field,
            surface: scene.surface.clone(),
            bezier_blades: scene.bezier_blades(),
            species: scene.species.clone(),
            paint: sward_core::paint::PaintParams {
                strokes: Vec::new(),
                ..scene.paint.clone()
            },
            clearing: clearing.chain(bodies).collect(),
        }
    }
}

struct StressRun {
    storm: Stress,
    start: (Scene, [u32; 2]),
    acted: Option<u32>,
    minimised: bool,
}

/// Mouse and keyboard state the camera and collider controls need.
#[derive(Default)]
struct Input {
    cursor: Option<Vec2>,
    primary: bool,
    secondary: bool,
    modifiers: ModifiersState,
}

impl View {
    fn new(event_loop: &ActiveEventLoop, args: &ViewArgs, gpu: &GpuArgs, scene: Scene) -> anyhow::Result<View> {
        let attributes = Window::default_attributes()
            .with_title(format!("sward — {}", scene.name))
            .with_inner_size(PhysicalSize::new(args.width, args.height));
        let window = Arc::new(event_loop.create_window(attributes).context("cannot create a window")?);
        let display = window.display_handle().context("no display handle")?.as_raw();
        let handle = window.window_handle().context("no window handle")?.as_raw();
        let ctx = Context::new(&ContextDesc {
            display: Some(display),
            ..gpu.context_desc()
        })?;
        let surface = Surface::new(&ctx, display, handle)?;
        let size = window.inner_size();
        let mut presenter = Presenter::new(
            &ctx,
            surface,
            [size.width, size.height],
            present_mode(args.present_mode),
            scene.quality.preset,
            scene.quality.route,
        )?;
        sward_gpu::renderer::check_field_fits(&ctx, scene.bezier_blades() as u64)?;
        let field = scene.grow_field()?;
        presenter.renderer.upload(&field)?;
        presenter.renderer.upload_ground(field.ground.as_ref())?;
        let egui = egui::Context::default();
        let egui_state = egui_winit::State::new(
            egui.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            None,
        );
        let stats = Stats {
            device: format!("{} ({})", ctx.info.name, ctx.info.driver_info),
            ..Stats::default()
        };
        let controls = Controls {
            paused: false,
            wireframe: false,
            camera_mode: Mode::Orbit,
            samples: presenter.samples(),
        };
        let scene_at_start = scene.clone();
        let ground_grid = field.ground.as_ref().and_then(Mesh::height_grid);
        let mut camera = CameraControl::new(scene.camera);
        if args.walk {
            // Orbit → fly → walk.
            let ground = Ground::of(&scene.surface, field.ground.as_ref(), ground_grid.as_ref());
            camera.toggle_mode(&ground);
            camera.toggle_mode(&ground);
        }
        let mut panel = Panel::new(&scene, ctx.info.wireframe);
        panel.show_trample = args.show_trample_map;
        Ok(View {
            panel,
            camera,
            shaders: hot_reload::ShaderWatch::find(),
            presenter,
            egui_state,
            egui,
            window,
            field,
            ground_grid,
            scene,
            controls,
            clock: SimClock::default(),
            stats,
            input: Input::default(),
            last_frame: Instant::now(),
            overlay_read: None,
            frames_drawn: 0,
            screenshot_count: 0,
            pending_screenshot: None,
            single_step: false,
            resize_pending: false,
            regrow_after_paint: false,
            validate: gpu.validation,
            stress: args.stress.map(|seed| StressRun {
                storm: Stress::new(seed, args.frames.unwrap_or(1000), STRESS_MAX_BLADES),
                start: (scene_at_start, [args.width, args.height]),
                acted: None,
                minimised: false,
            }),
            args: args.clone(),
        })
    }

    fn on_event(&mut self, event: &WindowEvent) -> anyhow::Result<Flow> {
        let consumed = self.egui_state.on_window_event(&self.window, event).consumed;
        match event {
            WindowEvent::CloseRequested => return Ok(Flow::Exit),
            WindowEvent::Resized(_) => self.resize_pending = true,
            WindowEvent::ModifiersChanged(m) => self.input.modifiers = m.state(),
            WindowEvent::RedrawRequested => return self.redraw(),
            _ if consumed => {}
            WindowEvent::KeyboardInput { event, .. } => {
                if let PhysicalKey::Code(code) = event.physical_key {
                    self.on_key(code, event.state == ElementState::Pressed);
                }
            }
            WindowEvent::MouseInput { state, button, .. } => {
                let down = *state == ElementState::Pressed;
                match button {
                    MouseButton::Left => {
                        self.input.primary = down;
                        if down && self.panel.brush.on {
                            self.paint_under_cursor();
                        } else if !down && self.panel.brush.lift() {
                            self.regrow_after_paint = true;
                        }
                    }
                    MouseButton::Right | MouseButton::Middle => self.input.secondary = down,
                    _ => {}
                }
            }
            WindowEvent::CursorMoved { position, .. } => {
                let at = Vec2::new(position.x as f32, position.y as f32);
                if let Some(previous) = self.input.cursor {
                    self.on_drag(at, at - previous);
                }
                self.input.cursor = Some(at);
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => *y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
                self.camera.zoom(lines);
            }
            _ => {}
        }
        Ok(Flow::Continue)
    }

    fn on_key(&mut self, code: KeyCode, down: bool) {
        let keys = &mut self.camera.keys;
        match code {
            KeyCode::KeyW => keys.forward = down,
            KeyCode::KeyS => keys.back = down,
            KeyCode::KeyA => keys.left = down,
            KeyCode::KeyD => keys.right = down,
            KeyCode::KeyE => keys.up = down,
            KeyCode::KeyQ => keys.down = down,
            KeyCode::ShiftLeft | KeyCode::ShiftRight => keys.fast = down,
            _ if !down => {}
            KeyCode::Tab => self.apply(Action::ToggleCameraMode),
            KeyCode::KeyR => self.apply(Action::ResetCamera),
            KeyCode::Space => self.controls.paused = !self.controls.paused,
            KeyCode::F12 => self.apply(Action::Screenshot),
            KeyCode::ArrowLeft => self.nudge_collider(Vec3::new(-0.2, 0.0, 0.0)),
            KeyCode::ArrowRight => self.nudge_collider(Vec3::new(0.2, 0.0, 0.0)),
            KeyCode::ArrowUp => self.nudge_collider(Vec3::new(0.0, 0.0, 0.2)),
            KeyCode::ArrowDown => self.nudge_collider(Vec3::new(0.0, 0.0, -0.2)),
            KeyCode::PageUp => self.nudge_collider(Vec3::new(0.0, 0.1, 0.0)),
            KeyCode::PageDown => self.nudge_collider(Vec3::new(0.0, -0.1, 0.0)),
            _ => {}
        }
    }

    fn on_drag(&mut self, at: Vec2, delta: Vec2) {
        if self.input.primary && self.panel.brush.on {
            self.input.cursor = Some(at);
            self.paint_under_cursor();
        } else if self.input.primary && self.input.modifiers.control_key() {
            self.drag_collider_to(at);
        } else if self.input.primary {
            self.camera.rotate(delta);
        } else if self.input.secondary {
            match self.camera.mode {
                Mode::Orbit => self.camera.pan(delta),
                Mode::Fly | Mode::Walk => self.camera.rotate(delta),
            }
        }
    }

    fn nudge_collider(&mut self, by: Vec3) {
        if let Some(c) = self.panel.edit.colliders.get_mut(self.panel.selected_collider) {
            c.shift(by);
        }
    }

    /// The ray from the eye through the cursor, from the eye.
    fn cursor_ray(&self, cursor: Vec2) -> (Vec3, Vec3) {
        let size = self.window.inner_size();
        let ndc = Vec2::new(
            cursor.x / size.width.max(1) as f32 * 2.0 - 1.0,
            cursor.y / size.height.max(1) as f32 * 2.0 - 1.0,
        );
        let camera = self.camera.camera(&self.scene.camera);
        let inverse = camera
            .view_projection(size.width as f32 / size.height.max(1) as f32)
            .inverse();
        let far = inverse * Vec4::new(ndc.x, ndc.y, 1.0, 1.0);
        (
            camera.position,
            (far.truncate() / far.w - camera.position).normalize_or_zero(),
        )
    }

    /// A dab of the brush where the cursor meets the ground, shown from the next frame on.
    fn paint_under_cursor(&mut self) {
        let Some(cursor) = self.input.cursor else {
            return;
        };
        let (eye, ray) = self.cursor_ray(cursor);
        let Some(hit) = brush::ground_hit(eye, ray, self.ground_grid.as_ref()) else {
            return;
        };
        self.paint_at(Vec2::new(hit.x, hit.z));
    }

    /// A dab of the brush at world ground point `xz`.
    fn paint_at(&mut self, xz: Vec2) {
        if self.panel.brush.dab(&mut self.panel.edit, &mut self.field.paint, xz) {
            if let Err(e) = self.presenter.renderer.upload_paint(self.field.paint.as_ref()) {
                self.panel.error = Some(format!("{e:#}"));
            }
        }
    }

    /// Put the selected collider under the cursor, keeping its height.
    fn drag_collider_to(&mut self, cursor: Vec2) {
        let (eye, ray) = self.cursor_ray(cursor);
        let Some(c) = self.panel.edit.colliders.get_mut(self.panel.selected_collider) else {
            return;
        };
        if ray.y.abs() > 1e-4 {
            let t = (c.center.y - eye.y) / ray.y;
            if t > 0.0 {
                let hit = eye + ray * t;
                c.shift(Vec3::new(hit.x - c.center.x, 0.0, hit.z - c.center.z));
            }
        }
    }

    /// Bake the paint into PNG files beside the scene's save path, named in the scene.
    fn save_paint_maps(&mut self) {
        let Some(paint) = self.field.paint.clone() else {
            self.panel.error = Some("nothing is painted yet: paint with the brush first".into());
            return;
        };
        let dir = std::path::Path::new(&self.panel.save_path)
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .map_or_else(|| PathBuf::from("."), PathBuf::from);
        match brush::save_maps(&mut self.panel.edit, &paint, &dir) {
            Ok(files) => {
                let names: Vec<String> = files.iter().map(|f| f.display().to_string()).collect();
                self.panel.note = Some(format!("saved {}; save the scene to keep them named", names.join(", ")));
            }
            Err(e) => self.panel.error = Some(format!("{e:#}")),
        }
    }

    fn redraw(&mut self) -> anyhow::Result<Flow> {
        self.stress_act();
        let size = self.window.inner_size();
        if size.width == 0 || size.height == 0 {
            return Ok(Flow::Continue); // minimised: nothing to draw into
        }
        if self.resize_pending {
            let resized = self.presenter.resize([size.width, size.height])?;
            self.resize_pending = false;
            if let Some(note) = resized.note {
                self.panel.note = Some(note);
            }
            if resized.renderer_rebuilt {
                self.controls.samples = self.presenter.samples();
                if let Err(e) = self.regrow_field() {
                    self.panel.error = Some(format!("{e:#}"));
                }
            }
        }
        let readback = self.presenter.begin_frame()?;
        self.stats.gpu = readback.gpu.or(self.stats.gpu);
        self.stats.blades_visible = readback.visible.or(self.stats.blades_visible);
        self.poll_shaders();

        let now = Instant::now();
        let dt = (now - self.last_frame).as_secs_f32();
        self.last_frame = now;
        self.record_cpu_time(dt);

        let ui = self.run_ui()?;
        let ground = Ground::of(
            &self.scene.surface,
            self.field.ground.as_ref(),
            self.ground_grid.as_ref(),
        );
        self.camera.update(dt, &ground);
        let desc = self.frame_desc(dt, [size.width, size.height]);
        let screenshot = self.take_screenshot_request();
        if self
            .presenter
            .draw(&desc, ui, screenshot.as_deref(), [size.width, size.height])?
        {
            self.frames_drawn += 1;
        }
        self.scripted_resize();
        Ok(match self.args.frames {
            Some(n) if self.frames_drawn >= n => Flow::Exit,
            _ => Flow::Continue,
        })
    }

    fn record_cpu_time(&mut self, dt: f32) {
        let ms = dt * 1000.0;
        self.stats.cpu_ms = if self.stats.cpu_ms == 0.0 {
            ms
        } else {
            self.stats.cpu_ms * 0.9 + ms * 0.1
        };
        self.stats.fps = 1000.0 / self.stats.cpu_ms.max(1e-3);
        self.stats.history.push_back(ms);
        if self.stats.history.len() > 240 {
            self.stats.history.pop_front();
        }
        self.stats.blades_total = self.presenter.renderer.blade_count();
    }

    /// While the panel shows the trample map, read it back twice a second (a wait for the GPU,
    /// so not every frame) and turn it into the panel's picture.
    fn refresh_trample_overlay(&mut self) -> anyhow::Result<()> {
        let due = self.overlay_read.is_none_or(|t| t.elapsed().as_secs_f32() > 0.5);
        if !self.panel.show_trample || !self.scene.tramples() || !due {
            return Ok(());
        }
        self.overlay_read = Some(Instant::now());
        let texels = self.presenter.renderer.read_trample_map()?;
        if texels.is_empty() {
            return Ok(());
        }
        const SIDE: u32 = 128;
        let eye = self.camera.camera(&self.scene.camera).position;
        let grass_top = self.scene.instanced.grid.height[1].max(self.scene.field.height[1]);
        let pixels = sward_core::trample::overlay(&self.scene.trample, &texels, eye, grass_top, SIDE);
        let bytes: Vec<u8> = pixels.into_iter().flatten().collect();
        let image = egui::ColorImage::from_rgba_unmultiplied([SIDE as usize; 2], &bytes);
        match &mut self.panel.trample_overlay {
            Some(texture) => texture.set(image, egui::TextureOptions::NEAREST),
            None => {
                self.panel.trample_overlay = Some(self.egui.load_texture(
                    "trample map",
                    image,
                    egui::TextureOptions::NEAREST,
                ));
            }
        }
        Ok(())
    }

    fn run_ui(&mut self) -> anyhow::Result<UiFrame> {
        self.refresh_trample_overlay()?;
        let input = self.egui_state.take_egui_input(&self.window);
        self.controls.camera_mode = self.camera.mode;
        let mut actions = Vec::new();
        let previous = GrownFrom::of(&self.scene);
        let output = self.egui.run_ui(input, |ui| {
            egui::Panel::left("sward-controls").show(ui, |ui| {
                actions = self.panel.show(ui, &mut self.scene, &mut self.controls, &self.stats);
            });
        });
        self.egui_state
            .handle_platform_output(&self.window, output.platform_output);
        for action in actions {
            self.apply(action);
        }
        let mut regrow = GrownFrom::of(&self.scene) != previous;
        // A fixed field's blades obey the paint they were grown with: grow them again once a
        // brush drag ends (a streamed field, the generated grass and the ground follow it at once).
        let fixed = self.field.stream.is_none() && self.scene.technique.draws_bezier();
        regrow |= std::mem::take(&mut self.regrow_after_paint) && fixed;
        match self.presenter.set_quality(self.scene.quality.preset) {
            // A new renderer starts without the field.
            Ok(rebuilt) => {
                regrow |= rebuilt;
                self.controls.samples = self.presenter.samples();
            }
            Err(e) => self.panel.error = Some(format!("{e:#}")),
        }
        if regrow {
            // A mesh file still being typed, or too many blades, is shown, not fatal.
            if let Err(e) = self.regrow_field() {
                self.panel.error = Some(format!("{e:#}"));
            }
        }
        self.presenter.renderer.wireframe = self.controls.wireframe;
        // Cheap: the route only picks which pipeline and commands the next frame records. A
        // route this GPU lacks falls back, said once in the panel, which then shows the route
        // drawn (`Auto` stays `Auto` in the scene where it resolved).
        if let Some(note) = self.presenter.renderer.set_route(self.scene.quality.route) {
            self.panel.note = Some(note.to_string());
            let drawn = self.presenter.renderer.route();
            self.scene.quality.route = drawn;
            self.panel.edit.quality.route = drawn;
        }
        let pixels_per_point = output.pixels_per_point;
        Ok(UiFrame {
            primitives: self.egui.tessellate(output.shapes, pixels_per_point),
            textures_delta: output.textures_delta,
            pixels_per_point,
        })
    }

    fn apply(&mut self, action: Action) {
        match action {
            Action::ResetToRest => {
                if let Err(e) = self.presenter.renderer.upload(&self.field) {
                    self.panel.error = Some(e.to_string());
                }
            }
            Action::SingleStep => {
                self.controls.paused = true;
                self.single_step = true;
            }
            Action::SaveScene(path) => {
                let written = std::fs::write(&path, self.scene.to_toml());
                self.panel.error = written.err().map(|e| format!("cannot save {path}: {e}"));
            }
            Action::LoadScene(path) => self.load_scene(&path),
            Action::SavePaintMaps => self.save_paint_maps(),
            Action::Screenshot => {
                self.screenshot_count += 1;
                self.pending_screenshot =
                    Some(PathBuf::from(format!("sward-screenshot-{}.png", self.screenshot_count)));
            }
            Action::ResetCamera => self.camera.reset(),
            Action::ToggleCameraMode => {
                let ground = Ground::of(
                    &self.scene.surface,
                    self.field.ground.as_ref(),
                    self.ground_grid.as_ref(),
                );
                self.camera.toggle_mode(&ground);
            }
            Action::KeepView => {
                let view = self.camera.camera(&self.scene.camera);
                self.panel.edit.camera = view;
                self.camera.set_start(view);
            }
            Action::AddPathPoint => {
                let eye = self.camera.camera(&self.scene.camera).position;
                self.panel.edit.camera_path.points.push(eye);
            }
        }
    }

    fn load_scene(&mut self, path: &str) {
        match scenes::load(path) {
            Ok(scene) => {
                self.panel = Panel::new(&scene, self.panel.wireframe_available);
                self.camera.set_start(scene.camera);
                self.scene = scene;
                if let Err(e) = self.regrow_field() {
                    self.panel.error = Some(e.to_string());
                }
            }
            Err(e) => self.panel.error = Some(format!("{e:#}")),
        }
    }

    /// Grow the field again after its description changed, without restarting.
    fn regrow_field(&mut self) -> anyhow::Result<()> {
        // The old field goes first, so the new one may have its memory.
        self.presenter.renderer.upload_field(&[], &[])?;
        sward_gpu::renderer::check_field_fits(&self.presenter.ctx, self.scene.bezier_blades() as u64)?;
        self.field = self.scene.grow_field()?;
        self.ground_grid = self.field.ground.as_ref().and_then(Mesh::height_grid);
        self.presenter.renderer.upload(&self.field)?;
        self.presenter.renderer.upload_ground(self.field.ground.as_ref())?;
        Ok(())
    }

    fn frame_desc(&mut self, dt: f32, viewport: [u32; 2]) -> FrameDesc {
        let (steps, time) = if self.single_step {
            self.single_step = false;
            let t = self.clock.time;
            self.clock.time += self.scene.simulation.step;
            (1, t)
        } else if self.controls.paused {
            (0, self.clock.time)
        } else {
            self.clock.advance(dt, &self.scene.simulation)
        };
        let mut scene = self.scene.clone();
        scene.camera = self.camera.camera(&self.scene.camera);
        // Walking, the walker's legs tread the grass (where the scene leaves room for them).
        if let Some(legs) = self.camera.walker_colliders() {
            if scene.colliders_at(0.0).len() + legs.len() <= MAX_COLLIDERS {
                scene.colliders.extend(legs);
            }
        }
        FrameDesc::of_scene(&scene, self.field.size, (time, steps), viewport)
    }

    /// A screenshot asked for by F12 / the panel, or `--screenshot` on the last `--frames` frame.
    fn take_screenshot_request(&mut self) -> Option<PathBuf> {
        let last = self.args.frames.is_some_and(|n| self.frames_drawn + 1 >= n);
        match (&self.args.screenshot, last) {
            (Some(path), true) => Some(path.clone()),
            _ => self.pending_screenshot.take(),
        }
    }

    /// `--resize-at FRAME:WxH` and `--quality-at FRAME:PRESET`: resize the window or pick
    /// another quality preset mid-run, as a person would (used by the tests).
    fn scripted_resize(&mut self) {
        if let Some((frame, [w, h])) = self.args.resize_at {
            if self.frames_drawn == frame {
                let _ = self.window.request_inner_size(PhysicalSize::new(w, h));
            }
        }
        if let Some((frame, quality)) = self.args.quality_at {
            if self.frames_drawn == frame {
                self.scene.quality.preset = quality.into();
                self.panel.edit.quality.preset = quality.into();
            }
        }
        if let Some((frame, [x0, z0, x1, z1])) = self.args.brush_at {
            if self.frames_drawn == frame {
                self.scripted_brush(Vec2::new(x0, z0), Vec2::new(x1, z1));
            }
        }
    }

    /// `--brush-at`: the brush dragged from `from` to `to` as the mouse drags it, dab by dab.
    fn scripted_brush(&mut self, from: Vec2, to: Vec2) {
        let kept = self.panel.brush.clone();
        self.panel.brush.painting = brush::Painting::Density;
        self.panel.brush.value = 0.0;
        self.panel.brush.radius = 2.0;
        let dabs = (from.distance(to) / 0.5).ceil().max(1.0) as u32;
        for i in 0..=dabs {
            self.paint_at(from.lerp(to, i as f32 / dabs as f32));
        }
        self.regrow_after_paint |= self.panel.brush.lift();
        self.panel.brush = kept;
    }

    /// `--stress`: this drawn frame's act of the storm, once per drawn frame; a window the
    /// storm minimised, or sized to nothing, is given back its start size first, as a user
    /// who restores it (no frame is drawn into nothing).
    fn stress_act(&mut self) {
        let Some(run) = self.stress.as_mut() else { return };
        let size = self.window.inner_size();
        let [w, h] = run.start.1;
        if run.minimised || size.width == 0 || size.height == 0 {
            self.window.set_minimized(false);
            let _ = self.window.request_inner_size(PhysicalSize::new(w, h));
            run.minimised = false;
            return;
        }
        if run.acted == Some(self.frames_drawn) {
            return;
        }
        run.acted = Some(self.frames_drawn);
        match run.storm.act(self.frames_drawn) {
            Act::Resize([w, h]) => {
                let _ = self.window.request_inner_size(PhysicalSize::new(w, h));
            }
            Act::Minimise => {
                self.window.set_minimized(true);
                run.minimised = true;
            }
            Act::Blades(n) => self.panel.edit.field.blades = n,
            Act::Technique(t) => self.panel.edit.technique = t,
            Act::Route(r) => self.panel.edit.quality.route = r,
            Act::Quality(q) => self.panel.edit.quality.preset = q,
            Act::Wait => {}
            Act::Settle => {
                self.panel.edit = run.start.0.clone();
                let _ = self.window.request_inner_size(PhysicalSize::new(w, h));
            }
            Act::Measure => {
                // sward's own bytes (requested sizes: the allocator's figures move with where
                // an allocation landed) and the allocator's count of allocations, the UI's
                // too (its mesh buffers' sizes follow the panel's text, their number does not).
                let allocations = self.presenter.ctx.allocator().generate_report().allocations.len();
                run.storm.measured.push((self.presenter.ctx.memory.used(), allocations));
            }
        }
    }

    fn poll_shaders(&mut self) {
        let Some(watch) = self.shaders.as_mut() else { return };
        let Some(compiled) = watch.poll() else { return };
        self.stats.shader_status =
            match compiled.and_then(|set| self.presenter.reload_shaders(&set).map_err(|e| format!("{e:#}"))) {
                Ok(()) => Some(format!("shaders reloaded from {}", watch.dir().display())),
                Err(e) => Some(format!("shader error (keeping the last good pipelines): {e}")),
            };
    }

    /// Called when the window closes or `--frames` is reached: report validation problems.
    fn finish(&mut self) -> anyhow::Result<()> {
        let ctx = &self.presenter.ctx;
        let messages = ctx.take_validation_messages();
        if self.validate && !messages.is_empty() {
            bail!(
                "the Vulkan validation layer reported {} problem(s), the first: {}",
                messages.len(),
                messages[0]
            );
        }
        if let Some(run) = &self.stress {
            println!("{}", run.storm.report());
        }
        if self.args.frames.is_some() {
            let samples = self.presenter.samples();
            println!(
                "drew {} frames on {} at {samples}× MSAA",
                self.frames_drawn, ctx.info.name
            );
        }
        Ok(())
    }
}

/// Bezier blades a `--stress` storm asks for at most: enough to regrow a field, few enough
/// for a CPU Vulkan driver to draw a thousand frames.
const STRESS_MAX_BLADES: u32 = 1500;

fn present_mode(mode: PresentMode) -> vk::PresentModeKHR {
    match mode {
        PresentMode::Fifo => vk::PresentModeKHR::FIFO,
        PresentMode::Mailbox => vk::PresentModeKHR::MAILBOX,
        PresentMode::Immediate => vk::PresentModeKHR::IMMEDIATE,
    }
}

/// Whether a window can be opened here (an X11 or Wayland display is set).
pub fn display_available() -> bool {
    std::env::var_os("DISPLAY").is_some() || std::env::var_os("WAYLAND_DISPLAY").is_some()
}

#[cfg(test)]
mod tests {
    use super::GrownFrom;
    use sward_core::Scene;

    /// A panel edit of the kinds of grass, the paint's noise or a clearing grows the field (and
    /// its paint) again; a brush stroke being dragged does not (its end does), nor does wind.
    #[test]
    fn what_regrows_the_field() {
        let park = Scene::from_toml(include_str!("../../../../scenes/park.toml"), "park").unwrap();
        let grown = GrownFrom::of(&park);
        let changed = |edit: &dyn Fn(&mut Scene)| {
            let mut s = park.clone();
            edit(&mut s);
            GrownFrom::of(&s) != grown
        };
        assert!(changed(&|s| s.species[0].height[1] = 2.0));
        assert!(changed(&|s| s.paint.noise = Some(Default::default())));
        assert!(changed(&|s| s.bodies[0].clear = false));
        assert!(changed(&|s| s.field.blades = 1000));
        assert!(!changed(&|s| s.paint.strokes.push(Default::default())));
        assert!(!changed(&|s| s.wind.0[0].strength = 1.0));
    }
}
