//! The structs the shaders read, laid out once here (`#[repr(C)]`, std140/std430-compatible:
//! only `vec4`, `uvec4` and `mat4` members) and written into the shaders from `declared.rs`. Sizes are asserted at
//! compile time; the GPU-vs-CPU tests catch any disagreement in member order.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, UVec4, Vec2, Vec3, Vec4};

use crate::flags;
use crate::frame::{FrameColliders, FrameDesc, GroundShape};
use crate::instanced::GridParams;
use crate::physics::MAX_COLLIDERS;
use crate::plan::{FrameDecisions, RendererCan};
use crate::trample::TrampleParams;
use crate::wind::{Wind, MAX_WINDS};

/// Per-frame uniforms shared by every pass.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct FrameUniforms {
    /// World to clip space of the frame's camera.
    pub view_proj: Mat4,
    /// Inverse of `view_proj`, for the sky's view rays.
    pub inv_view_proj: Mat4,
    /// The sun's orthographic view of the scene, for the shadow map's field cascade.
    pub sun_view_proj: Mat4,
    /// The sun's orthographic view of the ball `shading_extra.w` around the eye, for the shadow
    /// map's near cascade (blades cast into it).
    pub sun_near_view_proj: Mat4,
    /// xyz eye position, w simulated time of the frame's first step.
    pub camera_position: Vec4,
    /// xyz unit direction, w strength.
    pub gravity: Vec4,
    /// xyz position, w strength.
    pub point_gravity: Vec4,
    /// x step, y η decay rate, z point-gravity blend, w unused.
    pub simulation: Vec4,
    /// x blade count, y steps to simulate, z collider count, w the `FORCE_*` flags.
    pub counts: UVec4,
    /// x orientation threshold, y frustum tolerance, z distance max, w distance levels.
    pub cull: Vec4,
    /// x tile margin (units), y occlusion depth tolerance (units), z camera near, w camera far.
    pub coarse_cull: Vec4,
    /// x the `CULL_*` flags, y wind field count, z patches per draw command (0: one command), w the
    /// `DRAW_*` flags (`flags.rs`).
    pub modes: UVec4,
    /// x min level, y max level, z near, w far.
    pub lod: Vec4,
    /// x shape (`flags::BLADE_*`), y tip threshold, w min width in pixels (the ridge is the
    /// `DRAW_BLADE_RIDGE` flag).
    pub blade_style: Vec4,
    /// x width, y height, z 1/width, w 1/height (pixels).
    pub viewport: Vec4,
    /// xyz unit direction toward the sun, w ambient share.
    pub light_direction: Vec4,
    /// Sunlight colour (rgb).
    pub light_color: Vec4,
    /// rgb, w colour jitter.
    pub root_color: Vec4,
    /// Colour at the tip (rgb).
    pub tip_color: Vec4,
    /// Ground colour (rgb), w how wet the ground is (standing water where bare).
    pub ground_color: Vec4,
    /// Sky colour overhead (rgb).
    pub sky_zenith: Vec4,
    /// rgb, w fog density.
    pub sky_horizon: Vec4,
    /// x model (`flags::SHADING_*`), y specular strength, z shininess, w translucency.
    pub shading_model: Vec4,
    /// x ambient occlusion strength, y clump colour variation, z clump scale (1/units), w how far
    /// from the eye blades cast shadows (the near cascade's radius; 0 without blade shadows).
    pub shading_extra: Vec4,
    /// xy half extent of the ground quad, zw half extent of the grown field.
    pub ground_extent: Vec4,
    /// A sphere ground (`GROUND_SPHERE`): xyz its centre, w its radius.
    pub surface: Vec4,
    /// Instanced grass: x grid spacing, y cut-off radius, z inner radius, w clump scale.
    pub instanced_grid: Vec4,
    /// Instanced grass: height min, max; half-width min, max.
    pub instanced_shape: Vec4,
    /// Instanced grass: x bend, y sway (unread: the blades settle in the wind), z where the
    /// compute rasterizer takes over from the raster
    /// hardware (`instanced::raster_from`).
    pub instanced_motion: Vec4,
    /// Instanced grass: xyz the distances where levels 1, 2 and 3 start.
    pub instanced_lod: Vec4,
    /// Instanced grass: where each level's visible list starts (set by the renderer).
    pub instanced_lists: UVec4,
    /// Instanced grass: each level's capacity (set by the renderer).
    pub instanced_caps: UVec4,
    /// x the instanced grass's seed, y technique (`Technique::index`), z splat cells per pixel
    /// side (set by the renderer), w unused (the occlusion bit of `modes.x` says where the culls
    /// test the pyramid).
    pub instanced_meta: UVec4,
    /// Instanced grass on a height grid (the uploaded ground): x, y its min x, z; z, w its max x, z.
    pub instanced_ground: Vec4,
    /// x, y the height grid's vertices along x and z (0: the plane y = 0), z the ground's shape
    /// (`flags::GROUND_*`).
    pub instanced_ground_cells: UVec4,
    /// Billboards: x grid spacing, y cut-off radius, z inner radius, w clump scale.
    pub billboard_grid: Vec4,
    /// Billboards: height min, max; half-width min, max.
    pub billboard_shape: Vec4,
    /// Billboards: x sway, y cross-fade band with the instanced grass (units).
    pub billboard_motion: Vec4,
    /// Billboards: x where their list starts, y its capacity, z their first patch row (set by the
    /// renderer), w seed.
    pub billboard_meta: UVec4,
    /// Draw routes: x the first distance bucket the compute route splats, the first wholly beyond
    /// `lod.splat_distance` (the renderer sets `DISTANCE_BUCKETS`, none, on the other routes);
    /// y the first it rasterizes by compute (up to x): with `lod.compute_raster` the first
    /// wholly beyond `lod.strip_distance`, else x (the renderer sets x too where compute
    /// cannot rasterize); z the first bucket wholly beyond the blade-shadow distance (the
    /// buckets before it cast into the near cascade); w unused.
    pub routes: UVec4,
    /// Occlusion by grass: x how many of the nearest blades the last frame drew are drawn into
    /// the depth pyramid (`cull.blade_occluders`; 0: only the ground and the colliders, and the
    /// cull tests blade points as SPEC §4 does, else whole blades, piece by piece); y the depth
    /// pyramid's side in texels (set by the renderer); zw unused.
    pub occlusion: UVec4,
    /// The generated grass's patch lists (`patch_cull.wesl`): x the row of the patch buffer where
    /// the ring order of offsets starts (after both grids' rows), y its length (both set by the
    /// renderer), z the instanced grass's reach in patches, w the billboards'.
    pub patch_cull: UVec4,
    /// Their patches' boxes: x the ground's lowest, y its highest point (set by the renderer on
    /// a height grid, else 0), z how high an instanced blade reaches, w a billboard.
    pub patch_bounds: Vec4,
    /// The Bezier field's tiles (set by the renderer): x how many, where the GPU decides which
    /// run (`tile_cull.wesl`; 0: the host wrote the list), y the workgroups of one tile's row.
    pub tiles: UVec4,
    /// The trample map (`trample.rs`): x its texels along a side (0: off), y unused, zw the
    /// window's first cell (i32 bits).
    pub trample: UVec4,
    /// Mowing: x the cutters (in `colliders` after the `counts.z` pushing spheres), y unused, z
    /// the spheres that only hide grass (after the cutters), w unused.
    pub mowing: UVec4,
    /// The trample map's lengths: x a texel's size in units, y how fast mown grass grows back
    /// (`trample.regrow`, units of height per second), zw unused.
    pub trample_scale: Vec4,
    /// Billboards far and near: x the distance from which a billboard is one quad, y from which it is
    /// splatted by compute, z 1 where billboards are drawn with a depth pre-pass (else 0), w from
    /// which the listed billboards are rasterized by compute.
    pub billboard_far: Vec4,
    /// Instanced grass: the list of the blades rasterized by compute, x where it starts in the
    /// visible lists, y its capacity (set by the renderer).
    pub instanced_raster: UVec4,
    /// The streamed field (`stream.rs`): x tiles along a side of its window (0: the field does not
    /// stream), y cells along a tile's side, zw the window's first tile (i32 bits).
    pub stream: UVec4,
    /// The streamed field's hand-over: x where the Bezier blades end and the instanced grass
    /// begins, y where the Bezier blades begin easing into their instanced twins (x: no easing),
    /// zw the grass's stiffness range (`FrameDesc::stiffness`, also where the field does not
    /// stream: the generated blades settle by it).
    pub stream_reach: Vec4,
    /// Where the frame's positions are measured from (`stream::frame_origin`): xy the world x
    /// and z of the point every position the GPU holds is less (0 unless the field streams), zw
    /// what the stored Bezier blades move by this frame (non-zero only in the frame the origin
    /// moves; the rebase pass (stream.wesl `rebase_field`) subtracts it).
    pub origin: Vec4,
    /// The paint maps (`paint.rs`): xy the world x and z of their lowest corner, zw texels per
    /// unit of ground along x and z.
    pub paint_area: Vec4,
    /// The paint maps' texels along x and z (0: no map).
    pub paint_size: UVec4,
    /// The paint's noise (`paint::PaintNoise`): x patches per unit (0: none), y cover, z softness.
    pub paint_noise: Vec4,
    /// The paint's tint noise (`paint::TintNoise`): x patches per unit (0: none), y cover, z
    /// softness.
    pub paint_tint_noise: Vec4,
    /// What the grass's colour is multiplied by in a tint-noise patch.
    pub paint_tint_color: Vec4,
    /// The kinds of grass: x how many (0: one, from the scene's ranges and colours), y whether
    /// any has seed heads.
    pub species_meta: UVec4,
    /// Per species four vectors: height min, max, half-width min, max; stiffness min, max,
    /// bend, weight; root colour; tip colour (`species.rs`).
    pub species: [Vec4; 4 * crate::species::MAX_SPECIES],
    /// Per species two vectors (`species::SeedHeads`): x the share of blades with a head, y the
    /// head's part of the blade (0: none); the head's colour.
    pub seed_heads: [Vec4; 2 * crate::species::MAX_SPECIES],
    /// The lamps (`look::Lamp`): x how many.
    pub lamp_meta: UVec4,
    /// Per lamp three vectors: xyz position (frame space), w range; rgb its light at one unit,
    /// w the cosine of a spot light's outer angle (-2: all round); xyz where a spot light
    /// points, w the cosine of its inner angle.
    pub lamps: [Vec4; 3 * crate::look::MAX_LAMPS],
    /// The view frustum's planes in frame space (`tiles::frustum_planes`), for bounding spheres.
    pub frustum: [Vec4; 6],
    /// Per wind field three vectors: xyz unit direction and w strength; x gust amplitude, y gust
    /// frequency, z noise scale, w noise speed; xyz centre (radial, whirl) and w the field's kind.
    pub winds: [Vec4; 3 * MAX_WINDS],
    /// xyz centre, w radius.
    pub colliders: [Vec4; MAX_COLLIDERS],
    /// The field's space (a frame point plus the origin) to the application's world
    /// (`FrameDesc::placement`): only an engine's draw reads it, to put the points the passes
    /// made where its world has the field (the identity for sward's own).
    pub placed: Mat4,
    /// `placed` as the last frame had it (the motion vectors' other end).
    pub placed_before: Mat4,
}

