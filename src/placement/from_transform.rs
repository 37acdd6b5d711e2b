//! A Bevy `Transform` read as a [`Placement`]: what an entity means when it
//! arrives under a [`ManifoldSpace`] root with a transform and no
//! placement, as every existing Bevy scene spawns its entities.
//!
//! The translation `t` is a tangent vector at the origin, followed along
//! its geodesic (the exponential map): the entity lands at geodesic
//! distance `|t|` in the direction of `t`, so the distances a scene's
//! author wrote stay distances in H3 and S3 (in E3 nothing changes). The
//! rotation is the entity's frame there (parallel transported along that
//! geodesic); a scale with an odd number of negative axes is a mirror
//! image. The scale itself stays in the `Transform` (meshes are drawn
//! scaled by it, each axis by its own). After that the placement is the truth, wrapped into
//! the domain like any other, and the placement systems write the chart
//! position back into the `Transform` ([`super::sync_transforms`]).
//!
//! ```
//! use bevy::prelude::*;
//! use bevy_manifold::prelude::*;
//!
//! let mut app = App::new();
//! app.add_plugins((MinimalPlugins, PlacementPlugin::default()));
//! let space = catalog::seifert_weber();
//! let g = space.geometry();
//! let root = app.world_mut().spawn(ManifoldSpace::new(space)).id();
//! // As a Bevy scene would spawn it: a transform, no placement.
//! let cube = app.world_mut().spawn((ChildOf(root), Transform::from_xyz(0.0, 0.5, 0.0))).id();
//! app.update();
//! let p = app.world().get::<Placement>(cube).unwrap();
//! // Half a unit from the centre along +y, measured along the geodesic.
//! assert!((g.distance::<f64>(glam::DVec4::W, p.position()) - 0.5).abs() < 1e-6);
//! ```

use super::components::{ManifoldSpace, Placement};
use super::membership::InSpace;
use super::tracked::TrackedPose;
use crate::geometry::isometry;
use bevy::prelude::*;
use bevy_manifold_core::space::Space;
use glam::{DMat3, DMat4};

impl Placement {
    /// The placement a Bevy `Transform` means directly under a space's
    /// root: its translation followed from the origin along the geodesic
    /// (the exponential map), its rotation as the frame there, mirrored
    /// when its scale turns an odd number of axes over. The scale is not
    /// part of a placement (it stays in the `Transform`).
    ///
    /// ```
    /// use bevy::prelude::*;
    /// use bevy_manifold::prelude::*;
    /// let h = catalog::seifert_weber();
    /// let p = Placement::from_transform(&h, &Transform::from_xyz(1.2, 0.0, 0.0));
    /// // Geodesic distance 1.2, so chart distance tanh 1.2.
    /// assert!((p.position().x / p.position().w - 1.2f64.tanh()).abs() < 1e-6);
    /// ```
    #[must_use]
    pub fn from_transform(space: &Space, transform: &Transform) -> Self {
        let g = space.geometry();
        let mut frame = DMat3::from_quat(transform.rotation.normalize().as_dquat());
        if turns_over(transform) {
            // As `sync_transforms` writes a mirror image: x turned over.
            frame.x_axis = -frame.x_axis;
        }
        let to = isometry::translation(g, transform.translation.as_dvec3());
        Placement::from_isometry(isometry::orthonormalize(g, to * DMat4::from_mat3(frame)))
    }
}

/// Whether a transform's scale turns an odd number of axes over (a mirror
/// image, as `sync_transforms` writes one).
fn turns_over(transform: &Transform) -> bool {
    transform.scale.x * transform.scale.y * transform.scale.z < 0.0
}

/// The observer: an entity that joins a space as a child of the root, with
/// a `Transform` that moves or turns it and no placement of its own (none,
/// or the identity a required component put there), takes the placement
/// its transform means ([`Placement::from_transform`]). Entities a tracker
/// writes ([`TrackedPose`]), those Bevy rasterises in the chart
/// (`Rasterized`), and those below a placed entity (positioned relative to
/// it) keep their transforms as they are.
pub(super) fn place_from_transform(
    event: On<Insert, InSpace>,
    entities: Query<(&InSpace, &ChildOf, &Transform, Option<&Placement>), Without<TrackedPose>>,
    #[cfg(feature = "render")] rasterized: Query<(), With<crate::drawables::Rasterized>>,
    spaces: Query<&ManifoldSpace>,
    mut commands: Commands,
) {
    let entity = event.event_target();
    #[cfg(feature = "render")]
    if rasterized.contains(entity) {
        return;
    }
    let Ok((in_space, parent, transform, placement)) = entities.get(entity) else {
        return;
    };
    let root = in_space.space();
    let unplaced = placement.is_none_or(|p| *p == Placement::default());
    let moved = transform.translation != Vec3::ZERO || transform.rotation != Quat::IDENTITY || turns_over(transform);
    if parent.parent() != root || !unplaced || !moved {
        return;
    }
    let Ok(ms) = spaces.get(root) else {
        return;
    };
    let placement = Placement::from_transform(ms.space(), transform);
    if placement.isometry.is_finite() {
        commands.entity(entity).insert(placement);
    } else {
        warn!("bevy_manifold: entity {entity}'s Transform is not finite: it stays at the origin");
    }
}
