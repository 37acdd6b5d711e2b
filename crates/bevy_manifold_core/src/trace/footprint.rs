//! Cone tracing: each pixel is a thin cone rather than a ray, so a ball or
//! an edge tube narrower than the cone's footprint fades to the part of
//! the pixel it covers instead of flickering on and off as the view
//! moves.
//!
//! A pixel's cone has the half-angle `beta` of half a pixel
//! ([`pixel_half_angle`]). At distance `D` along its axis (the ray) it is
//! `w = beta * spread(D)` wide ([`spread`]: geodesics leaving a point at
//! a small angle part as `sinh D` in H3, `D` in E3, `|sin D|` in S3), and
//! at most [`FOOTPRINT_CAP`] of the domain's inradius. Objects are grown
//! by the segment's widest footprint ([`Inflation`]); each one the ray's
//! geodesic passes within its grown radius of ([`approach`],
//! [`Approach::within`]) is a layer, placed where the ray passes nearest
//! it, and its gap to the object's centre or axis ([`Approach::gap`]) and
//! the footprint there give the part of the pixel it covers
//! ([`coverage`]: a strip across a tube, a spread disc for a ball). The
//! layers are added front to back ([`Layers`]) until one covers all that
//! is left.
//!
//! WGSL twin: `shaders/footprint.wgsl` in `bevy_manifold_gpu` (the same
//! names), used by `cone.wgsl`, `nearest.wgsl` and `trace.wgsl`.

use super::step::{Ray, Segment};
use crate::geometry::{Geometry, Real};

/// Most layers one pixel adds: after them what is left sees the
/// background ([`Layers::full`]). WGSL twin: `MAX_LAYERS` in
/// `shaders/footprint.wgsl`.
pub const MAX_LAYERS: u32 = 16;

/// Most layers kept on one segment of a ray's walk: the nearest.
/// WGSL twin: `SEGMENT_LAYERS`.
pub const SEGMENT_LAYERS: usize = 4;

/// The widest a pixel's cone grows, as a fraction of the domain's
/// inradius (`FlatScene::footprint_cap`). Far away, where the pixel's
/// footprint is wider, the cone stays this wide: it samples the far
/// copies as a narrower cone would, each layer covering more of the
/// pixel, and tests and shades a few objects a segment instead of all
/// of them. Measured (`bench aa`): as close to 16 samples per pixel as
/// the uncapped cone and flickering as little as that reference, at half
/// the uncapped cost on the CPU. WGSL twin: `params.footprint_cap`.
pub const FOOTPRINT_CAP: f64 = 0.25;

/// How many footprints balls are grown by: the Gaussian [`disc`] spreads
/// a small ball that far. Tubes grow by one, the half-width of the
/// [`strip`] filter. WGSL twin: `BALL_GROWTH`.
pub const BALL_GROWTH: f64 = 3.5;

/// Light left behind the layers below which the next layer takes it all.
/// WGSL twin: `LAYERS_CLEAR` in `shaders/footprint.wgsl`.
pub const LAYERS_CLEAR: f32 = 1.0 / 255.0;

/// The half-angle of a pixel's cone for an image `height` pixels high:
/// half the slope of one row (`half_height`, the frustum's half height in
/// slopes, over `height`) in a perspective view, half a row's latitude
/// (`pi / height`, halved) in an equirectangular panorama, and the same
/// for each eye's half of a top-bottom stereo one.
///
/// ```
/// use bevy_manifold_core::trace::{Projection, pixel_half_angle};
/// // 90 degrees over 100 rows: each row spans a slope of 2/100.
/// assert!((pixel_half_angle(Projection::Perspective, 1.0, 100) - 0.01).abs() < 1e-12);
/// ```
#[must_use]
pub fn pixel_half_angle(projection: super::Projection, half_height: f64, height: u32) -> f64 {
    let h = f64::from(height.max(1));
    match projection {
        super::Projection::Perspective => half_height / h,
        super::Projection::Equirect => core::f64::consts::PI / (2.0 * h),
        super::Projection::Ods { .. } => core::f64::consts::PI / (2.0 * (h / 2.0).floor().max(1.0)),
    }
}

