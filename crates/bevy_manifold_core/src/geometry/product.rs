//! The product geometries H2xR and S2xR: a surface of constant curvature
//! (the hyperbolic plane or the round sphere) times the real line.
//!
//! Unlike E3, H3 and S3 they have no chart in which every geodesic is a
//! straight line, so they do not fit the 4x4 projective model of
//! [`Geometry`](super::Geometry). They have exact geodesics all the same:
//! a geodesic is a geodesic of the surface at speed `cos a` times a line
//! of R at speed `sin a` ([`ProductGeometry::exp`]).
//!
//! - A point is a point of the surface in its linear model (the
//!   hyperboloid `x^2 + y^2 - w^2 = -1`, `w > 0`, or the unit sphere
//!   `x^2 + y^2 + w^2 = 1`; the origin is `(0, 0, 1)` in both) and a
//!   height ([`ProductPoint`]).
//! - A tangent vector is a tangent vector of the surface and a vertical
//!   speed ([`ProductTangent`]); its length is `sqrt(<v, v> + h^2)`.
//! - An isometry is an isometry of the surface (a 3x3 matrix keeping the
//!   surface's form) times a translation of R, possibly turned upside
//!   down ([`ProductIsometry`]): the whole isometry group.
//!
//! ```
//! use bevy_manifold_core::geometry::product::{ProductGeometry, ProductPoint, ProductTangent};
//! use glam::DVec3;
//! let g = ProductGeometry::H2xR;
//! // Up at 45 degrees: after distance 2, sqrt(2) along the plane and
//! // sqrt(2) up.
//! let v = ProductTangent::new(DVec3::X, 1.0).unit(g);
//! let (p, _) = g.exp(ProductPoint::ORIGIN, v, 2.0);
//! assert!((p.height - 2f64.sqrt()).abs() < 1e-12);
//! assert!((g.distance(ProductPoint::ORIGIN, p) - 2.0).abs() < 1e-12);
//! ```

use glam::{DMat3, DVec3};

/// H2xR or S2xR.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum ProductGeometry {
    /// The hyperbolic plane times the line.
    #[serde(rename = "h2xr")]
    H2xR,
    /// The round sphere (curvature 1) times the line.
    #[serde(rename = "s2xr")]
    S2xR,
}

/// A point: a point of the surface's model and a height.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProductPoint {
    /// On the hyperboloid (H2) or the unit sphere (S2).
    pub surface: DVec3,
    /// Along the line.
    pub height: f64,
}

/// A tangent vector: along the surface and up the line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProductTangent {
    /// Tangent to the surface at the point (`<p, v> = 0`).
    pub surface: DVec3,
    /// The vertical speed.
    pub height: f64,
}

/// An isometry: `(p, h) -> (m p, flip h + shift)`, with `m` an isometry of
/// the surface's model and `flip` 1 or -1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProductIsometry {
    /// The surface part: keeps the surface's form.
    pub surface: DMat3,
    /// 1, or -1 where the line is turned upside down.
    pub flip: f64,
    /// The translation of the line, after the flip.
    pub shift: f64,
}

impl ProductPoint {
    /// The origin: the surface's `(0, 0, 1)` at height 0.
    pub const ORIGIN: Self = Self {
        surface: DVec3::Z,
        height: 0.0,
    };

    /// A point from its parts.
    #[must_use]
    pub const fn new(surface: DVec3, height: f64) -> Self {
        Self { surface, height }
    }
}

impl ProductTangent {
    /// A tangent from its parts.
    #[must_use]
    pub const fn new(surface: DVec3, height: f64) -> Self {
        Self { surface, height }
    }

    /// Its length in the product metric.
    #[must_use]
    pub fn length(self, g: ProductGeometry) -> f64 {
        (g.form(self.surface, self.surface).max(0.0) + self.height * self.height).sqrt()
    }

    /// Scaled to unit length.
    #[must_use]
    pub fn unit(self, g: ProductGeometry) -> Self {
        let n = self.length(g);
        Self::new(self.surface / n, self.height / n)
    }
}

impl ProductGeometry {
    /// The surface's curvature: -1 (H2) or +1 (S2).
    #[must_use]
    pub const fn curvature(self) -> f64 {
        match self {
            ProductGeometry::H2xR => -1.0,
            ProductGeometry::S2xR => 1.0,
        }
    }

