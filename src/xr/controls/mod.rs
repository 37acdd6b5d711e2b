//! The controllers, as a resource any system can read: grip poses
//! (metres, in the room), thumbsticks, triggers and buttons
//! ([`XrControllers`]), and the trigger as an action ([`XrTrigger`], a
//! message sent when it is pulled or let go). [`actions`] fills them from
//! OpenXR; a test or a desktop stand-in can write the resource itself.

pub mod actions;

use bevy::prelude::*;

/// Which hand.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Reflect)]
pub enum XrHandSide {
    /// The left hand (index 0).
    Left,
    /// The right hand (index 1).
    Right,
}

impl XrHandSide {
    /// Both, left first.
    pub const BOTH: [XrHandSide; 2] = [XrHandSide::Left, XrHandSide::Right];

    /// 0 for the left hand, 1 for the right.
    #[must_use]
    pub fn index(self) -> usize {
        match self {
            XrHandSide::Left => 0,
            XrHandSide::Right => 1,
        }
    }
}

/// One controller this frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct XrController {
    /// The grip's pose in the room (metres, the tracking space's axes),
    /// when the runtime knows it.
    pub grip: Option<(Vec3, Quat)>,
    /// The thumbstick (or trackpad), each axis in [-1, 1], +y away from
    /// the user.
    pub stick: Vec2,
    /// How far the trigger is pulled, in [0, 1].
    pub trigger: f32,
    /// The primary face button (A on the right, X on the left; the
    /// trackpad's click on controllers without one).
    pub primary: bool,
    /// The secondary face button (B, Y; the menu button where there is
    /// none).
    pub secondary: bool,
}

/// Both controllers, left then right ([`XrHandSide::index`]).
///
/// ```
/// use bevy::prelude::*;
/// use bevy_manifold::xr::{XrControllers, XrHandSide};
///
/// fn fire(controllers: Res<XrControllers>) {
///     let right = controllers.hand(XrHandSide::Right);
///     if right.trigger > 0.9 {
///         // fire from right.grip ...
///     }
/// }
/// # let _ = fire;
/// ```
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq)]
pub struct XrControllers {
    /// Left, right.
    pub hands: [XrController; 2],
}

impl XrControllers {
    /// The controller in `side`'s hand.
    #[must_use]
    pub fn hand(&self, side: XrHandSide) -> &XrController {
        &self.hands[side.index()]
    }
}

/// The trigger as an action: sent when a trigger is pulled past
/// [`TRIGGER_PULLED`] (`pulled: true`) and when it is let go below
/// [`TRIGGER_RELEASED`] (`pulled: false`); the gap keeps a trigger held
/// near the threshold from firing twice.
#[derive(Message, Clone, Copy, Debug, PartialEq, Eq)]
pub struct XrTrigger {
    /// The hand.
    pub hand: XrHandSide,
    /// Pulled or let go.
    pub pulled: bool,
}

/// How far a trigger is pulled before [`XrTrigger`] says so.
pub const TRIGGER_PULLED: f32 = 0.75;
/// How far a pulled trigger is let go before [`XrTrigger`] says so.
pub const TRIGGER_RELEASED: f32 = 0.35;

/// Sends [`XrTrigger`] on each trigger's edges.
pub(super) fn trigger_edges(
    controllers: Res<XrControllers>,
    mut held: Local<[bool; 2]>,
    mut triggers: MessageWriter<XrTrigger>,
) {
    for side in XrHandSide::BOTH {
        let value = controllers.hand(side).trigger;
        let was = &mut held[side.index()];
        let now = if *was {
            value > TRIGGER_RELEASED
        } else {
            value >= TRIGGER_PULLED
        };
        if now != *was {
            *was = now;
            triggers.write(XrTrigger {
                hand: side,
                pulled: now,
            });
        }
    }
}