/// How far apart two geodesics leaving one point at unit angle are after
/// distance `d`, to first order in the angle: `sinh d` (H3), `d` (E3),
/// `|sin d|` (S3, where they meet again at the antipode, a half turn on,
/// and a far copy there is as sharp as a near one). WGSL twin: `spread`.
#[inline]
#[must_use]
pub fn spread<R: Real>(g: Geometry, d: R) -> R {
    match g {
        Geometry::Euclidean => d,
        Geometry::Hyperbolic => d.sinh(),
        Geometry::Spherical => d.sin().abs(),
    }
}

/// The most [`spread`] between distances `d0` and `d1 >= d0` from the
/// eye: at `d1` in E3 and H3, where it only grows; in S3 1 when a quarter
/// turn (plus a whole number of half turns) lies between, else the more
/// of the two ends. WGSL twin: `widest_spread`.
#[inline]
#[must_use]
pub fn widest_spread<R: Real>(g: Geometry, d0: R, d1: R) -> R {
    if g != Geometry::Spherical {
        return spread(g, d1);
    }
    let pi = core::f64::consts::PI;
    // The first quarter turn (mod a half turn) at or after d0.
    let k = ((d0.f64() - pi / 2.0) / pi).ceil();
    if k * pi + pi / 2.0 <= d1.f64() {
        R::of(1.0)
    } else {
        spread(g, d0).max(spread(g, d1))
    }
}

/// Objects grown by a footprint `w`: the `k` (`cosh r`, `cos r`, `r^2`)
/// of radius `r + w` from that of `r` for a tube ([`Inflation::k`]), of
/// `r + BALL_GROWTH w` for a ball ([`Inflation::ball_k`]), with the
/// functions of the growths computed once per segment. WGSL twin:
/// `Inflation` and `grow_k`.
#[derive(Clone, Copy, Debug)]
pub struct Inflation<R: Real> {
    /// The footprint, a distance (0: nothing grows).
    pub w: R,
    tube: (R, R),
    ball: (R, R),
}

impl<R: Real> Inflation<R> {
    /// Growth by `w` in `g`.
    #[must_use]
    pub fn new(g: Geometry, w: R) -> Self {
        let trig = |x: R| match g {
            Geometry::Euclidean => (R::of(1.0), x),
            Geometry::Hyperbolic => (x.cosh(), x.sinh()),
            Geometry::Spherical => (x.cos(), x.sin()),
        };
        Inflation {
            w,
            tube: trig(w),
            ball: trig(w * R::of(BALL_GROWTH)),
        }
    }

    /// No growth: `k` comes back unchanged.
    #[must_use]
    pub fn none() -> Self {
        let (one, zero) = (R::of(1.0), R::of(0.0));
        Inflation {
            w: zero,
            tube: (one, zero),
            ball: (one, zero),
        }
    }

    /// A tube's `k` grown by `w`. Exactly `k` when `w` is 0.
    #[inline]
    #[must_use]
    pub fn k(&self, g: Geometry, k: R) -> R {
        if self.w == R::of(0.0) {
            k
        } else {
            grow_k(g, k, self.tube)
        }
    }

    /// A ball's `k` grown by [`BALL_GROWTH`] `w`. Exactly `k` when `w` is 0.
    #[inline]
    #[must_use]
    pub fn ball_k(&self, g: Geometry, k: R) -> R {
        if self.w == R::of(0.0) {
            k
        } else {
            grow_k(g, k, self.ball)
        }
    }
}

