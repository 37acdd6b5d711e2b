//! The shooter example's game, played headless from scripts (as the
//! example's `--play FILE --headless` plays it): shots that come back
//! around, hits through faces at any speed, the per-cell on/off rule,
//! enemies on the shortest route, exact replays. Expected values come from
//! the geometry (periods, distances through faces, the Seifert-Weber
//! closed geodesic's length and twist), not from the game.

#[path = "../examples/shooter/combat.rs"]
#[allow(dead_code, reason = "the tests use part of the game")]
mod combat;
#[path = "../examples/shooter/game.rs"]
#[allow(dead_code, reason = "the tests use part of the game")]
mod game;
#[path = "../examples/shooter/input.rs"]
#[allow(dead_code, reason = "the tests use part of the input")]
mod input;
#[path = "../examples/shooter/product.rs"]
#[allow(dead_code, reason = "the tests use part of the product game")]
mod product;
#[cfg(feature = "xr")]
#[path = "../examples/shooter/xr.rs"]
mod xr;

use bevy::ecs::system::RunSystemOnce;
use bevy::prelude::*;
use bevy_manifold::geometry::isometry;
use bevy_manifold::prelude::*;
use bevy_manifold::space::rule::{CellRule, OnOff};
use game::{Difficulty, Game, GameConfig, GameEvent, Player, Shot, Target};
use glam::{DMat4, DVec3, DVec4};
use input::{Script, ScriptEntry, TickInput, headless_app};
use std::f64::consts::PI;
use std::time::Duration;

const TICK: f64 = 1.0 / game::TICK_HZ;

fn config(space: &str) -> GameConfig {
    GameConfig {
        space: space.into(),
        seed: 3,
        difficulty: Difficulty::Normal,
        spawn: false,
    }
}

/// A script that fires once, at the first tick, and then holds still.
fn fire_once(space: &str) -> Script {
    Script {
        space: space.into(),
        seed: 3,
        difficulty: Difficulty::Normal,
        inputs: vec![
            ScriptEntry {
                at: 0,
                input: TickInput {
                    fire: true,
                    ..default()
                },
            },
            ScriptEntry {
                at: 1,
                input: TickInput::default(),
            },
        ],
        ticks: 0,
    }
}

fn new_game(space: &str, script: Script, dt: f64) -> App {
    headless_app(config(space), Some(script), Duration::from_secs_f64(dt))
}

fn game(app: &App) -> &Game {
    app.world().resource::<Game>()
}

/// Plays until `done` says so or `max` ticks have gone.
fn play_until(app: &mut App, max: u64, done: impl Fn(&Game) -> bool) {
    while !done(game(app)) && game(app).tick < max {
        app.update();
    }
}

fn events(app: &App) -> Vec<GameEvent> {
    game(app).log.iter().map(|(_, e)| e.clone()).collect()
}

/// Puts the player at `v` from the origin, facing the unit direction `dir`
/// (in the origin's frame), in `cell`.
fn place_player(app: &mut App, v: DVec3, dir: DVec3, cell: Option<DomainCell>) {
    let player = game(app).player;
    let root = game(app).root;
    let space = app.world().get::<ManifoldSpace>(root).unwrap().space().clone();
    let turn = DMat4::from_quat(glam::DQuat::from_rotation_arc(DVec3::NEG_Z, dir));
    let p = Placement::from_isometry(isometry::translation(space.geometry(), v) * turn);
    let mut e = app.world_mut().entity_mut(player);
    e.insert((p, bevy_manifold::placement::WrapOrigin(Some(p.isometry))));
    if let Some(c) = cell {
        e.insert(c);
    }
}

fn spawn_target_at(app: &mut App, v: DVec3) -> Entity {
    app.world_mut()
        .run_system_once(
            move |mut commands: Commands, game: Res<Game>, spaces: Query<&ManifoldSpace>| {
                let space = spaces.get(game.root).unwrap().space();
                game::spawn_target(&mut commands, &game, Placement::at(space, v))
            },
        )
        .expect("spawns")
}

fn no_player_collider(app: &mut App) {
    let player = game(app).player;
    app.world_mut().entity_mut(player).remove::<ManifoldCollider>();
}