    /// Lower-case name as used in files and on the command line.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            ProductGeometry::H2xR => "h2xr",
            ProductGeometry::S2xR => "s2xr",
        }
    }

    /// The surface's form `<u, v> = ux vx + uy vy + k uw vw`, `k` the
    /// curvature. Points of the surface have `<p, p> = k`.
    #[must_use]
    pub fn form(self, u: DVec3, v: DVec3) -> f64 {
        u.x * v.x + u.y * v.y + self.curvature() * u.z * v.z
    }

    /// The surface's cosine-like and sine-like functions of arc length:
    /// `(cosh s, sinh s)` on H2, `(cos s, sin s)` on S2.
    #[must_use]
    pub fn trig(self, s: f64) -> (f64, f64) {
        match self {
            ProductGeometry::H2xR => (s.cosh(), s.sinh()),
            ProductGeometry::S2xR => (s.cos(), s.sin()),
        }
    }

    /// The distance between two points of the surface, stable for near and
    /// far points alike (no `acosh` or `acos` near 1).
    #[must_use]
    pub fn surface_distance(self, p: DVec3, q: DVec3) -> f64 {
        let d = p - q;
        match self {
            ProductGeometry::H2xR => 2.0 * (self.form(d, d).max(0.0).sqrt() * 0.5).asinh(),
            ProductGeometry::S2xR => 2.0 * d.length().atan2((p + q).length()),
        }
    }

    /// The distance between two points: `sqrt(d_surface^2 + dh^2)`.
    #[must_use]
    pub fn distance(self, p: ProductPoint, q: ProductPoint) -> f64 {
        self.surface_distance(p.surface, q.surface).hypot(p.height - q.height)
    }

    /// The geodesic flow: from `p` with unit tangent `v`, the point at
    /// distance `s` and the tangent there. The surface part runs along its
    /// geodesic at speed `|v.surface|`, the height at speed `v.height`.
    #[must_use]
    pub fn exp(self, p: ProductPoint, v: ProductTangent, s: f64) -> (ProductPoint, ProductTangent) {
        let speed = self.form(v.surface, v.surface).max(0.0).sqrt();
        let height = p.height + v.height * s;
        if speed == 0.0 {
            return (ProductPoint::new(p.surface, height), v);
        }
        let u = v.surface / speed;
        let (c, sn) = self.trig(speed * s);
        let k = self.curvature();
        let surface = p.surface * c + u * sn;
        let along = (u * c - p.surface * (k * sn)) * speed;
        (ProductPoint::new(surface, height), ProductTangent::new(along, v.height))
    }

    /// The inverse of [`ProductGeometry::exp`]: the unit tangent at `p`
    /// towards `q` and the distance, or `None` for `q = p` (and for
    /// antipodal points of the sphere at the same height, joined by every
    /// great circle).
    #[must_use]
    pub fn log(self, p: ProductPoint, q: ProductPoint) -> Option<(ProductTangent, f64)> {
        let dh = q.height - p.height;
        let ds = self.surface_distance(p.surface, q.surface);
        let k = self.curvature();
        // q's component tangent to the surface at p, towards q.
        let t = q.surface - p.surface * (self.form(q.surface, p.surface) * k);
        let n = self.form(t, t).max(0.0).sqrt();
        let surface = if n > 1e-300 && ds > 0.0 {
            t * (ds / n)
        } else {
            DVec3::ZERO
        };
        if ds > 0.0 && surface == DVec3::ZERO {
            return None;
        }
        let v = ProductTangent::new(surface, dh);
        let d = v.length(self);
        (d > 0.0).then(|| (ProductTangent::new(v.surface / d, v.height / d), d))
    }

    /// Area of the geodesic sphere of radius `d` (light falls off as its
    /// inverse). In polar coordinates about a point the sphere's area
    /// element is `d * S(d cos a) da dtheta`, `S` the surface's sine
    /// (sinh on H2, sin on S2), so the area is `2 pi d` times the integral
    /// of `|S(d cos a)|` over `a` in `[-pi/2, pi/2]`; there is no
    /// elementary closed form (on H2 it is a modified Struve function), so
    /// it is integrated here by Simpson's rule on 64 intervals (relative
    /// error below 1e-9 for `d` up to 20). On S2 the absolute value counts
    /// a sphere that has wrapped past the antipode once more.
    #[must_use]
    pub fn sphere_area(self, d: f64) -> f64 {
        let n = 64;
        let h = std::f64::consts::PI / f64::from(n);
        let f = |a: f64| self.trig(d * a.cos()).1.abs();
        let mut sum = f(-std::f64::consts::FRAC_PI_2) + f(std::f64::consts::FRAC_PI_2);
        for i in 1..n {
            let a = -std::f64::consts::FRAC_PI_2 + h * f64::from(i);
            sum += f(a) * if i % 2 == 1 { 4.0 } else { 2.0 };
        }
        2.0 * std::f64::consts::PI * d * sum * h / 3.0
    }

    /// The product metric on tangents: `<u, v>` of the surface parts
    /// plus the product of the vertical speeds.
    #[must_use]
    pub fn dot(self, u: ProductTangent, v: ProductTangent) -> f64 {
        self.form(u.surface, v.surface) + u.height * v.height
    }

    /// The area a point light's power spreads over at distance `d` along
    /// a geodesic whose surface part is `surface` long (the fall-off of
    /// its irradiance is the inverse): `4 pi d^2 S(surface) / surface`,
    /// `S` the surface's sine (`sinh` on H2, `|sin|` on S2), and
    /// `4 pi d^2` for a vertical geodesic. This is exact and local: in
    /// polar coordinates the geodesic sphere's area element in that
    /// direction is `d S(d cos a) da dtheta` against the unit sphere's
    /// `cos a da dtheta` (`surface = d cos a`), so a light's rays spread
    /// by their ratio `d^2 S(surface) / surface`; its mean over the
    /// directions is [`ProductGeometry::sphere_area`] over `4 pi`. On S2
    /// it vanishes where the rays refocus (`surface` a multiple of `pi`):
    /// a caustic, which the lights cap by their size.
    #[must_use]
    pub fn light_area(self, d: f64, surface: f64) -> f64 {
        let spread = if surface.abs() < 1e-9 {
            1.0
        } else {
            self.trig(surface).1.abs() / surface.abs()
        };
        4.0 * std::f64::consts::PI * d * d * spread
    }

    /// How far `p` is from the surface's model (`|<p, p> - k|`).
    #[must_use]
    pub fn point_error(self, p: ProductPoint) -> f64 {
        (self.form(p.surface, p.surface) - self.curvature()).abs()
    }

    /// `p` put back on the surface's model (its height kept).
    #[must_use]
    pub fn normalize_point(self, p: ProductPoint) -> ProductPoint {
        let n = (self.form(p.surface, p.surface) * self.curvature()).abs().sqrt();
        ProductPoint::new(p.surface / n, p.height)
    }

    /// `v` made tangent at `p` (its component along `p` removed) and of
    /// unit length.
    #[must_use]
    pub fn normalize_tangent(self, p: ProductPoint, v: ProductTangent) -> ProductTangent {
        let k = self.curvature();
        let surface = v.surface - p.surface * (self.form(v.surface, p.surface) * k);
        ProductTangent::new(surface, v.height).unit(self)
    }

    /// How far `m` is from keeping the surface's form: the largest entry
    /// of `m^T J m - J`, `J = diag(1, 1, k)`.
    #[must_use]
    pub fn isometry_error(self, m: DMat3) -> f64 {
        let j = DMat3::from_diagonal(DVec3::new(1.0, 1.0, self.curvature()));
        let e = m.transpose() * j * m - j;
        [e.x_axis, e.y_axis, e.z_axis]
            .iter()
            .map(|c| c.abs().max_element())
            .fold(0.0, f64::max)
    }

    /// The rotation of the surface by `angle` about the origin.
    #[must_use]
    pub fn rotation(self, angle: f64) -> DMat3 {
        DMat3::from_rotation_z(angle)
    }

    /// The translation of the surface by `d` along the geodesic through
    /// the origin in direction `angle` (from the x axis towards y).
    #[must_use]
    pub fn translation(self, angle: f64, d: f64) -> DMat3 {
        let (c, s) = self.trig(d);
        let k = self.curvature();
        // Along x: (1,0,0) -> (c, 0, -k s), (0,0,1) -> (s, 0, c).
        let along_x = DMat3::from_cols(DVec3::new(c, 0.0, -k * s), DVec3::Y, DVec3::new(s, 0.0, c));
        self.rotation(angle) * along_x * self.rotation(-angle)
    }

    /// The reflection of the surface in the geodesic `<n, p> = 0` (`n` a
    /// unit normal covector, `<n, n> = 1`): `p -> p - 2 <n, p> n`.
    #[must_use]
    pub fn reflection(self, n: DVec3) -> DMat3 {
        let jn = DVec3::new(n.x, n.y, self.curvature() * n.z);
        DMat3::IDENTITY - DMat3::from_cols(jn * n.x, jn * n.y, jn * n.z).transpose() * 2.0
    }
}

