//! The portable renderer's draw: the visible Bezier blades as triangle strips (one indirect
//! command per distance bucket, as the cull laid them out), the collider spheres, the ground
//! and the sky, into the caller's colour and depth attachments — front to back, so the depth
//! test rejects hidden ground and sky before they are shaded. Also what the draw reads beside
//! the field: the ground mesh and the paint maps.

use sward_core::commands::DISTANCE_BUCKETS;
use sward_core::declared::bindings;
use sward_core::gpu::PaintArea;
use sward_core::mesh::Mesh;
use sward_core::paint::GroundPaint;
use wgpu::util::DeviceExt;

use crate::field::{CullLists, PortableField, DRAWN_BUCKETS_OFFSET};
use crate::passes::generated::{GeneratedLists, GrassTexture};
use crate::passes::splats::{record_resolve, SplatPipelines, SplatShape, SplatTarget};
use crate::shaders::{PipelineSource, ShaderModules, DRAW_SOURCES};
use crate::{catch_errors, shader_module, BindGroups, Bindable, Bound, PortableError, Reading, FRAME};

/// Vertices of the sphere ground (scenery.wesl: 96 rings of 192 quads).
const SPHERE_GROUND_VERTICES: u32 = 96 * 192 * 6;
/// Vertices of a collider sphere (scenery.wesl: 16 rings of 32 quads).
pub(crate) const COLLIDER_VERTICES: u32 = 16 * 32 * 6;
/// A paint texel where nothing is painted (never read: the frame says there is no map).
const NO_PAINT: [u32; 4] = [u32::MAX, 0x0080_8080, u32::MAX, 0];

/// What the portable renderer draws into: the colour and depth formats and the samples per
/// pixel of the caller's attachments. Depth runs forward (0 near, `Less`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PortableTarget {
    /// The colour attachment's format (sward shades in linear light: an sRGB format encodes).
    pub color: wgpu::TextureFormat,
    /// The depth attachment's format.
    pub depth: wgpu::TextureFormat,
    /// Samples per pixel of both attachments.
    pub samples: u32,
}

/// One frame's attachments: the colour (multisampled where the target is, then resolved into
/// `resolve`) and the depth. The draw clears both.
pub struct PortableViews<'a> {
    /// The colour attachment, of the target's samples.
    pub color: &'a wgpu::TextureView,
    /// Where a multisampled colour is resolved to (None: single-sampled).
    pub resolve: Option<&'a wgpu::TextureView>,
    /// The depth attachment, of the target's samples.
    pub depth: &'a wgpu::TextureView,
}

/// What a frame draws besides the blades, as the last packed frame said.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct DrawnScenery {
    /// Collider spheres drawn (the pushing ones, then the cutters).
    pub colliders: u32,
    /// Spheres after them that only hide grass (drawn into the depth pyramid only).
    pub hiders: u32,
    /// Whether the ground is the sphere the shaders make.
    pub sphere_ground: bool,
}

/// The draws' pipelines.
#[derive(Clone)]
pub(crate) struct DrawPipelines {
    strips: Reading<wgpu::RenderPipeline>,
    ground: Reading<wgpu::RenderPipeline>,
    colliders: Reading<wgpu::RenderPipeline>,
    sky: Reading<wgpu::RenderPipeline>,
    /// The generated grass's listed blades, and its billboards.
    generated: Reading<wgpu::RenderPipeline>,
    billboards: Reading<wgpu::RenderPipeline>,
    /// Whether the device draws indirect with a count from a buffer
    /// (`MULTI_DRAW_INDIRECT_COUNT`): the blades' draw then stops at the farthest bucket that
    /// holds one.
    draw_count: bool,
}

