//! [`ManifoldPlugin`]: the one line to add to a Bevy app.

use crate::placement::PlacementPlugin;
use bevy::prelude::*;

/// Everything bevy_manifold adds to an app. For now: [`PlacementPlugin`]
/// (entities placed, moved and wrapped in their manifolds, gameplay ray
/// casts). The ray-traced render pass joins it in a later version; apps
/// that add this plugin get it without changes.
///
/// The camera controller is separate and optional:
/// [`crate::camera_controller::FlyCameraPlugin`].
///
/// ```
/// use bevy::prelude::*;
/// use bevy_manifold::prelude::*;
/// App::new().add_plugins((MinimalPlugins, ManifoldPlugin::default()));
/// ```
#[derive(Debug, Clone, Default)]
pub struct ManifoldPlugin {
    /// Settings of the placement systems.
    pub placement: PlacementPlugin,
}

impl Plugin for ManifoldPlugin {
    fn build(&self, app: &mut App) {
        app.add_plugins(self.placement.clone());
    }
}
