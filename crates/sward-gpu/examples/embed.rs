//! An application that owns its Vulkan device and draws its own world — a ground plane, a sky and
//! a ball rolling across the ground — and adds sward's grass to its frame through the library:
//! the grass stands on the application's ground, is hidden where the ball is in front of it,
//! and the ball tramples it. Headless: 120 frames at 60 fps, the last written to a PNG.
//!
//! `cargo run --release -p sward-gpu --example embed [-- OUT.png]` (default `embed.png`)
//!
//! The application's side is plain `ash`; sward's side is five calls: `create_device_for` (the
//! device with what sward needs enabled), `Context::from_device`, `Renderer::new`,
//! `upload_field`, and `record_frame` into the application's command buffer each frame.

use std::error::Error;

use ash::vk;
use glam::{Mat4, Vec3, Vec4};
use sward_core::frame::Sphere;
use sward_core::{Camera, FrameDesc, Scene};
use sward_gpu::image::subresource_range;
use sward_gpu::pipelines::{TargetFormat, DEPTH_FORMAT};
use sward_gpu::{ContextDesc, ExistingDevice, Passes, Renderer, RendererDesc, TargetViews, Validation};

const WIDTH: u32 = 640;
const HEIGHT: u32 = 360;
const FRAMES: u32 = 120;
const COLOR_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;
const BALL_RADIUS: f32 = 0.8;
const FOV_Y_DEGREES: f32 = 50.0;
const NEAR: f32 = 0.1;
const FAR: f32 = 100.0;