#[test]
fn in_the_torus_a_shot_comes_back_after_one_period_and_hits_its_shooter() {
    let mut app = new_game("torus", fire_once("torus"), TICK);
    place_player(&mut app, DVec3::ZERO, DVec3::X, None);
    let rules = game(&app).rules;
    play_until(&mut app, 200, |g| {
        g.log.iter().any(|(_, e)| matches!(e, GameEvent::PlayerHit { .. }))
    });
    let (tick, hit) = game(&app)
        .log
        .iter()
        .find(|(_, e)| matches!(e, GameEvent::PlayerHit { .. }))
        .cloned()
        .expect("the shot came back");
    // One period (1) less the player's and the shot's radii (the shot is
    // a ball), from its centre.
    let GameEvent::PlayerHit { own, distance } = hit else {
        unreachable!()
    };
    assert!(own);
    let reach = 1.0 - rules.player_radius - rules.shot_radius;
    assert!((distance - reach).abs() < 1e-9, "hit after {distance}");
    // At the shot's speed, in the tick that covers that distance from
    // where the shot appears, after the grace period.
    let expected_tick =
        ((reach - rules.player_radius - 2.0 * rules.shot_radius) / (rules.shot_speed * TICK)).floor() as u64;
    assert!(
        tick.abs_diff(expected_tick) <= 1,
        "tick {tick}, expected {expected_tick}"
    );
    assert!(tick as f64 * TICK > rules.grace);
    assert!((game(&app).health - 80.0).abs() < 1e-12);
}

#[test]
fn a_target_seen_through_a_face_is_hit_at_the_distance_through_the_face() {
    let mut app = new_game("torus", fire_once("torus"), TICK);
    // The player at x = -0.3 looks along -x: the target at x = +0.3 is
    // 0.2 + 0.2 away through the face x = -1/2 (0.6 the other way).
    place_player(&mut app, DVec3::new(-0.3, 0.0, 0.0), DVec3::NEG_X, None);
    let target = spawn_target_at(&mut app, DVec3::new(0.3, 0.0, 0.0));
    // The target's radius and the shot's: the shot is a ball.
    let r = game(&app).rules.target_radius + game(&app).rules.shot_radius;
    play_until(&mut app, 120, |g| g.hits > 0);
    let hit = events(&app)
        .into_iter()
        .find_map(|e| match e {
            GameEvent::TargetHit { distance, faces, cell } => Some((distance, faces, cell)),
            _ => None,
        })
        .expect("the target is hit");
    assert!((hit.0 - (0.4 - r)).abs() < 1e-9, "hit after {}", hit.0);
    assert!(hit.1 <= 1, "the last step's ray crossed {} faces", hit.1);
    assert_eq!(hit.2.lattice(), Some(IVec3::new(-1, 0, 0)), "the image in the -x copy");
    assert!(app.world().get_entity(target).is_err(), "the target is gone");
    assert_eq!(game(&app).score, 100);
}

/// The first image of a ball of radius `r` at `c` in the torus of period
/// 1 met by the ray `p + t u` with `t >= from`, by brute force over the
/// lattice (every image within 25 periods).
fn first_torus_hit(p: DVec3, u: DVec3, c: DVec3, r: f64, from: f64) -> f64 {
    let mut best = f64::INFINITY;
    for (i, j, k) in (-25..=25).flat_map(|i| (-25..=25).flat_map(move |j| (-25..=25).map(move |k| (i, j, k)))) {
        let q = c + DVec3::new(f64::from(i), f64::from(j), f64::from(k)) - p;
        let b = q.dot(u);
        let disc = b * b - (q.length_squared() - r * r);
        if disc >= 0.0 {
            let t = b - disc.sqrt();
            if t >= from {
                best = best.min(t);
            }
        }
    }
    best
}

