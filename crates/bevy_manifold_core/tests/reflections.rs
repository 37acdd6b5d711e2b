//! Reflections (`TraceSettings::reflections`): the ray a mirror ball sends on
//! goes where the geometry says, checked against facts found here without
//! the tracer: in E3 the first hit of the reflected line among every
//! lattice copy of every ball (closed-form line-sphere hits in the cover),
//! and in each geometry the symmetry of a camera and a target at equal
//! distances from the mirror's centre, whose reflection the camera sees on
//! the mirror's bisecting radius.

use bevy_manifold_core::geometry::{Geometry, isometry};
use bevy_manifold_core::material::{Pbr, reflectance};
use bevy_manifold_core::prelude::*;
use bevy_manifold_core::trace::step::Ray;
use bevy_manifold_core::trace::{FlatScene, Projection, Stop, TracePixel, mirror_ray, trace_path, view_ray};
use glam::{DMat4, DVec3, DVec4};

const MIRROR: Pbr = Pbr {
    metallic: 1.0,
    roughness: 0.0,
};

fn ball(center: DVec4, radius: f64, color: [f32; 3], pbr: Option<Pbr>) -> Ball {
    Ball {
        center,
        radius,
        color,
        glow: 0.0,
        pbr,
    }
}

/// Each leg's pixel of the path of `ray`.
fn legs(space: &Space, flat: &FlatScene<f64>, ray: Ray<f64>, settings: &TraceSettings) -> Vec<(TracePixel, Stop)> {
    let mut out = Vec::new();
    trace_path(space, flat, ray, settings, &mut |_| {}, &mut |p, s| out.push((*p, s)));
    out
}

/// The first of `balls` (centre, radius) the line `o + t d` (unit `d`,
/// `t > t_min`) enters, with its parameter: closed-form line-sphere hits.
fn first_hit(o: DVec3, d: DVec3, balls: &[(DVec3, f64, usize, DVec3)], t_min: f64) -> Option<(f64, usize, DVec3)> {
    let mut best: Option<(f64, usize, DVec3)> = None;
    for &(c, r, id, lattice) in balls {
        let q = o - c;
        let b = q.dot(d);
        let disc = b * b - (q.dot(q) - r * r);
        if disc < 0.0 {
            continue;
        }
        let t = -b - disc.sqrt();
        if t > t_min && best.is_none_or(|(bt, _, _)| t < bt) {
            best = Some((t, id, lattice));
        }
    }
    best
}

#[test]
fn a_mirror_ball_in_the_torus_shows_what_the_reflected_line_meets_in_the_cover() {
    let space = catalog::torus(1.0);
    let mut scene = Scene::empty();
    scene
        .balls
        .push(ball(DVec4::new(0.0, 0.0, -0.1, 1.0), 0.2, [0.95; 3], Some(MIRROR)));
    scene
        .balls
        .push(ball(DVec4::new(0.3, 0.25, 0.2, 1.0), 0.1, [0.9, 0.3, 0.2], None));
    scene
        .balls
        .push(ball(DVec4::new(-0.3, -0.2, 0.3, 1.0), 0.08, [0.2, 0.8, 0.3], None));
    scene.camera.isometry = DMat4::from_translation(DVec3::new(0.1, 0.05, 0.3));
    let flat = FlatScene::<f64>::new(&space, &scene);
    let settings = TraceSettings {
        width: 96,
        height: 64,
        levels: 24,
        reflections: 1,
        ..TraceSettings::default()
    };
    // Every copy of every ball within reach, by its lattice vector.
    let mut copies = Vec::new();
    for (i, b) in scene.balls.iter().enumerate() {
        for x in -5..=5 {
            for y in -5..=5 {
                for z in -5..=5 {
                    let l = DVec3::new(f64::from(x), f64::from(y), f64::from(z));
                    copies.push((b.center.truncate() + l, b.radius, i + 1, l));
                }
            }
        }
    }
    let (mut compared, mut equal) = (0, 0);
    for j in 0..settings.height {
        for i in 0..settings.width {
            let ray = view_ray(&flat, Projection::Perspective, i, j, settings.width, settings.height);
            let (o, d) = (ray.origin.truncate(), ray.dir.truncate().normalize());
            let Some((t, 1, lattice)) = first_hit(o, d, &copies, 0.0) else {
                continue;
            };
            // Reflected off the copy at `lattice`: the normal is radial,
            // the direction mirrored about it.
            let x = o + d * t;
            let n = (x - (scene.balls[0].center.truncate() + lattice)).normalize();
            let r = d - 2.0 * d.dot(n) * n;
            let Some((s, id, cell)) = first_hit(x, r, &copies, 1e-9) else {
                continue;
            };
            // Within the reach of the levels (a unit cube: at most
            // three crossings a unit of length) and of the copies.
            if s > 3.5 {
                continue;
            }
            let got = legs(&space, &flat, ray, &settings);
            assert_eq!(got[0].0.object, 1, "pixel {i},{j}: the first leg meets the mirror");
            assert_eq!(got.len(), 2, "pixel {i},{j}: one reflection");
            compared += 1;
            let want_cell = space.cell_id(&DMat4::from_translation(cell));
            if got[1].0.object == id as u32 && got[1].0.cell == want_cell {
                equal += 1;
            }
        }
    }
    assert!(compared > 600, "{compared} pixels see something in the mirror");
    assert!(
        equal * 1000 >= compared * 995,
        "{equal} of {compared} reflected hits are the ball and copy the cover says"
    );
}

