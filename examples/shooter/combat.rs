//! The fight, each tick: the shortest route through the faces (the
//! plugin's nearest image, [`contact::nearest_image`]), which the enemies
//! fly and aim along ([`enemies_fly_and_fire`]), contacts through the faces
//! ([`ManifoldContacts`]: an enemy touching any image of the player rams
//! it, [`enemies_ram`]), and every shot's step swept as a ball along the
//! geodesic against every image of every target ([`sweep_shots`]).

use crate::game::{Enemy, Game, GameEvent, Player, Shot, TICK_HZ, Target, random_placement, spawn_shot, spawn_target};
use bevy::prelude::*;
use bevy_manifold::contact;
use bevy_manifold::geometry::isometry;
use bevy_manifold::prelude::*;
use glam::{DMat4, DVec3, DVec4};

/// A tangent at the entity's position, in its own frame.
fn local_direction(g: Geometry, placement: &Placement, tangent: DVec4) -> DVec3 {
    (isometry::inverse(g, placement.isometry) * tangent).truncate()
}

/// Turns `placement` so its forward (local -z) points along the local
/// direction `dir`, keeping its position.
fn facing(placement: &Placement, dir: DVec3) -> Placement {
    let f = dir.normalize();
    let up = if f.y.abs() < 0.9 { DVec3::Y } else { DVec3::X };
    let x = up.cross(-f).normalize();
    let y = (-f).cross(x);
    let turn = DMat4::from_cols(x.extend(0.0), y.extend(0.0), (-f).extend(0.0), DVec4::W);
    placement.rotated(turn)
}

/// Enemies fly towards the player's nearest image, and fire along the same
/// route when it is near enough.
pub fn enemies_fly_and_fire(
    mut commands: Commands,
    mut game: ResMut<Game>,
    spaces: Query<&ManifoldSpace>,
    player: Query<&Placement, With<Player>>,
    mut enemies: Query<(Entity, &mut Placement, &DomainCell, &mut GeodesicVelocity, &mut Enemy), Without<Player>>,
) {
    let (Ok(ms), Ok(target)) = (spaces.get(game.root), player.get(game.player)) else {
        return;
    };
    let space = ms.space();
    let g = space.geometry();
    let rules = game.rules;
    let mut fired = Vec::new();
    for (entity, mut placement, cell, mut velocity, mut enemy) in &mut enemies {
        // Where the two coincide there is no way to face.
        let Some(near) =
            contact::nearest_image(space, placement.position(), target.position()).filter(|i| i.distance > 0.0)
        else {
            velocity.linear = DVec3::ZERO;
            continue;
        };
        let distance = near.distance;
        *placement = facing(&placement, local_direction(g, &placement, near.direction));
        if game.tick >= enemy.wake {
            velocity.linear = DVec3::NEG_Z * rules.enemy_speed;
        }
        if distance < rules.enemy_fire_range && game.tick >= enemy.next_fire {
            enemy.next_fire = game.tick + (rules.enemy_fire_interval * TICK_HZ).round() as u64;
            fired.push((entity, *placement, cell.clone()));
        }
    }
    let ahead = rules.enemy_radius + 2.0 * rules.shot_radius;
    for (entity, placement, cell) in fired {
        spawn_shot(&mut commands, &game, ms, (entity, false), (placement, cell), ahead);
        game.event(GameEvent::EnemyFired);
    }
}

