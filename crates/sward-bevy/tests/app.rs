//! sward's grass in a headless Bevy app (lavapipe in CI, under the validation layer): a camera
//! rendering into an image sees the grass over Bevy's clear colour, a Bevy mesh standing in
//! the grass hides the blades behind it, a collider rolled through the field leaves a trail
//! that the same app without it does not have, a streamed field follows Bevy's camera
//! wherever it walks, a system of the app changes the grass while it runs, and a game paints
//! it (clearing a disc) while it runs.

// A native test: it finds an adapter and waits for read-backs.
#![allow(clippy::disallowed_methods)]

use std::sync::{Arc, Mutex};
use std::time::Duration;

use bevy::app::ScheduleRunnerPlugin;
use bevy::asset::RenderAssetUsages;
use bevy::camera::RenderTarget;
use bevy::image::Image;
use bevy::log::LogPlugin;
use bevy::prelude::*;
use bevy::render::gpu_readback::{Readback, ReadbackComplete};
use bevy::render::render_resource::{TextureFormat, TextureUsages};
use bevy::time::TimeUpdateStrategy;
use bevy::window::ExitCondition;
use bevy::winit::WinitPlugin;
use sward_bevy::{
    Grass, GrassCollider, GrassLighting, GrassOccluder, GrassQuality, GrassRoute, GrassSplats, SwardContext,
    SwardPlugin,
};
use sward_core::Scene;
use sward_gpu::Validation;

const NEEDS: &str = "this test needs a Vulkan device and the Khronos validation layer \
     (Debian/Ubuntu: apt-get install libvulkan1 mesa-vulkan-drivers vulkan-validationlayers)";
/// A multiple of 64 pixels, so the read-back rows carry no padding.
const WIDTH: u32 = 128;
const HEIGHT: u32 = 96;
const FRAMES: u32 = 50;
/// The cube that hides grass behind it.
const RED_CUBE: Color = Color::srgb(0.9, 0.05, 0.05);
/// Bevy's clear colour: a blue sky no grass has.
const SKY: Color = Color::srgb(0.2, 0.3, 0.9);

/// The limits of the Vulkan adapter Bevy picks.
fn vulkan_limits() -> wgpu::Limits {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    desc.backends = wgpu::Backends::VULKAN;
    let instance = wgpu::Instance::new(desc);
    let adapter = pollster::block_on(instance.request_adapter(&Default::default()));
    adapter.unwrap_or_else(|e| panic!("{NEEDS}: {e}")).limits()
}

/// What wgpu's backends say (the Vulkan validation layer's messages through wgpu-hal, wgpu's
/// own warnings) while a test app runs on Bevy's device: kept, for the test to fail on.
mod wgpu_messages {
    use std::sync::Mutex;

    use bevy::log::{tracing, tracing_subscriber};
    use tracing_subscriber::layer::{Context, Layer, SubscriberExt};

    static MESSAGES: Mutex<Vec<String>> = Mutex::new(Vec::new());

    struct Keeper;

    impl log::Log for Keeper {
        fn enabled(&self, meta: &log::Metadata) -> bool {
            // Not GL's: Bevy's default backends probe EGL too, which says when it finds no
            // driver; the apps run on Vulkan.
            let target = meta.target();
            meta.level() <= log::Level::Warn && target.starts_with("wgpu") && !target.starts_with("wgpu_hal::gles")
        }

        fn log(&self, record: &log::Record) {
            let line = format!("{}: {}", record.target(), record.args());
            // Bevy's own: its deferred lighting pass tests depth Equal against a fullscreen
            // triangle without @invariant (bevy_pbr deferred_lighting.wgsl); sward's pipelines
            // test GreaterEqual.
            let bevy_s_deferred_lighting = line.contains("without the @invariant attribute");
            // Another test's: an app on sward's device runs wgpu with its DEBUG flag (sward's
            // messenger needs the debug utils it brings), which marks every shader's debug
            // source as WGSL, a language Debian 12's validation layer does not know; this log
            // is the process's, and the tests run side by side. The apps here run without it.
            let debug_source = line.contains("Invalid source language operand");
            let newer_than_the_layer = super::layer_predates_position_fetch(&line);
            // The objects, queues and command buffers a message names, logged after it line
            // by line: a message kept fails the test on its own line.
            let detail = format!("{}", record.args()).starts_with('\t');
            if self.enabled(record.metadata())
                && !bevy_s_deferred_lighting
                && !debug_source
                && !newer_than_the_layer
                && !detail
            {
                MESSAGES.lock().unwrap_or_else(|e| e.into_inner()).push(line);
            }
        }

        fn flush(&self) {}
    }

    /// Bevy's errors (a shader that does not compose, a pipeline wgpu refused, a render error):
    /// Bevy logs them through `tracing`, which has no subscriber with Bevy's log plugin off.
    struct BevyErrors;

    impl<S: tracing::Subscriber> Layer<S> for BevyErrors {
        fn on_event(&self, event: &tracing::Event<'_>, _: Context<'_, S>) {
            let meta = event.metadata();
            // Not GL's EGL probe (as `Keeper`).
            if *meta.level() != tracing::Level::ERROR || meta.target().starts_with("wgpu_hal::gles") {
                return;
            }
            let mut line = format!("{}: ", meta.target());
            event.record(&mut Message(&mut line));
            MESSAGES.lock().unwrap_or_else(|e| e.into_inner()).push(line);
        }
    }

    /// An event's fields, written out.
    struct Message<'a>(&'a mut String);

    impl tracing::field::Visit for Message<'_> {
        fn record_debug(&mut self, field: &tracing::field::Field, value: &dyn std::fmt::Debug) {
            use std::fmt::Write;
            let _ = write!(self.0, "{}={value:?} ", field.name());
        }
    }

    /// Keep wgpu's warnings and errors, and Bevy's errors, from now on.
    pub fn listen() {
        if log::set_logger(&Keeper).is_ok() {
            log::set_max_level(log::LevelFilter::Warn);
            let errors = tracing_subscriber::registry().with(BevyErrors);
            tracing::subscriber::set_global_default(errors).expect("no other tracing subscriber");
        }
    }

    /// The messages kept so far.
    pub fn take() -> Vec<String> {
        std::mem::take(&mut *MESSAGES.lock().unwrap_or_else(|e| e.into_inner()))
    }
}

/// The last frame read back, as RGBA bytes.
#[derive(Resource, Clone, Default)]
struct Pixels(Arc<Mutex<Vec<u8>>>);

/// Where the rolling collider is at frame `k`: across the field in front of the camera.
fn ball_at(k: u32) -> Vec3 {
    let t = k as f32 / FRAMES as f32;
    Vec3::new(-4.0 + 8.0 * t, 0.45, -1.5)
}

#[derive(Component)]
struct Rolling;

/// Where the camera is at frame `k`.
#[derive(Resource, Clone, Copy)]
struct Eye(fn(u32) -> Transform);

/// Looking at the field from behind its edge, still.
fn still_eye(_: u32) -> Transform {
    Transform::from_xyz(0.0, 3.0, -9.0).looking_at(Vec3::new(0.0, 0.0, 0.0), Vec3::Y)
}

/// What a test app holds besides the camera and the grass.
#[derive(Clone, Copy)]
struct Props {
    /// A collider rolling through the grass.
    ball: bool,
    /// A Bevy cube of this colour standing in it.
    mesh: Option<Color>,
    eye: Eye,
    /// The camera renders in HDR (Bevy tonemaps after its passes, the grass's colour too).
    hdr: bool,
    /// The grass is drawn in Bevy's own passes (`GrassLighting::Pbr`) and the sun casts
    /// shadows.
    pbr: bool,
    /// Whose render device: the one `render_plugin` opens for sward's Vulkan renderer, or
    /// the one Bevy opens itself on these backends (sward's portable passes).
    device: Device,
    /// Every camera draws with Bevy's default 4× MSAA; else with none, a quarter of the
    /// fragments on a CPU device (most tests: what they check does not depend on the samples).
    msaa: bool,
    /// How the far field reaches Bevy's passes (`SwardPlugin::splats`).
    splats: GrassSplats,
}

/// The render device a test app runs on.
#[derive(Clone, Copy, PartialEq, Debug)]
enum Device {
    /// `sward_bevy::render_plugin`'s: sward's Vulkan renderer.
    Sward,
    /// The one Bevy opens itself, as a game's (its default backends and adapter): sward's
    /// portable passes.
    Bevy,
    /// Bevy's own, its limits the adapter's but for four storage buffers a shader stage,
    /// fewer than sward's passes bind.
    Starved,
}

/// The still camera over the grass, nothing else in the field.
const STILL: Props = Props {
    ball: false,
    mesh: None,
    eye: Eye(still_eye),
    hdr: false,
    pbr: false,
    device: Device::Sward,
    msaa: false,
    splats: GrassSplats::Auto,
};

/// The sun at frame `k`: the direction toward it and its colour.
#[derive(Resource, Clone, Copy)]
struct SunAt(fn(u32) -> (Vec3, Color));

/// Behind the field's far edge, high, white.
fn still_sun(_: u32) -> (Vec3, Color) {
    (Vec3::new(1.0, 3.0, -2.0), Color::WHITE)
}

/// The tests' field: 3,000 blades on 12 × 12 units, about 21 a square unit. A frame on a CPU
/// device (lavapipe) costs about 33 µs a blade, and these apps draw hundreds of frames: with
/// twice as many blades the suite took 308 s instead of 259.
fn grass_scene() -> Scene {
    let mut scene = Scene::default();
    scene.field.blades = 3000;
    scene.field.size = glam::Vec2::splat(12.0);
    // Meadow grass, knee high: the collider's sphere reaches the blades' tips and middles.
    scene.field.height = [0.45, 1.1];
    // A still day: the trail is the collider's, not the wind's.
    for wind in &mut scene.wind.0 {
        wind.strength = 0.0;
    }
    scene
}

/// A headless app: Bevy's renderer on a device opened for sward, validated; a camera drawing
/// into an image that is read back every frame, moved by `props.eye`; the grass of `scene`;
/// and the props.
fn app(scene: Scene, props: Props) -> (App, Pixels) {
    app_with(scene, props, |_| {})
}

/// [`app`], `extra` adding to it before it is finished (the render world's systems: Bevy moves
/// the render world to its own thread then).
fn app_with(scene: Scene, props: Props, extra: impl FnOnce(&mut App)) -> (App, Pixels) {
    let Props {
        ball,
        mesh,
        eye,
        hdr,
        pbr,
        device,
        msaa,
        splats,
    } = props;
    let flags = wgpu::InstanceFlags::VALIDATION | wgpu::InstanceFlags::DEBUG;
    let mut render = match device {
        Device::Sward => sward_bevy::render_plugin_with(flags).unwrap_or_else(|e| panic!("{NEEDS}: {e}")),
        Device::Bevy | Device::Starved => {
            wgpu_messages::listen();
            let starved = wgpu::Limits {
                max_storage_buffers_per_shader_stage: 4,
                ..vulkan_limits()
            };
            bevy::render::RenderPlugin {
                render_creation: bevy::render::settings::WgpuSettings {
                    constrained_limits: (device == Device::Starved).then_some(starved),
                    // Without DEBUG: the shaders' debug source is marked as WGSL, a language
                    // Debian 12's validation layer does not know yet (it says so of every
                    // shader of Bevy's).
                    instance_flags: wgpu::InstanceFlags::VALIDATION,
                    ..default()
                }
                .into(),
                ..default()
            }
        }
    };
    render.synchronous_pipeline_compilation = true;
    let mut app = App::new();
    app.add_plugins((
        DefaultPlugins
            .set(render)
            .set(WindowPlugin {
                primary_window: None,
                exit_condition: ExitCondition::DontExit,
                ..default()
            })
            .disable::<WinitPlugin>()
            .disable::<LogPlugin>(),
        ScheduleRunnerPlugin::run_loop(Duration::ZERO),
        SwardPlugin {
            validation: Validation::Required,
            splats,
            ..default()
        },
    ))
    .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f64(1.0 / 60.0)))
    .insert_resource(ClearColor(SKY))
    // Shadow maps sized for a 128×96 picture: Bevy's default (four cascades of 2048²) draws
    // texels far finer than the picture's pixels, slowly on a CPU device.
    .insert_resource(bevy::light::DirectionalLightShadowMap { size: 512 })
    .insert_resource(eye)
    .insert_resource(CameraMsaa(if msaa { Msaa::Sample4 } else { Msaa::Off }))
    .init_resource::<SunAt>();
    let pixels = Pixels::default();
    app.insert_resource(pixels.clone());
    let setup = move |mut commands: Commands,
                      mut images: ResMut<Assets<Image>>,
                      mut meshes: ResMut<Assets<Mesh>>,
                      mut materials: ResMut<Assets<StandardMaterial>>,
                      pixels: Res<Pixels>,
                      msaa: Res<CameraMsaa>| {
        let mut image = Image::new_target_texture(WIDTH, HEIGHT, TextureFormat::Rgba8UnormSrgb, None);
        image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
        image.asset_usage = RenderAssetUsages::RENDER_WORLD;
        let image = images.add(image);
        let camera = commands
            .spawn((
                Camera3d::default(),
                RenderTarget::Image(image.clone().into()),
                (eye.0)(0),
                msaa.0,
            ))
            .id();
        if hdr {
            commands.entity(camera).insert(bevy::camera::Hdr);
        }
        let mut grass = Grass::new(scene.clone()).unwrap();
        grass.lighting = if pbr { GrassLighting::Pbr } else { GrassLighting::Bevy };
        commands.spawn(grass);
        commands.spawn((
            DirectionalLight {
                shadow_maps_enabled: pbr,
                ..default()
            },
            Transform::default(),
        ));
        if ball {
            commands.spawn((
                Rolling,
                GrassCollider::sphere(0.6),
                Transform::from_translation(ball_at(0)),
            ));
        }
        if let Some(colour) = mesh {
            commands.spawn((
                Mesh3d(meshes.add(Cuboid::new(2.0, 2.0, 2.0))),
                MeshMaterial3d(materials.add(StandardMaterial {
                    base_color: colour,
                    // Diffuse only, as the grass's Lambert part.
                    perceptual_roughness: 1.0,
                    reflectance: 0.0,
                    ..default()
                })),
                Transform::from_xyz(0.0, 1.0, -4.0),
            ));
        }
        let sink = pixels.0.clone();
        commands
            .spawn(Readback::texture(image))
            .observe(move |event: On<ReadbackComplete>| *sink.lock().unwrap() = event.data.clone());
    };
    app.add_systems(Startup, setup);
    app.add_systems(Update, move_props);
    extra(&mut app);
    app.finish();
    app.cleanup();
    (app, pixels)
}

