//! Property tests of the geometry core, in each geometry and both
//! precisions: isometries preserve the form, distance is a metric, exp and
//! log invert each other. Each property is checked on 400 random cases
//! from the shared seeded RNG (the same cases every run), cycling through
//! the three geometries; a failure names the case.

use bevy_manifold_core::geometry::{Geometry, Real, isometry};
use bevy_manifold_test_support::Rng;
use glam::{DMat4, DVec3, DVec4};

const GEOMETRIES: [Geometry; 3] = [Geometry::Euclidean, Geometry::Hyperbolic, Geometry::Spherical];

/// Cases per property.
const CASES: usize = 400;

/// Runs `check` on `CASES` cases drawn from a generator seeded with `seed`.
fn for_each_case(seed: u64, mut check: impl FnMut(usize, Geometry, &mut Rng)) {
    let mut rng = Rng(seed);
    for case in 0..CASES {
        check(case, GEOMETRIES[case % 3], &mut rng);
    }
}

/// A value uniform in `[lo, hi)`.
fn uniform(rng: &mut Rng, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * rng.next_f64()
}

/// An isometry: a rotation then a translation by up to `reach`.
fn motion(rng: &mut Rng, g: Geometry, reach: f64) -> DMat4 {
    let (dir, d) = (rng.unit(), uniform(rng, 0.0, reach));
    let (axis, a) = (rng.unit(), uniform(rng, 0.0, std::f64::consts::TAU));
    isometry::translation(g, dir * d) * isometry::rotation(axis, a)
}

/// How far a point may be placed: H3 isometries of translation length `d`
/// have entries of size `e^d`, so f64 keeps digits to about 8.
fn reach(g: Geometry) -> f64 {
    match g {
        Geometry::Spherical => 3.0,
        _ => 4.0,
    }
}

fn point(rng: &mut Rng, g: Geometry) -> DVec4 {
    motion(rng, g, reach(g)) * DVec4::W
}

/// A point and a unit tangent at it.
fn point_and_tangent(rng: &mut Rng, g: Geometry) -> (DVec4, DVec4) {
    let m = motion(rng, g, reach(g));
    let v = rng.unit();
    let p = m * DVec4::W;
    (p, g.normalize_tangent::<f64>(p, m * v.extend(0.0)))
}

/// The scale of a value's rounding error: f64 epsilon times the size of
/// what went into it.
fn tol(scale: f64) -> f64 {
    1e-12 * scale.max(1.0)
}

#[test]
fn isometries_preserve_the_form() {
    for_each_case(1, |case, g, rng| {
        let m = motion(rng, g, reach(g));
        let (p, a) = point_and_tangent(rng, g);
        let (q, b) = point_and_tangent(rng, g);
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
            assert!(
                (before - after).abs() <= tol(scale),
                "case {case}, {g}: <x,y> {before} became {after}"
            );
        }
        assert!(
            isometry::isometry_error(g, m) <= tol(m.w_axis.length().powi(2)),
            "case {case}, {g}"
        );
    });
}

#[test]
fn distance_is_a_metric() {
    for_each_case(2, |case, g, rng| {
        let (p, q, r) = (point(rng, g), point(rng, g), point(rng, g));
        let d = |a, b| g.distance::<f64>(a, b);
        assert!(d(p, p).abs() < 1e-12, "case {case}, {g}");
        assert!(
            (d(p, q) - d(q, p)).abs() <= tol(d(p, q)),
            "case {case}, {g}: not symmetric"
        );
        assert!(d(p, q) >= 0.0, "case {case}, {g}");
        assert!(
            d(p, r) <= d(p, q) + d(q, r) + tol(d(p, r)),
            "case {case}, {g}: triangle inequality"
        );
        if g == Geometry::Spherical {
            assert!(d(p, q) <= std::f64::consts::PI + 1e-12, "case {case}");
        }
        // Isometries keep it.
        let m = isometry::translation(g, DVec3::new(0.3, -0.1, 0.2));
        assert!(
            (d(m * p, m * q) - d(p, q)).abs() <= 1e-9 * d(p, q).max(1.0),
            "case {case}, {g}"
        );
    });
}

