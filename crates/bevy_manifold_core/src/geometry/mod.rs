//! The three classical geometries in one projective chart.
//!
//! WGSL twin of the metric functions: `shaders/geometry.wgsl` in
//! `bevy_manifold_gpu` (`form`, `normalize_point`, `distance`, ...).
//!
//! Points are homogeneous 4-vectors `(x, y, z, w)`, normalised per geometry:
//! `w = 1` in E3, `<p,p> = -1` with `w > 0` in H3 (hyperboloid, seen in the
//! Klein ball), `|p| = 1` in S3 (seen in the gnomonic chart). In every chart
//! geodesics are straight lines and planes are flat, so a face is a covector
//! `n` with `n . p <= 0` inside, whatever the geometry.
//!
//! The metric appears only in this module: the form, normalisation, distance,
//! the exponential map and the chart-parameter/distance conversion. The rest
//! of the crate is geometry-neutral. Functions here are generic over [`Real`]
//! so the f64 reference and the f32 mirror of the GPU run the same steps.
//!
//! Matrix convention, fixed once: matrices act on column vectors (`m * p`),
//! and files write them row-major.
//!
//! ```
//! use bevy_manifold_core::geometry::{Geometry, isometry};
//! use glam::{DVec3, DVec4};
//! let h = Geometry::Hyperbolic;
//! let origin = DVec4::W;
//! let t = isometry::translation(h, DVec3::X * 1.5);
//! assert!((h.distance::<f64>(origin, t * origin) - 1.5).abs() < 1e-12);
//! ```

pub mod isometry;
pub mod plane;
pub mod product;
mod real;

pub use real::Real;

use serde::{Deserialize, Serialize};

/// One of the three model geometries.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Geometry {
    /// Flat space E3: affine chart, `w = 1`.
    Euclidean,
    /// Hyperbolic space H3: hyperboloid `<p,p> = -1`, Klein-ball chart.
    Hyperbolic,
    /// The 3-sphere S3: `|p| = 1`, gnomonic chart.
    Spherical,
}

impl Geometry {
    /// The sign of the `w w` term of the form: 0 (E3), -1 (H3), +1 (S3).
    /// It is also the sectional curvature.
    #[must_use]
    pub const fn curvature(self) -> f64 {
        match self {
            Geometry::Euclidean => 0.0,
            Geometry::Hyperbolic => -1.0,
            Geometry::Spherical => 1.0,
        }
    }

