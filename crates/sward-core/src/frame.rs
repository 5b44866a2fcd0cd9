//! A frame's description: everything the renderer is told each frame, as typed values — the
//! technique, the camera, the clock, the winds and colliders where they are now, each
//! subsystem's settings, and the route and quality decisions. Whoever drives sward builds one
//! (the viewer, `render`, `bench`, `soak`, an application embedding it); the renderer packs it
//! into the block the shaders read once ([`crate::gpu::FrameUniforms::pack`]), write-only, and
//! decides what may be replayed from its named parts. Nothing here knows the GPU's layout.

use glam::{Mat4, Vec2, Vec3};

use crate::billboard::BillboardParams;
use crate::camera::Camera;
use crate::cull::{BladeOccluders, CullParams, LodParams};
use crate::instanced::{InstancedParams, Technique};
use crate::look::{BladeStyle, Shading};
use crate::physics::{travel, SimParams, MAX_COLLIDERS};
use crate::quality::{DrawRoute, QualityPreset};
use crate::scene::{Scene, Surface};
use crate::stream::StreamWindow;
use crate::trample::TrampleParams;
use crate::wind::Wind;

/// Views of one frame that each cull the grass for their own camera (split screen, a minimap):
/// view 0 steps the grass, the others cull and draw what it stepped. Both renderers and the
/// Bevy plugin hold to it.
pub const VIEWS_PER_FRAME: usize = 4;

/// The eye a frame is seen from: its place, its view and projection (Vulkan clip space: depth
/// 0 at `near`, 1 at `far`, y down), and the lens's scale in pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameCamera {
    /// Eye position, world space.
    pub eye: Vec3,
    /// World to view space (right-handed, looking down −z).
    pub view: Mat4,
    /// View to clip space.
    pub projection: Mat4,
    /// Near clip distance.
    pub near: f32,
    /// Far clip distance.
    pub far: f32,
    /// Pixels per unit at unit depth on the frame's target.
    pub focal: f32,
}

impl FrameCamera {
    /// `camera` on a target of `viewport` pixels.
    pub fn from_camera(camera: &Camera, [width, height]: [u32; 2]) -> FrameCamera {
        FrameCamera {
            eye: camera.position,
            view: camera.view(),
            projection: camera.projection(width as f32 / height.max(1) as f32),
            near: camera.near,
            far: camera.far,
            focal: camera.focal(height),
        }
    }

    /// The same eye with positions measured from `origin` (the frame origin of a streamed field,
    /// `stream::frame_origin`): the eye less the origin, and the view rebuilt around it rather
    /// than composed with a translation, so the frame's numbers near the eye are as fine as at
    /// the world's origin. The view must be rigid (a rotation and a translation), as a camera's is.
    pub fn relative_to(&self, origin: Vec3) -> FrameCamera {
        if origin == Vec3::ZERO {
            return *self;
        }
        let eye = self.eye - origin;
        let mut view = self.view;
        view.w_axis = (-(glam::Mat3::from_mat4(self.view) * eye)).extend(1.0);
        FrameCamera { eye, view, ..*self }
    }

    /// An application's own `view` and `projection` on a target `height` pixels tall. The
    /// projection must map view space as sward's does — right-handed, depth 0 at the near plane
    /// and 1 at the far, y down in normalised device coordinates (as [`Camera::projection`]
    /// makes it); near, far and the lens are read from it.
    pub fn from_matrices(view: Mat4, projection: Mat4, height: u32) -> FrameCamera {
        // A perspective with depth 0..1: z' = a z + b, w' = −z, so near = b / a, far = b / (a + 1).
        let (a, b) = (projection.z_axis.z, projection.w_axis.z);
        let far = if (a + 1.0).abs() > 1e-12 {
            b / (a + 1.0)
        } else {
            f32::MAX
        };
        FrameCamera {
            eye: view.inverse().w_axis.truncate(),
            view,
            projection,
            near: b / a,
            far,
            focal: 0.5 * height as f32 * projection.y_axis.y.abs(),
        }
    }

    /// World to clip space: `projection · view`.
    pub fn view_projection(&self) -> Mat4 {
        self.projection * self.view
    }
}

