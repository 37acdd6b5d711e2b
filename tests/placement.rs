//! Entities in the manifold, in a headless `App` with `MinimalPlugins` and
//! time stepped by hand.

use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bevy_manifold::geometry::{Geometry, isometry};
use bevy_manifold::prelude::*;
use bevy_manifold::space::element::CellElement;
use glam::{DMat4, DVec3, DVec4, IVec3};
use std::f64::consts::PI;
use std::time::Duration;

#[derive(Resource, Default)]
struct Crossings(Vec<FaceCrossed>);

fn collect(mut reader: MessageReader<FaceCrossed>, mut all: ResMut<Crossings>) {
    all.0.extend(reader.read().copied());
}

fn app(step: Duration) -> App {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, ManifoldPlugins::default()))
        .insert_resource(TimeUpdateStrategy::ManualDuration(step))
        .init_resource::<Crossings>()
        .add_systems(Last, collect);
    // These apps run a handful of tiny systems millions of times (the
    // wander test): every schedule on one thread, without the multi-threaded
    // executor's hand-offs, is several times faster.
    for (_, schedule) in app.world_mut().resource_mut::<Schedules>().iter_mut() {
        schedule.set_executor(bevy::ecs::schedule::SingleThreadedExecutor::new());
    }
    app
}

fn spawn_space(app: &mut App, space: Space) -> Entity {
    app.world_mut().spawn(ManifoldSpace::new(space)).id()
}

/// Updates until the virtual clock reads `t`.
fn run_until(app: &mut App, t: Duration) {
    for _ in 0..1_000_000 {
        if app.world().resource::<Time>().elapsed() >= t {
            return;
        }
        app.update();
    }
    panic!("time did not reach {t:?}");
}

fn max_abs(m: DMat4) -> f64 {
    m.to_cols_array().iter().fold(0.0f64, |a, x| a.max(x.abs()))
}

/// A mover leaving the centre of `space` with velocity `linear` for one
/// second (at twice the inradius, back at the centre): the app, the mover
/// and its placement then, asserted to be at the centre.
fn back_at_the_centre(space: &Space, linear: DVec3) -> (App, Entity, DMat4) {
    let mut app = app(Duration::from_millis(10));
    let root = spawn_space(&mut app, space.clone());
    let e = app
        .world_mut()
        .spawn((ChildOf(root), GeodesicVelocity { linear, ..default() }))
        .id();
    run_until(&mut app, Duration::from_secs(1));
    let p = app.world().get::<Placement>(e).unwrap().isometry;
    assert!(
        (p.w_axis - DVec4::W).length() < 1e-9,
        "{}: back at the centre: {:?}",
        space.name(),
        p.w_axis
    );
    (app, e, p)
}

#[test]
fn torus_mover_crosses_the_x_face_once_per_unit_of_time() {
    let mut app = app(Duration::from_millis(10));
    let root = spawn_space(&mut app, catalog::torus(1.0));
    let e = app
        .world_mut()
        .spawn((
            ChildOf(root),
            GeodesicVelocity {
                linear: DVec3::X,
                ..default()
            },
        ))
        .id();
    for n in 1..=4 {
        // The +x face is at x = 1/2: crossings at t = 0.5, 1.5, 2.5, ...
        run_until(&mut app, Duration::from_millis(n * 1000));
        let cell = app.world().get::<DomainCell>(e).unwrap();
        assert_eq!(cell.id.lattice(), Some(IVec3::new(n as i32, 0, 0)), "after {n} s");
        let x = app.world().get::<Placement>(e).unwrap().position().x;
        assert!(x.abs() < 1e-9, "back at x = 0 after {n} s, got {x}");
        let crossed = &app.world().resource::<Crossings>().0;
        assert_eq!(crossed.len(), n as usize);
        for (k, c) in crossed.iter().enumerate() {
            assert_eq!((c.entity, c.face), (e, 0), "out through +x");
            assert_eq!(c.old_cell.lattice(), Some(IVec3::new(k as i32, 0, 0)));
            assert_eq!(c.new_cell.lattice(), Some(IVec3::new(k as i32 + 1, 0, 0)));
        }
    }
    // Transform follows the chart position.
    run_until(&mut app, Duration::from_millis(4250));
    let t = app.world().get::<Transform>(e).unwrap().translation;
    assert!((t.x - 0.25).abs() < 1e-6 && t.y == 0.0, "{t}");
}

#[test]
fn dodecahedral_spaces_return_along_an_axis_turned_by_the_twist() {
    for (space, twist) in [
        (catalog::seifert_weber(), 3.0 * PI / 5.0),
        (catalog::poincare(), PI / 5.0),
    ] {
        let g = space.geometry();
        let (face, r) = (2, space.inradius());
        let u = space.faces()[face].plane.truncate().normalize();
        let expected_cell = space.crossing(face);
        // Speed 2r per second: back at the centre after exactly one second.
        let (app, e, p) = back_at_the_centre(&space, u * 2.0 * r);
        // The frame is turned about the direction of travel by the twist.
        let turned = isometry::rotation(u, twist);
        assert!(max_abs(p - turned) < 1e-9, "{}: frame turned by {twist}", space.name());
        assert!(isometry::isometry_error(g, p) < 1e-12);
        let cell = app.world().get::<DomainCell>(e).unwrap();
        assert!(max_abs(cell.element - expected_cell) < 1e-9, "{}", space.name());
        assert_eq!(cell.id, space.cell_id(&expected_cell));
        let crossed = &app.world().resource::<Crossings>().0;
        assert_eq!(
            crossed.iter().map(|c| c.face).collect::<Vec<_>>(),
            vec![face],
            "{}",
            space.name()
        );
    }
}

