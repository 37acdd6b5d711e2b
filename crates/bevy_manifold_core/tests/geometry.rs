//! The geometry core, each property checked in all three geometries and (where
//! the shader uses the step) in both precisions.

use bevy_manifold_core::geometry::{Geometry, Real, isometry, plane};
use bevy_manifold_test_support::Rng;
use glam::{DMat4, DVec3, DVec4};

const ALL: [Geometry; 3] = [Geometry::Euclidean, Geometry::Hyperbolic, Geometry::Spherical];

fn max_abs(m: DMat4) -> f64 {
    m.to_cols_array().iter().fold(0.0f64, |a, x| a.max(x.abs()))
}

#[test]
fn translations_move_the_origin_by_their_length_and_preserve_the_form() {
    let mut rng = Rng(7);
    for g in ALL {
        for _ in 0..200 {
            let v = rng.unit() * rng.next_f64() * 1.4;
            let t = isometry::translation(g, v);
            assert!(isometry::isometry_error(g, t) < 1e-13, "{g}");
            let d = g.distance::<f64>(DVec4::W, t * DVec4::W);
            assert!((d - v.length()).abs() < 1e-13, "{g}: {d} vs {}", v.length());
            // Composition with the inverse is the identity.
            let back = isometry::inverse(g, t) * t;
            assert!(max_abs(back - DMat4::IDENTITY) < 1e-13, "{g}");
        }
    }
}

#[test]
fn distance_is_symmetric_accurate_when_tiny_and_obeys_the_triangle_inequality() {
    let mut rng = Rng(11);
    for g in ALL {
        for _ in 0..500 {
            let (a, b, c) = (rng.isometry(g, 1.2), rng.isometry(g, 1.2), rng.isometry(g, 1.2));
            let (p, q, r) = (a * DVec4::W, b * DVec4::W, c * DVec4::W);
            let (pq, qp) = (g.distance::<f64>(p, q), g.distance::<f64>(q, p));
            assert_eq!(pq, qp, "{g}");
            assert!(pq <= g.distance::<f64>(p, r) + g.distance::<f64>(r, q) + 1e-12, "{g}");
            // Isometries preserve distance.
            assert!((g.distance::<f64>(c * p, c * q) - pq).abs() < 1e-11, "{g}");
        }
        // Near points: 1e-9 apart, measured to 1e-6 relative (acos would give ~1e-8 absolute noise).
        let p = rng.isometry(g, 1.0) * DVec4::W;
        let v = g.normalize_tangent::<f64>(p, rng.unit().extend(0.3));
        let (q, _) = g.exp::<f64>(p, v, 1e-9);
        let d = g.distance::<f64>(p, q);
        assert!((d / 1e-9 - 1.0).abs() < 1e-6, "{g}: {d}");
    }
}

fn exp_log_round_trip<R: Real>(tol: f64) {
    let mut rng = Rng(3);
    for g in ALL {
        for _ in 0..300 {
            let p = g.normalize_point::<R>(R::v4_of(rng.isometry(g, 1.0) * DVec4::W));
            let v = g.normalize_tangent::<R>(p, R::v4_of(rng.unit().extend(rng.next_f64() - 0.5)));
            let s = rng.next_f64() * 1.5;
            let (q, w) = g.exp::<R>(p, v, R::of(s));
            assert!(g.point_error::<R>(q).f64() < tol, "{g}");
            assert!(g.tangent_error::<R>(q, w).f64() < tol, "{g}");
            let d = g.distance::<R>(p, q).f64();
            assert!((d - s).abs() < tol * 4.0, "{g}: exp by {s} lands at distance {d}");
            // The chart parameter along the ray is the same point.
            let t = g.distance_to_chart::<R>(R::of(s));
            let q2 = g.normalize_point::<R>(p + v * t);
            assert!(R::v4_f64(q2 - q).length() < tol * 8.0, "{g}");
            assert!((g.chart_to_distance::<R>(t).f64() - s).abs() < tol * 4.0, "{g}");
        }
    }
}

#[test]
fn exp_and_chart_parameter_round_trip_f64() {
    exp_log_round_trip::<f64>(1e-12);
}

#[test]
fn exp_and_chart_parameter_round_trip_f32() {
    exp_log_round_trip::<f32>(2e-5);
}

#[test]
fn reflections_are_involutions_fixing_their_plane() {
    let mut rng = Rng(5);
    for g in ALL {
        for _ in 0..100 {
            let m = rng.isometry(g, 0.8);
            let (a, b, c) = (
                m * rng.isometry(g, 0.3) * DVec4::W,
                m * rng.isometry(g, 0.3) * DVec4::W,
                m * DVec4::W,
            );
            let Some(n) = plane::through_points(g, a, b, c, None) else {
                continue;
            };
            for p in [a, b, c] {
                assert!(n.dot(p).abs() < 1e-12, "{g}: point not on its plane");
            }
            let r = isometry::reflection(g, n);
            assert!(isometry::isometry_error(g, r) < 1e-11, "{g}");
            assert!(max_abs(r * r - DMat4::IDENTITY) < 1e-11, "{g}");
            assert!(isometry::is_orientation_reversing(r));
            for p in [a, b, c] {
                assert!(
                    (r * p - p).length() < 1e-11,
                    "{g}: reflection moved a point of its plane"
                );
            }
            // The normal at a point of the plane is a unit tangent, and the
            // reflection reverses it.
            let nrm = plane::normal_at(g, n, a);
            assert!(g.tangent_error::<f64>(a, nrm) < 1e-12, "{g}");
            assert!((r * nrm + nrm).length() < 1e-10, "{g}");
        }
    }
}

