//! What a Bevy app puts in its world: the [`Grass`] (a sward scene: the field, its wind, its
//! look, its physics) and the [`GrassCollider`]s that press and cut it.

use std::path::Path;

use bevy::camera::visibility::Visibility;
use bevy::ecs::prelude::*;
use bevy::math::{Vec3, Vec4};
use bevy::mesh::{Indices, Mesh, VertexAttributeValues};
use bevy::prelude::ReflectDefault;
use sward_core::{Scene, SceneError};

use crate::lighting::GrassLighting;

/// A field of sward's grass: a whole sward scene (field, surface, winds, physics, culling, LOD,
/// shading, quality), in the space its `Transform` places (moves, turns and scales — by its
/// largest scale, the same along every axis — while the game runs; the blades ride along,
/// trails and all). Any number of fields may stand in a world, each with its own scene, kinds
/// of grass and paint; the colliders press them all, and the world's gravity, wind and lights
/// are the same for each. Change `scene` from any system: the next frame draws with it, and a
/// changed field or surface is grown and uploaded again. The scene's camera is not used:
/// Bevy's camera sees the grass, and Bevy's lights light it (`lighting`). Like a Bevy mesh it
/// has a `Visibility` (hidden grass is neither drawn nor simulated) and may have
/// `RenderLayers` (a camera sees it where their layers meet).
#[derive(Component, Clone, Debug, bevy::reflect::Reflect)]
#[reflect(Component, Clone, Default)]
#[require(Visibility, bevy::transform::components::Transform, crate::GrassSampling)]
pub struct Grass {
    /// Every parameter of the grass.
    pub scene: Scene,
    /// What lights it: Bevy's lights, exposure and fog (the default), or the scene's own sun.
    pub lighting: GrassLighting,
    /// How far from the camera the far grass (the generated levels and the billboards) casts
    /// into Bevy's shadow maps, in world units (default [`Grass::SHADOW_DISTANCE`]): past it a
    /// blade's shadow is smaller than a texel of the sun's far cascades, and casting it costs
    /// every cascade its draw. Blades thin out of the shadow maps over its last fifth, so the
    /// edge does not follow the eye as a line. The Bezier blades near the eye always cast. A
    /// value below 0, or not a number, casts nothing and is said once as a warning. Each value
    /// makes the shadow pipelines again: set it, do not animate it.
    pub shadow_distance: f32,
}

impl Grass {
    /// How far from the camera the far grass casts shadows unless told otherwise.
    pub const SHADOW_DISTANCE: f32 = 40.0;

    /// Grass as `scene` describes it (checked: a scene that fails validation is an error).
    pub fn new(scene: Scene) -> Result<Grass, SceneError> {
        scene.validate("Grass")?;
        Ok(Grass::validated(scene))
    }

    /// Grass of a scene already validated (a loaded [`GrassScene`](crate::GrassScene)).
    pub(crate) fn validated(scene: Scene) -> Grass {
        Grass {
            scene,
            lighting: GrassLighting::default(),
            shadow_distance: Grass::SHADOW_DISTANCE,
        }
    }

    /// Paint `stroke` over the grass from the next frame on (`Stroke::circle(xz, 2.0).mow(0.3)`:
    /// clear, mow, burn, regrow, a density, a kind of grass or a tint, over a circle or along a
    /// path, with a softness and a strength), lasting until painted over. The generated grass
    /// and the billboards take it as it is, trails and all; a streamed field of Bezier blades
    /// (every preset's) makes the tiles under it anew, every other tile's blades keeping their
    /// poses and trails; Bezier blades grown once (not streamed) grow again, as a change to
    /// `[paint]` grows them. A stroke naming a kind of
    /// grass the scene does not list paints nothing but what else it names. The strokes are
    /// the scene's edits (`Scene::edits`), merged into the paint they change every
    /// `MERGE_AFTER` of them (sward_core::paint_edits): a thousand cost what one does.
    pub fn paint(&mut self, stroke: sward_core::paint::Stroke) -> &mut Grass {
        self.scene.edits.paint(stroke);
        self
    }

    /// Grass from a scene file (`scenes/meadow.toml`, say), read from the working directory;
    /// a game loads it as an asset instead ([`GrassSource`](crate::GrassSource)).
    pub fn load(path: impl AsRef<Path>) -> Result<Grass, SceneError> {
        Grass::new(Scene::load(path.as_ref())?)
    }
}

