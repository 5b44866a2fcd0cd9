//! A field's content as Bevy assets: the ground it grows on (a Bevy [`Mesh`], or a height map
//! [`Image`]) and the maps that say where it grows, how tall, its tint and where each kind grows
//! (grey or colour `Image`s), given to a [`Grass`] by a [`GrassContent`] in place of the files
//! its scene names; or made in code from a function of position, baked to an image at a stated
//! resolution ([`GroundContent::from_height`], [`GrassContent::bake_map`]). The images and
//! meshes stay in the main world, where the CPU sampler reads them too; each version of an asset
//! is converted once, however many fields use it.

use std::sync::Arc;

use bevy::app::{App, PostUpdate};
use bevy::asset::{AssetEvent, Assets, Handle, RenderAssetUsages, UntypedAssetId};
use bevy::ecs::prelude::*;
use bevy::image::Image;
use bevy::log::warn;
use bevy::math::{Rect, Vec2};
use bevy::mesh::{Mesh, PrimitiveTopology, VertexAttributeValues};
use bevy::platform::collections::{HashMap, HashSet};
use bevy::prelude::ReflectDefault;
use bevy::reflect::Reflect;
use sward_core::content::Content;
use sward_core::field::Surface;
use sward_core::Scene;
use wgpu::{Extent3d, TextureDimension, TextureFormat};

use crate::components::Grass;

/// What a [`Grass`] grows on and is painted with, as Bevy assets, in place of what its scene
/// names (on the same entity as the `Grass`). Each part that is set replaces the scene's; the
/// rest of the scene stays. Until every asset it names has loaded, the grass grows from its
/// scene as written; when an asset changes (a hot-reloaded image, a mesh edited in code), the
/// field grows again from the new one.
#[derive(Component, Clone, Debug, Default, PartialEq, Reflect)]
#[reflect(Component, Default, Clone)]
pub struct GrassContent {
    /// The ground the grass grows on, in place of the scene's `[surface]`.
    pub ground: Option<GroundContent>,
    /// Where the grass grows, read as grey (black: none, white: all), in place of `[paint]
    /// density`.
    pub density: Option<Handle<Image>>,
    /// How tall it grows, read as grey (a fraction of its height), in place of `[paint] length`.
    pub length: Option<Handle<Image>>,
    /// Its colour there times twice the image's (mid grey keeps the scene's colours), in place of
    /// `[paint] color`.
    pub color: Option<Handle<Image>>,
    /// Where each kind grows, by its `[[species]]` name, read as grey, in place of its
    /// `weight_map`.
    pub weight_maps: Vec<(String, Handle<Image>)>,
    /// The ground the maps cover, in the field's own x and z (`min` the lowest x and z), in
    /// place of `[paint] area`; `None` keeps the scene's.
    pub area: Option<Rect>,
}

/// A ground given as a Bevy asset.
#[derive(Clone, Debug, PartialEq, Reflect)]
pub enum GroundContent {
    /// The triangles of a Bevy mesh (a triangle list with positions, in the field's own space),
    /// as a mesh file would give them: blades grow over every triangle facing up.
    Mesh(Handle<Mesh>),
    /// Terrain from a height map image read as grey: black is y = 0, white is y = `height`, the
    /// image spanning `size` (x and z) centred on the field's origin, one vertex per pixel (as
    /// `[surface] type = "heightmap"`).
    HeightMap {
        /// The height map.
        image: Handle<Image>,
        /// The ground it spans, x and z.
        size: Vec2,
        /// The height of white.
        height: f32,
    },
}

/// The most samples along a baked height map's side: what a height map file is sampled down to.
pub const MAX_HEIGHT_SAMPLES: u32 = 1025;

