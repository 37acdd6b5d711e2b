//! [`ManifoldPlugin`]: the one line to add to a Bevy app.

use crate::drawables::DrawablesPlugin;
use crate::placement::PlacementPlugin;
use bevy::prelude::*;

/// Everything bevy_manifold adds to an app:
/// - [`PlacementPlugin`]: entities placed, moved and wrapped in their
///   manifolds, gameplay ray casts;
/// - [`DrawablesPlugin`]: the balls, lights and edges the tracer draws,
///   gathered per space when they change;
/// - with the `render` feature and a renderer in the app,
///   [`crate::render::pass::ManifoldRenderPlugin`]: every
///   [`crate::render::pass::ManifoldCamera`] is ray-traced. Other cameras
///   render exactly as before.
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
    /// Settings of the scene gathering (same schedule as the placement).
    pub drawables: DrawablesPlugin,
}

impl Plugin for ManifoldPlugin {
    fn build(&self, app: &mut App) {
        app.add_plugins((self.placement.clone(), self.drawables.clone()));
        #[cfg(feature = "render")]
        app.add_plugins(crate::render::pass::ManifoldRenderPlugin);
    }
}
