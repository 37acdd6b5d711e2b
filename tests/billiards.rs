//! The billiards example's table, played headless: balls that strike
//! each other through the faces, pockets at the domain's corners, strokes
//! along the line of sight, and the hands of a headset as cues. Expected
//! values come from mechanics (an elastic collision of equal masses
//! swaps the velocities head on and leaves at right angles when
//! glancing; a ball off a wall moving at `u` leaves at `2u`) and from the
//! spaces' known vertex classes, not from the game.

#[path = "../examples/billiards/table.rs"]
#[allow(dead_code, reason = "the tests use part of the table")]
mod table;
#[cfg(feature = "xr")]
#[path = "../examples/billiards/xr.rs"]
#[allow(dead_code, reason = "the tests use part of the headset")]
mod xr;

use bevy::ecs::system::RunSystemOnce;
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bevy_manifold::contact;
use bevy_manifold::geometry::{Geometry, isometry};
use bevy_manifold::prelude::*;
use bevy_manifold_test_support::Rng;
use glam::{DMat4, DVec3};
use std::time::Duration;
use table::{Ball, Cue, Pocket, Table, TableConfig, TableEvent, TablePlugin};

/// A table in `space` with no clock but the test's: each update is one
/// tick. With `rack`, the ten balls; without, the cue ball only.
fn headless(space: &str, rack: bool) -> App {
    let dt = Duration::from_secs_f64(1.0 / table::TICK_HZ);
    let mut app = App::new();
    app.add_plugins((
        MinimalPlugins,
        ManifoldPlugins::in_schedule(FixedPostUpdate),
        TablePlugin {
            config: TableConfig {
                space: space.into(),
                rack,
            },
        },
    ));
    app.insert_resource(Time::<Fixed>::from_duration(dt))
        .insert_resource(TimeUpdateStrategy::ManualDuration(dt));
    // The first update sets the table up (no tick yet).
    app.update();
    app
}

fn space_of(app: &App) -> Space {
    let root = app.world().resource::<Table>().root;
    app.world().get::<ManifoldSpace>(root).unwrap().space().clone()
}

/// Friction off, so speeds are exact.
fn frictionless(app: &mut App) {
    app.world_mut().resource_mut::<Table>().rules.drag = 0.0;
}

/// Puts `entity` at `isometry` with velocity `v` in its own frame.
fn put(app: &mut App, entity: Entity, isometry: DMat4, v: DVec3) {
    let mut e = app.world_mut().entity_mut(entity);
    *e.get_mut::<Placement>().unwrap() = Placement::from_isometry(isometry);
    if let Some(mut velocity) = e.get_mut::<GeodesicVelocity>() {
        velocity.linear = v;
    }
}

/// Spawns numbered ball `number` at `isometry` moving at `v`.
fn ball(app: &mut App, number: u8, isometry: DMat4, v: DVec3) -> Entity {
    let entity = app
        .world_mut()
        .run_system_once(move |mut commands: Commands, mut table: ResMut<Table>| {
            table.left += 1;
            table::spawn_ball(
                &mut commands,
                table.root,
                &table.rules,
                number,
                Placement::from_isometry(isometry),
            )
        })
        .unwrap();
    put(app, entity, isometry, v);
    entity
}

fn velocity(app: &App, entity: Entity) -> DVec3 {
    app.world().get::<GeodesicVelocity>(entity).unwrap().linear
}

fn ticks(app: &mut App, n: usize) {
    for _ in 0..n {
        app.update();
    }
}

fn events(app: &App) -> Vec<TableEvent> {
    app.world()
        .resource::<Table>()
        .log
        .iter()
        .map(|(_, e)| e.clone())
        .collect()
}

/// The unit direction of face `f`'s outward normal (the polyhedra are
/// centred on the origin, each face at the inradius along its normal).
fn face_normal(space: &Space, f: usize) -> DVec3 {
    space.faces()[f].plane.truncate().normalize()
}

/// Two placements on the geodesic through face `f`'s centre along its
/// normal, on either side of the face: the first `0.2 r` inside, the
/// second `0.1 r` beyond (`r` the inradius), carried back into the domain
/// by the pairing. Two balls there meet before the first reaches the
/// face, as the second is nearer to it than two radii (`0.14 r`).
/// Each is a pure translation along the normal before the wrap, so along
/// the normal is local `u` in both frames.
fn across_face(space: &Space, f: usize) -> (DVec3, DMat4, DMat4) {
    let u = face_normal(space, f);
    let r = space.inradius();
    let g = space.geometry();
    let inside = isometry::translation(g, u * 0.8 * r);
    let (beyond, _) = space.wrap(isometry::translation(g, u * 1.1 * r), 64);
    (u, inside, beyond)
}