impl DrawPipelines {
    pub fn new(
        device: &wgpu::Device,
        target: &PortableTarget,
        modules: &ShaderModules,
    ) -> Result<DrawPipelines, PortableError> {
        let [strips, ground, colliders, sky, generated, billboards] = &DRAW_SOURCES;
        let target = &Attachments::from(target);
        let render_pipeline =
            |source, topology, writes_depth| render_pipeline(device, (source, modules), target, topology, writes_depth);
        Ok(DrawPipelines {
            strips: render_pipeline(strips, wgpu::PrimitiveTopology::TriangleStrip, true)?,
            ground: render_pipeline(ground, wgpu::PrimitiveTopology::TriangleList, true)?,
            colliders: render_pipeline(colliders, wgpu::PrimitiveTopology::TriangleList, true)?,
            // The sky only where nothing else is: the depth still at the cleared 1.0.
            sky: render_pipeline(sky, wgpu::PrimitiveTopology::TriangleList, false)?,
            generated: render_pipeline(generated, wgpu::PrimitiveTopology::TriangleStrip, true)?,
            billboards: covering_pipeline(
                device,
                (billboards, modules),
                target,
                wgpu::PrimitiveTopology::TriangleList,
                (true, true),
            )?,
            draw_count: device.features().contains(wgpu::Features::MULTI_DRAW_INDIRECT_COUNT),
        })
    }
}

/// The ground mesh and the paint maps on the GPU.
pub(crate) struct Scenery {
    /// The mesh's vertices (position, normal), or a placeholder where the shaders make the ground.
    ground_vertices: wgpu::Buffer,
    /// The mesh's triangles and their index count.
    ground_indices: Option<(wgpu::Buffer, u32)>,
    paint: wgpu::Buffer,
    /// Where the paint maps lie (None: nothing painted).
    pub paint_area: Option<PaintArea>,
    /// The ground mesh as a height grid, where it is one (the trample map finds the ground's
    /// height on it).
    pub height_grid: Option<sward_core::gpu::GridBounds>,
}

impl Scenery {
    /// The plane or sphere the shaders make, nothing painted.
    pub fn new(device: &wgpu::Device) -> Scenery {
        Scenery {
            ground_vertices: storage(device, "sward ground placeholder", &[0u8; 32]),
            ground_indices: None,
            paint: storage(device, "sward paint maps", bytemuck::cast_slice(&[NO_PAINT])),
            paint_area: None,
            height_grid: None,
        }
    }

    /// Hold the ground `mesh` (None: the shaders make the plane or sphere).
    pub fn set_ground(&mut self, device: &wgpu::Device, mesh: Option<&Mesh>) {
        self.height_grid = mesh
            .and_then(Mesh::height_grid)
            .as_ref()
            .map(sward_core::gpu::GridBounds::of);
        let Some(mesh) = mesh else {
            self.ground_vertices = storage(device, "sward ground placeholder", &[0u8; 32]);
            self.ground_indices = None;
            return;
        };
        let vertices = mesh.pulled_vertices();
        let indices: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
        self.ground_vertices = storage(device, "sward ground vertices", bytemuck::cast_slice(&vertices));
        let index_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("sward ground indices"),
            contents: bytemuck::cast_slice(&indices),
            usage: wgpu::BufferUsages::INDEX,
        });
        self.ground_indices = Some((index_buffer, indices.len() as u32));
    }

    /// The ground mesh's vertices (a placeholder where the shaders make the ground).
    pub fn ground_vertices(&self) -> &wgpu::Buffer {
        &self.ground_vertices
    }

    /// Draw the ground with the pipeline and bind group set: the mesh, else the sphere
    /// (`sphere`) or plane the vertex stage makes.
    pub fn record_ground(&self, pass: &mut wgpu::RenderPass, sphere: bool) {
        match &self.ground_indices {
            Some((indices, count)) => {
                pass.set_index_buffer(indices.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..*count, 0, 0..1);
            }
            None if sphere => pass.draw(0..SPHERE_GROUND_VERTICES, 0..1),
            None => pass.draw(0..6, 0..1),
        }
    }

    /// The paint maps' texels (a placeholder where nothing is painted).
    pub fn paint(&self) -> &wgpu::Buffer {
        &self.paint
    }

    /// Hold `paint`'s maps (None, or no map: nothing painted).
    pub fn set_paint(&mut self, device: &wgpu::Device, paint: Option<&GroundPaint>) {
        let texels = paint
            .and_then(|p| p.map.as_ref())
            .map_or(&[NO_PAINT][..], |m| &m.texels);
        self.paint = storage(device, "sward paint maps", bytemuck::cast_slice(texels));
        self.paint_area = paint.map(PaintArea::of);
    }
}