/// Lens spaces and RP3, whose domains have no vertices: a mover leaving
/// the centre across a face (RP3: towards the face a quarter turn away)
/// at twice the inradius a second is back at the centre after a second,
/// through that one face, placed where the cover says: the crossing's
/// inverse times its straight path in S3.
#[test]
fn lens_movers_return_to_the_centre_through_one_face() {
    for name in ["rp3", "lens-3-1", "lens-5-1"] {
        let space = bevy_manifold::space::library::by_name(name)
            .expect("library")
            .dirichlet_domain()
            .expect("builds");
        let g = space.geometry();
        let r = space.inradius();
        let face = 0;
        let u = match space.faces()[face].plane.truncate().normalize() {
            n if n.is_finite() => n,
            _ => DVec3::X, // RP3: its face is the sphere at w = 0
        };
        let (app, e, p) = back_at_the_centre(&space, u * 2.0 * r);
        let cell = app.world().get::<DomainCell>(e).unwrap();
        let cover = isometry::translation(g, u * 2.0 * r);
        assert!(
            max_abs(cell.element * p - cover) < 1e-9,
            "{name}: the cell times the placement is the path in the cover"
        );
        assert!(max_abs(cell.element - space.crossing(face)) < 1e-9, "{name}");
        let crossed = &app.world().resource::<Crossings>().0;
        assert_eq!(crossed.len(), 1, "{name}: one face crossed");
    }
}

#[test]
fn mirrored_cube_crossings_flip_parity() {
    let mut app = app(Duration::from_millis(10));
    let root = spawn_space(&mut app, catalog::mirrored_cube(1.0));
    let e = app
        .world_mut()
        .spawn((
            ChildOf(root),
            GeodesicVelocity {
                linear: DVec3::new(1.0, 0.3, 0.0),
                ..default()
            },
        ))
        .id();
    let mut seen = 0;
    for step in 0..400 {
        app.update();
        let crossed = app.world().resource::<Crossings>().0.len();
        let p = *app.world().get::<Placement>(e).unwrap();
        assert_eq!(
            p.mirrored,
            crossed % 2 == 1,
            "step {step}: parity after {crossed} mirror crossings"
        );
        assert_eq!(
            p.isometry.determinant() < 0.0,
            p.mirrored,
            "the frame's handedness is the parity"
        );
        let sx = app.world().get::<Transform>(e).unwrap().scale.x;
        assert_eq!(sx < 0.0, p.mirrored, "Transform shows the mirror image");
        seen = crossed;
    }
    assert!(seen >= 4, "bounced between the mirrors {seen} times");
}

#[test]
fn random_wanderers_stay_in_the_group_inside_and_in_the_right_cell() {
    const CROSSINGS: usize = 1_000_000;
    for name in catalog::NAMES {
        let space = catalog::by_name(name).unwrap();
        let g = space.geometry();
        let mut app = app(Duration::from_millis(100));
        let root = spawn_space(&mut app, space.clone());
        // About one face per frame.
        let speed = 2.0 * space.circumradius() / 0.1;
        let e = app
            .world_mut()
            .spawn((
                ChildOf(root),
                GeodesicVelocity {
                    linear: DVec3::new(0.3, -0.2, -1.0) * speed,
                    ..default()
                },
            ))
            .id();
        // The ground truth: the same motion followed in the cover, where
        // nothing wraps (each frame the closed-form screw motion of that
        // frame's velocity), so the mover's cell is cover * placement^-1,
        // found without the face word the wrap produced.
        let mut cover = DMat4::IDENTITY;
        let (mut checked, mut total, mut frame) = (0usize, 0usize, 0u64);
        let horizon = bevy_manifold::space::cells::HASHED_HORIZON;
        let mut beyond = false;
        while total < CROSSINGS {
            frame += 1;
            // Turn a little differently every frame.
            let a = (frame as f64 * 0.618).sin();
            let angular = DVec3::new(a, 2.0 * a * a - 1.0, 0.5) * 3.0;
            app.world_mut().get_mut::<GeodesicVelocity>(e).unwrap().angular = angular;
            app.update();
            let dt = app.world().resource::<Time>().delta_secs_f64();
            let linear = app.world().get::<GeodesicVelocity>(e).unwrap().linear;
            cover = isometry::orthonormalize(g, cover * isometry::exp_twist(g, linear * dt, angular * dt));
            let p = *app.world().get::<Placement>(e).unwrap();
            let err = isometry::isometry_error(g, p.isometry);
            assert!(
                err < 1e-12,
                "{name}: left the group by {err:e} after {total} crossings at {:?}",
                p.position()
            );
            assert!(
                space.outside_face(p.position(), 1e-9).is_none(),
                "{name}: outside the domain"
            );
            let crossed = std::mem::take(&mut app.world_mut().resource_mut::<Crossings>().0);
            total += crossed.len();
            let cell = app.world().get::<DomainCell>(e).unwrap().clone();
            let element = cover * isometry::inverse(g, p.isometry);
            let w = element.w_axis.w.abs();
            // In H3 the cover's entries grow like e^distance and the two
            // routes part like e^distance too: they agree within the f64
            // horizon (distance ~12 from the origin copy); beyond it the
            // cover is no ground truth. A margin of 2 either side
            // keeps rounding off the threshold.
            if !beyond && w < horizon / 2.0 {
                assert_eq!(cell.id, space.cell_id(&element), "{name}: after {total} crossings");
                assert!(!cell.id.is_far());
                checked = total;
            } else if !element.is_finite() || w > 2.0 * horizon {
                beyond = true;
                // Where the space's ids are exact they stay exact past the
                // f64 horizon (tests/exact.rs in the core checks them
                // against the relations); elsewhere a far cell is flagged.
                let exact = matches!(cell.cell, CellElement::Exact(_));
                assert_eq!(exact, space.cells().kind() == "exact" && !cell.id.is_far(), "{name}");
                assert!(
                    exact || cell.id.is_far(),
                    "{name}: a far cell must be flagged, after {total} crossings"
                );
            }
        }
        eprintln!("{name}: {total} crossings, ids checked against the cover's over the first {checked}");
        match g {
            // About 12 units from the origin copy, at a crossing each unit
            // or so: the horizon is some crossings out.
            Geometry::Hyperbolic => assert!(checked >= 4, "{name}: checked {checked}"),
            _ => assert!(checked >= CROSSINGS, "{name}: checked {checked}"),
        }
    }
}

