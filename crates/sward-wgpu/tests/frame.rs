//! sward's grass drawn into a wgpu application's frame (lavapipe in CI, under the validation
//! layer): the application draws a cube with wgpu, sward draws a meadow over it through
//! `GrassRenderer`, and the grass matches sward's own render of the same scene where the cube
//! is not, the cube hides the grass behind it — in the depth test and in the cull — and the
//! same holds on a multisampled HDR target with reverse Z.

mod support;

use ash::vk;
use glam::{Mat4, Vec3};
use support::cube::Cube;
use support::NEEDS;
use sward_core::{FrameDesc, Scene};
use sward_gpu::barrier::Access;
use sward_gpu::target::{begin_rendering, OFFSCREEN_FORMAT};
use sward_gpu::{Context, ContextDesc, Headless, Passes, RendererDesc, TargetViews, Validation};
use sward_wgpu::{DepthDirection, FrameTarget, GrassRenderer, SwardDevice, TargetDesc};

const WIDTH: u32 = 160;
const HEIGHT: u32 = 120;
/// Fixed steps of physics before the compared frame.
const STEPS: u32 = 20;
/// The application's clear colour: darker than any grass, so grass pixels can be told from it.
const BACKGROUND: wgpu::Color = wgpu::Color {
    r: 0.0,
    g: 0.0,
    b: 0.02,
    a: 1.0,
};

fn validating() -> ContextDesc {
    ContextDesc {
        validation: Validation::Required,
        ..ContextDesc::default()
    }
}

fn open() -> (wgpu::Instance, SwardDevice) {
    let (instance, adapter) = support::vulkan_adapter();
    let sward = sward_wgpu::open(&adapter, &wgpu::DeviceDescriptor::default(), &validating())
        .unwrap_or_else(|e| panic!("{NEEDS}: {e}"));
    (instance, sward)
}

/// How the application's frame is made.
#[derive(Clone, Copy)]
struct Variant {
    color: wgpu::TextureFormat,
    samples: u32,
    direction: DepthDirection,
    /// Where the cube stands, if anywhere.
    cube: Option<(Vec3, f32)>,
    occlusion: bool,
}

const PLAIN: Variant = Variant {
    color: wgpu::TextureFormat::Rgba8UnormSrgb,
    samples: 1,
    direction: DepthDirection::Forward,
    cube: None,
    occlusion: true,
};

/// What the application saw: the frame as sRGB bytes and how many blades sward drew.
struct Seen {
    pixels: Vec<[u8; 4]>,
    visible: usize,
}

/// The scene's camera as a wgpu application holds it: its view, and a projection into wgpu's
/// clip space (y up) with depth running `direction` (reverse: infinite, as Bevy's).
fn application_camera(scene: &Scene, direction: DepthDirection) -> (Mat4, Mat4) {
    let cam = &scene.camera;
    let (fov, aspect) = (cam.fov_y_degrees.to_radians(), WIDTH as f32 / HEIGHT as f32);
    let projection = match direction {
        DepthDirection::Forward => glam::camera::rh::proj::directx::perspective(fov, aspect, cam.near, cam.far),
        DepthDirection::Reverse => glam::camera::rh::proj::directx::perspective_infinite_reverse(fov, aspect, cam.near),
    };
    (cam.view(), projection)
}

fn texture(
    device: &wgpu::Device,
    format: wgpu::TextureFormat,
    samples: u32,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: None,
        size: wgpu::Extent3d {
            width: WIDTH,
            height: HEIGHT,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: samples,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: usage | wgpu::TextureUsages::RENDER_ATTACHMENT,
        view_formats: &[],
    })
}