const _: () =
    assert!(std::mem::size_of::<FrameUniforms>() == 256 + 109 * 16 + 3 * MAX_WINDS * 16 + MAX_COLLIDERS * 16 + 2 * 64);

/// `VkDrawIndirectCommand`, as the cull pass writes it.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct DrawCommand {
    /// Vertices per instance (patch control points or strip vertices).
    pub vertex_count: u32,
    /// Instances: the blades this command draws.
    pub instance_count: u32,
    /// First vertex.
    pub first_vertex: u32,
    /// First instance: where in the ordered visible list the command's blades start.
    pub first_instance: u32,
}

const _: () = assert!(std::mem::size_of::<DrawCommand>() == 16);

/// A frame as the renderer plans it: the frame's decisions, made once from its description and
/// what the renderer can do ([`FrameDecisions`]), and where the renderer's own state puts things
/// (its lists in its buffers, the height grid, the streamed window, the tiles, the paint).
/// Packed with the description in one step ([`FrameUniforms::pack`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FramePlan {
    /// How each blade reaches the screen, the hand-overs, shadows and occlusion.
    pub decided: FrameDecisions,
    /// Bezier blades in the uploaded field.
    pub blade_count: u32,
    /// Visible blades per draw command (0: one command for all).
    pub patches_per_draw: u32,
    /// The depth pyramid's side in texels.
    pub pyramid_size: u32,
    /// Splat cells per pixel side.
    pub splat_scale: u32,
    /// Where the generated grass's lists and patches sit.
    pub generated: GeneratedLayout,
    /// The height grid generated grass stands on (the uploaded ground), where there is one.
    pub height_grid: Option<GridBounds>,
    /// Whether the trample map runs (its texels are ready).
    pub trample: bool,
    /// The window the renderer's field streams into, where it streams (the description's
    /// `stream` is packed only then, and with this window: the shaders read the field there is).
    pub stream_window: Option<crate::stream::StreamWindow>,
    /// The frame origin (world x and z) the renderer's field is held around, and how far it
    /// moved this frame (`FrameUniforms::origin`): zero unless the field streams.
    pub origin: [Vec2; 2],
    /// The Bezier field's tiles: how many the GPU decides among (0: the host wrote the list),
    /// and the workgroups of one tile's row.
    pub tiles: [u32; 2],
    /// Where the uploaded paint maps lie, where there are any.
    pub paint: Option<PaintArea>,
}

