//! Totally geodesic planes as covectors `n`: `n . p = 0` on the plane,
//! `n . p < 0` on its inner side. Flat in every chart.

use super::Geometry;
use glam::{DMat3, DVec4};

/// The pole of a plane: the vector `N` with `<N, p> = n . p` for all `p`
/// (`(a, b, c, -d)` in H3, `n` itself in S3), or the plane's normal
/// direction `(a, b, c, 0)` in E3. It is the plane's normal, up to scale.
#[must_use]
pub fn pole(g: Geometry, n: DVec4) -> DVec4 {
    match g {
        Geometry::Euclidean => n.truncate().extend(0.0),
        Geometry::Hyperbolic => DVec4::new(n.x, n.y, n.z, -n.w),
        Geometry::Spherical => n,
    }
}

/// Scales a plane so that `n . p` of a normalised point is `sinh` (H3),
/// `sin` (S3) or the value (E3) of the signed distance from the plane.
/// Returns `None` when the covector is no plane of the geometry (in H3 a
/// plane that misses the ball, or touches it at infinity).
#[must_use]
pub fn normalize(g: Geometry, n: DVec4) -> Option<DVec4> {
    let q = pole(g, n);
    let len2 = n.dot(q);
    (len2 > 0.0 && len2.is_finite()).then(|| n / len2.sqrt())
}

/// The unit normal of plane `n` at the normalised point `p`, a tangent
/// vector at `p` pointing to the outer side (`n . p > 0`).
#[must_use]
pub fn normal_at(g: Geometry, n: DVec4, p: DVec4) -> DVec4 {
    g.normalize_tangent::<f64>(p, pole(g, n))
}

/// Signed distance from the normalised point `p` to the plane: negative on
/// the inner side.
#[must_use]
pub fn signed_distance(g: Geometry, n: DVec4, p: DVec4) -> f64 {
    let Some(n) = normalize(g, n) else {
        return f64::NAN;
    };
    let s = n.dot(p);
    match g {
        Geometry::Euclidean => s,
        Geometry::Hyperbolic => s.asinh(),
        Geometry::Spherical => s.clamp(-1.0, 1.0).asin(),
    }
}

/// The plane through three points (a covector orthogonal to all three in
/// the plain dot product: the 4D cross product), normalised, oriented so
/// that `inside` is on its inner side when given. `None` when the points
/// are collinear.
#[must_use]
pub fn through_points(g: Geometry, a: DVec4, b: DVec4, c: DVec4, inside: Option<DVec4>) -> Option<DVec4> {
    let n = cross4(a, b, c);
    let n = normalize(g, n)?;
    Some(match inside {
        Some(q) if n.dot(q) > 0.0 => -n,
        _ => n,
    })
}

/// The plane through the normalised point `p` with unit normal `v` (a
/// tangent vector at `p`), its outer side towards `v`.
#[must_use]
pub fn from_point_normal(g: Geometry, p: DVec4, v: DVec4) -> DVec4 {
    match g {
        Geometry::Euclidean => v.truncate().extend(-v.truncate().dot(p.truncate() / p.w)),
        Geometry::Hyperbolic => DVec4::new(v.x, v.y, v.z, -v.w),
        Geometry::Spherical => v,
    }
}

/// The vector orthogonal (plain dot) to three 4-vectors, by cofactors: the
/// point where three planes meet, or the plane through three points.
#[must_use]
pub fn cross4(a: DVec4, b: DVec4, c: DVec4) -> DVec4 {
    let m = |i: usize, j: usize, k: usize| {
        DMat3::from_cols(
            glam::DVec3::new(a[i], b[i], c[i]),
            glam::DVec3::new(a[j], b[j], c[j]),
            glam::DVec3::new(a[k], b[k], c[k]),
        )
        .determinant()
    };
    DVec4::new(-m(1, 2, 3), m(0, 2, 3), -m(0, 1, 3), m(0, 1, 2))
}
