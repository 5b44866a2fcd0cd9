//! The grass as Bevy content: a sward scene file is a [`GrassScene`] asset, loaded through Bevy's
//! `AssetServer` from the app's asset folder (and loaded again when the file or a file it names
//! changes, where the app has Bevy's `file_watcher` feature), and a [`GrassSource`] on an entity
//! gives it the [`Grass`] its asset describes, kept up to date with the files.

use std::path::{Component, Path, PathBuf};

use bevy::app::{App, PostUpdate};
use bevy::asset::io::Reader;
use bevy::asset::{
    Asset, AssetApp, AssetEvent, AssetEventSystems, AssetId, AssetLoader, AssetPath, AssetPlugin, Assets, Handle,
    LoadContext,
};
use bevy::ecs::prelude::*;
use bevy::platform::collections::HashSet;
use bevy::prelude::ReflectDefault;
use bevy::reflect::{Reflect, TypePath};
use sward_core::content::{Content, Contents};
use sward_core::{Scene, SceneError};

use crate::components::Grass;

/// A sward scene file as a Bevy asset: the file's format (`docs/scene-reference.md`), named
/// `*.grass.toml`, or any name when loaded as this type (`asset_server.load::<GrassScene>(
/// "meadow.toml")`). Paths the file names (meshes, height and paint maps) are relative to it in
/// the asset folder, and are its dependencies: a changed map loads the scene again. A file that
/// does not parse or validate, or names a file that is not there, fails to load with Bevy's
/// asset error, which names the file, the line and the key (or the missing file).
#[derive(Asset, Reflect, Clone, Debug, PartialEq)]
#[reflect(Clone, PartialEq)]
pub struct GrassScene(pub Scene);

/// The scene asset an entity's [`Grass`] is grown from: once the asset is loaded the entity gets
/// its `Grass` (Bevy's lighting and the default shadow distance), and whenever the asset changes
/// (its file edited, with Bevy watching for changes) or the source is replaced, the `Grass`
/// takes the new scene; its `lighting` and `shadow_distance` stay as the app set them.
#[derive(Component, Clone, Debug, Default, PartialEq, Eq, Reflect)]
#[reflect(Component, Default, Clone, PartialEq)]
pub struct GrassSource(pub Handle<GrassScene>);

/// Reads scene files for the `AssetServer`, and every file a scene names through it too: the
/// scene carries their bytes ([`sward_core::content`]), so nothing is read from disk when its
/// field grows, and a scene loads from any asset source (a folder, the web, memory, a packed
/// archive).
#[derive(TypePath)]
struct GrassSceneLoader;

impl AssetLoader for GrassSceneLoader {
    type Asset = GrassScene;
    type Settings = ();
    type Error = SceneError;

    async fn load(
        &self,
        reader: &mut dyn Reader,
        _: &(),
        context: &mut LoadContext<'_>,
    ) -> Result<GrassScene, SceneError> {
        let origin = context.path().to_string();
        let unread = |reason: String| SceneError::Io {
            path: origin.clone(),
            reason,
        };
        let mut bytes = Vec::new();
        reader
            .read_to_end(&mut bytes)
            .await
            .map_err(|e| unread(e.to_string()))?;
        let text = String::from_utf8(bytes).map_err(|e| unread(format!("it is not UTF-8 text ({e})")))?;
        // The files it names are relative to it in the asset folder; parsed first (unvalidated
        // names) so that its bodies' meshes are there when it is validated.
        let beside = context.path().path().parent().unwrap_or(Path::new("")).to_path_buf();
        let named = Scene::files_named_in(&text, &origin, &beside)?;
        let mut contents = Contents::default();
        for file in named {
            let bytes = read_named(context, &origin, &file).await?;
            // A glTF file's buffers beside it are read with it.
            for buffer in sward_core::mesh::gltf_buffer_files(Path::new(&file), &bytes) {
                let buffer = buffer.display().to_string();
                let bytes = read_named(context, &origin, &buffer).await?;
                contents.insert(buffer, Content::File(bytes.into()));
            }
            contents.insert(file, Content::File(bytes.into()));
        }
        Scene::from_toml_given(&text, &origin, Some(&beside), contents).map(GrassScene)
    }

