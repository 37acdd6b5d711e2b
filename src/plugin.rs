//! [`ManifoldPlugins`]: the one line to add to a Bevy app.

use crate::camera::ManifoldCameraPlugin;
use crate::drawables::DrawablesPlugin;
use crate::placement::PlacementPlugin;
use crate::tour::TourPlugin;
use bevy::app::{PluginGroup, PluginGroupBuilder};
use bevy::ecs::schedule::{InternedScheduleLabel, ScheduleLabel};
use bevy::prelude::*;

/// Everything bevy_manifold adds to an app, as a plugin group whose every
/// plugin can be left out or replaced the usual Bevy way:
///
/// - [`PlacementPlugin`]: entities placed, moved and wrapped in their
///   manifolds, gameplay ray casts ([`crate::placement::ManifoldSystems`]);
/// - [`DrawablesPlugin`]: the balls, lights, edges and Bevy meshes the
///   tracer draws, gathered per space when they change
///   ([`crate::drawables::DrawablesSystems`]);
/// - [`TourPlugin`]: tours played by [`crate::tour::TourPlayer`]s
///   ([`crate::tour::TourSystems`]);
/// - [`ManifoldCameraPlugin`]: the camera components registered for
///   reflection, and (feature `render`) the render scale that holds a
///   frame rate;
/// - [`crate::assets::ManifoldAssetsPlugin`] (feature `asset`, on with
///   `render`): space and tour files as assets, where the app has an asset
///   server;
/// - [`crate::render::ManifoldRenderPlugin`] (feature `render`, the
///   default): every [`crate::camera::ManifoldCamera`] is ray-traced, where
///   the app has a renderer. Other cameras render exactly as before.
/// - [`crate::product::ProductPlugin`], where every
///   [`crate::product::ProductCamera`] (a view of an H2xR or S2xR space)
///   flies with its velocity and, with `render`, is ray-traced.
///
/// The fly camera is separate and optional:
/// [`crate::camera::FlyCameraPlugin`] (feature `fly_camera`).
///
/// One setting: the schedule the placement systems, the gathering and the
/// tours run in (`PostUpdate` by default; a game that moves entities in
/// fixed steps takes `FixedPostUpdate`).
///
/// ```
/// use bevy::prelude::*;
/// use bevy_manifold::prelude::*;
/// use bevy_manifold::tour::TourPlugin;
///
/// App::new().add_plugins((MinimalPlugins, ManifoldPlugins::default()));
/// App::new().add_plugins((MinimalPlugins, ManifoldPlugins::in_schedule(FixedPostUpdate)));
/// // Without the tours.
/// App::new().add_plugins((MinimalPlugins, ManifoldPlugins::default().build().disable::<TourPlugin>()));
/// ```
#[derive(Debug, Clone)]
pub struct ManifoldPlugins {
    schedule: InternedScheduleLabel,
}

impl Default for ManifoldPlugins {
    fn default() -> Self {
        Self::in_schedule(PostUpdate)
    }
}

impl ManifoldPlugins {
    /// The plugins with the placement systems, the gathering and the tours
    /// in `schedule`.
    #[must_use]
    pub fn in_schedule(schedule: impl ScheduleLabel) -> Self {
        ManifoldPlugins {
            schedule: schedule.intern(),
        }
    }
}

impl PluginGroup for ManifoldPlugins {
    fn build(self) -> PluginGroupBuilder {
        let group = PluginGroupBuilder::start::<Self>()
            .add(PlacementPlugin::in_schedule(self.schedule))
            .add(DrawablesPlugin::in_schedule(self.schedule))
            .add(TourPlugin::in_schedule(self.schedule))
            .add(ManifoldCameraPlugin)
            .add(crate::product::ProductPlugin);
        #[cfg(feature = "asset")]
        let group = group.add(crate::assets::ManifoldAssetsPlugin);
        #[cfg(feature = "render")]
        let group = group.add(crate::render::ManifoldRenderPlugin);
        group
    }
}