impl Default for SunAt {
    fn default() -> Self {
        SunAt(still_sun)
    }
}

/// The rolling balls (neither the camera nor the sun).
type BallsOnly = (With<Rolling>, Without<Camera3d>, Without<DirectionalLight>);

/// The samples every camera of a test app draws with (`Props::msaa`).
#[derive(Resource, Clone, Copy)]
struct CameraMsaa(Msaa);

/// The test's moving camera (neither the sun nor a second camera).
type FirstCamera = (With<Camera3d>, Without<DirectionalLight>, Without<SecondCamera>);

/// A second camera, drawn after the first (a minimap, the other half of a split screen), where
/// a test has one; it stays where it was put.
#[derive(Component)]
struct SecondCamera;

/// A second camera into an image of its own, read back every frame, where `eye` puts it.
fn second_camera(app: &mut App, eye: Transform) -> Pixels {
    let pixels = Pixels::default();
    let sink = pixels.0.clone();
    app.add_systems(
        Startup,
        move |mut commands: Commands, mut images: ResMut<Assets<Image>>, msaa: Res<CameraMsaa>| {
            let mut image = Image::new_target_texture(WIDTH, HEIGHT, TextureFormat::Rgba8UnormSrgb, None);
            image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
            image.asset_usage = RenderAssetUsages::RENDER_WORLD;
            let image = images.add(image);
            commands.spawn((
                SecondCamera,
                Camera3d::default(),
                Camera { order: 1, ..default() },
                RenderTarget::Image(image.clone().into()),
                eye,
                // As the first camera's: sward's own pass draws for cameras of one sample count.
                msaa.0,
            ));
            let sink = sink.clone();
            commands
                .spawn(Readback::texture(image))
                .observe(move |event: On<ReadbackComplete>| *sink.lock().unwrap() = event.data.clone());
        },
    );
    pixels
}

/// The ball, the camera and the sun where they are at this frame.
fn move_props(
    time: Res<Time>,
    eye: Res<Eye>,
    sun_at: Res<SunAt>,
    mut balls: Query<&mut Transform, BallsOnly>,
    mut camera: Single<&mut Transform, FirstCamera>,
    mut sun: Single<(&mut Transform, &mut DirectionalLight)>,
) {
    let k = (time.elapsed_secs() * 60.0).round() as u32;
    for mut ball in &mut balls {
        ball.translation = ball_at(k.min(FRAMES));
    }
    **camera = (eye.0)(k.min(FRAMES));
    let (toward, colour) = (sun_at.0)(k.min(FRAMES));
    *sun.0 = Transform::default().looking_to(
        -toward,
        if toward.x == 0.0 && toward.z == 0.0 {
            Vec3::Z
        } else {
            Vec3::Y
        },
    );
    sun.1.color = colour;
}

/// Whether `message` is the validation layer refusing a module only for its debug source's
/// language: Bevy 0.20 hands its shaders to wgpu as WGSL text (composed by WESL), and under
/// wgpu's DEBUG flag, which sward's messenger needs on sward's device, every such module's
/// SPIR-V names its source language as WGSL (10), which Debian 12's layer (1.3.239) does not
/// know. sward's own modules are naga's or glslang's and carry no such source.
fn bevy_s_wgsl_debug_source(message: &str) -> bool {
    message.contains("SPIR-V module not valid: Invalid source language operand: 10")
}

/// Whether `message` is the validation layer saying only that it is older than an extension
/// the device was made with: Bevy asks for every feature an adapter has, and on Mesa 25's
/// lavapipe that includes ray tracing's position fetch, which wgpu 30 turns on with
/// VK_KHR_ray_tracing_position_fetch (its features struct is VkStructureType 1000481000).
/// Debian 12's layer (1.3.239) predates it (Vulkan 1.3.253): it names the struct unknown at
/// device creation and the extension unsupported. Nothing else about the device goes unchecked,
/// and sward uses no ray tracing.
fn layer_predates_position_fetch(message: &str) -> bool {
    message.contains("unknown VkStructureType (1000481000)")
        || message.contains("Device Extension VK_KHR_ray_tracing_position_fetch is not supported by this layer")
}

/// Run `app` for `FRAMES` frames and a few more for the read-back, then take its last image and
/// check the validation layer was silent.
fn run(app: App, pixels: &Pixels) -> Vec<[u8; 4]> {
    walk(app, pixels).pop().expect("frames were drawn")
}

/// [`run`] for a test whose props stand still: a few frames settle the picture.
fn run_still(app: App, pixels: &Pixels) -> Vec<[u8; 4]> {
    walk_for(app, pixels, STILL_FRAMES).pop().expect("frames were drawn")
}

/// Run `app` for `FRAMES` frames and a few more for the read-back, taking the image read back
/// after each (the first few frames have none yet), and check the validation layer was silent.
fn walk(app: App, pixels: &Pixels) -> Vec<Vec<[u8; 4]>> {
    walk_for(app, pixels, FRAMES)
}

/// [`walk`] for `frames` frames (a test whose props stand still needs fewer).
fn walk_for(app: App, pixels: &Pixels, frames: u32) -> Vec<Vec<[u8; 4]>> {
    let mut views = walk_views(app, &[pixels], frames);
    views.pop().expect("one camera's images")
}

/// [`walk_for`], taking each frame the image of every camera in `cameras` (the first camera's
/// and a second's, say): per camera, its images.
fn walk_views(mut app: App, cameras: &[&Pixels], frames: u32) -> Vec<Vec<Vec<[u8; 4]>>> {
    let mut views = vec![Vec::new(); cameras.len()];
    for _ in 0..frames + 4 {
        app.update();
        for (images, pixels) in views.iter_mut().zip(cameras) {
            let bytes = pixels.0.lock().unwrap().clone();
            images.push(
                bytes
                    .as_chunks::<4>()
                    .0
                    .iter()
                    .map(|p| [p[0], p[1], p[2], p[3]])
                    .collect::<Vec<_>>(),
            );
        }
    }
    match app.world().get_resource::<GrassRoute>() {
        Some(GrassRoute::Vulkan) => {
            let context = app.world().get_resource::<SwardContext>().cloned();
            let context = context.expect("sward took Bevy's device back (SwardContext in the main world)");
            let messages: Vec<String> = context
                .0
                .take_validation_messages()
                .into_iter()
                .filter(|m| !bevy_s_wgsl_debug_source(m) && !layer_predates_position_fetch(m))
                .collect();
            assert!(context.0.validating(), "the validation layer is not active");
            assert!(messages.is_empty(), "validation:\n{}", messages.join("\n"));
        }
        Some(GrassRoute::Portable(_) | GrassRoute::Unavailable(_)) => {
            let messages = wgpu_messages::take();
            assert!(messages.is_empty(), "wgpu's validation:\n{}", messages.join("\n"));
        }
        None => panic!("the plugin said nothing of the grass's route"),
    }
    for images in &views {
        let last = images.last().expect("frames were drawn");
        assert_eq!(last.len(), (WIDTH * HEIGHT) as usize, "no frame was read back");
    }
    views
}

/// Pixels of `a` and `b` (images of one size) whose colour differs by more than 24 levels in a
/// channel.
fn pixels_apart(a: &[[u8; 4]], b: &[[u8; 4]]) -> usize {
    a.iter()
        .zip(b)
        .filter(|(a, b)| (0..3).any(|c| a[c].abs_diff(b[c]) > 24))
        .count()
}

fn is_grass(p: [u8; 4]) -> bool {
    p[1] > p[2] && p[1] > p[0]
}

fn is_cube(p: [u8; 4]) -> bool {
    p[0] > 60 && p[0] as u32 > 2 * p[1].max(p[2]) as u32
}

fn keep(name: &str, pixels: &[[u8; 4]]) {
    let path = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("{name}-actual.png"));
    let bytes = pixels.iter().flatten().copied().collect();
    if let Some(image) = image::RgbaImage::from_raw(WIDTH, HEIGHT, bytes) {
        image.save(path).unwrap();
    }
}

#[test]
fn a_headless_bevy_app_draws_the_grass_a_collider_s_trail_and_a_mesh_that_hides_it() {
    // Bevy's default camera: 4× MSAA.
    let props = Props {
        msaa: true,
        ball: true,
        mesh: Some(RED_CUBE),
        ..STILL
    };
    let (with_ball, pixels) = app(grass_scene(), props);
    let trail = run(with_ball, &pixels);
    keep("bevy-trail", &trail);
    let (without, pixels) = app(grass_scene(), Props { ball: false, ..props });
    let still = run(without, &pixels);
    keep("bevy-still", &still);
    let grass = still.iter().filter(|&&p| is_grass(p)).count();
    assert!(
        grass * 4 > still.len(),
        "little grass in Bevy's image: {grass} of {} pixels",
        still.len()
    );
    let cube = still.iter().filter(|&&p| is_cube(p)).count();
    assert!(
        cube > 300,
        "the Bevy cube shows in only {cube} pixels: grass is drawn over it"
    );
    // The trail: pixels that differ between the two apps, all from the collider's passage.
    let differ = pixels_apart(&trail, &still);
    assert!(differ > 150, "the collider left no trail: {differ} pixels differ");
}

/// The same app on the render device Bevy opens itself (its default: here lavapipe, through
/// wgpu's Vulkan backend), with no `render_plugin`: sward's portable passes simulate and cull
/// the grass, Bevy draws it in its passes, as on the device sward opens: the grass, the
/// collider's trail, the cube in front, the picture within 2 % of pixels of sward's own
/// device's. (Not on wgpu's GL backend: Bevy's own PBR shaders do not compile on Mesa's GL
/// there — Bevy's GL is its WebGL2 build.)
#[test]
fn on_bevy_s_own_device_the_portable_passes_draw_the_grass_its_trail_and_the_cube_that_hides_it() {
    let props = Props {
        ball: true,
        mesh: Some(RED_CUBE),
        pbr: true,
        ..STILL
    };
    let (reference, pixels) = app(grass_scene(), props);
    let reference = run(reference, &pixels);
    keep("bevy-device-reference", &reference);
    let device = Device::Bevy;
    let (with_ball, pixels) = app(grass_scene(), Props { device, ..props });
    let route = with_ball.world().get_resource::<GrassRoute>().cloned();
    assert!(
        matches!(route, Some(GrassRoute::Portable(_))),
        "the grass is not on the portable passes: {route:?}"
    );
    let trail = run(with_ball, &pixels);
    keep("bevy-device-trail", &trail);
    let (without, pixels) = app(
        grass_scene(),
        Props {
            ball: false,
            device,
            ..props
        },
    );
    let still = run(without, &pixels);
    let grass = still.iter().filter(|&&p| is_grass(p)).count();
    assert!(
        grass * 4 > still.len(),
        "little grass: {grass} of {} pixels",
        still.len()
    );
    let cube = still.iter().filter(|&&p| is_cube(p)).count();
    assert!(cube > 300, "the cube shows in only {cube} pixels");
    let differ = pixels_apart(&trail, &still);
    assert!(differ > 150, "the collider left no trail: {differ} pixels differ");
    // Against sward's own device: the same blades, stepped and culled by the other
    // renderer's passes, lit by the same Bevy PBR.
    let apart = pixels_apart(&trail, &reference);
    assert!(
        apart * 50 <= trail.len(),
        "{apart} pixels of {} differ from the picture on sward's own device",
        trail.len()
    );
}

/// Everything at once on Bevy's own device, as on sward's: the wind blowing, the sun high and
/// casting (the cube's shadow on the grass, the grass's on Bevy's ground), the camera's depth
/// and motion-vector prepass (the blades' last pose), the cube an occluder of the cull, and a
/// second camera culling for itself. Each camera's picture within 2 % of pixels of the same
/// app's on sward's device.
#[test]
fn on_bevy_s_own_device_shadows_the_prepass_occluders_and_a_second_camera_match_sward_s_device() {
    let pictures = |device: Device| {
        let mut scene = grass_scene();
        scene.wind = Scene::default().wind;
        let props = Props {
            pbr: true,
            mesh: Some(RED_CUBE),
            device,
            ..STILL
        };
        let mut second = None;
        let (mut app, pixels) = app_with(scene, props, |app| {
            second = Some(second_camera(app, west_corner_eye(0)));
        });
        app.insert_resource(SunAt(high_sun));
        with_prepass(&mut app, false);
        app.add_systems(Startup, bevy_ground);
        app.add_systems(
            Update,
            |mut commands: Commands, cube: Single<(Entity, Has<GrassOccluder>), With<Mesh3d>>| {
                if !cube.1 {
                    commands.entity(cube.0).insert(GrassOccluder::default());
                }
            },
        );
        let second = second.expect("made with the app");
        let mut views = walk_views(app, &[&pixels, &second], STILL_FRAMES);
        views
            .iter_mut()
            .map(|images| images.pop().expect("frames were drawn"))
            .collect::<Vec<_>>()
    };
    let reference = pictures(Device::Sward);
    let portable = pictures(Device::Bevy);
    for (k, (a, b)) in reference.iter().zip(&portable).enumerate() {
        keep(&format!("bevy-device-all-{k}-sward"), a);
        keep(&format!("bevy-device-all-{k}-bevy"), b);
        let grass = b.iter().filter(|&&p| is_grass(p)).count();
        assert!(
            grass * 8 > b.len(),
            "camera {k}: little grass on Bevy's device: {grass} pixels"
        );
        let apart = pixels_apart(a, b);
        eprintln!("camera {k}: {apart} of {} pixels apart", a.len());
        assert!(
            apart * 50 <= a.len(),
            "camera {k}: {apart} pixels of {} differ from the picture on sward's own device",
            a.len()
        );
    }
}

