//! The portable renderer's frame: planned by sward-core from the frame's description
//! (`FramePlan::of`, the decisions the Vulkan renderer reads too), prepared from the plan (the
//! window, the tiles, the trample map, the uniforms packed as the Vulkan renderer packs them),
//! and its passes recorded into the caller's encoder, each from what was prepared — where the
//! field streams, its window's entering tiles; the trample map and simulate; the depth
//! pyramid; cull into distance buckets; then (made for a target) draw.

use sward_core::declared::{self, bindings};
use sward_core::gpu::{FramePlan, FrameUniforms};
use sward_core::plan::RendererCan;
use sward_core::FrameDesc;

use crate::field::PortableField;
use crate::passes::bezier::BezierPasses;
use crate::passes::depth_pyramid::{CallerFold, DepthPyramid, Occluders, PyramidPipelines, PYRAMID_SIZE};
use crate::passes::draw::{drawn_scenery, record_draw, DrawInputs, DrawPipelines, DrawnScenery, Scenery};
use crate::passes::generated::{GeneratedDraws, GeneratedLists, GeneratedPipelines, GrassTexture};
use crate::passes::shadows::{record_shadows, Cascades, Casting, GroundKey, ShadowMap, ShadowPipelines};
use crate::passes::splats::{
    record_bezier_splats, record_clear, record_splatting, splat_cells, splat_modules, ListedBlades, SplatPipelines,
    SplatReads, SplatShape, SplatTarget,
};
use crate::passes::stream::StreamPasses;
use crate::passes::trample::{TramplePass, TrampleTexels};
use crate::passes::{blade_groups, FrameParts, TILE_GROUPS};
use crate::shaders::{ShaderModules, CALLER_DEPTH_SOURCES};
use crate::{compute_pipeline, BindGroups, PortableError, PortableTarget, PortableViews, Reading};

/// The caller's own depth of a view ([`PortableRenderer::set_caller_depth`]).
#[derive(Clone, Copy, Debug)]
pub struct CallerDepth<'a> {
    /// The depth, as a texture (a depth format, `TEXTURE_BINDING`).
    pub view: &'a wgpu::TextureView,
    /// Its samples per pixel.
    pub samples: u32,
}

/// Which of its passes a frame runs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PortablePasses {
    /// The frame's fixed steps of physics.
    pub simulate: bool,
    /// The depth pyramid's occluders drawn and reduced, where the frame's occlusion test is on.
    pub occluders: bool,
    /// Culling and the visible lists.
    pub cull: bool,
}

impl PortablePasses {
    /// Every pass there is.
    pub const ALL: PortablePasses = PortablePasses {
        simulate: true,
        occluders: true,
        cull: true,
    };
    /// The physics alone.
    pub const SIMULATE: PortablePasses = PortablePasses {
        simulate: true,
        occluders: false,
        cull: false,
    };
    /// A frame's culling: the depth pyramid, then the cull.
    pub const CULL: PortablePasses = PortablePasses {
        simulate: false,
        occluders: true,
        cull: true,
    };
}

/// The portable renderer's pipelines, each view's frame and depth pyramid, and what the draw
/// reads beside the field (the ground mesh, the paint maps).
pub struct PortableRenderer {
    /// A streamed field's passes: its blades carried to a moved origin, its entering tiles made.
    stream: StreamPasses,
    /// The Bezier field's simulation and cull.
    bezier: BezierPasses,
    /// The trample map's step, and its texels (kept from frame to frame).
    trample: TramplePass,
    trample_texels: TrampleTexels,
    /// The generated grass: keep its patches, count, scan, place.
    generated: GeneratedPipelines,
    /// The billboards' painted texture, made when a frame first draws billboards.
    grass_texture: Option<GrassTexture>,
    /// Made for a target (`with_target`, `made_of`): the draws, and the shadow map's casters.
    draw: Option<(DrawPipelines, ShadowPipelines)>,
    /// The sun's shadow map, sized for the last frame that had shadows (a placeholder before).
    shadow_map: ShadowMap,
    /// Where the device splats and the renderer draws into a target: the splatting passes and
    /// the first view's splat target (`passes/splats.rs`).
    splats: Option<(SplatPipelines, SplatTarget)>,
    /// Whether an engine lights and resolves the splats in its own passes
    /// ([`PortableRenderer::for_engine`]): its cells keep a surface, and the Bezier blades are
    /// all left to the engine's strips.
    lit_by_engine: bool,
    /// What fills a view's depth pyramid.
    pyramid: PyramidPipelines,
    /// The caller's depth folded into a pyramid, single-sampled and multisampled: made when a
    /// caller first gives its depth.
    folds: [Option<Reading<wgpu::ComputePipeline>>; 2],
    /// Each view's uniforms and pyramid, made as views are first recorded.
    views: Vec<ViewFrame>,
    scenery: Scenery,
    /// The passes' bind groups, made once, and the field they were made for.
    bind_groups: BindGroups,
    bound_field: Option<wgpu::Buffer>,
    max_groups: u32,
    /// The backend the device is of (its shading language reads what it can).
    backend: wgpu::Backend,
    /// The WESL modules its pipelines are made of (also those made later).
    modules: ShaderModules,
}