/// A collider sphere where it is this frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre, world space.
    pub center: Vec3,
    /// Radius.
    pub radius: f32,
}

/// The frame's collider spheres: those that push blades aside (spheres and the spheres packed
/// into mesh bodies), the cutters that mow them, and those that only hide grass. The GPU holds
/// `MAX_COLLIDERS` in all: the pushing ones first, then the cutters, then the hiding ones.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrameColliders {
    /// Spheres that push blades aside.
    pub pushing: Vec<Sphere>,
    /// Spheres that mow the grass under them.
    pub cutting: Vec<Sphere>,
    /// Spheres that only hide the grass behind them from the cull: an application's meshes
    /// (a house, a rock) packed into spheres inside them, which the application draws itself.
    /// They are drawn into the depth pyramid alone: they neither press nor mow the grass, and
    /// sward neither draws them nor casts their shadows.
    pub hiding: Vec<Sphere>,
}

impl FrameColliders {
    /// `scene`'s colliders at time `t`: its spheres where their paths take them, then the
    /// spheres of each body; its cutters apart.
    pub fn of_scene(scene: &Scene, t: f32) -> FrameColliders {
        let sphere = |c: &crate::Collider| Sphere {
            center: travel(c.center, &c.path, c.speed, t),
            radius: c.radius,
        };
        let bodies = scene
            .bodies
            .iter()
            .flat_map(|b| b.spheres_at(t, &scene.contents))
            .map(|s| Sphere {
                center: s.truncate(),
                radius: s.w,
            });
        FrameColliders {
            pushing: scene
                .colliders
                .iter()
                .filter(|c| !c.cut)
                .map(sphere)
                .chain(bodies)
                .collect(),
            cutting: scene.colliders.iter().filter(|c| c.cut).map(sphere).collect(),
            hiding: Vec::new(),
        }
    }

    /// Add `other`'s spheres to each of these lists (an application's colliders beside the
    /// scene's).
    pub fn extend_from(&mut self, other: &FrameColliders) {
        self.pushing.extend_from_slice(&other.pushing);
        self.cutting.extend_from_slice(&other.cutting);
        self.hiding.extend_from_slice(&other.hiding);
    }

    /// How many pushing, cutting and hiding spheres the GPU's block holds: the pushing ones
    /// first, then the cutters, then the hiding ones, `MAX_COLLIDERS` in all (what presses the
    /// grass goes before what only spares the GPU work).
    pub fn packed_counts(&self) -> [u32; 3] {
        packed_counts([self.pushing.len(), self.cutting.len(), self.hiding.len()]).map(|n| n as u32)
    }
}

/// How many of `asked` pushing, cutting and hiding spheres the GPU's block holds, in that order
/// of precedence, `MAX_COLLIDERS` in all ([`FrameColliders::packed_counts`]).
pub fn packed_counts(asked: [usize; 3]) -> [usize; 3] {
    let [pushing, cutting, hiding] = asked;
    let pushing = pushing.min(MAX_COLLIDERS);
    let cutting = cutting.min(MAX_COLLIDERS - pushing);
    let hiding = hiding.min(MAX_COLLIDERS - pushing - cutting);
    [pushing, cutting, hiding]
}

/// The shape of the ground the shaders draw and place generated grass on.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum GroundShape {
    /// The plane y = 0.
    #[default]
    Plane,
    /// A sphere (a planet).
    Sphere {
        /// Centre.
        center: Vec3,
        /// Radius.
        radius: f32,
    },
    /// The uploaded ground mesh (terrain, a height map, any mesh).
    Mesh,
}

impl GroundShape {
    /// The shape's number as the shaders read it (`flags::GROUND_*`).
    pub fn code(self) -> u32 {
        match self {
            GroundShape::Plane => crate::flags::GROUND_PLANE,
            GroundShape::Sphere { .. } => crate::flags::GROUND_SPHERE,
            GroundShape::Mesh => crate::flags::GROUND_MESH,
        }
    }

    /// The shape the shaders draw for `surface`.
    pub fn of(surface: &Surface) -> GroundShape {
        match surface {
            Surface::Plane => GroundShape::Plane,
            Surface::Sphere { center, radius } => GroundShape::Sphere {
                center: *center,
                radius: *radius,
            },
            Surface::Terrain { .. } | Surface::Mesh { .. } | Surface::Heightmap { .. } => GroundShape::Mesh,
        }
    }
}