#[test]
fn the_reflection_of_a_point_lies_where_the_symmetry_of_each_geometry_puts_it() {
    // Camera and target at distance `d` from the mirror's centre, `angle`
    // apart: the reflection across the plane bisecting them swaps them
    // and fixes the mirror, so the camera sees the target at the point
    // of the mirror on the bisecting radius, and the ray reflected there
    // heads straight for the target.
    let cases = [
        (catalog::torus(1.0), 0.15, 0.4, 1.6),
        (catalog::seifert_weber(), 0.2, 0.7, 1.4),
        (catalog::poincare(), 0.08, 0.25, 1.9),
    ];
    for (space, rho, d, angle) in cases {
        let g = space.geometry();
        let (u1, u2) = (
            DVec3::new(1.0, 0.2, 0.1).normalize(),
            glam::DQuat::from_axis_angle(DVec3::new(0.1, -0.3, 1.0).normalize(), angle)
                * DVec3::new(1.0, 0.2, 0.1).normalize(),
        );
        let point = |v: DVec3| isometry::translation(g, v) * DVec4::W;
        let camera = point(u1 * d);
        let target = point(u2 * d);
        let on_mirror = point((u1 + u2).normalize() * rho);
        let mut scene = Scene::empty();
        scene.balls.push(ball(DVec4::W, rho, [0.95; 3], Some(MIRROR)));
        scene.balls.push(ball(target, 0.2 * rho, [0.9, 0.3, 0.2], None));
        let flat = FlatScene::<f64>::new(&space, &scene);
        let settings = TraceSettings {
            reflections: 1,
            ..TraceSettings::default()
        };
        let ray = Ray {
            origin: camera,
            dir: g.normalize_tangent::<f64>(camera, on_mirror),
        };
        let got = legs(&space, &flat, ray, &settings);
        assert_eq!(got.len(), 2, "{}", space.name());
        assert_eq!(
            got[0].0.object,
            1,
            "{}: the camera's ray meets the mirror",
            space.name()
        );
        assert_eq!(got[1].0.object, 2, "{}: its reflection meets the target", space.name());
        assert_eq!(
            got[1].0.cell,
            space.cell_id(&DMat4::IDENTITY),
            "{}: in the mirror's own copy",
            space.name()
        );
        // The reflected ray leaves the bisecting point towards the target.
        let normal = g.normalize_tangent::<f64>(on_mirror, -DVec4::W);
        let normal = if g == Geometry::Euclidean {
            (on_mirror - DVec4::W).normalize()
        } else {
            -normal
        };
        let view = g.normalize_tangent::<f64>(on_mirror, camera);
        let m = mirror_ray::<f64>(g, on_mirror, normal, view);
        let toward = g.normalize_tangent::<f64>(m.origin, target);
        assert!(
            (m.dir - toward).length() < 1e-3,
            "{}: reflected {} against {toward}",
            space.name(),
            m.dir
        );
        // The distance the second leg reports is the way round: to the
        // mirror, then on to the target's near surface.
        let want = g.distance::<f64>(camera, on_mirror) + g.distance::<f64>(on_mirror, target) - 0.2 * rho;
        assert!(
            (f64::from(got[1].0.distance) - want).abs() < 1e-3,
            "{}: {} against {want}",
            space.name(),
            got[1].0.distance
        );
    }
}