#[test]
fn head_on_through_a_face_the_cue_ball_stops_and_the_other_goes_on() {
    for name in ["torus", "seifert-weber", "poincare"] {
        let mut app = headless(name, false);
        frictionless(&mut app);
        let space = space_of(&app);
        let (u, inside, beyond) = across_face(&space, 0);
        let speed = 0.5 * app.world().resource::<Table>().rules.max_speed;
        let cue = app.world().resource::<Table>().cue_ball;
        put(&mut app, cue, inside, u * speed);
        let other = ball(&mut app, 1, beyond, DVec3::ZERO);
        // They meet after (0.3 r - 2 radii) / speed, well within a second.
        ticks(&mut app, 60);
        let hits: Vec<_> = events(&app)
            .into_iter()
            .filter_map(|e| match e {
                TableEvent::Collision {
                    balls,
                    through_faces,
                    speed,
                    ..
                } => Some((balls.0.min(balls.1), balls.0.max(balls.1), through_faces, speed)),
                _ => None,
            })
            .collect();
        assert_eq!(hits.len(), 1, "{name}: {hits:?}");
        let (first, second, through_faces, closing) = hits[0];
        assert_eq!((first, second, through_faces), (0, 1, true), "{name}");
        // They closed in at the cue ball's speed.
        assert!((closing - speed).abs() < 1e-9, "{name}: closing at {closing}");
        // Head on, equal masses: the velocities swap exactly.
        assert!(velocity(&app, cue).length() < 1e-9, "{name}: {}", velocity(&app, cue));
        let v = velocity(&app, other);
        assert!((v - u * speed).length() < 1e-9, "{name}: {v} against {}", u * speed);
    }
}

#[test]
fn a_glancing_blow_in_flat_space_leaves_at_right_angles_and_keeps_momentum() {
    let g = Geometry::Euclidean;
    for (offset, v) in [
        (DVec3::new(0.06, 0.02, 0.0), DVec3::new(1.0, 0.0, 0.0)),
        (DVec3::new(0.03, -0.05, 0.04), DVec3::new(0.2, -0.7, 0.4)),
    ] {
        let b = isometry::translation(g, offset);
        let (va, vb) = table::collide(g, (DMat4::IDENTITY, v), (b, DVec3::ZERO), false).unwrap();
        assert!(va.dot(vb).abs() < 1e-12, "right angle: {va} . {vb}");
        assert!((va + vb - v).length() < 1e-12, "momentum");
        assert!((va.length_squared() + vb.length_squared() - v.length_squared()).abs() < 1e-12);
        // The struck ball leaves along the line of centres.
        assert!(vb.normalize().dot(offset.normalize()) > 1.0 - 1e-12);
    }
}

#[test]
fn collisions_keep_the_energy_and_part_the_balls_in_every_geometry() {
    let mut rng = Rng(7);
    for g in [Geometry::Euclidean, Geometry::Hyperbolic, Geometry::Spherical] {
        let mut met = 0;
        for _ in 0..400 {
            let a = rng.isometry(g, 0.6);
            // The second ball within a ball's breadth of the first.
            let b = a * rng.isometry(g, 0.08);
            let va = rng.unit() * rng.next_f64();
            let vb = rng.unit() * rng.next_f64();
            let Some((va2, vb2)) = table::collide(g, (a, va), (b, vb), false) else {
                continue;
            };
            met += 1;
            let (before, after) = (
                va.length_squared() + vb.length_squared(),
                va2.length_squared() + vb2.length_squared(),
            );
            assert!(
                (before - after).abs() < 1e-12 * before.max(1.0),
                "{g:?}: {before} -> {after}"
            );
            // After the blow they part: no second blow.
            assert_eq!(table::collide(g, (a, va2), (b, vb2), false), None, "{g:?}");
        }
        assert!(met > 100, "{g:?}: only {met} of 400 pairs closing in");
    }
}

#[test]
fn a_hand_moving_into_a_ball_at_rest_sends_it_at_twice_its_speed() {
    for g in [Geometry::Euclidean, Geometry::Hyperbolic, Geometry::Spherical] {
        let hand = isometry::translation(g, DVec3::X * 0.1);
        let (ball, _) = table::collide(g, (DMat4::IDENTITY, DVec3::ZERO), (hand, DVec3::NEG_X * 0.3), true).unwrap();
        assert!((ball - DVec3::NEG_X * 0.6).length() < 1e-12, "{g:?}: {ball}");
        // A hand moving away does not strike.
        assert_eq!(
            table::collide(g, (DMat4::IDENTITY, DVec3::ZERO), (hand, DVec3::X * 0.3), true),
            None
        );
    }
}