/// Each shot's step this tick, swept as a ball along the geodesic before
/// it moves ([`ManifoldRayCast::shape_cast`]): the first thing its surface
/// touches along the whole step is hit, at any speed,
/// through the faces, against every image (those in "off" cells are
/// passed through, as the tracer passes them). Shots past their life go.
#[expect(
    clippy::too_many_arguments,
    reason = "a Bevy system: each parameter is one query or resource"
)]
pub fn sweep_shots(
    mut commands: Commands,
    mut game: ResMut<Game>,
    time: Res<Time>,
    cast: ManifoldRayCast,
    mut shots: Query<(Entity, &mut Shot)>,
    kinds: Query<(Has<Target>, Has<Enemy>, Has<Player>)>,
    spaces: Query<&ManifoldSpace>,
    players: Query<&Placement, With<Player>>,
    owners: Query<(), (With<Placement>, Without<Shot>)>,
) {
    let dt = time.delta_secs_f64();
    let rules = game.rules;
    let step = rules.shot_speed * dt;
    let mut gone = Vec::new();
    // What this tick's hits destroyed: not hit again by another shot.
    let mut dead: Vec<Entity> = Vec::new();
    for (entity, mut shot) in &mut shots {
        let settings = RayCastSettings {
            max_distance: step,
            levels: 64,
            exclude: (shot.age < rules.grace || !shot.by_player).then_some(shot.owner),
        };
        // A shot's first step is cast from its shooter's centre, which it
        // left this tick (not yet moved): so the way out to where it
        // appeared is swept too, and a target touching the shooter is hit.
        let first = shot.age == 0.0 && owners.contains(shot.owner);
        let (from, reach, before) = if first {
            (shot.owner, shot.flown + step, 0.0)
        } else {
            (entity, step, shot.flown)
        };
        let settings = RayCastSettings {
            max_distance: reach,
            ..settings
        };
        // The shot is a ball: swept along its step, it hits what its
        // surface first touches.
        let shot_ball = ManifoldCollider::Ball {
            radius: rules.shot_radius,
        };
        let hit = cast
            .shape_cast(from, shot_ball, DVec3::NEG_Z, &settings)
            .into_iter()
            .find(|h| {
                let (target, enemy, player) = kinds.get(h.entity).unwrap_or_default();
                !dead.contains(&h.entity)
                    && if shot.by_player {
                        target || enemy || player
                    } else {
                        player
                    }
            });
        shot.age += dt;
        if let Some(h) = hit {
            let distance = before + h.distance;
            let (target, enemy, _) = kinds.get(h.entity).unwrap_or_default();
            if target {
                game.score += 100 * u64::from(game.level);
                game.hits += 1;
                game.event(GameEvent::TargetHit {
                    distance,
                    faces: h.faces.len(),
                    cell: h.cell,
                });
                commands.entity(h.entity).despawn();
                dead.push(h.entity);
                if let Some(space) = spaces.get(game.root).ok().map(|m| m.space().clone()) {
                    let needed = Game::targets_for(game.level);
                    // A new target while the level still needs them.
                    if game.hits + 2 < needed {
                        let player_at = players.get(game.player).map_or(DVec4::W, Placement::position);
                        let p = random_placement(&mut game.rng, &space, player_at);
                        spawn_target(&mut commands, &game, p);
                    }
                }
            } else if enemy {
                game.score += 50;
                game.event(GameEvent::EnemyHit { distance });
                commands.entity(h.entity).despawn();
                dead.push(h.entity);
            } else {
                game.health -= if shot.by_player { 20.0 } else { 15.0 };
                game.event(GameEvent::PlayerHit {
                    own: shot.by_player,
                    distance,
                });
            }
            gone.push(entity);
        } else if shot.age >= rules.shot_life {
            gone.push(entity);
        } else {
            shot.flown += step;
        }
    }
    for e in gone {
        commands.entity(e).despawn();
    }
}

/// An enemy whose collider touches any image of the player's rams it and
/// is destroyed.
pub fn enemies_ram(
    mut commands: Commands,
    mut game: ResMut<Game>,
    contacts: ManifoldContacts,
    enemies: Query<Entity, With<Enemy>>,
) {
    for e in &enemies {
        if !contacts.contacts(e, game.player).is_empty() {
            game.health -= 20.0;
            game.event(GameEvent::Rammed);
            commands.entity(e).despawn();
        }
    }
}
