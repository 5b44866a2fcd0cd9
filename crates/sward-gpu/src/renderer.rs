//! The grass frame, as a short orchestrator of the passes in `passes/`: occluders (the depth
//! pyramid and the sun's field cascade, `occluders.rs`) → the trample map (`trample.rs`) →
//! simulate + cull + order (+ splat, on the compute route) of the Bezier field (`bezier.rs`) →
//! generated grass (`generated.rs`) → the sun's near cascade (`shadows.rs`) → the draw
//! (`draw.rs`: blades by their route, generated grass, the splats, colliders, ground and sky).
//! It decides the frame's plan (`prepare_frame`), keeps the passes' recordings
//! (`recordings.rs`) and owns what the passes record from, lent to them as `FrameParts`.
//! Recorded into a command buffer the caller gives, rendering into a target the caller gives;
//! the offscreen path, the tests and the viewer all go through `record_frame`.

use std::sync::Arc;

use ash::vk;
use sward_core::frame::FrameDesc;
use sward_core::gpu::{DrawCommand, FramePlan, FrameUniforms, GridBounds};
use sward_core::plan::{FrameDecisions, RendererCan};
use sward_core::quality::QualityPreset;
use sward_core::tiles::Tile;
use sward_core::Blade;

use crate::buffer::Buffer;
use crate::context::{Context, DeviceInfo};
use crate::error::{vk_check, Result};
use crate::frame_pipelines::Pipelines;
use crate::frame_set::FrameSets;
use crate::passes::bezier::{FieldBuffers, FieldWork};
use crate::passes::depth_pyramid::{DepthPyramid, HIZ_SIZE};
use crate::passes::drawn_blades::DrawnBlades;
use crate::passes::generated::{self, InstancedBuffers};
use crate::passes::grass_texture::GrassTexture;
use crate::passes::ground::Ground;
use crate::passes::paint::PaintTexels;
use crate::passes::routes::{self, DrawRoute};
use crate::passes::shadows::{self, ShadowMap};
use crate::passes::splats::SplatTarget;
use crate::passes::trample::TrampleTexels;
use crate::passes::{draw, occluders, FrameParts};
use crate::pipelines::{ComputeOptions, TargetFormat, STORAGE_BINDINGS};
use crate::recordings::{FrameShape, RecordingKey, Recordings, Replay, ShadowGround};
use crate::shaders::ShaderSet;
use crate::target::{CallerDepth, TargetViews};
use crate::timer::{GpuTimer, Stamp};

pub use crate::passes::bezier::check_field_fits;

/// Largest tessellated draw Mesa's lavapipe draws correctly: bigger single draws of patches come
/// out garbled (Mesa 22.3), so on that driver the draw is split into commands of this many patches.
pub const LAVAPIPE_PATCHES_PER_DRAW: u32 = 1024;

/// Which passes a frame runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Passes {
    /// Step the Bezier blades' physics.
    pub simulate: bool,
    /// Cull and order the blades (and generate the instanced grass and billboards).
    pub cull: bool,
    /// Draw the frame (needs a target).
    pub draw: bool,
}

impl Passes {
    /// Every pass: a whole frame.
    pub const ALL: Passes = Passes {
        simulate: true,
        cull: true,
        draw: true,
    };
    /// Only the physics.
    pub const SIMULATE: Passes = Passes {
        simulate: true,
        cull: false,
        draw: false,
    };
    /// Only the cull.
    pub const CULL: Passes = Passes {
        simulate: false,
        cull: true,
        draw: false,
    };
}

/// The buffers a renderer that draws the Bezier blades itself reads
/// ([`Renderer::drawn_blade_buffers`]; another owner of the device reads them through
/// [`crate::buffer::Buffer::alias`]).
#[derive(Clone, Copy)]
pub struct DrawnBladeBuffers<'a> {
    /// The blades (`sward_core::gpu::Blade`), positions measured from the frame's origin.
    pub blades: &'a crate::buffer::Buffer,
    /// The drawn blades, in draw order (`drawn_blades.wesl`).
    pub drawn: &'a crate::buffer::Buffer,
    /// The draw commands (`sward_core::gpu::DrawCommand`).
    pub draws: &'a crate::buffer::Buffer,
    /// The frame's uniforms (`sward_core::gpu::FrameUniforms`).
    pub uniforms: &'a crate::buffer::Buffer,
}

/// How to build a [`Renderer`].
#[derive(Clone, Copy, Debug)]
pub struct RendererDesc {
    /// Colour format and samples of the targets it will draw into.
    pub target: TargetFormat,
    /// Frames recorded before the first has finished on the GPU (one uniform buffer and set each).
    pub frames_in_flight: usize,
    /// Patches per indirect draw command; `None` picks per driver (see `LAVAPIPE_PATCHES_PER_DRAW`),
    /// `Some(0)` draws every visible blade with one command.
    pub patches_per_draw: Option<u32>,
    /// Workgroup size and other options of the compute passes.
    pub compute: ComputeOptions,
    /// Simulate and cull in one dispatch when a frame runs both.
    pub fused: bool,
    /// Side of the sun's shadow map in texels (`QualityPreset::shadow_map_size`).
    pub shadow_map_size: u32,
}