/// The application's frame: its cube (if any) drawn by wgpu, then sward's grass over it after
/// `STEPS` steps of physics, read back.
fn application_frame(sward: &SwardDevice, scene: &Scene, v: Variant) -> Seen {
    let device = &sward.device;
    let depth_format = wgpu::TextureFormat::Depth32Float;
    let color = texture(device, v.color, v.samples, wgpu::TextureUsages::COPY_SRC);
    let resolve = (v.samples > 1).then(|| texture(device, v.color, 1, wgpu::TextureUsages::COPY_SRC));
    let depth = texture(device, depth_format, v.samples, wgpu::TextureUsages::TEXTURE_BINDING);
    let views = [&color, &depth].map(|t| t.create_view(&Default::default()));
    let resolve_view = resolve.as_ref().map(|t| t.create_view(&Default::default()));
    let target = TargetDesc {
        samples: v.samples,
        depth_direction: v.direction,
        ..TargetDesc::new(v.color, depth_format)
    };
    let mut grass = GrassRenderer::new(sward, &target, scene.quality.preset).unwrap();
    let field = scene.grow_field().unwrap();
    grass.upload(&field).unwrap();
    let cube = Cube::new(
        device,
        v.color,
        depth_format,
        v.samples,
        v.direction == DepthDirection::Reverse,
    );
    let (view, projection) = application_camera(scene, v.direction);
    let ours = sward_wgpu::sward_projection(projection, v.direction);
    // The first frame simulates; the second draws with the first's blade occluders, as
    // sward's own render does (Headless::render_scene).
    for clock in [(0.0, STEPS), (STEPS as f32 * scene.simulation.step, 0)] {
        let desc = FrameDesc::of_scene(scene, field.size, clock, [WIDTH, HEIGHT]).with_view_projection(view, ours);
        let mut world = device.create_command_encoder(&Default::default());
        let hidden = (Vec3::new(0.0, -100.0, 0.0), 0.01);
        let attachments = (&views[0], resolve_view.as_ref(), &views[1]);
        cube.draw(
            &sward.queue,
            &mut world,
            attachments,
            projection * view,
            v.cube.unwrap_or(hidden),
            (BACKGROUND, false),
        );
        let mut target = FrameTarget::new(&views[0], &views[1]);
        target.occlusion = v.occlusion;
        if let Some(resolve) = &resolve_view {
            target = target.resolving_into(resolve);
        }
        let frame = grass.encode(&desc, &target).unwrap();
        sward.queue.submit(std::iter::once(world.finish()).chain(frame));
    }
    grass.wait_idle();
    let visible = grass.renderer_mut().read_visible().unwrap().0.len();
    let pixels = read_back(sward, resolve.as_ref().unwrap_or(&color));
    Seen { pixels, visible }
}

/// A single-sample colour texture as sRGB bytes (floating-point formats encoded as an sRGB
/// target would).
fn read_back(sward: &SwardDevice, texture: &wgpu::Texture) -> Vec<[u8; 4]> {
    let texels = support::readback::texels(&sward.device, &sward.queue, texture);
    match texture.format() {
        wgpu::TextureFormat::Rgba8UnormSrgb => texels
            .as_chunks::<4>()
            .0
            .iter()
            .map(|t| [t[0], t[1], t[2], t[3]])
            .collect(),
        wgpu::TextureFormat::Rgba16Float => texels
            .as_chunks::<8>()
            .0
            .iter()
            .map(|t| {
                let half = |i: usize| f16_to_f32(u16::from_le_bytes([t[2 * i], t[2 * i + 1]]));
                [encode_srgb(half(0)), encode_srgb(half(1)), encode_srgb(half(2)), 255]
            })
            .collect(),
        other => panic!("no read-back for {other:?}"),
    }
}

fn f16_to_f32(h: u16) -> f32 {
    let sign = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exponent = ((h >> 10) & 0x1f) as i32;
    let mantissa = (h & 0x3ff) as f32;
    sign * match exponent {
        0 => mantissa * 2f32.powi(-24),
        31 => f32::INFINITY,
        e => (1.0 + mantissa / 1024.0) * 2f32.powi(e - 15),
    }
}

/// Linear light to an sRGB byte, as an sRGB attachment stores it.
fn encode_srgb(linear: f32) -> u8 {
    let c = linear.clamp(0.0, 1.0);
    let encoded = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (encoded * 255.0).round() as u8
}

/// sward's own render of `scene` on its own device and target, `samples` samples per pixel,
/// as sRGB bytes: its grass drawn over the application's clear colour (and nothing else: no
/// sky or ground of its own), after the same steps and culls as the application's frames.
fn sward_own(scene: &Scene, samples: u32) -> Vec<[u8; 4]> {
    let ctx = Context::new(&validating()).unwrap_or_else(|e| panic!("{NEEDS}: {e}"));
    let mut desc = RendererDesc::for_quality(&ctx.info, OFFSCREEN_FORMAT, scene.quality.preset, 1);
    desc.target.samples = vk::SampleCountFlags::from_raw(samples);
    let mut headless = Headless::with_desc(&ctx, WIDTH, HEIGHT, &desc).unwrap();
    let field = scene.grow_field().unwrap();
    headless.renderer.upload(&field).unwrap();
    headless.renderer.upload_ground(field.ground.as_ref()).unwrap();
    headless.simulate(scene, field.size, 0, STEPS).unwrap();
    let desc = headless.frame(scene, field.size, (STEPS as f32 * scene.simulation.step, 0));
    headless.renderer.run_compute(&desc, Passes::CULL).unwrap();
    let d = &ctx.device;
    ctx.submit_and_wait("sward's own frame", |cmd| {
        let target = &headless.target;
        target.begin(d, cmd);
        let views = TargetViews {
            over_caller: true,
            ..target.views()
        };
        clear(d, cmd, &views);
        for written in [Access::COLOR_ATTACHMENT, Access::DEPTH_ATTACHMENT] {
            sward_gpu::barrier::memory(d, cmd, written, written);
        }
        headless
            .renderer
            .record_frame(cmd, 0, &desc, Passes::ALL, Some(&views), None);
        target.finish(d, cmd);
    })
    .unwrap();
    let pixels = headless.target.pixels();
    drop(headless);
    assert_clean(&ctx);
    pixels
        .as_chunks::<4>()
        .0
        .iter()
        .map(|p| [p[0], p[1], p[2], p[3]])
        .collect()
}