/// A storage buffer holding `contents`.
fn storage(device: &wgpu::Device, label: &str, contents: &[u8]) -> wgpu::Buffer {
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents,
        usage: wgpu::BufferUsages::STORAGE,
    })
}

/// What one draw reads: the view's frame, the field, the view's lists, the scenery.
pub(crate) struct DrawInputs<'a> {
    pub frame: &'a wgpu::Buffer,
    pub field: &'a PortableField,
    pub lists: &'a CullLists,
    pub scenery: &'a Scenery,
    pub drawn: DrawnScenery,
    /// The trample map's texels (the billboards lie down where it says).
    pub trample: &'a wgpu::Buffer,
    /// The view's generated grass, and the billboards' painted texture where it draws them.
    pub generated: &'a GeneratedLists,
    pub grass_texture: Option<&'a GrassTexture>,
    /// The sun's shadow map and its sampler, which the shading reads (where the frame has
    /// shadows), at their bindings.
    pub shadow_map: [(u32, Bound<'a>); 2],
    /// Where the bind groups are made once.
    pub groups: &'a BindGroups,
}

/// Record the frame's draw into `views`: the Bezier blades, the generated grass, the splats
/// resolved (where the renderer splats), the colliders, the ground, the sky (front to back).
pub(crate) fn record_draw(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    (pipelines, splats): (&DrawPipelines, Option<(&SplatPipelines, &SplatTarget, SplatShape)>),
    inputs: &DrawInputs,
    views: &PortableViews,
) {
    let DrawInputs {
        frame,
        field,
        lists,
        scenery,
        drawn,
        trample,
        generated,
        grass_texture,
        shadow_map,
        groups,
    } = inputs;
    let b = Bound::Buffer;
    // What any of the draws reads (each pipeline's group binds those it uses): the frame, the
    // field and its lists, the scenery, the shadow map.
    let [map, sampler] = *shadow_map;
    let read = [
        (FRAME, b(frame)),
        (bindings::BLADES, b(&field.blades)),
        (bindings::VISIBLE, b(&lists.visible)),
        (bindings::CULL_COUNTERS, b(&lists.counters)),
        (bindings::PAINT, b(&scenery.paint)),
        (bindings::GROUND, b(&scenery.ground_vertices)),
        map,
        sampler,
    ];
    let bind = |pipeline: &Reading<wgpu::RenderPipeline>| groups.of(device, Bindable::Render(pipeline), &read);
    let [strips, ground, colliders, sky] = [
        &pipelines.strips,
        &pipelines.ground,
        &pipelines.colliders,
        &pipelines.sky,
    ]
    .map(bind);
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("sward portable draw"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: views.color,
            resolve_target: views.resolve,
            depth_slice: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: views.depth,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Clear(1.0),
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        ..Default::default()
    });
    // The buckets drawn as strips: those short of the splatted ones.
    let buckets = splats.map_or(DISTANCE_BUCKETS, |(.., shape)| {
        shape.first_splatted.min(DISTANCE_BUCKETS)
    });
    if field.count() > 0 && buckets > 0 {
        pass.set_pipeline(&pipelines.strips);
        pass.set_bind_group(0, &strips, &[]);
        // Up to the farthest bucket that holds a blade where the device draws with a count,
        // else every bucket (the empty ones draw nothing).
        match pipelines.draw_count {
            true => pass.multi_draw_indirect_count(&lists.draws, 0, &lists.counters, DRAWN_BUCKETS_OFFSET, buckets),
            false => pass.multi_draw_indirect(&lists.draws, 0, buckets),
        }
    }
    let [blades, billboards] = generated.generates();
    if blades {
        let bound = [
            (FRAME, b(frame)),
            (bindings::GENERATED_BLADES, b(generated.listed())),
            (bindings::PAINT, b(&scenery.paint)),
            map,
            sampler,
        ];
        let listed = groups.of(device, Bindable::Render(&pipelines.generated), &bound);
        pass.set_pipeline(&pipelines.generated);
        pass.set_bind_group(0, &listed, &[]);
        generated.record_draw(&mut pass);
    }
    if let (true, Some(texture)) = (billboards, grass_texture) {
        let bound = [
            (FRAME, b(frame)),
            (bindings::TRAMPLE, b(trample)),
            (bindings::GENERATED_BLADES, b(generated.listed())),
            (bindings::GRASS_TEXTURE, Bound::View(&texture.view)),
            (bindings::GRASS_SAMPLER, Bound::Sampler(&texture.sampler)),
            (bindings::PAINT, b(&scenery.paint)),
            map,
            sampler,
        ];
        let group = groups.of(device, Bindable::Render(&pipelines.billboards), &bound);
        pass.set_pipeline(&pipelines.billboards);
        pass.set_bind_group(0, &group, &[]);
        let rasterized = splats.is_some_and(|(.., shape)| shape.billboards_rasterized);
        generated.record_billboards(&mut pass, rasterized);
    }
    if let Some((splatting, target, _)) = splats {
        record_resolve((device, &mut pass), (splatting, target), inputs);
    }
    if drawn.colliders > 0 {
        pass.set_pipeline(&pipelines.colliders);
        pass.set_bind_group(0, &colliders, &[]);
        pass.draw(0..COLLIDER_VERTICES, 0..drawn.colliders);
    }
    pass.set_pipeline(&pipelines.ground);
    pass.set_bind_group(0, &ground, &[]);
    scenery.record_ground(&mut pass, drawn.sphere_ground);
    pass.set_pipeline(&pipelines.sky);
    pass.set_bind_group(0, &sky, &[]);
    pass.draw(0..3, 0..1);
}

