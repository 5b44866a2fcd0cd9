//! sward inside an application that owns its Vulkan instance and device: the application makes
//! the device with `create_device_for`, hands it to `Context::from_device`, draws its own frame
//! first (here: a red backdrop and, on the left, an object nearer than any grass), and sward
//! records its grass into the same command buffer over it — depth-tested against the
//! application's depth (in a format of the application's choosing), without a sky or ground of
//! its own. sward never destroys what it was
//! given: the test destroys the device and instance itself, after sward is gone, with the
//! validation layer (synchronization validation too) silent throughout.

mod common;

use std::sync::{Arc, Mutex};

use ash::vk;
use sward_core::FrameDesc;
use sward_core::{Camera, Scene};
use sward_gpu::gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use sward_gpu::pipelines::TargetFormat;
use sward_gpu::target::{begin_rendering, OFFSCREEN_FORMAT};
use sward_gpu::{create_device_for, Context, ContextDesc, ExistingDevice, Headless, Passes, RendererDesc, Validation};

const WIDTH: u32 = 160;
const HEIGHT: u32 = 120;

/// The application's own instance, with the validation layer and its messenger extension.
fn application_instance(entry: &ash::Entry) -> ash::Instance {
    let app = vk::ApplicationInfo::default()
        .application_name(c"an application")
        .api_version(vk::API_VERSION_1_3);
    let layers = [c"VK_LAYER_KHRONOS_validation".as_ptr()];
    let extensions = [
        ash::ext::debug_utils::NAME.as_ptr(),
        ash::ext::validation_features::NAME.as_ptr(),
    ];
    let sync = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
    let mut features = vk::ValidationFeaturesEXT::default().enabled_validation_features(&sync);
    let info = vk::InstanceCreateInfo::default()
        .application_info(&app)
        .enabled_layer_names(&layers)
        .enabled_extension_names(&extensions)
        .push_next(&mut features);
    unsafe { entry.create_instance(&info, None) }.expect(
        "this test needs a Vulkan driver and the validation layer (apt-get install mesa-vulkan-drivers vulkan-validationlayers)",
    )
}

/// The first device with a graphics + compute queue family, and that family.
fn first_device(instance: &ash::Instance) -> (vk::PhysicalDevice, u32) {
    let devices = unsafe { instance.enumerate_physical_devices() }.unwrap();
    devices
        .into_iter()
        .find_map(|d| {
            let families = unsafe { instance.get_physical_device_queue_family_properties(d) };
            let family = families.iter().position(|f| {
                f.queue_flags
                    .contains(vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE)
            })?;
            Some((d, family as u32))
        })
        .expect("a Vulkan device with a graphics and compute queue")
}

/// The application's Vulkan objects, made and destroyed by the application, not by sward.
struct Application {
    entry: ash::Entry,
    instance: ash::Instance,
    physical_device: vk::PhysicalDevice,
    device: ash::Device,
    queue_family: u32,
    queue: vk::Queue,
}

impl Application {
    fn new() -> Application {
        let entry = unsafe { ash::Entry::load() }.expect("the Vulkan loader");
        let instance = application_instance(&entry);
        let (physical_device, queue_family) = first_device(&instance);
        let device = create_device_for(&instance, physical_device, queue_family, &[]).unwrap();
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        Application {
            entry,
            instance,
            physical_device,
            device,
            queue_family,
            queue,
        }
    }

    /// sward in this device, validation required, allocating from `allocator` where given.
    fn sward(&self, allocator: Option<Arc<Mutex<Allocator>>>) -> Arc<Context> {
        let existing = ExistingDevice {
            entry: self.entry.clone(),
            instance: self.instance.clone(),
            physical_device: self.physical_device,
            device: self.device.clone(),
            queue_family: self.queue_family,
            queue: self.queue,
            debug_utils: true,
            allocator,
        };
        let desc = ContextDesc {
            validation: Validation::Required,
            ..ContextDesc::default()
        };
        Context::from_device(existing, &desc).unwrap()
    }

    /// sward is gone; the device and instance are still the application's to destroy.
    fn destroy(self) {
        unsafe {
            self.device.destroy_device(None);
            self.instance.destroy_instance(None);
        }
    }
}

#[test]
fn grass_draws_into_an_applications_own_device_and_frame() {
    let app = Application::new();
    let pixels = {
        let ctx = app.sward(None);
        let pixels = draw_over_the_application(&ctx);
        common::assert_validation_clean(&ctx);
        pixels
    };
    app.destroy();
    assert_grass_over_the_application(&pixels);
}