impl RendererDesc {
    /// A renderer drawing into `color` as `quality` asks on this device — its samples per pixel
    /// (the most the device has, up to the preset's), its shadow map — one frame slot per frame
    /// in flight, the default compute options. (The route the blades are drawn by is each
    /// frame's: `FrameDesc::route`.)
    pub fn for_quality(
        info: &DeviceInfo,
        color: vk::Format,
        quality: QualityPreset,
        frames_in_flight: usize,
    ) -> RendererDesc {
        RendererDesc {
            target: TargetFormat {
                color,
                depth: crate::pipelines::DEPTH_FORMAT,
                samples: info.samples_up_to(quality.msaa_samples()),
                depth_direction: crate::pipelines::DepthDirection::Forward,
            },
            frames_in_flight,
            patches_per_draw: None,
            compute: ComputeOptions::default(),
            fused: true,
            shadow_map_size: quality.shadow_map_size(),
        }
    }
}

/// The grass frame: the field's buffers and every pass's pipelines, recorded into a command buffer the caller gives.
pub struct Renderer {
    field: Option<FieldBuffers>,
    sets: FrameSets,
    /// Every pass's pipelines (rebuilt for shader hot reload: `use_shaders`).
    pipelines: Pipelines,
    /// Draw blades as lines (if the device has a wireframe pipeline).
    pub wireframe: bool,
    /// Simulate and cull in one dispatch when a frame runs both.
    pub fused: bool,
    /// The route the Bezier blades are drawn by (resolved: never `Auto`), and the route asked
    /// for that resolved to it.
    route: DrawRoute,
    route_asked: DrawRoute,
    /// Why `route` is not the route asked for, where the device lacks what that one needs.
    route_note: Option<String>,
    patches_per_draw: u32,
    ground: Ground,
    /// The occluders seen from the camera, reduced for the culls.
    pyramid: DepthPyramid,
    /// The sun's shadow map.
    shadows: ShadowMap,
    /// What placed the ground the shadow map keeps for its field cascade (`FrameUniforms::shadow_ground_key`),
    /// and the last frame's: a frame that finds the kept one unchanged copies that ground in
    /// rather than drawing it again.
    shadow_ground: [Option<Vec<u32>>; 2],
    instanced: InstancedBuffers,
    splats: SplatTarget,
    trample: TrampleTexels,
    /// Kept alive for the grass texture's binding of every set.
    _grass_texture: GrassTexture,
    paint: PaintTexels,
    drawn_blades: DrawnBlades,
    /// What the field's bindings point at while there is no field.
    unused: Buffer,
    /// The formats and samples of the targets (the caller's depth is moved between layouts in
    /// its depth format; kept draws continue renderings of it).
    target_format: TargetFormat,
    /// Each frame slot's passes kept recorded (`recordings.rs`).
    recordings: Recordings,
    /// Replay a frame slot's kept passes, as a secondary command buffer, while nothing that
    /// shapes them changed; else every frame is recorded anew into the caller's command buffer.
    /// A query the caller keeps open around a frame (occlusion, pipeline statistics) needs the
    /// device's inheritedQueries with this on (`DeviceInfo::inherited_queries`; sward enables
    /// it where the device has it).
    pub keep_recordings: bool,
    /// Keep the ground the shadow map's field cascade sees in an image of its own, drawn
    /// again only where what places it changed, and copy it in each frame (the default); else
    /// draw it into the cascade every frame (the reference the kept ground is tested against).
    pub keep_shadow_ground: bool,
    /// Frames whose passes were recorded (not replayed) so far.
    frames_recorded: u64,
    ctx: Arc<Context>,
}

/// A frame as `record_frame` prepared it: what shapes its commands (its uniforms are written
/// into its slot), its set, and what it runs.
struct PreparedFrame {
    shape: FrameShape,
    /// The frame slot it was prepared in.
    slot: usize,
    set: vk::DescriptorSet,
    passes: Passes,
    /// The caller's depth, folded into the depth pyramid.
    caller_depth: Option<CallerDepth>,
}