fn main() -> Result<(), Box<dyn Error>> {
    let out = std::env::args().nth(1).unwrap_or_else(|| "embed.png".into());

    // The application's Vulkan: instance, device (made with what sward needs enabled), queue.
    let entry = unsafe { ash::Entry::load()? };
    let app_info = vk::ApplicationInfo::default().api_version(vk::API_VERSION_1_3);
    let instance =
        unsafe { entry.create_instance(&vk::InstanceCreateInfo::default().application_info(&app_info), None)? };
    let (physical, family) = pick_device(&instance).ok_or("no Vulkan device with a graphics and compute queue")?;
    let device = sward_gpu::create_device_for(&instance, physical, family, &[])?;
    let queue = unsafe { device.get_device_queue(family, 0) };

    // Its frame (colour, depth, read-back) and its world's pipeline.
    let frame = AppFrame::new(&instance, physical, &device)?;
    let world = WorldPipeline::new(&device)?;
    let pool =
        unsafe { device.create_command_pool(&vk::CommandPoolCreateInfo::default().queue_family_index(family), None)? };
    let cmd = unsafe {
        device.allocate_command_buffers(
            &vk::CommandBufferAllocateInfo::default()
                .command_pool(pool)
                .command_buffer_count(1),
        )?[0]
    };
    let fence = unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None)? };

    // sward in the application's device: a field of grass on the application's ground (y = 0).
    let existing = ExistingDevice {
        entry: entry.clone(),
        instance: instance.clone(),
        physical_device: physical,
        device: device.clone(),
        queue_family: family,
        queue,
        debug_utils: false,
        // Or the application's own `sward_gpu::gpu_allocator` allocator, shared.
        allocator: None,
    };
    let ctx = sward_gpu::Context::from_device(
        existing,
        &ContextDesc {
            validation: Validation::Off,
            ..ContextDesc::default()
        },
    )?;
    let mut scene = Scene::default();
    scene.field.blades = 40_000;
    scene.field.size = glam::Vec2::splat(10.0);
    scene.field.height = [0.5, 1.1];
    // A light breeze, so the trail shows.
    scene.wind[0].strength *= 0.3;
    let desc = RendererDesc {
        target: TargetFormat {
            color: COLOR_FORMAT,
            depth: DEPTH_FORMAT,
            samples: vk::SampleCountFlags::TYPE_1,
            depth_direction: sward_gpu::pipelines::DepthDirection::Forward,
        },
        ..RendererDesc::for_quality(&ctx.info, COLOR_FORMAT, scene.quality.preset, 1)
    };
    let mut renderer = Renderer::new(&ctx, &desc)?;
    let field = scene.grow_field()?;
    renderer.upload(&field)?;

    // The application's camera: its own view and projection (depth 0 near, 1 far, y down, as
    // sward's), and sward's camera made from the same view.
    let eye = Vec3::new(0.0, 5.0, -7.0);
    let view = glam::camera::rh::view::look_at_mat4(eye, Vec3::new(0.0, 0.0, 0.8), Vec3::Y);
    let camera = Camera::from_view(view, FOV_Y_DEGREES, NEAR, FAR);
    scene.camera = camera;
    let projection = camera.projection(WIDTH as f32 / HEIGHT as f32);
    let view_proj = projection * view;
    let steps = ((1.0 / 60.0) / scene.simulation.step).round() as u32;

    for k in 0..FRAMES {
        let t = k as f32 / 60.0;
        // The frame as sward is to draw it: the scene's settings, seen through the
        // application's own matrices, with the application's ball as a collider.
        let ball = Vec3::new(-5.0 + 4.0 * t, BALL_RADIUS * 0.7, 0.5);
        let mut desc =
            FrameDesc::of_scene(&scene, field.size, (t, steps), [WIDTH, HEIGHT]).with_view_projection(view, projection);
        desc.colliders.pushing = vec![Sphere {
            center: ball,
            radius: BALL_RADIUS,
        }];
        let push = WorldPush {
            inverse_view_proj: view_proj.inverse(),
            eye: eye.extend(0.0),
            forward: (camera.target - camera.position).normalize().extend(0.0),
            ball: ball.extend(BALL_RADIUS),
            lens: Vec4::new(NEAR, FAR, WIDTH as f32, HEIGHT as f32),
        };
        unsafe {
            device.begin_command_buffer(cmd, &vk::CommandBufferBeginInfo::default())?;
            frame.to_attachments(&device, cmd);
            world.draw(&device, cmd, &frame, &push);
            // Its writes done before sward draws into the same attachments.
            let written = sward_gpu::barrier::Access::COLOR_ATTACHMENT;
            sward_gpu::barrier::memory(&device, cmd, written, written);
            let depth = sward_gpu::barrier::Access::DEPTH_ATTACHMENT;
            sward_gpu::barrier::memory(&device, cmd, depth, depth);
            let views = TargetViews {
                color: frame.color.1,
                resolve: None,
                depth: frame.depth.1,
                extent: vk::Extent2D {
                    width: WIDTH,
                    height: HEIGHT,
                },
                keep_depth: false,
                over_caller: true,
                // The ball's depth culls the grass it hides (D32 has one aspect: one view serves).
                occlusion: Some(sward_gpu::CallerDepth {
                    image: frame.depth.0,
                    view: frame.depth.1,
                }),
            };
            renderer.record_frame(cmd, 0, &desc, Passes::ALL, Some(&views), None);
            if k + 1 == FRAMES {
                frame.copy_out(&device, cmd);
            }
            device.end_command_buffer(cmd)?;
            let cmds = [cmd];
            device.queue_submit(queue, &[vk::SubmitInfo::default().command_buffers(&cmds)], fence)?;
            device.wait_for_fences(&[fence], true, u64::MAX)?;
            device.reset_fences(&[fence])?;
        }
    }
    let pixels = frame.read(&device)?;
    image::RgbaImage::from_raw(WIDTH, HEIGHT, pixels)
        .ok_or("the frame has the wrong size")?
        .save(&out)?;
    println!(
        "wrote {out}: the application's ground and ball, with {} blades of sward's grass",
        field.blades.len()
    );

    // sward first (it destroys only what it made), then the application's own.
    drop(renderer);
    drop(ctx);
    unsafe {
        device.destroy_fence(fence, None);
        device.destroy_command_pool(pool, None);
        world.destroy(&device);
        frame.destroy(&device);
        device.destroy_device(None);
        instance.destroy_instance(None);
    }
    Ok(())
}

/// The first device with a queue family for graphics and compute.
fn pick_device(instance: &ash::Instance) -> Option<(vk::PhysicalDevice, u32)> {
    let devices = unsafe { instance.enumerate_physical_devices() }.ok()?;
    devices.into_iter().find_map(|d| {
        let families = unsafe { instance.get_physical_device_queue_family_properties(d) };
        let wanted = vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE;
        let family = families.iter().position(|f| f.queue_flags.contains(wanted))?;
        Some((d, family as u32))
    })
}

/// The application's frame: a colour and a depth image with their memory and views, and a
/// host-visible buffer the last frame is copied into.
struct AppFrame {
    color: (vk::Image, vk::ImageView, vk::DeviceMemory),
    depth: (vk::Image, vk::ImageView, vk::DeviceMemory),
    readback: (vk::Buffer, vk::DeviceMemory),
}