/// The application's clear, on sward's own target.
fn clear(d: &ash::Device, cmd: vk::CommandBuffer, views: &TargetViews) {
    let color = vk::RenderingAttachmentInfo::default()
        .image_view(views.color)
        .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::STORE)
        .clear_value(vk::ClearValue {
            color: vk::ClearColorValue {
                float32: [BACKGROUND.r, BACKGROUND.g, BACKGROUND.b, 1.0].map(|c| c as f32),
            },
        });
    let depth = vk::RenderingAttachmentInfo::default()
        .image_view(views.depth)
        .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::STORE)
        .clear_value(vk::ClearValue {
            depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: 0 },
        });
    begin_rendering(d, cmd, &[color], Some(&depth), views.extent);
    unsafe { d.cmd_end_rendering(cmd) };
}

fn assert_clean(ctx: &Context) {
    assert!(ctx.validating(), "the validation layer is not active");
    let messages = ctx.take_validation_messages();
    assert!(messages.is_empty(), "validation:\n{}", messages.join("\n"));
}

/// The scene both draw: a small meadow.
fn scene() -> Scene {
    let mut scene = Scene::default();
    scene.field.blades = 4096;
    scene.validate("test").unwrap();
    scene
}

/// Where the cube stands: on the ground a third of the way from the camera to what it looks
/// at, 3 units tall (the camera is 4 up), so that it hides a wedge of the field behind it —
/// whole blades, tips and all.
fn cube_of(scene: &Scene) -> Option<(Vec3, f32)> {
    let (eye, target) = (scene.camera.position, scene.camera.target);
    let center = eye + (target - eye) / 3.0;
    let half = 1.5;
    Some((Vec3::new(center.x, half, center.z), half))
}

/// The application's cube, lit anywhere from its darkest face to its brightest.
fn is_cube(p: [u8; 4]) -> bool {
    p[0] > 60 && p[0] as u32 > 3 * p[1].max(p[2]) as u32
}

/// Keep `pixels` as `name`-actual.png in the tests' scratch folder, to be looked at.
fn keep(name: &str, pixels: &[[u8; 4]]) {
    let path = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("{name}-actual.png"));
    let bytes = pixels.iter().flatten().copied().collect();
    image::RgbaImage::from_raw(WIDTH, HEIGHT, bytes)
        .unwrap()
        .save(&path)
        .unwrap();
}

/// The application's clear colour, where nothing was drawn.
fn is_background(p: [u8; 4]) -> bool {
    p[0] < 4 && p[1] < 4
}

/// The share of the pixels, not the application's cube, that differ from sward's own frame
/// by more than `tolerance` in some channel, and how many of sward's own are grass (not the
/// clear colour).
fn compare(app: &[[u8; 4]], own: &[[u8; 4]], tolerance: u8) -> (f64, usize) {
    let outside_cube = app.iter().zip(own).filter(|(&a, _)| !is_cube(a));
    let (mut pixels, mut differ) = (0usize, 0usize);
    for (a, o) in outside_cube {
        pixels += 1;
        differ += (0..3).any(|c| a[c].abs_diff(o[c]) > tolerance) as usize;
    }
    let grass = own.iter().filter(|&&p| !is_background(p)).count();
    (differ as f64 / pixels.max(1) as f64, grass)
}