/// The application's allocator (`ExistingDevice::allocator`): sward's buffers and images come
/// from it while sward lives, all are freed when sward is dropped, and the picture is the same
/// grass over the application's frame.
#[test]
fn grass_allocates_from_the_applications_allocator_when_given_one() {
    let app = Application::new();
    let allocator = Arc::new(Mutex::new(
        Allocator::new(&AllocatorCreateDesc {
            instance: app.instance.clone(),
            device: app.device.clone(),
            physical_device: app.physical_device,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        })
        .unwrap(),
    ));
    let allocations = || allocator.lock().unwrap().generate_report().allocations.len();
    {
        let ctx = app.sward(Some(Arc::clone(&allocator)));
        let buffer = sward_gpu::buffer::Buffer::new(
            &ctx,
            "a probe",
            1024,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            sward_gpu::gpu_allocator::MemoryLocation::GpuOnly,
        )
        .unwrap();
        assert_eq!(allocations(), 1, "sward's buffer is not in the application's allocator");
        drop(buffer);
        let pixels = draw_over_the_application(&ctx);
        assert_grass_over_the_application(&pixels);
        common::assert_validation_clean(&ctx);
    }
    assert_eq!(
        allocations(),
        0,
        "sward left allocations in the application's allocator"
    );
    drop(allocator);
    app.destroy();
}

/// The picture of [`draw_over_the_application`]: the application's red backdrop at the top and
/// its nearer object on the left untouched, grass over the backdrop on the right.
fn assert_grass_over_the_application(pixels: &[u8]) {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"));
    image::RgbaImage::from_raw(WIDTH, HEIGHT, pixels.to_vec())
        .unwrap()
        .save(dir.join("embed-actual.png"))
        .unwrap();
    let at = |x: u32, y: u32| {
        let i = 4 * (y * WIDTH + x) as usize;
        [pixels[i], pixels[i + 1], pixels[i + 2]]
    };
    let red = |[r, g, b]: [u8; 3]| r > 150 && g < 60 && b < 60;
    let grass = |[r, g, b]: [u8; 3]| g > r && g > b;
    assert!(
        (0..WIDTH).all(|x| red(at(x, 0))),
        "the top row is the application's backdrop, not a sky"
    );
    let left = (0..WIDTH / 2 - 4).flat_map(|x| (0..HEIGHT).map(move |y| (x, y)));
    assert!(
        left.clone().all(|(x, y)| red(at(x, y))),
        "grass drew over the application's nearer object on the left"
    );
    let right = (WIDTH / 2 + 4..WIDTH).flat_map(|x| (0..HEIGHT).map(move |y| (x, y)));
    let blades = right.filter(|&(x, y)| grass(at(x, y))).count() as u32;
    assert!(
        blades > WIDTH * HEIGHT / 10,
        "too little grass on the right: {blades} pixels"
    );
}

/// The application's depth format: one with a stencil part (or 16-bit), not sward's own
/// D32_SFLOAT, so the grass is seen to draw into whatever depth the application keeps.
fn application_depth_format(ctx: &Context) -> vk::Format {
    let formats = [
        vk::Format::D24_UNORM_S8_UINT,
        vk::Format::D32_SFLOAT_S8_UINT,
        vk::Format::D16_UNORM,
    ];
    *formats
        .iter()
        .find(|&&f| {
            let props = unsafe {
                ctx.instance
                    .get_physical_device_format_properties(ctx.physical_device, f)
            };
            props
                .optimal_tiling_features
                .contains(vk::FormatFeatureFlags::DEPTH_STENCIL_ATTACHMENT)
        })
        .expect("a depth format besides D32_SFLOAT")
}

/// The application's frame: its backdrop and near object, then sward's grass over them, read
/// back as RGBA8.
fn draw_over_the_application(ctx: &std::sync::Arc<Context>) -> Vec<u8> {
    let (scene, field) = application_scene();
    let mut headless = application_headless(ctx, &scene, &field, vk::SampleCountFlags::TYPE_1);
    let desc = headless.frame(&scene, field.size, (0.5, 4));
    let d = &ctx.device;
    ctx.submit_and_wait("the application's frame", |cmd| {
        let target = &headless.target;
        target.begin(d, cmd);
        let views = sward_gpu::TargetViews {
            over_caller: true,
            ..target.views()
        };
        application_draws(d, cmd, &views);
        // The application's writes must be done before sward's draw reads and writes them.
        let written = sward_gpu::barrier::Access::COLOR_ATTACHMENT;
        sward_gpu::barrier::memory(d, cmd, written, written);
        let depth = sward_gpu::barrier::Access::DEPTH_ATTACHMENT;
        sward_gpu::barrier::memory(d, cmd, depth, depth);
        headless
            .renderer
            .record_frame(cmd, 0, &desc, Passes::ALL, Some(&views), None);
        target.finish(d, cmd);
    })
    .unwrap();
    headless.target.pixels()
}