#[test]
fn a_shot_at_100_per_second_at_10_ticks_per_second_never_tunnels() {
    // Straight at a target 0.5 ahead; behind the player, its image ahead
    // 0.75 away; and obliquely, where the first image on the way is 8.4
    // away, near the end of the first 10-unit step.
    let (p, c) = (DVec3::new(-0.3, 0.0, 0.0), DVec3::new(0.3, 0.2, 0.1));
    for (dir, target) in [
        (DVec3::X, DVec3::new(0.3, 0.0, 0.0)),
        (DVec3::X, DVec3::new(-0.45, 0.0, 0.0)),
        (DVec3::new(1.0, 0.29, 0.41).normalize(), c),
    ] {
        let mut app = new_game("torus", fire_once("torus"), 0.1);
        app.world_mut().resource_mut::<Game>().rules.shot_speed = 100.0;
        no_player_collider(&mut app);
        place_player(&mut app, p, dir, None);
        spawn_target_at(&mut app, target);
        let rules = game(&app).rules;
        let ahead = rules.player_radius + 2.0 * rules.shot_radius;
        let want = first_torus_hit(p, dir, target, rules.target_radius + rules.shot_radius, ahead);
        play_until(&mut app, 4, |g| g.hits > 0);
        let distance = events(&app).into_iter().find_map(|e| match e {
            GameEvent::TargetHit { distance, .. } => Some(distance),
            _ => None,
        });
        let d = distance.unwrap_or_else(|| panic!("target at {target}: no hit in {:?}", events(&app)));
        assert!((d - want).abs() < 1e-9, "target at {target}: hit after {d}, not {want}");
        // In the tick that covers it (the first: ticks are 10 long).
        let tick = game(&app)
            .log
            .iter()
            .find(|(_, e)| matches!(e, GameEvent::TargetHit { .. }))
            .unwrap()
            .0;
        assert_eq!(tick, ((want - ahead) / 10.0).floor() as u64, "target at {target}");
    }
}

/// The lattice copy `(k, 0, 0)` of the torus's domain, reached by crossing
/// the face towards +x (or -x) `|k|` times.
fn copy_along_x(space: &Space, k: i32) -> DomainCell {
    let face = |x: f64| space.outside_face(DVec4::new(x, 0.0, 0.0, 1.0), 1e-9).expect("a face");
    let f = if k > 0 { face(0.6) } else { face(-0.6) };
    let mut cell = space.origin_cell();
    for _ in 0..k.unsigned_abs() {
        cell = space.cross_cell(&cell, f);
    }
    DomainCell::new(space, cell)
}

#[test]
fn an_image_in_an_off_cell_is_passed_through_and_one_in_an_on_cell_is_hit() {
    let space = catalog::torus(1.0);
    // A rule and a copy k along x that is off while copy k + 1 is on,
    // decided by the rule itself from the copies' ids.
    let rule_seed = 11;
    let rule = CellRule {
        hidden: Some(OnOff {
            on_fraction: 0.5,
            seed: rule_seed,
        }),
        walls: None,
    };
    let k = (1..50)
        .find(|&k| !rule.visible(copy_along_x(&space, k).id) && rule.visible(copy_along_x(&space, k + 1).id))
        .expect("such a copy");
    for ruled in [false, true] {
        let mut app = new_game("torus", fire_once("torus"), TICK);
        no_player_collider(&mut app);
        let root = game(&app).root;
        if ruled {
            app.world_mut().get_mut::<ManifoldSpace>(root).unwrap().set_rule(rule);
        }
        place_player(
            &mut app,
            DVec3::new(-0.3, 0.0, 0.0),
            DVec3::X,
            Some(copy_along_x(&space, k)),
        );
        spawn_target_at(&mut app, DVec3::new(0.3, 0.0, 0.0));
        let r = game(&app).rules.target_radius + game(&app).rules.shot_radius;
        play_until(&mut app, 200, |g| g.hits > 0);
        let (distance, cell) = events(&app)
            .into_iter()
            .find_map(|e| match e {
                GameEvent::TargetHit { distance, cell, .. } => Some((distance, cell)),
                _ => None,
            })
            .expect("a hit");
        // Without the rule the image in the player's own copy is hit;
        // with it, that copy is off and the next one along, a period
        // further, is hit.
        let (want_d, want_cell) = if ruled {
            (1.6 - r, copy_along_x(&space, k + 1).id)
        } else {
            (0.6 - r, copy_along_x(&space, k).id)
        };
        assert!((distance - want_d).abs() < 1e-9, "ruled {ruled}: hit after {distance}");
        assert_eq!(cell, want_cell, "ruled {ruled}");
    }
}