#[test]
fn walls_stop_movers_and_casts_and_hidden_cells_are_not_hit() {
    use bevy_manifold::space::rule::{CellRule, OnOff, Walls};
    let space = catalog::seifert_weber();
    let walls = CellRule {
        hidden: None,
        walls: Some(Walls { density: 1.0, seed: 2 }),
    };
    // A seed that hides the neighbour through face 0.
    let neighbour = space.cell_id_of(&space.cell_of_word(&[0]));
    let hide = |seed| CellRule {
        hidden: Some(OnOff { on_fraction: 0.5, seed }),
        walls: None,
    };
    let hidden = hide((0..1000).find(|&seed| !hide(seed).visible(neighbour)).unwrap());
    // (rule, the mover crosses, the copy through face 0 is hit, a wall)
    for (rule, expect_crossing, expect_beyond, expect_wall) in [
        (CellRule::default(), true, true, None),
        (walls, false, false, Some(0)),
        (hidden, true, false, None),
    ] {
        let mut app = app(Duration::from_millis(50));
        let root = app
            .world_mut()
            .spawn(ManifoldSpace::new(space.clone()).with_rule(rule))
            .id();
        let mover = app
            .world_mut()
            .spawn((
                ChildOf(root),
                GeodesicVelocity {
                    linear: DVec3::new(0.3, 0.1, -1.0),
                    ..default()
                },
            ))
            .id();
        // A target one face away along the shot, and a shooter.
        let shooter = app.world_mut().spawn((ChildOf(root), Placement::default())).id();
        let through = space.cell_matrix(&space.cell_of_word(&[0])) * DVec4::W;
        let (target_at, _) = space.wrap(isometry::translation_to(space.geometry(), through), 10);
        app.world_mut().spawn((
            ChildOf(root),
            Placement::from_isometry(target_at),
            ManifoldCollider::Ball { radius: 0.3 },
        ));
        run_until(&mut app, Duration::from_secs(4));
        let crossed = app.world().resource::<Crossings>().0.len();
        let cell = app.world().get::<DomainCell>(mover).unwrap().clone();
        let inside = space
            .outside_face(app.world().get::<Placement>(mover).unwrap().isometry.w_axis, 1e-9)
            .is_none();
        assert!(inside);
        assert_eq!(crossed > 0, expect_crossing, "{crossed} crossings under {rule:?}");
        if !expect_crossing {
            assert_eq!(cell.id, CellId(0));
        }
        // Aim the shooter along face 0's axis.
        let axis = space.faces()[0].plane.truncate().normalize();
        let look = DMat4::look_to_rh(DVec3::ZERO, axis, if axis.y.abs() < 0.9 { DVec3::Y } else { DVec3::X }).inverse();
        app.world_mut().get_mut::<Placement>(shooter).unwrap().isometry = look;
        app.update();
        let (hits, wall) = app
            .world_mut()
            .run_system_once(move |cast: ManifoldRayCast| {
                let s = RayCastSettings {
                    exclude: Some(shooter),
                    ..default()
                };
                (
                    cast.cast(shooter, DVec3::NEG_Z, &s),
                    cast.wall(shooter, DVec3::NEG_Z, &s),
                )
            })
            .unwrap();
        let beyond = hits.iter().any(|h| h.faces == [0]);
        assert_eq!(beyond, expect_beyond, "the copy through face 0 under {rule:?}");
        assert_eq!(wall.map(|w| w.face), expect_wall);
    }
}