/// On a device that cannot run sward's passes (Bevy's, allowed four storage buffers a shader
/// stage, fewer than Bevy's draws of the blades bind), the app runs on: the route says why
/// there is no grass, no grass pipeline is made, and frames go on without a panic or an error
/// of sward's. (Bevy itself draws nothing at four storage buffers a stage on lavapipe: its own
/// pipelines fail validation there, so the picture is not checked.)
#[test]
fn on_a_device_without_what_the_grass_needs_the_app_runs_without_grass_and_says_why() {
    let props = Props {
        mesh: Some(RED_CUBE),
        pbr: true,
        device: Device::Starved,
        ..STILL
    };
    let (mut app, _) = app(grass_scene(), props);
    let route = app.world().get_resource::<GrassRoute>().cloned();
    let Some(GrassRoute::Unavailable(why)) = route else {
        panic!("a device of four storage buffers a stage took the grass: {route:?}");
    };
    assert!(
        why.contains("binds 4 storage buffers") && why.contains("bind 6"),
        "the reason does not say what is missing: {why}"
    );
    for _ in 0..STILL_FRAMES {
        app.update();
    }
    assert_eq!(
        app.world().get_resource::<GrassRoute>(),
        Some(&GrassRoute::Unavailable(why)),
        "the route changed while the app ran"
    );
    // Bevy's own pipelines are refused at four storage buffers a stage (its errors are kept
    // too): none of sward's may be.
    let messages = wgpu_messages::take();
    let sward_s: Vec<_> = messages.iter().filter(|m| m.contains("sward")).collect();
    assert!(sward_s.is_empty(), "wgpu's messages of sward's:\n{sward_s:?}");
}

/// How far the walking camera goes in `FRAMES` frames: several streamed tiles, and far beyond
/// a fixed field of the same blades.
const WALK: f32 = 60.0;

/// Walking along x at a person's height, looking at the ground a few steps ahead.
fn walking_eye(k: u32) -> Transform {
    let x = WALK * k as f32 / FRAMES as f32;
    Transform::from_xyz(x, 1.7, 0.0).looking_at(Vec3::new(x, 0.0, 3.5), Vec3::Y)
}

/// Bezier blades only (no instanced grass beyond them to hide a bare patch), 2 × 2 tiles of
/// the streamed window around the eye, or the same blades in a fixed field at the origin.
fn streamed_scene(stream: bool) -> Scene {
    let mut scene = grass_scene();
    scene.field.stream = stream;
    scene.field.blades = 4 * sward_core::stream::TILE_CELLS.pow(2);
    // The streamed blades are cut from the instanced grass's grid: 60 a square unit, tiles 8.3
    // units on a side, so the window reaches 4.1 units from the eye at least. Knee-high all
    // over (no clump of short grass to look like a gap).
    scene.instanced.grid.height = [0.6, 1.0];
    // Drawn up to where the window surely reaches (Bezier blades alone hand over to nothing).
    scene.cull.distance_max = 4.0;
    scene.field.stiffness = [14.0, 28.0];
    scene
}

/// The share of grass in the lower half of an image (the ground near the camera).
fn near_grass(image: &[[u8; 4]]) -> f32 {
    let lower = &image[image.len() / 2..];
    lower.iter().filter(|&&p| is_grass(p)).count() as f32 / lower.len() as f32
}

#[test]
fn a_streamed_field_follows_bevy_s_camera_wherever_it_walks() {
    let props = Props {
        eye: Eye(walking_eye),
        ..STILL
    };
    let (streamed, pixels) = app(streamed_scene(true), props);
    let walked = walk(streamed, &pixels);
    keep("bevy-streamed", walked.last().unwrap());
    // Every frame read back, from the first with grass to the last, 60 units from where the
    // walk began: knee-high grass covers 70–93 % of the ground there on lavapipe; a tile
    // missing before the eye leaves sky. The first read-back lags the frames by 4 or more
    // where the tests beside this one keep both cores busy (one cold run read frame 4 bare):
    // the grass shows by frame 8, and once shown, never leaves the ground bare again.
    let first = walked.iter().position(|image| near_grass(image) > 0.5);
    let first = first.expect("no frame shows grass before the walking camera");
    assert!(first <= 8, "the grass first shows at frame {first}");
    for (k, image) in walked.iter().enumerate().skip(first) {
        let share = near_grass(image);
        assert!(
            share > 0.5,
            "frame {k}: grass covers {:.0} % of the ground before the walking camera",
            share * 100.0
        );
    }
    // The same blades in a fixed field: the camera walks off it into bare ground.
    let (fixed, pixels) = app(streamed_scene(false), props);
    let walked = walk(fixed, &pixels);
    keep("bevy-fixed-walked", walked.last().unwrap());
    let share = near_grass(walked.last().unwrap());
    assert!(
        share < 0.05,
        "the fixed field covers {:.0} % of the ground 60 units away",
        share * 100.0
    );
}

/// Above and behind the walking camera at frame `k`, looking down at the grass around it: a
/// chase camera, drawn after the walker's (near enough that the scene's 4-unit distance cull
/// leaves it the grass it looks at).
fn chasing_eye(k: u32) -> Transform {
    let walker = walking_eye(k).translation;
    Transform::from_xyz(walker.x - 1.0, 2.4, walker.z - 1.0).looking_at(Vec3::new(walker.x, 0.0, 1.5), Vec3::Y)
}

/// Two cameras over a streamed field in motion, drawn in Bevy's passes, on sward's Vulkan device
/// and on Bevy's own (the portable passes): the walker carries the
/// window, and a chase camera following it sees the grass around the walker every frame, with
/// no frame where the grass it sees drops (a tile handed over late, a cull with another
/// view's window).
#[test]
fn a_second_camera_sees_the_streamed_grass_around_the_walker_frame_after_frame() {
    for device in [Device::Sward, Device::Bevy] {
        chase_camera_sees_the_walkers_grass(device);
    }
}

fn chase_camera_sees_the_walkers_grass(device: Device) {
    let props = Props {
        eye: Eye(walking_eye),
        pbr: true,
        device,
        ..STILL
    };
    let mut chase = None;
    let (app, pixels) = app_with(streamed_scene(true), props, |app| {
        chase = Some(second_camera(app, chasing_eye(0)));
        app.add_systems(
            Update,
            |time: Res<Time>, mut camera: Single<&mut Transform, With<SecondCamera>>| {
                let k = (time.elapsed_secs() * 60.0).round() as u32;
                **camera = chasing_eye(k.min(FRAMES));
            },
        );
    });
    let chase = chase.expect("made with the app");
    let views = walk_views(app, &[&pixels, &chase], FRAMES);
    let chased = &views[1];
    keep(&format!("bevy-chase-camera-{device:?}"), chased.last().unwrap());
    let shares: Vec<f32> = chased.iter().skip(4).map(|image| near_grass(image)).collect();
    for (k, pair) in shares.windows(2).enumerate() {
        assert!(
            pair[1] > 0.4,
            "{device:?}, frame {}: the chase camera sees grass over {:.0} % of the ground near it",
            k + 5,
            pair[1] * 100.0
        );
        assert!(
            pair[1] > pair[0] - 0.1,
            "{device:?}, frame {}: the grass the chase camera sees dropped from {:.0} % to {:.0} %",
            k + 5,
            pair[0] * 100.0,
            pair[1] * 100.0
        );
    }
}

/// From this frame on, a system recolours the grass.
const RECOLOURED_AT: u32 = 24;

/// Red-dominant pixels: the recoloured grass.
fn is_red(p: [u8; 4]) -> bool {
    p[0] > 60 && p[0] as u32 > 2 * p[1].max(p[2]) as u32
}

#[test]
fn a_bevy_system_changes_the_grass_while_the_app_runs() {
    let (mut app, pixels) = app(grass_scene(), STILL);
    // A system of the app's own, as a game changes its grass: red blades from a frame on.
    app.add_systems(Update, |time: Res<Time>, mut grass: Query<&mut Grass>| {
        if (time.elapsed_secs() * 60.0).round() as u32 == RECOLOURED_AT {
            for mut grass in &mut grass {
                grass.scene.shading.root_color = glam::Vec3::new(0.6, 0.0, 0.0);
                grass.scene.shading.tip_color = glam::Vec3::new(0.9, 0.05, 0.05);
            }
        }
    });
    let frames = walk(app, &pixels);
    let share = |image: &[[u8; 4]], what: fn([u8; 4]) -> bool| {
        image.iter().filter(|&&p| what(p)).count() as f32 / image.len() as f32
    };
    // Read back a few frames late: frame 12 is well before the change, the last well after.
    let (before, after) = (&frames[12], frames.last().unwrap());
    keep("bevy-recoloured", after);
    assert!(
        share(before, is_grass) > 0.25 && share(before, is_red) < 0.01,
        "before the change the grass is green: {:.2} green, {:.2} red",
        share(before, is_grass),
        share(before, is_red)
    );
    assert!(
        share(after, is_red) > 0.25 && share(after, is_grass) < 0.05,
        "after the change the grass is red: {:.2} red, {:.2} green",
        share(after, is_red),
        share(after, is_grass)
    );
}

/// The lighting test's phases: from these frames on the sun turns red, then below the ground,
/// then a point light shines between the camera and the cube.
const RED_SUN: u32 = 13;
const SUN_BELOW: u32 = 26;
const LAMP_ON: u32 = 39;

/// The sun of the lighting test at frame `k`: high and white, then red, then turned to shine up
/// from below the ground.
fn changing_sun(k: u32) -> (Vec3, Color) {
    if k < RED_SUN {
        (Vec3::new(1.0, 3.0, -2.0), Color::WHITE)
    } else if k < SUN_BELOW {
        (Vec3::new(1.0, 3.0, -2.0), Color::srgb(1.0, 0.35, 0.35))
    } else {
        (Vec3::new(0.0, -1.0, 0.0), Color::WHITE)
    }
}

/// A bright grey pixel: the lighting test's cube under the white sun.
fn is_grey(p: [u8; 4]) -> bool {
    let (lo, hi) = (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]));
    hi > 100 && hi - lo < 30
}

/// Mean colour (the image's bytes, averaged) of the pixels `mask` marks.
fn mean_of(image: &[[u8; 4]], mask: &[bool]) -> [f32; 3] {
    let n = mask.iter().filter(|&&m| m).count().max(1) as f32;
    [0, 1, 2].map(|c| {
        image
            .iter()
            .zip(mask)
            .filter(|(_, &m)| m)
            .map(|(p, _)| p[c] as f32)
            .sum::<f32>()
            / n
    })
}

fn brightness([r, g, b]: [f32; 3]) -> f32 {
    r + g + b
}

/// Bevy's lights light the grass as they light a Bevy mesh beside it: the sun recoloured red,
/// both go redder; turned below the ground, both go dark (but for the ambient light); a point
/// light switched on before them, both brighten. Lit by the scene's own sun
/// (`GrassLighting::Scene`, all the grass had before) it did none of these.
#[test]
fn bevy_s_sun_lights_the_grass_as_it_lights_a_mesh() {
    sun_lights_the_grass_as_it_lights_a_mesh(false);
}

/// The same, the grass drawn in Bevy's own passes, lit by Bevy's PBR (`GrassLighting::Pbr`).
#[test]
fn bevy_s_sun_lights_the_grass_drawn_in_bevy_s_passes_as_it_lights_a_mesh() {
    sun_lights_the_grass_as_it_lights_a_mesh(true);
}

fn sun_lights_the_grass_as_it_lights_a_mesh(pbr: bool) {
    let props = Props {
        mesh: Some(Color::srgb(0.6, 0.6, 0.6)),
        hdr: true,
        pbr,
        ..STILL
    };
    let (mut app, pixels) = app(grass_scene(), props);
    app.insert_resource(SunAt(changing_sun));
    app.add_systems(Update, |time: Res<Time>, mut commands: Commands| {
        if (time.elapsed_secs() * 60.0).round() as u32 == LAMP_ON {
            commands.spawn((
                PointLight {
                    intensity: 200_000.0,
                    range: 20.0,
                    ..default()
                },
                Transform::from_xyz(0.0, 1.5, -6.5),
            ));
        }
    });
    let frames = walk(app, &pixels);
    // Read back a few frames late: each image is well inside one phase.
    let at = |k: u32| &frames[k as usize - 3];
    let (white, red, below, lamp) = (at(RED_SUN), at(SUN_BELOW), at(LAMP_ON), frames.last().unwrap());
    let shape = if pbr { "pbr" } else { "bevy" };
    keep(&format!("{shape}-sun-white"), white);
    keep(&format!("{shape}-sun-red"), red);
    keep(&format!("{shape}-sun-below"), below);
    keep(&format!("{shape}-lamp"), lamp);
    let grass: Vec<bool> = white.iter().map(|&p| is_grass(p)).collect();
    let cube: Vec<bool> = white.iter().map(|&p| is_grey(p)).collect();
    assert!(
        grass.iter().filter(|&&g| g).count() > 2000,
        "too little grass under the white sun"
    );
    assert!(
        cube.iter().filter(|&&c| c).count() > 300,
        "too little cube under the white sun"
    );
    let [gw, gr, gb, gl] = [white, red, below, lamp].map(|image| mean_of(image, &grass));
    let [cw, cr, cb, cl] = [white, red, below, lamp].map(|image| mean_of(image, &cube));
    eprintln!("grass: white {gw:?}, red {gr:?}, below {gb:?}, lamp {gl:?}; cube: white {cw:?}, red {cr:?}, below {cb:?}, lamp {cl:?}");
    // Red sunlight: less green on both, by comparable shares.
    let (grass_green, cube_green) = (gr[1] / gw[1], cr[1] / cw[1].max(1.0));
    assert!(
        grass_green < 0.85,
        "the grass keeps {grass_green:.2} of its green under a red sun"
    );
    assert!(
        (grass_green - cube_green).abs() < 0.3,
        "under a red sun the grass keeps {grass_green:.2} of its green, the mesh {cube_green:.2}"
    );
    // The sun below the ground: both darken.
    let (grass_dark, cube_dark) = (brightness(gb) / brightness(gw), brightness(cb) / brightness(cw));
    assert!(
        grass_dark < 0.7,
        "with the sun below the ground the grass keeps {grass_dark:.2} of its light"
    );
    assert!(
        cube_dark < 0.7,
        "with the sun below the ground the mesh keeps {cube_dark:.2} of its light"
    );
    // A point light: both brighten.
    let (grass_lit, cube_lit) = (brightness(gl) / brightness(gb), brightness(cl) / brightness(cb));
    assert!(
        grass_lit > 1.3,
        "a point light brightens the grass only {grass_lit:.2} times"
    );
    assert!(
        cube_lit > 1.3,
        "a point light brightens the mesh only {cube_lit:.2} times"
    );
}

