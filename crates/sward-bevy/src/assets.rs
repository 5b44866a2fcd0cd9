//! The grass as Bevy content: a sward scene file is a [`GrassScene`] asset, loaded through Bevy's
//! `AssetServer` from the app's asset folder (and loaded again when the file or a file it names
//! changes, where the app has Bevy's `file_watcher` feature), and a [`GrassSource`] on an entity
//! gives it the [`Grass`] its asset describes, kept up to date with the files.

use std::path::{Path, PathBuf};

use bevy::app::{App, PostUpdate};
#[cfg(not(target_arch = "wasm32"))]
use bevy::asset::io::file::FileAssetReader;
use bevy::asset::io::Reader;
use bevy::asset::{
    Asset, AssetApp, AssetEvent, AssetEventSystems, AssetId, AssetLoader, AssetPath, AssetPlugin, Assets, Handle,
    LoadContext,
};
use bevy::ecs::prelude::*;
use bevy::platform::collections::HashSet;
use bevy::prelude::ReflectDefault;
use bevy::reflect::{Reflect, TypePath};
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

/// How many times the files a [`GrassSource`]'s scene names (a height map, a paint map) were
/// loaded again with the scene itself unchanged: each time, the field is grown again from them.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct GrassFiles(pub u32);

/// Reads scene files for the `AssetServer`, with the asset folder on disk (where the default
/// asset source is files) that the paths in a scene are resolved in.
#[derive(TypePath)]
struct GrassSceneLoader {
    folder: PathBuf,
}

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
        let beside = context.path().path().parent().unwrap_or(Path::new("")).to_path_buf();
        // The files it names, read through the asset server so that they are the scene's
        // dependencies (a changed map loads the scene again); absolute paths are outside it.
        let written = Scene::from_toml_in(&text, &origin, None)?;
        for file in written.named_files().iter().filter(|f| Path::new(f).is_relative()) {
            let path = AssetPath::from_path_buf(beside.join(file)).with_source(context.path().source().clone_owned());
            context.read_asset_bytes(path).await.map_err(|e| SceneError::Io {
                path: format!("{origin}: the file it names, {file}"),
                reason: e.to_string(),
            })?;
        }
        Scene::from_toml_in(&text, &origin, Some(&self.folder.join(&beside))).map(GrassScene)
    }

    fn extensions(&self) -> &[&str] {
        &["grass.toml"]
    }
}

/// The asset, its loader and the system that grows each [`GrassSource`]'s grass (where the app
/// has Bevy's asset plugin).
pub(crate) fn build(app: &mut App) {
    let Some(assets) = app
        .get_added_plugins::<AssetPlugin>()
        .first()
        .map(|p| p.file_path.clone())
    else {
        return;
    };
    // Where the files a scene names are read from when its field grows: the asset folder on
    // disk (in a browser there is no disk; a scene that names files fails to grow there).
    #[cfg(not(target_arch = "wasm32"))]
    let folder = FileAssetReader::get_base_path().join(assets);
    #[cfg(target_arch = "wasm32")]
    let folder = std::path::PathBuf::from(assets);
    app.init_asset::<GrassScene>()
        .register_asset_loader(GrassSceneLoader { folder })
        .configure_sets(PostUpdate, crate::GrassSystems.after(AssetEventSystems))
        .add_systems(PostUpdate, grow_from_sources.in_set(crate::GrassSystems));
}

/// An entity grown from a scene asset: its source, its grass once grown, and how many times the
/// files its scene names were read again.
type Sourced = (
    Entity,
    Ref<'static, GrassSource>,
    Option<&'static mut Grass>,
    Option<&'static GrassFiles>,
    Option<&'static crate::edits::GrassEdits>,
);

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
    for (entity, source, grass, files, edits) in &mut sources {
        let reloaded = modified.contains(&source.0.id());
        if !source.is_changed() && !changed.contains(&source.0.id()) && !reloaded {
            continue;
        }
        // Not loaded yet: its event comes when it is.
        let Some(GrassScene(scene)) = scenes.get(&source.0) else {
            continue;
        };
        // What the game's edits painted is painted again over the file's scene.
        let scene = crate::edits::repainted(scene, edits);
        match grass {
            Some(mut grass) if grass.scene != scene => grass.scene = scene,
            // Loaded again as it was: the files it names changed (or were saved unchanged).
            Some(_) if reloaded => {
                let count = files.map_or(0, |f| f.0) + 1;
                commands.entity(entity).insert(GrassFiles(count));
            }
            Some(_) => {}
            // Validated by the loader.
            None => {
                commands.entity(entity).insert(Grass::validated(scene));
            }
        }
    }
}
