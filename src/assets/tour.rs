//! Tours as Bevy assets (feature `asset`): `.tour.json` files loaded by
//! the asset server, validated off the main thread (every error names the
//! file, the entry and the field), with the space they name: a catalog or
//! library name, or a space file next to the tour, read through the asset
//! server too.
//!
//! An entity with [`TourSource`] (under a [`crate::placement::ManifoldSpace`]
//! root showing the tour's space, usually the camera) gets a
//! [`TourPlayer`] once the tour has loaded, and a new one when the file
//! changes (hot reload, with Bevy's `file_watcher` feature). A root with
//! [`TourSource`] and no `ManifoldSpace` yet gets the tour's space. A tour
//! that fails to load is reported through Bevy's [`AssetLoadFailedEvent`]
//! and as a warning in the log; nothing else changes.
//!
//! ```no_run
//! use bevy::prelude::*;
//! use bevy_manifold::prelude::*;
//! use bevy_manifold::assets::TourSource;
//!
//! fn setup(mut commands: Commands, assets: Res<AssetServer>) {
//!     let tour = TourSource(assets.load("tours/seifert-weber.tour.json"));
//!     // The root takes the tour's space, the camera flies the tour.
//!     let root = commands.spawn(tour.clone()).id();
//!     commands.spawn((ChildOf(root), ManifoldCamera::default(), tour));
//! }
//! # App::new().add_plugins((DefaultPlugins, ManifoldPlugins::default())).add_systems(Startup, setup);
//! ```

use crate::placement::ManifoldSpace;
use crate::space::Space;
use crate::tour::{Tour, TourDesc, TourError, TourPlayer};
use bevy::asset::{AssetLoadFailedEvent, AssetLoader, LoadContext, io::Reader};
use bevy::prelude::*;
use std::sync::Arc;

/// A tour loaded from a file, with the space it flies in.
#[derive(Asset, TypePath, Clone, Debug)]
pub struct TourAsset {
    /// The tour's space.
    pub space: Arc<Space>,
    /// The tour.
    pub tour: Arc<Tour>,
}

/// Loads `.tour.json` files into [`TourAsset`]s.
#[derive(Default, TypePath)]
pub struct TourAssetLoader;

/// Why a tour did not load: the tour's or its space file's error, or a
/// file that cannot be read.
#[derive(Debug, thiserror::Error)]
pub enum TourAssetError {
    /// The tour file's own error, naming the file, entry and field.
    #[error(transparent)]
    Tour(#[from] TourError),
    /// The space file it names.
    #[error("{path}: space: {message}")]
    Space {
        /// The tour file.
        path: String,
        /// What is wrong with the space file (named).
        message: String,
    },
}

fn read_error(path: &str, what: &str, e: impl std::fmt::Display) -> TourAssetError {
    TourAssetError::Tour(TourError::Io {
        path: path.to_owned(),
        message: format!("cannot read {what}: {e}"),
    })
}

impl AssetLoader for TourAssetLoader {
    type Asset = TourAsset;
    type Settings = ();
    type Error = TourAssetError;

    async fn load(
        &self,
        reader: &mut dyn Reader,
        _settings: &(),
        load_context: &mut LoadContext<'_>,
    ) -> Result<TourAsset, TourAssetError> {
        let path = load_context.path().path().to_path_buf();
        let file = path.display().to_string();
        let mut bytes = Vec::new();
        reader
            .read_to_end(&mut bytes)
            .await
            .map_err(|e| read_error(&file, "the tour", e))?;
        let text = String::from_utf8(bytes).map_err(|_| read_error(&file, "the tour", "not a text file"))?;
        let desc = TourDesc::parse(&text, &file)?;
        // A name is resolved as it is; a space file is an asset next to
        // the tour.
        let space = match desc.resolve_space(None) {
            Ok(space) => space,
            Err(_) => {
                let space_path = path.parent().unwrap_or(std::path::Path::new("")).join(&desc.space);
                let bytes =
                    load_context
                        .read_asset_bytes(space_path.clone())
                        .await
                        .map_err(|e| TourAssetError::Space {
                            path: file.clone(),
                            message: format!("{}: {e}", space_path.display()),
                        })?;
                let text = String::from_utf8(bytes).map_err(|_| TourAssetError::Space {
                    path: file.clone(),
                    message: format!("{}: not a text file", space_path.display()),
                })?;
                Space::parse_file(&text, &space_path).map_err(|e| TourAssetError::Space {
                    path: file.clone(),
                    message: e.to_string(),
                })?
            }
        };
        let tour = desc.build(&space, &file)?;
        Ok(TourAsset {
            space: Arc::new(space),
            tour: Arc::new(tour),
        })
    }

    fn extensions(&self) -> &[&str] {
        &["tour.json"]
    }
}

/// On an entity: the tour it flies (a [`TourPlayer`] is put on it once
/// the asset loads). On a space root without a `ManifoldSpace`: the
/// tour's space is put on it.
#[derive(Component, Clone, Debug)]
pub struct TourSource(pub Handle<TourAsset>);

/// Registers the asset, its loader and the systems that apply it; added by
/// [`crate::ManifoldPlugins`] when the app has an asset server.
pub(super) fn register(app: &mut App) {
    let world = app.world();
    if !world.contains_resource::<AssetServer>() || world.contains_resource::<Assets<TourAsset>>() {
        return;
    }
    app.init_asset::<TourAsset>()
        .init_asset_loader::<TourAssetLoader>()
        .add_systems(PreUpdate, (apply_tour_assets, report_failed_tours));
}

/// An entity with a tour source: its player, and whether it is a root
/// with a space, or below one.
type Sourced<'a> = (
    Entity,
    Ref<'a, TourSource>,
    Option<&'a TourPlayer>,
    Has<ManifoldSpace>,
    Has<ChildOf>,
);

/// Puts a player of each loaded or changed tour on the entities that name
/// it, and the tour's space on roots that have none.
pub fn apply_tour_assets(
    mut commands: Commands,
    mut events: MessageReader<AssetEvent<TourAsset>>,
    assets: Res<Assets<TourAsset>>,
    sources: Query<Sourced>,
) {
    let changed: Vec<AssetId<TourAsset>> = events
        .read()
        .filter_map(|e| match e {
            AssetEvent::LoadedWithDependencies { id } | AssetEvent::Modified { id } => Some(*id),
            _ => None,
        })
        .collect();
    for (entity, source, player, has_space, has_parent) in &sources {
        let id = source.0.id();
        let Some(asset) = assets.get(id) else {
            continue;
        };
        let fresh = source.is_changed() || player.is_none();
        if !(fresh || changed.contains(&id)) {
            continue;
        }
        if !has_parent {
            // A root: the tour's space, unless it has one.
            if !has_space {
                commands
                    .entity(entity)
                    .insert(ManifoldSpace::from_shared(asset.space.clone()));
            }
            continue;
        }
        if player.is_some_and(|p| std::ptr::eq(p.tour(), asset.tour.as_ref())) {
            continue;
        }
        commands.entity(entity).insert(TourPlayer::shared(asset.tour.clone()));
    }
}

/// Logs each tour file that failed to load, with its path and error.
pub fn report_failed_tours(mut failed: MessageReader<AssetLoadFailedEvent<TourAsset>>) {
    for event in failed.read() {
        warn!("tour {} did not load: {}", event.path, event.error);
    }
}