/// Grass of another technique than the Bezier blades, on sward's Vulkan device, asking for
/// Bevy's passes (the default): instanced grass, drawn there by the portable passes' lists (not
/// turned over to sward's own pass: the grass's lighting stays Bevy's PBR), still seen.
#[test]
fn on_sward_s_vulkan_device_bevy_s_passes_draw_instanced_grass() {
    let (mut app, pixels) = app(generated_scene(), Props { pbr: true, ..STILL });
    app.add_systems(Update, |grass: Query<&Grass>| {
        assert!(grass.iter().all(|g| g.lighting == GrassLighting::default()));
    });
    let image = run_still(app, &pixels);
    keep("instanced-in-bevy-s-passes", &image);
    let share = grass_share(&image);
    assert!(
        share > 0.25,
        "the instanced grass covers {:.0} % of the image",
        share * 100.0
    );
}

/// The frame from which the fog test's camera has Bevy's `DistanceFog`.
const FOG_FROM: u32 = 8;

/// How far `after` went from `before` toward `fog`: 0 not at all, 1 all the way.
fn toward(before: [f32; 3], after: [f32; 3], fog: [f32; 3]) -> f32 {
    let way = [0, 1, 2].map(|c| fog[c] - before[c]);
    let went = [0, 1, 2].map(|c| after[c] - before[c]);
    let dot = |a: [f32; 3], b: [f32; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    dot(went, way) / dot(way, way)
}

/// Bevy's distance fog covers the grass as it covers a Bevy mesh beside it, in sward's own pass
/// and in Bevy's: a magenta exponential fog on the camera takes the grass and the cube (both a
/// few units away) about as far toward magenta.
#[test]
fn bevy_s_distance_fog_covers_the_grass_as_it_covers_a_mesh() {
    const FOG: [f32; 3] = [230.0, 20.0, 230.0];
    for pbr in [false, true] {
        let shape = if pbr { "Bevy's passes" } else { "sward's own pass" };
        let props = Props {
            mesh: Some(RED_CUBE),
            pbr,
            ..STILL
        };
        let (mut app, pixels) = app(grass_scene(), props);
        app.add_systems(
            Update,
            |time: Res<Time>, mut commands: Commands, camera: Single<Entity, FirstCamera>| {
                let k = (time.elapsed_secs() * 60.0).round() as u32;
                if k == FOG_FROM {
                    commands.entity(*camera).insert(DistanceFog {
                        color: Color::srgb_u8(FOG[0] as u8, FOG[1] as u8, FOG[2] as u8),
                        directional_light_color: Color::NONE,
                        falloff: FogFalloff::Exponential { density: 0.12 },
                        ..default()
                    });
                }
            },
        );
        let frames = walk_for(app, &pixels, 2 * FOG_FROM);
        let (clear, foggy) = (&frames[FOG_FROM as usize - 3], frames.last().unwrap());
        keep(&format!("fog-clear-{pbr}"), clear);
        keep(&format!("fog-foggy-{pbr}"), foggy);
        let grass: Vec<bool> = clear.iter().map(|&p| is_grass(p)).collect();
        let cube: Vec<bool> = clear.iter().map(|&p| is_cube(p)).collect();
        assert!(grass_share(clear) > 0.25, "{shape}: the grass is in view");
        assert!(
            cube.iter().filter(|&&c| c).count() > 200,
            "{shape}: the cube is in view"
        );
        let [grass, cube] = [grass, cube].map(|mask| toward(mean_of(clear, &mask), mean_of(foggy, &mask), FOG));
        assert!(
            cube > 0.2,
            "{shape}: the fog took the cube {:.0} % of the way to its colour",
            cube * 100.0
        );
        assert!(
            grass > 0.6 * cube && grass < 1.6 * cube,
            "{shape}: the fog took the grass {:.0} % of the way to its colour, and the cube {:.0} %",
            grass * 100.0,
            cube * 100.0
        );
    }
}

/// Like a Bevy mesh, the grass can be hidden (`Visibility`) and kept off a camera's render
/// layers (`RenderLayers`): hidden until frame 4, shown until 14, hidden until 24, then shown on
/// layer 1, which the camera (layer 0) does not see; drawn by sward's own pass and in Bevy's.
#[test]
fn hidden_grass_and_grass_on_another_layer_are_not_drawn() {
    for pbr in [false, true] {
        let shape = if pbr { "Bevy's passes" } else { "sward's own pass" };
        let (mut app, pixels) = app(grass_scene(), Props { pbr, ..STILL });
        app.add_systems(
            Update,
            |time: Res<Time>, mut commands: Commands, mut grass: Single<(Entity, &mut Visibility), With<Grass>>| {
                let k = (time.elapsed_secs() * 60.0).round() as u32;
                // Hidden at first too: the grass's scene reaches the GPU once it is shown.
                *grass.1 = if k < 4 || (14..24).contains(&k) {
                    Visibility::Hidden
                } else {
                    Visibility::Inherited
                };
                if k == 24 {
                    commands
                        .entity(grass.0)
                        .insert(bevy::camera::visibility::RenderLayers::layer(1));
                }
            },
        );
        let frames = walk_for(app, &pixels, 32);
        // Read back a few frames late: each image is well inside its phase.
        let (shown, hidden, elsewhere) = (
            grass_share(&frames[11]),
            grass_share(&frames[21]),
            grass_share(frames.last().unwrap()),
        );
        assert!(
            shown > 0.25,
            "{shape}: shown, the grass covers {:.0} % of the image",
            shown * 100.0
        );
        assert!(
            hidden < 0.01,
            "{shape}: hidden, the grass still covers {:.0} %",
            hidden * 100.0
        );
        assert!(
            elsewhere < 0.01,
            "{shape}: on a layer the camera does not see, the grass covers {:.0} %",
            elsewhere * 100.0
        );
    }
}

/// Low over the field's -x, -z corner, looking into it: it sees none of the other corner.
fn west_corner_eye(_: u32) -> Transform {
    Transform::from_xyz(-2.5, 1.0, -2.5).looking_at(Vec3::new(-6.0, 0.0, -6.0), Vec3::Y)
}

/// Low over the field's +x, +z corner, looking into it.
fn east_corner_eye(_: u32) -> Transform {
    Transform::from_xyz(2.5, 1.0, 2.5).looking_at(Vec3::new(6.0, 0.0, 6.0), Vec3::Y)
}

fn grass_share(image: &[[u8; 4]]) -> f32 {
    image.iter().filter(|&&p| is_grass(p)).count() as f32 / image.len() as f32
}

/// Frames enough for a still scene without wind.
const STILL_FRAMES: u32 = 12;

/// Two cameras of one app look into opposite corners of the field (a split screen, a minimap):
/// each culls the grass for itself, so the second sees its corner's grass as it does when it
/// is the only camera (the first camera's cull would leave it none), in sward's own pass and
/// in Bevy's.
#[test]
fn each_of_two_cameras_culls_the_grass_for_itself() {
    for pbr in [false, true] {
        let shape = if pbr { "Bevy's passes" } else { "sward's own pass" };
        let props = Props {
            eye: Eye(west_corner_eye),
            pbr,
            ..STILL
        };
        let mut second = None;
        let (both, pixels) = app_with(grass_scene(), props, |app| {
            second = Some(second_camera(app, east_corner_eye(0)));
        });
        // Nothing moves: a few frames settle the picture.
        let first = walk_for(both, &pixels, STILL_FRAMES).pop().expect("frames were drawn");
        let second = second.expect("made with the app");
        let second = second
            .0
            .lock()
            .unwrap()
            .as_chunks::<4>()
            .0
            .iter()
            .map(|p| [p[0], p[1], p[2], p[3]])
            .collect::<Vec<_>>();
        let alone = Props {
            eye: Eye(east_corner_eye),
            ..props
        };
        let (alone, pixels) = app(grass_scene(), alone);
        let alone = walk_for(alone, &pixels, STILL_FRAMES).pop().expect("frames were drawn");
        keep(&format!("two-cameras-first-{pbr}"), &first);
        keep(&format!("two-cameras-second-{pbr}"), &second);
        keep(&format!("two-cameras-alone-{pbr}"), &alone);
        let (first, second, alone) = (grass_share(&first), grass_share(&second), grass_share(&alone));
        assert!(
            first > 0.3,
            "{shape}: the first camera sees grass over {:.0} % of its image",
            first * 100.0
        );
        assert!(
            alone > 0.3,
            "{shape}: alone, the second camera sees grass over {:.0} %",
            alone * 100.0
        );
        assert!(
            (second - alone).abs() < 0.02,
            "{shape}: beside the first camera, the second sees grass over {:.1} % of its image, and {:.1} % alone",
            second * 100.0,
            alone * 100.0
        );
    }
}

/// The frame from which a mesh-less occluder stands on the field's left.
const MESHLESS_OCCLUDER_FROM: u32 = 12;

/// The grass's share of the left and right halves of an image.
fn grass_by_halves(image: &[[u8; 4]]) -> [f32; 2] {
    let mut halves = [0u32; 2];
    for (i, &p) in image.iter().enumerate() {
        let right = (i as u32 % WIDTH) >= WIDTH / 2;
        halves[right as usize] += is_grass(p) as u32;
    }
    halves.map(|n| n as f32 / (image.len() / 2) as f32)
}

/// Bevy's meshes hide grass in the cull of the grass drawn in Bevy's passes, as sward's own
/// occluders do. Marked as a [`GrassOccluder`], the cube standing in the grass is packed into
/// spheres inside it, which leave the picture as the same app without them draws it (they
/// hide only what the cube hides). And the cull reads the spheres: a mesh-less occluder on the
/// left takes the grass behind it away (no mesh is drawn there, so the hole shows).
#[test]
fn bevy_s_meshes_hide_the_grass_behind_them_in_the_cull_of_bevy_s_passes() {
    let props = Props {
        mesh: Some(RED_CUBE),
        pbr: true,
        ..STILL
    };
    let (plain, pixels) = app(grass_scene(), props);
    let plain = walk_for(plain, &pixels, 2 * MESHLESS_OCCLUDER_FROM);
    let (mut app, pixels) = app(grass_scene(), props);
    app.add_systems(
        Update,
        |time: Res<Time>, mut commands: Commands, cube: Single<(Entity, Has<GrassOccluder>), With<Mesh3d>>| {
            let k = (time.elapsed_secs() * 60.0).round() as u32;
            if !cube.1 {
                commands.entity(cube.0).insert(GrassOccluder::default());
            }
            if k == MESHLESS_OCCLUDER_FROM {
                commands.spawn((
                    GrassOccluder::spheres(vec![Vec4::new(0.0, 0.0, 0.0, 1.2)]),
                    Transform::from_xyz(2.5, 0.6, -3.0),
                ));
            }
        },
    );
    let frames = walk_for(app, &pixels, 2 * MESHLESS_OCCLUDER_FROM);
    // A frame before the mesh-less occluder came (read back a few frames late), and the last,
    // well after; each against the plain app's same frame.
    let before = MESHLESS_OCCLUDER_FROM as usize - 3;
    let (packed, hiding) = (&frames[before], frames.last().unwrap());
    let (plain, plain_last) = (&plain[before], plain.last().unwrap());
    keep("occluder-plain", plain);
    keep("occluder-packed", packed);
    keep("occluder-hiding", hiding);
    let changed = plain
        .iter()
        .zip(packed)
        .filter(|(a, b)| a.iter().zip(b.iter()).any(|(x, y)| x.abs_diff(*y) > 24))
        .count();
    assert!(
        changed as f32 / plain.len() as f32 <= 0.005,
        "the cube's spheres changed {changed} pixels of the picture: they hid grass the cube does not"
    );
    assert!(
        plain.iter().filter(|&&p| is_cube(p)).count() > 200,
        "the cube is in view"
    );
    let ([left_before, right_before], [left, right]) = (grass_by_halves(plain_last), grass_by_halves(hiding));
    // The camera looks along +z: the world's +x is the image's left.
    assert!(
        left < left_before - 0.04,
        "the mesh-less occluder left grass over {:.1} % of the left half, as much as without it ({:.1} %)",
        left * 100.0,
        left_before * 100.0
    );
    assert!(
        (right - right_before).abs() < 0.01,
        "the right half has grass over {:.1} %, without the mesh-less occluder {:.1} %",
        right * 100.0,
        right_before * 100.0
    );
}

/// High and behind the camera's side of the field: a hovering mesh's shadow falls beyond it.
fn high_sun(_: u32) -> (Vec3, Color) {
    (Vec3::new(0.0, 1.0, -1.0), Color::WHITE)
}

/// The grass drawn in Bevy's own passes (`GrassLighting::Pbr`) receives Bevy's shadows: a slab
/// hovering over the field darkens the grass under it, which the same slab casting no shadow
/// (`NotShadowCaster`) leaves lit. (Drawn by sward's own pass, the grass had no Bevy shadow.)
#[test]
fn a_bevy_mesh_s_shadow_darkens_the_grass_drawn_in_bevy_s_passes() {
    let shadowed = |casts: bool| {
        let props = Props { pbr: true, ..STILL };
        let (mut app, pixels) = app(grass_scene(), props);
        app.insert_resource(SunAt(high_sun));
        app.add_systems(
            Startup,
            move |mut commands: Commands,
                  mut meshes: ResMut<Assets<Mesh>>,
                  mut materials: ResMut<Assets<StandardMaterial>>| {
                let slab = commands
                    .spawn((
                        Mesh3d(meshes.add(Cuboid::new(1.6, 0.2, 1.6))),
                        MeshMaterial3d(materials.add(StandardMaterial::from(Color::srgb(0.6, 0.6, 0.6)))),
                        Transform::from_xyz(0.0, 1.9, -4.0),
                    ))
                    .id();
                if !casts {
                    commands.entity(slab).insert(bevy::light::NotShadowCaster);
                }
            },
        );
        run_still(app, &pixels)
    };
    let (lit, dark) = (shadowed(false), shadowed(true));
    keep("pbr-no-shadow", &lit);
    keep("pbr-shadow", &dark);
    let grass: Vec<bool> = lit
        .iter()
        .zip(&dark)
        .map(|(&a, &b)| is_grass(a) && is_grass(b))
        .collect();
    let seen = grass.iter().filter(|&&g| g).count();
    assert!(seen > 2000, "Bevy drew only {seen} pixels of grass");
    let light = |p: [u8; 4]| p[0] as i32 + p[1] as i32 + p[2] as i32;
    let change: Vec<i32> = lit.iter().zip(&dark).map(|(&a, &b)| light(a) - light(b)).collect();
    let darker = change.iter().zip(&grass).filter(|(&c, &g)| g && c > 30).count();
    let lighter = change.iter().zip(&grass).filter(|(&c, &g)| g && c < -30).count();
    eprintln!("grass pixels {seen}: darker under the slab's shadow {darker}, lighter {lighter}");
    assert!(darker > 80, "the slab's shadow darkens only {darker} pixels of grass");
    assert!(
        lighter * 4 < darker,
        "{lighter} pixels of grass are lighter with the shadow, {darker} darker: not a shadow"
    );
}

/// Back from the field's near edge, looking over it.
fn back_eye(_: u32) -> Transform {
    Transform::from_xyz(0.0, 3.0, -15.0).looking_at(Vec3::new(0.0, 0.0, -4.0), Vec3::Y)
}

/// Low, beyond the field's far edge: the grass's shadows fall toward the camera.
fn low_sun(_: u32) -> (Vec3, Color) {
    (Vec3::new(0.0, 0.6, 1.0), Color::WHITE)
}

/// The grass drawn in Bevy's own passes casts into Bevy's shadow maps: on a Bevy ground under
/// a low sun its shadow falls past the field's near edge, which the same grass with
/// `NotShadowCaster` does not darken.
#[test]
fn the_grass_drawn_in_bevy_s_passes_casts_its_shadow_on_bevy_s_ground() {
    let ground = |casts: bool| {
        let props = Props {
            pbr: true,
            eye: Eye(back_eye),
            ..STILL
        };
        let (mut app, pixels) = app(grass_scene(), props);
        app.insert_resource(SunAt(low_sun));
        app.add_systems(Startup, bevy_ground);
        if !casts {
            // Once the grass is there (the app's setup spawns it).
            app.add_systems(
                Update,
                |mut commands: Commands, grass: Query<Entity, (With<Grass>, Without<bevy::light::NotShadowCaster>)>| {
                    for grass in &grass {
                        commands.entity(grass).insert(bevy::light::NotShadowCaster);
                    }
                },
            );
        }
        run_still(app, &pixels)
    };
    let (bare, shaded) = (ground(false), ground(true));
    keep("pbr-ground-unshaded", &bare);
    keep("pbr-ground-shaded", &shaded);
    let plane: Vec<bool> = bare.iter().map(|&p| is_grey(p)).collect();
    let seen = plane.iter().filter(|&&g| g).count();
    assert!(seen > 500, "only {seen} pixels of Bevy's ground are seen");
    let light = |p: [u8; 4]| p[0] as i32 + p[1] as i32 + p[2] as i32;
    let darker = bare
        .iter()
        .zip(&shaded)
        .zip(&plane)
        .filter(|((&a, &b), &g)| g && light(a) - light(b) > 30)
        .count();
    eprintln!("ground pixels {seen}: {darker} in the grass's shadow");
    assert!(
        darker > 150,
        "the grass's shadow darkens only {darker} pixels of Bevy's ground"
    );
}

/// The last frame's motion vectors as the prepass wrote them (Rg16Float, row by row), copied
/// out of Bevy's render world into a buffer read once the app has run.
#[derive(Resource, Clone, Default)]
struct Motion(Arc<Mutex<Option<wgpu::Buffer>>>);

impl Motion {
    /// The motion vectors of the last frame copied (waits for the GPU).
    fn read(&self, device: &wgpu::Device) -> Vec<[f32; 2]> {
        let Some(buffer) = self.0.lock().unwrap().take() else {
            return Vec::new();
        };
        buffer.slice(..).map_async(wgpu::MapMode::Read, |_| {});
        let _ = device.poll(wgpu::PollType::wait_indefinitely());
        let bytes = buffer.slice(..).get_mapped_range().unwrap().to_vec();
        bytemuck::cast_slice::<u8, [f32; 2]>(&bytes).to_vec()
    }
}

/// Copy the camera's motion-vector texture, after the prepass, into a buffer read on the host
/// (the texture cannot be copied from: a compute pass reads it).
fn copy_motion_vectors(
    view: bevy::render::renderer::ViewQuery<&bevy::core_pipeline::prepass::ViewPrepassTextures>,
    mut ctx: bevy::render::renderer::RenderContext,
    motion: Res<Motion>,
    mut pipeline: Local<Option<wgpu::ComputePipeline>>,
) {
    let Some(vectors) = view.into_inner().motion_vectors.as_ref() else {
        return;
    };
    let device = ctx.render_device().wgpu_device().clone();
    let pipeline = pipeline.get_or_insert_with(|| {
        // Parsed here and handed over as naga's module, as Bevy hands over its shaders: a module
        // with WGSL source gets a SPIR-V source language the validation layer does not know.
        let module = wgpu::naga::front::wgsl::parse_str(
            "@group(0) @binding(0) var vectors: texture_2d<f32>;
                 @group(0) @binding(1) var<storage, read_write> read: array<vec2<f32>>;
                 @compute @workgroup_size(8, 8) fn main(@builtin(global_invocation_id) id: vec3<u32>) {
                     let size = textureDimensions(vectors);
                     if id.x < size.x && id.y < size.y {
                         read[id.y * size.x + id.x] = textureLoad(vectors, vec2<i32>(id.xy), 0).xy;
                     }
                 }",
        )
        .expect("the read-back shader");
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: None,
            source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(module)),
        });
        device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: None,
            layout: None,
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        })
    });
    let bytes = (WIDTH * HEIGHT * 8) as u64;
    let buffer = |usage| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size: bytes,
            usage,
            mapped_at_creation: false,
        })
    };
    let storage = buffer(wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC);
    let readable = buffer(wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ);
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&vectors.texture.default_view),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: storage.as_entire_binding(),
            },
        ],
    });
    let encoder = ctx.command_encoder();
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups(WIDTH.div_ceil(8), HEIGHT.div_ceil(8), 1);
    }
    encoder.copy_buffer_to_buffer(&storage, 0, &readable, 0, bytes);
    *motion.0.lock().unwrap() = Some(readable);
}

