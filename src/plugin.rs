//! [`ManifoldPlugin`]: the one line to add to a Bevy app.

use crate::drawables::DrawablesPlugin;
use crate::placement::PlacementPlugin;
use crate::view::{CellShading, ManifoldFog};
use bevy::ecs::schedule::{InternedScheduleLabel, ScheduleLabel};
use bevy::prelude::*;

/// Everything bevy_manifold adds to an app:
/// - [`PlacementPlugin`]: entities placed, moved and wrapped in their
///   manifolds, gameplay ray casts;
/// - [`DrawablesPlugin`]: the balls, lights and edges the tracer draws,
///   gathered per space when they change;
/// - the view components [`ManifoldFog`] and [`CellShading`], registered
///   for reflection (they need no renderer);
/// - with the `asset` feature (on with `render`) and an asset server in the
///   app, [`crate::space_asset`]: space files (`.gen`, `.space.json`,
///   `.gens.json`) as assets, applied to roots with a
///   [`crate::space_asset::ManifoldSpaceSource`]; and tour files
///   (`.tour.json`, [`crate::tour_asset`]) played by entities with a
///   [`crate::tour_asset::TourSource`];
/// - with the `render` feature and a renderer in the app,
///   [`crate::render::ManifoldRenderPlugin`]: every
///   [`crate::render::ManifoldCamera`] is ray-traced. Other cameras
///   render exactly as before.
///
/// The camera controller is separate and optional:
/// `camera_controller::FlyCameraPlugin` (feature `fly_camera`).
///
/// One setting: the schedule the placement systems and the scene
/// gathering run in (`PostUpdate` by default; a game that moves entities
/// in fixed steps takes `FixedPostUpdate`).
///
/// ```
/// use bevy::prelude::*;
/// use bevy_manifold::prelude::*;
/// App::new().add_plugins((MinimalPlugins, ManifoldPlugin::default()));
/// App::new().add_plugins((MinimalPlugins, ManifoldPlugin::in_schedule(FixedPostUpdate)));
/// ```
#[derive(Debug, Clone)]
pub struct ManifoldPlugin {
    schedule: InternedScheduleLabel,
}

impl Default for ManifoldPlugin {
    fn default() -> Self {
        Self::in_schedule(PostUpdate)
    }
}

impl ManifoldPlugin {
    /// The plugin with the placement systems and the scene gathering in
    /// `schedule`.
    #[must_use]
    pub fn in_schedule(schedule: impl ScheduleLabel) -> Self {
        ManifoldPlugin {
            schedule: schedule.intern(),
        }
    }
}

impl Plugin for ManifoldPlugin {
    fn build(&self, app: &mut App) {
        app.add_plugins((
            PlacementPlugin::in_schedule(self.schedule),
            DrawablesPlugin::in_schedule(self.schedule),
            crate::tour::TourPlugin::in_schedule(self.schedule),
        ))
        .register_type::<ManifoldFog>()
        .register_type::<CellShading>();
        #[cfg(feature = "render")]
        app.add_plugins(crate::render::ManifoldRenderPlugin);
        // Space files as assets, when the app has an asset server: now if
        // it is there (so handles can be made before the app runs), else
        // once every plugin is built, whatever the plugin order.
        #[cfg(feature = "asset")]
        crate::space_asset::register(app);
        #[cfg(feature = "asset")]
        crate::tour_asset::register(app);
    }

    fn finish(&self, app: &mut App) {
        #[cfg(feature = "asset")]
        crate::space_asset::register(app);
        #[cfg(feature = "asset")]
        crate::tour_asset::register(app);
        #[cfg(not(feature = "asset"))]
        let _ = app;
    }
}