impl FramePlan {
    /// The plan of the frame `desc` describes, decided for a renderer that can do what `can`
    /// says; the renderer's own parts empty until it fills them.
    pub fn of(desc: &FrameDesc, can: RendererCan) -> FramePlan {
        FramePlan {
            decided: FrameDecisions::of(desc, can),
            blade_count: 0,
            patches_per_draw: 0,
            pyramid_size: 0,
            splat_scale: 1,
            generated: GeneratedLayout::default(),
            height_grid: None,
            trample: false,
            stream_window: None,
            origin: [Vec2::ZERO; 2],
            tiles: [0, 0],
            paint: None,
        }
    }

    /// Where the frame's Bezier field streams around the eye: the scene's streaming and the
    /// window the renderer's field holds (None: the field does not stream this frame).
    pub fn streamed(&self, desc: &FrameDesc) -> Option<(crate::frame::FrameStream, crate::stream::StreamWindow)> {
        desc.stream.zip(self.stream_window)
    }
}

/// Where the paint maps the renderer holds lie over the ground, and its noise.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PaintArea {
    /// The world x and z of the maps' lowest corner.
    pub min: Vec2,
    /// Texels per unit of ground along x and z.
    pub per_unit: Vec2,
    /// Texels along x and z (zero: no map).
    pub size: [u32; 2],
    /// The noise, where the ground is painted by noise.
    pub noise: Option<crate::paint::PaintNoise>,
    /// The tint noise, where the grass is tinted by noise.
    pub tint_noise: Option<crate::paint::TintNoise>,
}

impl PaintArea {
    /// Where `paint`'s maps lie, and its noise.
    pub fn of(paint: &crate::paint::GroundPaint) -> PaintArea {
        let map = paint.map.as_ref();
        PaintArea {
            min: map.map_or(Vec2::ZERO, |m| m.min),
            per_unit: map.map_or(Vec2::ZERO, |m| m.texels_per_unit()),
            size: map.map_or([0, 0], |m| m.size),
            noise: paint.noise,
            tint_noise: paint.tint_noise,
        }
    }
}

/// Where the generated grass's lists start and what they hold, and how its patch buffer is laid out.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct GeneratedLayout {
    /// The instanced grass's levels: (first entry, capacity).
    pub levels: [[u32; 2]; 4],
    /// The instanced blades rasterized by compute: (first entry, capacity).
    pub rasterized: [u32; 2],
    /// The billboards: (first entry, capacity).
    pub billboards: [u32; 2],
    /// The patch buffer's rows: the instanced grass's, then the billboards'.
    pub patch_rows: [u32; 2],
    /// The ring order of patch offsets: its length (it starts after both grids' rows).
    pub ring_len: u32,
}

/// How many patches each grid of a frame's generated grass may keep (a row of workgroups each)
/// and how far around the eye's patch its ring order reaches: what the renderer's patch
/// buffer must hold.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GeneratedRows {
    /// The instanced grass's rows, then the billboards' (0 where the technique draws none).
    pub rows: [u32; 2],
    /// Patches each way from the eye's, for the larger reach of the two grids.
    pub reach: i32,
}

impl GeneratedRows {
    /// The rows a frame may keep on the grids `decided` generates, drawn as it says, at most
    /// `rows_limit` a grid (the rows of workgroups a dispatch may have).
    pub fn of(decided: &FrameDecisions, rows_limit: u32) -> GeneratedRows {
        let billboards = decided.billboards.as_grid();
        let grids = [(decided.grids[0], &decided.instanced), (decided.grids[1], &billboards)];
        let rows = grids.map(|(on, p)| match on {
            true => crate::instanced::patch_candidates(p).min(rows_limit),
            false => 0,
        });
        let reach = grids
            .iter()
            .map(|&(on, p)| if on { crate::instanced::patch_reach(p) } else { 0 })
            .max()
            .unwrap_or(0);
        GeneratedRows { rows, reach }
    }

    /// Whether a patch buffer laid out for `self` holds what `other` asks.
    pub fn holds(&self, other: &GeneratedRows) -> bool {
        other.rows[0] <= self.rows[0] && other.rows[1] <= self.rows[1] && other.reach <= self.reach
    }