#[test]
fn in_seifert_weber_a_shot_along_a_face_axis_returns_turned_by_three_fifths_of_pi() {
    let space = catalog::seifert_weber();
    // The published length of the closed geodesic through the centre
    // and two opposite face centres: twice the inradius.
    assert!((2.0 * space.inradius() - 1.99277).abs() < 1e-5);
    let two_r = 2.0 * space.inradius();
    // Face 0's axis: the direction from the centre out of face 0.
    let n = space.faces()[0].plane.truncate().normalize();
    let axis = [n, -n]
        .into_iter()
        .find(|&u| {
            let p = isometry::translation(space.geometry(), u * (space.inradius() + 0.01)).w_axis;
            space.outside_face(p, 1e-9) == Some(0)
        })
        .expect("face 0 is on one side");
    let mut app = new_game("seifert-weber", fire_once("seifert-weber"), TICK);
    place_player(&mut app, DVec3::ZERO, axis, None);
    let rules = game(&app).rules;
    // The shot, once it has flown the closed geodesic, back at the centre
    // (the player's collider off, so it passes).
    let start_frame = app.world().get::<Placement>(game(&app).player).unwrap().isometry;
    no_player_collider(&mut app);
    let mut seen = None;
    for _ in 0..200 {
        app.update();
        let mut shots = app.world_mut().query::<(&Shot, &Placement)>();
        if let Some((shot, p)) = shots.iter(app.world()).next()
            && shot.flown >= two_r
        {
            seen = Some((shot.flown, p.isometry));
            break;
        }
    }
    let (flown, m) = seen.expect("the shot flew the loop");
    // Back along its own forward by the overshoot: at the centre.
    let back = m * isometry::translation(space.geometry(), DVec3::Z * (flown - two_r));
    assert!((back.w_axis - DVec4::W).length() < 1e-9, "at {:?}", back.w_axis);
    // Facing the same axis, its frame turned about it by 3 pi / 5.
    let forward = -back.z_axis.truncate();
    assert!((forward - axis).length() < 1e-9, "forward {forward:?}");
    let (x0, x1) = (start_frame.x_axis.truncate(), back.x_axis.truncate());
    let angle = x0.dot(x1).clamp(-1.0, 1.0).acos();
    assert!(
        (angle - 3.0 * PI / 5.0).abs() < 1e-6,
        "turned by {} degrees",
        angle.to_degrees()
    );
    // And with the player's collider on, the shot hits its shooter there.
    let mut app = new_game("seifert-weber", fire_once("seifert-weber"), TICK);
    place_player(&mut app, DVec3::ZERO, axis, None);
    play_until(&mut app, 200, |g| g.health < 100.0);
    let hit = events(&app).into_iter().find_map(|e| match e {
        GameEvent::PlayerHit { distance, .. } => Some(distance),
        _ => None,
    });
    let d = hit.expect("hit by its own shot");
    let reach = two_r - rules.player_radius - rules.shot_radius;
    assert!((d - reach).abs() < 1e-9, "hit after {d}");
}

/// The nearest image in the torus, in closed form: each coordinate of the
/// difference reduced to `[-1/2, 1/2]`.
fn torus_nearest(p: DVec3, q: DVec3) -> f64 {
    let d = q - p;
    (d - d.round()).length()
}

fn spawn_enemy_at(app: &mut App, v: DVec3) {
    app.world_mut()
        .run_system_once(
            move |mut commands: Commands, game: Res<Game>, spaces: Query<&ManifoldSpace>| {
                let space = spaces.get(game.root).unwrap().space();
                game::spawn_enemy(&mut commands, &game, Placement::at(space, v), DomainCell::default());
            },
        )
        .expect("spawns");
}