    fn extensions(&self) -> &[&str] {
        &["grass.toml"]
    }
}

/// The bytes of `file`, a file the scene `origin` names (relative to the asset folder), read
/// through the asset server so that it is one of the scene's dependencies (a changed map loads
/// the scene again). A path outside the asset folder is refused: a game's assets are all the
/// plugin reads.
async fn read_named(context: &mut LoadContext<'_>, origin: &str, file: &str) -> Result<Vec<u8>, SceneError> {
    let fail = |reason: String| SceneError::Io {
        path: format!("{origin}: the file it names, {file}"),
        reason,
    };
    let Some(inside) = within_assets(Path::new(file)) else {
        return Err(fail(
            "it lies outside the asset folder; a scene loaded as a Bevy asset names files in the asset folder, relative to itself".into(),
        ));
    };
    let path = AssetPath::from_path_buf(inside).with_source(context.path().source().clone_owned());
    context.read_asset_bytes(path).await.map_err(|e| fail(e.to_string()))
}

/// `path` (relative to the asset folder) with its `..` steps taken, or `None` where it is
/// absolute or steps out of the folder.
fn within_assets(path: &Path) -> Option<PathBuf> {
    let mut inside = PathBuf::new();
    for part in path.components() {
        match part {
            Component::Normal(name) => inside.push(name),
            Component::CurDir => {}
            Component::ParentDir => {
                if !inside.pop() {
                    return None;
                }
            }
            Component::RootDir | Component::Prefix(_) => return None,
        }
    }
    Some(inside)
}

/// The asset, its loader and the system that grows each [`GrassSource`]'s grass (where the app
/// has Bevy's asset plugin).
pub(crate) fn build(app: &mut App) {
    if app.get_added_plugins::<AssetPlugin>().is_empty() {
        return;
    }
    app.init_asset::<GrassScene>()
        .register_asset_loader(GrassSceneLoader)
        .configure_sets(PostUpdate, crate::GrassSystems.after(AssetEventSystems))
        .add_systems(PostUpdate, grow_from_sources.in_set(crate::GrassSystems));
}

/// An entity grown from a scene asset: its source, its grass once grown.
type Sourced = (Entity, Ref<'static, GrassSource>, Option<&'static mut Grass>);

/// Give each [`GrassSource`] whose asset loaded or changed this frame, or that is new or
/// replaced, the asset's scene.
pub(crate) fn grow_from_sources(
    mut commands: Commands,
    mut events: MessageReader<AssetEvent<GrassScene>>,
    scenes: Res<Assets<GrassScene>>,
    mut sources: Query<Sourced>,
) {
    let (mut changed, mut modified) = (HashSet::<AssetId<GrassScene>>::new(), HashSet::new());
    for event in events.read() {
        match *event {
            AssetEvent::LoadedWithDependencies { id } => _ = changed.insert(id),
            AssetEvent::Modified { id } => _ = modified.insert(id),
            _ => {}
        }
    }
    for (entity, source, grass) in &mut sources {
        let reloaded = modified.contains(&source.0.id());
        if !source.is_changed() && !changed.contains(&source.0.id()) && !reloaded {
            continue;
        }
        // Not loaded yet: its event comes when it is.
        let Some(GrassScene(scene)) = scenes.get(&source.0) else {
            continue;
        };
        // What the game's edits painted is painted again over the file's scene.
        let scene = crate::edits::repainted(scene, grass.as_deref());
        match grass {
            // A file it names loaded again is new content: a changed scene.
            Some(mut grass) if grass.scene != scene => grass.scene = scene,
            Some(_) => {}
            // Validated by the loader.
            None => {
                commands.entity(entity).insert(Grass::validated(scene));
            }
        }
    }
}