#[test]
fn a_fast_mover_ends_where_a_finely_stepped_one_does() {
    for (space, angular) in [
        (catalog::seifert_weber(), DVec3::ZERO),
        (catalog::torus(1.0), DVec3::ZERO),
        (catalog::poincare(), DVec3::new(0.2, 0.1, -0.3)),
        (catalog::mirrored_dodecahedron(), DVec3::new(0.0, 0.4, 0.1)),
    ] {
        let velocity = GeodesicVelocity {
            linear: DVec3::new(0.41, 0.23, -1.0) * 3.0 * space.circumradius(),
            angular,
        };
        let run = |step_ms: u64| {
            let mut a = app(Duration::from_millis(step_ms));
            let root = spawn_space(&mut a, space.clone());
            let e = a.world_mut().spawn((ChildOf(root), velocity)).id();
            run_until(&mut a, Duration::from_secs(2));
            let faces: Vec<usize> = a.world().resource::<Crossings>().0.iter().map(|c| c.face).collect();
            (
                *a.world().get::<Placement>(e).unwrap(),
                a.world().get::<DomainCell>(e).unwrap().clone(),
                faces,
            )
        };
        let (coarse, coarse_cell, coarse_faces) = run(1000);
        let (fine, fine_cell, fine_faces) = run(1);
        assert!(
            coarse_faces.len() >= 4,
            "{}: {} faces in two steps",
            space.name(),
            coarse_faces.len()
        );
        assert!(max_abs(coarse.isometry - fine.isometry) < 1e-9, "{}", space.name());
        assert_eq!(coarse_cell.id, fine_cell.id, "{}", space.name());
        assert_eq!(coarse.mirrored, fine.mirrored);
        if angular == DVec3::ZERO {
            // A straight path crosses the same faces in the same order.
            assert_eq!(coarse_faces, fine_faces, "{}", space.name());
        }
    }
}

#[test]
fn ray_casts_see_through_faces_and_not_behind() {
    // Seifert-Weber: caster at the centre facing face 0's axis; a ball on
    // the same axis behind it. The ray leaves through face 0, comes back in
    // through face 6 (the twist turns about the axis, so the ball stays on
    // it) and meets the ball at 2r - a - radius.
    let sw = catalog::seifert_weber();
    let r = sw.inradius();
    let u = sw.faces()[0].plane.truncate().normalize();
    let (a, radius) = (0.4, 0.1);
    let mut world_app = app(Duration::from_millis(10));
    let root = spawn_space(&mut world_app, sw.clone());
    let facing = isometry::rotation(DVec3::Z.cross(-u), DVec3::Z.angle_between(-u));
    let caster = world_app
        .world_mut()
        .spawn((ChildOf(root), Placement::from_isometry(facing)))
        .id();
    let target = world_app
        .world_mut()
        .spawn((
            ChildOf(root),
            Placement::at(&sw, -u * a),
            ManifoldCollider::Ball { radius },
        ))
        .id();
    world_app.update();
    let hits = world_app
        .world_mut()
        .run_system_once(move |cast: ManifoldRayCast| {
            cast.cast(
                caster,
                DVec3::NEG_Z,
                &RayCastSettings {
                    max_distance: 3.0,
                    exclude: Some(caster),
                    ..default()
                },
            )
        })
        .unwrap();
    assert!(!hits.is_empty(), "the ball is seen through the face");
    let h = &hits[0];
    assert_eq!(h.entity, target);
    assert!(
        (h.distance - (2.0 * r - a - radius)).abs() < 1e-9,
        "hit at {}",
        h.distance
    );
    assert_eq!(h.faces, vec![0]);
    assert_eq!(h.cell, sw.cell_id(&sw.crossing(0)));
    // Nothing at the short distance a - radius straight behind.
    assert!(hits.iter().all(|h| h.distance > a), "{hits:?}");

    // Torus: a ball straddling the +x face is hit from the -x side of the
    // domain through its ghost, and everything is reported in order.
    let mut t_app = app(Duration::from_millis(10));
    let root = spawn_space(&mut t_app, catalog::torus(1.0));
    let facing = isometry::rotation(DVec3::Y, PI / 2.0); // -z turned to -x
    let caster = t_app
        .world_mut()
        .spawn((
            ChildOf(root),
            Placement::from_isometry(DMat4::from_translation(DVec3::new(-0.1, 0.0, 0.0)) * facing),
        ))
        .id();
    let ball = t_app
        .world_mut()
        .spawn((
            ChildOf(root),
            Placement::from_isometry(DMat4::from_translation(DVec3::new(0.45, 0.0, 0.0))),
            ManifoldCollider::Ball { radius: 0.1 },
        ))
        .id();
    t_app.update();
    let hits = t_app
        .world_mut()
        .run_system_once(move |cast: ManifoldRayCast| {
            cast.cast(
                caster,
                DVec3::NEG_Z,
                &RayCastSettings {
                    max_distance: 2.5,
                    ..default()
                },
            )
        })
        .unwrap();
    let distances: Vec<f64> = hits.iter().map(|h| h.distance).collect();
    assert_eq!(hits[0].entity, ball);
    assert!((distances[0] - 0.35).abs() < 1e-9, "{distances:?}");
    assert!(
        hits[0].faces.is_empty(),
        "the ghost is inside the domain: no face crossed"
    );
    assert!(
        (distances[1] - 1.35).abs() < 1e-9,
        "the next copy, one unit on: {distances:?}"
    );
    assert!(distances.windows(2).all(|w| w[0] <= w[1]));
}

use bevy::ecs::system::RunSystemOnce;

#[test]
fn a_nan_placement_is_refused_and_the_old_one_kept() {
    let mut app = app(Duration::from_millis(10));
    let root = spawn_space(&mut app, catalog::torus(1.0));
    let e = app
        .world_mut()
        .spawn((ChildOf(root), Placement::at(&catalog::torus(1.0), DVec3::X * 0.2)))
        .id();
    app.update();
    let before = *app.world().get::<Placement>(e).unwrap();
    app.world_mut().get_mut::<Placement>(e).unwrap().isometry.w_axis.x = f64::NAN;
    app.update();
    let after = *app.world().get::<Placement>(e).unwrap();
    assert_eq!(after, before);
    assert_eq!(app.world().get::<DomainCell>(e).unwrap().id, CellId(0));
}