#[test]
fn plane_orientation_and_signed_distance() {
    for g in ALL {
        let q = isometry::translation(g, DVec3::X * 0.4) * DVec4::W;
        let n = plane::from_point_normal(g, q, g.normalize_tangent::<f64>(q, DVec4::X));
        let p = isometry::translation(g, DVec3::X * 0.1) * DVec4::W;
        let d = plane::signed_distance(g, n, p);
        assert!((d + 0.3).abs() < 1e-12, "{g}: {d}");
        let inside = plane::through_points(
            g,
            isometry::translation(g, DVec3::new(0.4, 0.1, 0.0)) * DVec4::W,
            isometry::translation(g, DVec3::new(0.4, 0.0, 0.2)) * DVec4::W,
            isometry::translation(g, DVec3::new(0.4, -0.2, -0.1)) * DVec4::W,
            Some(DVec4::W),
        )
        .expect("three points in general position span a plane");
        assert!(inside.dot(DVec4::W) < 0.0, "{g}: oriented with the origin inside");
    }
}

#[test]
fn orthonormalize_repairs_a_drifted_isometry() {
    let mut rng = Rng(9);
    for g in ALL {
        let m = rng.isometry(g, 1.0);
        let mut drifted = m;
        // Rounding-like noise on every entry.
        for c in 0..4 {
            for r in 0..4 {
                drifted.col_mut(c)[r] += (rng.next_f64() - 0.5) * 1e-6;
            }
        }
        if g == Geometry::Euclidean {
            *drifted.col_mut(3) = drifted.col(3) / drifted.col(3).w;
            for c in 0..3 {
                drifted.col_mut(c).w = 0.0;
            }
        }
        assert!(
            isometry::isometry_error(g, drifted) > 1e-8,
            "{g}: noise too small to test"
        );
        let fixed = isometry::orthonormalize(g, drifted);
        assert!(isometry::isometry_error(g, fixed) < 1e-14, "{g}");
        assert!(max_abs(fixed - m) < 1e-5, "{g}: repair moved the isometry too far");
        assert_eq!(
            fixed.determinant() > 0.0,
            m.determinant() > 0.0,
            "{g}: orientation kept"
        );
    }
}

#[test]
fn frames_and_tangent_bases() {
    let mut rng = Rng(13);
    for g in ALL {
        for _ in 0..50 {
            let p = rng.isometry(g, 1.2) * DVec4::W;
            let [e1, e2, e3] = isometry::tangent_basis(g, p);
            for (i, e) in [e1, e2, e3].iter().enumerate() {
                assert!(g.tangent_error::<f64>(p, *e) < 1e-12, "{g}: e{i}");
            }
            assert!(g.form::<f64>(e1, e2).abs() < 1e-12 && g.form::<f64>(e2, e3).abs() < 1e-12);
            let m = isometry::from_frame(p, e1, e2, e3);
            assert!(isometry::isometry_error(g, m) < 1e-12, "{g}");
            assert!((m * DVec4::W - p).length() < 1e-14, "{g}");
        }
    }
}

#[test]
fn screw_motion_trace_matches_its_length_and_angle() {
    // In H3 a screw by distance l and angle a has trace 2 cosh l + 2 cos a;
    // in S3, 2 cos l + 2 cos a.
    for (g, f) in [
        (Geometry::Hyperbolic, f64::cosh as fn(f64) -> f64),
        (Geometry::Spherical, f64::cos),
    ] {
        let m = isometry::screw(g, DVec3::new(1.0, 2.0, 3.0), 0.7, 1.1);
        let trace = m.x_axis.x + m.y_axis.y + m.z_axis.z + m.w_axis.w;
        assert!((trace - 2.0 * f(0.7) - 2.0 * 1.1f64.cos()).abs() < 1e-13, "{g}");
    }
}

#[test]
fn light_falloff_areas() {
    let d = 0.9f64;
    let pi4 = 4.0 * core::f64::consts::PI;
    assert!((Geometry::Euclidean.sphere_area::<f64>(d) - pi4 * d * d).abs() < 1e-14);
    assert!((Geometry::Hyperbolic.sphere_area::<f64>(d) - pi4 * d.sinh().powi(2)).abs() < 1e-13);
    assert!((Geometry::Spherical.sphere_area::<f64>(d) - pi4 * d.sin().powi(2)).abs() < 1e-13);
}