/// The `k` of radius `r + x` from the `k` of radius `r` and `(cosh x,
/// sinh x)`, `(cos x, sin x)` or `(1, x)`: `cosh(r + x) = k cosh x +
/// sinh r sinh x`, `cos(r + x) = k cos x - sin r sin x` (at least -1),
/// `(sqrt k + x)^2`. WGSL twin: `grow_k`.
#[inline]
#[must_use]
pub fn grow_k<R: Real>(g: Geometry, k: R, (cosine, sine): (R, R)) -> R {
    let (zero, one) = (R::of(0.0), R::of(1.0));
    match g {
        Geometry::Euclidean => {
            let r = k.max(zero).sqrt() + sine;
            r * r
        }
        Geometry::Hyperbolic => k * cosine + (k * k - one).max(zero).sqrt() * sine,
        Geometry::Spherical => (k * cosine - (one - k * k).max(zero).sqrt() * sine).max(-one),
    }
}

/// The reach of [`super::step::near_faces`]' test for objects grown by
/// `w`: `s(near_distance + w)` (`s` as in [`super::near_reach`]: `sinh`,
/// `sin` up to a quarter turn and infinite from there, the distance
/// itself), what `FlatScene::near_reach` is for objects not grown. An
/// object within `near_distance` of the planes of its face mask is,
/// grown, within `near_distance + w` of them. WGSL twin: `grown_reach`.
#[inline]
#[must_use]
pub fn grown_reach<R: Real>(g: Geometry, near_distance: R, w: R) -> R {
    let r = near_distance + w;
    match g {
        Geometry::Euclidean => r,
        Geometry::Hyperbolic => r.sinh(),
        Geometry::Spherical if r.f64() < core::f64::consts::FRAC_PI_2 => r.sin(),
        Geometry::Spherical => R::of(f64::INFINITY),
    }
}

/// The radius whose `k` is `k`: `acosh k`, `acos k`, `sqrt k`.
/// WGSL twin: `radius_of`.
#[inline]
#[must_use]
pub fn radius_of<R: Real>(g: Geometry, k: R) -> R {
    let zero = R::of(0.0);
    match g {
        Geometry::Euclidean => k.max(zero).sqrt(),
        Geometry::Hyperbolic => (k * k - R::of(1.0)).max(zero).sqrt().asinh(),
        Geometry::Spherical => (R::of(1.0) - k * k).max(zero).sqrt().atan2(k),
    }
}

/// The part of `x` (a point or a tangent, homogeneous) off the flat
/// through the point `a` along the unit tangent `e` (a geodesic), or
/// through `a` alone when `e` is zero (a point): `x` less its projection
/// onto the span of `a` and `e`, whose form with itself is `sinh^2`
/// (H3), `sin^2` (S3) or the square (E3) of the distance from a point
/// `x` to the flat. WGSL twin: `off_flat`.
#[inline]
#[must_use]
pub fn off_flat<R: Real>(g: Geometry, x: R::V4, a: R::V4, e: R::V4) -> R::V4 {
    match g {
        Geometry::Euclidean => {
            let y = x - a * R::xyzw(x)[3];
            y - e * g.form::<R>(y, e)
        }
        Geometry::Hyperbolic => x + a * g.form::<R>(x, a) - e * g.form::<R>(x, e),
        Geometry::Spherical => x - a * g.form::<R>(x, a) - e * g.form::<R>(x, e),
    }
}

/// Where the whole geodesic of `ray` comes nearest the flat through `a`
/// along `e` ([`off_flat`]): a ball's centre (`e` zero) or a tube's
/// axis. (The distance itself, [`Approach::gap`], a transcendental, is
/// left until a test on `lambda` has let the object through.) Along the
/// ray `p = o + t d`, the squared off-flat part is
/// `P + 2 M t + Q t^2` over `1 - t^2` (H3), `1 + t^2` (S3) or 1 (E3); its
/// least value `lambda` is where the quotient touches it, a double root
/// of the numerator less `lambda` times the denominator, taken in the
/// form that does not cancel; the root is the chart parameter.
/// WGSL twin: `Approach` and `approach`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Approach<R: Real> {
    /// The least distance's `sinh^2` (H3), `sin^2` (S3) or square (E3):
    /// what [`Approach::within`] compares; [`Approach::gap`] is the
    /// distance.
    pub lambda: R,
    /// The chart parameter on the ray where it is reached (perhaps
    /// behind the origin or past the segment).
    pub t: R,
}