/// The cells an engine's renderer on `device` splats in, as `narrow` asks
/// ([`PortableRenderer::for_engine`]): `Some(false)` 64-bit (the device has 64-bit atomic min
/// and max; asked for them or for none in particular), `Some(true)` 32-bit (asked, or the device
/// has no 64-bit atomics: WebGPU, GL), `None` none (64-bit asked where the device has none, or
/// too few storage buffers a stage).
pub fn engine_splat_cells(device: &wgpu::Device, narrow: Option<bool>) -> Option<bool> {
    splat_cells(device.features(), &device.limits(), narrow)
}

/// One view's part of a frame: its uniforms, the occluders' depth for its occlusion test, and
/// what it draws besides the blades (as its last recorded frame said).
struct ViewFrame {
    frame: wgpu::Buffer,
    pyramid: DepthPyramid,
    drawn: DrawnScenery,
    /// The caller's depth of the view, folded into its pyramid, where it gives one.
    caller: Option<CallerFold>,
    /// The view's generated grass: its patches, counts and lists.
    generated: GeneratedLists,
    /// What its last recorded frame casts into the shadow map.
    casting: Casting,
    /// What its last recorded frame rasterizes by compute, where it splats.
    splat_shape: SplatShape,
    /// Whether its last recorded frame drew the shadow map's field cascade before splatting
    /// (its draw then adds the near cascade alone).
    field_cascade_drawn: bool,
    /// What places its last recorded frame's ground in the shadow map's field cascade.
    ground_key: Option<GroundKey>,
}

impl ViewFrame {
    /// A view's frame; its generated grass listed by the splatting passes (`splats`) or not.
    fn new(device: &wgpu::Device, splats: bool) -> ViewFrame {
        ViewFrame {
            frame: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("sward frame"),
                size: declared::FRAME_BYTES as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            pyramid: DepthPyramid::new(device),
            drawn: DrawnScenery::default(),
            caller: None,
            generated: GeneratedLists::new(device, splats),
            casting: Casting::default(),
            splat_shape: SplatShape::default(),
            field_cascade_drawn: false,
            ground_key: None,
        }
    }
}

/// One field's part of a view culled with others ([`PortableRenderer::record_fields_view`]):
/// its renderer, the field, its frame's description (placed in the field's space) and which
/// passes it runs.
pub struct FieldView<'a> {
    /// The field's own renderer (a sibling of the others').
    pub renderer: &'a mut PortableRenderer,
    /// The field's blades and lists.
    pub field: &'a mut PortableField,
    /// The frame as the field sees it (`FrameDesc::placed` where it is placed).
    pub desc: &'a FrameDesc,
    /// The passes it runs this view (only the first view of a frame simulates).
    pub passes: PortablePasses,
    /// Which of the field's views this is (its lists, uniforms and pyramid): the same camera
    /// may be another view of another field.
    pub view: usize,
}

/// What a view's prepared frame tells its passes.
struct PreparedView {
    /// Workgroups across and down for an invocation per blade it runs (a row per tile).
    per_blade: [u32; 2],
    /// The trample map's workgroups, where the frame steps it.
    texel_groups: Option<[u32; 2]>,
    /// Whether its occlusion test runs (the depth pyramid is drawn).
    occlusion: bool,
}

impl PortableRenderer {
    /// The simulation and culling pipelines on `device` (of `adapter`), or why this device
    /// cannot run them.
    pub fn new(adapter: &wgpu::Adapter, device: &wgpu::Device) -> Result<PortableRenderer, PortableError> {
        PortableRenderer::made_of(adapter, device, None, ShaderModules::built_in())
    }

    /// Every pipeline composed of `modules` (the built-in WESL modules with a shader directory's
    /// in place of theirs: `--shaders DIR`), the draws' made where `target` says, for
    /// attachments like it; or why this device cannot run them, or which pipeline does not
    /// compile.
    pub fn made_of(
        adapter: &wgpu::Adapter,
        device: &wgpu::Device,
        target: Option<&PortableTarget>,
        modules: ShaderModules,
    ) -> Result<PortableRenderer, PortableError> {
        supports(adapter, device)?;
        let cells = splat_cells(device.features(), &device.limits(), modules.narrow_splats());
        let splats = match (target, cells) {
            (Some(t), Some(narrow)) => Some((
                SplatPipelines::new(
                    (device, adapter.get_info().backend),
                    Some(&t.into()),
                    &splat_modules(&modules, narrow, adapter.get_info().backend),
                )?,
                SplatTarget::new(device, t.samples, narrow),
            )),
            _ => None,
        };
        PortableRenderer::with_splats(adapter, device, target, modules, splats)
    }