/// sward drawing `field` into targets of the application's depth format and `samples`.
fn application_headless(
    ctx: &Arc<Context>,
    scene: &Scene,
    field: &sward_core::field::Field,
    samples: vk::SampleCountFlags,
) -> Headless {
    let desc = RendererDesc {
        target: TargetFormat {
            color: OFFSCREEN_FORMAT,
            depth: application_depth_format(ctx),
            samples,
            depth_direction: sward_gpu::pipelines::DepthDirection::Forward,
        },
        ..RendererDesc::for_quality(&ctx.info, OFFSCREEN_FORMAT, scene.quality.preset, 1)
    };
    let mut headless = Headless::with_desc(ctx, WIDTH, HEIGHT, &desc).unwrap();
    headless.renderer.upload(field).unwrap();
    headless.renderer.upload_ground(field.ground.as_ref()).unwrap();
    headless
}

/// The grass the application adds: a small field seen through the application's own view
/// matrix, given to sward as a camera.
fn application_scene() -> (Scene, sward_core::field::Field) {
    let mut scene = Scene::default();
    scene.field.blades = 3000;
    scene.field.size = glam::Vec2::splat(6.0);
    let view = glam::camera::rh::view::look_at_mat4(glam::Vec3::new(0.0, 5.0, -9.0), glam::Vec3::ZERO, glam::Vec3::Y);
    scene.camera = Camera::from_view(view, 50.0, 0.1, 100.0);
    let field = scene.grow_field().unwrap();
    (scene, field)
}

