//! Per-cell rules (`space::rule`) in the CPU tracer and the gameplay
//! casts: objects in off cells are neither drawn nor hit (rays pass
//! through to what lies behind), walls stop rays and casts at the face.

use bevy_manifold_core::prelude::*;
use bevy_manifold_core::space::rule::{CellRule, OnOff, WALL_OBJECT, Walls};
use bevy_manifold_core::trace::step::Ray;
use bevy_manifold_core::trace::{CastBall, FaceTables, cast_with_rule};
use glam::{DVec3, DVec4};

fn settings(rule: CellRule) -> TraceSettings {
    TraceSettings {
        width: 96,
        height: 96,
        levels: 8,
        cell_rule: rule,
        ..TraceSettings::default()
    }
}

fn ball_scene(space: &Space) -> Scene {
    let mut scene = Scene::empty();
    scene.camera.isometry = bevy_manifold_core::geometry::isometry::translation(
        space.geometry(),
        DVec3::new(0.2, 0.1, 0.3) * space.inradius(),
    ) * glam::DMat4::from_rotation_y(0.5);
    scene.camera.fov_y_degrees = 90.0;
    scene.balls.push(Ball {
        center: DVec4::W,
        radius: 0.4 * space.inradius(),
        color: [1.0; 3],
        glow: 0.0,
        pbr: None,
    });
    scene
}

#[test]
fn off_cells_are_not_drawn_and_rays_pass_through_them() {
    let hidden = CellRule {
        hidden: Some(OnOff {
            on_fraction: 0.5,
            seed: 3,
        }),
        walls: None,
    };
    for name in ["torus", "seifert-weber", "poincare"] {
        let space = catalog::by_name(name).unwrap();
        let scene = ball_scene(&space);
        let plain = render::<f64>(&space, &scene, &settings(CellRule::default()));
        let ruled = render::<f64>(&space, &scene, &settings(hidden));
        let (mut through, mut kept) = (0, 0);
        for (p, q) in plain.pixels.iter().zip(&ruled.pixels) {
            if q.object != 0 {
                assert!(hidden.visible(q.cell), "{name}: a ball drawn in an off cell");
            }
            if p.object == 0 {
                continue;
            }
            if hidden.visible(p.cell) {
                // The nearest copy was on: the same hit.
                assert_eq!((q.object, q.cell), (p.object, p.cell), "{name}");
                kept += 1;
            } else {
                // It was off: the ray went on, to something farther or to
                // nothing.
                assert!(q.object == 0 || q.distance > p.distance, "{name}");
                through += 1;
            }
        }
        eprintln!("{name}: {kept} pixels kept their copy, {through} passed through an off copy");
        assert!(kept > 100 && through > 100, "{name}: {kept} kept, {through} through");
    }
}

#[test]
fn walls_everywhere_keep_every_ray_in_its_cell() {
    let walls = CellRule {
        hidden: None,
        walls: Some(Walls { density: 1.0, seed: 9 }),
    };
    for name in ["torus", "seifert-weber", "mirrored-dodecahedron"] {
        let space = catalog::by_name(name).unwrap();
        let scene = ball_scene(&space);
        let img = render::<f64>(&space, &scene, &settings(walls));
        let plain = render::<f64>(&space, &scene, &settings(CellRule::default()));
        let mut wall = 0;
        for (p, q) in img.pixels.iter().zip(&plain.pixels) {
            assert_eq!(p.levels, 0, "{name}: a ray crossed a wall");
            if p.object == WALL_OBJECT {
                wall += 1;
                // It stopped on the domain's boundary: no nearer than the
                // inradius from the centre's side, no farther than the
                // circumradius plus the camera's offset.
                assert!(
                    p.distance as f64 <= 2.0 * space.circumradius(),
                    "{name}: {}",
                    p.distance
                );
            } else {
                // The ball in the camera's own cell, as without walls.
                assert_eq!((p.object, p.cell), (q.object, q.cell), "{name}");
                assert_eq!(q.levels, 0, "{name}");
            }
        }
        assert!(wall > 1000, "{name}: {wall} wall pixels");
        // With half the faces walls, some rays cross and some stop.
        let half = CellRule {
            hidden: None,
            walls: Some(Walls { density: 0.5, seed: 9 }),
        };
        let img = render::<f64>(&space, &scene, &settings(half));
        let crossed = img.pixels.iter().filter(|p| p.levels > 0).count();
        let stopped = img.pixels.iter().filter(|p| p.object == WALL_OBJECT).count();
        assert!(
            crossed > 500 && stopped > 500,
            "{name}: {crossed} crossed, {stopped} stopped"
        );
    }
}

#[test]
fn casts_pass_off_cells_and_stop_at_walls() {
    // Seifert-Weber: a cast from the centre along face 0's axis meets the
    // ball's copy in the neighbour through face 0 (about 2 inradii away).
    let space = catalog::seifert_weber();
    let tables = FaceTables::<f64>::new(&space);
    let axis = space.faces()[0].plane.truncate().normalize();
    let ray = Ray {
        origin: DVec4::W,
        dir: axis.extend(0.0),
    };
    let balls = [CastBall {
        key: 7u32,
        center: DVec4::W,
        radius: 0.2,
    }];
    let start = space.origin_cell();
    let neighbour = space.cell_id_of(&space.cross_cell(&start, 0));
    let (plain, wall) = cast_with_rule(&space, &tables, ray, &balls, 5.0, 4, &start, &CellRule::default());
    assert!(wall.is_none());
    let first_beyond = plain
        .iter()
        .find(|h| h.faces == [0])
        .expect("the neighbour's copy")
        .distance;
    // Hide exactly the neighbour's copy: find a seed whose rule hides it
    // and shows the origin (always shown).
    let seed = (0..1000)
        .find(|&seed| {
            !CellRule {
                hidden: Some(OnOff { on_fraction: 0.5, seed }),
                walls: None,
            }
            .visible(neighbour)
        })
        .unwrap();
    let hidden = CellRule {
        hidden: Some(OnOff { on_fraction: 0.5, seed }),
        walls: None,
    };
    let (hits, _) = cast_with_rule(&space, &tables, ray, &balls, 5.0, 4, &start, &hidden);
    assert!(hits.iter().all(|h| h.faces != [0]), "the off neighbour's copy was hit");
    // Every other hit is the plain cast's, in a cell the rule shows.
    for h in &hits {
        assert!(plain.contains(h));
        let cell = h
            .faces
            .iter()
            .fold(space.origin_cell(), |c, &f| space.cross_cell(&c, f));
        assert!(hidden.visible(space.cell_id_of(&cell)));
    }
    // A wall on every face: the cast stops at face 0, before that copy.
    let walls = CellRule {
        hidden: None,
        walls: Some(Walls { density: 1.0, seed: 1 }),
    };
    let (hits, wall) = cast_with_rule(&space, &tables, ray, &balls, 5.0, 4, &start, &walls);
    let wall = wall.expect("a wall");
    assert_eq!(wall.face, 0);
    assert!(
        (wall.distance - space.inradius()).abs() < 1e-9,
        "{} vs {}",
        wall.distance,
        space.inradius()
    );
    assert!(wall.distance < first_beyond);
    assert!(hits.iter().all(|h| h.faces.is_empty()));
}