    /// Lower-case name as used in files and on the command line.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Geometry::Euclidean => "euclidean",
            Geometry::Hyperbolic => "hyperbolic",
            Geometry::Spherical => "spherical",
        }
    }

    /// The bilinear form `<u,v>`: `ux vx + uy vy + uz vz + k uw vw` with `k`
    /// the curvature. In E3 it is the form on tangent vectors (`w = 0`).
    #[inline]
    #[must_use]
    pub fn form<R: Real>(self, u: R::V4, v: R::V4) -> R {
        let [ux, uy, uz, uw] = R::xyzw(u);
        let [vx, vy, vz, vw] = R::xyzw(v);
        let s = ux * vx + uy * vy + uz * vz;
        match self {
            Geometry::Euclidean => s,
            Geometry::Hyperbolic => s - uw * vw,
            Geometry::Spherical => s + uw * vw,
        }
    }

    /// Brings a homogeneous point back onto the model: `w = 1` (E3),
    /// `<p,p> = -1, w > 0` (H3), `|p| = 1` (S3).
    #[inline]
    #[must_use]
    pub fn normalize_point<R: Real>(self, p: R::V4) -> R::V4 {
        let [_, _, _, w] = R::xyzw(p);
        match self {
            Geometry::Euclidean => p * (R::of(1.0) / w),
            Geometry::Hyperbolic => {
                let n = (-self.form::<R>(p, p)).abs().sqrt();
                let s = if w < R::of(0.0) { -n } else { n };
                p * (R::of(1.0) / s)
            }
            Geometry::Spherical => p * (R::of(1.0) / R::dot4(p, p).sqrt()),
        }
    }

    /// Projects `v` onto the tangent space at the (normalised) point `p` and
    /// scales it to unit length with the form.
    #[inline]
    #[must_use]
    pub fn normalize_tangent<R: Real>(self, p: R::V4, v: R::V4) -> R::V4 {
        let t = self.project_tangent::<R>(p, v);
        t * (R::of(1.0) / self.form::<R>(t, t).abs().sqrt())
    }

    /// Projects `v` onto the tangent space at the normalised point `p`
    /// without rescaling. For `v` a point `q`, the result points from `p`
    /// towards `q`; for `v = -q`, away from it.
    #[inline]
    #[must_use]
    pub fn project_tangent<R: Real>(self, p: R::V4, v: R::V4) -> R::V4 {
        match self {
            // Tangent vectors of E3 have w = 0; p has w = 1.
            Geometry::Euclidean => v - p * R::xyzw(v)[3],
            // <p,p> = -1: the component of v along p is -<v,p> p.
            Geometry::Hyperbolic => v + p * self.form::<R>(v, p),
            Geometry::Spherical => v - p * self.form::<R>(v, p),
        }
    }

    /// Distance between two normalised points, stable for near and far
    /// points alike: `2 asinh(|p-q|/2)` (H3, Minkowski length of the
    /// difference) and `2 atan2(|p-q|, |p+q|)` (S3); no `acos`/`acosh` near 1.
    #[inline]
    #[must_use]
    pub fn distance<R: Real>(self, p: R::V4, q: R::V4) -> R {
        let d = p - q;
        match self {
            Geometry::Euclidean => self.form::<R>(d, d).sqrt(),
            Geometry::Hyperbolic => R::of(2.0) * (self.form::<R>(d, d).max(R::of(0.0)).sqrt() * R::of(0.5)).asinh(),
            Geometry::Spherical => {
                let s = p + q;
                R::of(2.0) * R::dot4(d, d).sqrt().atan2(R::dot4(s, s).sqrt())
            }
        }
    }

    /// The exponential map: from the normalised point `p` with unit tangent
    /// `v`, the point at distance `s` along the geodesic and the unit tangent
    /// there.
    #[inline]
    #[must_use]
    pub fn exp<R: Real>(self, p: R::V4, v: R::V4, s: R) -> (R::V4, R::V4) {
        match self {
            Geometry::Euclidean => (p + v * s, v),
            Geometry::Hyperbolic => {
                let (c, sh) = (s.cosh(), s.sinh());
                (p * c + v * sh, p * sh + v * c)
            }
            Geometry::Spherical => {
                let (c, sn) = (s.cos(), s.sin());
                (p * c + v * sn, v * c - p * sn)
            }
        }
    }

    /// The inverse of [`Geometry::exp`]: the unit tangent at the normalised
    /// point `p` pointing towards the normalised point `q`, and the
    /// distance from `p` to `q`, so that `exp(p, v, s) = q`. `None` when no
    /// direction is defined: `q = p`, or `q = -p` in S3 (antipodal points
    /// are joined by every great circle).
    #[inline]
    #[must_use]
    pub fn log<R: Real>(self, p: R::V4, q: R::V4) -> Option<(R::V4, R)> {
        let t = self.project_tangent::<R>(p, q);
        let n = self.form::<R>(t, t).abs().sqrt();
        // Below the rounding of the projection (about epsilon |q|^2) the
        // direction is noise: the points are equal or antipodal.
        let noise = R::of(16.0) * R::EPSILON * R::dot4(q, q);
        (n > noise && n.is_finite()).then(|| (t * (R::of(1.0) / n), self.distance::<R>(p, q)))
    }

    /// Distance `s` along a ray `o + t d` (normalised `o`, unit tangent `d`)
    /// at chart parameter `t`: `t` itself (E3), `atanh t` (H3), `atan t` (S3).
    /// The parameter is monotone in the distance, so nearest hits can be
    /// compared by `t` alone (one division per face).
    #[inline]
    #[must_use]
    pub fn chart_to_distance<R: Real>(self, t: R) -> R {
        match self {
            Geometry::Euclidean => t,
            Geometry::Hyperbolic => t.atanh(),
            Geometry::Spherical => t.atan(),
        }
    }

    /// The inverse of [`Geometry::chart_to_distance`].
    #[inline]
    #[must_use]
    pub fn distance_to_chart<R: Real>(self, s: R) -> R {
        match self {
            Geometry::Euclidean => s,
            Geometry::Hyperbolic => s.sinh() / s.cosh(),
            Geometry::Spherical => s.sin() / s.cos(),
        }
    }

    /// The largest chart parameter a ray segment may use: 1 in H3 (the
    /// sphere at infinity), and in S3 `tan 1` so segments stay well short of
    /// a quarter turn, where the gnomonic parameter blows up. The tracer
    /// splits longer spherical segments.
    #[inline]
    #[must_use]
    pub fn max_chart_parameter<R: Real>(self) -> R {
        match self {
            Geometry::Euclidean => R::of(f64::INFINITY),
            Geometry::Hyperbolic => R::of(1.0),
            Geometry::Spherical => R::of(1.0f64.tan()),
        }
    }

    /// Area of the sphere of radius `d` around a point: `4 pi d^2`,
    /// `4 pi sinh^2 d`, `4 pi sin^2 d`. Light falls off as its inverse.
    #[inline]
    #[must_use]
    pub fn sphere_area<R: Real>(self, d: R) -> R {
        let four_pi = R::of(4.0 * core::f64::consts::PI);
        match self {
            Geometry::Euclidean => four_pi * d * d,
            Geometry::Hyperbolic => four_pi * d.sinh() * d.sinh(),
            Geometry::Spherical => four_pi * d.sin() * d.sin(),
        }
    }

    /// The chart origin `(0, 0, 0, 1)`, a normalised point in all three.
    #[inline]
    #[must_use]
    pub fn origin<R: Real>(self) -> R::V4 {
        R::v4(R::of(0.0), R::of(0.0), R::of(0.0), R::of(1.0))
    }

    /// How far a point is from being normalised: `|w - 1|` (E3) or
    /// `|<p,p> -+ 1|` (H3, S3). Used by tests and the stability checks.
    #[must_use]
    pub fn point_error<R: Real>(self, p: R::V4) -> R {
        match self {
            Geometry::Euclidean => (R::xyzw(p)[3] - R::of(1.0)).abs(),
            Geometry::Hyperbolic => (self.form::<R>(p, p) + R::of(1.0)).abs(),
            Geometry::Spherical => (self.form::<R>(p, p) - R::of(1.0)).abs(),
        }
    }

    /// How far `v` is from a unit tangent vector at `p`: the larger of
    /// `|<v,v> - 1|` and the component along `p`.
    #[must_use]
    pub fn tangent_error<R: Real>(self, p: R::V4, v: R::V4) -> R {
        let along = match self {
            Geometry::Euclidean => R::xyzw(v)[3].abs(),
            _ => self.form::<R>(p, v).abs(),
        };
        along.max((self.form::<R>(v, v) - R::of(1.0)).abs())
    }

    /// True when `p` is a point of the model (finite, `w > 0`, and inside the
    /// Klein ball in H3).
    #[must_use]
    pub fn is_point(self, p: glam::DVec4) -> bool {
        p.is_finite()
            && p.w > 0.0
            && match self {
                Geometry::Hyperbolic => self.form::<f64>(p, p) < 0.0,
                _ => true,
            }
    }
}

impl core::fmt::Display for Geometry {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

impl core::str::FromStr for Geometry {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "euclidean" => Ok(Geometry::Euclidean),
            "hyperbolic" => Ok(Geometry::Hyperbolic),
            "spherical" => Ok(Geometry::Spherical),
            _ => Err(format!(
                "unknown geometry '{s}' (expected euclidean, hyperbolic or spherical)"
            )),
        }
    }
}