/// The application's own drawing: a red backdrop at the far plane, and on the left half an
/// object at the very front (depth 0), as clears of its attachments.
fn application_draws(d: &ash::Device, cmd: vk::CommandBuffer, views: &sward_gpu::TargetViews) {
    let color = vk::RenderingAttachmentInfo::default()
        .image_view(views.color)
        .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::STORE)
        .clear_value(vk::ClearValue {
            color: vk::ClearColorValue {
                float32: [0.8, 0.0, 0.0, 1.0],
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
    let near_object = vk::ClearAttachment {
        aspect_mask: vk::ImageAspectFlags::DEPTH,
        color_attachment: 0,
        clear_value: vk::ClearValue {
            depth_stencil: vk::ClearDepthStencilValue { depth: 0.0, stencil: 0 },
        },
    };
    let left = vk::ClearRect {
        rect: vk::Rect2D {
            offset: vk::Offset2D { x: 0, y: 0 },
            extent: vk::Extent2D {
                width: views.extent.width / 2,
                height: views.extent.height,
            },
        },
        base_array_layer: 0,
        layer_count: 1,
    };
    unsafe {
        d.cmd_clear_attachments(cmd, &[near_object], &[left]);
        d.cmd_end_rendering(cmd);
    }
}

/// The application's depth for occlusion (`TargetViews::occlusion`): its near object on the left
/// is folded into sward's depth pyramid, so the grass behind it is culled — not drawn and then
/// hidden — on single-sample and 4× targets. The pyramid's left half holds the object's depth,
/// the cull keeps fewer blades, and the picture is the one drawn without it.
#[test]
fn the_applications_depth_culls_the_grass_its_scene_hides() {
    let app = Application::new();
    {
        let ctx = app.sward(None);
        for samples in [vk::SampleCountFlags::TYPE_1, vk::SampleCountFlags::TYPE_4] {
            let mut frames = OccludedFrames::new(&ctx, samples);
            let unseen = frames.draw(false);
            let seen = frames.draw(true);
            let left_of_object = seen.pyramid[..(HIZ_SIDE * HIZ_SIDE) as usize]
                .chunks(HIZ_SIDE as usize)
                .all(|row| row[..(HIZ_SIDE / 2 - 2) as usize].iter().all(|&d| d == 0.0));
            assert!(
                left_of_object,
                "{samples:?}: the pyramid's left half is not the application's object"
            );
            assert!(
                seen.visible * 4 < unseen.visible * 3 && seen.visible * 5 > unseen.visible,
                "{samples:?}: {} blades visible with the application's depth, {} without",
                seen.visible,
                unseen.visible
            );
            let off = seen
                .pixels
                .iter()
                .zip(&unseen.pixels)
                .filter(|(a, b)| a.abs_diff(**b) > 8)
                .count();
            assert!(
                off * 200 < seen.pixels.len(),
                "{samples:?}: {off} channels differ with the application's depth"
            );
            assert_grass_over_the_application(&seen.pixels);
        }
        common::assert_validation_clean(&ctx);
    }
    app.destroy();
}

const HIZ_SIDE: u32 = sward_gpu::passes::depth_pyramid::HIZ_SIZE;

/// What one frame of [`OccludedFrames`] left: the picture, the blades the cull kept and level 0
/// of the depth pyramid.
struct OccludedFrame {
    pixels: Vec<u8>,
    visible: usize,
    pyramid: Vec<f32>,
}

/// sward over the application's frame as [`draw_over_the_application`] draws it, but with a
/// depth image of the application's own that sward may read.
struct OccludedFrames {
    headless: Headless,
    depth: sward_gpu::image::Image,
    depth_only: vk::ImageView,
    desc: FrameDesc,
    ctx: Arc<Context>,
}

impl OccludedFrames {
    fn new(ctx: &Arc<Context>, samples: vk::SampleCountFlags) -> OccludedFrames {
        let (scene, field) = application_scene();
        let format = application_depth_format(ctx);
        let headless = application_headless(ctx, &scene, &field, samples);
        let extent = vk::Extent2D {
            width: WIDTH,
            height: HEIGHT,
        };
        let usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::SAMPLED;
        let depth =
            sward_gpu::image::Image::new_2d(ctx, "the application's depth", extent, format, samples, usage).unwrap();
        // Its depth aspect alone, for sward to read (the format has a stencil part).
        let info = vk::ImageViewCreateInfo::default()
            .image(depth.raw)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(sward_gpu::image::subresource_range(vk::ImageAspectFlags::DEPTH));
        let depth_only = unsafe { ctx.device.create_image_view(&info, None) }.unwrap();
        OccludedFrames {
            desc: headless.frame(&scene, field.size, (0.5, 0)),
            headless,
            depth,
            depth_only,
            ctx: ctx.clone(),
        }
    }

    /// Cull and draw a frame (no simulation: every frame sees the same blades), handing sward
    /// the application's depth for occlusion or not.
    fn draw(&mut self, with_depth: bool) -> OccludedFrame {
        let d = &self.ctx.device;
        let passes = Passes {
            simulate: false,
            cull: true,
            draw: true,
        };
        self.ctx
            .submit_and_wait("the application's frame", |cmd| {
                let target = &self.headless.target;
                target.begin(d, cmd);
                let aspect = sward_gpu::image::aspect_of(self.depth.format);
                let fresh = (vk::ImageLayout::UNDEFINED, sward_gpu::barrier::Access::NOTHING);
                let depth_access = sward_gpu::barrier::Access::DEPTH_ATTACHMENT;
                let attachment = (vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL, depth_access);
                sward_gpu::barrier::image(d, cmd, self.depth.raw, aspect, fresh, attachment);
                let views = sward_gpu::TargetViews {
                    over_caller: true,
                    depth: self.depth.view,
                    occlusion: with_depth.then_some(sward_gpu::CallerDepth {
                        image: self.depth.raw,
                        view: self.depth_only,
                    }),
                    ..target.views()
                };
                application_draws(d, cmd, &views);
                let written = sward_gpu::barrier::Access::COLOR_ATTACHMENT;
                sward_gpu::barrier::memory(d, cmd, written, written);
                sward_gpu::barrier::memory(d, cmd, depth_access, depth_access);
                self.headless
                    .renderer
                    .record_frame(cmd, 0, &self.desc, passes, Some(&views), None);
                target.finish(d, cmd);
            })
            .unwrap();
        let renderer = &self.headless.renderer;
        OccludedFrame {
            pixels: self.headless.target.pixels(),
            visible: renderer.read_visible().unwrap().0.len(),
            pyramid: renderer.read_depth_pyramid().unwrap().swap_remove(0),
        }
    }
}

impl Drop for OccludedFrames {
    fn drop(&mut self) {
        unsafe {
            let _ = self.ctx.device.device_wait_idle();
            self.ctx.device.destroy_image_view(self.depth_only, None);
        }
    }
}