/// A frame: what to draw, from where, when, and how.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameDesc {
    /// Bezier blades, generated grass, or the chain of both.
    pub technique: Technique,
    /// The eye.
    pub camera: FrameCamera,
    /// Simulated time of the frame's first step.
    pub time: f32,
    /// Fixed steps to simulate this frame (0: the blades stand as they are).
    pub steps: u32,
    /// The target's size in pixels.
    pub viewport: [u32; 2],
    /// Forces, gravity and the fixed step.
    pub simulation: SimParams,
    /// The wind fields, summed (the GPU holds `MAX_WINDS`).
    pub winds: Vec<Wind>,
    /// The collider spheres where they are this frame.
    pub colliders: FrameColliders,
    /// Which culling tests run, and their thresholds (`blade_occluders` resolved to a count).
    pub cull: CullParams,
    /// Level of detail and the compute route's hand-overs, before the quality preset scales them.
    pub lod: LodParams,
    /// The Bezier blades' shape.
    pub blades: BladeStyle,
    /// Light, colours, shadows and fog.
    pub shading: Shading,
    /// The instanced grass.
    pub instanced: InstancedParams,
    /// The billboards.
    pub billboard: BillboardParams,
    /// The trample map, where it runs.
    pub trample: Option<TrampleParams>,
    /// How much is spent per pixel and per blade.
    pub quality: QualityPreset,
    /// How the Bezier blades reach the screen (`Auto`: per device).
    pub route: DrawRoute,
    /// The ground's shape.
    pub ground: GroundShape,
    /// Width and depth of the grown field (the sun's field cascade, the ground's reach).
    pub field_size: Vec2,
    /// Where the Bezier field streams around the eye (`field.stream`).
    pub stream: Option<FrameStream>,
    /// The grass's stiffness range (`field.stiffness`): what a blade made from the instanced
    /// grass's grid gets by its cell's hash — a streamed Bezier blade, and the generated blade
    /// that stands as such a blade settles in the frame's gravity and wind.
    pub stiffness: [f32; 2],
    /// The kinds of grass (`[[species]]`; empty: one kind, from the values above).
    pub species: Vec<crate::species::Species>,
    /// Lights besides the sun (point and spot lights; none from a scene file): the
    /// `look::MAX_LAMPS` that matter most to the eye light the grass and the ground.
    pub lamps: Vec<crate::look::Lamp>,
    /// Where the field stands in the application's world this frame and the last
    /// ([`FrameDesc::placed`]): everything above is in the field's own space.
    pub placement: [crate::placement::Placement; 2],
}

/// The streamed field's part of a frame (`stream.rs`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameStream {
    /// The window of tiles.
    pub window: StreamWindow,
    /// Bezier blades nearer the eye than this are drawn, the instanced grass beyond.
    pub hand_over: f32,
    /// Whether the instanced grass takes over there: then over the last `HAND_OVER_BAND` before
    /// the hand-over each Bezier blade eases into its instanced twin's shape, so the twin takes
    /// over a blade the same in every way.
    pub twins: bool,
}

impl FrameStream {
    /// The share of the hand-over radius over which a Bezier blade eases into its twin.
    pub const HAND_OVER_BAND: f32 = 0.15;

    /// The streamed part of a frame of `scene`, where its field streams.
    pub fn of_scene(scene: &Scene) -> Option<FrameStream> {
        scene.stream_window().map(|window| FrameStream {
            window,
            hand_over: scene.hand_over(),
            twins: scene.technique.draws_instanced(),
        })
    }

    /// Where the easing into the twin's shape begins (the hand-over itself without twins).
    pub fn band_start(&self) -> f32 {
        if self.twins {
            self.hand_over * (1.0 - Self::HAND_OVER_BAND)
        } else {
            self.hand_over
        }
    }
}