impl GroundContent {
    /// Terrain from `height_at(x, z)` (the ground's height at a point, 0 to `height`; outside
    /// that, clamped) over `size` centred on the origin, baked to a 16-bit height map of
    /// `samples` × `samples` points (2 to [`MAX_HEIGHT_SAMPLES`]; a point every
    /// `size / (samples - 1)`) and added to `images`, where the sampler and the grass read it.
    pub fn from_height(
        images: &mut Assets<Image>,
        size: Vec2,
        height: f32,
        samples: u32,
        height_at: impl Fn(Vec2) -> f32,
    ) -> GroundContent {
        let n = samples.clamp(2, MAX_HEIGHT_SAMPLES);
        let mut data = Vec::with_capacity((2 * n * n) as usize);
        for j in 0..n {
            for i in 0..n {
                let at = (Vec2::new(i as f32, j as f32) / (n - 1) as f32 - 0.5) * size;
                let level = (height_at(at) / height.max(f32::MIN_POSITIVE)).clamp(0.0, 1.0);
                data.extend_from_slice(&((level * 65535.0).round() as u16).to_le_bytes());
            }
        }
        GroundContent::HeightMap {
            image: images.add(main_world_image(n, n, TextureFormat::R16Unorm, data)),
            size,
            height,
        }
    }
}

/// The most texels along a baked map's side (a paint map's limit).
pub const MAX_MAP_TEXELS: u32 = sward_core::paint::MAX_MAP_SIDE;

impl GrassContent {
    /// A grey map of `value_at(x, z)` (0 to 1, clamped) over `area`, `texels_per_unit` texels a
    /// unit (2 to [`MAX_MAP_TEXELS`] a side: coarser over a wider area), each texel the value at
    /// its centre, added to `images`: a `density`, `length` or weight map for a field whose
    /// [`GrassContent::area`] is `area`.
    pub fn bake_map(
        images: &mut Assets<Image>,
        area: Rect,
        texels_per_unit: f32,
        value_at: impl Fn(Vec2) -> f32,
    ) -> Handle<Image> {
        let texels = (area.size() * texels_per_unit.max(0.0))
            .ceil()
            .clamp(Vec2::splat(2.0), Vec2::splat(MAX_MAP_TEXELS as f32))
            .as_uvec2();
        let texel = area.size() / texels.as_vec2();
        let mut data = Vec::with_capacity((texels.x * texels.y) as usize);
        for j in 0..texels.y {
            for i in 0..texels.x {
                let centre = area.min + (Vec2::new(i as f32, j as f32) + 0.5) * texel;
                data.push((value_at(centre).clamp(0.0, 1.0) * 255.0).round() as u8);
            }
        }
        images.add(main_world_image(texels.x, texels.y, TextureFormat::R8Unorm, data))
    }

    /// Every asset it names, with what the scene calls it.
    fn assets(&self) -> Vec<(Named, UntypedAssetId)> {
        let mut named = Vec::new();
        match &self.ground {
            Some(GroundContent::Mesh(mesh)) => named.push((Named::Ground, mesh.id().untyped())),
            Some(GroundContent::HeightMap { image, .. }) => named.push((Named::Ground, image.id().untyped())),
            None => {}
        }
        let maps = [
            (Named::Density, &self.density),
            (Named::Length, &self.length),
            (Named::Color, &self.color),
        ];
        named.extend(
            maps.into_iter()
                .filter_map(|(n, h)| Some((n, h.as_ref()?.id().untyped()))),
        );
        named.extend(
            self.weight_maps
                .iter()
                .map(|(kind, h)| (Named::Weight(kind.clone()), h.id().untyped())),
        );
        named
    }
}

/// An image of `data` kept in the main world (the sampler reads it) and the render world.
fn main_world_image(width: u32, height: u32, format: TextureFormat, data: Vec<u8>) -> Image {
    let size = Extent3d {
        width,
        height,
        depth_or_array_layers: 1,
    };
    Image::new(size, TextureDimension::D2, data, format, RenderAssetUsages::default())
}

/// What part of the scene an asset stands in for.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum Named {
    Ground,
    Density,
    Length,
    Color,
    Weight(String),
}

/// Assets converted to what sward grows from, by asset: each version converted once.
#[derive(Resource, Default)]
struct Converted(HashMap<UntypedAssetId, Result<Content, String>>);

