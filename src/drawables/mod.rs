//! What the tracer draws, as components: balls and lights placed in a
//! manifold, and the domain's edges. [`gather_scenes`] collects them per
//! space into a [`ManifoldScene`] on the space's root entity, rebuilt only
//! when one of them (or the space) changed. The scene is render-agnostic
//! (the CPU reference can trace it as it is); the render world's prepare
//! stage packs it for the GPU when its generation changes.
//!
//! ```
//! use bevy::prelude::*;
//! use bevy_manifold::prelude::*;
//! use glam::DVec3;
//!
//! let mut app = App::new();
//! app.add_plugins((MinimalPlugins, ManifoldPlugins::default()));
//! let space = catalog::torus(1.0);
//! let root = app.world_mut().spawn((ManifoldSpace::new(space.clone()), DomainEdges::default())).id();
//! app.world_mut().spawn((ChildOf(root), TracedBall::new(0.2, Color::srgb(0.9, 0.3, 0.2))));
//! app.world_mut().spawn((ChildOf(root), ManifoldLight::default(), Placement::at(&space, DVec3::Y * 0.3)));
//! app.update();
//! let scene = app.world().get::<ManifoldScene>(root).unwrap();
//! assert_eq!(scene.scene().balls.len(), 1);
//! assert_eq!(scene.scene().lights.len(), 1);
//! assert!(scene.scene().edge_radius.is_some());
//! ```

#[cfg(feature = "render")]
mod bevy_lights;
mod components;
mod gather;
#[cfg(feature = "render")]
mod meshes;
#[cfg(feature = "paper_scene")]
pub mod paper;

#[cfg(feature = "render")]
pub use bevy_lights::{BEVY_EXPOSURE, FromBevyLight, from_point_light, from_spot_light, sync_bevy_lights};
pub use components::{
    DomainEdges, ManifoldLight, ManifoldLighting, ManifoldMeshes, ManifoldScene, SpotCone, TracedBall,
};
pub use gather::{gather_scenes, spawn_scene};
#[cfg(feature = "render")]
pub use meshes::{
    ASYNC_BVH_TRIANGLES, CameraBody, MeshBvhCache, REFIT_GROWTH, Rasterized, bevy_mesh, gather_meshes,
    morphed_tri_mesh, skinned_tri_mesh, texture, tri_mesh,
};

use crate::placement::ManifoldSystems;
use bevy::ecs::schedule::{InternedScheduleLabel, ScheduleLabel};
use bevy::prelude::*;

/// Runs [`gather_scenes`] after the placement systems, so it sees the
/// frame's final placements, and (feature `render`) the gathering of
/// Bevy meshes before it. Part of [`crate::ManifoldPlugins`].
#[derive(Debug, Clone)]
pub struct DrawablesPlugin {
    schedule: InternedScheduleLabel,
}

impl Default for DrawablesPlugin {
    fn default() -> Self {
        Self::in_schedule(PostUpdate)
    }
}

impl DrawablesPlugin {
    /// The plugin with its system in `schedule` (the placement systems'
    /// schedule).
    #[must_use]
    pub fn in_schedule(schedule: impl ScheduleLabel) -> Self {
        DrawablesPlugin {
            schedule: schedule.intern(),
        }
    }
}

impl Plugin for DrawablesPlugin {
    fn build(&self, app: &mut App) {
        app.register_type::<TracedBall>()
            .register_type::<ManifoldLight>()
            .register_type::<ManifoldLighting>()
            .register_type::<DomainEdges>()
            .configure_sets(
                self.schedule,
                (DrawablesSystems::Meshes, DrawablesSystems::Scenes)
                    .chain()
                    .after(ManifoldSystems::Sync),
            )
            .add_systems(self.schedule, gather_scenes.in_set(DrawablesSystems::Scenes));
        // Bevy's point lights in a manifold are manifold lights.
        #[cfg(feature = "render")]
        app.add_systems(self.schedule, sync_bevy_lights.before(DrawablesSystems::Scenes));
    }

    fn finish(&self, app: &mut App) {
        // Bevy meshes are traced where the app has them.
        #[cfg(feature = "render")]
        meshes::build(app, self.schedule, DrawablesSystems::Meshes);
        #[cfg(not(feature = "render"))]
        let _ = app;
    }
}

/// What [`DrawablesPlugin`] runs, in order, after the placement systems
/// ([`ManifoldSystems::Sync`]).
#[derive(SystemSet, Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DrawablesSystems {
    /// Bevy meshes under a space gathered into its [`ManifoldMeshes`]
    /// (feature `render`; BVHs built off the frame).
    Meshes,
    /// Every space's drawables gathered into its [`ManifoldScene`]
    /// ([`gather_scenes`]).
    Scenes,
}
