//! Optional camera controllers: keyboard and mouse set a
//! [`GeodesicVelocity`], so the camera moves along geodesics and wraps like
//! any entity (after a loop around a non-trivial path its view is turned as
//! the group says). [`FlyCamera`] flies freely; [`Vehicle`] rides the
//! paper's airplane, always moving forward (see its docs for its keys).
//!
//! [`FlyCamera`]'s keys:
//!
//! | key | motion |
//! |---|---|
//! | W / S | forward / back |
//! | A / D | left / right |
//! | Space / Left Shift | up / down |
//! | Q / E | roll |
//! | arrows, mouse | yaw and pitch (the mouse only while [`FlyCamera::mouse_button`] is held, when set) |
//!
//! With the `gamepad` feature every connected gamepad flies it too: the
//! left stick moves (forward, back and sideways, as far as it is pushed),
//! the right stick turns, the triggers go up (right) and down (left), the
//! bumpers roll.

use crate::placement::{GeodesicVelocity, ManifoldSystems};
use bevy::input::mouse::AccumulatedMouseMotion;
use bevy::prelude::*;
use glam::DVec3;

/// Adds [`fly_camera_input`] and [`vehicle_input`], which drive every
/// [`FlyCamera`] and [`Vehicle`].
#[derive(Debug, Clone, Copy, Default)]
pub struct FlyCameraPlugin;

impl Plugin for FlyCameraPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(
            PostUpdate,
            (fly_camera_input, vehicle_input).before(ManifoldSystems::Integrate),
        );
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

/// The mouse's turn this frame as a rate (radians per second about x and
/// y): it integrates back to exactly the angle moved. Zero unless
/// `button` (when set) is held.
fn mouse_turn(
    mouse: Option<&AccumulatedMouseMotion>,
    buttons: Option<&ButtonInput<MouseButton>>,
    button: Option<MouseButton>,
    sensitivity: f64,
    dt: f64,
) -> DVec3 {
    let looking = button.is_none_or(|b| buttons.is_some_and(|buttons| buttons.pressed(b)));
    let delta = mouse.map_or(Vec2::ZERO, |m| m.delta);
    if dt > 0.0 && looking {
        DVec3::new(-f64::from(delta.y), -f64::from(delta.x), 0.0) * sensitivity / dt
    } else {
        DVec3::ZERO
    }
}

/// Turns held keys and mouse motion into each [`FlyCamera`]'s velocity.
pub fn fly_camera_input(
    time: Res<Time>,
    keys: Option<Res<ButtonInput<KeyCode>>>,
    mouse: Option<Res<AccumulatedMouseMotion>>,
    buttons: Option<Res<ButtonInput<MouseButton>>>,
    #[cfg(feature = "gamepad")] gamepads: Query<&Gamepad>,
    mut cameras: Query<(&FlyCamera, &mut GeodesicVelocity)>,
) {
    let held = |k: KeyCode| keys.as_ref().is_some_and(|keys| keys.pressed(k));
    let axis = |pos: KeyCode, neg: KeyCode| f64::from(u8::from(held(pos))) - f64::from(u8::from(held(neg)));
    let dt = time.delta_secs_f64();
    #[cfg(feature = "gamepad")]
    let (pad_linear, pad_angular) = gamepads.iter().fold((DVec3::ZERO, DVec3::ZERO), |(l, a), pad| {
        let (ml, ma) = gamepad_motion(pad);
        (l + ml, a + ma)
    });
    #[cfg(not(feature = "gamepad"))]
    let (pad_linear, pad_angular) = (DVec3::ZERO, DVec3::ZERO);
    for (fly, mut velocity) in &mut cameras {
        let linear = DVec3::new(
            axis(KeyCode::KeyD, KeyCode::KeyA),
            axis(KeyCode::Space, KeyCode::ShiftLeft),
            axis(KeyCode::KeyS, KeyCode::KeyW),
        ) + pad_linear;
        let angular = (DVec3::new(
            axis(KeyCode::ArrowUp, KeyCode::ArrowDown),
            axis(KeyCode::ArrowLeft, KeyCode::ArrowRight),
            axis(KeyCode::KeyQ, KeyCode::KeyE),
        ) + pad_angular)
            .clamp(DVec3::splat(-1.0), DVec3::splat(1.0))
            * fly.turn_rate;
        // Keys give full speed in any direction; a stick pushed part way,
        // part of it.
        velocity.linear = linear.clamp_length_max(1.0) * fly.speed;
        velocity.angular = angular
            + mouse_turn(
                mouse.as_deref(),
                buttons.as_deref(),
                fly.mouse_button,
                fly.mouse_sensitivity,
                dt,
            );
    }
}

