//! Property-based tests of the geometry core (proptest), in each geometry
//! and both precisions: isometries preserve the form, distance is a metric,
//! exp and log invert each other.

use bevy_manifold::geometry::{Geometry, Real, isometry};
use glam::{DMat4, DVec3, DVec4};
use proptest::prelude::*;

const GEOMETRIES: [Geometry; 3] = [Geometry::Euclidean, Geometry::Hyperbolic, Geometry::Spherical];

fn geometry() -> impl Strategy<Value = Geometry> {
    (0usize..3).prop_map(|i| GEOMETRIES[i])
}

fn unit() -> impl Strategy<Value = DVec3> {
    (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0)
        .prop_filter("not too short", |(x, y, z)| DVec3::new(*x, *y, *z).length() > 0.1)
        .prop_map(|(x, y, z)| DVec3::new(x, y, z).normalize())
}

/// An isometry: a rotation then a translation by up to `reach`.
fn motion(g: Geometry, reach: f64) -> impl Strategy<Value = DMat4> {
    (unit(), 0.0..reach, unit(), 0.0..std::f64::consts::TAU)
        .prop_map(move |(dir, d, axis, a)| isometry::translation(g, dir * d) * isometry::rotation(axis, a))
}

/// How far a point may be placed: H3 isometries of translation length `d`
/// have entries of size `e^d`, so f64 keeps digits to about 8.
fn reach(g: Geometry) -> f64 {
    match g {
        Geometry::Spherical => 3.0,
        _ => 4.0,
    }
}

fn point(g: Geometry) -> impl Strategy<Value = DVec4> {
    motion(g, reach(g)).prop_map(|m| m * DVec4::W)
}

/// A point and a unit tangent at it.
fn point_and_tangent(g: Geometry) -> impl Strategy<Value = (DVec4, DVec4)> {
    (motion(g, reach(g)), unit()).prop_map(move |(m, v)| {
        let p = m * DVec4::W;
        (p, g.normalize_tangent::<f64>(p, m * v.extend(0.0)))
    })
}

/// The scale of a value's rounding error: f64 epsilon times the size of
/// what went into it.
fn tol(scale: f64) -> f64 {
    1e-12 * scale.max(1.0)
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 400,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn isometries_preserve_the_form(
        (g, m, u, v) in geometry().prop_flat_map(|g| (Just(g), motion(g, reach(g)), point_and_tangent(g), point_and_tangent(g)))
    ) {
        let (p, a) = u;
        let (q, b) = v;
        // Points and tangent vectors alike (in E3 the form is on tangents).
        let pairs: Vec<(DVec4, DVec4)> = if g == Geometry::Euclidean {
            vec![(a, b), (a, a), (p - q, a)]
        } else {
            vec![(p, q), (a, b), (p, a), (p, p)]
        };
        for (x, y) in pairs {
            let before = g.form::<f64>(x, y);
            let after = g.form::<f64>(m * x, m * y);
            let scale = x.length() * y.length() * m.to_cols_array().iter().fold(1.0f64, |s, e| s.max(e.abs())).powi(2);
            prop_assert!((before - after).abs() <= tol(scale), "{g}: <x,y> {before} became {after}");
        }
        prop_assert!(isometry::isometry_error(g, m) <= tol(m.w_axis.length().powi(2)));
    }

    #[test]
    fn distance_is_a_metric((g, p, q, r) in geometry().prop_flat_map(|g| (Just(g), point(g), point(g), point(g)))) {
        let d = |a, b| g.distance::<f64>(a, b);
        prop_assert!(d(p, p).abs() < 1e-12);
        prop_assert!((d(p, q) - d(q, p)).abs() <= tol(d(p, q)), "{g}: not symmetric");
        prop_assert!(d(p, q) >= 0.0);
        prop_assert!(d(p, r) <= d(p, q) + d(q, r) + tol(d(p, r)), "{g}: triangle inequality");
        if g == Geometry::Spherical {
            prop_assert!(d(p, q) <= std::f64::consts::PI + 1e-12);
        }
        // Isometries keep it.
        let m = isometry::translation(g, DVec3::new(0.3, -0.1, 0.2));
        prop_assert!((d(m * p, m * q) - d(p, q)).abs() <= 1e-9 * d(p, q).max(1.0));
    }

    #[test]
    fn exp_and_log_invert_each_other(
        (g, (p, v), s) in geometry().prop_flat_map(|g| (Just(g), point_and_tangent(g), 1e-3..3.0f64))
    ) {
        let (q, w) = g.exp::<f64>(p, v, s);
        prop_assert!(g.point_error::<f64>(q) <= tol(q.length().powi(2)), "{g}: exp leaves the model");
        prop_assert!(g.tangent_error::<f64>(q, w) <= 1e-9 * q.length().powi(2), "{g}: exp's tangent");
        let (v2, s2) = g.log::<f64>(p, q).expect("distinct points have a direction");
        prop_assert!((s2 - s).abs() <= 1e-9 * s.max(1.0) * p.length(), "{g}: log distance {s2} for {s}");
        prop_assert!((v2 - v).length() <= 1e-7 * p.length().powi(2) / s.min(1.0), "{g}: log direction");
        // And the other way round: log then exp.
        let (q2, _) = g.exp::<f64>(p, v2, s2);
        prop_assert!((q2 - q).length() <= 1e-8 * q.length().powi(2), "{g}: exp(log q) != q");
    }

    #[test]
    fn f32_follows_f64_within_its_precision(
        (g, (p, v), s) in geometry().prop_flat_map(|g| (Just(g), point_and_tangent(g), 1e-2..2.0f64))
    ) {
        // The GPU's precision: the same formulas, errors of order 1e-7
        // times the size of the coordinates.
        let (q, _) = g.exp::<f64>(p, v, s);
        let (p32, q32) = (f32::v4_of(p), f32::v4_of(q));
        let d32 = f64::from(g.distance::<f32>(p32, q32));
        let scale = p.length() * q.length();
        prop_assert!((d32 - s).abs() <= 2e-6 * scale / s.min(1.0), "{g}: f32 distance {d32} for {s}");
        let (v32, _) = g.log::<f32>(p32, q32).expect("direction");
        prop_assert!((f32::v4_f64(v32) - v).length() <= 1e-5 * scale / s.min(1.0));
    }
}

#[test]
fn log_has_no_direction_for_a_point_to_itself() {
    for g in GEOMETRIES {
        let p = isometry::translation(g, DVec3::new(0.2, 0.1, -0.3)) * DVec4::W;
        assert!(g.log::<f64>(p, p).is_none(), "{g}");
    }
}