#[test]
fn fly_camera_keys_set_the_velocity() {
    let mut app = app(Duration::from_millis(10));
    app.add_plugins((bevy::input::InputPlugin, FlyCameraPlugin));
    let root = spawn_space(&mut app, catalog::seifert_weber());
    let cam = app
        .world_mut()
        .spawn((
            ChildOf(root),
            FlyCamera {
                speed: 2.0,
                ..default()
            },
        ))
        .id();
    app.update();
    app.world_mut()
        .resource_mut::<ButtonInput<KeyCode>>()
        .press(KeyCode::KeyW);
    app.world_mut()
        .resource_mut::<ButtonInput<KeyCode>>()
        .press(KeyCode::KeyQ);
    app.update();
    let v = *app.world().get::<GeodesicVelocity>(cam).unwrap();
    assert_eq!(v.linear, DVec3::new(0.0, 0.0, -2.0), "W flies forward (-z)");
    assert!(v.angular.z > 0.0, "Q rolls");
    app.update();
    let p = app.world().get::<Placement>(cam).unwrap();
    assert!(
        p.position().z < 0.0 && p.position().z > -0.1,
        "moved forward: {:?}",
        p.position()
    );
}

#[test]
fn two_spaces_at_once_each_wrap_their_own() {
    let mut app = app(Duration::from_millis(10));
    let torus = spawn_space(&mut app, catalog::torus(1.0));
    let cube = spawn_space(&mut app, catalog::mirrored_cube(2.0));
    let v = GeodesicVelocity {
        linear: DVec3::X,
        ..default()
    };
    let a = app.world_mut().spawn((ChildOf(torus), v)).id();
    // Nested deeper in the hierarchy: still in its root's space.
    let group = app.world_mut().spawn(ChildOf(cube)).id();
    let b = app.world_mut().spawn((ChildOf(group), v)).id();
    run_until(&mut app, Duration::from_millis(1200));
    // Torus: through +x once, on at x = 0.2. Mirrored cube of edge 2: hits
    // the mirror at x = 1 and comes back to x = 0.8, mirrored.
    let (pa, pb) = (
        *app.world().get::<Placement>(a).unwrap(),
        *app.world().get::<Placement>(b).unwrap(),
    );
    assert!(
        (pa.position().x - 0.2).abs() < 1e-9 && !pa.mirrored,
        "{:?}",
        pa.position()
    );
    assert!(
        (pb.position().x - 0.8).abs() < 1e-9 && pb.mirrored,
        "{:?}",
        pb.position()
    );
    let faces: Vec<(Entity, usize)> = app
        .world()
        .resource::<Crossings>()
        .0
        .iter()
        .map(|c| (c.entity, c.face))
        .collect();
    assert_eq!(faces, vec![(a, 0), (b, 0)]);
}

#[test]
fn membership_follows_the_hierarchy_and_the_scene_follows_membership() {
    let mut app = app(Duration::from_millis(10));
    let torus = spawn_space(&mut app, catalog::torus(1.0));
    let cube = spawn_space(&mut app, catalog::mirrored_cube(2.0));
    let balls_in = |app: &App, root: Entity| app.world().get::<ManifoldScene>(root).map(|s| s.scene().balls.len());
    let members = |app: &App, root: Entity| {
        let mut m: Vec<Entity> = app
            .world()
            .get::<SpaceMembers>(root)
            .map(|m| m.iter().collect())
            .unwrap_or_default();
        m.sort();
        m
    };
    // A ball under a group under the torus: both live in the torus.
    let group = app.world_mut().spawn(ChildOf(torus)).id();
    let ball = app
        .world_mut()
        .spawn((ChildOf(group), TracedBall::new(0.1, Color::WHITE)))
        .id();
    app.update();
    assert_eq!(app.world().get::<InSpace>(ball).map(InSpace::space), Some(torus));
    assert_eq!(members(&app, torus), {
        let mut m = vec![group, ball];
        m.sort();
        m
    });
    assert_eq!((balls_in(&app, torus), balls_in(&app, cube)), (Some(1), Some(0)));
    // Re-parented into the cube: the group's whole subtree moves.
    app.world_mut().entity_mut(group).insert(ChildOf(cube));
    app.update();
    assert_eq!(app.world().get::<InSpace>(ball).map(InSpace::space), Some(cube));
    assert!(members(&app, torus).is_empty());
    assert_eq!((balls_in(&app, torus), balls_in(&app, cube)), (Some(0), Some(1)));
    // Detached: in no space, drawn nowhere.
    app.world_mut().entity_mut(group).remove::<ChildOf>();
    app.update();
    assert!(app.world().get::<InSpace>(ball).is_none());
    assert_eq!((balls_in(&app, torus), balls_in(&app, cube)), (Some(0), Some(0)));
    // The group becomes a space root itself: its children live in it.
    app.world_mut()
        .entity_mut(group)
        .insert(ManifoldSpace::new(catalog::poincare()));
    app.update();
    assert_eq!(app.world().get::<InSpace>(ball).map(InSpace::space), Some(group));
    assert_eq!(balls_in(&app, group), Some(1));
    // And stops being one: the ball is in no space again.
    app.world_mut().entity_mut(group).remove::<ManifoldSpace>();
    app.update();
    assert!(app.world().get::<InSpace>(ball).is_none());
}