/// [`Approach`] of `ray` to the flat through `a` along `e`.
#[inline]
#[must_use]
pub fn approach<R: Real>(g: Geometry, ray: &Ray<R>, a: R::V4, e: R::V4) -> Approach<R> {
    let (po, pd) = (off_flat::<R>(g, ray.origin, a, e), off_flat::<R>(g, ray.dir, a, e));
    let (p, m, q) = (g.form::<R>(po, po), g.form::<R>(po, pd), g.form::<R>(pd, pd));
    let (zero, two) = (R::of(0.0), R::of(2.0));
    let det = (p * q - m * m).max(zero);
    // The least value and the leading coefficient of the touching
    // quadratic, whose double root is at -m over it.
    let (lambda, lead) = match g {
        Geometry::Euclidean => (if q > zero { det / q } else { p }, q),
        // Roots of l^2 - (P - Q) l - det = 0: the one not negative.
        Geometry::Hyperbolic => {
            let s = ((p + q) * (p + q) - two * two * m * m).max(zero).sqrt();
            let lambda = if p >= q {
                (p - q + s) / two
            } else if s - (p - q) > zero {
                two * det / (s - (p - q))
            } else {
                zero
            };
            (lambda, q + lambda)
        }
        // Roots of l^2 - (P + Q) l + det = 0: the smaller.
        Geometry::Spherical => {
            let s = ((p - q) * (p - q) + two * two * m * m).max(zero).sqrt();
            let lambda = if p + q + s > zero {
                two * det / (p + q + s)
            } else {
                zero
            };
            (lambda, q - lambda)
        }
    };
    // Where the least value is not at a finite chart parameter the
    // touching quadratic can place (its leading coefficient lost to
    // rounding: the ray all but parallel to the flat, or nearest it a
    // quarter turn away in S3), the start's own value, at the start. (The
    // least value with t 0 passed a lens space's start 0.25 from an edge's
    // faces as within its tube, in f32.)
    let (lambda, t) = if lead.abs() > R::EPSILON {
        (lambda, -m / lead)
    } else {
        (p, zero)
    };
    Approach { lambda, t }
}

impl<R: Real> Approach<R> {
    /// The least distance: `asinh`, `asin` or the square root of
    /// `lambda`. WGSL twin: `gap_of`.
    #[inline]
    #[must_use]
    pub fn gap(&self, g: Geometry) -> R {
        let (zero, one) = (R::of(0.0), R::of(1.0));
        let root = self.lambda.max(zero).sqrt();
        match g {
            Geometry::Euclidean => root,
            Geometry::Hyperbolic => root.asinh(),
            Geometry::Spherical => root.min(one).atan2((one - self.lambda).max(zero).sqrt()),
        }
    }

    /// True when the gap is at most the radius whose `k` (`cosh`, `cos`,
    /// square) is `k`: `lambda <= k^2 - 1`, `1 - k^2`, `k`.
    #[inline]
    #[must_use]
    pub fn within(&self, g: Geometry, k: R) -> bool {
        let one = R::of(1.0);
        self.lambda
            <= match g {
                Geometry::Euclidean => k,
                Geometry::Hyperbolic => k * k - one,
                Geometry::Spherical => one - k * k,
            }
    }
}

/// [`approach`] to a ball's centre `c`. WGSL twin: `ball_approach`.
#[inline]
#[must_use]
pub fn ball_approach<R: Real>(g: Geometry, ray: &Ray<R>, c: R::V4) -> Approach<R> {
    let zero = R::of(0.0);
    approach::<R>(g, ray, c, R::v4(zero, zero, zero, zero))
}

/// [`approach`] to the geodesic of a tube's segment. WGSL twin:
/// `tube_approach`.
#[inline]
#[must_use]
pub fn tube_approach<R: Real>(g: Geometry, ray: &Ray<R>, seg: &Segment<R>) -> Approach<R> {
    approach::<R>(g, ray, seg.a, seg.e)
}

