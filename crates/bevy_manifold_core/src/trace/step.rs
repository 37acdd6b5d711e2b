//! The steps of Algorithm 1 on one ray, generic over precision so the f64
//! reference and the f32 mirror of the GPU run the same arithmetic in the
//! same order. Their WGSL twins have the same names, in the same order
//! (`bevy_manifold_gpu`'s `shaders/step.wgsl`).
//!
//! A ray is a normalised point `o` and a unit tangent `d` there; its points
//! are `o + t d` in the chart (`t` the chart parameter, monotone in the
//! distance, see [`Geometry::chart_to_distance`]).

use crate::geometry::{Geometry, Real};

/// A ray: origin point and unit tangent direction, both normalised.
/// WGSL twin: `Ray` in `shaders/step.wgsl`.
#[derive(Clone, Copy, Debug)]
pub struct Ray<R: Real> {
    /// Normalised origin.
    pub origin: R::V4,
    /// Unit tangent at the origin.
    pub dir: R::V4,
}

/// Where a ray crosses a face: the nearest face the ray leaves through
/// (`n . d > 0`), skipping the face it just entered, with the chart
/// parameter `t = -(n . o) / (n . d)` of the crossing. Crossings behind the
/// origin (a point already a hair outside after rounding) count as `t = 0`,
/// so the ray leaves at once instead of slipping out of the domain.
/// WGSL twin: `exit_face` in `shaders/step.wgsl`.
#[inline]
#[must_use]
pub fn exit_face<R: Real>(planes: &[R::V4], ray: &Ray<R>, skip: usize) -> Option<(usize, R)> {
    let mut best: Option<(usize, R)> = None;
    for (i, n) in planes.iter().enumerate() {
        if i == skip {
            continue;
        }
        let nd = R::dot4(*n, ray.dir);
        if nd > R::of(0.0) {
            let t = (-R::dot4(*n, ray.origin) / nd).max(R::of(0.0));
            if best.is_none_or(|(_, b)| t < b) {
                best = Some((i, t));
            }
        }
    }
    best
}

/// Every face bit: what [`near_faces`] answers when it cannot cull.
pub const ALL_FACES: u32 = u32::MAX;

/// The faces the segment `o + t d`, `0 <= t <= t_end`, of a ray inside the
/// domain comes near: bit `i % 32` is set when some point of it may be
/// within the reach of face `i`'s plane (faces from 32 on fold onto the
/// bits as in the culling masks ([`super::FlatBall::face_mask`]): a bit is set when any of its faces
/// is near), the reach given by
/// `reach` (`sinh r`, `sin r` or `r` of the distance `r`, see
/// `FlatScene::near_reach`) times the space's `near_scale`
/// (`FaceTables::near_scale`). An object lying within that distance of
/// the planes of its face mask can be hit on the segment only if all of
/// its faces are near (`FlatBall::face_mask`), so the tracer tests no other.
///
/// Why the endpoints suffice: along the segment the ratio `n . p / p_w` of
/// a face's covector to the chart's `w` is a Moebius function of `t`, so
/// it is monotone where `p_w > 0` (all of the domain, see `near_scale`),
/// and its least absolute value is at an end, or zero where it changes
/// sign. A segment whose end is not finite is near every face.
///
/// WGSL twin: `near_faces` in `shaders/step.wgsl`.
#[inline]
#[must_use]
pub fn near_faces<R: Real>(planes: &[R::V4], near_scale: R, reach: R, ray: &Ray<R>, t_end: R) -> u32 {
    let within = near_scale * reach;
    if !(t_end.is_finite() && within.is_finite()) {
        return ALL_FACES;
    }
    let (wa, wb) = (R::xyzw(ray.origin)[3], R::xyzw(ray.origin + ray.dir * t_end)[3]);
    let mut near = ALL_FACES;
    for (i, n) in planes.iter().enumerate() {
        // n . o and n . d, as exit_face has them; the end's value from them.
        let (sa, sd) = (R::dot4(*n, ray.origin), R::dot4(*n, ray.dir));
        let sb = sa + t_end * sd;
        let crosses = (sa < R::of(0.0)) != (sb < R::of(0.0));
        let is_near = crosses || sa.abs() <= within * wa || sb.abs() <= within * wb;
        // Faces 0 to 31 clear their bit when far; the folded ones set it
        // again when near.
        if i < 32 && !is_near {
            near &= !(1u32 << i);
        } else if i >= 32 && is_near {
            near |= 1u32 << (i % 32);
        }
    }
    near
}

/// True when an object whose face mask is `mask` can be hit on a
/// segment near the faces `near` (from [`near_faces`]).
/// WGSL twin: `may_hit` in `shaders/step.wgsl`.
#[inline]
#[must_use]
pub fn may_hit(mask: u32, near: u32) -> bool {
    mask & !near == 0
}

/// The point of the ray at chart parameter `t`, normalised, and the unit
/// tangent of the geodesic there (the ray's direction carried along).
#[inline]
#[must_use]
pub fn advance<R: Real>(g: Geometry, ray: &Ray<R>, t: R) -> Ray<R> {
    let p = g.normalize_point::<R>(ray.origin + ray.dir * t);
    Ray {
        origin: p,
        dir: g.normalize_tangent::<R>(p, ray.dir),
    }
}

