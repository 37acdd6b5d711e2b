//! The tracked body in the manifold: the hands on the controllers' grips
//! ([`XrHand`]), and moving the whole room with the thumbsticks
//! ([`XrLocomotion`]): flight along geodesics through the head, snap
//! turns about the head's vertical, and a reset to the start.
//!
//! Everything moves as one rigid body ([`crate::placement::tracked`]):
//! flying and turning move the room (the [`super::XrBody`]'s placement);
//! the head, eyes and hands follow from it by their tracked offsets.

use super::controls::{XrControllers, XrHandSide};
use super::{XrBody, XrHead};
use crate::geometry::isometry;
use crate::placement::tracked;
use crate::placement::{DomainCell, InSpace, ManifoldSpace, Placement, WrapOrigin};
use bevy::prelude::*;
use glam::{DMat4, DVec3};

/// A hand that follows its controller's grip (put the hand's meshes below
/// it, or a [`crate::drawables::TracedBall`] on it): placed each frame from the head by the grip's offset,
/// so it appears where the hand is felt. Put it under the
/// [`crate::placement::ManifoldSpace`] root, next to the [`XrBody`].
///
/// ```no_run
/// use bevy::prelude::*;
/// use bevy_manifold::prelude::*;
/// use bevy_manifold::xr::{XrHand, XrHandSide};
///
/// fn hands(mut commands: Commands, root: Entity) {
///     for side in XrHandSide::BOTH {
///         // A ball in the hand; a hand mesh would be a child with its scale.
///         commands.spawn((ChildOf(root), XrHand(side), TracedBall::new(0.02, Color::srgb(0.9, 0.7, 0.5))));
///     }
/// }
/// # let _ = hands;
/// ```
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq, Reflect)]
#[reflect(Component, Debug)]
#[require(Placement, DomainCell, WrapOrigin)]
pub struct XrHand(pub XrHandSide);

/// How the thumbsticks move the room: the left stick flies the head along
/// geodesics (forward where the head faces, level with the floor), the
/// right stick's y flies up and down, its x snap-turns about the head;
/// the secondary button (B, Y, or the menu button) puts the room back at
/// the start of the domain. On the [`XrBody`]'s entity (added with it).
#[derive(Component, Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Component, Debug, Default)]
pub struct XrLocomotion {
    /// Speed at full stick, in units of the space per second.
    pub speed: f64,
    /// One snap turn, in degrees (0: no snap turns).
    pub snap_turn_degrees: f64,
    /// Off: the sticks move nothing (a game reads [`XrControllers`] itself).
    pub enabled: bool,
}

impl Default for XrLocomotion {
    fn default() -> Self {
        XrLocomotion {
            speed: 0.3,
            snap_turn_degrees: 30.0,
            enabled: true,
        }
    }
}

/// A stick past this turns once; it turns again after coming back inside
/// [`SNAP_REARM`].
pub const SNAP_AT: f32 = 0.7;
/// See [`SNAP_AT`].
pub const SNAP_REARM: f32 = 0.3;
/// Stick travel ignored around the centre.
pub const DEAD_ZONE: f32 = 0.15;

/// The room's move this frame, in the body's frame: a transport along the
/// geodesic through the head of the stick's direction (turned to the
/// head's yaw, level with the floor), then a snap turn about the head's
/// vertical. `head_room` is the head's pose in the room; `turn` the snap
/// turn in radians (positive: to the left).
#[must_use]
pub fn room_move(
    g: crate::geometry::Geometry,
    head_room: (DVec3, glam::DQuat),
    stick: DVec3,
    distance: f64,
    turn: f64,
    scale: f64,
) -> DMat4 {
    // The head's position with the body's axes: fly and turn about it.
    let at = isometry::translation(g, head_room.0 / scale);
    let forward = head_room.1 * DVec3::NEG_Z;
    let yaw = f64::atan2(-forward.x, -forward.z);
    let turn_to_head = glam::DQuat::from_rotation_y(yaw);
    let step = if stick.length_squared() > 0.0 && distance > 0.0 {
        isometry::translation(g, turn_to_head * stick.clamp_length_max(1.0) * distance)
    } else {
        DMat4::IDENTITY
    };
    let spin = DMat4::from_quat(glam::DQuat::from_rotation_y(turn));
    at * step * spin * isometry::inverse(g, at)
}

/// What the sticks ask of the room this frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum RoomAsk {
    /// Nothing.
    Stay,
    /// Back to the start of the domain.
    Reset,
    /// A flight (the stick, in the head's level frame) and a snap turn
    /// (radians, positive to the left).
    Move { stick: DVec3, turn: f64 },
}