    /// The simulation and culling pipelines for an engine that draws the lists in its own
    /// passes, and the splatting passes in 32-bit cells where `narrow`, else 64-bit ones (the
    /// cells [`engine_splat_cells`] finds `device` splats in; an engine that splats none makes
    /// [`PortableRenderer::new`] instead and draws the far field as geometry): the far field
    /// splatted into cells that keep each point's surface (64-bit cells: its albedo, normal and
    /// height along the blade; 32-bit cells its albedo: `splat_words.wesl`) for the engine to
    /// light and resolve into its frame ([`PortableRenderer::splat_cells`]); the Bezier blades
    /// all left to the engine's strips.
    pub fn for_engine(
        adapter: &wgpu::Adapter,
        device: &wgpu::Device,
        narrow: bool,
    ) -> Result<PortableRenderer, PortableError> {
        let modules = ShaderModules::built_in();
        let backend = adapter.get_info().backend;
        let splats = Some((
            SplatPipelines::new(
                (device, backend),
                None,
                &splat_modules(&modules, narrow, backend).with_splat_surface(true),
            )?,
            SplatTarget::new(device, 1, narrow),
        ));
        let mut renderer = PortableRenderer::with_splats(adapter, device, None, modules, splats)?;
        renderer.lit_by_engine = true;
        Ok(renderer)
    }

    /// The renderer of `modules` with `splats` made.
    fn with_splats(
        adapter: &wgpu::Adapter,
        device: &wgpu::Device,
        target: Option<&PortableTarget>,
        modules: ShaderModules,
        splats: Option<(SplatPipelines, SplatTarget)>,
    ) -> Result<PortableRenderer, PortableError> {
        Ok(PortableRenderer {
            stream: StreamPasses::new(device, &modules)?,
            bezier: BezierPasses::new(device, &modules)?,
            trample: TramplePass::new(device, &modules)?,
            trample_texels: TrampleTexels::new(device),
            generated: GeneratedPipelines::new(device, &modules)?,
            grass_texture: None,
            draw: target
                .map(|t| -> Result<_, PortableError> {
                    Ok((
                        DrawPipelines::new(device, t, &modules)?,
                        ShadowPipelines::new(device, &modules)?,
                    ))
                })
                .transpose()?,
            shadow_map: ShadowMap::new(device, 1),
            views: vec![ViewFrame::new(device, splats.is_some())],
            splats,
            lit_by_engine: false,
            pyramid: PyramidPipelines::new(device, &modules)?,
            folds: [None, None],
            scenery: Scenery::new(device),
            bind_groups: BindGroups::default(),
            bound_field: None,
            max_groups: device.limits().max_compute_workgroups_per_dimension,
            backend: adapter.get_info().backend,
            modules,
        })
    }

    /// Passes for another field on the same device: these pipelines shared (nothing is
    /// compiled again), everything a field holds beside them its own — each view's uniforms,
    /// pyramid and generated lists, the ground, the paint, the trample map. What an engine
    /// with several fields makes for each after the first.
    pub fn sibling(&self, device: &wgpu::Device) -> PortableRenderer {
        PortableRenderer {
            stream: self.stream.clone(),
            bezier: self.bezier.clone(),
            trample: self.trample.clone(),
            trample_texels: TrampleTexels::new(device),
            generated: self.generated.clone(),
            grass_texture: None,
            draw: self.draw.clone(),
            shadow_map: ShadowMap::new(device, 1),
            splats: self.splats.as_ref().map(|(p, t)| (p.clone(), t.sibling(device))),
            lit_by_engine: self.lit_by_engine,
            pyramid: self.pyramid.clone(),
            folds: self.folds.clone(),
            views: vec![ViewFrame::new(device, self.splats.is_some())],
            scenery: Scenery::new(device),
            bind_groups: BindGroups::default(),
            bound_field: None,
            max_groups: self.max_groups,
            backend: self.backend,
            modules: self.modules.clone(),
        }
    }

    /// Every pipeline, the draws' made for attachments like `target`.
    pub fn with_target(
        adapter: &wgpu::Adapter,
        device: &wgpu::Device,
        target: &PortableTarget,
    ) -> Result<PortableRenderer, PortableError> {
        PortableRenderer::made_of(adapter, device, Some(target), ShaderModules::built_in())
    }

    /// Draw the ground `mesh` from the next frame on (None: the plane or sphere the frame's
    /// description asks for, which the shaders make).
    pub fn upload_ground(&mut self, device: &wgpu::Device, mesh: Option<&sward_core::mesh::Mesh>) {
        self.scenery.set_ground(device, mesh);
        self.bind_groups.forget();
    }

    /// Let go of the generated grass's lists, grown for an earlier scene: the next frame that
    /// generates makes them as large as it needs, and a scene that generates none holds none.
    pub fn forget_generated(&mut self, device: &wgpu::Device) {
        for view in &mut self.views {
            view.generated = GeneratedLists::new(device, view.generated.splats);
        }
        self.bind_groups.forget();
    }