    /// The rows that hold both `self` and `other`.
    pub fn max(&self, other: &GeneratedRows) -> GeneratedRows {
        GeneratedRows {
            rows: [self.rows[0].max(other.rows[0]), self.rows[1].max(other.rows[1])],
            reach: self.reach.max(other.reach),
        }
    }
}

/// Bytes of one listed generated blade or billboard (an entry of [`GeneratedLayout`]'s lists):
/// root, height and half-width, facing and tip, hash, outline.
pub const LISTED_BLADE_BYTES: u64 = 32;

/// Entries the billboards' list of `cap` takes with what follows it: the indices of the
/// billboards the raster hardware draws where the rest are rasterized by compute, eight to an
/// entry.
pub fn billboard_entries(cap: u32) -> u64 {
    cap as u64 + (cap as u64).div_ceil(8)
}

impl GeneratedLayout {
    /// The lists of a frame whose grids keep at most `kept` rows of patches, one after another
    /// — the instanced grass's four levels, its blades rasterized by compute, the billboards —
    /// each as many blades as its distances can hold (within the sector the camera sees, where
    /// `seen` gives it), all within one binding of `binding` bytes
    /// (scaled down together where they would not fit); over a patch buffer of `buffer`'s rows
    /// with a ring order of `ring_len` offsets. Also the entries the lists take in all.
    pub fn of(
        decided: &FrameDecisions,
        kept: &GeneratedRows,
        (buffer, ring_len): (&GeneratedRows, u32),
        (binding, seen): (u64, Option<&crate::instanced::SeenSector>),
    ) -> (GeneratedLayout, u64) {
        let limit = binding / LISTED_BLADE_BYTES;
        use crate::instanced::{disk_capacity, lod_capacities, raster_capacity};
        let params = &decided.instanced;
        let billboards = decided.billboards.as_grid();
        let [l0, l1, l2, l3] = lod_capacities(params, kept.rows[0] as usize, seen);
        let mut caps = [l0, l1, l2, l3, raster_capacity(params, kept.rows[0] as usize, seen)];
        let mut billboard_cap = disk_capacity(&billboards, billboards.grid.radius, kept.rows[1] as usize, seen);
        let total: u64 = caps.iter().map(|&c| c as u64).sum::<u64>() + billboard_entries(billboard_cap);
        if total > limit {
            caps = caps.map(|c| (c as u64 * limit / total) as u32);
            billboard_cap = (billboard_cap as u64 * limit / total) as u32;
        }
        let listed: u32 = caps.iter().sum();
        let mut layout = GeneratedLayout {
            billboards: [listed, billboard_cap],
            patch_rows: buffer.rows,
            ring_len,
            ..GeneratedLayout::default()
        };
        let mut start = 0;
        for (k, cap) in caps.into_iter().enumerate() {
            match k < layout.levels.len() {
                true => layout.levels[k] = [start, cap],
                false => layout.rasterized = [start, cap],
            }
            start += cap;
        }
        (layout, (listed as u64 + billboard_entries(billboard_cap)).max(1))
    }
}

/// The extent of a height grid the generated grass stands on.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GridBounds {
    /// Smallest x and z.
    pub min: Vec2,
    /// Largest x and z.
    pub max: Vec2,
    /// Vertices along x and z.
    pub cells: [u32; 2],
    /// Its lowest and highest point.
    pub span: [f32; 2],
}

impl GridBounds {
    /// The bounds of `grid`.
    pub fn of(grid: &crate::mesh::HeightGrid) -> GridBounds {
        GridBounds {
            min: grid.min,
            max: grid.max,
            cells: [grid.nx, grid.nz],
            span: grid.span,
        }
    }
}

/// How far the ground plane reaches beyond the field, as a multiple of the field's extent, so
/// the horizon is ground fading into fog rather than the edge of a board.
const GROUND_REACH: f32 = 12.0;
/// The farthest the ground reaches from the eye (units): the far plane of a camera with one
/// at infinity is not a place.
const MAX_GROUND_REACH: f32 = 1.0e5;

impl FrameUniforms {
    /// What places the ground as the shadow map's field cascade sees it (the ground's vertex
    /// stage from the sun), where the frame's field streams (`streamed`) or not: the sun's view,
    /// the ground's kind, extent and sphere, and where a streamed field puts it (its origin, the
    /// eye it follows where the field streams). Both renderers keep the cascade's ground while it
    /// stays the same; the mesh itself is the renderer's (an upload forgets the kept ground).
    pub fn shadow_ground_key(&self, streamed: bool) -> Vec<u32> {
        let u = self;
        // The eye a streamed plane follows (its w is the time, which the ground does not read).
        let eye = if streamed {
            u.camera_position.truncate().extend(0.0)
        } else {
            glam::Vec4::ZERO
        };
        let mut key: Vec<u32> = bytemuck::cast_slice(&u.sun_view_proj.to_cols_array()).to_vec();
        for v in [u.ground_extent, u.surface, u.origin, eye] {
            key.extend_from_slice(bytemuck::cast_slice(&v.to_array()));
        }
        key.extend_from_slice(&u.instanced_ground_cells.to_array());
        key.extend_from_slice(&u.stream.to_array());
        key
    }