#[test]
fn an_enemy_reaches_the_player_by_the_shortest_route_through_the_faces() {
    // The player at x = -0.4, the enemy at x = +0.4, y = 0.1: 0.2236
    // apart through the face x = 1/2, 0.806 across the cube.
    let (p, e) = (DVec3::new(-0.4, 0.0, 0.0), DVec3::new(0.4, 0.1, 0.0));
    let mut app = new_game("torus", fire_once("torus"), TICK);
    app.world_mut().resource_mut::<input::InputSource>().script = None;
    place_player(&mut app, p, DVec3::NEG_Z, None);
    spawn_enemy_at(&mut app, e);
    let rules = game(&app).rules;
    play_until(&mut app, 600, |g| g.log.iter().any(|(_, e)| *e == GameEvent::Rammed));
    let tick = game(&app)
        .log
        .iter()
        .find(|(_, e)| *e == GameEvent::Rammed)
        .map(|(t, _)| *t)
        .expect("the enemy got there");
    let route = torus_nearest(p, e);
    assert!((route - 0.05f64.sqrt()).abs() < 1e-12);
    // It wakes 1.5 s after it appears, then flies straight there.
    let wake = 1.5 / TICK;
    let want = wake + (route - rules.enemy_radius - rules.player_radius) / (rules.enemy_speed * TICK);
    assert!(
        (tick as f64 - want).abs() <= 2.0,
        "rammed at tick {tick}, the shortest route predicts {want:.1}"
    );
}

/// A script that flies, turns and fires for `ticks`, from a seed.
fn busy_script(space: &str, ticks: u64, seed: u64) -> Script {
    let mut rng = bevy_manifold_test_support::Rng(seed);
    let mut inputs = Vec::new();
    let mut at = 0;
    while at < ticks {
        let mut axis = || (rng.next_f64() * 2.0 - 1.0).clamp(-1.0, 1.0);
        inputs.push(ScriptEntry {
            at,
            input: TickInput {
                thrust: DVec3::new(0.0, 0.0, -axis().abs()),
                turn: DVec3::new(axis() * 0.3, axis(), 0.0),
                fire: rng.next_f64() < 0.7,
            },
        });
        at += 20 + (rng.next_f64() * 40.0) as u64;
    }
    Script {
        space: space.into(),
        seed: 9,
        difficulty: Difficulty::Hard,
        inputs,
        ticks,
    }
}

fn play_script(script: &Script) -> (u64, Vec<(u64, GameEvent)>, Script) {
    let mut app = headless_app(script.config(), Some(script.clone()), Duration::from_secs_f64(TICK));
    play_until(&mut app, script.ticks, |g| g.phase != game::Phase::Playing);
    let g = game(&app);
    let recorded = app
        .world()
        .resource::<input::InputSource>()
        .recording(&script.config(), g.tick);
    (g.score, g.log.clone(), recorded)
}

#[test]
fn a_recorded_game_replays_exactly() {
    let script = busy_script("torus", 1200, 4);
    let (score, log, recorded) = play_script(&script);
    let hits = log
        .iter()
        .filter(|(_, e)| matches!(e, GameEvent::TargetHit { .. } | GameEvent::PlayerHit { .. }))
        .count();
    assert!(hits >= 2, "a busy game has hits: {log:?}");
    assert!(
        log.iter().any(|(_, e)| *e == GameEvent::EnemyFired),
        "the enemy fires back"
    );
    // The same script again, and the recording of the first game read
    // back from its JSON: the same score and the same events.
    let (score2, log2, _) = play_script(&script);
    assert_eq!((score, &log), (score2, &log2));
    let reread = Script::parse(&recorded.to_json()).expect("the recording reads back");
    let (score3, log3, _) = play_script(&reread);
    assert_eq!((score, &log), (score3, &log3));
    // And another seed is another game.
    let mut other = script.clone();
    other.seed = 10;
    assert_ne!(play_script(&other).1, log);
}

#[test]
fn bad_scripts_are_refused_naming_the_field() {
    let good = busy_script("torus", 100, 1).to_json();
    assert!(Script::parse(&good).is_ok());
    let e = Script::parse(&good.replace("\"torus\"", "\"klein-bottle\"")).unwrap_err();
    assert!(e.starts_with("space: no catalog space \"klein-bottle\""), "{e}");
    let mut s = busy_script("torus", 100, 1);
    s.inputs[1].at = 0;
    let e = Script::parse(&s.to_json()).unwrap_err();
    assert!(e.starts_with("inputs[1].at: 0 does not come after 0"), "{e}");
    s = busy_script("torus", 100, 1);
    s.inputs[0].input.turn = DVec3::new(0.0, 3.0, 0.0);
    let e = Script::parse(&s.to_json()).unwrap_err();
    assert!(e.starts_with("inputs[0].turn: "), "{e}");
    let e = Script::parse(&good.replace("\"ticks\": 100", "\"ticks\": 99999999999")).unwrap_err();
    assert!(e.starts_with("ticks: at most"), "{e}");
    let e = Script::read(std::path::Path::new("/nonexistent/game.json")).unwrap_err();
    assert!(e.starts_with("/nonexistent/game.json: "), "{e}");
    let e = Script::parse("{\"space\": \"torus\"").unwrap_err();
    assert!(e.contains("EOF"), "{e}");
    let _ = (Player, Target);
}