/// What was said of a field's content, so that each problem is said once.
#[derive(Component, Default)]
struct SaidOfContent(HashSet<String>);

pub(crate) fn build(app: &mut App) {
    app.init_resource::<Converted>().add_systems(
        PostUpdate,
        give_content
            .in_set(crate::GrassSystems)
            .after(crate::assets::grow_from_sources)
            .after(crate::edits::paint_edits)
            .before(crate::changes::keep_valid)
            .before(crate::sampling::keep_in_step),
    );
}

/// The assets a frame's events touched (loaded, changed or gone): each dropped from the
/// converted ones. (No events where the app has no such assets.)
fn touched<A: bevy::asset::Asset>(
    events: Option<MessageReader<AssetEvent<A>>>,
    converted: &mut Converted,
) -> HashSet<UntypedAssetId> {
    let mut touched = HashSet::new();
    let Some(mut events) = events else {
        return touched;
    };
    for event in events.read() {
        let id = match *event {
            AssetEvent::Added { id }
            | AssetEvent::Modified { id }
            | AssetEvent::Removed { id }
            | AssetEvent::LoadedWithDependencies { id } => id.untyped(),
            AssetEvent::Unused { .. } => continue,
        };
        converted.0.remove(&id);
        touched.insert(id);
    }
    touched
}

/// Each field whose content, grass or assets changed this frame gets its scene with the
/// content's assets in place of what it names, once every asset has loaded.
#[allow(clippy::type_complexity)]
fn give_content(
    mut commands: Commands,
    mut fields: Query<(Entity, Ref<GrassContent>, &mut Grass, Option<&mut SaidOfContent>)>,
    images: Option<Res<Assets<Image>>>,
    meshes: Option<Res<Assets<Mesh>>>,
    image_events: Option<MessageReader<AssetEvent<Image>>>,
    mesh_events: Option<MessageReader<AssetEvent<Mesh>>>,
    mut converted: ResMut<Converted>,
) {
    let mut changed = touched(image_events, &mut converted);
    changed.extend(touched(mesh_events, &mut converted));
    for (entity, content, mut grass, said) in &mut fields {
        // The field's assets listed only where an asset changed this frame (most frames none).
        let an_asset_changed = || content.assets().iter().any(|(_, id)| changed.contains(id));
        if !content.is_changed() && !grass.is_changed() && (changed.is_empty() || !an_asset_changed()) {
            continue;
        }
        let given = content.assets().into_iter().map(|(part, id)| {
            let as_content = convert(id, images.as_deref(), meshes.as_deref(), &mut converted)?;
            Some((part, id, as_content))
        });
        // An asset not loaded yet: its event comes when it is.
        let Some(given) = given.collect::<Option<Vec<_>>>() else {
            continue;
        };
        match given_scene(&grass.scene, &content, given) {
            Ok(scene) => {
                if grass.scene != scene {
                    grass.scene = scene;
                }
            }
            Err(problem) => say_once(&mut commands, entity, said, problem),
        }
    }
}

/// Warn of `problem` with a field's content, unless it was said of that field already.
fn say_once(commands: &mut Commands, entity: Entity, said: Option<Mut<SaidOfContent>>, problem: String) {
    match said {
        Some(mut said) => {
            if said.0.insert(problem.clone()) {
                warn!("{problem}");
            }
        }
        None => {
            warn!("{problem}");
            commands.entity(entity).insert(SaidOfContent(HashSet::from([problem])));
        }
    }
}

/// The asset `id` as sward's content (converted once per version), or `None` where it has not
/// loaded.
fn convert(
    id: UntypedAssetId,
    images: Option<&Assets<Image>>,
    meshes: Option<&Assets<Mesh>>,
    converted: &mut Converted,
) -> Option<Result<Content, String>> {
    if let Some(done) = converted.0.get(&id) {
        return Some(done.clone());
    }
    let done = if let Ok(image) = id.try_typed::<Image>() {
        image_content(images?.get(image)?)
    } else {
        mesh_content(meshes?.get(id.try_typed::<Mesh>().ok()?)?)
    };
    converted.0.insert(id, done.clone());
    Some(done)
}

