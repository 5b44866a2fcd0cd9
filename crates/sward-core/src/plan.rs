//! The frame's decisions, made once: how each blade reaches the screen (the Bezier blades'
//! distance buckets drawn by the hardware, rasterized by compute or splatted; the generated
//! grass listed, rasterized or splatted), where those hand-overs fall, which shadows are cast,
//! and what the occlusion cull tests against. They follow from the frame's description
//! ([`FrameDesc`]) and what the renderer can do this frame ([`RendererCan`]), and every reader —
//! the uniforms' packing, the Vulkan renderer's recordings and generated grass, the tiles' host
//! decision, the portable renderer — reads the one [`FrameDecisions`] rather than deriving them.

use crate::billboard::BillboardParams;
use crate::commands::{self, DISTANCE_BUCKETS};
use crate::cull::LodParams;
use crate::flags;
use crate::frame::{FrameDesc, GroundShape};
use crate::instanced::InstancedParams;
use crate::quality::DrawRoute;

/// What the renderer can do this frame, as far as the frame's decisions go.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RendererCan {
    /// Splat and rasterize by compute: 64-bit atomics, and a splat target it could make.
    pub splat: bool,
    /// The route the Bezier blades are drawn by, as the device resolved it.
    pub route: DrawRoute,
    /// Let the compute rasterizer take near buckets: a splat cell per sample (1× and 4×
    /// targets; elsewhere the near blades stay strips so the picture keeps the preset's
    /// antialiasing) and not wireframe (the hardware's).
    pub rasterize: bool,
    /// A Bezier field is uploaded.
    pub bezier_field: bool,
    /// The nearest blades the last frame drew can join the depth pyramid (from an ordered list).
    pub blade_occluders: bool,
    /// This frame culls. A frame that only draws redraws the last cull's lists by the hardware:
    /// it splats and generates nothing.
    pub cull: bool,
    /// The caller gives its own depth this frame, to join the occluders (embedding).
    pub caller_depth: bool,
}

impl RendererCan {
    /// What a renderer that draws strips can do where it also splats (`splats`): the generated
    /// grass splatted and rasterized by compute, and where the frame asks for the compute route
    /// or leaves the route to the renderer (`asked`), the far Bezier buckets splatted by it (none
    /// rasterized by compute) — the portable renderer with 64-bit atomic min/max.
    pub fn splatting(self, splats: bool, asked: DrawRoute) -> RendererCan {
        let route = match asked {
            DrawRoute::Auto | DrawRoute::Compute => DrawRoute::Compute,
            _ => self.route,
        };
        match splats {
            true => RendererCan {
                splat: true,
                route,
                rasterize: false,
                ..self
            },
            false => self,
        }
    }

    /// A renderer that draws every Bezier blade as a strip and splats nothing (the portable
    /// renderer), with a field, its ordered list and a cull this frame.
    pub fn strips() -> RendererCan {
        RendererCan {
            splat: false,
            route: DrawRoute::Strips,
            rasterize: false,
            bezier_field: true,
            blade_occluders: true,
            cull: true,
            caller_depth: false,
        }
    }
}

/// Where the Bezier blades' distance buckets change hands: the first splatted, the first
/// rasterized by compute (up to the splatted), the first whose blades cast no shadow
/// (`DISTANCE_BUCKETS`: none).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BucketHandOvers {
    /// The first bucket wholly beyond the splat distance.
    pub splatted: u32,
    /// The first bucket the compute route rasterizes (the splatted one where it rasterizes none).
    pub rasterized: u32,
    /// The first bucket wholly beyond the blade-shadow distance.
    pub casting: u32,
}