/// [`advance`] without renormalisation: the point and tangent at chart
/// parameter `t` scaled by the factors that are exact for a normalised ray
/// (`1/sqrt(1 - t^2)` in H3, `1/sqrt(1 + t^2)` in S3) instead of measured
/// from the vectors, so rounding error is carried on, never removed. Only
/// for measuring drift (`TraceSettings::renormalize` off).
#[inline]
#[must_use]
pub fn advance_raw<R: Real>(g: Geometry, ray: &Ray<R>, t: R) -> Ray<R> {
    let (o, d) = (ray.origin, ray.dir);
    let one = R::of(1.0);
    match g {
        Geometry::Euclidean => Ray {
            origin: o + d * t,
            dir: d,
        },
        Geometry::Hyperbolic => {
            let s = one / (one - t * t).sqrt();
            Ray {
                origin: (o + d * t) * s,
                dir: (o * t + d) * s,
            }
        }
        Geometry::Spherical => {
            let s = one / (one + t * t).sqrt();
            Ray {
                origin: (o + d * t) * s,
                dir: (d - o * t) * s,
            }
        }
    }
}

/// [`advance`], or [`advance_raw`] when `renormalize` is off.
#[inline]
#[must_use]
pub fn advance_or_raw<R: Real>(g: Geometry, ray: &Ray<R>, t: R, renormalize: bool) -> Ray<R> {
    if renormalize {
        advance(g, ray, t)
    } else {
        advance_raw(g, ray, t)
    }
}

/// Carries a ray that reached a face through its pairing `T` and brings it
/// back onto the model (renormalisation, so error does not accumulate).
#[inline]
#[must_use]
pub fn transport<R: Real>(g: Geometry, pairing: R::M4, ray: &Ray<R>) -> Ray<R> {
    let o = g.normalize_point::<R>(pairing * ray.origin);
    Ray {
        origin: o,
        dir: g.normalize_tangent::<R>(o, pairing * ray.dir),
    }
}

/// [`transport`] without renormalisation: `T o`, `T d` as they come out
/// of the (rounded) matrix. Only for measuring drift.
#[inline]
#[must_use]
pub fn transport_raw<R: Real>(pairing: R::M4, ray: &Ray<R>) -> Ray<R> {
    Ray {
        origin: pairing * ray.origin,
        dir: pairing * ray.dir,
    }
}

/// [`transport`], or [`transport_raw`] when `renormalize` is off.
#[inline]
#[must_use]
pub fn transport_or_raw<R: Real>(g: Geometry, pairing: R::M4, ray: &Ray<R>, renormalize: bool) -> Ray<R> {
    if renormalize {
        transport(g, pairing, ray)
    } else {
        transport_raw(pairing, ray)
    }
}

/// Smallest root `t >= t_min` of `a t^2 + 2 b t + c = 0` at which the
/// quadratic goes from positive to non-positive (the ray enters the region
/// `q <= 0`). Stable for tiny `a`.
#[inline]
#[must_use]
pub fn entering_root<R: Real>(a: R, b: R, c: R, t_min: R) -> Option<R> {
    let zero = R::of(0.0);
    let disc = b * b - a * c;
    if disc < zero {
        return None;
    }
    let s = disc.sqrt();
    // q = -(b + sign(b) s); roots q/a and c/q.
    let q = if b < zero { s - b } else { -(b + s) };
    let mut roots = [None, None];
    if q != zero {
        roots[0] = Some(c / q);
    }
    if a.abs() > R::EPSILON * (b.abs() + c.abs()) {
        roots[1] = Some(q / a);
    }
    let mut best: Option<R> = None;
    for t in roots.into_iter().flatten() {
        // Entering where the derivative 2(a t + b) is negative.
        if t >= t_min && a * t + b < zero && best.is_none_or(|x| t < x) {
            best = Some(t);
        }
    }
    best
}

/// The chart parameter where a ray enters the ball of centre `c` (a
/// normalised point) and radius given by `k`: `cosh r` (H3), `cos r` (S3),
/// `r^2` (E3). Exact: the ball is a quadric in the chart.
#[inline]
#[must_use]
pub fn hit_ball<R: Real>(g: Geometry, ray: &Ray<R>, c: R::V4, k: R, t_min: R) -> Option<R> {
    let (o, d) = (ray.origin, ray.dir);
    match g {
        Geometry::Euclidean => {
            let q = o - c;
            let b = g.form::<R>(q, d);
            entering_root(g.form::<R>(d, d), b, g.form::<R>(q, q) - k, t_min)
        }
        Geometry::Hyperbolic => {
            // -<p,c> <= cosh r |p|, |p|^2 = 1 - t^2 for p = o + t d.
            let (a0, b0) = (g.form::<R>(o, c), g.form::<R>(d, c));
            let t = entering_root(b0 * b0 + k * k, a0 * b0, a0 * a0 - k * k, t_min)?;
            (a0 + t * b0 < R::of(0.0)).then_some(t)
        }
        Geometry::Spherical => {
            // <p,c> >= cos r |p|, |p|^2 = 1 + t^2.
            let (a0, b0) = (g.form::<R>(o, c), g.form::<R>(d, c));
            let t = entering_root(k * k - b0 * b0, -(a0 * b0), k * k - a0 * a0, t_min)?;
            (a0 + t * b0 > R::of(0.0)).then_some(t)
        }
    }
}