/// In a headset the controllers are the game's input, through the same
/// per-tick input a script records: the left stick pushed forward is
/// thrust along the player's -z, the right trigger (the XR plugin's
/// trigger action) fires; the player carries the room (`XrBody`) and the
/// game, not the sticks' own flight, moves it.
#[cfg(feature = "xr")]
#[test]
fn in_a_headset_the_left_stick_flies_and_the_trigger_fires() {
    use bevy_manifold::xr::{XrBody, XrControllers, XrLocomotion};
    let mut app = headless_app(config("torus"), None, Duration::from_secs_f64(TICK));
    app.add_plugins(xr::ShooterXrPlugin {
        world_scale: 4.0,
        capture: None,
    });
    no_player_collider(&mut app);
    {
        let mut c = app.world_mut().resource_mut::<XrControllers>();
        c.hands[0].stick = Vec2::Y;
        c.hands[1].trigger = 1.0;
    }
    play_until(&mut app, 20, |g| g.tick >= 10);
    assert!(events(&app).contains(&GameEvent::Fired), "{:?}", events(&app));
    let recorded = &app.world().resource::<input::InputSource>().recorded;
    assert!(
        recorded
            .iter()
            .any(|e| e.input.fire && e.input.thrust == DVec3::NEG_Z && e.input.turn == DVec3::ZERO),
        "{recorded:?}"
    );
    let player = game(&app).player;
    let body = app.world().entity(player);
    assert!(body.contains::<XrBody>());
    assert!(!body.get::<XrLocomotion>().expect("locomotion").enabled);
}

/// In a headset each eye draws its own crosshair where it sees the point
/// one inradius ahead on the shots' geodesic, so the two converge there:
/// with eyes `a` to either side of the head, that point is off each eye's
/// axis by the slope `sinh a / tanh d` in H3 (`a / d` in E3), the right
/// triangle at the head, and level with it. Checked through the eyes' own
/// off-centre projection (bevy_mod_xr's), to a thousandth of a pixel.
#[cfg(feature = "xr")]
#[test]
fn in_a_headset_the_eyes_crosshairs_converge_where_the_geometry_says() {
    use bevy_manifold::placement::tracked;
    use bevy_mod_xr::camera::{Fov, calculate_projection};
    let fov = |eye: usize| {
        let [l, r, d, u] = [-0.87f32, 0.70, -0.84, 0.77];
        if eye == 0 { [l, r, d, u] } else { [-r, -l, d, u] }
    };
    let size = Vec2::new(1512.0, 1680.0);
    for (space, hyperbolic) in [(catalog::torus(1.0), false), (catalog::seifert_weber(), true)] {
        let g = space.geometry();
        let ahead = space.inradius();
        // 64 mm at 0.32 m per unit: each eye 0.1 from the head.
        let room = [
            (Vec3::new(-0.032, 0.0, 0.0), Quat::IDENTITY),
            (Vec3::new(0.032, 0.0, 0.0), Quat::IDENTITY),
        ];
        let (_, eyes) = tracked::head_and_eyes(g, DMat4::IDENTITY, room, 0.32);
        let a = f64::from(0.032f32) / 0.32;
        let off = if hyperbolic { a.sinh() / ahead.tanh() } else { a / ahead };
        for (k, eye) in eyes.iter().enumerate() {
            let [l, r, d, u] = fov(k);
            let p = calculate_projection(
                0.01,
                Fov {
                    angle_left: l,
                    angle_right: r,
                    angle_down: d,
                    angle_up: u,
                },
            );
            let at = xr::crosshair_pixel(g, *eye, p, size, ahead).expect("in front");
            let [l, r, d, u] = [l, r, d, u].map(|x| f64::from(x).tan());
            let slope = if k == 0 { off } else { -off };
            let want = (
                ((slope - (r + l) / 2.0) / ((r - l) / 2.0) + 1.0) / 2.0 * f64::from(size.x),
                (1.0 - (0.0 - (u + d) / 2.0) / ((u - d) / 2.0)) / 2.0 * f64::from(size.y),
            );
            eprintln!(
                "{}: eye {k}: crosshair at ({:.3}, {:.3}), predicted ({:.3}, {:.3})",
                space.name(),
                at.x,
                at.y,
                want.0,
                want.1
            );
            assert!((f64::from(at.x) - want.0).abs() < 1e-3 && (f64::from(at.y) - want.1).abs() < 1e-3);
        }
    }
}