#[test]
fn grass_in_a_wgpu_frame_is_sward_s_own_and_the_application_s_cube_hides_what_is_behind_it() {
    let scene = scene();
    let own = sward_own(&scene, 1);
    let (_instance, sward) = open();
    // Without a cube: the grass sward draws into the application's frame is its own picture.
    let open_field = application_frame(&sward, &scene, PLAIN);
    keep("wgpu-own", &own);
    keep("wgpu-open-field", &open_field.pixels);
    let (differ, grass) = compare(&open_field.pixels, &own, 3);
    assert!(grass > 4000, "little grass in sward's own render: {grass} pixels");
    assert!(
        differ < 0.005,
        "the wgpu frame's grass is not sward's own: {:.2} % of the pixels differ by more than 3 levels",
        100.0 * differ
    );
    // A cube in the grass: it hides the grass behind it, grass in front of it stands over it,
    // and the grass it hides is not even drawn (the cull reads the application's depth).
    let cube = cube_of(&scene);
    let with_cube = application_frame(&sward, &scene, Variant { cube, ..PLAIN });
    keep("wgpu-cube", &with_cube.pixels);
    // Where the cube is not, the grass is as before (the edge of the cube aside, where the
    // grass behind it was drawn in sward's own frame).
    let (differ, _) = compare(&with_cube.pixels, &own, 3);
    assert!(
        differ < 0.02,
        "around the cube the grass changed: {:.2} % of the pixels",
        100.0 * differ
    );
    let unculled = application_frame(
        &sward,
        &scene,
        Variant {
            cube,
            occlusion: false,
            ..PLAIN
        },
    );
    keep("wgpu-cube-unculled", &unculled.pixels);
    let changed = unculled
        .pixels
        .iter()
        .zip(&with_cube.pixels)
        .filter(|(a, b)| a != b)
        .count();
    assert!(changed < 50, "the cull changed {changed} pixels of the picture");
    assert_cube_hides(&with_cube, &unculled, "single sample");
    assert_clean(&sward.context);
}

#[test]
fn a_multisampled_hdr_target_with_reverse_z_gets_the_same_grass() {
    let scene = scene();
    let own = sward_own(&scene, 4);
    let (_instance, sward) = open();
    let hdr = Variant {
        color: wgpu::TextureFormat::Rgba16Float,
        samples: 4,
        direction: DepthDirection::Reverse,
        cube: None,
        occlusion: true,
    };
    let seen = application_frame(&sward, &scene, hdr);
    keep("wgpu-own-msaa", &own);
    keep("wgpu-hdr-reverse-z", &seen.pixels);
    // The float target is resolved in floats and encoded on the host, sward's own in sRGB
    // bytes: a level or two apart, so a looser bound than the single-sample frame's.
    let (differ, _) = compare(&seen.pixels, &own, 6);
    assert!(
        differ < 0.005,
        "the HDR reverse-Z frame's grass is not sward's own: {:.2} % of the pixels differ by more than 6 levels",
        100.0 * differ
    );
    // Reverse Z: the cube, nearer, is larger in depth; grass behind it fails the test.
    let with_cube = application_frame(
        &sward,
        &scene,
        Variant {
            cube: cube_of(&scene),
            ..hdr
        },
    );
    keep("wgpu-hdr-reverse-z-cube", &with_cube.pixels);
    assert_cube_hides(&with_cube, &seen, "reverse Z");
    assert_clean(&sward.context);
}

/// The cube in `with_cube` stands over the grass behind it (its pixels are not drawn over)
/// and its depth culls a tenth of the blades `without` draws.
fn assert_cube_hides(with_cube: &Seen, without: &Seen, what: &str) {
    let cube_pixels = with_cube.pixels.iter().filter(|&&p| is_cube(p)).count();
    assert!(
        cube_pixels > 1500,
        "{what}: the cube covers only {cube_pixels} pixels: grass is drawn over it"
    );
    assert!(
        with_cube.visible * 100 < without.visible * 90,
        "{what}: the cube's depth culled too few blades: {} drawn with it, {} without",
        with_cube.visible,
        without.visible
    );
}

#[test]
fn a_target_unlike_the_renderer_s_is_one_sentence() {
    let (_instance, sward) = open();
    let target = TargetDesc::new(wgpu::TextureFormat::Rgba8UnormSrgb, wgpu::TextureFormat::Depth32Float);
    let mut grass = GrassRenderer::new(&sward, &target, Default::default()).unwrap();
    let color = texture(
        &sward.device,
        wgpu::TextureFormat::Rgba16Float,
        1,
        wgpu::TextureUsages::empty(),
    );
    let depth = texture(
        &sward.device,
        wgpu::TextureFormat::Depth32Float,
        1,
        wgpu::TextureUsages::empty(),
    );
    let views = [&color, &depth].map(|t| t.create_view(&Default::default()));
    let desc = FrameDesc::of_scene(&scene(), glam::Vec2::splat(10.0), (0.0, 0), [WIDTH, HEIGHT]);
    let err = grass
        .encode(&desc, &FrameTarget::new(&views[0], &views[1]))
        .err()
        .unwrap()
        .to_string();
    assert!(err.contains("Rgba16Float") && err.contains("Rgba8UnormSrgb"), "{err}");
    let unsupported = TargetDesc::new(wgpu::TextureFormat::R8Unorm, wgpu::TextureFormat::Depth32Float);
    let err = GrassRenderer::new(&sward, &unsupported, Default::default())
        .err()
        .unwrap()
        .to_string();
    assert!(err.contains("R8Unorm") && err.contains("Rgba16Float"), "{err}");
    assert_clean(&sward.context);
}