impl BucketHandOvers {
    /// Which distance buckets `route` draws how: the first bucket rasterized by compute and the
    /// first splatted (`DISTANCE_BUCKETS`: none). The buckets before the first are drawn by the
    /// route's hardware path; only the compute route hands any over, and the compute rasterizer
    /// only where `rasterize` (see [`RendererCan::rasterize`]).
    pub fn split_for(&self, route: DrawRoute, rasterize: bool) -> (u32, u32) {
        match route {
            DrawRoute::Compute => {
                let splatted = self.splatted.min(DISTANCE_BUCKETS);
                let rasterized = match rasterize {
                    true => self.rasterized.min(splatted),
                    false => splatted,
                };
                (rasterized, splatted)
            }
            _ => (DISTANCE_BUCKETS, DISTANCE_BUCKETS),
        }
    }
}

/// Everything a frame decides from its description and the renderer's abilities.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameDecisions {
    /// The level of detail as the quality preset scales it.
    pub lod: LodParams,
    /// The instanced grass as this frame draws it: the compute rasterizer taking over where the
    /// lens puts it (`instanced::raster_from`), and neither splats nor the compute rasterizer
    /// where the frame splats nothing.
    pub instanced: InstancedParams,
    /// The billboards as this frame draws them (splats as for the instanced grass).
    pub billboards: BillboardParams,
    /// Anything may be splatted or rasterized by compute this frame.
    pub splats: bool,
    /// The generated grass (instanced blades, billboards) is made this frame.
    pub generates: bool,
    /// The grids the generated grass is made on this frame: the instanced grass's, the
    /// billboards' (each where the technique draws it, in a frame that generates).
    pub grids: [bool; 2],
    /// The generated grass is splatted or rasterized by compute somewhere within its reach.
    pub generated_splats: bool,
    /// Instanced blades are rasterized by compute (the hand-over short of the splat distance
    /// and the cut-off).
    pub blades_rasterized: bool,
    /// Billboards are rasterized by compute (short of their splat distance).
    pub billboards_rasterized: bool,
    /// Where the Bezier blades' buckets change hands: the first rasterized by compute, the
    /// first splatted (`DISTANCE_BUCKETS`: none).
    pub buckets: [u32; 2],
    /// Bezier blades are rasterized or splatted by compute (a field, and buckets handed over).
    pub bezier_splats: bool,
    /// The splat target is needed this frame.
    pub splatting: bool,
    /// The sun's shadow map is drawn.
    pub shadows: bool,
    /// Blades near the eye cast shadows into the sun's near cascade.
    pub blade_shadows: bool,
    /// How far from the eye blades cast shadows (0 where they cast none).
    pub blade_shadow_distance: f32,
    /// The first Bezier bucket wholly beyond the blade shadows' reach, and how many of the
    /// instanced grass's levels begin within it.
    pub casting: [u32; 2],
    /// How many of the nearest blades the last frame drew join the depth pyramid.
    pub blade_occluders: u32,
    /// The depth pyramid is drawn with this frame's occluders: where the cull tests occlusion.
    /// It is drawn even where nothing in it can hide grass (`occlusion_tested` false): on the
    /// H200 the frame took 0.2 ms longer without it, the shadow map's kept ground then copied
    /// in first and slower (BENCHMARKS.md, "The occlusion test only where something occludes").
    pub depth_pyramid: bool,
    /// The culls test occlusion against the depth pyramid: where it is drawn and something can
    /// hide grass (`anything_occludes`).
    pub occlusion_tested: bool,
}