impl ProductIsometry {
    /// The identity.
    pub const IDENTITY: Self = Self {
        surface: DMat3::IDENTITY,
        flip: 1.0,
        shift: 0.0,
    };

    /// An isometry from its parts.
    #[must_use]
    pub const fn new(surface: DMat3, flip: f64, shift: f64) -> Self {
        Self { surface, flip, shift }
    }

    /// A translation of the line by `shift`.
    #[must_use]
    pub const fn vertical(shift: f64) -> Self {
        Self::new(DMat3::IDENTITY, 1.0, shift)
    }

    /// The image of a point.
    #[must_use]
    pub fn apply(&self, p: ProductPoint) -> ProductPoint {
        ProductPoint::new(self.surface * p.surface, self.flip * p.height + self.shift)
    }

    /// The image of a tangent vector.
    #[must_use]
    pub fn apply_tangent(&self, v: ProductTangent) -> ProductTangent {
        ProductTangent::new(self.surface * v.surface, self.flip * v.height)
    }

    /// `self` after `other` (`other` applied first).
    #[must_use]
    pub fn compose(&self, other: &Self) -> Self {
        Self::new(
            self.surface * other.surface,
            self.flip * other.flip,
            self.flip * other.shift + self.shift,
        )
    }

    /// The inverse. The surface part is inverted by its form,
    /// `J m^T J`, exact for an isometry.
    #[must_use]
    pub fn inverse(&self, g: ProductGeometry) -> Self {
        let j = DMat3::from_diagonal(DVec3::new(1.0, 1.0, g.curvature()));
        Self::new(j * self.surface.transpose() * j, self.flip, -self.flip * self.shift)
    }
}
