//! The ground the grass grows on, as a Bevy mesh: an entity with a [`GrassGround`] of a
//! [`Grass`] gets the `Mesh3d` of that grass's surface — the terrain or height map (or mesh
//! file) the blades stand on, a planet's sphere, or the plane — so a game draws the ground
//! under the grass with a material of its own instead of building it by hand.

use bevy::app::{App, PostUpdate};
use bevy::asset::{Assets, RenderAssetUsages};
use bevy::ecs::prelude::*;
use bevy::log::warn;
use bevy::math::Vec2;
use bevy::mesh::{Indices, Mesh, Mesh3d, MeshBuilder, Meshable, PrimitiveTopology};
use bevy::shape::{Plane3d, Sphere};
use sward_core::field::Surface;
use sward_core::mesh::MeshError;
use sward_core::Scene;

use crate::components::Grass;

/// The ground of the grass of entity `grass`, on an entity of its own (with a `MeshMaterial3d`
/// of the game's choosing: `commands.spawn((GrassGround::of(grass), MeshMaterial3d(soil)))`):
/// the plugin gives this entity the `Mesh3d` of the ground that grass's scene grows it on
/// ([`ground_mesh`]), made again when the scene's ground changes. (Not on the grass's own
/// entity: Bevy's passes draw the grass as that entity's items; make it a child of the grass's
/// entity, and it stands wherever the grass's `Transform` places the field.)
#[derive(Component, Clone, Debug, bevy::reflect::Reflect)]
#[reflect(Component, Clone)]
pub struct GrassGround {
    /// The entity whose [`Grass`] grows on this ground.
    pub grass: Entity,
    /// The ground the mesh was made for: its surface, the plane's reach and the serial of the
    /// ground given in memory (a Bevy mesh or image).
    #[reflect(ignore)]
    made_for: Option<(Surface, Vec2, Option<u64>)>,
}

impl GrassGround {
    /// The ground of the grass of entity `grass`.
    pub fn of(grass: Entity) -> GrassGround {
        GrassGround { grass, made_for: None }
    }
}

/// The ground `scene` grows its grass on, as a Bevy mesh with normals: its terrain, height map
/// or mesh file as sward grows the blades on it, the sphere of a planet, or, for the plane, a
/// square centred on the origin as wide as the grass reaches ([`plane_reach`]). Fails only
/// where the mesh or height-map file cannot be used.
pub fn ground_mesh(scene: &Scene) -> Result<Mesh, MeshError> {
    Ok(match (&scene.surface, scene.surface.mesh(&scene.contents)?) {
        (_, Some(mesh)) => triangles(&mesh),
        (Surface::Sphere { center, radius }, None) => {
            let sphere = Sphere::new(*radius).mesh().ico(6).expect("a small subdivision");
            sphere.translated_by(*center)
        }
        (_, None) => {
            let side = plane_reach(scene);
            Plane3d::default().mesh().size(side.x, side.y).build()
        }
    })
}

/// How wide a plane's ground is drawn: the fixed field's size, or, where grass is generated
/// around the eye wherever it goes, twice the farthest it reaches (the billboards', the
/// generated blades') and at least 4 km: the eye roams, the ground does not follow it.
pub fn plane_reach(scene: &Scene) -> Vec2 {
    let t = scene.technique;
    let far = match (t.draws_billboards(), t.draws_instanced()) {
        (true, _) => scene.billboard.grid.radius,
        (false, true) => scene.instanced.grid.radius,
        (false, false) => return scene.field.size,
    };
    Vec2::splat((2.0 * far).max(4000.0)).max(scene.field.size)
}

/// Sward's mesh as a Bevy triangle list with its normals.
fn triangles(mesh: &sward_core::mesh::Mesh) -> Mesh {
    let positions: Vec<[f32; 3]> = mesh.positions.iter().map(|p| p.to_array()).collect();
    let normals: Vec<[f32; 3]> = mesh.normals.iter().map(|n| n.to_array()).collect();
    let indices: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
    Mesh::new(PrimitiveTopology::TriangleList, RenderAssetUsages::default())
        .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, positions)
        .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, normals)
        .with_inserted_indices(Indices::U32(indices))
}

/// The main world's part, where the app has meshes.
pub(crate) fn build(app: &mut App) {
    app.add_systems(PostUpdate, make_ground.in_set(crate::GrassSystems));
}

/// Give each [`GrassGround`] the mesh of its grass's ground, where it has none yet or the
/// ground changed.
fn make_ground(
    mut commands: Commands,
    mut grounds: Query<(Entity, &mut GrassGround)>,
    grass: Query<Ref<Grass>>,
    meshes: Option<ResMut<Assets<Mesh>>>,
) {
    let Some(mut meshes) = meshes else { return };
    for (entity, mut ground) in &mut grounds {
        let Ok(grass) = grass.get(ground.grass) else { continue };
        if !grass.is_changed() && ground.made_for.is_some() {
            continue;
        }
        let scene = &grass.scene;
        let given = match &scene.surface {
            Surface::Mesh { path, .. } | Surface::Heightmap { path, .. } => scene.contents.serial(path),
            _ => None,
        };
        let wanted = (scene.surface.clone(), plane_reach(scene), given);
        if ground.made_for.as_ref() == Some(&wanted) {
            continue;
        }
        ground.made_for = Some(wanted);
        match ground_mesh(scene) {
            Ok(mesh) => _ = commands.entity(entity).insert(Mesh3d(meshes.add(mesh))),
            Err(e) => warn!("the grass's ground cannot be made: {e}"),
        }
    }
}