impl FrameDecisions {
    /// Decide the frame `desc` describes, drawn by a renderer that can do what `can` says.
    pub fn of(desc: &FrameDesc, can: RendererCan) -> FrameDecisions {
        let lod = desc.quality.apply_to_lod(&desc.lod);
        let blade_shadows = blade_shadows(desc);
        let blade_shadow_distance = match blade_shadows {
            true => desc.shading.blade_shadow_distance,
            false => 0.0,
        };
        let hand_overs = hand_overs(desc, &lod, blade_shadow_distance);
        let (instanced, billboards) = (
            instanced_as_drawn(desc, can.splat),
            billboards_as_drawn(desc, can.splat),
        );
        let generates = desc.generates() && can.cull;
        let technique_grids = [desc.technique.draws_instanced(), desc.technique.draws_billboards()];
        let generated_splats = (technique_grids[0]
            && instanced.splat_distance.min(instanced.raster_distance) < instanced.grid.radius)
            || (technique_grids[1]
                && billboards.splat_distance.min(billboards.raster_distance) < billboards.grid.radius);
        // Splats and compute-rasterized blades are made after this frame's cull.
        let buckets = match can.splat && can.cull {
            true => hand_overs.split_for(can.route, can.rasterize).into(),
            false => [DISTANCE_BUCKETS; 2],
        };
        let bezier_splats = can.bezier_field && buckets[0] < DISTANCE_BUCKETS;
        let occlusion = desc.cull.bits() & flags::CULL_OCCLUSION != 0;
        let depth_pyramid = (can.bezier_field || generates) && can.cull && occlusion;
        FrameDecisions {
            lod,
            instanced,
            billboards,
            splats: can.splat,
            generates,
            grids: technique_grids.map(|on| on && generates),
            generated_splats,
            blades_rasterized: instanced.raster_distance < instanced.splat_distance.min(instanced.grid.radius),
            billboards_rasterized: billboards.raster_distance < billboards.splat_distance,
            buckets,
            bezier_splats,
            splatting: can.cull && ((generates && generated_splats) || bezier_splats),
            shadows: desc.shading.shadows,
            blade_shadows,
            blade_shadow_distance,
            casting: [hand_overs.casting, casting_levels(desc, blade_shadow_distance)],
            blade_occluders: match can.blade_occluders {
                true => desc.blade_occluders(),
                false => 0,
            },
            depth_pyramid,
            occlusion_tested: depth_pyramid && anything_occludes(desc, can),
        }
    }

    /// The sun's direction toward the scene where blades cast shadows (the tiles that may cast
    /// into the near cascade are kept), else none.
    pub fn toward_sun(&self, desc: &FrameDesc) -> Option<glam::Vec3> {
        self.blade_shadows
            .then(|| desc.shading.light_direction.normalize_or_zero())
    }
}

/// Whether anything the depth pyramid holds can hide grass from the eye: ground with relief or
/// a horizon (a mesh, a planet), a collider, the nearest blades the last frame drew, the
/// caller's own depth. A plane seen from above hides nothing standing on it, so the meadow's
/// generated grass culls nothing by occlusion, and its patches' test against the pyramid is
/// spared (on the H200 0.15 ms of the instanced grass's generating at 2^26 candidates). The
/// pictures are the same: occlusion only spares work.
fn anything_occludes(desc: &FrameDesc, can: RendererCan) -> bool {
    let ground = match desc.ground {
        GroundShape::Plane => desc.camera.eye.y < 0.0,
        GroundShape::Sphere { .. } | GroundShape::Mesh => true,
    };
    let c = &desc.colliders;
    let colliders = !(c.pushing.is_empty() && c.cutting.is_empty() && c.hiding.is_empty());
    let blades = can.bezier_field && can.blade_occluders && desc.blade_occluders() > 0;
    ground || colliders || blades || can.caller_depth
}

/// Whether blades near the eye cast shadows into the sun's near cascade.
fn blade_shadows(desc: &FrameDesc) -> bool {
    let s = &desc.shading;
    s.shadows && s.blade_shadows.at(desc.quality) && s.blade_shadow_distance > 0.0
}

/// Where the Bezier blades' distance buckets change hands, as the lod and the shadows say.
fn hand_overs(desc: &FrameDesc, lod: &LodParams, blade_shadow_distance: f32) -> BucketHandOvers {
    let range = commands::bucket_range(lod.far, desc.cull.distance_max);
    let splatted = commands::first_bucket_beyond(range, lod.splat_distance);
    let rasterized = match lod.compute_raster {
        true => commands::first_bucket_beyond(range, lod.strip_distance).min(splatted),
        false => splatted,
    };
    BucketHandOvers {
        splatted,
        rasterized,
        casting: commands::first_bucket_beyond(range, blade_shadow_distance),
    }
}