#[test]
fn a_mirror_shows_the_reflectance_of_what_it_reflects_and_no_bounce_costs_nothing() {
    // Off a mirror the second leg's colour adds in, weighted by the
    // reflectance; with no reflections the pixel is the mirror's own shading.
    let space = catalog::torus(1.0);
    let mut scene = Scene::empty();
    scene.balls.push(ball(DVec4::W, 0.2, [0.8, 0.6, 0.4], Some(MIRROR)));
    let mut glowing = ball(DVec4::new(0.0, 0.0, 0.4, 1.0), 0.05, [0.9, 0.3, 0.2], None);
    glowing.glow = 5.0;
    scene.balls.push(glowing);
    scene.camera.isometry = DMat4::from_translation(DVec3::new(0.0, 0.0, 0.35));
    let flat = FlatScene::<f64>::new(&space, &scene);
    let ray = Ray {
        origin: DVec4::new(0.0, 0.0, 0.34, 1.0),
        dir: DVec4::new(0.0, 0.0, -1.0, 0.0),
    };
    let none = TraceSettings::default();
    let one = TraceSettings {
        reflections: 1,
        ..none.clone()
    };
    let plain = legs(&space, &flat, ray, &none);
    let bounced = legs(&space, &flat, ray, &one);
    assert_eq!(plain.len(), 1);
    assert_eq!(bounced[0].0, plain[0].0, "the first leg is the same");
    let (p0, _) = trace_path(&space, &flat, ray, &one, &mut |_| {}, &mut |_, _| {});
    // Head on: the reflected ray comes straight back, off the mirror's
    // pole, and meets the glowing ball between the mirror and the eye.
    assert_eq!(bounced[1].0.object, 2);
    let w = reflectance([0.8, 0.6, 0.4], MIRROR, 1.0);
    for c in 0..3 {
        let want = plain[0].0.color[c] + w[c] * bounced[1].0.color[c];
        assert!(
            (p0.color[c] - want).abs() < 1e-5,
            "channel {c}: {} against {want}",
            p0.color[c]
        );
        assert!(w[c] > 0.9 * [0.8, 0.6, 0.4][c], "a smooth metal reflects its colour");
    }
}

#[test]
fn mirrors_facing_each_other_stay_finite_and_bounded() {
    // A metal and a smooth dielectric mirror ball facing each other and a
    // light on the metal's surface, at every reflection budget: every pixel
    // finite, at least its first leg's colour and at most the sum of its
    // legs' (each reflectance is below one).
    for space in [catalog::torus(1.0), catalog::seifert_weber(), catalog::poincare()] {
        let g = space.geometry();
        let r = 0.25 * space.inradius();
        let point = |v: DVec3| isometry::translation(g, v * space.inradius()) * DVec4::W;
        let mut scene = Scene::default_for(&space);
        scene.balls.clear();
        scene.balls.push(ball(point(DVec3::X * 0.4), r, [1.0; 3], Some(MIRROR)));
        let glass = Pbr {
            metallic: 0.0,
            roughness: 0.0,
        };
        scene.balls.push(ball(point(-DVec3::X * 0.4), r, [1.0; 3], Some(glass)));
        let on_surface = point(DVec3::X * 0.4);
        let on_surface = isometry::translation(g, DVec3::Y * r) * on_surface;
        scene.lights = vec![Light::point(on_surface, 1.0, [1.0; 3])];
        scene.lighting.images = 8;
        let flat = FlatScene::<f32>::new(&space, &scene);
        for reflections in [0, 1, 4, 8] {
            let settings = TraceSettings {
                width: 32,
                height: 24,
                reflections,
                ..TraceSettings::default()
            };
            let mut legs_seen = 0;
            for j in 0..settings.height {
                for i in 0..settings.width {
                    let ray = view_ray(&flat, Projection::Perspective, i, j, settings.width, settings.height);
                    let mut legs = Vec::new();
                    let (p, _) = trace_path(&space, &flat, ray, &settings, &mut |_| {}, &mut |l, _| legs.push(*l));
                    legs_seen += legs.len() - 1;
                    assert!(legs.len() <= reflections as usize + 1);
                    for c in 0..3 {
                        let sum: f32 = legs.iter().map(|l| l.color[c]).sum();
                        assert!(p.color[c].is_finite(), "{}: {:?}", space.name(), p.color);
                        assert!(
                            p.color[c] >= legs[0].color[c] - 1e-6 && p.color[c] <= sum + 1e-5,
                            "{}: {} against legs {legs:?}",
                            space.name(),
                            p.color[c]
                        );
                    }
                }
            }
            assert_eq!(
                legs_seen > 0,
                reflections > 0,
                "{}: {reflections} reflections",
                space.name()
            );
        }
    }
}