/// Where a layer that the ray does not hit squarely is shaded: at the
/// offset, across the object as seen along the ray, that stands for the
/// part of it the pixel covers, as a fraction of its radius `r`. The
/// ray's own offset `gap` when it is within that, else at most the rim
/// (1) for an object much wider than the footprint `w`, and for one much
/// thinner the mean offset over its width: 2/3 over a disc (a ball), 1/2
/// across a strip (a tube), blended by `w / r`. WGSL twin: `shading_offset`.
#[inline]
#[must_use]
pub fn shading_offset<R: Real>(ball: bool, gap: R, r: R, w: R) -> R {
    let one = R::of(1.0);
    let thin = if ball { R::of(1.0 / 3.0) } else { R::of(0.5) };
    let cap = one - thin * (w / r).min(one);
    (gap / r).min(cap).max(R::of(0.0))
}

/// The normal at offset `s` (a fraction of the radius) across a round
/// object seen along `view` (the unit tangent towards the eye at `x`),
/// on the side of the normal `n0` there: `sqrt(1 - s^2) view + s u`,
/// `u` the unit part of `n0` across `view`; `view` when there is none.
/// WGSL twin: `normal_at_offset`.
#[inline]
#[must_use]
pub fn normal_at_offset<R: Real>(g: Geometry, n0: R::V4, view: R::V4, s: R) -> R::V4 {
    let zero = R::of(0.0);
    let across = n0 - view * g.form::<R>(n0, view);
    let len = g.form::<R>(across, across).max(zero).sqrt();
    let up = (R::of(1.0) - s * s).max(zero).sqrt();
    if len > R::of(1e-12) {
        view * up + across * (s / len)
    } else {
        view
    }
}

/// The part of a pixel of half-width `w` (centred on 0) that a strip from
/// `delta - r` to `delta + r` covers: the box filter of a pixel across an
/// edge. 1 or 0 by `delta <= r` when `w` is 0. WGSL twin: `strip`.
#[inline]
#[must_use]
pub fn strip<R: Real>(delta: R, r: R, w: R) -> R {
    let zero = R::of(0.0);
    if w <= zero || !w.is_finite() {
        return if delta <= r { R::of(1.0) } else { zero };
    }
    let covered = (delta + r).min(w) - (delta - r).max(-w);
    (covered / (w + w)).max(zero).min(R::of(1.0))
}

/// The part of a pixel of half-width `w` that a ball seen as a disc of
/// radius `r`, centred `delta` from the pixel's centre, covers. A disc
/// much smaller than the pixel is spread as a Gaussian of deviation
/// `sqrt(1.5) w` (its area `pi r^2` times the Gaussian's density at
/// `delta`, in pixels of side `2 w`): on a grid of pixels these sum to
/// the disc's area wherever it lies, to a fraction of a percent. One
/// more than three half-widths across is the [`strip`] across its rim,
/// and the two are blended in between. Nothing is spread past
/// [`BALL_GROWTH`] half-widths beyond the rim, how far balls are grown.
/// Knowing only `delta`, not where in the pixel grid the disc is, no
/// kernel sums exactly; this one stays within 6% of the area for every
/// radius, 3% below half a pixel. 1 or 0 by `delta <= r` when `w` is 0.
/// WGSL twin: `disc`.
#[inline]
#[must_use]
pub fn disc<R: Real>(delta: R, r: R, w: R) -> R {
    let (zero, one) = (R::of(0.0), R::of(1.0));
    if w <= zero || !w.is_finite() {
        return if delta <= r { one } else { zero };
    }
    if delta > r + R::of(BALL_GROWTH) * w {
        return zero;
    }
    let spread2 = R::of(3.0) * w * w;
    let gauss = r * r / spread2 * (-(delta * delta) / spread2).exp();
    let rim = strip(delta, r, w);
    let blend = ((r / w - R::of(1.5)) / R::of(1.5)).max(zero).min(one);
    (gauss + blend * (rim - gauss)).max(zero).min(one)
}

