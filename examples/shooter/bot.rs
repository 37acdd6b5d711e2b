//! The autopilot (`--bot`): it plays the game through the same
//! [`crate::input::TickInput`] a person gives, turning towards the nearest
//! image of the nearest target or enemy and firing when it is lined up.
//! It is how the long play-tests ran (`--bot --headless --ticks 36000` is
//! ten minutes of play), and a demo to watch.

use crate::game::{Enemy, Game, Player, Target};
use crate::input::{InputSource, TickInput};
use bevy::prelude::*;
use bevy_manifold::contact;
use bevy_manifold::geometry::isometry;
use bevy_manifold::prelude::*;
use glam::DVec3;

/// Present: the autopilot sets the live input every tick.
#[derive(Resource, Debug, Default)]
pub struct Autopilot;

/// The autopilot's system; runs in `FixedUpdate` before the game reads
/// the tick's input. It aims at the nearest image it can hit: a ray cast
/// along it meets that entity first (an image in an "off" cell, or behind
/// another, is passed over, as a person passes over what is not shown).
#[expect(clippy::type_complexity, reason = "Bevy queries")]
pub fn autopilot(
    game: Res<Game>,
    mut source: ResMut<InputSource>,
    cast: ManifoldRayCast,
    spaces: Query<&ManifoldSpace>,
    player: Query<&Placement, With<Player>>,
    aims: Query<(Entity, &Placement, Has<Enemy>), (Or<(With<Target>, With<Enemy>)>, Without<Player>)>,
) {
    let (Ok(ms), Ok(me)) = (spaces.get(game.root), player.get(game.player)) else {
        return;
    };
    let space = ms.space();
    let g = space.geometry();
    let rules = game.rules;
    let to_local = |dir: glam::DVec4| (isometry::inverse(g, me.isometry) * dir).truncate();
    let visible = |entity, local: DVec3, d: f64| {
        let settings = RayCastSettings {
            max_distance: d + 1.0,
            levels: 64,
            exclude: Some(game.player),
        };
        cast.cast(game.player, local, &settings)
            .first()
            .is_some_and(|h| h.entity == entity)
    };
    // Enemies count as nearer than they are: they shoot back.
    let mut best: Option<(DVec3, f64, f64, bool)> = None;
    for (entity, p, enemy) in &aims {
        let weight = if enemy { 0.6 } else { 1.0 };
        // The nearest few images, nearest first.
        for (dir, d) in contact::nearest_images(space, me.position(), p.position(), 8)
            .into_iter()
            .filter(|i| i.distance > 0.0)
            .map(|i| (i.direction, i.distance))
        {
            if best.is_some_and(|b| b.2 <= d * weight) {
                break;
            }
            let local = to_local(dir);
            if visible(entity, local, d) {
                best = Some((local, d, d * weight, enemy));
                break;
            }
        }
    }
    let Some((local, d, _, enemy)) = best else {
        // Nothing in sight: look around.
        source.live = TickInput {
            turn: DVec3::new(0.0, 0.6, 0.0),
            thrust: DVec3::NEG_Z * 0.3,
            fire: false,
        };
        return;
    };
    let yaw = (-local.x).atan2(-local.z);
    let pitch = local.y.atan2((local.x * local.x + local.z * local.z).sqrt());
    let radius = if enemy { rules.enemy_radius } else { rules.target_radius };
    let off = local.angle_between(DVec3::NEG_Z);
    source.live.turn = DVec3::new(pitch * 3.0, yaw * 3.0, 0.0).clamp(DVec3::splat(-1.0), DVec3::splat(1.0));
    source.live.thrust = if d > 3.0 * radius {
        DVec3::NEG_Z * 0.4
    } else {
        DVec3::ZERO
    };
    source.live.fire = off < 0.7 * (radius / d).atan();
}