/// A tube of radius `r` around the geodesic segment from the point `a` with
/// unit tangent `e` (towards the other end) to the point `b` with unit
/// tangent `e_b` there (pointing on, away from `a`). `k` is `cosh r`,
/// `cos r` or `r^2` as for balls. Returns the entering chart parameter
/// where the hit lies between the segment's end planes.
#[inline]
#[must_use]
pub fn hit_tube<R: Real>(g: Geometry, ray: &Ray<R>, seg: &Segment<R>, k: R, t_min: R) -> Option<R> {
    let (o, d) = (ray.origin, ray.dir);
    let t = match g {
        Geometry::Euclidean => {
            let q = o - seg.a;
            let (qe, de) = (g.form::<R>(q, seg.e), g.form::<R>(d, seg.e));
            entering_root(
                R::of(1.0) - de * de,
                g.form::<R>(q, d) - qe * de,
                g.form::<R>(q, q) - qe * qe - k,
                t_min,
            )?
        }
        Geometry::Hyperbolic => {
            // cosh^2(dist) = <p,a>^2 - <p,e>^2 <= cosh^2 r |p|^2.
            let (a1, b1) = (g.form::<R>(o, seg.a), g.form::<R>(d, seg.a));
            let (a2, b2) = (g.form::<R>(o, seg.e), g.form::<R>(d, seg.e));
            entering_root(
                b1 * b1 - b2 * b2 + k * k,
                a1 * b1 - a2 * b2,
                a1 * a1 - a2 * a2 - k * k,
                t_min,
            )?
        }
        Geometry::Spherical => {
            // cos^2(dist) = <p,a>^2 + <p,e>^2 >= cos^2 r |p|^2.
            let (a1, b1) = (g.form::<R>(o, seg.a), g.form::<R>(d, seg.a));
            let (a2, b2) = (g.form::<R>(o, seg.e), g.form::<R>(d, seg.e));
            entering_root(
                k * k - b1 * b1 - b2 * b2,
                -(a1 * b1 + a2 * b2),
                k * k - a1 * a1 - a2 * a2,
                t_min,
            )?
        }
    };
    on_edge(g, o + d * t, seg).then_some(t)
}

/// True when the point `p` (homogeneous, not necessarily normalised) lies
/// between the end planes of a tube's segment: past `a` along `e`, short
/// of `b` along `e_b`. WGSL twin: `on_edge` in `shaders/step.wgsl`.
#[inline]
#[must_use]
pub fn on_edge<R: Real>(g: Geometry, p: R::V4, seg: &Segment<R>) -> bool {
    let zero = R::of(0.0);
    let (along_a, along_b) = match g {
        Geometry::Euclidean => (g.form::<R>(p - seg.a, seg.e), g.form::<R>(p - seg.b, seg.e_b)),
        _ => (g.form::<R>(p, seg.e), g.form::<R>(p, seg.e_b)),
    };
    along_a >= zero && along_b <= zero
}

/// A geodesic segment prepared for [`hit_tube`].
#[derive(Clone, Copy, Debug)]
pub struct Segment<R: Real> {
    /// Start point.
    pub a: R::V4,
    /// Unit tangent at `a` towards `b`.
    pub e: R::V4,
    /// End point.
    pub b: R::V4,
    /// Unit tangent at `b`, pointing away from `a`.
    pub e_b: R::V4,
}

/// The foot of the perpendicular from the normalised point `x` to the
/// segment's geodesic (not normalised): used for the tube's normal.
#[inline]
#[must_use]
pub fn foot_on_line<R: Real>(g: Geometry, x: R::V4, seg: &Segment<R>) -> R::V4 {
    match g {
        Geometry::Euclidean => seg.a + seg.e * g.form::<R>(x - seg.a, seg.e),
        Geometry::Hyperbolic => seg.e * g.form::<R>(x, seg.e) - seg.a * g.form::<R>(x, seg.a),
        Geometry::Spherical => seg.a * g.form::<R>(x, seg.a) + seg.e * g.form::<R>(x, seg.e),
    }
}

/// The outward unit normal at `x` of a round object centred at `c` (a
/// ball's centre, a tube's foot point): the tangent at `x` pointing away.
#[inline]
#[must_use]
pub fn normal_from<R: Real>(g: Geometry, x: R::V4, c: R::V4) -> R::V4 {
    g.normalize_tangent::<R>(x, -c)
}

/// The radius parameter `k` of [`hit_ball`]/[`hit_tube`] for radius `r`.
#[must_use]
pub fn radius_param(g: Geometry, r: f64) -> f64 {
    match g {
        Geometry::Euclidean => r * r,
        Geometry::Hyperbolic => r.cosh(),
        Geometry::Spherical => r.cos(),
    }
}
