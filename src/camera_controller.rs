//! An optional fly camera: keyboard and mouse set a [`GeodesicVelocity`],
//! so the camera moves along geodesics and wraps like any entity (after a
//! loop around a non-trivial path its view is turned as the group says).
//!
//! | key | motion |
//! |---|---|
//! | W / S | forward / back |
//! | A / D | left / right |
//! | Space / Left Shift | up / down |
//! | Q / E | roll |
//! | arrows, mouse | yaw and pitch (the mouse only while [`FlyCamera::mouse_button`] is held, when set) |

use crate::placement::{GeodesicVelocity, ManifoldSystems};
use bevy::input::mouse::AccumulatedMouseMotion;
use bevy::prelude::*;
use glam::DVec3;

/// Adds [`fly_camera_input`], which drives every [`FlyCamera`].
#[derive(Debug, Clone, Copy, Default)]
pub struct FlyCameraPlugin;

impl Plugin for FlyCameraPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(PostUpdate, fly_camera_input.before(ManifoldSystems::Integrate));
    }
}

/// Flies an entity (usually the manifold camera) from the keyboard and mouse.
///
/// ```
/// use bevy::prelude::*;
/// use bevy_manifold::prelude::*;
/// let mut world = World::new();
/// world.spawn((FlyCamera::default(), Placement::default()));
/// ```
#[derive(Component, Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Component, Debug)]
#[require(GeodesicVelocity)]
pub struct FlyCamera {
    /// Speed in distance per second.
    pub speed: f64,
    /// Turn rate for keys, radians per second.
    pub turn_rate: f64,
    /// Radians per pixel of mouse motion.
    pub mouse_sensitivity: f64,
    /// The mouse turns the camera only while this button is held (`None`:
    /// always, for apps that grab the cursor).
    pub mouse_button: Option<MouseButton>,
}

impl Default for FlyCamera {
    fn default() -> Self {
        FlyCamera {
            speed: 0.5,
            turn_rate: 1.2,
            mouse_sensitivity: 0.003,
            mouse_button: None,
        }
    }
}

/// Turns held keys and mouse motion into each [`FlyCamera`]'s velocity.
pub fn fly_camera_input(
    time: Res<Time>,
    keys: Option<Res<ButtonInput<KeyCode>>>,
    mouse: Option<Res<AccumulatedMouseMotion>>,
    buttons: Option<Res<ButtonInput<MouseButton>>>,
    mut cameras: Query<(&FlyCamera, &mut GeodesicVelocity)>,
) {
    let held = |k: KeyCode| keys.as_ref().is_some_and(|keys| keys.pressed(k));
    let axis = |pos: KeyCode, neg: KeyCode| f64::from(u8::from(held(pos))) - f64::from(u8::from(held(neg)));
    let dt = time.delta_secs_f64();
    // Mouse motion is an angle this frame; as a rate it integrates back to
    // exactly that angle.
    let mouse_delta = mouse.map_or(Vec2::ZERO, |m| m.delta);
    for (fly, mut velocity) in &mut cameras {
        let linear = DVec3::new(
            axis(KeyCode::KeyD, KeyCode::KeyA),
            axis(KeyCode::Space, KeyCode::ShiftLeft),
            axis(KeyCode::KeyS, KeyCode::KeyW),
        );
        let mut angular = DVec3::new(
            axis(KeyCode::ArrowUp, KeyCode::ArrowDown),
            axis(KeyCode::ArrowLeft, KeyCode::ArrowRight),
            axis(KeyCode::KeyQ, KeyCode::KeyE),
        ) * fly.turn_rate;
        let looking = fly
            .mouse_button
            .is_none_or(|b| buttons.as_ref().is_some_and(|buttons| buttons.pressed(b)));
        if dt > 0.0 && looking {
            angular.x -= f64::from(mouse_delta.y) * fly.mouse_sensitivity / dt;
            angular.y -= f64::from(mouse_delta.x) * fly.mouse_sensitivity / dt;
        }
        velocity.linear = linear.normalize_or_zero() * fly.speed;
        velocity.angular = angular;
    }
}
