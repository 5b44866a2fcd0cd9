//! An application's own world, drawn by wgpu: a cube on the ground, lit flat, with a depth test
//! that runs either way (forward or reverse Z). Shared by the tests and the `meadow` example.

use glam::{Mat4, Vec3};

const SHADER: &str = r#"
struct Camera { model_view_proj: mat4x4<f32>, view_proj: mat4x4<f32>, color: vec4<f32> };
@group(0) @binding(0) var<uniform> camera: Camera;

struct Out { @builtin(position) position: vec4<f32>, @location(0) shade: f32 };

// Instance 0 is the cube; instance 1 the ground around it, a square at y = 0 (the model matrix
// scales the cube only).
@vertex
fn vs(@builtin(vertex_index) i: u32, @builtin(instance_index) instance: u32) -> Out {
    // 6 faces × 2 triangles; each face's corners from its axis and side.
    let face = i / 6u;
    let corner = array<vec2<f32>, 6>(vec2(-1., -1.), vec2(1., -1.), vec2(1., 1.), vec2(-1., -1.), vec2(1., 1.), vec2(-1., 1.))[i % 6u];
    let axis = face % 3u;
    let side = select(-1.0, 1.0, face < 3u);
    var p = vec3<f32>(0.0);
    var n = vec3<f32>(0.0);
    if axis == 0u { p = vec3(side, corner.x, corner.y); n = vec3(side, 0., 0.); }
    if axis == 1u { p = vec3(corner.y, side, corner.x); n = vec3(0., side, 0.); }
    if axis == 2u { p = vec3(corner.x, corner.y, side); n = vec3(0., 0., side); }
    var out: Out;
    out.position = camera.model_view_proj * vec4(p, 1.0);
    out.shade = 0.55 + 0.45 * max(dot(n, normalize(vec3(0.4, 0.8, 0.3))), 0.0);
    if instance == 1u {
        out.position = camera.view_proj * vec4(80.0 * corner.x, 0.0, 80.0 * corner.y, 1.0);
        out.shade = -1.0;
    }
    return out;
}

@fragment
fn fs(in: Out) -> @location(0) vec4<f32> {
    // The ground: the meadow's turf colour (linear).
    if in.shade < 0.0 { return vec4(0.07, 0.12, 0.03, 1.0); }
    return vec4(camera.color.rgb * in.shade, 1.0);
}
"#;

/// The cube's colour (linear): a red nothing in a meadow has.
pub const CUBE_COLOR: [f32; 3] = [0.8, 0.05, 0.05];

/// A cube's pipeline and uniforms for one target.
pub struct Cube {
    pipeline: wgpu::RenderPipeline,
    uniforms: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    /// Whether the target's depth runs reversed (1 near).
    reversed: bool,
}

impl Cube {
    /// A cube drawn into `color` and `depth` attachments of `samples` samples.
    pub fn new(
        device: &wgpu::Device,
        color: wgpu::TextureFormat,
        depth: wgpu::TextureFormat,
        samples: u32,
        reversed: bool,
    ) -> Cube {
        // Parsed here and handed over as naga's module: wgpu then has no source text to attach
        // as debug information (OpSource WGSL, which Debian 12's validation layer rejects).
        let parsed = wgpu::naga::front::wgsl::parse_str(SHADER).expect("the cube's WGSL");
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("cube"),
            source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(parsed)),
        });
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("cube camera"),
            size: 144,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: None,
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: uniforms.as_entire_binding(),
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: None,
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("cube"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &[Some(color.into())],
            }),
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: depth,
                depth_write_enabled: Some(true),
                depth_compare: Some(if reversed {
                    wgpu::CompareFunction::Greater
                } else {
                    wgpu::CompareFunction::Less
                }),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState {
                count: samples,
                ..Default::default()
            },
            multiview_mask: None,
            cache: None,
        });
        Cube {
            pipeline,
            uniforms,
            bind_group,
            reversed,
        }
    }

    /// Clear `color` to `background` and the depth to its far plane, then draw the cube at
    /// `center` with half-size `half` through `view_proj` (wgpu's clip space), and with
    /// `ground` the ground around it.
    pub fn draw(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        (color, resolve, depth): (&wgpu::TextureView, Option<&wgpu::TextureView>, &wgpu::TextureView),
        view_proj: Mat4,
        (center, half): (Vec3, f32),
        (background, ground): (wgpu::Color, bool),
    ) {
        let model = Mat4::from_translation(center) * Mat4::from_scale(Vec3::splat(half));
        let mut words = (view_proj * model).to_cols_array().to_vec();
        words.extend(view_proj.to_cols_array());
        words.extend(CUBE_COLOR);
        words.push(1.0);
        queue.write_buffer(&self.uniforms, 0, bytemuck::cast_slice(&words));
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("the application's world"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: color,
                depth_slice: None,
                resolve_target: resolve,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(background),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(if self.reversed { 0.0 } else { 1.0 }),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.draw(0..36, 0..1);
        if ground {
            pass.draw(0..6, 1..2);
        }
    }
}