    /// Shade with `paint`'s maps from the next frame on (None: nothing painted). The frame's
    /// plan must say where they lie (`FramePlan::paint`).
    pub fn upload_paint(&mut self, device: &wgpu::Device, paint: Option<&sward_core::paint::GroundPaint>) {
        self.scenery.set_paint(device, paint);
        self.bind_groups.forget();
    }

    /// The paint maps the blades are shaded with (a storage buffer: shading.wesl
    /// `paint_texels`).
    pub fn paint_texels(&self) -> &wgpu::Buffer {
        self.scenery.paint()
    }

    /// View `view`'s generated grass as its last recorded frame listed it, where that frame
    /// generated any: what an engine's passes draw it from.
    pub fn generated_draws(&self, view: usize) -> Option<GeneratedDraws<'_>> {
        let this = self.views.get(view)?;
        let lists = &this.generated;
        let [instanced, billboards] = lists.generates();
        let texture = self.grass_texture.as_ref().filter(|_| billboards);
        (instanced || billboards).then(|| GeneratedDraws {
            listed: lists.listed(),
            draws: lists.draws(),
            instanced,
            billboards: texture.map(|t| (&t.view, &t.sampler)),
            starts: lists.starts(),
            billboard_command: lists.billboard_command(this.splat_shape.billboards_rasterized),
        })
    }

    /// The trample map's texels (the billboards lie down where it says).
    pub fn trample_texels(&self) -> &wgpu::Buffer {
        &self.trample_texels.buffer
    }

    /// View `view`'s uniforms as its last recorded frame wrote them (sward-core's
    /// `FrameUniforms`; a uniform buffer), where it has been recorded.
    pub fn frame_uniforms(&self, view: usize) -> Option<&wgpu::Buffer> {
        self.views.get(view).map(|v| &v.frame)
    }

    /// Write the frame `desc` describes for `field` (its `steps` fixed steps from its time, seen
    /// by its camera), and record its `passes` into `encoder`.
    pub fn record(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        desc: &FrameDesc,
        field: &mut PortableField,
        passes: PortablePasses,
    ) {
        self.record_view(device, queue, encoder, (desc, 0), field, passes);
    }

    /// [`PortableRenderer::record`] for view `view` of the frame (a camera of several, each
    /// culling the field into its own lists; record each view in its own submission, since a
    /// view's uniforms are written once per submission). Only the first view should simulate.
    pub fn record_view(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        (desc, view): (&FrameDesc, usize),
        field: &mut PortableField,
        passes: PortablePasses,
    ) {
        let alone = FieldView {
            renderer: self,
            field,
            desc,
            passes,
            view,
        };
        PortableRenderer::record_fields_view(device, queue, encoder, &mut [alone]);
    }

    /// One camera's view of several fields, each with its own renderer (siblings on one
    /// device), culled together: each field prepared, streamed and stepped; then one depth
    /// pyramid for all of them — the first occluding field's, shared with the others — holding
    /// every field's occluders (its ground and nearest blades, in its own placement; the
    /// colliders once), so one field's grass and ground hide another's and the pyramid is
    /// reduced once, with the first field's caller depth folded in; then each field culled
    /// against it into its lists and its far grass generated. What an engine with several
    /// fields records for each view, in one submission.
    pub fn record_fields_view(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        fields: &mut [FieldView<'_>],
    ) {
        let frames: Vec<PreparedView> = fields
            .iter_mut()
            .map(|f| {
                f.renderer
                    .record_before_occlusion(device, queue, encoder, (f.desc, f.view), f.field, f.passes)
            })
            .collect();
        let occluding: Vec<usize> = (0..fields.len())
            .filter(|&k| fields[k].passes.occluders && frames[k].occlusion)
            .collect();
        // The occluders are the blades as the last frame left them, drawn before this frame's
        // step, as the Vulkan renderer draws them before its simulation and cull (one pass
        // there): its cull then tests the stepped blades against them, and so does this one.
        if let Some(&first) = occluding.first() {
            let shared = fields[first].renderer.views[fields[first].view].pyramid.clone();
            for (n, &k) in occluding.iter().enumerate() {
                let FieldView {
                    renderer, field, view, ..
                } = &mut fields[k];
                renderer.views[*view].pyramid = shared.clone();
                let which = match (n, occluding.len()) {
                    (0, 1) => Occluders::Alone,
                    (0, _) => Occluders::First,
                    _ => Occluders::Added,
                };
                renderer.record_occluders(device, encoder, (*view, &**field), which);
            }
            let FieldView { renderer, view, .. } = &fields[first];
            renderer.reduce_pyramid(device, encoder, *view);
        }
        for (f, frame) in fields.iter().zip(&frames) {
            f.renderer
                .record_step(device, encoder, (f.desc, f.view, frame), f.field, f.passes);
        }
        for (f, frame) in fields.iter_mut().zip(&frames) {
            if f.passes.cull {
                f.renderer
                    .record_after_occlusion(device, encoder, (f.view, frame), f.field);
            }
        }
    }

    /// A view's passes before its depth pyramid: the frame prepared (`prepare_view`) and a
    /// streamed field's tiles.
    fn record_before_occlusion(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        (desc, view): (&FrameDesc, usize),
        field: &mut PortableField,
        passes: PortablePasses,
    ) -> PreparedView {
        let frame = self.prepare_view(device, queue, encoder, (desc, view), field, passes);
        self.stream.record(&self.parts(device, view), encoder, field);
        frame
    }

    /// A view's step, after its occluders are drawn: the trample map and the simulation.
    fn record_step(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        (desc, view, frame): (&FrameDesc, usize, &PreparedView),
        field: &PortableField,
        passes: PortablePasses,
    ) {
        let stepped = passes.simulate && desc.steps > 0 && field.count() > 0;
        self.record_physics(device, encoder, (view, frame), field, stepped);
    }

    /// `field`'s occluders drawn into view `view`'s pyramid: the `First` clears it and draws
    /// the colliders too.
    fn record_occluders(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        (view, field): (usize, &PortableField),
        which: Occluders,
    ) {
        let inputs = self.draw_inputs(field, view);
        self.pyramid
            .record_occluders(device, encoder, &self.views[view].pyramid, &inputs, which);
    }

    /// View `view`'s pyramid reduced from its occluders, its caller depth folded in.
    fn reduce_pyramid(&self, device: &wgpu::Device, encoder: &mut wgpu::CommandEncoder, view: usize) {
        let this = &self.views[view];
        self.pyramid.reduce(
            device,
            encoder,
            (&this.pyramid, this.caller.as_ref()),
            &self.bind_groups,
        );
    }

    /// A view's passes after its depth pyramid: the cull into its lists, the far grass.
    fn record_after_occlusion(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        (view, frame): (usize, &PreparedView),
        field: &PortableField,
    ) {
        self.record_cull(device, encoder, (view, frame), field);
        self.record_splats(device, encoder, (view, field));
        self.record_generated(device, encoder, view);
    }

    /// Plan view `view`'s frame `desc` (sward-core's `FramePlan`: the frame's decisions, then
    /// what the renderer's state adds) and prepare from it: a streamed field's window moved, the
    /// tiles the view runs written, the trample map's texels fitted, the uniforms packed and
    /// written.
    fn prepare_view(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        (desc, view): (&FrameDesc, usize),
        field: &mut PortableField,
        passes: PortablePasses,
    ) -> PreparedView {
        field.reserve_views(device, view + 1);
        if self.bound_field.as_ref() != Some(&field.blades) {
            // Another field: the groups of the last one would hold its buffers.
            self.bind_groups.forget();
            self.bound_field = Some(field.blades.clone());
        }
        self.reserve_views(device, view);
        let mut plan = FramePlan {
            blade_count: field.count(),
            paint: self.scenery.paint_area,
            pyramid_size: PYRAMID_SIZE,
            height_grid: self.scenery.height_grid,
            ..FramePlan::of(
                desc,
                RendererCan {
                    caller_depth: self.views[view].caller.is_some(),
                    ..RendererCan::strips()
                }
                .splatting(self.views[view].generated.splats, self.route_asked(desc)),
            )
        };
        if let (true, Some((_, target))) = (self.views[view].generated.splats, &mut self.splats) {
            plan.splat_scale = target.scale();
            if target.prepare(device, desc.viewport, plan.decided.splatting) {
                self.bind_groups.forget();
            }
        }
        // The field cascade is drawn before the splats where the frame splats, else with the
        // near cascade in the draw.
        let splatting = self.views[view].generated.splats && plan.decided.splatting;
        self.views[view].field_cascade_drawn = splatting && passes.cull;
        self.views[view].splat_shape = SplatShape {
            blades_rasterized: plan.decided.blades_rasterized,
            billboards_rasterized: plan.decided.billboards_rasterized,
            bezier: plan.decided.bezier_splats,
            first_splatted: plan.decided.buckets[1],
        };
        // A streamed field's window follows the frame that steps it (view 0's, simulating).
        let ground = self.scenery.height_grid.map_or([0.0, 0.0], |g| g.span);
        let follows = passes.simulate && view == 0;
        if let Some((window, origin)) = field.advance_window(queue, encoder, desc, (ground, follows)) {
            (plan.stream_window, plan.origin) = (Some(window), origin);
        }
        // The first view of several simulates every tile (the others' views may need them).
        let every_tile = view == 0 && field.views.len() > 1;
        let tiles_run = field.write_tiles(queue, (desc, &plan.decided, view), every_tile);
        plan.tiles = [0, tiles_run.map_or(0, |_| TILE_GROUPS)];
        // The trample map's texels are read by every pass of the frame (the generated grass lies
        // along its trails, is mown where it says); only a frame that simulates steps it.
        plan.trample = self.prepare_trample(device, desc);
        // Its lists hold the blades of the ground its camera sees, not of the whole disk.
        let seen = sward_core::instanced::SeenSector::of(&desc.camera);
        if self.views[view].generated.prepare(device, &plan.decided, seen.as_ref()) {
            self.bind_groups.forget();
        }
        // The billboards are painted with it; the splatting passes bind it on either grid.
        let [blades, billboards] = self.views[view].generated.generates();
        let painted = billboards || (blades && self.views[view].generated.splats);
        if painted && self.grass_texture.is_none() {
            self.grass_texture = Some(GrassTexture::new(device, queue));
        }
        plan.generated = self.views[view].generated.layout();
        let texel_groups = (plan.trample && passes.simulate).then(|| self.trample_texels.begin_frame(encoder));
        let uniforms = FrameUniforms::pack(desc, &plan);
        self.views[view].ground_key = Some(GroundKey {
            placed: uniforms.shadow_ground_key(plan.streamed(desc).is_some()),
            mesh: self.scenery.ground_vertices().clone(),
        });
        self.views[view].drawn = drawn_scenery(desc);
        self.prepare_shadows(device, view, Casting::of(&plan.decided, desc.quality.shadow_map_size()));
        queue.write_buffer(&self.views[view].frame, 0, &declared::frame_bytes(&uniforms));
        PreparedView {
            per_blade: match tiles_run {
                Some(tiles) => [TILE_GROUPS, tiles],
                None => blade_groups(field.count(), self.max_groups),
            },
            texel_groups,
            occlusion: plan.decided.depth_pyramid,
        }
    }

    /// View `view`'s frame casts `casting` into the shadow map: the map made at its size where
    /// the frame has shadows and it is not (only a renderer that draws makes one).
    fn prepare_shadows(&mut self, device: &wgpu::Device, view: usize, casting: Casting) {
        self.views[view].casting = casting;
        if self.draw.is_some() && casting.shadows && self.shadow_map.size() != casting.size {
            self.shadow_map = ShadowMap::new(device, casting.size).keeping_ground(self.backend != wgpu::Backend::Gl);
        }
    }

    /// What view `view`'s passes record with (`passes::FrameParts`).
    fn parts<'a>(&'a self, device: &'a wgpu::Device, view: usize) -> FrameParts<'a> {
        FrameParts {
            device,
            groups: &self.bind_groups,
            frame: &self.views[view].frame,
            ground: self.scenery.ground_vertices(),
            trample: &self.trample_texels.buffer,
            paint: self.scenery.paint(),
        }
    }

    /// The trample map's step where the frame prepared it, then (where the frame `stepped`)
    /// the simulation over view 0's tiles: the blades read this frame's trails.
    fn record_physics(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        (view, frame): (usize, &PreparedView),
        field: &PortableField,
        stepped: bool,
    ) {
        let parts = self.parts(device, view);
        if let Some(groups) = frame.texel_groups {
            self.trample.record(&parts, encoder, groups);
        }
        if stepped {
            self.bezier.record_simulation(&parts, encoder, field, frame.per_blade);
        }
    }

    /// View `view`'s cull into its lists, against its depth pyramid.
    fn record_cull(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        (view, frame): (usize, &PreparedView),
        field: &PortableField,
    ) {
        let levels = &self.views[view].pyramid.levels;
        let lists = (field, &field.views[view]);
        self.bezier
            .record_cull(&self.parts(device, view), encoder, lists, (levels, frame.per_blade));
    }

    /// Where view `view`'s frame splats, after its cull: the shadow map's field cascade, which
    /// the splats are shaded with, the splat buffer cleared, and the far Bezier blades splatted
    /// (the generated grass is splatted by its own passes next).
    fn record_splats(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        (view, field): (usize, &PortableField),
    ) {
        let this = &self.views[view];
        let Some((pipelines, target)) = self
            .splats
            .as_ref()
            .filter(|(_, t)| this.generated.splats && t.in_use())
        else {
            return;
        };
        if let (true, Some((_, casters)), Some(ground)) = (this.field_cascade_drawn, &self.draw, &this.ground_key) {
            let inputs = self.draw_inputs(field, view);
            let casting = (this.casting, Cascades::Field);
            record_shadows(device, encoder, (casters, &self.shadow_map), (&inputs, ground), casting);
        }
        let parts = self.parts(device, view);
        record_clear(&parts, encoder, (pipelines, target));
        if this.splat_shape.bezier && field.count() > 0 {
            let lists = &field.views[view];
            let listed = ListedBlades {
                blades: &field.blades,
                visible: &lists.visible,
                draws: &lists.draws,
                counters: &lists.counters,
            };
            let shadow_map = self.shadow_map.bound();
            record_bezier_splats(&parts, encoder, (pipelines, target), (&listed, shadow_map));
        }
    }

    /// View `view`'s generated grass, after its cull: its patches kept, its blades counted,
    /// placed in its levels' lists — where it splats, by the splatting passes, after
    /// `record_splats`.
    fn record_generated(&self, device: &wgpu::Device, encoder: &mut wgpu::CommandEncoder, view: usize) {
        let this = &self.views[view];
        let parts = self.parts(device, view);
        let splatting = self.splats.as_ref().filter(|_| this.generated.splats);
        let Some((pipelines, target)) = splatting else {
            this.generated
                .record((&parts, &this.pyramid.levels), encoder, &self.generated);
            return;
        };
        let reads = SplatReads {
            levels: &this.pyramid.levels,
            shadow_map: self.shadow_map.bound(),
            grass_texture: self.grass_texture.as_ref(),
        };
        record_splatting(
            &parts,
            encoder,
            (pipelines, target),
            (&this.generated, &reads),
            this.splat_shape,
        );
    }

    #[cfg(feature = "blocking")]
    /// The generated grass's lists of view `view` as the GPU holds them now: each level's
    /// listed blades (32 bytes each: root, height and half-width, facing and tip, hash,
    /// outline), in the order they are drawn (for tests and tools).
    pub fn read_generated(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        view: usize,
    ) -> Result<Vec<Vec<[u32; 8]>>, PortableError> {
        self.views[view].generated.read(device, queue)
    }

    #[cfg(feature = "blocking")]
    /// How many generated blades and billboards view `view`'s last culled frame made visible
    /// (its lists' instances, and those splatted or rasterized by compute; none where it
    /// generated none), and of them how many were splatted or rasterized.
    pub fn generated_count(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        view: usize,
    ) -> Result<[u32; 2], PortableError> {
        self.views[view].generated.count(device, queue)
    }

    /// From the next frame on, fold `depth` — the caller's own depth of view `view`, drawn from
    /// the frame's camera before the grass (an engine's scene: buildings, rocks) — into the
    /// view's depth pyramid, so the grass behind it is culled as the grass behind sward's own
    /// occluders is (None: sward's occluders alone). The depth runs forward (0 near, as sward's
    /// draw) and is read as a texture (`TEXTURE_BINDING`), where the frame's occlusion test is
    /// on. Fails, in one sentence, where the device cannot read it.
    pub fn set_caller_depth(
        &mut self,
        device: &wgpu::Device,
        view: usize,
        depth: Option<CallerDepth>,
    ) -> Result<(), PortableError> {
        self.reserve_views(device, view);
        let Some(depth) = depth else {
            self.views[view].caller = None;
            return Ok(());
        };
        if self.backend == wgpu::Backend::Gl {
            return Err(PortableError::CallerDepthUnread("GL".into()));
        }
        let multisampled = depth.samples > 1;
        let pipeline = match &mut self.folds[multisampled as usize] {
            Some(made) => made.clone(),
            none => none
                .insert(compute_pipeline(
                    device,
                    &CALLER_DEPTH_SOURCES[multisampled as usize],
                    &self.modules,
                )?)
                .clone(),
        };
        self.views[view].caller = Some(CallerFold {
            pipeline,
            binding: if multisampled {
                bindings::CALLER_DEPTH_SAMPLES
            } else {
                bindings::CALLER_DEPTH
            },
            depth: depth.view.clone(),
        });
        Ok(())
    }

    /// Uniforms and a pyramid for views up to `view`.
    fn reserve_views(&mut self, device: &wgpu::Device, view: usize) {
        while self.views.len() <= view {
            // Only the first view is drawn, so only it splats.
            self.views.push(ViewFrame::new(device, false));
        }
    }

    /// The Bezier blades' route frame `desc` asks of the plan: the strips where an engine draws
    /// them (its passes draw every distance bucket), else the frame's.
    fn route_asked(&self, desc: &FrameDesc) -> sward_core::quality::DrawRoute {
        match self.lit_by_engine {
            true => sward_core::quality::DrawRoute::Strips,
            false => desc.route,
        }
    }

    /// Resolve view 0's splats into attachments of `samples` per pixel from the next frame on
    /// (an engine's camera, [`PortableRenderer::for_engine`]; one cell per sample on a 4×
    /// target, else one per pixel).
    pub fn set_splat_samples(&mut self, samples: u32) {
        if let Some((_, target)) = &mut self.splats {
            target.set_samples(samples);
        }
    }

    /// View `view`'s splat cells where its last recorded frame splatted (only view 0 splats),
    /// for an engine to resolve them into its frame ([`PortableRenderer::for_engine`]: each
    /// cell's depth above its surface word; the cells per pixel side are in the frame's
    /// uniforms, `grids.instanced_meta.z`).
    pub fn splat_cells(&self, view: usize) -> Option<&wgpu::Buffer> {
        let (_, target) = self.splats.as_ref()?;
        let splatted = view == 0 && self.views.first()?.generated.splats && target.in_use();
        splatted.then(|| target.cells())
    }

    /// Whether the frame `desc` steps the trample map: asked for, and its texels fit the
    /// device's bindings (else said once in the log, and the grass runs without it).
    fn prepare_trample(&mut self, device: &wgpu::Device, desc: &FrameDesc) -> bool {
        let Some(map) = &desc.trample else {
            return false;
        };
        let prepared = self.trample_texels.prepare(device, map);
        if prepared == Some(true) {
            self.bind_groups.forget();
        }
        prepared.is_some()
    }

    #[cfg(feature = "blocking")]
    /// The trample map's texels as the GPU holds them now, row by row (push, mown height, cell
    /// tag; for tests and tools).
    pub fn read_trample_map(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<sward_core::trample::Texel>, PortableError> {
        self.trample_texels.read(device, queue)
    }

    /// What view `view`'s draws (and its pyramid's occluders) read this frame.
    fn draw_inputs<'a>(&'a self, field: &'a PortableField, view: usize) -> DrawInputs<'a> {
        let this = &self.views[view];
        DrawInputs {
            frame: &this.frame,
            field,
            lists: &field.views[view],
            scenery: &self.scenery,
            drawn: this.drawn,
            trample: &self.trample_texels.buffer,
            generated: &this.generated,
            grass_texture: self.grass_texture.as_ref(),
            shadow_map: self.shadow_map.bound(),
            groups: &self.bind_groups,
        }
    }

    #[cfg(feature = "blocking")]
    /// Level `level` of the first view's depth pyramid as the last culled frame left it, row by
    /// row: each texel's farthest occluder depth, as the bits of a float (for tests and tools).
    pub fn read_pyramid(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        level: u32,
    ) -> Result<Vec<u32>, PortableError> {
        self.views[0].pyramid.read_level(device, queue, level)
    }

    /// Bytes of GPU memory the renderer holds beside the field: each view's uniforms, pyramid
    /// and generated grass, the trample map.
    pub fn bytes(&self) -> u64 {
        let views: u64 = self
            .views
            .iter()
            .map(|v| v.frame.size() + v.pyramid.bytes() + v.generated.bytes())
            .sum();
        let splats = self.splats.as_ref().map_or(0, |(_, t)| t.bytes());
        views + self.trample_texels.bytes() + self.shadow_map.bytes() + splats
    }

    /// Record the frame the last [`PortableRenderer::record`] wrote, culled there, into
    /// `views`: the sun's shadow map where the frame has shadows, then the visible blades as
    /// strips, the generated grass, the colliders, the ground and the sky. Nothing where the
    /// renderer was made without a target ([`PortableRenderer::new`]).
    pub fn draw(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        field: &PortableField,
        views: &PortableViews,
    ) {
        self.draw_shadow_map(device, encoder, field);
        self.draw_lit(device, encoder, field, views);
    }

    /// The first part of [`PortableRenderer::draw`]: the sun's shadow map, where the frame has
    /// shadows (a caller that times it apart records the two parts itself).
    pub fn draw_shadow_map(&self, device: &wgpu::Device, encoder: &mut wgpu::CommandEncoder, field: &PortableField) {
        if let (Some((_, casters)), Some(ground)) = (&self.draw, &self.views[0].ground_key) {
            let inputs = self.draw_inputs(field, 0);
            // Where the far field was splatted, its field cascade was drawn before it.
            let cascades = match self.views[0].field_cascade_drawn {
                true => Cascades::Near,
                false => Cascades::Both,
            };
            let casting = (self.views[0].casting, cascades);
            record_shadows(device, encoder, (casters, &self.shadow_map), (&inputs, ground), casting);
        }
    }

    /// The rest of [`PortableRenderer::draw`], after its shadow map: what the camera sees.
    pub fn draw_lit(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        field: &PortableField,
        views: &PortableViews,
    ) {
        if let Some((pipelines, _)) = &self.draw {
            let splats = self.splats.as_ref().map(|(p, t)| (p, t, self.views[0].splat_shape));
            record_draw(device, encoder, (pipelines, splats), &self.draw_inputs(field, 0), views);
        }
    }
}

/// Whether `device` (of `adapter`) runs the portable passes, or why not, in one sentence:
/// compute shaders, storage buffers in the vertex stage, and as many storage buffers in a stage
/// as the cull binds.
pub fn supports(adapter: &wgpu::Adapter, device: &wgpu::Device) -> Result<(), PortableError> {
    let info = adapter.get_info();
    let what = || format!("{:?} ({})", info.backend, info.name);
    let flags = adapter.get_downlevel_capabilities().flags;
    if !flags.contains(wgpu::DownlevelFlags::COMPUTE_SHADERS) {
        return Err(PortableError::NoCompute(what()));
    }
    if !flags.contains(wgpu::DownlevelFlags::VERTEX_STORAGE) {
        return Err(PortableError::NoVertexStorage(what()));
    }
    let has = device.limits().max_storage_buffers_per_shader_stage;
    if has < STORAGE_BUFFERS_PER_STAGE {
        return Err(PortableError::FewStorageBuffers {
            adapter: what(),
            has,
            needs: STORAGE_BUFFERS_PER_STAGE,
        });
    }
    Ok(())
}

/// Storage buffers the portable passes bind in one stage at most: the generated grass's
/// counting and placing passes (the ground, the trample map, the patches, the counts, the paint
/// and the draws or the lists). WebGPU's default limit is 8.
pub const STORAGE_BUFFERS_PER_STAGE: u32 = 6;