    /// The block of a frame described by `desc`, as the renderer planned it (`plan`): the one
    /// place a frame is packed for the GPU.
    pub fn pack(desc: &FrameDesc, plan: &FramePlan) -> Self {
        let [w, h] = desc.viewport;
        // Every position the GPU reads is measured from the frame origin; the grids' cells
        // (trample map, streamed window) stay in world cells around the world's eye.
        let origin = Vec3::new(plan.origin[0].x, 0.0, plan.origin[0].y);
        let world_eye = desc.camera.eye;
        let cam = &desc.camera.relative_to(origin);
        let sim = &desc.simulation;
        let shading = &desc.shading;
        let (colliders, [pushing, cutting, hiding]) = collider_uniforms(&desc.colliders, origin);
        let decided = &plan.decided;
        let inst = decided.instanced;
        let streamed = plan.streamed(desc);
        let bill = decided.billboards;
        let half_field = desc.field_size * 0.5;
        // Out to the far plane, but not to an infinite one's (an application's camera).
        let reach = (half_field * GROUND_REACH).max(Vec2::splat(cam.far.min(MAX_GROUND_REACH)));
        let view_proj = cam.view_projection();
        let quality = desc.quality;
        let blade_shadow_distance = decided.blade_shadow_distance;
        let sun_near = SunCascade {
            toward_sun: shading.light_direction,
            eye: cam.eye,
            reach: shading.blade_shadow_distance.max(1.0),
            texels: quality.shadow_map_size(),
        };
        let lod = decided.lod;
        let [rasterized, splatted] = decided.buckets;
        let g = &plan.generated;
        let grid = plan.height_grid.unwrap_or_default();
        Self {
            view_proj,
            inv_view_proj: view_proj.inverse(),
            sun_view_proj: sun_view_projection(
                shading.light_direction,
                &desc.ground,
                desc.field_size,
                field_center(desc) - origin,
            ),
            sun_near_view_proj: sun_near.view_projection(),
            camera_position: cam.eye.extend(desc.time),
            gravity: sim.gravity_direction.normalize_or_zero().extend(sim.gravity_strength),
            point_gravity: (sim.point_gravity - origin).extend(sim.point_gravity_strength),
            simulation: Vec4::new(sim.step, sim.eta_decay, sim.point_gravity_blend, 0.0),
            counts: UVec4::new(plan.blade_count, desc.steps, pushing, sim.forces.bits()),
            cull: Vec4::new(
                desc.cull.orientation_threshold,
                desc.cull.frustum_tolerance,
                desc.cull.distance_max,
                desc.cull.distance_levels as f32,
            ),
            coarse_cull: Vec4::new(desc.cull.tile_margin, desc.cull.occlusion_tolerance, cam.near, cam.far),
            modes: UVec4::new(
                culling_tests(desc, decided),
                desc.winds.len() as u32,
                plan.patches_per_draw,
                flags::when(decided.shadows, flags::DRAW_SHADOWS)
                    | flags::when(decided.blade_shadows, flags::DRAW_BLADE_SHADOWS)
                    | flags::when(desc.blades.ridge, flags::DRAW_BLADE_RIDGE),
            ),
            lod: Vec4::new(lod.min_level, lod.max_level, lod.near, lod.far),
            blade_style: Vec4::new(
                desc.blades.shape.code() as f32,
                desc.blades.tip_threshold,
                0.0,
                desc.blades.min_width_pixels,
            ),
            viewport: Vec4::new(w as f32, h as f32, 1.0 / w.max(1) as f32, 1.0 / h.max(1) as f32),
            light_direction: shading.light_direction.normalize_or_zero().extend(shading.ambient),
            light_color: shading.light_color.extend(1.0),
            root_color: shading.root_color.extend(shading.color_jitter),
            tip_color: shading.tip_color.extend(1.0),
            ground_color: shading.ground_color.extend(shading.ground_water),
            sky_zenith: shading.sky_zenith.extend(1.0),
            sky_horizon: shading.sky_horizon.extend(shading.fog_density),
            shading_model: Vec4::new(
                shading.model.code() as f32,
                shading.specular,
                shading.shininess,
                shading.translucency,
            ),
            shading_extra: Vec4::new(
                shading.ambient_occlusion,
                shading.clump_variation,
                shading.clump_scale,
                blade_shadow_distance,
            ),
            ground_extent: Vec4::new(reach.x, reach.y, half_field.x, half_field.y),
            surface: match desc.ground {
                GroundShape::Sphere { center, radius } => center.extend(radius),
                GroundShape::Plane | GroundShape::Mesh => Vec4::ZERO,
            },
            instanced_grid: grid_words(&inst.grid),
            instanced_shape: shape_words(&inst.grid),
            instanced_motion: Vec4::new(inst.bend, inst.grid.sway, inst.raster_distance, 0.0),
            instanced_lod: Vec3::from(inst.lod_distances).extend(inst.splat_distance),
            instanced_lists: UVec4::from_array(g.levels.map(|l| l[0])),
            instanced_caps: UVec4::from_array(g.levels.map(|l| l[1])),
            instanced_meta: UVec4::new(inst.grid.seed, desc.technique.index(), plan.splat_scale, 0),
            instanced_ground: Vec4::new(grid.min.x, grid.min.y, grid.max.x, grid.max.y),
            instanced_ground_cells: UVec4::new(grid.cells[0], grid.cells[1], desc.ground.code(), 0),
            billboard_grid: grid_words(&bill.grid),
            billboard_shape: shape_words(&bill.grid),
            billboard_motion: Vec4::new(bill.grid.sway, bill.fade, 0.0, 0.0),
            billboard_far: Vec4::new(
                bill.one_quad_distance,
                bill.splat_distance,
                bill.depth_prepass as u32 as f32,
                bill.raster_distance,
            ),
            billboard_meta: UVec4::new(g.billboards[0], g.billboards[1], g.patch_rows[0], bill.grid.seed),
            instanced_raster: UVec4::new(g.rasterized[0], g.rasterized[1], 0, 0),
            routes: UVec4::new(splatted, rasterized, decided.casting[0], 0),
            occlusion: UVec4::new(decided.blade_occluders, plan.pyramid_size, 0, 0),
            patch_cull: UVec4::new(
                g.patch_rows[0] + g.patch_rows[1],
                g.ring_len,
                crate::instanced::patch_reach(&inst) as u32,
                crate::instanced::patch_reach(&bill.as_grid()) as u32,
            ),
            patch_bounds: Vec4::new(
                grid.span[0],
                grid.span[1],
                crate::instanced::patch_top(&inst),
                crate::instanced::patch_top(&bill.as_grid()),
            ),
            tiles: UVec4::new(plan.tiles[0], plan.tiles[1], 0, 0),
            trample: match (&desc.trample, plan.trample) {
                (Some(t), true) => trample_words(t, world_eye),
                _ => UVec4::ZERO,
            },
            mowing: UVec4::new(cutting, 0, hiding, 0),
            trample_scale: match (&desc.trample, plan.trample) {
                (Some(t), true) => Vec4::new(t.texel_size(), t.regrow, 0.0, 0.0),
                _ => Vec4::new(0.0, desc.trample.unwrap_or_default().regrow, 0.0, 0.0),
            },
            stream: streamed.map_or(UVec4::ZERO, |(_, window)| stream_words(&window, world_eye)),
            stream_reach: {
                let [soft, stiff] = desc.stiffness;
                let (hand_over, band) = streamed.map_or((0.0, 0.0), |(s, _)| (s.hand_over, s.band_start()));
                Vec4::new(hand_over, band, soft, stiff)
            },
            origin: Vec4::new(plan.origin[0].x, plan.origin[0].y, plan.origin[1].x, plan.origin[1].y),
            paint_area: plan
                .paint
                .map_or(Vec4::ZERO, |p| Vec4::new(p.min.x, p.min.y, p.per_unit.x, p.per_unit.y)),
            paint_size: plan
                .paint
                .map_or(UVec4::ZERO, |p| UVec4::new(p.size[0], p.size[1], 0, 0)),
            paint_noise: plan
                .paint
                .and_then(|p| p.noise)
                .map_or(Vec4::ZERO, |n| Vec4::new(n.scale, n.cover, n.softness, 0.0)),
            paint_tint_noise: plan
                .paint
                .and_then(|p| p.tint_noise)
                .map_or(Vec4::ZERO, |n| Vec4::new(n.scale, n.cover, n.softness, 0.0)),
            paint_tint_color: plan
                .paint
                .and_then(|p| p.tint_noise)
                .map_or(Vec4::ONE, |n| n.color.extend(1.0)),
            species_meta: species_meta(&desc.species),
            species: species_uniforms(&desc.species),
            seed_heads: seed_head_uniforms(&desc.species),
            lamp_meta: UVec4::new(desc.lamps.len().min(crate::look::MAX_LAMPS) as u32, 0, 0, 0),
            lamps: lamp_uniforms(&desc.lamps, cam.eye, origin),
            frustum: crate::tiles::frustum_planes(&view_proj),
            winds: wind_uniforms(&desc.winds),
            colliders,
            placed: desc.placement[0].to_world(),
            placed_before: desc.placement[1].to_world(),
        }
    }
}