impl Default for Grass {
    /// The default scene's grass (`Scene::default()`: the course set-up, 2^13 Bezier blades on
    /// a 15 × 15 plane), as an inspector or a Bevy scene's entity builds one.
    fn default() -> Self {
        Grass::validated(Scene::default())
    }
}

/// An entity that presses the grass aside (or, [`GrassCollider::cutting`], mows it) as sward's
/// colliders do: spheres in the entity's own space, placed each frame by its `GlobalTransform`
/// (scaled by its largest scale). A ball is one sphere; a mesh is packed into spheres as
/// sward's mesh bodies are. Every field's scene colliders and the app's share the GPU's 128
/// spheres: those past them, and any that is not a sphere (a centre not finite, a radius below
/// 0 or not a number), are left out, counted in [`GrassSpheres`](crate::GrassSpheres) and said
/// once.
#[derive(Component, Clone, Debug, PartialEq, bevy::reflect::Reflect)]
#[reflect(Component, Clone, PartialEq)]
pub struct GrassCollider {
    /// Centre (xyz) and radius (w) of each sphere, in the entity's space.
    pub spheres: Vec<Vec4>,
    /// Whether it cuts the grass under it instead of pressing it.
    pub cuts: bool,
}

impl GrassCollider {
    /// A ball of `radius` around the entity's origin.
    pub fn sphere(radius: f32) -> GrassCollider {
        GrassCollider {
            spheres: vec![Vec3::ZERO.extend(radius)],
            cuts: false,
        }
    }

    /// `mesh` packed into `spheres` spheres, as sward packs its mesh bodies: `None` where the
    /// mesh has no triangle list of positions.
    pub fn from_mesh(mesh: &Mesh, spheres: usize) -> Option<GrassCollider> {
        let (positions, triangles) = triangles_of(mesh)?;
        Some(GrassCollider {
            spheres: pack_triangles(positions, triangles, spheres),
            cuts: false,
        })
    }

    /// The same shape, mowing the grass under it.
    pub fn cutting(self) -> GrassCollider {
        GrassCollider { cuts: true, ..self }
    }
}

/// A Bevy mesh's positions and triangles, where it is a triangle list of positions.
pub(crate) fn triangles_of(mesh: &Mesh) -> Option<(Vec<glam::Vec3>, Vec<[u32; 3]>)> {
    let Some(VertexAttributeValues::Float32x3(positions)) = mesh.attribute(Mesh::ATTRIBUTE_POSITION) else {
        return None;
    };
    let positions: Vec<Vec3> = positions.iter().map(|&p| Vec3::from_array(p)).collect();
    let indices: Vec<u32> = match mesh.indices() {
        Some(Indices::U16(i)) => i.iter().map(|&i| i as u32).collect(),
        Some(Indices::U32(i)) => i.clone(),
        None => (0..positions.len() as u32).collect(),
    };
    let triangles: Vec<[u32; 3]> = indices
        .as_chunks::<3>()
        .0
        .iter()
        .map(|t| [t[0], t[1], t[2]])
        .filter(|t| t.iter().all(|&i| (i as usize) < positions.len()))
        .collect();
    (!triangles.is_empty()).then_some((positions, triangles))
}

/// Triangles packed into at most `spheres` spheres (centre, radius), as sward packs its mesh
/// bodies (normals from the faces); none where there are no triangles.
pub(crate) fn pack_triangles(positions: Vec<glam::Vec3>, triangles: Vec<[u32; 3]>, spheres: usize) -> Vec<Vec4> {
    if triangles.is_empty() {
        return Vec::new();
    }
    let mut normals = vec![glam::Vec3::ZERO; positions.len()];
    for t in &triangles {
        let [a, b, c] = t.map(|i| positions[i as usize]);
        let n = (b - a).cross(c - a);
        for &i in t {
            normals[i as usize] += n;
        }
    }
    let normals = normals.into_iter().map(|n| n.normalize_or(glam::Vec3::Y)).collect();
    let mesh = sward_core::mesh::Mesh {
        positions,
        normals,
        triangles,
    };
    sward_core::bodies::pack_spheres(&mesh, spheres.max(1))
}
