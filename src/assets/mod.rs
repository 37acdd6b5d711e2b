//! Space and tour files as Bevy assets (feature `asset`):
//! [`ManifoldAssetsPlugin`] registers their loaders, so a root with a
//! [`ManifoldSpaceSource`] takes the space a `.gen`, `.space.json` or
//! `.gens.json` file describes, and an entity with a [`TourSource`] plays
//! the tour a `.tour.json` file describes. A broken file is an
//! `AssetLoadFailedEvent` naming the file and the field; the rest of the
//! app keeps working.

mod space;
mod tour;

pub use space::{
    ManifoldSpaceSource, SpaceAsset, SpaceAssetError, SpaceAssetLoader, apply_space_assets, report_failed_spaces,
};
pub use tour::{TourAsset, TourAssetError, TourAssetLoader, TourSource, apply_tour_assets, report_failed_tours};

use bevy::prelude::*;

/// Space files and tour files as assets. Part of [`crate::ManifoldPlugins`].
/// Needs an asset server (Bevy's `AssetPlugin`, as `DefaultPlugins` has):
/// the loaders are registered when the plugin is built if the server is
/// there, else once every plugin is built, whatever the plugin order;
/// without one it does nothing.
///
/// ```
/// use bevy::prelude::*;
/// use bevy_manifold::prelude::*;
/// App::new().add_plugins((MinimalPlugins, AssetPlugin::default(), ManifoldPlugins::default()));
/// ```
#[derive(Debug, Clone, Copy, Default)]
pub struct ManifoldAssetsPlugin;

impl Plugin for ManifoldAssetsPlugin {
    fn build(&self, app: &mut App) {
        space::register(app);
        tour::register(app);
    }

    fn finish(&self, app: &mut App) {
        space::register(app);
        tour::register(app);
    }
}
