//! Spaces as Bevy assets: `.gen` files (Curved Spaces generators),
//! `.space.json` files (the space format) and `.gens.json` generator lists,
//! loaded by the asset server and put on a [`ManifoldSpace`] root.
//!
//! A root that carries [`ManifoldSpaceSource`] gets the loaded space as its
//! [`ManifoldSpace`] once the asset is ready, and again whenever the asset
//! changes (hot reload, with Bevy's `file_watcher` feature): the new file
//! is parsed and validated off the main thread (the loader runs on Bevy's
//! task pool), the space swapped in, and every member re-wrapped into the
//! new domain from its origin cell. A file that fails to load is reported
//! through Bevy's [`AssetLoadFailedEvent`] with the file and field named,
//! as a warning in the log; the root keeps the space it had.
//!
//! ```no_run
//! use bevy::prelude::*;
//! use bevy_manifold::prelude::*;
//!
//! fn setup(mut commands: Commands, assets: Res<AssetServer>) {
//!     commands.spawn(ManifoldSpaceSource(assets.load("spaces/lens-7-2.gen")));
//! }
//! # App::new().add_plugins((DefaultPlugins, ManifoldPlugins::default())).add_systems(Startup, setup);
//! ```

use crate::placement::{DomainCell, ManifoldSpace, SpaceMembers, WrapOrigin};
use crate::space::{Space, SpaceFileError};
use bevy::asset::{AssetLoadFailedEvent, AssetLoader, LoadContext, io::Reader};
use bevy::prelude::*;
use std::sync::Arc;

/// A space loaded from a file.
#[derive(Asset, TypePath, Clone, Debug)]
pub struct SpaceAsset(pub Arc<Space>);

/// Loads `.gen`, `.space.json` and `.gens.json` files into [`SpaceAsset`]s,
/// building the Dirichlet domain of generator files.
#[derive(Default, TypePath)]
pub struct SpaceAssetLoader;

/// Why a space file did not load: the file's error, or bytes that are not
/// text.
#[derive(Debug, thiserror::Error)]
pub enum SpaceAssetError {
    /// The file could not be read.
    #[error("{path}: cannot read: {error}")]
    Io {
        /// The asset path.
        path: String,
        /// The reader's error.
        error: std::io::Error,
    },
    /// Not UTF-8.
    #[error("{path}: not a text file")]
    NotText {
        /// The asset path.
        path: String,
    },
    /// The file's own error, naming the file and the field.
    #[error(transparent)]
    File(#[from] SpaceFileError),
}

impl AssetLoader for SpaceAssetLoader {
    type Asset = SpaceAsset;
    type Settings = ();
    type Error = SpaceAssetError;

    async fn load(
        &self,
        reader: &mut dyn Reader,
        _settings: &(),
        load_context: &mut LoadContext<'_>,
    ) -> Result<SpaceAsset, SpaceAssetError> {
        let path = load_context.path().path().to_path_buf();
        let mut bytes = Vec::new();
        reader
            .read_to_end(&mut bytes)
            .await
            .map_err(|error| SpaceAssetError::Io {
                path: path.display().to_string(),
                error,
            })?;
        let text = String::from_utf8(bytes).map_err(|_| SpaceAssetError::NotText {
            path: path.display().to_string(),
        })?;
        let space = Space::parse_file(&text, &path)?;
        Ok(SpaceAsset(Arc::new(space)))
    }

    fn extensions(&self) -> &[&str] {
        &["gen", "space.json", "gens.json"]
    }
}

/// On a space root: the asset its [`ManifoldSpace`] comes from. The root
/// has no `ManifoldSpace` until the asset has loaded (its members wait,
/// placed but not wrapped); afterwards every change of the asset swaps it.
#[derive(Component, Clone, Debug)]
pub struct ManifoldSpaceSource(pub Handle<SpaceAsset>);

/// Registers the asset, its loader and the systems that apply it; added by
/// [`crate::ManifoldPlugins`] when the app has an asset server.
pub(super) fn register(app: &mut App) {
    let world = app.world();
    if !world.contains_resource::<AssetServer>() || world.contains_resource::<Assets<SpaceAsset>>() {
        return;
    }
    app.init_asset::<SpaceAsset>()
        .init_asset_loader::<SpaceAssetLoader>()
        .add_systems(PreUpdate, (apply_space_assets, report_failed_spaces));
}

/// A root with a source: its current space and members, if any.
type SourcedRoot<'a> = (
    Entity,
    Ref<'a, ManifoldSpaceSource>,
    Option<&'a ManifoldSpace>,
    Option<&'a SpaceMembers>,
);

/// Puts each loaded or changed space on the roots that name it, and
/// re-wraps their members into the new domain.
pub fn apply_space_assets(
    mut commands: Commands,
    mut events: MessageReader<AssetEvent<SpaceAsset>>,
    assets: Res<Assets<SpaceAsset>>,
    roots: Query<SourcedRoot>,
) {
    let changed: Vec<AssetId<SpaceAsset>> = events
        .read()
        .filter_map(|e| match e {
            AssetEvent::LoadedWithDependencies { id } | AssetEvent::Modified { id } => Some(*id),
            _ => None,
        })
        .collect();
    for (root, source, current, members) in &roots {
        let id = source.0.id();
        // A source set after its asset loaded has no event to wait for.
        let fresh = source.is_changed() && current.is_none();
        if !(fresh || changed.contains(&id)) {
            continue;
        }
        let Some(asset) = assets.get(id) else {
            continue;
        };
        if current.is_some_and(|c| Arc::ptr_eq(c.shared(), &asset.0)) {
            continue;
        }
        info!("space {} loaded onto entity {root}", asset.0.name());
        commands
            .entity(root)
            .insert(ManifoldSpace::from_shared(asset.0.clone()));
        for member in members.into_iter().flat_map(SpaceMembers::iter) {
            // Start each member's chord at the new domain's origin cell.
            commands
                .entity(member)
                .try_insert((WrapOrigin(None), DomainCell::default()));
        }
    }
}

/// Logs each space file that failed to load, with its path and error.
pub fn report_failed_spaces(mut failed: MessageReader<AssetLoadFailedEvent<SpaceAsset>>) {
    for event in failed.read() {
        warn!("space {} did not load: {}", event.path, event.error);
    }
}