#[test]
fn exp_and_log_invert_each_other() {
    for_each_case(3, |case, g, rng| {
        let (p, v) = point_and_tangent(rng, g);
        let s = uniform(rng, 1e-3, 3.0);
        let (q, w) = g.exp::<f64>(p, v, s);
        assert!(
            g.point_error::<f64>(q) <= tol(q.length().powi(2)),
            "case {case}, {g}: exp leaves the model"
        );
        assert!(
            g.tangent_error::<f64>(q, w) <= 1e-9 * q.length().powi(2),
            "case {case}, {g}: exp's tangent"
        );
        let (v2, s2) = g.log::<f64>(p, q).expect("distinct points have a direction");
        // f64 rounding of the same formulas: k eps |p|^2, the direction's
        // over the distance.
        let unit = f64::EPSILON * p.length().max(q.length()).powi(2);
        assert!(
            (s2 - s).abs() <= 16.0 * unit,
            "case {case}, {g}: log distance {s2} for {s}"
        );
        assert!((v2 - v).length() <= 64.0 * unit / s, "case {case}, {g}: log direction");
        // And the other way round: log then exp.
        let (q2, _) = g.exp::<f64>(p, v2, s2);
        assert!(
            (q2 - q).length() <= 1e-8 * q.length().powi(2),
            "case {case}, {g}: exp(log q) != q"
        );
    });
}

/// f32 against f64 for one pair: the distance within `8 eps_32 |p|^2`
/// (the chord formula's rounding: the points' own f32 rounding is
/// `eps |p|`, the difference's form cancels to `eps |p|^2`, independent
/// of the distance), the log's direction within that over `s`.
fn f32_case(case: usize, g: Geometry, p: DVec4, v: DVec4, s: f64) -> (f64, f64) {
    let (q, _) = g.exp::<f64>(p, v, s);
    let (p32, q32) = (f32::v4_of(p), f32::v4_of(q));
    let d32 = f64::from(g.distance::<f32>(p32, q32));
    let size = p.length().max(q.length()).powi(2);
    let unit = f64::from(f32::EPSILON) * size;
    let distance_error = (d32 - s).abs() / unit;
    assert!(
        distance_error <= 16.0,
        "case {case}, {g}: f32 distance {d32} for {s} ({distance_error:.1} eps |p|^2)"
    );
    let (v32, _) = g.log::<f32>(p32, q32).expect("direction");
    let direction_error = (f32::v4_f64(v32) - v).length() * s / unit;
    assert!(
        direction_error <= 64.0,
        "case {case}, {g}: f32 direction off by {direction_error:.1} eps |p|^2 / s"
    );
    (distance_error, direction_error)
}

#[test]
fn f32_follows_f64_within_its_precision() {
    // Far points, distances of order one; then points near the origin at
    // short distances: the two regimes one scale must serve.
    let mut worst = [0.0f64; 4];
    for_each_case(4, |case, g, rng| {
        let (p, v) = point_and_tangent(rng, g);
        let (d, a) = f32_case(case, g, p, v, uniform(rng, 0.5, 2.0));
        worst[0] = worst[0].max(d);
        worst[1] = worst[1].max(a);
    });
    for_each_case(5, |case, g, rng| {
        let m = motion(rng, g, 0.5);
        let p = m * DVec4::W;
        let v = g.normalize_tangent::<f64>(p, m * rng.unit().extend(0.0));
        let (d, a) = f32_case(case, g, p, v, uniform(rng, 1e-3, 1e-2));
        worst[2] = worst[2].max(d);
        worst[3] = worst[3].max(a);
    });
    eprintln!(
        "f32 against f64, in eps |p|^2: far distance {:.2}, far direction {:.2}, near distance {:.2}, near direction {:.2}",
        worst[0], worst[1], worst[2], worst[3]
    );
}

#[test]
fn log_has_no_direction_for_a_point_to_itself() {
    for g in GEOMETRIES {
        let p = isometry::translation(g, DVec3::new(0.2, 0.1, -0.3)) * DVec4::W;
        assert!(g.log::<f64>(p, p).is_none(), "{g}");
    }
}
