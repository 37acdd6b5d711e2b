//! Tracked poses (a headset's eyes, its controllers) carried into the
//! manifold: a tracker measures them in metres in its own Euclidean
//! tracking space; here they become placements reached from a body's
//! placement along geodesics, wrapped into the domain.
//!
//! The rule, after Jeff Weeks' "Body coherence in curved-space virtual
//! reality games" (arXiv 2011.00510): one rigid body carries the whole
//! tracking space, so holonomy turns head and hands together; the head is
//! reached from the body by the geodesic of its tracked offset, and each
//! eye and hand from the head by the geodesic of its offset in the head's
//! own frame. What the eyes see of a hand then matches where the hand is
//! felt: both are measured from the head, as in the room.
//!
//! ```
//! use bevy_manifold::placement::{Placement, tracked};
//! use bevy_manifold::space::catalog;
//! use glam::{DQuat, DVec3};
//!
//! let sw = catalog::seifert_weber();
//! let g = sw.geometry();
//! let body = Placement::default().isometry;
//! // The head 1.6 m up, at 10 m of tracking space per unit of the space.
//! let head = tracked::pose_isometry(g, body, DVec3::Y * 1.6, DQuat::IDENTITY, 10.0);
//! let up = g.distance::<f64>(body.w_axis, head.w_axis);
//! assert!((up - 0.16).abs() < 1e-12);
//! ```

use super::components::{DomainCell, ManifoldSpace, Placement};
use super::systems::MAX_CROSSINGS_PER_STEP;
use crate::geometry::{Geometry, isometry};
use crate::motion::move_placement;
use crate::space::FaceKind;
use crate::space::product::ProductSpace;
use crate::trace::product::ProductView;
use bevy::prelude::*;
use glam::{DMat4, DQuat, DVec3};

/// Marks an entity whose `Transform` a tracker writes (an XR eye or
/// controller, in metres of tracking space): the placement systems leave
/// that `Transform` alone, and its [`Placement`] is set from the pose (see
/// [`tracked_placement`]) rather than the other way round.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Eq, Reflect)]
#[reflect(Component, Default)]
pub struct TrackedPose;

/// The isometry of a pose measured from `anchor`: the geodesic of the
/// tangent `translation / scale` in the anchor's frame, then the turn
/// `rotation` (`scale`: metres of tracking space per unit of the space).
#[must_use]
pub fn pose_isometry(g: Geometry, anchor: DMat4, translation: DVec3, rotation: DQuat, scale: f64) -> DMat4 {
    anchor * isometry::translation(g, translation / scale) * DMat4::from_quat(rotation)
}

/// A head and its two eyes (or any poses measured in one tracking space):
/// the head where the two eyes' midpoint is, facing as the first eye does,
/// reached from `body`; each eye reached from the head by its offset in
/// the head's frame. Returns the head, then the eyes.
#[must_use]
pub fn head_and_eyes(g: Geometry, body: DMat4, eyes: [(Vec3, Quat); 2], scale: f64) -> (DMat4, [DMat4; 2]) {
    let room = head_in_room(eyes);
    let head = pose_isometry(g, body, room.0, room.1, scale);
    let eye = |(t, q): (Vec3, Quat)| from_head(g, head, room, (t, q), scale);
    (head, [eye(eyes[0]), eye(eyes[1])])
}

/// The head's pose in the room: the eyes' midpoint, facing as the first
/// eye does (in `f64`, normalised).
#[must_use]
pub fn head_in_room(eyes: [(Vec3, Quat); 2]) -> (DVec3, DQuat) {
    (
        (eyes[0].0.as_dvec3() + eyes[1].0.as_dvec3()) / 2.0,
        eyes[0].1.as_dquat().normalize(),
    )
}

/// A pose measured in the room (an eye, a controller's grip) placed from
/// the head (`head`, whose room pose is `head_room`) by the geodesic of
/// its offset in the head's frame: what [`head_and_eyes`] does for the
/// eyes, for anything else the tracker follows.
#[must_use]
pub fn from_head(g: Geometry, head: DMat4, head_room: (DVec3, DQuat), pose: (Vec3, Quat), scale: f64) -> DMat4 {
    let back = head_room.1.inverse();
    let offset = back * (pose.0.as_dvec3() - head_room.0);
    pose_isometry(g, head, offset, back * pose.1.as_dquat().normalize(), scale)
}

/// [`head_and_eyes`] in a product space (H2xR, S2xR): the head's view
/// reached from the body's `body` along the geodesic of its tracked
/// offset, each eye's from the head's by its offset in the head's frame
/// ([`ProductView::posed`], through the faces). Returns the head's view,
/// then the eyes'.
///
/// ```
/// use bevy::prelude::*;
/// use bevy_manifold::placement::tracked;
/// use bevy_manifold::space::product::ProductSpace;
/// use bevy_manifold::trace::product::ProductScene;
///
/// let space = ProductSpace::genus_two_x_s1(2.0);
/// let body = ProductScene::default_for(&space).view;
/// // Eyes 64 mm apart, 1.6 m up, at 4 m per unit of the space.
/// let eyes = [-0.032, 0.032].map(|x| (Vec3::new(x, 1.6, 0.0), Quat::IDENTITY));
/// let (head, [left, right]) = tracked::product_head_and_eyes(&space, &body, eyes, 4.0);
/// let g = space.geometry;
/// assert!((g.distance(body.eye, head.eye) - 0.4).abs() < 1e-6);
/// assert!((g.distance(left.eye, right.eye) - 0.016).abs() < 1e-6);
/// ```
#[must_use]
pub fn product_head_and_eyes(
    space: &ProductSpace,
    body: &ProductView,
    eyes: [(Vec3, Quat); 2],
    scale: f64,
) -> (ProductView, [ProductView; 2]) {
    let room = head_in_room(eyes);
    let head = body.posed(space, room.0, room.1, scale);
    let back = room.1.inverse();
    let eye = |(t, q): (Vec3, Quat)| {
        head.posed(
            space,
            back * (t.as_dvec3() - room.0),
            back * q.as_dquat().normalize(),
            scale,
        )
    };
    (head, [eye(eyes[0]), eye(eyes[1])])
}

/// Where the pose `to` (reached from `from`, inside the domain) lies in
/// the domain: carried back through the faces on the geodesic between
/// them, the cell and parity following each face crossed.
#[must_use]
pub fn tracked_placement(
    ms: &ManifoldSpace,
    from: &Placement,
    cell: &DomainCell,
    to: DMat4,
) -> (Placement, DomainCell) {
    let space = ms.space();
    let moved = move_placement(space, ms.tables(), from.isometry, to, MAX_CROSSINGS_PER_STEP);
    let mut placement = Placement {
        isometry: moved.placement,
        mirrored: from.mirrored,
    };
    let mut cell = cell.clone();
    for &face in &moved.faces {
        cell = DomainCell::new(space, space.cross_cell(&cell.cell, face));
        if space.faces()[face].kind == FaceKind::Mirror {
            placement.mirrored = !placement.mirrored;
        }
    }
    (placement, cell)
}
