//! Isometries as 4x4 matrices acting on column vectors, in f64.
//!
//! H3 isometries preserve the form `diag(1,1,1,-1)` (the group O(3,1)), S3
//! ones preserve the Euclidean dot of R^4 (O(4)), E3 ones are affine maps
//! with an orthogonal linear part. All are built here; the tracer only
//! multiplies them.

use super::Geometry;
use glam::{DMat3, DMat4, DVec3, DVec4};

/// The isometry carrying the origin to the normalised point `p`, and the
/// standard frame at the origin to the frame `(e1, e2, e3)` of unit,
/// mutually orthogonal tangent vectors at `p`: its columns are
/// `e1, e2, e3, p`.
#[must_use]
pub fn from_frame(p: DVec4, e1: DVec4, e2: DVec4, e3: DVec4) -> DMat4 {
    DMat4::from_cols(e1, e2, e3, p)
}

/// A rotation about the chart origin (the same matrix in all geometries).
#[must_use]
pub fn rotation(axis: DVec3, angle: f64) -> DMat4 {
    DMat4::from_mat3(DMat3::from_axis_angle(axis.normalize(), angle))
}

/// The translation moving the origin by the tangent vector `v` (a 3-vector
/// at the origin): along the geodesic in direction `v` by distance `|v|`,
/// fixing every direction perpendicular to it. In H3 this is a boost, in S3
/// a rotation of R^4 in the plane of `v` and `w`.
#[must_use]
pub fn translation(g: Geometry, v: DVec3) -> DMat4 {
    let s = v.length();
    if s == 0.0 {
        return DMat4::IDENTITY;
    }
    let u = v / s;
    let u4 = u.extend(0.0);
    let w4 = DVec4::W;
    // M = I + (c-1)(u u^T + w w^T) + sh (u w^T) + k sh (w u^T), where k
    // makes the matrix preserve the form (k = +1 in H3, -1 in S3).
    let (c, sh, k) = match g {
        Geometry::Euclidean => return DMat4::from_cols(DVec4::X, DVec4::Y, DVec4::Z, v.extend(1.0)),
        Geometry::Hyperbolic => (s.cosh(), s.sinh(), 1.0),
        Geometry::Spherical => (s.cos(), s.sin(), -1.0),
    };
    let outer = |a: DVec4, b: DVec4| DMat4::from_cols(a * b.x, a * b.y, a * b.z, a * b.w);
    DMat4::IDENTITY + (outer(u4, u4) + outer(w4, w4)) * (c - 1.0) + outer(u4, w4) * sh + outer(w4, u4) * (k * sh)
}

/// A screw motion along the axis through the origin in direction `axis`:
/// translation by `distance` composed with a rotation by `angle` about the
/// same axis (they commute). Face pairings of the dodecahedral spaces are of
/// this kind.
#[must_use]
pub fn screw(g: Geometry, axis: DVec3, distance: f64, angle: f64) -> DMat4 {
    rotation(axis, angle) * translation(g, axis.normalize() * distance)
}

/// The translation along the geodesic from the origin to the normalised
/// point `p` (the "parallel" placement of `p`: no extra rotation).
#[must_use]
pub fn translation_to(g: Geometry, p: DVec4) -> DMat4 {
    let v = g.project_tangent::<f64>(DVec4::W, p);
    let dir = v.truncate();
    let len = dir.length();
    if len == 0.0 {
        return DMat4::IDENTITY;
    }
    let dist = g.distance::<f64>(DVec4::W, p);
    translation(g, dir / len * dist)
}

/// The reflection in the plane `n` (a covector, `n . p = 0` on the plane):
/// `p - 2 (n . p) N / (n . N)` with `N` the plane's pole.
#[must_use]
pub fn reflection(g: Geometry, n: DVec4) -> DMat4 {
    let pole = super::plane::pole(g, n);
    let denom = n.dot(pole);
    // R = I - 2 N n^T / (n . N)
    let m = DMat4::from_cols(pole * n.x, pole * n.y, pole * n.z, pole * n.w);
    DMat4::IDENTITY - m * (2.0 / denom)
}

/// The inverse of an isometry, exact for an exact isometry and cheap:
/// `J M^T J` in H3 and S3, the affine inverse in E3.
#[must_use]
pub fn inverse(g: Geometry, m: DMat4) -> DMat4 {
    match g {
        Geometry::Spherical => m.transpose(),
        Geometry::Hyperbolic => {
            let j = DMat4::from_diagonal(DVec4::new(1.0, 1.0, 1.0, -1.0));
            j * m.transpose() * j
        }
        Geometry::Euclidean => {
            let r = DMat3::from_mat4(m).transpose();
            let t = -(r * m.w_axis.truncate());
            DMat4::from_cols(
                r.x_axis.extend(0.0),
                r.y_axis.extend(0.0),
                r.z_axis.extend(0.0),
                t.extend(1.0),
            )
        }
    }
}