impl FrameUniforms {
    /// The block of `scene`'s frame at time 1 stepping once, into a 640×480 target, as a
    /// device that splats would plan it (every distance reaches the GPU): what the checks of
    /// loaded inputs (the fuzz replay and fuzz targets) hold to [`FrameUniforms::first_non_finite`].
    pub fn as_loaded(scene: &crate::Scene) -> Self {
        let desc = FrameDesc::of_scene(scene, scene.field.size, (1.0, 1), [640, 480]);
        let can = RendererCan {
            splat: true,
            route: crate::quality::DrawRoute::Compute,
            rasterize: true,
            ..RendererCan::strips()
        };
        let plan = FramePlan {
            blade_count: 1000,
            ..FramePlan::of(&desc, can)
        };
        Self::pack(&desc, &plan)
    }

    /// The index (in field order) of the first float a shader reads as a number that is not
    /// finite — a NaN or infinity that would reach the GPU — or `None`. The checks of loaded
    /// inputs (the fuzz replay and fuzz targets) use this.
    pub fn first_non_finite(&self) -> Option<usize> {
        let matrices = [self.view_proj, self.sun_view_proj, self.sun_near_view_proj];
        let vectors = [
            self.camera_position,
            self.gravity,
            self.cull,
            self.lod,
            self.light_direction,
            self.shading_extra,
            self.instanced_grid,
            self.billboard_grid,
        ];
        matrices
            .iter()
            .flat_map(|m| m.to_cols_array())
            .chain(self.frustum.iter().flat_map(|v| v.to_array()))
            .chain(self.colliders.iter().flat_map(|v| v.to_array()))
            .chain(self.winds.iter().flat_map(|v| v.to_array()))
            .chain(vectors.iter().flat_map(|v| v.to_array()))
            .position(|f| !f.is_finite())
    }
}

/// The culls' tests as the frame runs them: occlusion only where something in the pyramid can
/// hide grass (`FrameDecisions::occlusion_tested`).
fn culling_tests(desc: &FrameDesc, decided: &FrameDecisions) -> u32 {
    match decided.occlusion_tested {
        true => desc.cull.bits(),
        false => desc.cull.bits() & !flags::CULL_OCCLUSION,
    }
}

/// A grid of generated grass as `instanced_grid` and `billboard_grid` hold it: x spacing, y
/// cut-off radius, z inner radius, w clump scale.
fn grid_words(g: &GridParams) -> Vec4 {
    Vec4::new(g.spacing(), g.radius, g.inner_radius, g.clump_scale)
}

/// Its items' sizes as `instanced_shape` and `billboard_shape` hold them: height min, max;
/// half-width min, max.
fn shape_words(g: &GridParams) -> Vec4 {
    Vec4::new(g.height[0], g.height[1], g.width[0], g.width[1])
}

/// The collider spheres as `FrameUniforms::colliders` holds them — the pushing ones first
/// (`counts.z` of them), then the cutters (`mowing.x`), then the hiding ones (`mowing.z`), as
/// many as fit, measured from `origin` — and the three counts.
fn collider_uniforms(c: &FrameColliders, origin: Vec3) -> ([Vec4; MAX_COLLIDERS], [u32; 3]) {
    let counts = c.packed_counts();
    let mut slots = [Vec4::ZERO; MAX_COLLIDERS];
    let lists = [&c.pushing, &c.cutting, &c.hiding];
    let spheres = lists
        .into_iter()
        .zip(counts)
        .flat_map(|(list, n)| list.iter().take(n as usize));
    for (slot, s) in slots.iter_mut().zip(spheres) {
        *slot = (s.center - origin).extend(s.radius);
    }
    (slots, counts)
}