impl FrameDesc {
    /// A frame of `scene` over a field `field_size` wide, at simulated `time`, stepping `steps`
    /// fixed steps, into a target of `viewport` pixels, seen by the scene's camera.
    pub fn of_scene(scene: &Scene, field_size: Vec2, (time, steps): (f32, u32), viewport: [u32; 2]) -> FrameDesc {
        let density = scene.bezier_blades() as f32 / field_size.x.max(1e-6) / field_size.y.max(1e-6);
        let stream = FrameStream::of_scene(scene);
        let cull = CullParams {
            blade_occluders: BladeOccluders::Count(scene.cull.blade_occluders.resolve(density)),
            // A streamed field's blades are drawn up to the hand-over: its distance buckets span that.
            distance_max: stream.map_or(scene.cull.distance_max, |s| s.hand_over),
            ..scene.cull
        };
        // With species the generated grass's ranges are theirs: its bounds hold every kind.
        let mut instanced = scene.instanced;
        let mut stiffness = scene.field.stiffness;
        if let Some(all) = crate::species::envelope(&scene.species) {
            instanced.grid.height = all.height;
            instanced.grid.width = all.width;
            instanced.bend = all.bend;
            stiffness = all.stiffness;
        }
        FrameDesc {
            technique: scene.technique,
            camera: FrameCamera::from_camera(&scene.camera, viewport),
            time,
            steps,
            viewport,
            simulation: scene.simulation,
            winds: scene.wind.0.clone(),
            colliders: FrameColliders::of_scene(scene, time),
            cull,
            lod: scene.lod,
            blades: scene.blades,
            shading: scene.shading,
            instanced,
            billboard: scene.billboard,
            trample: scene.tramples().then_some(scene.trample),
            quality: scene.quality.preset,
            route: scene.quality.route,
            ground: GroundShape::of(&scene.surface),
            field_size,
            stream,
            stiffness,
            species: scene.species.clone(),
            lamps: Vec::new(),
            placement: Default::default(),
        }
    }

    /// The frame seen through an application's own `view` and `projection` instead of the
    /// scene's camera (a jittered, off-centre or otherwise its own perspective; see
    /// [`FrameCamera::from_matrices`]). The frustum, the eye and all that follows them move
    /// with it — the sun's near cascade and the trample map's window too.
    pub fn with_view_projection(mut self, view: Mat4, projection: Mat4) -> FrameDesc {
        self.camera = FrameCamera::from_matrices(view, projection, self.viewport[1]);
        self
    }

    /// How many of the nearest blades the last frame drew go into the depth pyramid: the count
    /// `of_scene` resolved from the field's density (`Auto` in a description made otherwise:
    /// the floor, `BladeOccluders::AUTO_FLOOR`).
    pub fn blade_occluders(&self) -> u32 {
        self.cull.blade_occluders.resolve(0.0)
    }

    /// Whether the instanced grass or the billboards are generated.
    pub fn generates(&self) -> bool {
        self.technique.draws_instanced() || self.technique.draws_billboards()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_applications_own_matrices_give_the_camera_the_scene_would() {
        let cam = Camera::default();
        let ours = FrameCamera::from_camera(&cam, [640, 480]);
        let theirs = FrameCamera::from_matrices(cam.view(), cam.projection(640.0 / 480.0), 480);
        assert!(theirs.eye.abs_diff_eq(ours.eye, 1e-4), "{} {}", theirs.eye, ours.eye);
        assert!((theirs.near - ours.near).abs() < 1e-5 && (theirs.far - ours.far).abs() < 1e-2);
        assert!(
            (theirs.focal - ours.focal).abs() < 1e-3,
            "{} {}",
            theirs.focal,
            ours.focal
        );
        assert!(theirs.view_projection().abs_diff_eq(ours.view_projection(), 1e-6));
    }

    #[test]
    fn colliders_keep_pushing_and_cutting_apart() {
        let mut scene = Scene::default();
        let mut cutter = crate::Collider::sphere(Vec3::new(1.0, 0.0, 0.0), 0.5);
        cutter.cut = true;
        scene.colliders = vec![crate::Collider::sphere(Vec3::ZERO, 1.0), cutter];
        let c = FrameColliders::of_scene(&scene, 0.0);
        assert_eq!((c.pushing.len(), c.cutting.len()), (1, 1));
        assert_eq!(c.cutting[0].center, Vec3::new(1.0, 0.0, 0.0));
    }
}