/// What a layer covers of a pixel whose footprint there is `w`: a ball of
/// radius `r` whose centre is `delta` from the pixel's axis covers
/// [`disc`]`(delta, r, w)`. A tube of radius `r` and length `length`
/// whose axis passes `delta` from it covers [`strip`]`(delta, r, w)` of
/// the pixel's width, and of its height at most its length (an edge
/// shorter than a far pixel is not a strip across it). WGSL twin:
/// `coverage`.
#[inline]
#[must_use]
pub fn coverage<R: Real>(ball: bool, delta: R, r: R, length: R, w: R) -> R {
    if ball {
        disc(delta, r, w)
    } else if w > R::of(0.0) {
        strip(delta, r, w) * (length / (w + w)).min(R::of(1.0))
    } else {
        strip(delta, r, w)
    }
}

/// How many copies of the domain lie side by side across a cone's
/// cross-section of half-width `w` (area `4 w^2`, on the geodesic sphere
/// it crosses), for a domain whose shadow is `cell_shadow` on average:
/// at least 1. The cone's axis walks one of them; an object it meets
/// stands for its copies in all. WGSL twin: `side_by_side`.
#[inline]
#[must_use]
pub fn side_by_side<R: Real>(w: R, cell_shadow: R) -> R {
    (R::of(4.0) * w * w / cell_shadow).max(R::of(1.0))
}

/// The layers a pixel's cone has met, front to back: the colour so far,
/// the light left (`1 -` what they cover) and how many. A layer that
/// covers all that is left, or leaves less than [`LAYERS_CLEAR`], takes
/// the rest and ends the pixel; after [`MAX_LAYERS`] the pixel ends too,
/// the light left seeing the background, as a ray that used up its
/// levels does. WGSL twin: `Layers`, `add_layer` and `layers_over`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Layers {
    /// Linear colour of the layers so far, each times its coverage and
    /// the light left in front of it.
    pub color: [f32; 3],
    /// The light the layers leave.
    pub left: f32,
    /// Layers added.
    pub count: u32,
}

impl Default for Layers {
    fn default() -> Self {
        Layers {
            color: [0.0; 3],
            left: 1.0,
            count: 0,
        }
    }
}

impl Layers {
    /// Adds a layer of `color` covering `part` of the pixel. True when it
    /// takes all the light left.
    pub fn add(&mut self, color: [f32; 3], part: f32) -> bool {
        self.count += 1;
        let part = part.clamp(0.0, 1.0);
        let last = part >= 1.0 || self.left * (1.0 - part) < LAYERS_CLEAR;
        let take = if last { self.left } else { self.left * part };
        for (s, c) in self.color.iter_mut().zip(color) {
            *s += take * c;
        }
        self.left -= take;
        last
    }

    /// True once [`MAX_LAYERS`] layers are in: the pixel ends.
    #[must_use]
    pub fn full(&self) -> bool {
        self.count >= MAX_LAYERS
    }