/// An orthonormal tangent frame at the normalised point `p`: the images of
/// the origin's axes under [`translation_to`], so the frame at the origin is
/// the standard one.
#[must_use]
pub fn tangent_basis(g: Geometry, p: DVec4) -> [DVec4; 3] {
    let t = translation_to(g, p);
    [t.x_axis, t.y_axis, t.z_axis]
}

/// Re-orthonormalises an isometry with respect to the form (Gram-Schmidt),
/// so that rounding error from long products never builds up. The image of
/// the origin (last column) is normalised first, then the frame columns are
/// made tangent there and orthonormal in order; orientation is kept.
#[must_use]
pub fn orthonormalize(g: Geometry, m: DMat4) -> DMat4 {
    let p = g.normalize_point::<f64>(m.w_axis);
    let mut cols = [m.x_axis, m.y_axis, m.z_axis];
    for i in 0..3 {
        let mut v = g.project_tangent::<f64>(p, cols[i]);
        for prev in &cols[..i] {
            v -= *prev * g.form::<f64>(v, *prev);
        }
        cols[i] = v / g.form::<f64>(v, v).sqrt();
    }
    DMat4::from_cols(cols[0], cols[1], cols[2], p)
}

/// How far `m` is from an isometry of `g`: the largest entry of
/// `M^T J M - J` (H3, S3), or of the linear part's `R^T R - I` and the
/// bottom row's departure from `(0,0,0,1)` (E3).
#[must_use]
pub fn isometry_error(g: Geometry, m: DMat4) -> f64 {
    let max_abs = |a: DMat4| a.to_cols_array().iter().fold(0.0f64, |acc, x| acc.max(x.abs()));
    match g {
        Geometry::Euclidean => {
            let r = DMat3::from_mat4(m);
            let e = r.transpose() * r - DMat3::IDENTITY;
            let lin = e.to_cols_array().iter().fold(0.0f64, |acc, x| acc.max(x.abs()));
            let row = m.row(3) - DVec4::W;
            lin.max(row.abs().max_element())
        }
        _ => {
            let j = DMat4::from_diagonal(DVec4::new(1.0, 1.0, 1.0, g.curvature()));
            max_abs(m.transpose() * j * m - j)
        }
    }
}

/// True when `m` reverses orientation (a reflection, or a glide reflection).
#[must_use]
pub fn is_orientation_reversing(m: DMat4) -> bool {
    m.determinant() < 0.0
}

/// The isometry exponential: the motion after unit time at constant linear
/// velocity `v` and angular velocity `w` (both in the frame at the origin),
/// `exp(X)` with `X` the Lie algebra element `[[W, v], [-k v^T, 0]]`
/// (`W u = w x u`, `k` the curvature). Exact up to rounding for any speed:
/// scaling and squaring of a Taylor series, then re-orthonormalised.
/// Entities move by `M <- M * exp_twist(v dt, w dt)`, never by Euler steps
/// in the chart.
#[must_use]
pub fn exp_twist(g: Geometry, v: DVec3, w: DVec3) -> DMat4 {
    let k = g.curvature();
    let x = DMat4::from_cols(
        DVec4::new(0.0, w.z, -w.y, -k * v.x),
        DVec4::new(-w.z, 0.0, w.x, -k * v.y),
        DVec4::new(w.y, -w.x, 0.0, -k * v.z),
        v.extend(0.0),
    );
    let norm = x.to_cols_array().iter().fold(0.0f64, |a, e| a + e.abs());
    if !norm.is_finite() {
        return DMat4::IDENTITY;
    }
    // Scale so the series converges fast, then square back up.
    let squarings = (norm / 0.25).log2().ceil().max(0.0) as i32;
    let y = x * 0.5f64.powi(squarings);
    let mut term = DMat4::IDENTITY;
    let mut sum = DMat4::IDENTITY;
    for n in 1..=18 {
        term = term * y * (1.0 / f64::from(n));
        sum += term;
    }
    for _ in 0..squarings {
        sum = sum * sum;
    }
    orthonormalize(g, sum)
}

