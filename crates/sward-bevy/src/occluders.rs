//! Bevy's meshes in sward's cull: an entity with a [`GrassOccluder`] hides the grass behind it
//! from the cull, as sward's own occluders do, in both of the plugin's shapes. Its mesh is
//! packed into spheres inside it (as sward packs its mesh bodies) when it is loaded and again
//! when it changes; each frame the spheres follow the entity's `GlobalTransform` into sward's
//! depth pyramid. Spheres inside the mesh hide only what the mesh hides, so the picture stays
//! the same while the GPU draws fewer blades.
//!
//! Why spheres and not the mesh's depth: in the Pbr shape sward's cull runs before Bevy draws
//! anything this frame, so Bevy's depth is not there yet; last frame's depth would hide grass
//! wrongly wherever the camera moved.

use bevy::app::{App, PostUpdate};
use bevy::asset::{AssetEvent, AssetId, Assets};
use bevy::ecs::message::MessageReader;
use bevy::ecs::prelude::*;
use bevy::math::Vec4;
use bevy::mesh::{Mesh, Mesh3d};

use crate::components::{pack_triangles, triangles_of};

/// Spheres a mesh is packed into unless told otherwise: enough to fill a house or a rock.
const DEFAULT_SPHERES: usize = 16;

/// An entity that hides the grass behind it from sward's cull: a house, a wall, a rock. It
/// neither presses nor mows the grass (that is [`GrassCollider`](crate::GrassCollider)), and
/// sward does not draw it: the app draws its mesh. A hidden entity hides nothing.
///
/// The spheres share sward's 128 collider slots, after the colliders that press and mow:
/// where those fill them, the last occluders are left out (the grass behind them is drawn),
/// counted in [`GrassSpheres`](crate::GrassSpheres) and said once.
#[derive(Component, Clone, Debug, PartialEq, bevy::reflect::Reflect)]
#[reflect(Component, Clone, PartialEq)]
pub struct GrassOccluder {
    /// Centre (xyz) and radius (w) of each sphere, in the entity's space.
    pub spheres: Vec<Vec4>,
    /// `Some(n)`: the entity's `Mesh3d` is packed into at most `n` spheres once loaded, and
    /// again when it changes, replacing `spheres`.
    pub pack: Option<usize>,
    /// The mesh `spheres` were last packed from.
    #[reflect(ignore)]
    packed_from: Option<AssetId<Mesh>>,
}

impl Default for GrassOccluder {
    /// The entity's own mesh, packed into up to 16 spheres.
    fn default() -> Self {
        GrassOccluder::packed(DEFAULT_SPHERES)
    }
}

impl GrassOccluder {
    /// The entity's own mesh (its `Mesh3d`), packed into at most `spheres` spheres.
    pub fn packed(spheres: usize) -> GrassOccluder {
        GrassOccluder {
            spheres: Vec::new(),
            pack: Some(spheres.max(1)),
            packed_from: None,
        }
    }

    /// These spheres (centre and radius, in the entity's space), whatever its mesh: an
    /// occluder the app shapes itself, or one with no mesh in the world.
    pub fn spheres(spheres: Vec<Vec4>) -> GrassOccluder {
        GrassOccluder {
            spheres,
            pack: None,
            packed_from: None,
        }
    }
}

pub(crate) fn build(app: &mut App) {
    app.add_systems(PostUpdate, pack_occluders.in_set(crate::GrassSystems));
}

/// Pack each occluder's mesh where it has not been packed from that mesh yet (a new occluder,
/// a mesh swapped or still loading) or the mesh asset changed.
fn pack_occluders(
    mut occluders: Query<(Entity, &mut GrassOccluder, &Mesh3d)>,
    meshes: Res<Assets<Mesh>>,
    mut events: MessageReader<AssetEvent<Mesh>>,
) {
    let modified: Vec<AssetId<Mesh>> = events
        .read()
        .filter_map(|event| match event {
            AssetEvent::Modified { id } => Some(*id),
            _ => None,
        })
        .collect();
    for (entity, mut occluder, mesh) in &mut occluders {
        let Some(budget) = occluder.pack else { continue };
        let id = mesh.id();
        if occluder.packed_from == Some(id) && !modified.contains(&id) {
            continue;
        }
        // Still loading: tried again next frame.
        let Some(mesh) = meshes.get(id) else { continue };
        let spheres = triangles_of(mesh).map(|(positions, triangles)| pack_triangles(positions, triangles, budget));
        if spheres.is_none() {
            bevy::log::warn!("entity {entity}'s mesh has no triangle list of positions to pack: it hides no grass");
        }
        occluder.spheres = spheres.unwrap_or_default();
        occluder.packed_from = Some(id);
    }
}