/// A product game (`product.rs`) with no targets, the player's view put
/// at the origin looking along `forward` (a unit tangent there; right is
/// the origin's x, or y when looking along x), firing once.
fn product_game(space: &str, forward: bevy_manifold::geometry::product::ProductTangent) -> App {
    use bevy_manifold::geometry::product::{ProductPoint, ProductTangent};
    let mut app = product::product_headless_app(config(space), Some(fire_once(space)), Duration::from_secs_f64(TICK));
    let player = app.world().resource::<product::ProductGame>().player;
    let mut camera = app
        .world_mut()
        .get_mut::<bevy_manifold::product::ProductCamera>(player)
        .expect("the player");
    let along_x = forward.surface.x.abs() > 0.5;
    let right = if along_x {
        ProductTangent::new(DVec3::Y, 0.0)
    } else {
        ProductTangent::new(DVec3::X, 0.0)
    };
    let up = if forward.height.abs() > 0.5 {
        ProductTangent::new(DVec3::Y, 0.0)
    } else {
        ProductTangent::new(DVec3::ZERO, 1.0)
    };
    camera.view.eye = ProductPoint::ORIGIN;
    camera.view.frame = [
        forward,
        if along_x {
            right
        } else {
            ProductTangent::new(DVec3::X, 0.0)
        },
        up,
    ];
    app
}

fn product_log(app: &App) -> Vec<(u64, product::ProductEvent)> {
    app.world().resource::<product::ProductGame>().log.clone()
}

/// Plays until an event past the firing, or `max` ticks.
fn play_product_until_hit(app: &mut App, max: u64) {
    while product_log(app).len() < 2 && app.world().resource::<product::ProductGame>().tick < max {
        app.update();
    }
}

/// In S2 x S1 with a circle of 2, a shot fired straight up comes back
/// from below after the circle and hits its shooter: it starts `r_p +
/// r_s` above the eye and is met `r_p + r_s` below it, so it flies `2 -
/// 2 (r_p + r_s)` through one face (the top), in the tick whose step
/// holds that distance (60 ticks a second).
#[test]
fn in_s2xs1_a_shot_up_the_circle_comes_back_and_hits_its_shooter() {
    use bevy_manifold::geometry::product::ProductTangent;
    let mut app = product_game("s2xs1", ProductTangent::new(DVec3::ZERO, 1.0));
    play_product_until_hit(&mut app, 200);
    let rules = app.world().resource::<product::ProductGame>().rules;
    let reach = rules.player_radius + rules.shot_radius;
    let expected = 2.0 - 2.0 * reach;
    let log = product_log(&app);
    assert_eq!(log[0], (0, product::ProductEvent::Fired));
    let (tick, product::ProductEvent::PlayerHit { distance, faces }) = log[1].clone() else {
        panic!("{log:?}");
    };
    assert!((distance - expected).abs() < 1e-9, "{distance} against {expected}");
    assert_eq!(faces, 1);
    // In the tick whose step holds that distance.
    let step = rules.shot_speed * TICK;
    assert!(
        tick as f64 * step < expected + 1e-9 && expected <= (tick + 1) as f64 * step + 1e-9,
        "tick {tick}, step {step}, distance {expected}"
    );
}