/// A gamepad's motion in the fly camera's terms, each component in
/// `[-1, 1]`: the linear velocity (left stick; triggers up and down) and
/// the turn (right stick pitch and yaw; bumpers roll).
#[cfg(feature = "gamepad")]
#[must_use]
pub fn gamepad_motion(pad: &Gamepad) -> (DVec3, DVec3) {
    let v = |input: GamepadAxis| f64::from(pad.get(input).unwrap_or(0.0));
    let b = |button: GamepadButton| f64::from(pad.get(button).unwrap_or(0.0));
    let linear = DVec3::new(
        v(GamepadAxis::LeftStickX),
        b(GamepadButton::RightTrigger2) - b(GamepadButton::LeftTrigger2),
        -v(GamepadAxis::LeftStickY),
    );
    let roll = f64::from(u8::from(pad.pressed(GamepadButton::LeftTrigger)))
        - f64::from(u8::from(pad.pressed(GamepadButton::RightTrigger)));
    let angular = DVec3::new(v(GamepadAxis::RightStickY), -v(GamepadAxis::RightStickX), roll);
    (linear, angular)
}

/// Rides an entity (usually the manifold camera, with the paper's vehicle
/// spawned on it: `PaperOptions { vehicle: true, .. }`) like an airplane:
/// it always moves forward (local -z) at [`Vehicle::speed`] along the
/// geodesic, wrapping through the faces, and the keys steer it.
///
/// | key | motion |
/// |---|---|
/// | W / S | faster / slower (between [`Vehicle::min_speed`] and [`Vehicle::max_speed`]) |
/// | arrows up / down | pitch |
/// | arrows left / right, A / D | yaw |
/// | Q / E | roll |
/// | mouse | pitch and yaw (only while [`Vehicle::mouse_button`] is held, when set) |
///
/// ```
/// use bevy::prelude::*;
/// use bevy_manifold::prelude::*;
/// let mut world = World::new();
/// world.spawn((Vehicle::cruising(0.3), Placement::default()));
/// ```
#[derive(Component, Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Component, Debug)]
#[require(GeodesicVelocity)]
pub struct Vehicle {
    /// Speed now, distance per second.
    pub speed: f64,
    /// Slowest (may be 0: hovering).
    pub min_speed: f64,
    /// Fastest.
    pub max_speed: f64,
    /// Speed gained or lost per second while W or S is held.
    pub throttle: f64,
    /// Turn rate for keys, radians per second.
    pub turn_rate: f64,
    /// Radians per pixel of mouse motion.
    pub mouse_sensitivity: f64,
    /// The mouse steers only while this button is held (`None`: always).
    pub mouse_button: Option<MouseButton>,
}

impl Vehicle {
    /// A vehicle at `speed`, between a tenth of it and three times it,
    /// reaching either in about two seconds of throttle.
    #[must_use]
    pub fn cruising(speed: f64) -> Self {
        let speed = if speed.is_finite() { speed.abs() } else { 0.0 };
        Vehicle {
            speed,
            min_speed: 0.1 * speed,
            max_speed: 3.0 * speed,
            throttle: 1.5 * speed,
            turn_rate: 0.8,
            mouse_sensitivity: 0.003,
            mouse_button: None,
        }
    }
}

impl Default for Vehicle {
    fn default() -> Self {
        Vehicle::cruising(0.3)
    }
}

/// Sets each [`Vehicle`]'s speed from the throttle keys and its velocity
/// from its speed and the steering keys and mouse.
pub fn vehicle_input(
    time: Res<Time>,
    keys: Option<Res<ButtonInput<KeyCode>>>,
    mouse: Option<Res<AccumulatedMouseMotion>>,
    buttons: Option<Res<ButtonInput<MouseButton>>>,
    mut vehicles: Query<(&mut Vehicle, &mut GeodesicVelocity)>,
) {
    let held = |k: KeyCode| keys.as_ref().is_some_and(|keys| keys.pressed(k));
    let axis = |pos: &[KeyCode], neg: &[KeyCode]| {
        f64::from(u8::from(pos.iter().any(|&k| held(k)))) - f64::from(u8::from(neg.iter().any(|&k| held(k))))
    };
    let dt = time.delta_secs_f64();
    for (mut vehicle, mut velocity) in &mut vehicles {
        let throttle = axis(&[KeyCode::KeyW], &[KeyCode::KeyS]);
        if throttle != 0.0 && dt > 0.0 {
            let v = &mut *vehicle;
            let lo = v.min_speed.min(v.max_speed);
            v.speed = (v.speed + throttle * v.throttle * dt).clamp(lo, v.max_speed.max(lo));
        }
        let angular = DVec3::new(
            axis(&[KeyCode::ArrowUp], &[KeyCode::ArrowDown]),
            axis(
                &[KeyCode::ArrowLeft, KeyCode::KeyA],
                &[KeyCode::ArrowRight, KeyCode::KeyD],
            ),
            axis(&[KeyCode::KeyQ], &[KeyCode::KeyE]),
        ) * vehicle.turn_rate;
        velocity.linear = DVec3::NEG_Z * vehicle.speed;
        velocity.angular = angular
            + mouse_turn(
                mouse.as_deref(),
                buttons.as_deref(),
                vehicle.mouse_button,
                vehicle.mouse_sensitivity,
                dt,
            );
    }
}
