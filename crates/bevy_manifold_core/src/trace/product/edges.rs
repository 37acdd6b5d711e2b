//! The prism's edges drawn as tubes of the product metric: the vertical
//! edge over each corner of the polygon (the whole height of the prism)
//! and each side of the polygon at the bottom and at the top.
//!
//! A tube of radius `r` about a vertical edge is where the surface
//! distance to its corner is at most `r`, a cylinder the ray enters in
//! closed form (the surface part of [`super::reach`]). About a horizontal
//! edge it is where `d(p, side)^2 + (h - height)^2 <= r^2` (`d(p, side)`
//! the surface distance to the side, a segment), entered by sphere
//! tracing on the part of the ray within `r` of that height. The gluings
//! take the prism's edges onto edges, so each copy of the prism shows its
//! share of every tube and the tubes are whole in the space.
//!
//! WGSL twin: `edge_entry` in `product.wgsl`.
//!
//! ```
//! use bevy_manifold_core::space::product::ProductSpace;
//! use bevy_manifold_core::trace::product::{ProductEdges, ProductTubes};
//! // The genus-2 octagon times a circle: 8 vertical edges, and 8 sides
//! // at the bottom and 8 at the top.
//! let space = ProductSpace::genus_two_x_s1(2.0);
//! let tubes = ProductTubes::of(&space, Some(ProductEdges::default()));
//! assert_eq!(tubes.edges.len(), 24);
//! // S2 x S1: the whole sphere has no sides, so the prism no edges.
//! assert!(ProductTubes::of(&ProductSpace::s2_x_s1(2.0), Some(ProductEdges::default())).edges.is_empty());
//! ```

use super::{MAX_STEPS, ProductRay, SURFACE, height_window, surface_window};
use crate::geometry::product::{ProductGeometry, ProductPoint};
use crate::space::product::ProductSpace;
use glam::DVec3;

/// The object id a ray reports when it meets an edge's tube.
pub const EDGE_ID: u32 = 0xffff_fffe;

/// How a view draws the prism's edges: tubes of the product metric of
/// `radius` about them, of `color`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProductEdges {
    /// The tubes' radius.
    pub radius: f64,
    /// Their colour (linear RGB).
    pub color: [f32; 3],
}

impl Default for ProductEdges {
    /// Thin dark tubes, 0.02 across.
    fn default() -> Self {
        Self {
            radius: 0.02,
            color: [0.18, 0.2, 0.24],
        }
    }
}

/// One edge of the prism.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ProductEdge {
    /// Over a corner of the polygon, the whole height of the prism.
    Vertical {
        /// The corner, a point of the surface's model.
        corner: DVec3,
    },
    /// A side of the polygon at the bottom or the top of the prism.
    Horizontal {
        /// The side's line: its unit normal (`<n, p> = 0` on it).
        normal: DVec3,
        /// The side's two corners.
        ends: [DVec3; 2],
        /// The height.
        height: f64,
    },
}

impl ProductEdge {
    /// The point of the edge nearest `p`, a point of the prism, and its
    /// distance from `p`. A side's nearest point is the foot of the
    /// perpendicular from `p`'s surface point where that falls between
    /// the corners, else the nearer corner.
    #[must_use]
    pub fn nearest(&self, g: ProductGeometry, p: ProductPoint) -> (ProductPoint, f64) {
        match *self {
            ProductEdge::Vertical { corner } => (
                ProductPoint::new(corner, p.height),
                g.surface_distance(p.surface, corner),
            ),
            ProductEdge::Horizontal {
                normal,
                ends: [a, b],
                height,
            } => {
                let q = p.surface;
                // The tangents at each corner along the side, towards the
                // other: the foot is between the corners where `q` is on
                // their inner side of both perpendiculars.
                let toward = |from: DVec3, to: DVec3| to - from * (g.curvature() * g.form(from, to));
                let between = g.form(q, toward(a, b)) >= 0.0 && g.form(q, toward(b, a)) >= 0.0;
                let foot = if between {
                    g.normalize_point(ProductPoint::new(q - normal * g.form(q, normal), height))
                        .surface
                } else if g.surface_distance(q, a) <= g.surface_distance(q, b) {
                    a
                } else {
                    b
                };
                let at = ProductPoint::new(foot, height);
                (at, g.distance(p, at))
            }
        }
    }
}

/// The prism's edges as tubes of one radius: what the tracers look for
/// besides the balls.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ProductTubes {
    /// The edges: every corner's vertical edge, then every side at the
    /// bottom and at the top.
    pub edges: Vec<ProductEdge>,
    /// The tubes' radius.
    pub radius: f64,
    /// The height of the bottom's edges.
    pub bottom: f64,
    /// The height of the top's edges.
    pub top: f64,
}

impl ProductTubes {
    /// The tubes `edges` asks for about `space`'s edges; none where it is
    /// `None` or its radius is not finite and positive.
    #[must_use]
    pub fn of(space: &ProductSpace, edges: Option<ProductEdges>) -> Self {
        let Some(radius) = Self::radius_of(space, edges) else {
            return Self::default();
        };
        let g = space.geometry;
        let corners = space.vertices();
        let n = corners.len();
        let mut out: Vec<ProductEdge> = corners.iter().map(|&corner| ProductEdge::Vertical { corner }).collect();
        for height in [-space.height / 2.0, space.height / 2.0] {
            for (i, side) in space.sides.iter().enumerate() {
                // Side i runs between the corners it shares with sides
                // i - 1 and i + 1.
                let ends = [corners[(i + n - 1) % n], corners[i]];
                let normal = *side / g.form(*side, *side).abs().sqrt();
                out.push(ProductEdge::Horizontal { normal, ends, height });
            }
        }
        Self {
            edges: out,
            radius,
            bottom: -space.height / 2.0,
            top: space.height / 2.0,
        }
    }