impl AppFrame {
    fn new(
        instance: &ash::Instance,
        physical: vk::PhysicalDevice,
        device: &ash::Device,
    ) -> Result<AppFrame, vk::Result> {
        let memory = unsafe { instance.get_physical_device_memory_properties(physical) };
        let color_usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
        let color = image(device, &memory, COLOR_FORMAT, color_usage, vk::ImageAspectFlags::COLOR)?;
        // Sampled too: sward reads it to cull the grass the ball hides.
        let depth_usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::SAMPLED;
        let depth = image(device, &memory, DEPTH_FORMAT, depth_usage, vk::ImageAspectFlags::DEPTH)?;
        let info = vk::BufferCreateInfo::default()
            .size(4 * WIDTH as u64 * HEIGHT as u64)
            .usage(vk::BufferUsageFlags::TRANSFER_DST);
        let buffer = unsafe { device.create_buffer(&info, None)? };
        let needs = unsafe { device.get_buffer_memory_requirements(buffer) };
        let visible = vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT;
        let readback = allocate(device, &memory, needs, visible)?;
        unsafe { device.bind_buffer_memory(buffer, readback, 0)? };
        Ok(AppFrame {
            color,
            depth,
            readback: (buffer, readback),
        })
    }

    /// Both images ready to be drawn into (their old contents dropped: the world covers them).
    fn to_attachments(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        let barriers = [
            layout(
                self.color.0,
                vk::ImageAspectFlags::COLOR,
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            ),
            layout(
                self.depth.0,
                vk::ImageAspectFlags::DEPTH,
                vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
            ),
        ];
        unsafe { device.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().image_memory_barriers(&barriers)) };
    }

    /// Copy the colour image into the read-back buffer, after sward's draw.
    fn copy_out(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        let barrier = [vk::ImageMemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT)
            .src_access_mask(vk::AccessFlags2::COLOR_ATTACHMENT_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::TRANSFER)
            .dst_access_mask(vk::AccessFlags2::TRANSFER_READ)
            .old_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .new_layout(vk::ImageLayout::TRANSFER_SRC_OPTIMAL)
            .image(self.color.0)
            .subresource_range(subresource_range(vk::ImageAspectFlags::COLOR))];
        let region = vk::BufferImageCopy::default()
            .image_subresource(vk::ImageSubresourceLayers {
                aspect_mask: vk::ImageAspectFlags::COLOR,
                mip_level: 0,
                base_array_layer: 0,
                layer_count: 1,
            })
            .image_extent(vk::Extent3D {
                width: WIDTH,
                height: HEIGHT,
                depth: 1,
            });
        unsafe {
            device.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().image_memory_barriers(&barrier));
            let layout = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
            device.cmd_copy_image_to_buffer(cmd, self.color.0, layout, self.readback.0, &[region]);
        }
    }

    /// The copied frame as RGBA8, top row first (after the GPU finished).
    fn read(&self, device: &ash::Device) -> Result<Vec<u8>, vk::Result> {
        let bytes = 4 * WIDTH as usize * HEIGHT as usize;
        unsafe {
            let at = device.map_memory(self.readback.1, 0, bytes as u64, vk::MemoryMapFlags::empty())?;
            let pixels = std::slice::from_raw_parts(at as *const u8, bytes).to_vec();
            device.unmap_memory(self.readback.1);
            Ok(pixels)
        }
    }

    unsafe fn destroy(&self, device: &ash::Device) {
        for (image, view, memory) in [self.color, self.depth] {
            device.destroy_image_view(view, None);
            device.destroy_image(image, None);
            device.free_memory(memory, None);
        }
        device.destroy_buffer(self.readback.0, None);
        device.free_memory(self.readback.1, None);
    }
}

/// A device-local 2D image of the frame's size, its memory and a view.
fn image(
    device: &ash::Device,
    memory: &vk::PhysicalDeviceMemoryProperties,
    format: vk::Format,
    usage: vk::ImageUsageFlags,
    aspect: vk::ImageAspectFlags,
) -> Result<(vk::Image, vk::ImageView, vk::DeviceMemory), vk::Result> {
    let info = vk::ImageCreateInfo::default()
        .image_type(vk::ImageType::TYPE_2D)
        .format(format)
        .extent(vk::Extent3D {
            width: WIDTH,
            height: HEIGHT,
            depth: 1,
        })
        .mip_levels(1)
        .array_layers(1)
        .samples(vk::SampleCountFlags::TYPE_1)
        .usage(usage);
    unsafe {
        let image = device.create_image(&info, None)?;
        let needs = device.get_image_memory_requirements(image);
        let bound = allocate(device, memory, needs, vk::MemoryPropertyFlags::DEVICE_LOCAL)?;
        device.bind_image_memory(image, bound, 0)?;
        let view = vk::ImageViewCreateInfo::default()
            .image(image)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(subresource_range(aspect));
        Ok((image, device.create_image_view(&view, None)?, bound))
    }
}