/// The inverse of [`exp_twist`]: the linear and angular velocity `(v, w)`
/// (in the frame at the origin) whose motion after unit time is `m`, the
/// screw motion of `m`: `exp_twist(g, v, w) = m`. Tours interpolate poses
/// along `a exp(t log(a^-1 b))`, exact in all three geometries.
///
/// Computed as the matrix logarithm by inverse scaling and squaring
/// (Denman-Beavers square roots until `m` is near the identity, then the
/// series of `log(I + X)`), projected onto the Lie algebra of the form and
/// checked by exponentiating back. `None` when `m` has no unique real
/// logarithm, a half turn (rotation by pi: both senses are shortest) or
/// worse, or is not finite.
///
/// ```
/// use bevy_manifold_core::geometry::{Geometry, isometry};
/// use glam::DVec3;
/// let h = Geometry::Hyperbolic;
/// let m = isometry::screw(h, DVec3::Z, 1.5, 0.6);
/// let (v, w) = isometry::log_twist(h, m).unwrap();
/// assert!((v - DVec3::Z * 1.5).length() < 1e-12 && (w - DVec3::Z * 0.6).length() < 1e-12);
/// ```
#[must_use]
pub fn log_twist(g: Geometry, m: DMat4) -> Option<(DVec3, DVec3)> {
    if !m.is_finite() {
        return None;
    }
    let max_abs = |a: DMat4| a.to_cols_array().iter().fold(0.0f64, |acc, x| acc.max(x.abs()));
    // Square roots until m is close to the identity (each halves the
    // logarithm); Denman-Beavers converges quadratically.
    let mut a = m;
    let mut roots = 0;
    while max_abs(a - DMat4::IDENTITY) > 0.2 {
        if roots == 60 {
            return None;
        }
        let (mut y, mut z) = (a, DMat4::IDENTITY);
        for _ in 0..64 {
            let (yi, zi) = (y.inverse(), z.inverse());
            let (y1, z1) = ((y + zi) * 0.5, (z + yi) * 0.5);
            let step = max_abs(y1 - y);
            (y, z) = (y1, z1);
            if step <= 1e-15 * max_abs(y) {
                break;
            }
        }
        if !y.is_finite() {
            return None;
        }
        a = y;
        roots += 1;
    }
    // log(I + X) = X - X^2/2 + X^3/3 - ...; |X| <= 0.2 * 4 in norm, so
    // 60 terms leave less than rounding.
    let x = a - DMat4::IDENTITY;
    let mut power = x;
    let mut log = DMat4::ZERO;
    for n in 1..=60 {
        let sign = if n % 2 == 1 { 1.0 } else { -1.0 };
        log += power * (sign / f64::from(n));
        power *= x;
    }
    let log = log * 2f64.powi(roots);
    // The Lie algebra of the form: W antisymmetric, the translation in the
    // last column (and, mirrored by -k, in the last row).
    let c = |col: usize, row: usize| log.col(col)[row];
    let w = DVec3::new(c(1, 2) - c(2, 1), c(2, 0) - c(0, 2), c(0, 1) - c(1, 0)) * 0.5;
    let k = g.curvature();
    let col = log.w_axis.truncate();
    let v = if k == 0.0 {
        col
    } else {
        (col - DVec3::new(c(0, 3), c(1, 3), c(2, 3)) / k) * 0.5
    };
    // A half turn (or more) about some axis: the other sense is as short,
    // no screw is the one. The largest rotation angle of the motion: |w|
    // in E3; in H3 and S3 from the invariants of the twist (S3: two
    // angles of SO(4), `a^2 + b^2 = |v|^2 + |w|^2`, `a b = v . w`; H3: a
    // boost by d and a turn by a, `d^2 - a^2 = |v|^2 - |w|^2`, `d a = v . w`).
    let (s, p) = (v.length_squared(), v.dot(w));
    let angle_sq = match g {
        Geometry::Euclidean => w.length_squared(),
        Geometry::Spherical => {
            let t = s + w.length_squared();
            (t + (t * t - 4.0 * p * p).max(0.0).sqrt()) * 0.5
        }
        Geometry::Hyperbolic => {
            let t = s - w.length_squared();
            (-t + (t * t + 4.0 * p * p).sqrt()) * 0.5
        }
    };
    if angle_sq.sqrt() >= core::f64::consts::PI - 1e-7 {
        return None;
    }
    // A matrix without a real logarithm (a reflection) comes out as
    // something else: check.
    let back = exp_twist(g, v, w);
    (v.is_finite() && w.is_finite() && max_abs(back - m) <= 1e-9 * max_abs(m).max(1.0)).then_some((v, w))
}