#[test]
fn a_space_with_more_balls_and_lights_than_it_holds_draws_the_first_ones() {
    // 254 balls (their ghosts within the GPU's ball array), and every hit
    // loops over the lights: 300 balls and 100 lights are cut to 254 and
    // 64 with a warning; a huge H3 radius is drawn at the cap.
    let mut app = app(Duration::from_millis(10));
    let space = catalog::seifert_weber();
    let root = spawn_space(&mut app, space.clone());
    for i in 0..300 {
        let radius = if i == 0 { 500.0 } else { 0.01 };
        app.world_mut()
            .spawn((ChildOf(root), TracedBall::new(radius, Color::WHITE)));
    }
    for _ in 0..100 {
        app.world_mut().spawn((ChildOf(root), ManifoldLight::default()));
    }
    app.update();
    let scene = app.world().get::<ManifoldScene>(root).expect("gathered").scene();
    assert_eq!(scene.balls.len(), 254);
    assert_eq!(scene.lights.len(), bevy_manifold::trace::MAX_LIGHTS);
    let biggest = scene.balls.iter().map(|b| b.radius).fold(0.0, f64::max);
    assert_eq!(biggest, bevy_manifold::trace::max_radius(Geometry::Hyperbolic));
}

/// A tracer scene spawned as entities (`spawn_scene`, what offscreen views
/// and tools use) gathers back to the same lights and balls: a spot points
/// where the scene's does (its placement's forward), in each geometry and
/// away from the origin; a ball keeps its material; the root keeps the
/// scene's lighting.
#[test]
fn a_scene_spawned_as_entities_gathers_back_to_itself() {
    use bevy_manifold::drawables::spawn_scene;
    use bevy_manifold::trace::{Lighting, Spot};
    for space in [catalog::torus(1.0), catalog::seifert_weber(), catalog::poincare()] {
        let g = space.geometry();
        let mut scene = Scene::default_for(&space);
        let p = scene.lights[0].position;
        let dir = g.normalize_tangent::<f64>(p, g.project_tangent::<f64>(p, DVec4::new(0.3, -0.8, 0.5, 0.4)));
        scene.lights[0].spot = Some(Spot {
            direction: dir,
            inner: 0.2,
            outer: 0.5,
        });
        scene.balls[0].pbr = Some(bevy_manifold::material::Pbr {
            metallic: 0.25,
            roughness: 0.75,
        });
        scene.lighting = Lighting {
            images: 16,
            shadows: true,
        };
        let mut app = app(Duration::from_millis(10));
        let root = spawn_space(&mut app, space.clone());
        let world = app.world_mut();
        spawn_scene(&mut world.commands(), root, &space, &scene);
        world.flush();
        app.update();
        let got = app.world().get::<ManifoldScene>(root).expect("gathered").scene();
        let spot = got.lights[0].spot.expect("a spot");
        let back = g.normalize_tangent::<f64>(got.lights[0].position, spot.direction);
        assert!((got.lights[0].position - p).length() < 1e-12, "{g}");
        assert!(
            (back - dir).length() < 1e-9,
            "{g}: the spot points along {back}, not {dir}"
        );
        assert_eq!((spot.inner, spot.outer), (0.2, 0.5));
        assert_eq!(got.balls[0].pbr, scene.balls[0].pbr, "{g}");
        assert_eq!(got.lighting, scene.lighting, "{g}");
    }
}

/// Balls in a product space as entities: a [`ProductBody`] with a
/// [`ProductVelocity`] under a [`ProductSpaceRoot`] moves along its
/// geodesic through the faces (where the core's `flow` takes it, the
/// centre always in the prism), and the root's [`ProductCamera`] shows
/// it where it is each frame, with the root's space.
///
/// [`ProductBody`]: bevy_manifold::product::ProductBody
/// [`ProductVelocity`]: bevy_manifold::product::ProductVelocity
/// [`ProductSpaceRoot`]: bevy_manifold::product::ProductSpaceRoot
/// [`ProductCamera`]: bevy_manifold::product::ProductCamera
#[test]
fn product_bodies_move_through_the_faces_and_the_camera_shows_them() {
    use bevy_manifold::geometry::product::{ProductPoint, ProductTangent};
    use bevy_manifold::product::{ProductBody, ProductCamera, ProductSpaceRoot, ProductVelocity};
    use bevy_manifold::space::product::ProductSpace;
    use bevy_manifold::trace::product::{ProductRay, flow};
    use std::sync::Arc;
    let space = ProductSpace::genus_two_x_s1(2.0);
    let g = space.geometry;
    let mut app = app(Duration::from_millis(100));
    let root = app.world_mut().spawn(ProductSpaceRoot(Arc::new(space.clone()))).id();
    let start = ProductPoint::ORIGIN;
    let v = ProductTangent::new(DVec3::new(1.2, 0.5, 0.0), 0.7);
    let body = app
        .world_mut()
        .spawn((
            ChildOf(root),
            ProductBody {
                center: start,
                radius: 0.2,
                id: 7,
            },
            ProductVelocity(v),
        ))
        .id();
    // A camera with a scene of its own, which the root's replaces.
    let camera = app
        .world_mut()
        .spawn((ChildOf(root), ProductCamera::default_for(ProductSpace::s2_x_s1(1.0))))
        .id();
    let mut travelled = 0.0;
    for _ in 0..60 {
        app.update();
        let dt = f64::from(app.world().resource::<Time>().delta_secs());
        travelled += dt * v.length(g);
        let at = app.world().get::<ProductBody>(body).expect("the body").center;
        assert!(space.contains(at, 1e-9), "{at:?} left the prism");
    }
    assert!(travelled > 5.0, "{travelled}");
    // Where the core's flow takes the centre over the same distance.
    let expected = flow(
        &space,
        ProductRay {
            origin: start,
            dir: v.unit(g),
        },
        travelled,
        1000,
    );
    eprintln!("travelled {travelled:.3} through {} faces", expected.faces.len());
    assert!(expected.faces.len() >= 2, "{} faces", expected.faces.len());
    let at = app.world().get::<ProductBody>(body).expect("the body").center;
    assert!(
        g.distance(at, expected.ray.origin) < 1e-9,
        "{at:?} vs {:?}",
        expected.ray.origin
    );
    let speed = app.world().get::<ProductVelocity>(body).expect("velocity").0.length(g);
    assert!((speed - v.length(g)).abs() < 1e-9);
    // The camera shows the body where it is, in the root's space.
    let shown = app.world().get::<ProductCamera>(camera).expect("the camera");
    assert_eq!(shown.space.name, "genus 2 x S1");
    assert_eq!(shown.balls.len(), 1);
    assert_eq!(shown.balls[0].id, 7);
    assert!(g.distance(shown.balls[0].center, at) < 1e-12);
}