/// Memory for `needs` of the first type with `flags`.
fn allocate(
    device: &ash::Device,
    memory: &vk::PhysicalDeviceMemoryProperties,
    needs: vk::MemoryRequirements,
    flags: vk::MemoryPropertyFlags,
) -> Result<vk::DeviceMemory, vk::Result> {
    let types = &memory.memory_types[..memory.memory_type_count as usize];
    let index = types
        .iter()
        .enumerate()
        .position(|(i, t)| needs.memory_type_bits & (1 << i) != 0 && t.property_flags.contains(flags))
        .ok_or(vk::Result::ERROR_OUT_OF_DEVICE_MEMORY)?;
    let info = vk::MemoryAllocateInfo::default()
        .allocation_size(needs.size)
        .memory_type_index(index as u32);
    unsafe { device.allocate_memory(&info, None) }
}

/// An image from whatever it held to `new` (contents dropped), after any earlier use of it.
fn layout(image: vk::Image, aspect: vk::ImageAspectFlags, new: vk::ImageLayout) -> vk::ImageMemoryBarrier2<'static> {
    vk::ImageMemoryBarrier2::default()
        .src_stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)
        .src_access_mask(vk::AccessFlags2::MEMORY_WRITE)
        .dst_stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)
        .dst_access_mask(vk::AccessFlags2::MEMORY_READ | vk::AccessFlags2::MEMORY_WRITE)
        .old_layout(vk::ImageLayout::UNDEFINED)
        .new_layout(new)
        .image(image)
        .subresource_range(subresource_range(aspect))
}

/// What the world's shader needs: rays from the pixels, the ball, and how to write depth as
/// sward's projection does (0 at `near`, 1 at `far`).
#[repr(C)]
#[derive(Clone, Copy)]
struct WorldPush {
    inverse_view_proj: Mat4,
    eye: Vec4,
    forward: Vec4,
    /// Centre (xyz) and radius (w).
    ball: Vec4,
    /// near, far, width, height.
    lens: Vec4,
}