/// The streamed field's words of the frame (`FrameUniforms::stream`): the window around `eye`.
fn stream_words(window: &crate::stream::StreamWindow, eye: Vec3) -> UVec4 {
    let base = window.base(eye);
    UVec4::new(window.tiles, crate::stream::TILE_CELLS, base.x as u32, base.y as u32)
}

/// The trample map's words of the frame (`FrameUniforms::trample`): the window around `eye`.
fn trample_words(t: &TrampleParams, eye: Vec3) -> UVec4 {
    let base = t.window_base(eye);
    UVec4::new(t.resolution, 0, base.x as u32, base.y as u32)
}

/// How many species there are.
fn species_meta(species: &[crate::species::Species]) -> UVec4 {
    let heads = species
        .iter()
        .any(|s| s.seed_heads.as_ref().is_some_and(|h| h.share > 0.0));
    UVec4::new(species.len() as u32, heads as u32, 0, 0)
}

/// The lamps that matter most to the eye at `eye` (frame space), as `FrameUniforms::lamps`
/// holds them, measured from `origin`.
fn lamp_uniforms(lamps: &[crate::look::Lamp], eye: Vec3, origin: Vec3) -> [Vec4; 3 * crate::look::MAX_LAMPS] {
    let mut out = [Vec4::ZERO; 3 * crate::look::MAX_LAMPS];
    for (k, lamp) in crate::look::nearest_lamps(lamps, eye + origin).iter().enumerate() {
        let (direction, inner, outer) = match lamp.spot {
            Some(s) => (s.direction, s.inner_cos, s.outer_cos),
            None => (Vec3::ZERO, 1.0, -2.0),
        };
        out[3 * k] = (lamp.position - origin).extend(lamp.range);
        out[3 * k + 1] = lamp.color.extend(outer);
        out[3 * k + 2] = direction.extend(inner);
    }
    out
}

/// Each species' seed heads (`FrameUniforms::seed_heads`).
fn seed_head_uniforms(species: &[crate::species::Species]) -> [Vec4; 2 * crate::species::MAX_SPECIES] {
    let mut out = [Vec4::ZERO; 2 * crate::species::MAX_SPECIES];
    for (k, s) in species.iter().take(crate::species::MAX_SPECIES).enumerate() {
        if let Some(h) = &s.seed_heads {
            let blossom = f32::from(u8::from(h.shape == crate::species::HeadShape::Blossom));
            out[2 * k] = Vec4::new(h.share, h.length, h.width, blossom);
            out[2 * k + 1] = h.color.extend(0.0);
        }
    }
    out
}

/// Each species' four vectors (`FrameUniforms::species`).
fn species_uniforms(species: &[crate::species::Species]) -> [Vec4; 4 * crate::species::MAX_SPECIES] {
    let mut out = [Vec4::ZERO; 4 * crate::species::MAX_SPECIES];
    for (k, s) in species.iter().take(crate::species::MAX_SPECIES).enumerate() {
        out[4 * k] = Vec4::new(s.height[0], s.height[1], s.width[0], s.width[1]);
        out[4 * k + 1] = Vec4::new(s.stiffness[0], s.stiffness[1], s.bend, s.weight);
        out[4 * k + 2] = s.root_color.extend(0.0);
        out[4 * k + 3] = s.tip_color.extend(0.0);
    }
    out
}

/// The middle of the grown field: the origin, or the eye's ground point where the field streams
/// (its window follows the eye).
fn field_center(desc: &FrameDesc) -> Vec3 {
    match desc.stream {
        Some(_) => Vec3::new(desc.camera.eye.x, 0.0, desc.camera.eye.z),
        None => Vec3::ZERO,
    }
}

/// The sun's orthographic view of everything that casts or receives a shadow: the grown field (or
/// planet) and a few units around it for blades and colliders. Depth in [0, 1], nearest to the sun 0.
pub fn sun_view_projection(toward_sun: Vec3, ground: &GroundShape, field_size: Vec2, field_center: Vec3) -> Mat4 {
    const ABOVE: f32 = 4.0;
    let (center, radius) = match *ground {
        GroundShape::Sphere { center, radius } => (center, radius + ABOVE),
        _ => (field_center, 0.5 * field_size.length() + ABOVE),
    };
    let dir = toward_sun.try_normalize().unwrap_or(Vec3::Y);
    let up = if dir.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
    let view = glam::camera::rh::view::look_at_mat4(center + dir * 2.0 * radius, center, up);
    glam::camera::rh::proj::directx::orthographic(-radius, radius, -radius, radius, 0.0, 4.0 * radius) * view
}

/// The sun's near cascade: an orthographic view of the ball of radius `reach` around the eye,
/// where blades cast shadows, drawn into a `texels`-wide square of the shadow map.
pub struct SunCascade {
    /// Unit direction toward the sun.
    pub toward_sun: glam::Vec3,
    /// The eye the cascade follows.
    pub eye: glam::Vec3,
    /// Radius of the ball around the eye whose blades cast shadows.
    pub reach: f32,
    /// Side of the cascade in shadow-map texels.
    pub texels: u32,
}

impl SunCascade {
    /// Casters this far above the ball toward the sun (a rolling collider) still cast into it.
    const ABOVE: f32 = 50.0;

    /// The cascade's view and projection. Its centre is snapped to whole texels of the sun's
    /// view, so the shadows of blades that stand still do not crawl as the eye moves. Depth in
    /// [0, 1], nearest to the sun 0.
    pub fn view_projection(&self) -> Mat4 {
        let dir = self.toward_sun.try_normalize().unwrap_or(Vec3::Y);
        let up = if dir.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
        // A fixed orientation (through the origin), so only the box moves with the eye.
        let view = glam::camera::rh::view::look_at_mat4(Vec3::ZERO, -dir, up);
        let texel = 2.0 * self.reach / self.texels.max(1) as f32;
        let eye = view.transform_point3(self.eye);
        let centre = (eye.truncate() / texel).round() * texel;
        let r = self.reach;
        // The view looks down -z: the eye lies -eye.z in front of the origin.
        let (near, far) = (-eye.z - r - Self::ABOVE, -eye.z + r);
        glam::camera::rh::proj::directx::orthographic(centre.x - r, centre.x + r, centre.y - r, centre.y + r, near, far)
            * view
    }
}