#[test]
fn there_is_one_pocket_for_each_point_the_corners_are_glued_into() {
    // The cube's corners are one point of the 3-torus; the dodecahedron's
    // twenty vertices are one point of Seifert-Weber's space and five of
    // the Poincaré sphere (four each); mirrors glue nothing.
    for (name, pockets) in [
        ("torus", 1),
        ("seifert-weber", 1),
        ("poincare", 5),
        ("mirrored-cube", 8),
        ("mirrored-dodecahedron", 20),
    ] {
        let mut app = headless(name, false);
        let n = app.world_mut().query::<&Pocket>().iter(app.world()).count();
        assert_eq!(n, pockets, "{name}");
    }
}

#[test]
fn a_ball_rolled_at_any_corner_of_the_cube_drops_into_the_one_pocket() {
    let corners = [DVec3::ONE, DVec3::new(-1.0, -1.0, 1.0), DVec3::new(1.0, -1.0, -1.0)];
    for corner in corners {
        let mut app = headless("torus", false);
        frictionless(&mut app);
        let speed = app.world().resource::<Table>().rules.max_speed;
        let b = ball(&mut app, 1, DMat4::IDENTITY, corner.normalize() * speed);
        // The corner is sqrt(3)/2 = 0.866 away: there in 66 ticks.
        ticks(&mut app, 90);
        assert!(app.world().get_entity(b).is_err(), "toward {corner}: not sunk");
        assert!(events(&app).contains(&TableEvent::Sunk(1)), "{corner}");
        assert!(events(&app).contains(&TableEvent::Cleared { strokes: 0 }));
    }
    // Along an axis it only goes round the torus, never near a corner.
    let mut app = headless("torus", false);
    frictionless(&mut app);
    let speed = app.world().resource::<Table>().rules.max_speed;
    let b = ball(&mut app, 1, DMat4::IDENTITY, DVec3::X * speed);
    ticks(&mut app, 180);
    assert!(app.world().get_entity(b).is_ok());
    assert!(!events(&app).iter().any(|e| matches!(e, TableEvent::Sunk(_))));
}

#[test]
fn the_cue_ball_in_a_pocket_comes_back_to_its_spot_at_a_strokes_cost() {
    let mut app = headless("seifert-weber", false);
    frictionless(&mut app);
    let space = space_of(&app);
    let g = space.geometry();
    let cue = app.world().resource::<Table>().cue_ball;
    let spot = app.world().resource::<Table>().cue_spot;
    // Straight at a vertex (a geodesic through the origin is a line of
    // the chart).
    let v = space.vertices()[0].point.truncate().normalize();
    let speed = app.world().resource::<Table>().rules.max_speed;
    put(&mut app, cue, DMat4::IDENTITY, v * speed);
    let far = g.distance::<f64>(glam::DVec4::W, space.vertices()[0].point);
    ticks(&mut app, (far / speed * table::TICK_HZ) as usize + 10);
    assert!(events(&app).contains(&TableEvent::Scratch));
    assert_eq!(app.world().resource::<Table>().strokes, 1);
    let now = app.world().get::<Placement>(cue).unwrap();
    assert!(g.distance::<f64>(now.position(), spot.position()) < 1e-9);
    assert_eq!(velocity(&app, cue), DVec3::ZERO);
}

