//! Lens spaces and RP3, whose domains have no vertices
//! (`bevy_manifold_core::space::lens`), traced and wrapped: the tracer's
//! hits against the first meeting, in the cover S3 itself, of the ray's
//! great circle with the ball's images under the group (its elements the
//! powers of the face pairing, a different algorithm from walking through
//! faces), for rays from everywhere in the domain and a ball near the rim,
//! where the lens is thinnest; placements anywhere in S3 wrapped back
//! inside by the faces.

use bevy_manifold_core::prelude::*;
use bevy_manifold_core::space::library;
use bevy_manifold_core::trace::step::Ray;
use bevy_manifold_core::trace::{FlatScene, trace_ray};
use glam::{DMat4, DVec3, DVec4};
use std::f64::consts::{FRAC_PI_2, PI, TAU};

fn build(name: &str) -> Space {
    library::by_name(name)
        .unwrap_or_else(|| panic!("{name} is in the library"))
        .dirichlet_domain()
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// The group: the powers of face 0's pairing (cyclic, of the order the
/// volume says).
fn group(space: &Space) -> Vec<DMat4> {
    let order = (2.0 * PI * PI / space.volume()).round() as usize;
    let t = space.faces()[0].pairing;
    let mut out = vec![DMat4::IDENTITY];
    for _ in 1..order {
        out.push(t * *out.last().unwrap());
    }
    assert!(
        (t * *out.last().unwrap()).abs_diff_eq(DMat4::IDENTITY, 1e-9),
        "{}: the pairing has order {order}",
        space.name()
    );
    out
}

/// The arc length along the great circle `o cos s + d sin s` (s in (0,
/// 2 pi)) to where it first enters a ball of radius `r` about any of
/// `centres`: `o.c cos s + d.c sin s = cos r`, the entering root.
fn first_meeting(o: DVec4, d: DVec4, centres: &[DVec4], r: f64) -> Option<f64> {
    centres
        .iter()
        .filter_map(|&c| {
            let (a, b) = (o.dot(c), d.dot(c));
            let amp = a.hypot(b);
            if amp <= r.cos() {
                return None;
            }
            let s = (b.atan2(a) - (r.cos() / amp).acos()).rem_euclid(TAU);
            // A start inside the ball meets it at once; those are left out.
            (s > 1e-6 && s < TAU - 1e-6).then_some(s)
        })
        .min_by(f64::total_cmp)
}

/// A point of S3 a deterministic distance and direction from the origin.
fn point(k: u32, max: f64) -> (DVec4, DVec3) {
    let h = |m: u32| (f64::from(k) * (0.618_034 + f64::from(m) * 0.414_214)) % 1.0;
    let z = 2.0 * h(1) - 1.0;
    let phi = TAU * h(2);
    let u = DVec3::new((1.0 - z * z).sqrt() * phi.cos(), (1.0 - z * z).sqrt() * phi.sin(), z);
    let s = max * h(3).cbrt();
    ((u * s.sin()).extend(s.cos()), u)
}

#[test]
fn rays_meet_the_balls_images_where_the_great_circle_does() {
    for name in ["rp3", "lens-3-1", "lens-5-1"] {
        let space = build(name);
        let elements = group(&space);
        // The slab's axis (the faces' normal in the chart), and a unit
        // direction across it: along it the lens reaches the rim.
        let axis = if space.faces().len() == 2 {
            space.faces()[0].plane.truncate().normalize()
        } else {
            DVec3::Z
        };
        let along = axis.any_orthonormal_vector();
        // A ball at the centre, and one near the rim where the lens is
        // thinnest (it straddles both faces there).
        for (centre, r) in [(DVec4::W, 0.4), ((along * 1.4f64.sin()).extend(1.4f64.cos()), 0.08)] {
            let mut scene = Scene::empty();
            scene.camera.isometry = DMat4::IDENTITY;
            scene.balls.push(Ball {
                center: centre,
                radius: r,
                color: [1.0; 3],
                glow: 0.0,
                pbr: None,
            });
            let flat = FlatScene::<f64>::new(&space, &scene);
            let images: Vec<DVec4> = elements.iter().map(|g| *g * centre).collect();
            let settings = TraceSettings {
                levels: 64,
                max_distance: 7.0,
                ..TraceSettings::default()
            };
            let (mut checked, mut hits) = (0, 0);
            for k in 0..1200 {
                let (o, _) = point(k, FRAC_PI_2 - 1e-3);
                if space.outside_face(o, 0.0).is_some() {
                    continue;
                }
                let (_, u) = point(k + 7919, 1.0);
                // Every other ray aims near an image of the ball (often
                // one across a face), the rest anywhere.
                let d = if k % 2 == 0 {
                    let c = images[(k as usize / 2) % images.len()];
                    let toward = c - o * o.dot(c);
                    if toward.length() < 1e-6 {
                        continue;
                    }
                    let t = toward / toward.length() + g_tangent(o, u) * (0.6 * r);
                    t / t.length()
                } else {
                    g_tangent(o, u)
                };
                let want = first_meeting(o, d, &images, r);
                if images.iter().any(|c| o.dot(*c) > r.cos()) {
                    continue; // starts inside a ball
                }
                let (pixel, _) = trace_ray(&space, &flat, Ray { origin: o, dir: d }, &settings, &mut |_| {});
                checked += 1;
                match want {
                    Some(s) if s < settings.max_distance => {
                        hits += 1;
                        assert_eq!(pixel.object, 1, "{name}: ray {k} should meet the ball at {s}");
                        assert!(
                            (f64::from(pixel.distance) - s).abs() < 1e-4,
                            "{name}: ray {k} meets it at {} against the cover's {s}",
                            pixel.distance
                        );
                    }
                    _ => assert_eq!(pixel.object, 0, "{name}: ray {k} meets nothing in the cover"),
                }
            }
            eprintln!(
                "{name}: ball of radius {r} at {centre:?}: {hits} of {checked} rays meet it, all where the cover says"
            );
            assert!(checked >= 150 && hits >= 30, "{name}: {hits} of {checked}");
        }
    }
}

/// The unit tangent at `o` (S3) of the chart direction `u`.
fn g_tangent(o: DVec4, u: DVec3) -> DVec4 {
    let v = u.extend(0.0);
    let t = v - o * o.dot(v);
    t / t.length()
}

#[test]
fn placements_anywhere_in_s3_wrap_into_the_lens() {
    for name in ["rp3", "lens-3-1", "lens-5-1"] {
        let space = build(name);
        for k in 0..400 {
            let (p, _) = point(k, PI - 1e-3);
            let placement = bevy_manifold_core::geometry::isometry::translation_to(space.geometry(), p);
            let (wrapped, cell) = space.wrap(placement, 64);
            assert!(
                space.outside_face(wrapped.w_axis, 1e-9).is_none(),
                "{name}: {p:?} wrapped to {:?}, outside",
                wrapped.w_axis
            );
            assert!(
                (cell * wrapped).abs_diff_eq(placement, 1e-9),
                "{name}: the cell times the wrapped placement is not the placement"
            );
        }
    }
}