impl Renderer {
    /// A renderer without a field, for targets of `desc.target`.
    pub fn new(ctx: &Arc<Context>, desc: &RendererDesc) -> Result<Renderer> {
        let pipelines = Pipelines::new(ctx, desc.target, desc.compute)?;
        let mut sets = FrameSets::new(ctx, pipelines.frame.set_layout, desc.frames_in_flight.max(1) as u32)?;
        let patches_per_draw = desc
            .patches_per_draw
            .unwrap_or(if ctx.info.driver_id == vk::DriverId::MESA_LLVMPIPE {
                LAVAPIPE_PATCHES_PER_DRAW
            } else {
                0
            });
        // Until a field is uploaded every binding still points somewhere valid: frames without
        // Bezier blades (generated grass alone) bind the same set. This buffer outlives every
        // set that points at it; the ground's own placeholder is replaced by a ground mesh.
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let unused = Buffer::new(ctx, "unused binding", 64, usage, gpu_allocator::MemoryLocation::GpuOnly)?;
        let ground = Ground::built_by_shaders(ctx)?;
        let pyramid = DepthPyramid::new(ctx)?;
        let shadows = ShadowMap::new(ctx, desc.shadow_map_size)?;
        let grass_texture = GrassTexture::new(ctx)?;
        sets.write_images((&pyramid, &shadows), &grass_texture);
        let instanced = InstancedBuffers::new(ctx, &sets.raw_sets(), desc.compute.patch_groups_on(&ctx.info))?;
        let splats = SplatTarget::new(ctx, &sets.raw_sets(), desc.target.samples)?;
        let trample = TrampleTexels::new(ctx)?;
        trample.write_descriptors(&sets.raw_sets());
        let paint = PaintTexels::new(ctx, &sets.raw_sets())?;
        let drawn_blades = DrawnBlades::new(ctx, &sets.raw_sets())?;
        let (route, route_note) = routes::resolve(DrawRoute::Auto, &ctx.info, desc.compute.copy_blades);
        let recordings = Recordings::new(ctx, sets.slots.len())?;
        let renderer = Renderer {
            pyramid,
            shadows,
            shadow_ground: [None, None],
            instanced,
            splats,
            trample,
            paint,
            drawn_blades,
            _grass_texture: grass_texture,
            unused,
            ground,
            field: None,
            sets,
            route,
            route_asked: DrawRoute::Auto,
            route_note,
            pipelines,
            wireframe: false,
            patches_per_draw,
            fused: desc.fused,
            target_format: desc.target,
            recordings,
            keep_recordings: true,
            keep_shadow_ground: true,
            frames_recorded: 0,
            ctx: ctx.clone(),
        };
        renderer.point_sets_at_field();
        Ok(renderer)
    }

    /// Blades in the uploaded field.
    pub fn blade_count(&self) -> u32 {
        self.field.as_ref().map_or(0, |f| f.count)
    }

    /// The trample map's texels as the GPU holds them now, row by row (push, mown height, cell
    /// tag; empty before a frame asked for the map).
    pub fn read_trample_map(&self) -> Result<Vec<sward_core::trample::Texel>> {
        self.trample.read()
    }

    /// Every level of the depth pyramid the last frame built, level 0 first (rows of texels,
    /// `HIZ_SIZE` square at level 0, halving): each texel the farthest depth below it.
    pub fn read_depth_pyramid(&self) -> Result<Vec<Vec<f32>>> {
        self.pyramid.read_pyramid()
    }

    /// The tiles the last frame recorded in slot `slot` ran, as their list holds them (after
    /// the frame's fence; empty without a field).
    pub fn read_active_tiles(&self, slot: usize) -> Result<Vec<sward_core::tiles::ActiveTile>> {
        self.field
            .as_ref()
            .map_or(Ok(Vec::new()), |f| f.read_active_tiles(slot))
    }

    /// The route the Bezier blades are drawn by.
    pub fn route(&self) -> DrawRoute {
        self.route
    }

    /// Why the route drawn is not the route asked for (one sentence), where the device lacks
    /// what that route needs.
    pub fn route_note(&self) -> Option<&str> {
        self.route_note.as_deref()
    }

    /// Draw the Bezier blades by `route` (`Auto`: per device), as a frame asking for it will.
    /// A route this device lacks falls back to the one `Auto` picks; the sentence saying so is
    /// returned (and kept in `route_note`). `record_frame` does this with each frame's route.
    pub fn set_route(&mut self, route: DrawRoute) -> Option<&str> {
        self.route_asked = route;
        (self.route, self.route_note) = routes::resolve(route, &self.ctx.info, self.pipelines.options.copy_blades);
        self.route_note()
    }

    /// Take the splat target's memory for a `width` × `height` frame now rather than at the
    /// first frame that splats, so a field uploaded after it is measured against what is left.
    pub fn reserve_splats(&mut self, width: u32, height: u32) -> Result<()> {
        if !self.ctx.info.int64_atomics {
            return Ok(());
        }
        self.splats.prepare(&self.sets.raw_sets(), [width, height], true)
    }

    /// Put a field on the GPU (replacing any previous one), every blade at η = 0. `tiles` are the
    /// field's tiles (`sward_core::tiles::build`); with none, the whole field is one tile. No
    /// blades: no field (frames draw only what else the scene has).
    pub fn upload_field(&mut self, blades: &[Blade], tiles: &[Tile]) -> Result<()> {
        self.put_field(blades, tiles, None)
    }

    /// Put `field` on the GPU (replacing any previous one): its blades, or, where it streams,
    /// the window its tiles are made into as the eye moves (`sward_core::stream`), and the
    /// paint maps every technique grows its grass by.
    pub fn upload(&mut self, field: &sward_core::Field) -> Result<()> {
        self.put_field(&field.blades, &field.tiles, field.stream)?;
        self.upload_paint(field.paint.as_ref())
    }