/// The application's world in one screen-covering triangle: every pixel's ray meets the ball,
/// the ground or the sky, and writes its colour and depth.
const WORLD_VERT: &str = r#"#version 460
void main() {
    vec2 corner = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
"#;

const WORLD_FRAG: &str = r#"#version 460
layout(push_constant) uniform World {
    mat4 inverse_view_proj;
    vec4 eye, forward, ball, lens;
};
layout(location = 0) out vec4 color;

void main() {
    vec2 ndc = gl_FragCoord.xy / lens.zw * 2.0 - 1.0;
    vec4 far_point = inverse_view_proj * vec4(ndc, 1.0, 1.0);
    vec3 ray = normalize(far_point.xyz / far_point.w - eye.xyz);
    float hit = 1e30;
    vec3 normal = vec3(0.0);
    vec3 albedo = vec3(0.0);
    // The ball.
    vec3 to_eye = eye.xyz - ball.xyz;
    float b = dot(to_eye, ray), c = dot(to_eye, to_eye) - ball.w * ball.w;
    if (b * b - c > 0.0 && -b - sqrt(b * b - c) > 0.0) {
        hit = -b - sqrt(b * b - c);
        normal = normalize(eye.xyz + ray * hit - ball.xyz);
        albedo = vec3(0.75, 0.72, 0.68);
    }
    // The ground, y = 0.
    float ground = -eye.y / ray.y;
    if (ray.y < 0.0 && ground < hit) {
        hit = ground;
        normal = vec3(0.0, 1.0, 0.0);
        albedo = vec3(0.16, 0.11, 0.07);
    }
    if (hit > 1e29) {
        color = vec4(mix(vec3(0.75, 0.82, 0.9), vec3(0.35, 0.55, 0.85), clamp(ray.y * 3.0, 0.0, 1.0)), 1.0);
        gl_FragDepth = 1.0;
        return;
    }
    vec3 sun = normalize(vec3(0.4, 0.8, 0.3));
    color = vec4(albedo * (0.35 + 0.65 * max(dot(normal, sun), 0.0)), 1.0);
    // Depth as sward's projection writes it: distance along the view, 0 at near, 1 at far.
    float d = hit * dot(ray, forward.xyz);
    gl_FragDepth = lens.y * (d - lens.x) / (d * (lens.y - lens.x));
}
"#;

struct WorldPipeline {
    layout: vk::PipelineLayout,
    pipeline: vk::Pipeline,
}

impl WorldPipeline {
    fn new(device: &ash::Device) -> Result<WorldPipeline, Box<dyn Error>> {
        let vert = sward_gpu::glsl::compile_source("world.vert", WORLD_VERT)?;
        let frag = sward_gpu::glsl::compile_source("world.frag", WORLD_FRAG)?;
        let module = |words: &[u32]| unsafe {
            device.create_shader_module(&vk::ShaderModuleCreateInfo::default().code(words), None)
        };
        let (vert, frag) = (module(&vert)?, module(&frag)?);
        let push = [vk::PushConstantRange {
            stage_flags: vk::ShaderStageFlags::FRAGMENT,
            offset: 0,
            size: std::mem::size_of::<WorldPush>() as u32,
        }];
        let layout = unsafe {
            device.create_pipeline_layout(
                &vk::PipelineLayoutCreateInfo::default().push_constant_ranges(&push),
                None,
            )?
        };
        let stages = [
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::VERTEX)
                .module(vert)
                .name(c"main"),
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::FRAGMENT)
                .module(frag)
                .name(c"main"),
        ];
        let formats = [COLOR_FORMAT];
        let mut rendering = vk::PipelineRenderingCreateInfo::default()
            .color_attachment_formats(&formats)
            .depth_attachment_format(DEPTH_FORMAT);
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default();
        let assembly =
            vk::PipelineInputAssemblyStateCreateInfo::default().topology(vk::PrimitiveTopology::TRIANGLE_LIST);
        let viewports = [vk::Viewport {
            width: WIDTH as f32,
            height: HEIGHT as f32,
            max_depth: 1.0,
            ..Default::default()
        }];
        let scissors = [vk::Rect2D {
            extent: vk::Extent2D {
                width: WIDTH,
                height: HEIGHT,
            },
            ..Default::default()
        }];
        let viewport = vk::PipelineViewportStateCreateInfo::default()
            .viewports(&viewports)
            .scissors(&scissors);
        let raster = vk::PipelineRasterizationStateCreateInfo::default().line_width(1.0);
        let multisample =
            vk::PipelineMultisampleStateCreateInfo::default().rasterization_samples(vk::SampleCountFlags::TYPE_1);
        let depth = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(true)
            .depth_write_enable(true)
            .depth_compare_op(vk::CompareOp::ALWAYS);
        let blend = [vk::PipelineColorBlendAttachmentState::default().color_write_mask(vk::ColorComponentFlags::RGBA)];
        let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend);
        let info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&assembly)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth)
            .color_blend_state(&blend)
            .layout(layout)
            .push_next(&mut rendering);
        let pipeline = unsafe { device.create_graphics_pipelines(vk::PipelineCache::null(), &[info], None) }
            .map_err(|(_, e)| e)?[0];
        unsafe {
            device.destroy_shader_module(vert, None);
            device.destroy_shader_module(frag, None);
        }
        Ok(WorldPipeline { layout, pipeline })
    }

    /// Draw the world into the frame's attachments, clearing nothing (every pixel is written).
    fn draw(&self, device: &ash::Device, cmd: vk::CommandBuffer, frame: &AppFrame, push: &WorldPush) {
        let attachment = |view: vk::ImageView, layout: vk::ImageLayout| {
            vk::RenderingAttachmentInfo::default()
                .image_view(view)
                .image_layout(layout)
                .load_op(vk::AttachmentLoadOp::DONT_CARE)
                .store_op(vk::AttachmentStoreOp::STORE)
        };
        let colors = [attachment(frame.color.1, vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)];
        let depth = attachment(frame.depth.1, vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL);
        let area = vk::Rect2D {
            extent: vk::Extent2D {
                width: WIDTH,
                height: HEIGHT,
            },
            ..Default::default()
        };
        let info = vk::RenderingInfo::default()
            .render_area(area)
            .layer_count(1)
            .color_attachments(&colors)
            .depth_attachment(&depth);
        // SAFETY: `WorldPush` is plain floats, laid out as the shader's push constants.
        let bytes = unsafe {
            std::slice::from_raw_parts(
                (push as *const WorldPush).cast::<u8>(),
                std::mem::size_of::<WorldPush>(),
            )
        };
        unsafe {
            device.cmd_begin_rendering(cmd, &info);
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipeline);
            device.cmd_push_constants(cmd, self.layout, vk::ShaderStageFlags::FRAGMENT, 0, bytes);
            device.cmd_draw(cmd, 3, 1, 0, 0);
            device.cmd_end_rendering(cmd);
        }
    }

    unsafe fn destroy(&self, device: &ash::Device) {
        device.destroy_pipeline(self.pipeline, None);
        device.destroy_pipeline_layout(self.layout, None);
    }
}