/// `scene` with the content's assets in place of what it names, checked as any scene is; or
/// the one sentence saying what is wrong.
fn given_scene(
    scene: &Scene,
    content: &GrassContent,
    given: Vec<(Named, UntypedAssetId, Result<Content, String>)>,
) -> Result<Scene, String> {
    let mut scene = scene.clone();
    if let Some(area) = content.area {
        scene.paint.area = [area.min.x, area.min.y, area.max.x, area.max.y];
    }
    for (part, id, converted) in given {
        let what = describe(&part);
        let converted = converted.map_err(|e| format!("the grass's {what} cannot be used: {e}"))?;
        let name = format!("bevy-asset:{id:?}");
        scene.contents.insert(name.clone(), converted);
        match (&part, &content.ground) {
            (Named::Ground, Some(GroundContent::Mesh(_))) => scene.surface = Surface::Mesh { path: name, scale: 1.0 },
            (Named::Ground, Some(GroundContent::HeightMap { size, height, .. })) => {
                scene.surface = Surface::Heightmap {
                    path: name,
                    size: *size,
                    height: *height,
                }
            }
            (Named::Ground, None) => {}
            (Named::Density, _) => scene.paint.density = Some(name),
            (Named::Length, _) => scene.paint.length = Some(name),
            (Named::Color, _) => scene.paint.color = Some(name),
            (Named::Weight(kind), _) => {
                let Some(species) = scene.species.iter_mut().find(|s| s.name == *kind) else {
                    let kinds: Vec<&str> = scene.species.iter().map(|s| s.name.as_str()).collect();
                    return Err(format!(
                        "the grass's weight map for {kind:?} names no kind it grows; its kinds are {kinds:?}"
                    ));
                };
                species.weight_map = Some(name);
            }
        }
    }
    scene
        .validate("the grass with its content")
        .map_err(|e| e.to_string())?;
    Ok(scene)
}

/// The part of a field's content, in words.
fn describe(part: &Named) -> String {
    match part {
        Named::Ground => "ground".into(),
        Named::Density => "density map".into(),
        Named::Length => "length map".into(),
        Named::Color => "colour map".into(),
        Named::Weight(kind) => format!("weight map for {kind:?}"),
    }
}

/// A Bevy image as sward reads a map: its pixels, grey or colour, 8 or 16 bits or float.
fn image_content(image: &Image) -> Result<Content, String> {
    use image::{DynamicImage, ImageBuffer};
    let (width, height) = (image.width(), image.height());
    let Some(data) = image.data.as_ref() else {
        return Err("the image has no pixels in the main world (keep RenderAssetUsages::MAIN_WORLD)".into());
    };
    let words = || -> Vec<u16> { data.as_chunks::<2>().0.iter().map(|b| u16::from_le_bytes(*b)).collect() };
    let floats = || -> Vec<f32> { data.as_chunks::<4>().0.iter().map(|b| f32::from_le_bytes(*b)).collect() };
    let format = image.texture_descriptor.format;
    let decoded = match format {
        TextureFormat::R16Unorm => ImageBuffer::from_raw(width, height, words()).map(DynamicImage::ImageLuma16),
        TextureFormat::Rg16Unorm => ImageBuffer::from_raw(width, height, words()).map(DynamicImage::ImageLumaA16),
        TextureFormat::Rgba16Unorm => ImageBuffer::from_raw(width, height, words()).map(DynamicImage::ImageRgba16),
        TextureFormat::Rgba8Unorm => ImageBuffer::from_raw(width, height, data.clone()).map(DynamicImage::ImageRgba8),
        TextureFormat::R32Float => {
            let grey = floats().into_iter().flat_map(|v| [v, v, v, 1.0]).collect();
            ImageBuffer::from_raw(width, height, grey).map(DynamicImage::ImageRgba32F)
        }
        _ => Some(image.clone().try_into_dynamic().map_err(|_| {
            format!(
                "its format is {format:?}; a map is R8Unorm, R16Unorm, R32Float, Rg8Unorm, Rg16Unorm, Rgba8Unorm(Srgb), Bgra8Unorm(Srgb), Rgba16Unorm, Rgba16Float or Rgba32Float"
            )
        })?),
    };
    let decoded = decoded.ok_or_else(|| format!("its {width}×{height} pixels are not all there"))?;
    Ok(Content::Image(Arc::new(decoded)))
}