/// Gameplay casts in a product space ([`ProductRayCast`]): in S2 x S1
/// with a circle of 2, straight up from under two bodies on the pole
/// (at heights 0.5 and -0.5, radius 0.1), a ray meets each again every
/// circle, one more face crossed each time round; a body casting leaves
/// itself out; a ray along the sphere meets neither (they are 0.5 above
/// and below it), and a ray that is not finite meets nothing.
///
/// [`ProductRayCast`]: bevy_manifold::product::ProductRayCast
#[test]
fn product_casts_meet_each_body_again_every_circle() {
    use bevy::ecs::system::RunSystemOnce;
    use bevy_manifold::geometry::product::{ProductPoint, ProductTangent};
    use bevy_manifold::product::{ProductBody, ProductCamera, ProductRayCast, ProductSpaceRoot};
    use bevy_manifold::space::product::ProductSpace;
    use bevy_manifold::trace::product::ProductRay;
    use std::sync::Arc;
    let space = ProductSpace::s2_x_s1(2.0);
    let mut app = app(Duration::from_millis(16));
    let root = app.world_mut().spawn(ProductSpaceRoot(Arc::new(space.clone()))).id();
    let body = |app: &mut App, height: f64, id: u32| {
        app.world_mut()
            .spawn((
                ChildOf(root),
                ProductBody {
                    center: ProductPoint::new(DVec3::Z, height),
                    radius: 0.1,
                    id,
                },
            ))
            .id()
    };
    let (a, b) = (body(&mut app, 0.5, 1), body(&mut app, -0.5, 2));
    let mut camera = ProductCamera::default_for(space.clone());
    camera.view.eye = ProductPoint::ORIGIN;
    camera.view.frame = [
        ProductTangent::new(DVec3::ZERO, 1.0),
        ProductTangent::new(DVec3::X, 0.0),
        ProductTangent::new(DVec3::Y, 0.0),
    ];
    let eye = app.world_mut().spawn((ChildOf(root), camera)).id();
    app.update();
    let settings = RayCastSettings {
        max_distance: 4.5,
        ..default()
    };
    let seen = app
        .world_mut()
        .run_system_once(move |cast: ProductRayCast| {
            let up = cast.from_camera(eye, [1.0, 0.0, 0.0], &settings);
            let without_a = cast.from_camera(
                eye,
                [1.0, 0.0, 0.0],
                &RayCastSettings {
                    exclude: Some(a),
                    ..settings.clone()
                },
            );
            let from_a = cast.from_body(a, ProductTangent::new(DVec3::ZERO, 1.0), &settings);
            let across = cast.from_camera(
                eye,
                [0.0, 1.0, 0.0],
                &RayCastSettings {
                    max_distance: 10.0,
                    ..settings.clone()
                },
            );
            let broken = cast.cast(
                root,
                ProductRay {
                    origin: ProductPoint::ORIGIN,
                    dir: ProductTangent::new(DVec3::new(f64::NAN, 0.0, 0.0), 1.0),
                },
                &settings,
            );
            (up, without_a, from_a, across, broken)
        })
        .expect("the cast runs");
    let (up, without_a, from_a, across, broken) = seen;
    let summary = |hits: &[bevy_manifold::product::ProductRayHit]| -> Vec<(Entity, f64, usize)> {
        hits.iter()
            .map(|h| (h.entity, (h.distance * 1e9).round() / 1e9, h.faces.len()))
            .collect()
    };
    assert_eq!(
        summary(&up),
        vec![(a, 0.4, 0), (b, 1.4, 1), (a, 2.4, 1), (b, 3.4, 2), (a, 4.4, 2)]
    );
    assert_eq!(summary(&without_a), vec![(b, 1.4, 1), (b, 3.4, 2)]);
    // From A's centre up: the top at 0.5, then from -1 to B's bottom at -0.6.
    assert_eq!(summary(&from_a), vec![(b, 0.9, 1), (b, 2.9, 2)]);
    assert!(across.is_empty() && broken.is_empty(), "{across:?} {broken:?}");
}

