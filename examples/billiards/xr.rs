//! Billiards in a headset (`--xr`; the plugin's `xr` feature): the player
//! is the room's body (`XrBody`), recentred on the head (`XrRecentre`) so
//! the eyes start behind the cue ball; each eye is traced from where it is,
//! and the hands are the cues. Each hand is a small traced ball on its
//! controller's grip (`XrHand`); when it touches the cue ball (any image
//! of it, through the faces) and moves into it, the cue ball bounces off
//! it as off an infinitely heavy paddle ([`crate::table::collide`]). What
//! the eyes see the hand touch is what moves: Weeks' body coherence. The
//! sticks fly the room around the table (the plugin's `XrLocomotion`).

use crate::table::{Ball, Table, TableEvent, collide};
use bevy::prelude::*;
use bevy_manifold::contact;
use bevy_manifold::geometry::{Geometry, isometry};
use bevy_manifold::prelude::*;
use bevy_manifold::xr::{ManifoldXrPlugin, XrBody, XrHand, XrHandSide, XrRecentre, XrState, save_eyes_at};
use glam::{DMat4, DVec3};

/// Adds the headset to the table (after `bevy_mod_openxr::add_xr_plugins`).
pub struct BilliardsXrPlugin {
    /// Metres of the room per unit of the space.
    pub world_scale: f64,
    /// `--xr-capture`: at this frame, read both eyes back and save them as
    /// `eye0.png` and `eye1.png` in this folder.
    pub capture: Option<(u32, std::path::PathBuf)>,
}

#[derive(Resource, Clone, Copy)]
struct WorldScale(f64);

impl Plugin for BilliardsXrPlugin {
    fn build(&self, app: &mut App) {
        if let Some((at, dir)) = self.capture.clone() {
            app.add_systems(Last, save_eyes_at(at, dir));
        }
        app.insert_resource(WorldScale(self.world_scale))
            .add_plugins(ManifoldXrPlugin)
            .add_systems(Startup, say_if_unavailable)
            .add_systems(Update, body_and_hands)
            .add_systems(
                FixedPostUpdate,
                hands_strike
                    .run_if(resource_exists::<Table>)
                    .before(ManifoldSystems::Integrate),
            );
    }
}

fn say_if_unavailable(state: Option<Res<XrState>>) {
    if state.is_some_and(|s| *s == XrState::Unavailable) {
        println!("xr: no OpenXR runtime answered; playing on the desktop");
    }
}

/// A hand as a cue: its radius, where it was at the last tick, and
/// whether it is touching the cue ball (a touch strikes once).
#[derive(Component, Clone, Copy, Debug, Default)]
pub struct Paddle {
    /// Its ball's radius.
    pub radius: f64,
    /// Its isometry at the last tick.
    pub last: Option<DMat4>,
    /// It touched the cue ball at the last tick.
    pub touching: bool,
}

/// The player carries the room; each table gets two hands.
fn body_and_hands(
    mut commands: Commands,
    scale: Res<WorldScale>,
    table: Option<Res<Table>>,
    bodies: Query<(), With<XrBody>>,
    hands: Query<&ChildOf, With<XrHand>>,
) {
    let Some(table) = table else { return };
    if !bodies.contains(table.player) {
        // The room recentred on the head: the eyes start where the
        // desktop player does, looking at the cue ball.
        commands
            .entity(table.player)
            .insert((XrBody { world_scale: scale.0 }, XrRecentre::default()));
    }
    if hands.iter().any(|c| c.parent() == table.root) {
        return;
    }
    let radius = 0.8 * table.rules.ball_radius;
    for side in XrHandSide::BOTH {
        commands.spawn((
            ChildOf(table.root),
            XrHand(side),
            Paddle { radius, ..default() },
            TracedBall::new(radius, Color::srgb(0.9, 0.7, 0.55)),
        ));
    }
}

/// The hand's velocity in its own frame over the last tick, from where it
/// was and where it is (the twist between them, per second); `None` on
/// the first tick and when the hand jumped (the room was put back, or the
/// hand was wrapped through a face between the two).
#[must_use]
pub fn hand_velocity(g: Geometry, last: DMat4, now: DMat4, dt: f64, max_speed: f64) -> Option<DVec3> {
    let (v, _) = isometry::log_twist(g, isometry::inverse(g, last) * now)?;
    let v = v / dt;
    (dt > 0.0 && v.is_finite() && v.length() <= max_speed).then_some(v)
}

/// A hand moving into the cue ball strikes it.
fn hands_strike(
    mut table: ResMut<Table>,
    time: Res<Time>,
    spaces: Query<&ManifoldSpace>,
    mut hands: Query<(&Placement, &mut Paddle)>,
    mut balls: Query<(&Placement, &mut GeodesicVelocity), With<Ball>>,
) {
    let Ok(ms) = spaces.get(table.root) else { return };
    let space = ms.space();
    let g = space.geometry();
    let dt = time.delta_secs_f64();
    let rules = table.rules;
    let cue_ball = table.cue_ball;
    for (hand, mut paddle) in &mut hands {
        let velocity = paddle
            .last
            .and_then(|last| hand_velocity(g, last, hand.isometry, dt, 20.0 * rules.max_speed));
        paddle.last = Some(hand.isometry);
        let Ok((ball, mut ball_velocity)) = balls.get_mut(cue_ball) else {
            continue;
        };
        let touches = contact::ball_contacts(
            space,
            (ball.position(), rules.ball_radius),
            (hand.position(), paddle.radius),
        );
        let was_touching = std::mem::replace(&mut paddle.touching, !touches.is_empty());
        let (Some(touch), Some(v)) = (touches.first(), velocity) else {
            continue;
        };
        let image = touch.image.element * hand.isometry;
        if let Some((after, _)) = collide(g, (ball.isometry, ball_velocity.linear), (image, v), true) {
            // No faster than a full stroke.
            ball_velocity.linear = after.clamp_length_max(rules.max_speed);
            if !was_touching {
                table.strokes += 1;
                let speed = ball_velocity.linear.length();
                let tick = table.tick;
                table.log.push((tick, TableEvent::Struck { speed }));
            }
        }
    }
}