/// The draws' record of what the frame draws besides the blades, from its description: the
/// spheres as the frame's block holds them, and the ground's shape.
pub(crate) fn drawn_scenery(desc: &sward_core::FrameDesc) -> DrawnScenery {
    let [pushing, cutting, hiding] = desc.colliders.packed_counts();
    DrawnScenery {
        colliders: pushing + cutting,
        hiders: hiding,
        sphere_ground: matches!(desc.ground, sward_core::frame::GroundShape::Sphere { .. }),
    }
}

/// The bind group of `pipeline`'s group 0 with `buffers` at their bindings (made once).
pub(crate) fn bind(
    (device, groups): (&wgpu::Device, &BindGroups),
    pipeline: &Reading<wgpu::RenderPipeline>,
    buffers: &[(u32, &wgpu::Buffer)],
) -> wgpu::BindGroup {
    let bound: Vec<(u32, Bound)> = buffers.iter().map(|&(k, b)| (k, Bound::Buffer(b))).collect();
    groups.of(device, Bindable::Render(pipeline), &bound)
}

/// What a draw's pipeline draws into: a colour format (None: depth only), the depth format and
/// the samples.
pub(crate) struct Attachments {
    pub color: Option<wgpu::TextureFormat>,
    pub depth: wgpu::TextureFormat,
    pub samples: u32,
}

impl From<&PortableTarget> for Attachments {
    fn from(t: &PortableTarget) -> Attachments {
        Attachments {
            color: Some(t.color),
            depth: t.depth,
            samples: t.samples,
        }
    }
}