/// Gameplay casts meet meshes too: in genus 2 x S1 a box (the chart's
/// `[-0.125, 0.125]^3`) whose centre is `atanh 0.5` along x from the
/// origin is met by a ray along x at 10 degrees up where its surface part
/// reaches the box's near wall, at surface distance `atanh 0.5 -
/// atanh 0.125` (distances add along the geodesic), over `cos 10`; a body
/// in front of it is met first, and a cast that leaves the mesh out meets
/// only the body.
#[test]
fn product_casts_meet_meshes() {
    use bevy::ecs::system::RunSystemOnce;
    use bevy_manifold::geometry::product::{ProductIsometry, ProductPoint, ProductTangent};
    use bevy_manifold::mesh::{MeshData, shapes::cuboid};
    use bevy_manifold::product::{ProductBody, ProductMeshBody, ProductRayCast, ProductSpaceRoot};
    use bevy_manifold::space::product::ProductSpace;
    use bevy_manifold::trace::product::{ProductMesh, ProductRay};
    use std::sync::Arc;
    let space = ProductSpace::genus_two_x_s1(2.0);
    let g = space.geometry;
    let mut app = app(Duration::from_millis(16));
    let root = app.world_mut().spawn(ProductSpaceRoot(Arc::new(space.clone()))).id();
    let mesh = app
        .world_mut()
        .spawn((
            ChildOf(root),
            ProductMeshBody(ProductMesh {
                mesh: MeshData::shared(cuboid([0.125; 3])),
                placement: ProductIsometry::new(g.translation(0.0, 0.5f64.atanh()), 1.0, 0.0),
                id: 1,
            }),
        ))
        .id();
    // A ball below the ray's way but for its start: 0.1 along x, 0.2 off
    // the ray's height there.
    let a = 10f64.to_radians();
    let ball = app
        .world_mut()
        .spawn((
            ChildOf(root),
            ProductBody {
                center: ProductPoint::new(DVec3::new(0.1f64.sinh(), 0.0, 0.1f64.cosh()), 0.1 * a.tan() - 0.2),
                radius: 0.05,
                id: 2,
            },
        ))
        .id();
    app.update();
    let ray = ProductRay {
        origin: ProductPoint::ORIGIN,
        dir: ProductTangent::new(DVec3::X * a.cos(), a.sin()),
    };
    let (all, without) = app
        .world_mut()
        .run_system_once(move |cast: ProductRayCast| {
            let settings = RayCastSettings {
                max_distance: 2.0,
                ..default()
            };
            let all = cast.cast(root, ray, &settings);
            let without = cast.cast(
                root,
                ray,
                &RayCastSettings {
                    exclude: Some(mesh),
                    ..settings
                },
            );
            (all, without)
        })
        .expect("the cast runs");
    let wall = (0.5f64.atanh() - 0.125f64.atanh()) / a.cos();
    assert_eq!(all.len(), 1, "{all:?}");
    assert_eq!(all[0].entity, mesh);
    assert!(
        (all[0].distance - wall).abs() < 1e-9,
        "{} against {wall}",
        all[0].distance
    );
    assert!(without.is_empty(), "{without:?}");
    // Raised into the ray's way, the ball is met first.
    app.world_mut()
        .get_mut::<ProductBody>(ball)
        .expect("the ball")
        .center
        .height = 0.1 * a.tan();
    let first = app
        .world_mut()
        .run_system_once(move |cast: ProductRayCast| {
            cast.cast(
                root,
                ray,
                &RayCastSettings {
                    max_distance: 2.0,
                    ..default()
                },
            )
        })
        .expect("the cast runs");
    assert_eq!(first.iter().map(|h| h.entity).collect::<Vec<_>>(), [ball, mesh]);
}

/// [`ProductContacts`]: in S2 x S1 of circle 2, bodies of radius 0.3 at
/// heights 0.9 and -0.9 touch through the top (0.2 apart, 0.4 deep), a
/// third at height 0 touches neither (0.9 from each), and bodies of
/// another space are not asked about.
///
/// [`ProductContacts`]: bevy_manifold::product::ProductContacts
#[test]
fn product_bodies_touch_through_the_faces() {
    use bevy::ecs::system::RunSystemOnce;
    use bevy_manifold::geometry::product::ProductPoint;
    use bevy_manifold::product::{ProductBody, ProductContacts, ProductSpaceRoot};
    use bevy_manifold::space::product::ProductSpace;
    use std::sync::Arc;
    let mut app = app(Duration::from_millis(16));
    let root = app
        .world_mut()
        .spawn(ProductSpaceRoot(Arc::new(ProductSpace::s2_x_s1(2.0))))
        .id();
    let other = app
        .world_mut()
        .spawn(ProductSpaceRoot(Arc::new(ProductSpace::s2_x_s1(2.0))))
        .id();
    let mut body = |parent: Entity, h: f64| {
        app.world_mut()
            .spawn((
                ChildOf(parent),
                ProductBody {
                    center: ProductPoint::new(DVec3::Z, h),
                    radius: 0.3,
                    id: 1,
                },
            ))
            .id()
    };
    let (a, b, c, d) = (body(root, 0.9), body(root, -0.9), body(root, 0.0), body(other, -0.9));
    app.update();
    let (from_a, from_c, a_d) = app
        .world_mut()
        .run_system_once(move |contacts: ProductContacts| {
            let from_a: Vec<(Entity, f64)> = contacts
                .touching(a)
                .into_iter()
                .map(|(e, t)| (e, (t[0].depth * 1e9).round() / 1e9))
                .collect();
            (from_a, contacts.touching(c), contacts.contacts(a, d))
        })
        .expect("the query runs");
    assert_eq!(from_a, vec![(b, 0.4)]);
    assert!(from_c.is_empty() && a_d.is_empty(), "{from_c:?} {a_d:?}");
}