/// The instanced grass as a frame that may splat (`splats`) or not draws it.
fn instanced_as_drawn(desc: &FrameDesc, splats: bool) -> InstancedParams {
    let mut p = desc.instanced;
    p.raster_distance = crate::instanced::raster_from(&p, desc.camera.focal);
    if !splats {
        (p.splat_distance, p.raster_distance) = (f32::MAX, f32::MAX);
    }
    p
}

/// The billboards as a frame that may splat (`splats`) or not draws them.
fn billboards_as_drawn(desc: &FrameDesc, splats: bool) -> BillboardParams {
    let mut p = desc.billboard;
    if !splats {
        (p.splat_distance, p.raster_distance) = (f32::MAX, f32::MAX);
    }
    p
}

/// How many of the instanced grass's levels begin within the blade shadows' reach (they cast
/// into the sun's near cascade).
fn casting_levels(desc: &FrameDesc, reach: f32) -> u32 {
    1 + desc
        .instanced
        .lod_distances
        .iter()
        .filter(|&&start| start < reach)
        .count() as u32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::instanced::Technique;
    use crate::scene::Scene;
    use glam::Vec2;

    fn compute_route() -> RendererCan {
        RendererCan {
            splat: true,
            route: DrawRoute::Compute,
            rasterize: true,
            ..RendererCan::strips()
        }
    }

    #[test]
    fn a_frame_without_splats_neither_splats_nor_rasterizes_generated_grass() {
        let mut scene = Scene {
            technique: Technique::Landscape,
            ..Scene::default()
        };
        scene.instanced.raster_distance = 1.0;
        scene.billboard.raster_distance = 1.0;
        let desc = FrameDesc::of_scene(&scene, Vec2::splat(10.0), (0.0, 0), [320, 240]);
        let with = FrameDecisions::of(&desc, compute_route());
        assert!(with.generated_splats && with.billboards_rasterized && with.splatting);
        let without = FrameDecisions::of(
            &desc,
            RendererCan {
                splat: false,
                ..compute_route()
            },
        );
        assert!(!without.generated_splats && !without.splatting);
        assert!(!without.blades_rasterized && !without.billboards_rasterized);
        assert_eq!(without.buckets, [DISTANCE_BUCKETS; 2]);
    }

    #[test]
    fn occlusion_is_tested_only_where_something_can_hide_the_grass() {
        let scene = Scene {
            technique: Technique::Instanced,
            ..Scene::default()
        };
        let plane = FrameDesc::of_scene(&scene, Vec2::splat(10.0), (0.0, 0), [320, 240]);
        let generated = RendererCan {
            bezier_field: false,
            ..compute_route()
        };
        let pyramid = |desc: &FrameDesc, can: RendererCan| FrameDecisions::of(desc, can).occlusion_tested;
        assert!(!pyramid(&plane, generated), "a plane seen from above hid grass");
        assert!(
            FrameDecisions::of(&plane, generated).depth_pyramid,
            "the pyramid is not drawn"
        );
        let mut below = plane.clone();
        below.camera.eye.y = -1.0;
        let mut planet = plane.clone();
        planet.ground = GroundShape::Sphere {
            center: glam::Vec3::new(0.0, -100.0, 0.0),
            radius: 100.0,
        };
        let mut mesh = plane.clone();
        mesh.ground = GroundShape::Mesh;
        let mut hidden = plane.clone();
        hidden.colliders.hiding.push(crate::frame::Sphere {
            center: glam::Vec3::ONE,
            radius: 1.0,
        });
        for (what, desc) in [
            ("below the plane", &below),
            ("a planet", &planet),
            ("a mesh", &mesh),
            ("a sphere", &hidden),
        ] {
            assert!(pyramid(desc, generated), "{what} hid no grass");
        }
        let caller = RendererCan {
            caller_depth: true,
            ..generated
        };
        assert!(pyramid(&plane, caller), "the caller's depth hid no grass");
        // The Bezier field's nearest blades hide grass, where the scene lets them.
        assert!(pyramid(&plane, compute_route()), "the nearest blades hid no grass");
        let mut no_blades = plane.clone();
        no_blades.cull.blade_occluders = crate::cull::BladeOccluders::Count(0);
        assert!(
            !pyramid(&no_blades, compute_route()),
            "a plane with no blade occluders hid grass"
        );
        // Where occlusion is not tested the cull skips the pyramid; where it is, it reads it.
        let tests = crate::gpu::FrameUniforms::pack(&plane, &crate::gpu::FramePlan::of(&plane, generated))
            .modes
            .x;
        assert_eq!(tests & flags::CULL_OCCLUSION, 0, "the cull tests occlusion on a plane");
        let tests = crate::gpu::FrameUniforms::pack(&mesh, &crate::gpu::FramePlan::of(&mesh, generated))
            .modes
            .x;
        assert_ne!(
            tests & flags::CULL_OCCLUSION,
            0,
            "the cull skips the pyramid where the ground has relief"
        );
    }

    #[test]
    fn a_frame_that_only_draws_generates_and_splats_nothing() {
        let scene = Scene {
            technique: Technique::Landscape,
            ..Scene::default()
        };
        let desc = FrameDesc::of_scene(&scene, Vec2::splat(10.0), (0.0, 0), [320, 240]);
        let culled = FrameDecisions::of(&desc, compute_route());
        assert!(culled.generates && culled.splatting && culled.depth_pyramid && culled.occlusion_tested);
        let drawn = FrameDecisions::of(
            &desc,
            RendererCan {
                cull: false,
                ..compute_route()
            },
        );
        assert!(!drawn.generates && !drawn.splatting && !drawn.depth_pyramid && !drawn.occlusion_tested);
        assert_eq!(drawn.buckets, [DISTANCE_BUCKETS; 2]);
    }

    #[test]
    fn blade_shadows_reach_the_buckets_and_levels_they_say() {
        let mut scene = Scene::default();
        scene.shading.shadows = true;
        scene.shading.blade_shadows = crate::look::BladeShadows::On;
        scene.shading.blade_shadow_distance = 8.0;
        let desc = FrameDesc::of_scene(&scene, Vec2::splat(10.0), (0.0, 0), [320, 240]);
        let on = FrameDecisions::of(&desc, RendererCan::strips());
        assert!(on.shadows && on.blade_shadows && on.toward_sun(&desc).is_some());
        assert_eq!(on.blade_shadow_distance, 8.0);
        assert!(
            on.casting[0] > 0 && on.casting[0] < DISTANCE_BUCKETS,
            "{:?}",
            on.casting
        );
        scene.shading.shadows = false;
        let desc = FrameDesc::of_scene(&scene, Vec2::splat(10.0), (0.0, 0), [320, 240]);
        let off = FrameDecisions::of(&desc, RendererCan::strips());
        assert!(!off.blade_shadows && off.toward_sun(&desc).is_none());
        assert_eq!((off.blade_shadow_distance, off.casting), (0.0, [0, 1]));
    }

    #[test]
    fn only_the_compute_route_leaves_buckets_to_compute_and_never_past_its_splats() {
        let mut hand_overs = BucketHandOvers {
            splatted: 40,
            rasterized: 10,
            casting: 0,
        };
        assert_eq!(hand_overs.split_for(DrawRoute::Compute, true), (10, 40));
        // Without a cell per sample (2×, 8×) strips reach the splats.
        assert_eq!(hand_overs.split_for(DrawRoute::Compute, false), (40, 40));
        hand_overs.rasterized = 50;
        assert_eq!(hand_overs.split_for(DrawRoute::Compute, true), (40, 40));
        for route in [DrawRoute::Tessellation, DrawRoute::Strips, DrawRoute::Mesh] {
            assert_eq!(hand_overs.split_for(route, true), (DISTANCE_BUCKETS, DISTANCE_BUCKETS));
        }
    }
}