    /// The radius of the tubes [`ProductTubes::of`] makes: `None` where
    /// `edges` is `None`, its radius is not finite and positive, or the
    /// prism has no edges (S2 x S1, the whole sphere).
    #[must_use]
    pub fn radius_of(space: &ProductSpace, edges: Option<ProductEdges>) -> Option<f64> {
        let radius = edges.map(|e| e.radius).filter(|r| r.is_finite() && *r > 0.0)?;
        (!space.sides.is_empty()).then_some(radius)
    }

    /// The first distance in `[0, length]` at which `ray` (in the prism)
    /// enters a tube from outside, with the point of its edge nearest
    /// there (the way out of the tube's surface); `None` where it enters
    /// none. A ray that starts inside a tube enters that tube only after
    /// it has left. The vertical edges' tubes in closed form; a side's
    /// only on the part of the ray within the radius of its height, and
    /// only where the ray's surface part may come that near its line
    /// ([`line_bound`]).
    #[must_use]
    pub fn entry(&self, g: ProductGeometry, ray: &ProductRay, length: f64) -> Option<(f64, ProductPoint)> {
        let r = self.radius;
        let k = g.curvature();
        let cos_r = g.trig(r).0;
        let mut best: Option<(f64, &ProductEdge)> = None;
        let limit = |best: Option<(f64, &ProductEdge)>| best.map_or(length, |b| b.0);
        for edge in &self.edges {
            let ProductEdge::Vertical { corner } = *edge else {
                continue;
            };
            // cosh (H2) or cos (S2) of the distance to the corner: a ray
            // that starts inside the tube does not enter it.
            let c = k * g.form(ray.origin.surface, corner);
            if (k < 0.0 && c <= cos_r) || (k > 0.0 && c >= cos_r) {
                continue;
            }
            if let Some((s, _)) = surface_window(g, ray, corner, r, (0.0, limit(best))) {
                best = Some((s, edge));
            }
        }
        for height in [self.bottom, self.top] {
            let Some(window) = height_window(ray, height, r, limit(best)) else {
                continue;
            };
            let (p, bound) = line_bound(g, ray, r, window);
            for edge in &self.edges {
                let ProductEdge::Horizontal { normal, height: h, .. } = *edge else {
                    continue;
                };
                if h != height || g.form(p, normal).abs() > bound {
                    continue;
                }
                let end = window.1.min(limit(best));
                if let Some(s) = traced_entry(g, ray, edge, r, (window.0, end)) {
                    best = Some((s, edge));
                }
            }
        }
        best.map(|(s, edge)| (s, edge.nearest(g, g.exp(ray.origin, ray.dir, s).0).0))
    }
}

/// The ray's surface point at the start of `window`, and how far (as
/// `|<p, n>|`) a line `<n, p> = 0` may be from it for the ray's surface
/// part to come within `r` of it on the window: the line is `d` from `p`,
/// `sinh d = |<p, n>|` (H2; `sin d` on S2), and the ray moves
/// `speed (end - start)` over the surface. A side is no nearer than its
/// line. WGSL twin: `line_bound`.
fn line_bound(g: ProductGeometry, ray: &ProductRay, r: f64, (start, end): (f64, f64)) -> (DVec3, f64) {
    let speed = g.form(ray.dir.surface, ray.dir.surface).max(0.0).sqrt();
    let reach = r + speed * (end - start);
    let p = g.exp(ray.origin, ray.dir, start).0.surface;
    if g.curvature() > 0.0 && reach >= std::f64::consts::FRAC_PI_2 {
        return (p, f64::INFINITY);
    }
    (p, g.trig(reach).1)
}

/// The first distance in `[start, end]` (the part of the ray within `r`
/// of the edge's height) at which the ray enters the tube of radius `r`
/// about `edge` from outside, by sphere tracing (the distance to the edge
/// changes no faster than the ray moves). Where `start` is past the ray's
/// origin the ray is at least `r` from the edge there (its height alone
/// is that far), so it starts outside, on the tube where it meets it
/// there. WGSL twin: `tube_entry` in `product.wgsl`.
fn traced_entry(
    g: ProductGeometry,
    ray: &ProductRay,
    edge: &ProductEdge,
    r: f64,
    (start, end): (f64, f64),
) -> Option<f64> {
    let gap = |s: f64| edge.nearest(g, g.exp(ray.origin, ray.dir, s).0).1 - r;
    let mut s = start;
    let mut f = gap(s);
    let mut outside = f > SURFACE || start > 0.0;
    for _ in 0..MAX_STEPS {
        if outside && f <= SURFACE {
            return Some(s);
        }
        if !outside && f > SURFACE {
            outside = true;
        }
        s += f.abs().max(SURFACE);
        if s > end {
            return None;
        }
        f = gap(s);
    }
    None
}