    /// Grow every technique's grass by `paint` from the next frame on (`None`: everywhere,
    /// full height); waits for the GPU. (A fixed Bezier field obeys the paint it was grown
    /// with: `sward_core::Field::grow_painted`.)
    pub fn upload_paint(&mut self, paint: Option<&sward_core::paint::GroundPaint>) -> Result<()> {
        self.forget_recordings();
        self.paint.upload(&self.sets.raw_sets(), paint)
    }

    /// Strokes painted into the paint uploaded last ([`Renderer::upload_paint`]): where the
    /// field streams, the tiles under them are made anew next frame from the new paint
    /// (standing as their twins stand), every other tile's blades keeping their poses and
    /// trails; a field that does not stream keeps all its blades. `texel` is the side of a
    /// texel of that paint. Returns how many tiles will be made.
    pub fn repaint_under(&mut self, strokes: &[sward_core::paint::Stroke], texel: f32) -> usize {
        self.forget_recordings();
        self.field.as_mut().map_or(0, |f| f.remake_tiles_under(strokes, texel))
    }

    fn put_field(
        &mut self,
        blades: &[Blade],
        tiles: &[Tile],
        stream: Option<sward_core::stream::StreamWindow>,
    ) -> Result<()> {
        unsafe { self.ctx.device.device_wait_idle() }.map_err(vk_check("waiting for the GPU"))?;
        self.forget_recordings();
        self.field = None;
        if !blades.is_empty() {
            let slots = self.sets.slots.len();
            let copy = self.pipelines.options.copy_blades;
            let cull = (copy, self.pipelines.options.workgroup);
            let field = FieldBuffers::new(&self.ctx, (blades, tiles, stream), slots, self.patches_per_draw, cull)?;
            self.field = Some(field);
        }
        // The sets must never keep pointing at a field just freed.
        self.point_sets_at_field();
        if self.drawn_blades.on {
            let lists = self.drawn_blades.lists();
            self.drawn_blades
                .prepare(&self.sets.raw_sets(), Some(self.blade_count()), lists)?;
        }
        Ok(())
    }

    /// Write the listed blades each frame, after the ordering, for a renderer that draws them
    /// itself, into `lists` lists (or stop: 0): one per view that culls for itself in the same
    /// frame (split screen, a minimap), frame slot `k` writing list `k % lists`. See
    /// [`Renderer::drawn_blade_buffers`]. Waits for the GPU.
    pub fn set_drawn_blades(&mut self, lists: usize) -> Result<()> {
        self.forget_recordings();
        let blades = (lists > 0).then(|| self.blade_count());
        self.drawn_blades.prepare(&self.sets.raw_sets(), blades, lists)
    }