/// The wind fields as `FrameUniforms::winds` holds them (at most `MAX_WINDS`).
fn wind_uniforms(winds: &[Wind]) -> [Vec4; 3 * MAX_WINDS] {
    let mut out = [Vec4::ZERO; 3 * MAX_WINDS];
    for (slot, w) in out.as_chunks_mut::<3>().0.iter_mut().zip(winds) {
        slot[0] = w.direction.normalize_or_zero().extend(w.strength);
        slot[1] = Vec4::new(w.gust, w.gust_frequency, w.scale, w.speed);
        slot[2] = w.center.extend(w.kind.code() as f32);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn desc_of(scene: &crate::Scene) -> FrameDesc {
        FrameDesc::of_scene(scene, Vec2::splat(10.0), (0.5, 1), [640, 480])
    }

    #[test]
    fn an_applications_own_matrices_give_the_frame_its_camera_would() {
        let scene = crate::Scene::default();
        let cam = scene.camera;
        let plan = FramePlan::of(&desc_of(&scene), RendererCan::strips());
        let ours = FrameUniforms::pack(&desc_of(&scene), &plan);
        let theirs = desc_of(&scene).with_view_projection(cam.view(), cam.projection(640.0 / 480.0));
        let theirs = FrameUniforms::pack(&theirs, &plan);
        assert!(theirs.view_proj.abs_diff_eq(ours.view_proj, 1e-5));
        assert!(theirs.camera_position.abs_diff_eq(ours.camera_position, 1e-4));
        for (a, b) in theirs.frustum.iter().zip(&ours.frustum) {
            assert!(a.abs_diff_eq(*b, 1e-4), "{a} {b}");
        }
        assert!((theirs.coarse_cull.z - cam.near).abs() < 1e-5 && (theirs.coarse_cull.w - cam.far).abs() < 1e-2);
        // A jittered projection (a temporal antialiaser's) moves the frame by its sub-pixel offset.
        let jitter = Mat4::from_translation(Vec3::new(0.5 / 640.0, 0.0, 0.0)) * cam.projection(640.0 / 480.0);
        let jittered = FrameUniforms::pack(&desc_of(&scene).with_view_projection(cam.view(), jitter), &plan);
        let p = jittered.view_proj.project_point3(cam.target);
        let q = ours.view_proj.project_point3(cam.target);
        assert!((p.x - q.x - 0.5 / 640.0).abs() < 1e-5, "{p} {q}");
    }

    #[test]
    fn a_frame_that_splats_nothing_packs_no_splat_or_raster_distance() {
        let scene = crate::Scene {
            technique: crate::instanced::Technique::Landscape,
            ..crate::Scene::default()
        };
        let desc = desc_of(&scene);
        let can = RendererCan {
            splat: true,
            ..RendererCan::strips()
        };
        let splatting = FrameUniforms::pack(&desc, &FramePlan::of(&desc, can));
        let not = FrameUniforms::pack(&desc, &FramePlan::of(&desc, RendererCan::strips()));
        assert_eq!(splatting.instanced_lod.w, scene.instanced.splat_distance);
        assert_eq!(splatting.billboard_far.y, scene.billboard.splat_distance);
        for far in [
            not.instanced_lod.w,
            not.instanced_motion.z,
            not.billboard_far.y,
            not.billboard_far.w,
        ] {
            assert_eq!(far, f32::MAX);
        }
    }

    /// Where `p` lands in the cascade: x, y in [-1, 1] across it, z its depth.
    fn in_cascade(c: &SunCascade, p: Vec3) -> Vec3 {
        c.view_projection().project_point3(p)
    }

    #[test]
    fn the_near_cascade_holds_the_ball_around_the_eye_and_its_casters() {
        let c = SunCascade {
            toward_sun: Vec3::new(0.4, 0.8, 0.35),
            eye: Vec3::new(13.3, 1.7, -42.1),
            reach: 12.0,
            texels: 2048,
        };
        let sun = c.toward_sun.normalize();
        for dir in [Vec3::X, -Vec3::X, Vec3::Z, -Vec3::Z, Vec3::Y, -Vec3::Y] {
            let p = in_cascade(&c, c.eye + dir * 11.9);
            assert!(
                p.x.abs() <= 1.0 && p.y.abs() <= 1.0 && (0.0..=1.0).contains(&p.z),
                "{dir}: {p}"
            );
        }
        // A collider well above the ball, toward the sun, still casts into it.
        let above = in_cascade(&c, c.eye + sun * 40.0);
        assert!((0.0..=1.0).contains(&above.z), "{above}");
        // Nearer the sun is nearer 0.
        assert!(above.z < in_cascade(&c, c.eye).z);
    }

    #[test]
    fn the_near_cascade_moves_by_whole_texels() {
        let at = |eye: Vec3| SunCascade {
            toward_sun: Vec3::new(0.4, 0.8, 0.35),
            eye,
            reach: 12.0,
            texels: 2048,
        };
        let stone = Vec3::new(3.0, 0.0, 4.0);
        let eye = Vec3::new(0.0, 1.7, 0.0);
        let texel = 2.0 / 2048.0;
        for step in 1..20 {
            let moved = eye + Vec3::new(0.0137, 0.0, 0.0071) * step as f32;
            let shift = (in_cascade(&at(moved), stone) - in_cascade(&at(eye), stone)).truncate() / texel;
            // A fixed point moves across the map by whole texels (or not at all).
            assert!(
                (shift - shift.round()).abs().max_element() < 1e-2,
                "step {step}: {shift}"
            );
        }
    }
}