/// The render world of `app` copies each frame's motion vectors for `reader`.
fn copying_motion_vectors(app: &mut App, reader: Motion) {
    app.sub_app_mut(bevy::render::RenderApp)
        .insert_resource(reader)
        .add_systems(
            bevy::core_pipeline::schedule::Core3d,
            copy_motion_vectors
                .after(bevy::core_pipeline::Core3dSystems::Prepass)
                .before(bevy::core_pipeline::core_3d::main_opaque_pass_3d),
        );
}

/// A camera with Bevy's depth and motion-vector prepass (and `deferred`: the deferred G-buffer),
/// MSAA off, once the app's setup made it.
fn with_prepass(app: &mut App, deferred: bool) {
    app.add_systems(
        Update,
        move |mut commands: Commands,
              cameras: Query<Entity, (With<Camera3d>, Without<bevy::core_pipeline::prepass::DepthPrepass>)>| {
            for camera in &cameras {
                let mut camera = commands.entity(camera);
                camera.insert((
                    Msaa::Off,
                    bevy::core_pipeline::prepass::DepthPrepass,
                    bevy::core_pipeline::prepass::MotionVectorPrepass,
                ));
                if deferred {
                    camera.insert(bevy::core_pipeline::prepass::DeferredPrepass);
                }
            }
        },
    );
}

/// A Bevy ground beside and under the field.
fn bevy_ground(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    commands.spawn((
        Mesh3d(meshes.add(Plane3d::default().mesh().size(40.0, 40.0))),
        MeshMaterial3d(materials.add(StandardMaterial::from(Color::srgb(0.7, 0.7, 0.7)))),
    ));
}

/// The grass drawn in Bevy's passes is in the camera's prepass with motion vectors that carry
/// each blade's own motion: with the wind blowing and the camera still, the grass's pixels move
/// and Bevy's ground's do not.
#[test]
fn the_grass_s_motion_vectors_move_where_the_wind_sways_it_and_the_ground_s_do_not() {
    let mut scene = grass_scene();
    scene.wind = Scene::default().wind;
    let props = Props {
        pbr: true,
        eye: Eye(back_eye),
        ..STILL
    };
    let motion = Motion::default();
    let reader = motion.clone();
    let (mut app, pixels) = app_with(scene, props, move |app| copying_motion_vectors(app, reader));
    with_prepass(&mut app, false);
    app.add_systems(Startup, bevy_ground);
    let device = app
        .world()
        .resource::<bevy::render::renderer::RenderDevice>()
        .wgpu_device()
        .clone();
    let image = run(app, &pixels);
    keep("pbr-motion", &image);
    let vectors = motion.read(&device);
    assert_eq!(vectors.len(), image.len(), "the motion vectors were not read back");
    // In pixels.
    let moved = |v: [f32; 2]| (v[0] * WIDTH as f32).hypot(v[1] * HEIGHT as f32);
    let grass: Vec<f32> = image
        .iter()
        .zip(&vectors)
        .filter(|(&p, _)| is_grass(p))
        .map(|(_, &v)| moved(v))
        .collect();
    let ground: Vec<f32> = image
        .iter()
        .zip(&vectors)
        .filter(|(&p, _)| is_grey(p))
        .map(|(_, &v)| moved(v))
        .collect();
    // Moving: more than a thousandth of a pixel a frame (Bevy's own still meshes come out at
    // about 1e-5 px, rounding).
    const STILL_PX: f32 = 1e-3;
    let moving = grass.iter().filter(|&&m| m > STILL_PX).count();
    let quantile = |values: &[f32], q: f32| {
        let mut sorted = values.to_vec();
        sorted.sort_by(f32::total_cmp);
        sorted[(q * (sorted.len() - 1) as f32) as usize]
    };
    assert!(
        grass.len() > 500 && ground.len() > 500,
        "too little grass or ground seen"
    );
    let (grass_median, ground_95) = (quantile(&grass, 0.5), quantile(&ground, 0.95));
    eprintln!(
        "grass pixels {}: {moving} moving, median {grass_median:.4} px a frame; ground pixels {}: 95th percentile {ground_95} px",
        grass.len(),
        ground.len()
    );
    assert!(
        moving * 3 > grass.len() * 2,
        "only {moving} of {} grass pixels move in the wind",
        grass.len()
    );
    // (The ground pixels at the blades' edges move: the colour read back is a frame or two
    // older than the motion vectors.)
    assert!(ground_95 < STILL_PX, "the still ground moves {ground_95} px a frame");
}

/// On a deferred camera the grass drawn in Bevy's passes is in the G-buffer: it renders within
/// 3 levels of the forward camera's mean colour (lavapipe: 0.03), on sward's device and on
/// Bevy's own. The G-buffer has no diffuse transmission: the blades keep the diffuse share the
/// forward pass leaves them, and only the light through them from behind is lost, which this
/// front-lit view barely has.
#[test]
fn a_deferred_camera_renders_the_grass_as_the_forward_one() {
    let picture = |deferred: bool, device: Device| {
        let props = Props {
            pbr: true,
            mesh: Some(Color::srgb(0.6, 0.6, 0.6)),
            device,
            ..STILL
        };
        let (mut app, pixels) = app(grass_scene(), props);
        with_prepass(&mut app, deferred);
        if deferred {
            // The app's meshes are rendered deferred too (Bevy's default is forward).
            app.insert_resource(bevy::pbr::DefaultOpaqueRendererMethod::deferred());
        }
        run_still(app, &pixels)
    };
    let forward = picture(false, Device::Sward);
    keep("pbr-forward", &forward);
    for device in [Device::Sward, Device::Bevy] {
        let deferred = picture(true, device);
        keep(&format!("pbr-deferred-{device:?}"), &deferred);
        let both: Vec<bool> = forward
            .iter()
            .zip(&deferred)
            .map(|(&a, &b)| is_grass(a) && is_grass(b))
            .collect();
        let seen = both.iter().filter(|&&g| g).count();
        let shown = forward.iter().filter(|&&p| is_grass(p)).count();
        let [f, d] = [&forward, &deferred].map(|image| mean_of(image, &both));
        let difference = (0..3).map(|c| (f[c] - d[c]).abs()).fold(0.0, f32::max);
        eprintln!("{device:?}: grass in both {seen} of {shown} forward; mean colour forward {f:?}, deferred {d:?}");
        assert!(shown > 2000, "the forward camera shows only {shown} pixels of grass");
        assert!(
            seen * 10 > shown * 9,
            "{device:?}: the deferred camera shows grass on only {seen} of the forward's {shown} pixels"
        );
        assert!(
            difference < 12.0,
            "{device:?}: the deferred grass's mean colour is {difference:.1} levels off the forward's"
        );
    }
}

/// The frame Avian's colliders are put in the field.
#[cfg(feature = "avian")]
const COLLIDERS_AT: u32 = 12;

/// Avian's colliders in their own shapes (the `avian` feature): a capsule lying across the
/// field's -x side presses the grass there, a box standing on its +x side mows it (the trample
/// map), from the frame they are put there (no physics runs: the shapes alone); before it the
/// field is the same still grass. On sward's device and on Bevy's own (the portable passes).
#[cfg(feature = "avian")]
#[test]
fn avian_s_capsule_presses_the_grass_and_its_box_mows_it() {
    for device in [Device::Sward, Device::Bevy] {
        capsule_presses_and_box_mows(device);
    }
}