#[test]
fn a_stroke_sends_the_cue_ball_along_the_line_of_sight_through_a_face() {
    // From the start: the player looks at the cue ball; in the torus of
    // edge 1 (inradius 1/2) the player is at (0, 0.05, 0.1), the ball at
    // (0, 0, -0.15).
    let mut app = headless("torus", false);
    let cue = app.world().resource::<Table>().cue_ball;
    let full = app.world().resource::<Table>().rules.max_speed;
    app.world_mut().resource_mut::<Cue>().strike = Some(0.5);
    app.update();
    let want = DVec3::new(0.0, -0.05, -0.25).normalize() * 0.5 * full;
    // One tick of friction after the stroke.
    let drag = (-app.world().resource::<Table>().rules.drag / table::TICK_HZ).exp();
    assert!(
        (velocity(&app, cue) - want * drag).length() < 1e-9,
        "{}",
        velocity(&app, cue)
    );
    assert_eq!(events(&app), [TableEvent::Struck { speed: 0.5 * full }]);

    // Across a face, in the torus and in Seifert-Weber's twisted gluing:
    // the player just inside face 0 looking out along its normal, the
    // ball just beyond it (carried into the domain by the pairing).
    for name in ["torus", "seifert-weber"] {
        let mut app = headless(name, false);
        frictionless(&mut app);
        let space = space_of(&app);
        let (u, inside, beyond) = across_face(&space, 0);
        let full = app.world().resource::<Table>().rules.max_speed;
        let (player, cue) = {
            let t = app.world().resource::<Table>();
            (t.player, t.cue_ball)
        };
        let look = inside * DMat4::from_quat(glam::DQuat::from_rotation_arc(DVec3::NEG_Z, u));
        put(&mut app, player, look, DVec3::ZERO);
        put(&mut app, cue, beyond, DVec3::ZERO);
        app.update();
        app.world_mut().resource_mut::<Cue>().strike = Some(1.0);
        app.update();
        let v = velocity(&app, cue);
        assert!((v - u * full).length() < 1e-9, "{name}: {v} against {}", u * full);
    }

    // Out of the cue's reach: nothing happens.
    let mut app = headless("torus", false);
    let player = app.world().resource::<Table>().player;
    put(
        &mut app,
        player,
        isometry::translation(Geometry::Euclidean, DVec3::Z * 0.45),
        DVec3::ZERO,
    );
    app.update();
    app.world_mut().resource_mut::<Cue>().strike = Some(1.0);
    app.update();
    assert_eq!(app.world().resource::<Table>().strokes, 0);
}

#[test]
fn a_break_never_gains_energy_and_no_ball_passes_through_another() {
    for name in ["torus", "seifert-weber", "poincare"] {
        let mut app = headless(name, true);
        let space = space_of(&app);
        let rules = app.world().resource::<Table>().rules;
        app.world_mut().resource_mut::<Cue>().strike = Some(1.0);
        let mut energy = f64::INFINITY;
        // How deep two balls can be in one another before a tick parts
        // them: a tick's travel of each, twice (a ball that a third
        // turns back into the first is parted at the next tick). Two
        // balls that passed through each other would be 2 radii deep.
        let deepest = 4.0 * rules.max_speed / table::TICK_HZ + 1e-9;
        assert!(deepest < 0.8 * 2.0 * rules.ball_radius);
        for tick in 0..600 {
            app.update();
            let world = app.world_mut();
            let now = world
                .query_filtered::<&GeodesicVelocity, With<Ball>>()
                .iter(world)
                .map(|v| 0.5 * v.linear.length_squared())
                .sum::<f64>();
            assert!(now <= energy * (1.0 + 1e-12), "{name}: tick {tick}: {energy} -> {now}");
            energy = now;
            let centres: Vec<_> = world
                .query_filtered::<&Placement, With<Ball>>()
                .iter(world)
                .map(Placement::position)
                .collect();
            for (i, &a) in centres.iter().enumerate() {
                for &b in &centres[i + 1..] {
                    for touch in contact::ball_contacts(&space, (a, rules.ball_radius), (b, rules.ball_radius)) {
                        assert!(touch.depth <= deepest, "{name}: tick {tick}: {} deep", touch.depth);
                    }
                }
            }
        }
        let hits = events(&app)
            .iter()
            .filter(|e| matches!(e, TableEvent::Collision { .. }))
            .count();
        assert!(hits >= 3, "{name}: the break made {hits} collisions");
        assert!(
            energy < 0.5 * rules.max_speed * rules.max_speed,
            "{name}: friction took nothing"
        );
    }
}

#[cfg(feature = "xr")]
#[test]
fn a_hands_velocity_is_its_motion_over_the_tick() {
    for g in [Geometry::Euclidean, Geometry::Hyperbolic, Geometry::Spherical] {
        let last = isometry::translation(g, DVec3::new(0.1, 0.2, -0.1)) * isometry::rotation(DVec3::Y, 0.4);
        let now = last * isometry::translation(g, DVec3::new(0.0, 0.01, -0.02));
        let v = xr::hand_velocity(g, last, now, 0.5, 10.0).unwrap();
        assert!((v - DVec3::new(0.0, 0.02, -0.04)).length() < 1e-12, "{g:?}: {v}");
        // A jump (the hand wrapped through a face) is no velocity.
        let far = last * isometry::translation(g, DVec3::X * 0.5);
        assert_eq!(xr::hand_velocity(g, last, far, 0.01, 10.0), None);
    }
}