/// A Bevy mesh's triangles as sward grows on them.
fn mesh_content(mesh: &Mesh) -> Result<Content, String> {
    let topology = mesh.primitive_topology();
    if topology != PrimitiveTopology::TriangleList {
        return Err(format!("the mesh is a {topology:?}; grass grows on a triangle list"));
    }
    let extracted = |e: bevy::mesh::MeshAccessError| format!("{e} (keep RenderAssetUsages::MAIN_WORLD)");
    let Some(VertexAttributeValues::Float32x3(positions)) =
        mesh.try_attribute_option(Mesh::ATTRIBUTE_POSITION).map_err(extracted)?
    else {
        return Err("the mesh has no Float32x3 positions".into());
    };
    let indices: Vec<u32> = match mesh.try_indices_option().map_err(extracted)? {
        Some(indices) => indices.iter().map(|i| i as u32).collect(),
        None => (0..positions.len() as u32).collect(),
    };
    let triangles = indices.as_chunks::<3>().0.to_vec();
    let positions = positions.iter().map(|p| bevy::math::Vec3::from_array(*p)).collect();
    let mesh = sward_core::mesh::Mesh::new(positions, triangles).map_err(|e| e.to_string())?;
    Ok(Content::Mesh(Arc::new(mesh)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_baked_height_and_map_read_back_as_sward_reads_them() {
        let mut images = Assets::<Image>::default();
        let ground = GroundContent::from_height(&mut images, Vec2::new(8.0, 4.0), 2.0, 9, |p| p.x.abs() / 4.0 * 2.0);
        let GroundContent::HeightMap { image, .. } = &ground else {
            panic!("{ground:?}")
        };
        let Content::Image(read) = image_content(images.get(image).unwrap()).unwrap() else {
            panic!("not an image")
        };
        let grey = read.to_luma16();
        assert_eq!(grey.dimensions(), (9, 9));
        assert_eq!(grey.get_pixel(0, 4).0, [65535], "the edge at x = -4 is the top");
        assert_eq!(grey.get_pixel(4, 4).0, [0], "the middle at x = 0 is the bottom");

        let area = Rect::new(-2.0, -2.0, 2.0, 2.0);
        let map = GrassContent::bake_map(&mut images, area, 4.0, |p| if p.x < 0.0 { 0.0 } else { 1.0 });
        let Content::Image(read) = image_content(images.get(&map).unwrap()).unwrap() else {
            panic!("not an image")
        };
        let grey = read.to_luma8();
        assert_eq!(grey.dimensions(), (16, 16));
        assert_eq!((grey.get_pixel(7, 3).0, grey.get_pixel(8, 3).0), ([0], [255]));
    }

    #[test]
    fn a_mesh_that_is_not_a_triangle_list_or_an_image_of_no_pixels_is_one_sentence() {
        let lines = Mesh::new(PrimitiveTopology::LineList, RenderAssetUsages::default());
        let e = mesh_content(&lines).unwrap_err();
        assert!(e.contains("LineList") && e.contains("triangle list"), "{e}");
        let mut empty = main_world_image(2, 2, TextureFormat::R8Unorm, vec![0; 4]);
        empty.data = None;
        assert!(image_content(&empty).unwrap_err().contains("MAIN_WORLD"));
        let depth = main_world_image(2, 2, TextureFormat::Depth32Float, vec![0; 16]);
        assert!(image_content(&depth).unwrap_err().contains("Depth32Float"));
    }
}