    /// The pixel's colour with `behind` seen through what the layers left.
    #[must_use]
    pub fn over(&self, behind: [f32; 3]) -> [f32; 3] {
        [0, 1, 2].map(|c| self.color[c] + self.left * behind[c])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Geometry;
    use glam::DVec4;

    fn ray(g: Geometry, from: DVec4, to: DVec4) -> Ray<f64> {
        let o = g.normalize_point::<f64>(from);
        Ray {
            origin: o,
            dir: g.normalize_tangent::<f64>(o, to),
        }
    }

    // Points at distance s from the origin along a unit direction u.
    fn at(g: Geometry, u: [f64; 3], s: f64) -> DVec4 {
        let u = glam::DVec3::from(u).normalize();
        match g {
            Geometry::Euclidean => (u * s).extend(1.0),
            Geometry::Hyperbolic => (u * s.sinh()).extend(s.cosh()),
            Geometry::Spherical => (u * s.sin()).extend(s.cos()),
        }
    }

    #[test]
    fn a_ray_passes_a_point_at_the_distance_the_triangle_gives() {
        // A ray from the origin along x passes a point at distance L
        // from the origin, seen at angle A off the ray, at the distance
        // of the right triangle: sinh gap = sinh L sin A (H3), sin gap =
        // sin L sin A (S3), L sin A (E3).
        let (l, angle) = (0.8f64, 0.3f64);
        for g in [Geometry::Euclidean, Geometry::Hyperbolic, Geometry::Spherical] {
            let r = ray(g, DVec4::W, DVec4::X);
            let c = at(g, [angle.cos(), angle.sin(), 0.0], l);
            let want = match g {
                Geometry::Euclidean => l * angle.sin(),
                Geometry::Hyperbolic => (l.sinh() * angle.sin()).asinh(),
                Geometry::Spherical => (l.sin() * angle.sin()).asin(),
            };
            let got = ball_approach::<f64>(g, &r, c).gap(g);
            assert!((got - want).abs() < 1e-12, "{g:?}: {got} against {want}");
            // From another point of the same geodesic, pointing back: the
            // gap is the geodesic's, not the ray's.
            let r2 = ray(g, at(g, [1.0, 0.0, 0.0], 1.1), -DVec4::X);
            let got2 = ball_approach::<f64>(g, &r2, c).gap(g);
            assert!((got2 - want).abs() < 1e-9, "{g:?} from behind: {got2} against {want}");
        }
    }

    #[test]
    fn a_ray_passes_a_skew_line_at_their_common_perpendicular() {
        // The ray along x through the origin; the line through the point
        // at distance h up the y axis, along z. Their common
        // perpendicular is the y axis: the gap is h in every geometry.
        let h = 0.45f64;
        for g in [Geometry::Euclidean, Geometry::Hyperbolic, Geometry::Spherical] {
            let a = at(g, [0.0, 1.0, 0.0], h);
            let seg = Segment::<f64> {
                a,
                e: DVec4::Z,
                b: a,
                e_b: DVec4::Z,
            };
            // The ray from a point off the perpendicular's foot.
            let r = ray(g, at(g, [-1.0, 0.0, 0.0], 0.7), DVec4::X);
            let got = tube_approach::<f64>(g, &r, &seg);
            // The perpendicular's foot on the ray is the origin, 0.7 on.
            let foot = g.chart_to_distance::<f64>(got.t);
            assert!((foot - 0.7).abs() < 1e-9, "{g:?}: foot at {foot}");
            let got = got.gap(g);
            assert!((got - h).abs() < 1e-12, "{g:?}: {got} against {h}");
        }
    }

    #[test]
    fn cones_widen_with_distance_and_refocus_at_the_antipode_in_s3() {
        let s3 = Geometry::Spherical;
        assert!(
            spread::<f64>(s3, core::f64::consts::PI).abs() < 1e-15,
            "sharp again at the antipode"
        );
        assert_eq!(widest_spread::<f64>(s3, 1.0, 2.0), 1.0);
        assert_eq!(widest_spread::<f64>(s3, 2.0, 3.0), 2f64.sin());
        assert_eq!(widest_spread::<f64>(s3, 4.0, 5.0), 1.0);
        assert_eq!(widest_spread::<f64>(s3, 5.0, 6.0), 5f64.sin().abs());
        assert_eq!(widest_spread::<f64>(Geometry::Hyperbolic, 1.0, 2.0), 2f64.sinh());
        assert_eq!(widest_spread::<f64>(Geometry::Euclidean, 1.0, 2.0), 2.0);
    }

    #[test]
    fn a_grown_radius_is_the_sum_of_the_radii() {
        for g in [Geometry::Euclidean, Geometry::Hyperbolic, Geometry::Spherical] {
            let (r, w) = (0.05f64, 0.013f64);
            let k = super::super::step::radius_param(g, r);
            let grown = Inflation::<f64>::new(g, w);
            assert!((radius_of::<f64>(g, grown.k(g, k)) - (r + w)).abs() < 1e-12, "{g:?}");
            let ball = radius_of::<f64>(g, grown.ball_k(g, k));
            assert!((ball - (r + BALL_GROWTH * w)).abs() < 1e-12, "{g:?}");
            assert_eq!(Inflation::<f64>::none().k(g, k), k);
            assert!((radius_of::<f64>(g, k) - r).abs() < 1e-12);
        }
    }

    #[test]
    fn a_strip_covers_its_overlap_with_the_pixel() {
        // Half-width 1: a strip of half-width 0.25 in the middle covers a
        // quarter; one overhanging the edge by half its width an eighth.
        assert!((strip(0.0f64, 0.25, 1.0) - 0.25).abs() < 1e-15);
        assert!((strip(1.0f64, 0.25, 1.0) - 0.125).abs() < 1e-15);
        assert_eq!(strip(1.3f64, 0.25, 1.0), 0.0);
        assert_eq!(strip(0.0f64, 3.0, 1.0), 1.0);
        // No footprint: the ray's own hit or miss.
        assert_eq!(strip(0.1f64, 0.1, 0.0), 1.0);
        assert_eq!(strip(0.1001f64, 0.1, 0.0), 0.0);
    }

    #[test]
    fn a_disc_covers_its_area_summed_over_any_grid() {
        // Discs of radius 0.05 to 3 px (half-width w = 0.5) at offsets on a
        // grid of unit pixels: the coverages sum to the disc's area,
        // pi r^2, within 6%; those under a pixel across within 3.5%.
        for r in [0.05, 0.2, 0.4, 0.5, 0.7, 1.0, 1.5, 3.0] {
            for (ox, oy) in [(0.0, 0.0), (0.5, 0.5), (0.23, 0.71), (0.5, 0.0)] {
                let mut sum = 0.0f64;
                for i in -8..=8 {
                    for j in -8..=8 {
                        let (dx, dy) = (f64::from(i) - ox, f64::from(j) - oy);
                        sum += disc(dx.hypot(dy), r, 0.5);
                    }
                }
                let want = core::f64::consts::PI * r * r;
                let bound = if r <= 0.5 { 0.035 } else { 0.06 };
                assert!(
                    (sum / want - 1.0).abs() < bound,
                    "r {r} at ({ox}, {oy}): {sum} against {want}"
                );
            }
        }
        // A disc many pixels wide: inside covered, outside not, its rim
        // the strip.
        assert_eq!(disc(0.0f64, 10.0, 0.5), 1.0);
        assert_eq!(disc(11.0f64, 10.0, 0.5), 0.0);
        assert!((disc(10.0f64, 10.0, 0.5) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn layers_add_front_to_back_and_the_last_takes_the_rest() {
        let mut l = Layers::default();
        assert!(!l.add([1.0, 0.0, 0.0], 0.25));
        assert!(!l.add([0.0, 1.0, 0.0], 0.5));
        // 0.25 red, 0.75 * 0.5 green, 0.375 of the blue behind.
        assert_eq!(l.over([0.0, 0.0, 1.0]), [0.25, 0.375, 0.375]);
        assert!(l.add([0.0, 0.0, 0.0], 1.0));
        assert_eq!(l.left, 0.0);
        let mut m = Layers::default();
        for _ in 0..MAX_LAYERS {
            assert!(!m.full());
            assert!(!m.add([1.0; 3], 0.1));
        }
        assert!(m.full(), "the pixel ends after MAX_LAYERS");
        // What is left, 0.9^MAX_LAYERS, sees the background.
        let left = 0.9f32.powi(MAX_LAYERS as i32);
        assert!((m.left - left).abs() < 1e-6);
        assert!((m.over([0.0; 3])[0] - (1.0 - left)).abs() < 1e-6);
        // A layer leaving less than LAYERS_CLEAR takes the rest.
        let mut n = Layers::default();
        assert!(n.add([1.0; 3], 0.999));
        assert_eq!(n.left, 0.0);
    }
}