#[cfg(feature = "avian")]
fn capsule_presses_and_box_mows(device: Device) {
    use avian3d::prelude::Collider;
    use sward_bevy::GrassFromCollider;
    // With MSAA, as the mown share below was measured (without it the blades' edges count
    // differently).
    let props = Props {
        device,
        msaa: true,
        ..STILL
    };
    let (mut app, pixels) = app(grass_scene(), props);
    app.add_systems(
        Update,
        |time: Res<Time>, mut commands: Commands, mut done: Local<bool>| {
            let k = (time.elapsed_secs() * 60.0).round() as u32;
            if k >= COLLIDERS_AT && !std::mem::replace(&mut *done, true) {
                commands.spawn((
                    Collider::capsule(0.3, 3.0),
                    GrassFromCollider::default(),
                    Transform::from_xyz(-3.0, 0.3, -2.0)
                        .with_rotation(Quat::from_rotation_z(std::f32::consts::FRAC_PI_2)),
                ));
                commands.spawn((
                    Collider::cuboid(2.5, 1.0, 2.5),
                    GrassFromCollider::cutting(),
                    Transform::from_xyz(3.0, 0.5, -2.0),
                ));
            }
        },
    );
    // The mown blades shorten over many steps: the whole run.
    let frames = walk(app, &pixels);
    let (before, after) = (&frames[COLLIDERS_AT as usize - 2], frames.last().unwrap());
    keep(&format!("avian-before-{device:?}"), before);
    keep(&format!("avian-after-{device:?}"), after);
    let half = |image: &[[u8; 4]], left: bool| -> Vec<[u8; 4]> {
        image
            .iter()
            .enumerate()
            .filter(|(i, _)| ((*i as u32 % WIDTH) < WIDTH / 2) == left)
            .map(|(_, p)| *p)
            .collect()
    };
    let changed = pixels_apart;
    // The camera looks along +z: the field's +x side (the box) is the image's left half, its
    // -x side (the capsule) the right.
    let pressed = changed(&half(before, false), &half(after, false));
    assert!(
        pressed > 150,
        "{device:?}: the capsule changed only {pressed} pixels of its half"
    );
    let grass = |image: &[[u8; 4]]| image.iter().filter(|&&p| is_grass(p)).count();
    let (grown, mown) = (grass(&half(before, true)), grass(&half(after, true)));
    assert!(
        (mown as f32) < 0.9 * grown as f32,
        "{device:?}: the box mowed its half's grass only from {grown} to {mown} pixels"
    );
}

/// The frame a white environment map starts to light the scene.
const ENVIRONMENT_AT: u32 = 20;

/// No sun: below the field.
fn no_sun(_: u32) -> (Vec3, Color) {
    (Vec3::new(0.0, -1.0, -0.3), Color::WHITE)
}

/// A white cube map of one texel a face, as an environment map's diffuse and specular maps.
fn white_cube_map(images: &mut Assets<Image>) -> Handle<Image> {
    use bevy::render::render_resource::{Extent3d, TextureDimension, TextureViewDescriptor, TextureViewDimension};
    // Six texels of half floats 1.0 (0x3c00), alpha 1.
    let texel = [0x00u8, 0x3c, 0x00, 0x3c, 0x00, 0x3c, 0x00, 0x3c];
    let mut image = Image::new(
        Extent3d {
            width: 1,
            height: 1,
            depth_or_array_layers: 6,
        },
        TextureDimension::D2,
        texel.repeat(6),
        TextureFormat::Rgba16Float,
        RenderAssetUsages::RENDER_WORLD,
    );
    image.texture_view_descriptor = Some(TextureViewDescriptor {
        dimension: Some(TextureViewDimension::Cube),
        ..default()
    });
    images.add(image)
}

/// The grass drawn in Bevy's passes is lit by an environment map as a Bevy mesh is: with the sun
/// below the field, a white environment map put on the camera brightens both.
#[test]
fn an_environment_map_lights_the_grass_drawn_in_bevy_s_passes_as_it_lights_a_mesh() {
    let props = Props {
        mesh: Some(Color::srgb(0.6, 0.6, 0.6)),
        hdr: true,
        pbr: true,
        ..STILL
    };
    let (mut app, pixels) = app(grass_scene(), props);
    app.insert_resource(SunAt(no_sun));
    app.add_systems(
        Update,
        |time: Res<Time>,
         mut commands: Commands,
         mut images: ResMut<Assets<Image>>,
         camera: Single<Entity, With<Camera3d>>| {
            if (time.elapsed_secs() * 60.0).round() as u32 == ENVIRONMENT_AT {
                let map = white_cube_map(&mut images);
                commands.entity(*camera).insert(bevy::light::EnvironmentMapLight {
                    diffuse_map: map.clone(),
                    specular_map: map,
                    intensity: 1500.0,
                    ..default()
                });
            }
        },
    );
    let frames = walk_for(app, &pixels, ENVIRONMENT_AT + 10);
    let (dark, lit) = (&frames[ENVIRONMENT_AT as usize - 3], frames.last().unwrap());
    keep("environment-dark", dark);
    keep("environment-lit", lit);
    let grass: Vec<bool> = lit.iter().map(|&p| is_grass(p)).collect();
    let cube: Vec<bool> = lit.iter().map(|&p| is_grey(p)).collect();
    let count = |mask: &[bool]| mask.iter().filter(|&&m| m).count();
    assert!(count(&grass) > 2000, "too little grass under the environment map");
    assert!(count(&cube) > 300, "too little cube under the environment map");
    let gain = |mask: &[bool]| brightness(mean_of(lit, mask)) - brightness(mean_of(dark, mask));
    let (grass_gain, cube_gain) = (gain(&grass), gain(&cube));
    assert!(
        cube_gain > 60.0,
        "the environment map brightened the cube by only {cube_gain:.0} levels"
    );
    assert!(
        grass_gain > 0.3 * cube_gain,
        "the environment map brightened the grass by {grass_gain:.0} levels, the cube by {cube_gain:.0}"
    );
}

/// A camera looking across the field and past it, to the horizon.
fn horizon_eye(_: u32) -> Transform {
    Transform::from_xyz(0.0, 4.0, 5.0).looking_at(Vec3::new(0.0, 0.0, -40.0), Vec3::Y)
}

/// The meadow drawn by the whole level-of-detail chain: its Bezier blades near, the instanced
/// grass's four levels to 30 units, billboards beyond.
fn landscape_scene() -> Scene {
    let mut scene = grass_scene();
    scene.technique = sward_core::instanced::Technique::Landscape;
    scene.instanced.grid.radius = 30.0;
    // A third of the default density: the far rows the tests read are as covered (1.000 of them
    // either way), and the tests' frames on a CPU device quicker.
    scene.instanced.grid.density = 20.0;
    scene.instanced.lod_distances = [4.0, 10.0, 20.0];
    // Billboards to 100 units, past the far rows (80), not to the default 400: the 1.5 million
    // billboards of that disc were most of a frame's work on a CPU device.
    scene.billboard.grid.radius = 100.0;
    scene
}

/// The rows of the picture that show the ground past the Bezier field and its blades' tips (from
/// about 14 units to 80) below the horizon, as shares of the height from the top.
const FAR_ROWS: std::ops::Range<f32> = 0.45..0.70;

/// The share of the far rows' pixels that show something over Bevy's clear colour (whatever
/// lights it: Bevy's passes and sward's own light the grass differently).
fn far_grass(image: &[[u8; 4]]) -> f32 {
    let rows = (FAR_ROWS.start * HEIGHT as f32) as usize..(FAR_ROWS.end * HEIGHT as f32) as usize;
    let band = &image[rows.start * WIDTH as usize..rows.end * WIDTH as usize];
    band.iter().filter(|&&p| over_sky(p)).count() as f32 / band.len() as f32
}

/// Whether a pixel shows something over Bevy's clear colour.
fn over_sky(p: [u8; 4]) -> bool {
    let sky = SKY.to_srgba().to_u8_array();
    (0..3).any(|c| p[c].abs_diff(sky[c]) > 24)
}

/// The whole chain in Bevy's passes on Bevy's own device: past the Bezier field the generated
/// grass's levels and the billboards (their painted blades' coverage by alpha-to-coverage, as
/// in sward's own pass) cover the ground to the horizon as sward's own pass draws them on
/// sward's device, with the sun casting. The Bezier technique alone leaves those rows bare. On
/// sward's Vulkan device Bevy's passes draw the same chain, the same picture.
#[test]
fn bevy_s_passes_draw_the_generated_grass_and_billboards_to_the_horizon_on_either_device() {
    let picture = |scene: Scene, device: Device, pbr: bool| {
        // With MSAA: the billboards' painted blades are their coverage (alpha-to-coverage).
        let props = Props {
            msaa: true,
            pbr,
            eye: Eye(horizon_eye),
            device,
            ..STILL
        };
        let (app, pixels) = app(scene, props);
        run_still(app, &pixels)
    };
    let bezier = picture(grass_scene(), Device::Bevy, true);
    let chain = picture(landscape_scene(), Device::Bevy, true);
    let reference = picture(landscape_scene(), Device::Sward, false);
    let on_sward_s_device = picture(landscape_scene(), Device::Sward, true);
    keep("bevy-device-horizon-bezier", &bezier);
    keep("bevy-device-horizon-chain", &chain);
    keep("bevy-device-horizon-sward", &reference);
    keep("sward-device-horizon-chain", &on_sward_s_device);
    let [bare, covered, drawn_by_sward] = [&bezier, &chain, &reference].map(|image| far_grass(image));
    eprintln!(
        "grass in the far rows: Bezier alone {bare:.3}, the chain {covered:.3}, sward's pass {drawn_by_sward:.3}"
    );
    assert!(
        bare < 0.1,
        "the Bezier field alone reaches the far rows: {bare:.3} of them are grass"
    );
    assert!(
        covered > 0.9,
        "the far grass does not cover the far rows: {covered:.3} of them are grass"
    );
    assert!(
        (covered - drawn_by_sward).abs() < 0.05,
        "Bevy's passes cover {covered:.3} of the far rows, sward's own pass {drawn_by_sward:.3}"
    );
    // The same outline against the sky: the horizon's billboards as thin as sward's own.
    let outlines = chain
        .iter()
        .zip(&reference)
        .filter(|(a, b)| over_sky(**a) != over_sky(**b));
    let apart = outlines.count();
    eprintln!("{apart} of {} pixels over the sky in one picture only", chain.len());
    assert!(
        apart * 50 <= chain.len(),
        "{apart} of {} pixels are grass in one picture and sky in the other",
        chain.len()
    );
    // On sward's device, Bevy's passes and their lighting: as on Bevy's own device, not as
    // sward's own pass lights the grass.
    let [as_bevy_s, as_sward_s] = [&chain, &reference].map(|image| pixels_apart(&on_sward_s_device, image));
    eprintln!(
        "Bevy's passes on sward's device: {as_bevy_s} pixels apart from them on Bevy's, {as_sward_s} from sward's own pass"
    );
    assert!(
        as_bevy_s * 100 <= chain.len(),
        "on sward's device Bevy's passes draw the chain {as_bevy_s} pixels of {} apart from Bevy's device",
        chain.len()
    );
    assert!(
        as_sward_s > 4 * as_bevy_s.max(chain.len() / 200),
        "on sward's device the chain looks like sward's own pass ({as_sward_s} pixels apart) as much as Bevy's ({as_bevy_s})"
    );
}

/// The mean colour of the far rows' pixels that show grass over the sky.
fn far_colour(image: &[[u8; 4]]) -> [f32; 3] {
    let rows = (FAR_ROWS.start * HEIGHT as f32) as usize..(FAR_ROWS.end * HEIGHT as f32) as usize;
    let band = &image[rows.start * WIDTH as usize..rows.end * WIDTH as usize];
    let grass: Vec<bool> = band.iter().map(|&p| over_sky(p)).collect();
    mean_of(band, &grass)
}

