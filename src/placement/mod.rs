//! Entities that live in a manifold: placement, cells, motion along
//! geodesics, wrapping through the face pairings, gameplay ray casts.
//!
//! Add [`PlacementPlugin`] (or the umbrella [`crate::ManifoldPlugins`]), put
//! a [`ManifoldSpace`] on a root entity and give its descendants a
//! [`Placement`]:
//!
//! ```
//! use bevy::prelude::*;
//! use bevy_manifold::prelude::*;
//! use glam::DVec3;
//! use std::time::Duration;
//!
//! let mut app = App::new();
//! app.add_plugins((MinimalPlugins, PlacementPlugin::default()));
//! app.insert_resource(bevy::time::TimeUpdateStrategy::ManualDuration(Duration::from_millis(100)));
//! let root = app.world_mut().spawn(ManifoldSpace::new(catalog::torus(1.0))).id();
//! let ship = app
//!     .world_mut()
//!     .spawn((ChildOf(root), GeodesicVelocity { linear: DVec3::X * 2.0, ..default() }))
//!     .id();
//! for _ in 0..6 {
//!     app.update();
//! }
//! // Still inside the unit cube, but in another copy of it.
//! let p = app.world().get::<Placement>(ship).unwrap();
//! assert!(p.position().x.abs() <= 0.5);
//! assert_ne!(app.world().get::<DomainCell>(ship).unwrap().id, CellId(0));
//! ```

mod components;
mod contact;
mod from_transform;
mod membership;
mod raycast;
mod systems;
pub mod tracked;

pub use components::{
    DomainCell, FaceCrossed, GeodesicVelocity, ManifoldCollider, ManifoldSpace, Placement, WallHit, WrapOrigin,
};
pub use contact::{ContactEnded, ContactEvents, ContactStarted, ManifoldContacts, Overlap, Touching, detect_contacts};
pub use membership::{InSpace, SpaceMembers};
pub use raycast::{ManifoldRayCast, RayCastSettings, RayHit};
pub use systems::{MAX_CROSSINGS_PER_STEP, integrate_velocities, sync_transforms, wrap_placements};
pub use tracked::TrackedPose;

use bevy::ecs::schedule::{InternedScheduleLabel, ScheduleLabel};
use bevy::prelude::*;
use bevy::transform::TransformSystems;

/// The placement systems, in the order they run (each set after the one
/// before it).
#[derive(SystemSet, Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ManifoldSystems {
    /// Move entities with a [`GeodesicVelocity`] along geodesics.
    Integrate,
    /// Carry entities that left the domain back through the faces they
    /// crossed; update [`DomainCell`] and parity; re-orthonormalise; send
    /// [`FaceCrossed`].
    Wrap,
    /// Find the contacts of colliders with [`ContactEvents`]; send
    /// [`ContactStarted`] and [`ContactEnded`].
    Contacts,
    /// Write chart positions into `Transform` (before Bevy propagates
    /// transforms).
    Sync,
}

/// Places, moves and wraps entities in their manifolds. Runs in
/// `PostUpdate` by default, so game code in `Update` sets velocities and
/// placements and sees them wrapped the next frame; use
/// [`PlacementPlugin::in_schedule`] for `FixedPostUpdate` and the like.
#[derive(Debug, Clone)]
pub struct PlacementPlugin {
    schedule: InternedScheduleLabel,
}

impl Default for PlacementPlugin {
    fn default() -> Self {
        Self::in_schedule(PostUpdate)
    }
}

impl PlacementPlugin {
    /// The plugin with its systems in `schedule`.
    #[must_use]
    pub fn in_schedule(schedule: impl ScheduleLabel) -> Self {
        PlacementPlugin {
            schedule: schedule.intern(),
        }
    }
}

impl Plugin for PlacementPlugin {
    fn build(&self, app: &mut App) {
        membership::observe(app);
        app.add_observer(from_transform::place_from_transform);
        app.add_message::<FaceCrossed>()
            .add_message::<WallHit>()
            .add_message::<ContactStarted>()
            .add_message::<ContactEnded>()
            .init_resource::<Touching>()
            .register_type::<ContactEvents>()
            .register_type::<Placement>()
            .register_type::<DomainCell>()
            .register_type::<GeodesicVelocity>()
            .register_type::<ManifoldCollider>()
            .register_type::<TrackedPose>()
            .configure_sets(
                self.schedule,
                (
                    ManifoldSystems::Integrate,
                    ManifoldSystems::Wrap,
                    ManifoldSystems::Contacts,
                    ManifoldSystems::Sync,
                )
                    .chain()
                    .before(TransformSystems::Propagate),
            )
            .add_systems(
                self.schedule,
                (
                    integrate_velocities.in_set(ManifoldSystems::Integrate),
                    wrap_placements.in_set(ManifoldSystems::Wrap),
                    detect_contacts.in_set(ManifoldSystems::Contacts),
                    sync_transforms.in_set(ManifoldSystems::Sync),
                ),
            );
    }
}