    /// What a renderer that draws the Bezier blades itself reads, where the frames write the
    /// drawn blades and there is a field: the blades, the drawn blades of the last frame
    /// (`passes/drawn_blades.rs`) in the list frame slot `slot` writes, the draw commands (one
    /// per distance bucket from `COMMAND_BUCKETS` on, an instance per drawn blade: the last
    /// frame's, whichever list it wrote) and frame slot `slot`'s uniforms.
    /// The buffers live until the next upload or [`Renderer::set_drawn_blades`].
    pub fn drawn_blade_buffers(&self, slot: usize) -> Option<DrawnBladeBuffers<'_>> {
        let field = self.field.as_ref()?;
        Some(DrawnBladeBuffers {
            blades: &field.blades,
            drawn: self.drawn_blades.buffer(slot)?,
            draws: &field.draws,
            uniforms: &self.sets.slots.get(slot)?.uniforms,
        })
    }

    /// Point every set's field bindings at the field's buffers, or at the placeholder where there
    /// is no field; the ground's binding stays on the ground.
    fn point_sets_at_field(&self) {
        for k in 0..self.sets.slots.len() {
            let mut storage = [&self.unused; STORAGE_BINDINGS as usize];
            storage[5] = &self.ground.vertices;
            let mut ordered = &self.unused;
            if let Some(f) = &self.field {
                storage = [
                    &f.blades,
                    &f.etas,
                    &f.visible,
                    &f.draws,
                    &f.culled,
                    &self.ground.vertices,
                    &f.active_tiles[k],
                ];
                ordered = &f.ordered;
            }
            self.sets.write_buffers(k, &storage, ordered);
        }
    }

    /// Record one frame described by `desc` into `cmd`, using frame slot `slot` (< frames in
    /// flight; the caller makes sure that slot's previous frame has finished). The description
    /// is packed into the slot's uniforms here, with what the renderer decides (where the
    /// lists sit, which buckets are splatted); the Bezier blades are drawn by `desc.route`.
    ///
    /// `cmd` is a primary command buffer, outside any rendering. With
    /// [`Renderer::keep_recordings`] (the default) sward's commands go into secondary command
    /// buffers of the slot's — its passes, and its draw inside a rendering into the target that
    /// sward begins in `cmd` — and later frames of the slot replay them while nothing that
    /// shapes them changes (the camera, the time, the winds and the colliders' places do not:
    /// only the uniforms are written; the technique, route, quality, counts and the target's
    /// size do). Nothing kept names the target's images; a recording of the slot
    /// may be recorded anew at its next frame, so `cmd` is submitted before the slot's next
    /// frame is recorded, or recorded again.
    ///
    /// What the caller owes the target, and gets back: while these commands run, the colour
    /// attachment is in `COLOR_ATTACHMENT_OPTIMAL` and the depth attachment (0 near, 1 far) in
    /// `DEPTH_ATTACHMENT_OPTIMAL` (both aspects, for a format with stencil), with the colour and
    /// depth formats and samples the renderer was made for (`RendererDesc::target`). With [`TargetViews::over_caller`] the caller's own
    /// writes to them must be made visible first (a memory barrier from its colour-attachment
    /// output and fragment tests to the same stages); sward then only draws into them, and
    /// leaves them in the same layouts with its writes made at colour-attachment output and
    /// the late fragment tests, for the caller's next barrier. With [`TargetViews::occlusion`]
    /// sward also reads the depth before its cull: it moves the image to
    /// `DEPTH_READ_ONLY_OPTIMAL` (after the caller's barrier above) and back to
    /// `DEPTH_ATTACHMENT_OPTIMAL` before it draws. Everything else sward records — its compute
    /// passes, its depth pyramid and shadow map, their barriers — touches only sward's own
    /// buffers and images.
    pub fn record_frame(
        &mut self,
        cmd: vk::CommandBuffer,
        slot: usize,
        desc: &FrameDesc,
        passes: Passes,
        target: Option<&TargetViews>,
        timer: Option<&GpuTimer>,
    ) {
        let frame = self.prepare_frame(slot, desc, passes, target);
        let Some(key) = self.recording_key(&frame, target, timer) else {
            self.record_directly(cmd, &frame, target, timer);
            return;
        };
        let replay = match self.recordings.kept(slot, &key) {
            Some(replay) => replay,
            None => {
                let fresh = key.fresh;
                match self.record_kept(slot, key, &frame, target, timer) {
                    Ok(replay) => replay,
                    Err(e) => {
                        log::warn!("this frame is recorded directly: {e}");
                        (self.splats.fresh, self.trample.fresh) = (fresh[0], fresh[1]);
                        self.record_directly(cmd, &frame, target, timer);
                        return;
                    }
                }
            }
        };
        self.replay(cmd, replay, target, timer);
    }

    /// The frame recorded into `cmd` itself.
    fn record_directly(
        &mut self,
        cmd: vk::CommandBuffer,
        frame: &PreparedFrame,
        target: Option<&TargetViews>,
        timer: Option<&GpuTimer>,
    ) {
        self.record_passes(cmd, frame, target, timer);
        if let (true, Some(target)) = (frame.passes.draw, target) {
            self.begin_draw(cmd, target, vk::RenderingFlags::empty());
            self.record_draws(cmd, frame, (target.extent, target.over_caller));
            unsafe { self.ctx.device.cmd_end_rendering(cmd) };
        }
        stamp(cmd, timer, Stamp::Drawn);
    }

    /// Record the frame into a kept recording of slot `slot`, under `key`.
    fn record_kept(
        &mut self,
        slot: usize,
        key: RecordingKey,
        frame: &PreparedFrame,
        target: Option<&TargetViews>,
        timer: Option<&GpuTimer>,
    ) -> Result<Replay> {
        let place = self.recordings.take(slot);
        let passes = self.recordings.begin_passes(slot, place)?;
        self.record_passes(passes, frame, target, timer);
        if let Some((extent, over_caller)) = key.drawn_target() {
            let draws = self.recordings.begin_draws(slot, place, self.target_format)?;
            self.record_draws(draws, frame, (extent, over_caller));
        }
        self.recordings.end(slot, place, key)
    }

    /// A kept recording into `cmd`: its passes, then its draw inside a rendering into the
    /// caller's target begun here.
    fn replay(&self, cmd: vk::CommandBuffer, replay: Replay, target: Option<&TargetViews>, timer: Option<&GpuTimer>) {
        let d = &self.ctx.device;
        unsafe { d.cmd_execute_commands(cmd, &[replay.passes]) };
        if let (Some(draws), Some(target)) = (replay.draws, target) {
            self.begin_draw(cmd, target, vk::RenderingFlags::CONTENTS_SECONDARY_COMMAND_BUFFERS);
            unsafe {
                d.cmd_execute_commands(cmd, &[draws]);
                d.cmd_end_rendering(cmd);
            }
        }
        stamp(cmd, timer, Stamp::Drawn);
    }

    /// What shapes this frame's commands, where they can be kept and replayed: not where the
    /// host writes a tile list per frame (a field too large for the GPU to decide its tiles),
    /// nor when the caller asked for every frame recorded anew.
    fn recording_key(
        &self,
        frame: &PreparedFrame,
        target: Option<&TargetViews>,
        timer: Option<&GpuTimer>,
    ) -> Option<RecordingKey> {
        let host_tiles = self.field.as_ref().is_some_and(|f| !f.tiles_on_gpu());
        (self.keep_recordings && !host_tiles).then(|| RecordingKey {
            shape: frame.shape,
            passes: [frame.passes.simulate, frame.passes.cull, frame.passes.draw],
            target: target.map(|t| (t.extent, t.over_caller)),
            timer: timer.map(GpuTimer::id),
            route: self.route,
            wireframe: self.wireframe,
            fused: self.fused,
            fresh: [self.splats.fresh, self.trample.fresh],
            drawn_blades: self.drawn_blades.on,
            descriptor_writes: self.ctx.descriptor_writes(),
        })
    }

    /// Plan the frame `desc` describes (routes, lists, splat cells, tiles), growing what must
    /// grow, pack it into slot `slot`'s uniforms and point the slot's set at the caller's depth.
    fn prepare_frame(
        &mut self,
        slot: usize,
        desc: &FrameDesc,
        passes: Passes,
        target: Option<&TargetViews>,
    ) -> PreparedFrame {
        if desc.route != self.route_asked {
            self.set_route(desc.route);
        }
        let sets = self.sets.raw_sets();
        let can = RendererCan {
            // Splats need 64-bit atomics.
            splat: self.ctx.info.int64_atomics,
            route: self.route,
            // Wireframe is the hardware's: it rasterizes nothing by compute.
            rasterize: self.splats.cell_per_sample() && !self.wireframe,
            bezier_field: self.field.is_some(),
            // Blade occluders come from the ordered list (the bench's copy variant has none).
            blade_occluders: !self.pipelines.options.copy_blades,
            cull: passes.cull,
            caller_depth: target.is_some_and(|t| t.over_caller && t.occlusion.is_some()),
        };
        let mut plan = FramePlan {
            blade_count: self.blade_count(),
            patches_per_draw: self.patches_per_draw,
            pyramid_size: HIZ_SIZE,
            splat_scale: self.splats.scale(),
            ..FramePlan::of(desc, can)
        };
        if let Err(e) = self.splats.prepare(&sets, desc.viewport, plan.decided.splatting) {
            log::error!("nothing is splatted this frame, every blade is drawn: {e}");
            plan.decided = FrameDecisions::of(desc, RendererCan { splat: false, ..can });
        }
        if let Some(field) = self.field.as_mut() {
            let ground = self.ground.grid.as_ref().map_or([0.0, 0.0], |g| GridBounds::of(g).span);
            let work = (self.pipelines.options.workgroup, passes.simulate);
            plan.tiles = field.prepare_tiles(slot, (desc, &plan.decided), work, ground);
            plan.stream_window = field.stream_window();
            plan.origin = field.origin();
        }
        let generated = plan.decided.generates;
        // The generated grass and the streamed field's entering tiles stand on the height grid
        // (a streamed tile may enter in a frame that only simulates).
        if generated || plan.stream_window.is_some() {
            plan.height_grid = self.ground.grid.as_ref().map(GridBounds::of);
        }
        // The ground's tint reads the paint too.
        plan.paint = self.paint.area;
        if generated {
            match self.instanced.prepare(&sets, &plan.decided) {
                Ok(layout) => plan.generated = layout,
                Err(e) => log::error!("the instanced grass is skipped this frame: {e}"),
            }
        }
        plan.trample = desc.trample.is_some();
        if let Err(e) = self.trample.prepare(&sets, desc.trample.as_ref()) {
            log::error!("the generated grass is not trampled: {e}");
            plan.trample = false;
        }
        // The caller's depth joins the occluders where it gives it (and the pyramid is drawn).
        let caller_depth = target
            .filter(|t| t.over_caller && plan.decided.depth_pyramid)
            .and_then(|t| t.occlusion);
        let caller_info = caller_depth.map(|depth| self.pyramid.caller_depth_info(depth.view));
        self.sets.point_caller_depth(slot, caller_info);
        let uniforms = FrameUniforms::pack(desc, &plan);
        let mut shape = FrameShape::of(desc, &plan, self.splats.in_use());
        // The field cascade is drawn where the frame is drawn with shadows (`record_occluders`).
        if passes.draw && target.is_some() && shape.shadows && self.keep_shadow_ground {
            shape.shadow_ground = self.keep_shadow_ground_of(&uniforms, plan.streamed(desc).is_some());
        }
        let frame_slot = &mut self.sets.slots[slot];
        let mapped = frame_slot.uniforms.mapped_mut().expect("uniforms are host visible");
        sward_core::declared::write_frame(&uniforms, mapped);
        PreparedFrame {
            shape,
            slot,
            set: frame_slot.set,
            passes,
            caller_depth,
        }
    }

    /// How the frame of `uniforms` (its field `streamed` or not, as its plan says) brings the
    /// ground into the field cascade: the kept ground copied in where what places it is what
    /// placed the kept one; kept anew where it stood still since the last frame; else drawn into
    /// the cascade itself, as a ground that moves every frame (a streamed field's plane under a
    /// walking eye) is, at no cost beyond it.
    fn keep_shadow_ground_of(&mut self, uniforms: &FrameUniforms, streamed: bool) -> ShadowGround {
        let key = Some(uniforms.shadow_ground_key(streamed));
        let [kept, last] = &mut self.shadow_ground;
        let how = if *kept == key {
            ShadowGround::Kept { changed: false }
        } else if *last == key {
            *kept = key.clone();
            ShadowGround::Kept { changed: true }
        } else {
            ShadowGround::Drawn
        };
        *last = key;
        how
    }

    /// The frame's passes before its draw, as `prepare_frame` decided them.
    fn record_passes(
        &mut self,
        cmd: vk::CommandBuffer,
        frame: &PreparedFrame,
        target: Option<&TargetViews>,
        timer: Option<&GpuTimer>,
    ) {
        let PreparedFrame {
            ref shape,
            slot,
            set,
            passes,
            caller_depth,
        } = *frame;
        self.frames_recorded += 1;
        let [rasterized, splatted] = shape.buckets;
        let stamp = |s: Stamp| stamp(cmd, timer, s);
        occluders::record_occluders(
            &self.parts(cmd, set),
            shape,
            passes.draw && target.is_some(),
            caller_depth,
        );
        self.splats.record_clear(cmd);
        stamp(Stamp::Occluded);
        // The map steps with the simulation (`headless` steps without culling, in chunks).
        if passes.simulate && shape.trample_texels > 0 {
            self.record_trample(cmd, set, shape);
        }
        stamp(Stamp::Trampled);
        let work = FieldWork {
            simulate: passes.simulate && shape.steps,
            cull: passes.cull,
            fused: self.fused,
            order: !self.pipelines.options.copy_blades,
            splat: shape.bezier_splats,
            // Nothing to rasterize (the usual case: the rasterizer is the scene's choice): no
            // rasterizer passes and no full-screen tile passes.
            raster_tiles: self
                .pipelines
                .splats
                .tiles
                .as_ref()
                .filter(|_| rasterized < splatted)
                .map(|t| (t.bezier.each_ref().map(|p| p.raw), self.splats.tiles())),
            workgroup: self.pipelines.options.workgroup,
        };
        let layout = self.pipelines.layout();
        match &self.field {
            Some(field) => field.record(cmd, (slot, set, layout), &self.pipelines.field, work, &|| {
                stamp(Stamp::Simulated)
            }),
            None => stamp(Stamp::Simulated),
        }
        if shape.generated {
            generated::record_generated(&self.parts(cmd, set), shape);
        }
        if let (Some(field), true, true) = (&self.field, self.drawn_blades.on, passes.cull && work.order) {
            let blades = (field.count, self.pipelines.options.workgroup);
            self.drawn_blades.record(cmd, self.pipelines.drawn_blades.raw, blades);
        }
        stamp(Stamp::Ordered);
        let drawn = passes.draw && target.is_some();
        if drawn && shape.blade_shadows {
            shadows::record_near_shadows(&self.parts(cmd, set), shape, work.order);
        }
        stamp(Stamp::Shadowed);
        if let Some(field) = &self.field {
            field.record_compute_draws(cmd, (set, layout), &self.pipelines.field, work);
        }
        stamp(Stamp::Culled);
    }

    /// What the passes record from, into `cmd` with the frame's `set`.
    fn parts(&self, cmd: vk::CommandBuffer, set: vk::DescriptorSet) -> FrameParts<'_> {
        FrameParts {
            cmd,
            set,
            ctx: &self.ctx,
            pipelines: &self.pipelines,
            field: self.field.as_ref(),
            ground: &self.ground,
            pyramid: &self.pyramid,
            shadows: &self.shadows,
            instanced: &self.instanced,
            splats: &self.splats,
            target_format: self.target_format,
        }
    }

    /// Begin rendering into the caller's target with `flags` (`draw.rs`).
    fn begin_draw(&self, cmd: vk::CommandBuffer, target: &TargetViews, flags: vk::RenderingFlags) {
        draw::begin_draw((&self.ctx.device, cmd), target, (self.target_format, flags));
    }

    /// The frame's draws into a target of `extent` (over the caller's picture: `over_caller`).
    fn record_draws(&self, cmd: vk::CommandBuffer, frame: &PreparedFrame, target: (vk::Extent2D, bool)) {
        let parts = self.parts(cmd, frame.set);
        draw::record_draws(&parts, &frame.shape, target, (self.route, self.wireframe));
    }

    /// The trample map's frame (the grass recovers as the frame's steps pass), before the
    /// generated grass reads it.
    fn record_trample(&mut self, cmd: vk::CommandBuffer, set: vk::DescriptorSet, shape: &FrameShape) {
        let d = &self.ctx.device;
        let layout = self.pipelines.layout();
        unsafe { d.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::COMPUTE, layout, 0, &[set], &[]) };
        self.trample.record(cmd, self.pipelines.trample.raw, shape);
    }

    /// Put the ground mesh on the GPU (`None`: the plane or sphere the shaders make themselves).
    /// Call after [`Renderer::upload_field`].
    pub fn upload_ground(&mut self, mesh: Option<&sward_core::mesh::Mesh>) -> Result<()> {
        unsafe { self.ctx.device.device_wait_idle() }.map_err(vk_check("waiting for the GPU"))?;
        self.forget_recordings();
        self.shadow_ground = [None, None];
        self.ground = match mesh {
            Some(mesh) => Ground::from_mesh(&self.ctx, mesh)?,
            None => Ground::built_by_shaders(&self.ctx)?,
        };
        self.sets.write_ground(&self.ground.vertices);
        Ok(())
    }

    /// Rebuild every pass's pipelines from `shaders` (the viewer's hot reload, `--shaders`), on
    /// the renderer's own frame layout, target and compute options, once the GPU is idle.
    pub fn use_shaders(&mut self, shaders: &ShaderSet) -> Result<()> {
        let pipelines = self.pipelines.rebuilt(&self.ctx, shaders)?;
        unsafe { self.ctx.device.device_wait_idle() }.map_err(vk_check("waiting for the GPU"))?;
        self.forget_recordings();
        self.shadow_ground = [None, None];
        self.pipelines = pipelines;
        Ok(())
    }

    /// Every pass's pipelines.
    pub fn pipelines(&self) -> &Pipelines {
        &self.pipelines
    }

    /// Frames whose passes were recorded so far, rather than replayed from a kept recording
    /// (with [`Renderer::keep_recordings`], a frame is recorded only when what shapes its
    /// commands changed).
    pub fn frames_recorded(&self) -> u64 {
        self.frames_recorded
    }

    /// Drop the kept recordings: a field, ground or pipelines they point at is replaced.
    fn forget_recordings(&mut self) {
        self.recordings.forget();
    }

    /// Record a copy of the visible-blade count (after this frame's cull) into `dst` at byte 0,
    /// and of the blades the frame simulated at byte 4, for reading once the frame's fence has
    /// signalled.
    pub fn record_copy_visible_count(&self, cmd: vk::CommandBuffer, dst: &Buffer) {
        if let Some(field) = &self.field {
            field.record_copy_visible_count(cmd, dst);
        }
    }

    /// Run compute passes only (no target) and wait: for tests and simulation warm-up.
    pub fn run_compute(&mut self, desc: &FrameDesc, passes: Passes) -> Result<()> {
        let ctx = self.ctx.clone();
        ctx.submit_and_wait("running the compute passes", |cmd| {
            self.record_frame(cmd, 0, desc, Passes { draw: false, ..passes }, None, None);
        })
    }

    /// The instanced grass's draw commands as the GPU holds them now: `instance_count` of
    /// command k is the number of blades visible at level k.
    pub fn read_instanced_draws(&self) -> Result<Vec<DrawCommand>> {
        self.instanced.read_draws()
    }

    /// The generated grass's patch lists as the GPU built them in the last frame: the instanced
    /// field's, then the billboards' (patches in units of `PATCH_CELLS` cells, nearest ring
    /// first).
    pub fn read_generated_patches(&self) -> Result<[Vec<glam::IVec2>; 2]> {
        self.instanced.read_patches()
    }

    /// The generated grass's visible lists as the GPU holds them now, in draw order (the
    /// instanced grass's four levels, then the billboards).
    pub fn read_generated_lists(&self) -> Result<Vec<Vec<[u32; 8]>>> {
        self.instanced.read_lists()
    }

    /// The frame origin (world x and z) the field's blades are held around: zero unless the field
    /// streams (`sward_core::stream::frame_origin`). `read_blades` gives positions less it.
    pub fn origin(&self) -> glam::Vec2 {
        self.field.as_ref().map_or(glam::Vec2::ZERO, |f| f.origin()[0])
    }

    /// The blades as the GPU holds them now: positions measured from [`Renderer::origin`].
    pub fn read_blades(&self) -> Result<Vec<Blade>> {
        self.read(|f| &f.blades)
    }

    /// The collision strengths η as the GPU holds them now.
    pub fn read_etas(&self) -> Result<Vec<f32>> {
        self.read(|f| &f.etas)
    }

    /// The visible blade ids the last cull wrote, in draw order (nearest distance bucket first),
    /// and every draw command (`[0]`: the whole list in one; `sward_core::commands`).
    pub fn read_visible(&self) -> Result<(Vec<u32>, Vec<DrawCommand>)> {
        match &self.field {
            Some(field) => field.read_visible(),
            None => Ok((Vec::new(), Vec::new())),
        }
    }

    fn read<T: bytemuck::Pod>(&self, which: impl Fn(&FieldBuffers) -> &Buffer) -> Result<Vec<T>> {
        match &self.field {
            Some(field) => Ok(bytemuck::pod_collect_to_vec(&which(field).download()?)),
            None => Ok(Vec::new()),
        }
    }
}

impl Drop for Renderer {
    fn drop(&mut self) {
        unsafe {
            let _ = self.ctx.device.device_wait_idle();
        }
    }
}

/// Write `stamp` into `cmd` where the frame is timed.
fn stamp(cmd: vk::CommandBuffer, timer: Option<&GpuTimer>, stamp: Stamp) {
    if let Some(timer) = timer {
        timer.stamp(cmd, stamp);
    }
}