/// The far field splatted inside Bevy's frame (on Bevy's own device, which has 64-bit atomic
/// min and max on lavapipe): the generated grass and billboards beyond their splat distances
/// are splatted by the portable passes and resolved into Bevy's passes — lit by Bevy's PBR,
/// their depth written — and the picture is the one Bevy's passes draw with the far field as
/// geometry (`GrassSplats::Off`): the far rows as covered (within 0.05 of them under 4× MSAA, a
/// cell a sample; 0.15 without, where Bevy cuts billboards at half their coverage), their mean
/// colour within 12 of 255 a channel, and at most a tenth of the pixels apart by more than 24 —
/// with Bevy's prepass (depth, normals, motion vectors), on a deferred camera, and in the 32-bit
/// cells a device without 64-bit atomics splats in (`GrassSplats::Narrow`: the albedo alone, the
/// normal turned to the eye).
#[test]
fn bevy_s_passes_resolve_the_splatted_far_field_as_they_draw_it_as_geometry() {
    let picture = |scene: Scene, (msaa, splats): (bool, GrassSplats), prepass: Option<bool>| {
        let props = Props {
            msaa,
            pbr: true,
            eye: Eye(horizon_eye),
            device: Device::Bevy,
            splats,
            ..STILL
        };
        let (mut app, pixels) = app(scene, props);
        if let Some(deferred) = prepass {
            with_prepass(&mut app, deferred);
            if deferred {
                app.insert_resource(bevy::pbr::DefaultOpaqueRendererMethod::deferred());
                app.add_systems(Startup, bevy_ground);
            }
        }
        run_still(app, &pixels)
    };
    let [wide, narrow] = [GrassSplats::Auto, GrassSplats::Narrow];
    let cases = [
        ("forward", (false, wide), None),
        ("msaa", (true, wide), None),
        ("prepass", (false, wide), Some(false)),
        ("deferred", (false, wide), Some(true)),
        ("narrow-msaa", (true, narrow), None),
        ("narrow-prepass", (false, narrow), Some(false)),
    ];
    let mut failed = Vec::new();
    // The far field drawn as geometry, once for each way of drawing the wide and the narrow
    // cells are compared in.
    let mut drawn_in = Vec::<((bool, Option<bool>), Vec<[u8; 4]>)>::new();
    for (name, (msaa, splats), prepass) in cases {
        let splatted = picture(landscape_scene(), (msaa, splats), prepass);
        let drawn = match drawn_in.iter().find(|(way, _)| *way == (msaa, prepass)) {
            Some((_, drawn)) => drawn.clone(),
            None => {
                let drawn = picture(landscape_scene(), (msaa, GrassSplats::Off), prepass);
                drawn_in.push(((msaa, prepass), drawn.clone()));
                drawn
            }
        };
        keep(&format!("splats-in-bevy-{name}"), &splatted);
        keep(&format!("splats-in-bevy-{name}-drawn"), &drawn);
        let [covered, reference] = [&splatted, &drawn].map(|image| far_grass(image));
        let [a, b] = [&splatted, &drawn].map(|image| far_colour(image));
        let apart = pixels_apart(&splatted, &drawn);
        eprintln!(
            "{name}: far rows covered {covered:.3} splatted, {reference:.3} drawn; mean colour {a:.1?} against {b:.1?}; {apart} of {} pixels apart",
            splatted.len()
        );
        if splatted == drawn {
            failed.push(format!(
                "{name}: the splatted picture is the drawn one: nothing was splatted"
            ));
        }
        // Without MSAA Bevy draws a billboard where its painted coverage is over half, the compute
        // rasterizer covers the painted share of its cells (dithered, as sward's own pass does
        // at 1×): the splats cover less of the far rows there, by at most 0.15.
        let tolerance = if msaa { 0.05 } else { 0.15 };
        if (covered - reference).abs() >= tolerance {
            failed.push(format!(
                "{name}: the splats cover {covered:.3} of the far rows, the drawn far field {reference:.3}"
            ));
        }
        if (0..3).any(|c| (a[c] - b[c]).abs() > 12.0) {
            failed.push(format!(
                "{name}: the far rows' mean colour is {a:.1?} splatted, {b:.1?} drawn"
            ));
        }
        if apart * 10 > splatted.len() {
            failed.push(format!(
                "{name}: {apart} of {} pixels apart between the splatted and the drawn far field",
                splatted.len()
            ));
        }
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}

/// The quality tier a settings menu switches at run time (`GrassQuality`), on Bevy's own device
/// under 4× MSAA: at `Low` the far rows hold less grass than at `High` (half the blades, their
/// reach past the hand-over halved: the billboards end at 52 units of the far rows' 80), its far
/// field splatted a cell a pixel (the resolve's stage without alpha to coverage); an app switched
/// from `Low` to `High` while it runs draws `High`'s picture (within 1 % of the pixels).
#[test]
fn the_quality_tier_switches_at_run_time() {
    let picture = |first: GrassQuality, then: Option<GrassQuality>| {
        let props = Props {
            msaa: true,
            pbr: true,
            eye: Eye(horizon_eye),
            device: Device::Bevy,
            ..STILL
        };
        let (app, pixels) = app_with(landscape_scene(), props, move |app| {
            app.insert_resource(first);
            if let Some(then) = then {
                app.add_systems(Update, move |mut tier: ResMut<GrassQuality>, mut frame: Local<u32>| {
                    *frame += 1;
                    if *frame == 3 {
                        *tier = then;
                    }
                });
            }
        });
        run_still(app, &pixels)
    };
    let high = picture(GrassQuality::High, None);
    let low = picture(GrassQuality::Low, None);
    let switched = picture(GrassQuality::Low, Some(GrassQuality::High));
    for (name, image) in [("high", &high), ("low", &low), ("switched", &switched)] {
        keep(&format!("quality-{name}"), image);
    }
    let [at_high, at_low, after] = [&high, &low, &switched].map(|image| far_grass(image));
    eprintln!("far rows covered: {at_high:.3} high, {at_low:.3} low, {after:.3} switched from low to high");
    assert!(
        at_low < at_high - 0.1,
        "the far rows are as covered at Low ({at_low:.3}) as at High ({at_high:.3})"
    );
    let apart = pixels_apart(&switched, &high);
    assert!(
        apart * 100 <= high.len(),
        "switched from Low to High, {apart} of {} pixels are apart from High's picture",
        high.len()
    );
}

/// The far grass casts into Bevy's shadow maps within the grass's shadow distance: under a low
/// sun the far rows are darker where the generated grass and billboards shade each other than
/// with a shadow distance of nothing; on a deferred camera (with Bevy's ground in its G-buffer)
/// the far grass is drawn into the G-buffer, its picture as the forward camera's.
#[test]
fn the_far_grass_casts_within_its_shadow_distance_and_joins_a_deferred_camera_s_g_buffer() {
    let picture = |casting: f32, deferred: bool| {
        let props = Props {
            pbr: true,
            eye: Eye(horizon_eye),
            device: Device::Bevy,
            ..STILL
        };
        let (mut app, pixels) = app_with(landscape_scene(), props, move |app| {
            app.add_systems(Update, move |mut grass: Single<&mut Grass>| {
                if grass.shadow_distance != casting {
                    grass.shadow_distance = casting;
                }
            });
        });
        app.insert_resource(SunAt(western_sun));
        with_prepass(&mut app, deferred);
        if deferred {
            // Bevy's ground in the G-buffer too (Bevy's default is forward).
            app.insert_resource(bevy::pbr::DefaultOpaqueRendererMethod::deferred());
        }
        app.add_systems(Startup, bevy_ground);
        run_still(app, &pixels)
    };
    let casting = picture(100.0, false);
    let not_casting = picture(0.0, false);
    let deferred = picture(100.0, true);
    keep("far-shadows-casting", &casting);
    keep("far-shadows-not-casting", &not_casting);
    keep("far-shadows-deferred", &deferred);
    let band = |image: &[[u8; 4]]| {
        let rows = (FAR_ROWS.start * HEIGHT as f32) as usize..(FAR_ROWS.end * HEIGHT as f32) as usize;
        let pixels = &image[rows.start * WIDTH as usize..rows.end * WIDTH as usize];
        brightness(mean_of(pixels, &vec![true; pixels.len()]))
    };
    let (shaded, lit) = (band(&casting), band(&not_casting));
    eprintln!("far rows' brightness: casting {shaded:.1}, not casting {lit:.1}");
    assert!(
        shaded < 0.9 * lit,
        "the far grass casts no shadow: its rows are {shaded:.1} bright casting, {lit:.1} not"
    );
    let apart = pixels_apart(&casting, &deferred);
    eprintln!("deferred against forward: {apart} of {} pixels apart", casting.len());
    assert!(far_grass(&deferred) > 0.9, "the deferred camera shows no far grass");
    assert!(
        apart * 20 <= casting.len(),
        "{apart} pixels of {} differ between the deferred and the forward camera",
        casting.len()
    );
}

/// The sun low in the west: long shadows across the view.
fn western_sun(_: u32) -> (Vec3, Color) {
    (Vec3::new(-1.0, 0.35, 0.2), Color::WHITE)
}

/// The frame from which the painting test's game has cleared a disc of its grass.
const PAINTED_AT: u32 = 8;
/// The disc: around the field's middle.
const PAINTED_RADIUS: f32 = 2.0;

/// Generated grass (which takes strokes into the paint its renderer holds, with no new field).
fn generated_scene() -> Scene {
    let mut scene = grass_scene();
    scene.technique = sward_core::instanced::Technique::Instanced;
    scene.instanced.grid.density = 30.0;
    scene.instanced.grid.radius = 14.0;
    scene.instanced.lod_distances = [4.0, 8.0, 12.0];
    scene.instanced.splat_distance = 13.0;
    scene
}

/// Where on the still camera's image the cleared disc and the grass that stood on it are: the
/// pixels' box around the disc's edge at the ground and at the tallest blade's height.
fn painted_box() -> ([f32; 2], [f32; 2]) {
    let eye = still_eye(0);
    let projection = glam::camera::rh::proj::directx::perspective_infinite_reverse(
        std::f32::consts::FRAC_PI_4,
        WIDTH as f32 / HEIGHT as f32,
        0.1,
    );
    let clip_from_world = projection * eye.to_matrix().inverse();
    let (mut low, mut high) = ([f32::MAX; 2], [f32::MIN; 2]);
    for k in 0..32 {
        let a = k as f32 / 32.0 * std::f32::consts::TAU;
        for y in [0.0, grass_scene().field.height[1]] {
            let p = clip_from_world.project_point3(Vec3::new(a.cos() * PAINTED_RADIUS, y, a.sin() * PAINTED_RADIUS));
            let pixel = [(p.x * 0.5 + 0.5) * WIDTH as f32, (0.5 - p.y * 0.5) * HEIGHT as f32];
            for i in 0..2 {
                low[i] = low[i].min(pixel[i]);
                high[i] = high[i].max(pixel[i]);
            }
        }
    }
    (low, high)
}

/// A game paints its grass while the app runs (`Grass::paint`): the disc it clears is drawn
/// bare from the next frames on, and nothing else of the picture changes — on Bevy's own device
/// (the portable passes, Bevy's passes drawing) and on sward's (its Vulkan renderer).
#[test]
fn a_game_paints_the_grass_while_the_app_runs() {
    for (device, pbr) in [(Device::Bevy, true), (Device::Sward, false)] {
        let (mut app, pixels) = app(generated_scene(), Props { device, pbr, ..STILL });
        app.add_systems(Update, |time: Res<Time>, mut grass: Query<&mut Grass>| {
            if (time.elapsed_secs() * 60.0).round() as u32 == PAINTED_AT {
                for mut grass in &mut grass {
                    let disc = sward_bevy::prelude::Stroke::circle(Vec2::ZERO, PAINTED_RADIUS).softness(0.0);
                    grass.paint(disc.clear());
                }
            }
        });
        let frames = walk_for(app, &pixels, PAINTED_AT + 8);
        let (before, after) = (&frames[PAINTED_AT as usize - 2], frames.last().unwrap());
        keep(&format!("painted-{device:?}"), after);
        let (low, high) = painted_box();
        let inside = |i: usize| {
            let (x, y) = ((i as u32 % WIDTH) as f32 + 0.5, (i as u32 / WIDTH) as f32 + 0.5);
            (low[0]..high[0]).contains(&x) && (low[1]..high[1]).contains(&y)
        };
        let changed: Vec<usize> = (0..before.len())
            .filter(|&i| (0..3).any(|c| before[i][c].abs_diff(after[i][c]) > 24))
            .collect();
        let outside = changed.iter().filter(|&&i| !inside(i)).count();
        let bare = |image: &[[u8; 4]]| (0..image.len()).filter(|&i| inside(i) && !is_grass(image[i])).count();
        eprintln!(
            "{device:?}: {} pixels changed, {outside} outside the disc's box; bare in the box {} → {}",
            changed.len(),
            bare(before),
            bare(after)
        );
        assert!(
            changed.len() > 100,
            "{device:?}: the cleared disc changed {} pixels",
            changed.len()
        );
        assert!(
            outside * 10 < changed.len(),
            "{device:?}: {outside} of {} changed pixels lie outside the disc",
            changed.len()
        );
        assert!(
            bare(after) > bare(before) + 100,
            "{device:?}: the disc shows no more bare ground"
        );
    }
}

/// The trail test's ball: off the field (high above it) until frame 4, rolled across it until
/// frame 16, then lifted away; from frame `TINTED_AT`, where the test asks, the scene's paint has
/// a tint (of 1: the picture the same), which grows the field again from the same blades.
const TINTED_AT: u32 = 20;

#[derive(Component)]
struct Passing;

/// Whether the trail test's app tints its grass at `TINTED_AT`.
#[derive(Resource)]
struct Tints(bool);

fn pass_and_tint(
    time: Res<Time>,
    tints: Res<Tints>,
    mut balls: Query<&mut Transform, With<Passing>>,
    mut grass: Query<&mut Grass>,
) {
    let k = (time.elapsed_secs() * 60.0).round() as u32;
    for mut ball in &mut balls {
        ball.translation = match k {
            4..16 => Vec3::new(-4.0 + 8.0 * (k - 4) as f32 / 12.0, 0.45, -1.5),
            _ => Vec3::new(0.0, 50.0, 0.0),
        };
    }
    if k == TINTED_AT && tints.0 {
        for mut grass in &mut grass {
            grass.scene.paint.tint_noise = Some(sward_core::paint::TintNoise {
                color: glam::Vec3::ONE,
                ..default()
            });
        }
    }
}

/// The trail test's frames, the grass tinted at `TINTED_AT` where `tinted`.
fn passing_ball(device: Device, pbr: bool, tinted: bool) -> Vec<Vec<[u8; 4]>> {
    let (mut app, pixels) = app(grass_scene(), Props { device, pbr, ..STILL });
    app.world_mut()
        .spawn((Passing, GrassCollider::sphere(0.6), Transform::from_xyz(0.0, 50.0, 0.0)));
    app.insert_resource(Tints(tinted)).add_systems(Update, pass_and_tint);
    walk_for(app, &pixels, TINTED_AT + 8)
}

/// A change of the scene that grows the field again from the same blades (a tint over the
/// ground, a kind's colours: a scene file saved with such a change) keeps the Bezier blades on
/// the GPU, and with them the trail a collider pressed, still recovering, on either device:
/// the picture after the change is the picture of the same app unchanged.
#[test]
fn a_scene_changed_but_for_its_blades_keeps_the_trail() {
    for (device, pbr) in [(Device::Sward, false), (Device::Bevy, true)] {
        let unchanged = passing_ball(device, pbr, false);
        let tinted = passing_ball(device, pbr, true);
        let (untouched, last) = (&unchanged[3], unchanged.last().unwrap());
        let after = tinted.last().unwrap();
        keep(&format!("trail-kept-{device:?}"), after);
        let trail = pixels_apart(untouched, last);
        let apart = pixels_apart(last, after);
        eprintln!("{device:?}: the trail (and the blades settling) {trail} pixels; tinted, {apart} apart");
        assert!(trail > 150, "{device:?}: the ball left no trail: {trail} pixels");
        assert!(
            apart * 10 < trail,
            "{device:?}: tinted, the picture is {apart} pixels from the trail's {trail}"
        );
    }
}

/// A patch of dense grass two metres a side.
fn patch_scene() -> Scene {
    let mut scene = grass_scene();
    scene.field.blades = 1600;
    scene.field.size = glam::Vec2::splat(2.0);
    scene
}

/// The field a test slides across the near ground.
#[derive(Component)]
struct Sliding;

/// The four-field test's frames: the sliding field crosses in them.
const SLIDE_FRAMES: u32 = 28;

/// Where the sliding field stands at frame `k`: left to right over the run.
fn slide_at(k: u32) -> Vec3 {
    Vec3::new(-2.2 + 4.4 * k.min(SLIDE_FRAMES) as f32 / SLIDE_FRAMES as f32, 0.0, -4.5)
}

/// Where the four-field test's turned and scaled fields stand.
const TURNED_AT: Vec3 = Vec3::new(-3.5, 0.0, 0.5);
const SCALED_AT: Vec3 = Vec3::new(3.5, 0.0, 0.5);
/// The frame a ball drops into the turned field.
const PRESSED_FROM: u32 = 16;

/// Where on the image (in pixels, x to the right, y down) the still camera sees world point `p`.
fn screen_point(p: Vec3) -> Vec2 {
    let view = still_eye(0).to_matrix().inverse();
    let aspect = WIDTH as f32 / HEIGHT as f32;
    let projection = glam::camera::rh::proj::directx::perspective(std::f32::consts::FRAC_PI_4, aspect, 0.1, 1000.0);
    let ndc = (projection * view).project_point3(p);
    Vec2::new((ndc.x + 1.0) * 0.5 * WIDTH as f32, (1.0 - ndc.y) * 0.5 * HEIGHT as f32)
}

/// The pixel (column, row) where the still camera sees world point `p`.
fn seen_at(p: Vec3) -> (i32, i32) {
    let at = screen_point(p);
    (at.x as i32, at.y as i32)
}

fn is_sky(p: [u8; 4]) -> bool {
    let sky = SKY.to_srgba().to_u8_array();
    (0..3).all(|c| p[c].abs_diff(sky[c]) <= 12)
}

/// The pixels within `r` of pixel `at` of `image`.
fn window(image: &[[u8; 4]], (x, y): (i32, i32), r: i32) -> Vec<[u8; 4]> {
    let inside = |c: i32, n: u32| (0..n as i32).contains(&c);
    (y - r..=y + r)
        .flat_map(|row| (x - r..=x + r).map(move |column| (column, row)))
        .filter(|&(column, row)| inside(column, WIDTH) && inside(row, HEIGHT))
        .map(|(column, row)| image[(row as u32 * WIDTH + column as u32) as usize])
        .collect()
}

/// How much of the window of `r` around where the camera sees the grass standing at `p` (its
/// blades' middle) is grass, not sky.
fn drawn_around(image: &[[u8; 4]], p: Vec3, r: i32) -> f32 {
    let pixels = window(image, seen_at(p + Vec3::Y * 0.35), r);
    pixels.iter().filter(|&&p| !is_sky(p)).count() as f32 / pixels.len().max(1) as f32
}

/// How much redder than green the grass (not the sky) around `p` is, on average.
fn redness_around(image: &[[u8; 4]], p: Vec3) -> f32 {
    let grass: Vec<_> = window(image, seen_at(p + Vec3::Y * 0.35), 4)
        .into_iter()
        .filter(|&p| !is_sky(p))
        .collect();
    let sum: f32 = grass.iter().map(|p| p[0] as f32 - p[1] as f32).sum();
    sum / grass.len().max(1) as f32
}

/// The four-field test's budget: three quarters of the blades its fields ask together.
const FOUR_FIELDS_BUDGET: u32 = 4800;

/// Four fields, each its own grass entity placed by its `Transform`, in Bevy's passes on
/// Bevy's own device: the test's own at the origin, one turned to the left, one scaled half as
/// large again and red-tipped to the right (its own colours), and one sliding across the near
/// ground as the game runs. Each stands where its transform puts it, the sliding one moves
/// with it, and a ball dropped into the turned one presses its grass (the colliders are every
/// field's). They share one budget (`GrassBudget`, three quarters of what they ask: each grows
/// three quarters of its blades) and one cull (one depth pyramid a camera, in one submission):
/// a second camera at the same eye, culling all four for itself, sees what the first sees.
#[test]
fn four_fields_stand_where_their_transforms_put_them_and_one_slides() {
    let props = Props {
        pbr: true,
        device: Device::Bevy,
        ..STILL
    };
    let mut second = None;
    let (mut app, pixels) = app_with(patch_scene(), props, |app| {
        second = Some(second_camera(app, still_eye(0)));
    });
    app.insert_resource(sward_bevy::GrassBudget {
        blades: FOUR_FIELDS_BUDGET,
    });
    let shares = Arc::new(Mutex::new(Vec::new()));
    let kept = shares.clone();
    app.add_systems(Update, move |granted: Query<&sward_bevy::GrassShare>| {
        *kept.lock().unwrap() = granted.iter().map(|s| s.blades).collect::<Vec<_>>();
    });
    app.add_systems(Startup, |mut commands: Commands| {
        let place = |at: Vec3| Transform::from_translation(at);
        commands.spawn((
            Grass::new(patch_scene()).unwrap(),
            place(TURNED_AT).with_rotation(Quat::from_rotation_y(0.8)),
        ));
        let mut red = patch_scene();
        red.shading.root_color = glam::Vec3::new(0.35, 0.02, 0.02);
        red.shading.tip_color = glam::Vec3::new(0.9, 0.1, 0.05);
        commands.spawn((Grass::new(red).unwrap(), place(SCALED_AT).with_scale(Vec3::splat(1.5))));
        commands.spawn((Grass::new(patch_scene()).unwrap(), place(slide_at(0)), Sliding));
        commands.spawn((Passing, GrassCollider::sphere(0.7), place(Vec3::new(0.0, 50.0, 0.0))));
    });
    app.add_systems(
        Update,
        |time: Res<Time>,
         mut sliding: Single<&mut Transform, With<Sliding>>,
         mut ball: Single<&mut Transform, (With<Passing>, Without<Sliding>)>| {
            let k = (time.elapsed_secs() * 60.0).round() as u32;
            sliding.translation = slide_at(k);
            if k >= PRESSED_FROM {
                ball.translation = TURNED_AT + Vec3::Y * 0.5;
            }
        },
    );
    let second = second.expect("made with the app");
    let mut views = walk_views(app, &[&pixels, &second], SLIDE_FRAMES);
    let (seconds, frames) = (
        views.pop().expect("the second camera's"),
        views.pop().expect("the first's"),
    );
    let apart = pixels_apart(frames.last().unwrap(), seconds.last().unwrap());
    assert!(
        apart * 50 < (WIDTH * HEIGHT) as usize,
        "the second camera, at the first's eye, drew {apart} pixels apart from it"
    );
    let asked = patch_scene().field.blades;
    let shares = shares.lock().unwrap().clone();
    assert_eq!(
        shares,
        vec![asked * 3 / 4; 4],
        "each field's share of a budget of {FOUR_FIELDS_BUDGET} blades, {asked} asked each"
    );
    // The read-back runs a few frames behind: take images well inside their phase.
    let (early, before, last) = (&frames[6], &frames[PRESSED_FROM as usize - 1], frames.last().unwrap());
    keep("four-fields-early", early);
    keep("four-fields-last", last);
    let fields = [("origin", Vec3::ZERO), ("turned", TURNED_AT), ("scaled", SCALED_AT)];
    for (name, at) in fields {
        let share = drawn_around(last, at, 4);
        assert!(
            share > 0.5,
            "the {name} field covers {:.0} % around its place",
            share * 100.0
        );
    }
    let gap = drawn_around(last, Vec3::new(-1.9, 0.0, 8.0), 3);
    assert!(gap < 0.05, "grass where no field stands: {:.0} %", gap * 100.0);
    // Its own colours: the scaled field is red-tipped, the field at the origin green.
    let (red, green) = (redness_around(last, SCALED_AT), redness_around(last, Vec3::ZERO));
    assert!(
        red > green + 30.0,
        "the red-tipped field is {red:.0} redder than green, the other {green:.0}"
    );
    // The sliding field: where it stood early on, and later where it went.
    let (start, end) = (slide_at(6 - 3), slide_at(SLIDE_FRAMES));
    let [was_there, is_there] = [start, end].map(|at| [drawn_around(early, at, 3), drawn_around(last, at, 3)]);
    assert!(
        was_there[0] > 0.5 && was_there[1] < 0.1,
        "the sliding field covered {:.0} % of its first place early and {:.0} % at last",
        was_there[0] * 100.0,
        was_there[1] * 100.0
    );
    assert!(
        is_there[0] < 0.1 && is_there[1] > 0.5,
        "the sliding field covered {:.0} % of its last place early and {:.0} % at last",
        is_there[0] * 100.0,
        is_there[1] * 100.0
    );
    // The ball pressed the turned field's grass.
    let pressed = pixels_apart(
        &window(before, seen_at(TURNED_AT), 8),
        &window(last, seen_at(TURNED_AT), 8),
    );
    assert!(pressed > 25, "the ball changed {pressed} pixels of the turned field");
}

/// How the equivalence test turns and moves its field.
const TURN: f32 = 0.9;
const MOVE: Vec3 = Vec3::new(2.0, 0.5, 3.0);

/// The still camera carried into the turned and moved field's own space.
fn eye_in_field(k: u32) -> Transform {
    let field = Transform::from_translation(MOVE).with_rotation(Quat::from_rotation_y(TURN));
    Transform::from_matrix(field.to_matrix().inverse() * still_eye(k).to_matrix())
}

/// The still sun turned into the field's own space.
fn sun_in_field(k: u32) -> (Vec3, Color) {
    let (toward, colour) = still_sun(k);
    (Quat::from_rotation_y(-TURN) * toward, colour)
}

/// A field turned and moved by its `Transform` is the field where its scene puts it, seen by
/// the camera (and lit by the sun) carried into its space: the same picture, within a few
/// pixels where the shadow maps' texels fall otherwise — in sward's own pass on its Vulkan
/// device and in Bevy's passes on Bevy's own.
#[test]
fn a_placed_field_is_its_scene_seen_from_the_camera_carried_into_its_space() {
    for (device, pbr) in [(Device::Sward, false), (Device::Bevy, true)] {
        let (mut moved, placed_pixels) = app(grass_scene(), Props { device, pbr, ..STILL });
        moved.add_systems(Update, |mut grass: Single<&mut Transform, With<Grass>>| {
            **grass = Transform::from_translation(MOVE).with_rotation(Quat::from_rotation_y(TURN));
        });
        let placed = run_still(moved, &placed_pixels);
        let carried = Props {
            device,
            pbr,
            eye: Eye(eye_in_field),
            ..STILL
        };
        let (mut unmoved, pixels) = app(grass_scene(), carried);
        unmoved.insert_resource(SunAt(sun_in_field));
        let seen = run_still(unmoved, &pixels);
        keep(&format!("placed-{device:?}"), &placed);
        keep(&format!("carried-{device:?}"), &seen);
        let grass = placed.iter().filter(|&&p| !is_sky(p)).count();
        let apart = pixels_apart(&placed, &seen);
        eprintln!("{device:?}: {grass} pixels of grass, {apart} apart");
        assert!(grass > 2000, "{device:?}: the placed field covers only {grass} pixels");
        assert!(apart * 50 < grass, "{device:?}: {apart} of {grass} pixels differ");
    }
}

/// Where the field the motion-vector test slides stands at frame `k` (never stopping).
fn gliding_at(k: u32) -> Vec3 {
    Vec3::new(-2.2 + 0.15 * k as f32, 0.0, -4.5)
}

/// A field that slides as the game runs, the wind still and the camera too, moves in the
/// camera's motion vectors by as much as its transform moved it on the screen (the blades'
/// last pose is drawn where the field stood in the last frame), in Bevy's passes on sward's
/// Vulkan device and on Bevy's own.
#[test]
fn a_sliding_field_s_motion_vectors_carry_its_slide() {
    for device in [Device::Sward, Device::Bevy] {
        let motion = Motion::default();
        let reader = motion.clone();
        let props = Props {
            pbr: true,
            device,
            ..STILL
        };
        let (mut app, pixels) = app_with(patch_scene(), props, move |app| copying_motion_vectors(app, reader));
        with_prepass(&mut app, false);
        app.add_systems(
            Update,
            |time: Res<Time>, mut grass: Single<&mut Transform, With<Grass>>| {
                let k = (time.elapsed_secs() * 60.0).round() as u32;
                grass.translation = gliding_at(k);
            },
        );
        let device_of_bevy = app
            .world()
            .resource::<bevy::render::renderer::RenderDevice>()
            .wgpu_device()
            .clone();
        walk_for(app, &pixels, 16);
        let vectors = motion.read(&device_of_bevy);
        assert_eq!(
            vectors.len(),
            (WIDTH * HEIGHT) as usize,
            "the motion vectors were not read back"
        );
        // In pixels, x to the right.
        let moving: Vec<f32> = vectors
            .iter()
            .filter(|v| (v[0] * WIDTH as f32).hypot(v[1] * HEIGHT as f32) > 0.05)
            .map(|v| v[0] * WIDTH as f32)
            .collect();
        let centre = Vec3::Y * 0.35;
        let expected = screen_point(gliding_at(11) + centre).x - screen_point(gliding_at(10) + centre).x;
        let mut sorted = moving.clone();
        sorted.sort_by(f32::total_cmp);
        let median = sorted.get(sorted.len() / 2).copied().unwrap_or(0.0);
        eprintln!(
            "{device:?}: {} pixels move, median {median:.2} px a frame across, the field {expected:.2}",
            moving.len()
        );
        assert!(moving.len() > 300, "{device:?}: only {} pixels move", moving.len());
        assert!(
            (median - expected).abs() < 0.4 * expected.abs(),
            "{device:?}: the grass moves {median:.2} px a frame across, its field {expected:.2}"
        );
    }
}