/// In S2 x S1 a shot fired along the sphere goes round the great circle
/// and comes back from behind after `2 pi - 2 (r_p + r_s)`, through no
/// face.
#[test]
fn in_s2xs1_a_shot_round_the_sphere_comes_back_after_two_pi() {
    use bevy_manifold::geometry::product::ProductTangent;
    let mut app = product_game("s2xs1", ProductTangent::new(DVec3::X, 0.0));
    play_product_until_hit(&mut app, 400);
    let rules = app.world().resource::<product::ProductGame>().rules;
    let expected = 2.0 * PI - 2.0 * (rules.player_radius + rules.shot_radius);
    let log = product_log(&app);
    let product::ProductEvent::PlayerHit { distance, faces } = log[1].1.clone() else {
        panic!("{log:?}");
    };
    assert!((distance - expected).abs() < 1e-9, "{distance} against {expected}");
    assert_eq!(faces, 0);
}

/// In the genus-2 surface times a circle, a target 2 along x from the
/// eye lies past a side of the octagon (whose inradius is `acosh(cot
/// pi/8)` = 1.53): the game keeps it in the prism, as the gluing's image,
/// and the shot fired along x meets it through that side, after `2 - r_t
/// - r_s - (r_p + r_s)`; the target then moves on and the score is 1.
#[test]
fn in_genus2xs1_a_target_past_a_side_is_hit_through_it() {
    use bevy_manifold::geometry::product::{ProductPoint, ProductTangent};
    use bevy_manifold::trace::product::{ProductRay, flow};
    let inradius = (1.0 / (PI / 8.0).tan()).acosh();
    assert!(inradius < 2.0 && inradius > 1.5, "{inradius}");
    let mut app = product_game("genus2xs1", ProductTangent::new(DVec3::X, 0.0));
    let (space, rules, root) = {
        let game = app.world().resource::<product::ProductGame>();
        (game.space.clone(), game.rules, game.root)
    };
    let along = ProductRay {
        origin: ProductPoint::ORIGIN,
        dir: ProductTangent::new(DVec3::X, 0.0),
    };
    let walk = flow(&space, along, 2.0, 8);
    assert_eq!(walk.faces.len(), 1, "the target is past one side");
    let target = app
        .world_mut()
        .spawn((
            ChildOf(root),
            product::ProductTarget,
            bevy_manifold::product::ProductBody {
                center: walk.ray.origin,
                radius: rules.target_radius,
                id: product::TARGET_ID,
            },
        ))
        .id();
    play_product_until_hit(&mut app, 120);
    let expected = 2.0 - rules.target_radius - rules.shot_radius - (rules.player_radius + rules.shot_radius);
    let log = product_log(&app);
    let product::ProductEvent::TargetHit { distance, faces } = log[1].1.clone() else {
        panic!("{log:?}");
    };
    assert!((distance - expected).abs() < 1e-9, "{distance} against {expected}");
    assert_eq!(faces, 1);
    let game = app.world().resource::<product::ProductGame>();
    assert_eq!(game.score, 1);
    let moved = app
        .world()
        .get::<bevy_manifold::product::ProductBody>(target)
        .unwrap()
        .center;
    assert!(
        space.geometry.distance(moved, walk.ray.origin) > 1e-6,
        "the target did not move on"
    );
}

/// The autopilot plays the product game for 20 seconds in each product
/// space with its targets: it scores, and a recording of its inputs
/// replayed as a script plays the same game (the same events at the same
/// ticks).
#[test]
fn the_product_game_is_played_by_the_bot_and_replays_exactly() {
    for space in ["genus2xs1", "s2xs1", "mirrored-prism"] {
        let dt = Duration::from_secs_f64(TICK);
        let config = GameConfig {
            spawn: true,
            ..config(space)
        };
        let mut app = product::product_headless_app(config.clone(), None, dt);
        product::with_product_bot(&mut app);
        while app.world().resource::<product::ProductGame>().tick < 1200 {
            app.update();
        }
        let (score, log) = {
            let game = app.world().resource::<product::ProductGame>();
            (game.score, game.log.clone())
        };
        eprintln!("{space}: the bot scored {score} in 20 s ({} events)", log.len());
        assert!(score >= 2, "{space}: the bot scored {score}");
        let script = app.world().resource::<input::InputSource>().recording(&config, 1200);
        let script = Script::parse(&script.to_json()).expect("the recording reads back");
        let mut replay = product::product_headless_app(config, Some(script), dt);
        while replay.world().resource::<product::ProductGame>().tick < 1200 {
            replay.update();
        }
        assert_eq!(product_log(&replay), log, "{space}: the replay differs");
    }
}