/// A draw's pipeline from `source` composed of `modules`, for `target`: no face culled (a blade
/// is seen from both sides), depth tested `Less` and written (`writes_depth`), else tested
/// `LessEqual` only.
pub(crate) fn render_pipeline(
    device: &wgpu::Device,
    source: (&PipelineSource, &ShaderModules),
    target: &Attachments,
    topology: wgpu::PrimitiveTopology,
    writes_depth: bool,
) -> Result<Reading<wgpu::RenderPipeline>, PortableError> {
    covering_pipeline(device, source, target, topology, (writes_depth, false))
}

/// [`render_pipeline`], where `alpha_to_coverage` with the fragments' alpha picking the samples
/// they cover (and never reaching the image, which stays opaque).
fn covering_pipeline(
    device: &wgpu::Device,
    (source, modules): (&PipelineSource, &ShaderModules),
    target: &Attachments,
    topology: wgpu::PrimitiveTopology,
    (writes_depth, alpha_to_coverage): (bool, bool),
) -> Result<Reading<wgpu::RenderPipeline>, PortableError> {
    let module = shader_module(source, modules)?;
    let pipeline = catch_errors(device, source.name, || {
        let module = crate::device_module(device, module, modules);
        let stages = DrawStages {
            vertex: (&module, source.entry),
            fragment: source.fragment.map(|entry| (&module, entry)),
            layout: None,
        };
        draw_pipeline(
            device,
            source.name,
            stages,
            target,
            (topology, writes_depth, alpha_to_coverage),
        )
    })?;
    let entries = [source.entry, source.fragment.unwrap_or(source.entry)];
    Reading::new(pipeline, &modules.text(source)?, &entries)
}

/// A draw's stages: its vertex and fragment modules and entry points, and its layout (None:
/// laid out from the modules).
pub(crate) struct DrawStages<'a> {
    pub vertex: (&'a wgpu::ShaderModule, &'a str),
    pub fragment: Option<(&'a wgpu::ShaderModule, &'a str)>,
    pub layout: Option<&'a wgpu::PipelineLayout>,
}

/// The render pipeline of `stages` for `target`: no face culled (a blade is seen from both
/// sides), depth tested `Less` and written (`writes_depth`), else tested `LessEqual` only, the
/// fragments' alpha picking the samples they cover where `alpha_to_coverage`.
pub(crate) fn draw_pipeline(
    device: &wgpu::Device,
    name: &str,
    stages: DrawStages,
    target: &Attachments,
    (topology, writes_depth, alpha_to_coverage): (wgpu::PrimitiveTopology, bool, bool),
) -> wgpu::RenderPipeline {
    let write_mask = match alpha_to_coverage {
        true => wgpu::ColorWrites::COLOR,
        false => wgpu::ColorWrites::ALL,
    };
    let colors: Vec<Option<wgpu::ColorTargetState>> = target
        .color
        .iter()
        .map(|&format| {
            Some(wgpu::ColorTargetState {
                format,
                blend: None,
                write_mask,
            })
        })
        .collect();
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(name),
        layout: stages.layout,
        vertex: wgpu::VertexState {
            module: stages.vertex.0,
            entry_point: Some(stages.vertex.1),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState {
            topology,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: target.depth,
            depth_write_enabled: Some(writes_depth),
            depth_compare: Some(match writes_depth {
                true => wgpu::CompareFunction::Less,
                false => wgpu::CompareFunction::LessEqual,
            }),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: wgpu::MultisampleState {
            count: target.samples,
            alpha_to_coverage_enabled: alpha_to_coverage,
            ..Default::default()
        },
        fragment: stages.fragment.map(|(module, entry)| wgpu::FragmentState {
            module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            targets: &colors,
        }),
        multiview_mask: None,
        cache: None,
    })
}