/// Reads the sticks as [`XrLocomotion`] says (`armed`: whether a snap
/// turn and a reset may fire, each re-armed once let go).
pub(super) fn read_sticks(controllers: &XrControllers, motion: &XrLocomotion, armed: &mut (bool, bool)) -> RoomAsk {
    let (turn_armed, reset_armed) = (&mut armed.0, &mut armed.1);
    let left = controllers.hand(XrHandSide::Left);
    let right = controllers.hand(XrHandSide::Right);
    let reset = left.secondary || right.secondary;
    if !motion.enabled {
        return RoomAsk::Stay;
    }
    if reset && *reset_armed {
        *reset_armed = false;
        return RoomAsk::Reset;
    }
    *reset_armed = !reset;
    let dead = |v: f32| if v.abs() < DEAD_ZONE { 0.0 } else { f64::from(v) };
    let stick = DVec3::new(dead(left.stick.x), dead(right.stick.y), -dead(left.stick.y));
    let mut turn = 0.0;
    if right.stick.x.abs() >= SNAP_AT && *turn_armed && motion.snap_turn_degrees != 0.0 {
        *turn_armed = false;
        turn = -f64::from(right.stick.x.signum()) * motion.snap_turn_degrees.to_radians();
    } else if right.stick.x.abs() <= SNAP_REARM {
        *turn_armed = true;
    }
    if stick == DVec3::ZERO && turn == 0.0 {
        RoomAsk::Stay
    } else {
        RoomAsk::Move { stick, turn }
    }
}

/// Reads the sticks and moves the room.
pub(super) fn locomotion(
    time: Res<Time>,
    controllers: Res<XrControllers>,
    spaces: Query<&ManifoldSpace>,
    mut bodies: Query<(
        &XrBody,
        &XrLocomotion,
        &XrHead,
        &InSpace,
        &mut Placement,
        &mut DomainCell,
        &mut WrapOrigin,
    )>,
    mut armed: Local<Option<(bool, bool)>>,
) {
    let Ok((body, motion, head, in_space, mut placement, mut cell, mut origin)) = bodies.single_mut() else {
        return;
    };
    let armed = armed.get_or_insert((true, true));
    let (stick, turn) = match read_sticks(&controllers, motion, armed) {
        RoomAsk::Stay => return,
        RoomAsk::Reset => {
            placement.set_if_neq(Placement::default());
            cell.set_if_neq(DomainCell::default());
            origin.0 = Some(DMat4::IDENTITY);
            return;
        }
        RoomAsk::Move { stick, turn } => (stick, turn),
    };
    let Ok(ms) = spaces.get(in_space.space()) else { return };
    let distance = motion.speed * time.delta_secs_f64();
    let g = ms.space().geometry();
    let moved = room_move(g, head.room, stick, distance, turn, body.world_scale);
    // The wrap system carries the new placement back through the faces.
    placement.isometry = isometry::orthonormalize(g, placement.isometry * moved);
}

/// Where a hand rests when its controller is not tracked: low in front
/// of the head, to its side.
#[must_use]
pub fn rest_pose(head_room: (DVec3, glam::DQuat), side: XrHandSide) -> (Vec3, Quat) {
    let x = if side == XrHandSide::Left { -0.18 } else { 0.18 };
    (
        (head_room.0 + head_room.1 * DVec3::new(x, -0.3, -0.35)).as_vec3(),
        head_room.1.as_quat(),
    )
}

/// Places each hand from the head by its grip's offset (or at its
/// [`rest_pose`] while the controller is not tracked).
pub(super) fn place_hands(
    controllers: Res<XrControllers>,
    bodies: Query<(&XrBody, &Placement, &DomainCell, &XrHead, &InSpace), Without<XrHand>>,
    spaces: Query<&ManifoldSpace>,
    mut hands: Query<(&XrHand, &mut Placement, &mut DomainCell, &mut WrapOrigin), Without<XrBody>>,
) {
    let Ok((body, placement, cell, head, in_space)) = bodies.single() else {
        return;
    };
    let Ok(ms) = spaces.get(in_space.space()) else { return };
    let g = ms.space().geometry();
    let head_iso = tracked::pose_isometry(g, placement.isometry, head.room.0, head.room.1, body.world_scale);
    for (hand, mut p, mut c, mut origin) in &mut hands {
        let grip = match controllers.hand(hand.0).grip {
            Some((t, q)) => (t - head.recentred, q),
            None => rest_pose(head.room, hand.0),
        };
        let to = tracked::from_head(g, head_iso, head.room, grip, body.world_scale);
        if !to.is_finite() {
            continue;
        }
        let (np, nc) = tracked::tracked_placement(ms, placement, cell, to);
        origin.0 = Some(np.isometry);
        p.set_if_neq(np);
        c.set_if_neq(nc);
    }
}
