//! Triangle meshes in the product spaces (H2xR, S2xR).
//!
//! These spaces have no chart in which every geodesic is straight, so a
//! mesh cannot be made of totally geodesic triangles as in E3, H3 and S3
//! ([`crate::mesh`]). A mesh here is drawn in its object's *chart*: the
//! Klein model of H2 (the gnomonic projection of S2) times the height,
//! [`chart_point`]. Its triangles are flat in that chart, so every
//! vertical wall over a geodesic of the surface and every level floor is
//! exact, and a mesh of glTF metres is a shape of the space of about
//! that size (the chart is the identity to first order at the object's
//! centre).
//!
//! A ray in the chart is a curve: its surface part runs along a straight
//! line of the Klein (gnomonic) plane, `K0 + lambda D`, with `lambda =
//! S(t) / X_w(t)` increasing along the ray (`t` the surface arc length,
//! `S` the surface's sine, `X_w` the point's last coordinate), and its
//! height is linear in arc length. So the curve meets a box of the BVH
//! where its height is in the box's slab (an interval of the ray) and its
//! `lambda` in the box's slabs across (an interval of `lambda`): the
//! box test is exact. A triangle is met where the plane's function along
//! the ray changes sign within the part of the ray in the triangle's box,
//! found by Newton's method kept in the bracket; a ray that touches a
//! triangle's plane twice within that small part without crossing it
//! (a graze) counts as a miss.
//!
//! WGSL twins: `mesh_entry`, `chart_box` and `chart_normal` in
//! `bevy_manifold_gpu`'s `shaders/product.wgsl`.
//!
//! ```
//! use bevy_manifold_core::geometry::product::{ProductGeometry, ProductIsometry, ProductPoint, ProductTangent};
//! use bevy_manifold_core::mesh::{MeshData, TriMesh};
//! use bevy_manifold_core::space::product::ProductSpace;
//! use bevy_manifold_core::trace::product::{ProductMesh, ProductObjects, ProductRay, ProductScene, hits_in};
//! use glam::DVec3;
//! // A wall at chart x = 0.5 (the geodesic at distance atanh 0.5 from the
//! // origin), from y = -0.3 to 0.3 and height -0.3 to 0.3.
//! let wall = TriMesh::new(
//!     vec![[0.5, -0.3, -0.3], [0.5, 0.3, -0.3], [0.5, 0.3, 0.3], [0.5, -0.3, 0.3]],
//!     None,
//!     None,
//!     vec![[0, 1, 2], [0, 2, 3]],
//! )
//! .unwrap();
//! let space = ProductSpace::genus_two_x_s1(2.0);
//! let mesh = ProductMesh { mesh: MeshData::shared(wall), placement: ProductIsometry::IDENTITY, id: 7 };
//! let objects = ProductObjects::new(&space, &[], None, &[mesh]);
//! // Along x from the origin, 20 degrees up: the wall is met where the
//! // surface part has gone atanh 0.5.
//! let a = 20f64.to_radians();
//! let ray = ProductRay { origin: ProductPoint::ORIGIN, dir: ProductTangent::new(DVec3::X * a.cos(), a.sin()) };
//! let hit = &hits_in(&space, &objects, ray, 5.0, 8)[0];
//! assert_eq!(hit.object, 7);
//! assert!((hit.distance - 0.5f64.atanh() / a.cos()).abs() < 1e-9);
//! ```

use super::{ProductRay, advance, height_window, image_isometries, surface_window};
use crate::geometry::product::{ProductGeometry, ProductIsometry, ProductPoint, ProductTangent};
use crate::mesh::{BvhNode, MeshData, TriMesh};
use crate::space::product::ProductSpace;
use glam::{DVec2, DVec3};
use std::sync::Arc;

/// A mesh placed in a product space: its triangles in its own chart
/// ([`chart_point`]), and the isometry taking that chart's origin and
/// frame to where it stands in the prism.
#[derive(Clone, Debug, PartialEq)]
pub struct ProductMesh {
    /// The triangles and their BVH, shared by every instance.
    pub mesh: Arc<MeshData>,
    /// Where it stands: object space to the prism.
    pub placement: ProductIsometry,
    /// The object id a hit reports (its colour: [`super::palette`]).
    pub id: u32,
}

/// Why a mesh cannot stand in a product space.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ProductMeshError {
    /// In H2xR the chart is the Klein disc: every vertex needs `x^2 + y^2 < 1`.
    #[error("vertex {vertex} lies outside the Klein disc (x^2 + y^2 = {rho2} >= 1) of H2xR's chart")]
    OutsideChart {
        /// The vertex.
        vertex: usize,
        /// Its `x^2 + y^2`.
        rho2: f64,
    },
    /// The placement has a non-finite entry, or is not an isometry.
    #[error("the placement is not an isometry of the space (error {0:e})")]
    Placement(f64),
}

/// Most a chart's `x^2 + y^2` may be in H2xR (the Klein disc, with room
/// for rounding: the surface distance 3.8 from the centre).
pub const MAX_CHART_RHO2: f64 = 0.999;

impl ProductMesh {
    /// Whether the mesh can stand in `g`: in H2xR its vertices in the
    /// Klein disc ([`MAX_CHART_RHO2`]), and its placement an isometry.
    ///
    /// # Errors
    /// [`ProductMeshError`] naming the vertex or the placement.
    pub fn check(&self, g: ProductGeometry) -> Result<(), ProductMeshError> {
        let error = g.isometry_error(self.placement.surface);
        let finite =
            self.placement.surface.is_finite() && self.placement.shift.is_finite() && self.placement.flip.abs() == 1.0;
        if error.is_nan() || error >= 1e-6 || !finite {
            return Err(ProductMeshError::Placement(error));
        }
        if g == ProductGeometry::H2xR {
            for (vertex, p) in self.mesh.mesh.positions.iter().enumerate() {
                let rho2 = f64::from(p[0]).powi(2) + f64::from(p[1]).powi(2);
                if rho2.is_nan() || rho2 >= MAX_CHART_RHO2 {
                    return Err(ProductMeshError::OutsideChart { vertex, rho2 });
                }
            }
        }
        Ok(())
    }

    /// How far the mesh reaches from its chart's origin: the surface
    /// distance of its root box's farthest corner across, and its
    /// farthest height (a bound: both grow with the chart's
    /// coordinates). Its bounding ball's radius is their `hypot`.
    #[must_use]
    pub fn extent(&self, g: ProductGeometry) -> (f64, f64) {
        let Some(root) = self.mesh.nodes.first() else {
            return (0.0, 0.0);
        };
        let far = |a: f32, b: f32| f64::from(a.abs().max(b.abs()));
        let rho = far(root.min[0], root.max[0]).hypot(far(root.min[1], root.max[1]));
        let across = match g {
            ProductGeometry::H2xR => rho.min(MAX_CHART_RHO2.sqrt()).atanh(),
            ProductGeometry::S2xR => rho.atan(),
        };
        (across + 1e-9, far(root.min[2], root.max[2]) + 1e-9)
    }
}

/// `mesh` (made y up, as Bevy's and glTF's are: `x` right, `y` up, `z`
/// back) turned into the product chart's axes (`z` up: `(x, y, z) -> (x,
/// -z, y)`, a rotation) and scaled by `scale`.
#[must_use]
pub fn z_up(mesh: &TriMesh, scale: f32) -> TriMesh {
    let turn = |p: [f32; 3]| [p[0], -p[2], p[1]];
    TriMesh {
        positions: mesh.positions.iter().map(|p| turn(*p).map(|c| c * scale)).collect(),
        normals: mesh.normals.iter().map(|n| turn(*n)).collect(),
        ..mesh.clone()
    }
}

/// The point of the space at chart coordinates `q` (`x, y` the Klein or
/// gnomonic coordinates of the surface, `z` the height).
#[must_use]
pub fn chart_point(g: ProductGeometry, q: DVec3) -> ProductPoint {
    let w = 1.0 / (1.0 + g.curvature() * (q.x * q.x + q.y * q.y)).sqrt();
    ProductPoint::new(DVec3::new(q.x * w, q.y * w, w), q.z)
}

/// The chart coordinates of `p` (on the chart's side of the surface:
/// `w > 0`).
#[must_use]
pub fn chart_of(p: ProductPoint) -> DVec3 {
    DVec3::new(p.surface.x / p.surface.z, p.surface.y / p.surface.z, p.height)
}

/// The unit tangent at the chart point `q` normal to the chart's plane
/// whose normal (a covector, as a plane's `n . q = c`) is `n`: the
/// metric's gradient of `n . q`, `J G^-1 n`. In the chart the surface's
/// metric is `G = w^2 (I - k w^2 p p^T)` (`p = (x, y)`, `w^-2 = 1 + k
/// |p|^2`, `k` the curvature), whose inverse is `(I + k p p^T) / w^2`,
/// and `J` the chart's Jacobian. WGSL twin: `chart_normal`.
#[must_use]
pub fn chart_normal(g: ProductGeometry, q: DVec3, n: DVec3) -> ProductTangent {
    let k = g.curvature();
    let p = DVec2::new(q.x, q.y);
    let w2 = 1.0 / (1.0 + k * p.length_squared());
    let w = w2.sqrt();
    let m = (n.truncate() + p * (k * p.dot(n.truncate()))) / w2;
    // J m: w m + (x, y, 1) dw, dw = -k w^3 (p . m).
    let dw = -k * w * w2 * p.dot(m);
    let surface = DVec3::new(w * m.x + q.x * dw, w * m.y + q.y * dw, dw);
    ProductTangent::new(surface, n.z).unit(g)
}

/// A mesh as a copy of the prism sees it: the mesh, the isometry taking
/// its chart into the prism (its placement, or that through gluings:
/// [`mesh_images`]) and the inverse, and its bounding ball there.
#[derive(Clone, Debug, PartialEq)]
pub struct ProductMeshImage {
    /// The triangles.
    pub mesh: Arc<MeshData>,
    /// Its chart to the prism.
    pub placement: ProductIsometry,
    /// The prism to its chart.
    pub to_chart: ProductIsometry,
    /// Its chart's origin in the prism.
    pub center: ProductPoint,
    /// [`ProductMesh::extent`].
    pub extent: (f64, f64),
    /// The object id.
    pub id: u32,
}

/// Each mesh, then every image of it that may reach into the prism (as
/// [`super::images`] finds a ball's, of its bounding ball). A mesh that
/// cannot stand in the space ([`ProductMesh::check`]) is left out.
#[must_use]
pub fn mesh_images(space: &ProductSpace, meshes: &[ProductMesh]) -> Vec<ProductMeshImage> {
    let g = space.geometry;
    let mut out = Vec::new();
    for mesh in meshes.iter().filter(|m| m.check(g).is_ok()) {
        let center = g.normalize_point(mesh.placement.apply(ProductPoint::ORIGIN));
        let extent = mesh.extent(g);
        for m in image_isometries(space, center, extent.0.hypot(extent.1)) {
            let placement = m.compose(&mesh.placement);
            out.push(ProductMeshImage {
                mesh: mesh.mesh.clone(),
                placement,
                to_chart: placement.inverse(g),
                center: g.normalize_point(placement.apply(ProductPoint::ORIGIN)),
                extent,
                id: mesh.id,
            });
        }
    }
    out
}

/// Where a ray entered a mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshEntry {
    /// The distance along the ray.
    pub s: f64,
    /// The triangle (in the mesh's BVH order).
    pub triangle: u32,
    /// Barycentric weight of the triangle's second vertex.
    pub u: f64,
    /// Barycentric weight of its third vertex.
    pub v: f64,
    /// The unit normal there, in the prism, facing the ray.
    pub normal: ProductTangent,
}

/// A ray's curve in a mesh's chart: its surface part `K0 + lambda(s) D`,
/// its height `h0 + v s`. WGSL twin: `ChartRay`.
struct ChartRay {
    g: ProductGeometry,
    /// The ray's surface point and unit surface direction, in the chart's frame.
    p: DVec3,
    u: DVec3,
    /// The surface speed.
    speed: f64,
    k0: DVec2,
    d: DVec2,
    h0: f64,
    v: f64,
}

impl ChartRay {
    fn new(g: ProductGeometry, ray: &ProductRay) -> Self {
        let p = ray.origin.surface;
        let speed = g.form(ray.dir.surface, ray.dir.surface).max(0.0).sqrt();
        let u = if speed > 0.0 {
            ray.dir.surface / speed
        } else {
            DVec3::ZERO
        };
        let k0 = DVec2::new(p.x, p.y) / p.z;
        Self {
            g,
            p,
            u,
            speed,
            k0,
            d: DVec2::new(u.x, u.y) - k0 * u.z,
            h0: ray.origin.height,
            v: ray.dir.height,
        }
    }

    /// `tanh` (H2) or `tan` (S2) of the surface arc length at `s`:
    /// `lambda = S / X_w = tau / (P_w + U_w tau)`, one transcendental
    /// (`tan`'s pole is no trouble: `lambda` is `1 / U_w` there).
    fn tau(&self, s: f64) -> f64 {
        match self.g {
            ProductGeometry::H2xR => (self.speed * s).tanh(),
            ProductGeometry::S2xR => (self.speed * s).tan(),
        }
    }

    /// `lambda(s) = S(t) / X_w(t)`, `t` the surface arc length.
    fn lambda(&self, s: f64) -> f64 {
        let tau = self.tau(s);
        tau / (self.p.z + self.u.z * tau)
    }

    /// The derivative along the ray of `n . q(s)`: `lambda' = speed P_w
    /// / X_w^2 = speed P_w (1 + k tau^2) / (P_w + U_w tau)^2`.
    fn slope(&self, s: f64, n: DVec3) -> f64 {
        let tau = self.tau(s);
        let w = self.p.z + self.u.z * tau;
        n.truncate().dot(self.d) * self.speed * self.p.z * (1.0 + self.g.curvature() * tau * tau) / (w * w)
            + n.z * self.v
    }

    /// The chart point at `s`.
    fn at(&self, s: f64) -> DVec3 {
        let xy = self.k0 + self.d * self.lambda(s);
        DVec3::new(xy.x, xy.y, self.h0 + self.v * s)
    }

    /// The arc length at which `lambda` is reached (the inverse of
    /// [`ChartRay::lambda`], where the ray moves across).
    fn s_of(&self, lambda: f64) -> f64 {
        let (y, x) = (lambda * self.p.z, 1.0 - lambda * self.u.z);
        let t = match self.g {
            ProductGeometry::H2xR => (y / x).atanh(),
            ProductGeometry::S2xR => y.atan2(x),
        };
        t / self.speed
    }

    /// The part of `[lo, hi]` in which the curve is in the box: its
    /// height in the box's height slab, then its `lambda` in the slabs
    /// across (an exact test: `lambda` increases along the ray). WGSL
    /// twin: `chart_box`.
    fn in_box(&self, (min, max): (DVec3, DVec3), (lo, hi): (f64, f64)) -> Option<(f64, f64)> {
        let (mut lo, mut hi) = (lo, hi);
        if self.v == 0.0 {
            if self.h0 < min.z || self.h0 > max.z {
                return None;
            }
        } else {
            let (e, f) = ((min.z - self.h0) / self.v, (max.z - self.h0) / self.v);
            lo = lo.max(e.min(f));
            hi = hi.min(e.max(f));
        }
        if lo > hi {
            return None;
        }
        if self.speed == 0.0 {
            let inside = (0..2).all(|i| self.k0[i] >= min[i] && self.k0[i] <= max[i]);
            return inside.then_some((lo, hi));
        }
        let (l0, l1) = (self.lambda(lo), self.lambda(hi));
        let (mut a, mut b) = (l0, l1);
        for i in 0..2 {
            if self.d[i] == 0.0 {
                if self.k0[i] < min[i] || self.k0[i] > max[i] {
                    return None;
                }
                continue;
            }
            let (e, f) = ((min[i] - self.k0[i]) / self.d[i], (max[i] - self.k0[i]) / self.d[i]);
            a = a.max(e.min(f));
            b = b.min(e.max(f));
        }
        if a > b {
            return None;
        }
        if a > l0 {
            lo = self.s_of(a).max(lo);
        }
        if b < l1 {
            hi = self.s_of(b).min(hi);
        }
        (lo <= hi).then_some((lo, hi))
    }
}

/// How near the plane Newton's method stops (chart units).
const ON_PLANE: f64 = 1e-13;
/// How much a triangle's box is padded (chart units).
const BOX_PAD: f64 = 1e-9;
/// Most Newton (or bisection) steps per triangle.
const MAX_ROOT_STEPS: usize = 64;
/// How far outside a triangle a hit on its plane still counts (its
/// barycentric weights' rounding, so a ray down a shared edge meets one).
const EDGE_SLACK: f64 = 1e-9;

fn corner(p: [f32; 3]) -> DVec3 {
    DVec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]))
}

fn node_box(node: &BvhNode) -> (DVec3, DVec3) {
    (corner(node.min), corner(node.max))
}

impl ProductMeshImage {
    /// The first entry of `ray` (in the prism) into the mesh within
    /// `[0, length]`: for each stretch of the ray within its bounding
    /// ball, the ray taken into the mesh's chart and the BVH walked by
    /// its skip links with the exact box test, nearest triangle kept.
    #[must_use]
    pub fn entry(&self, g: ProductGeometry, ray: &ProductRay, length: f64) -> Option<MeshEntry> {
        let mut from = 0.0;
        while let Some((lo, hi)) = window(g, ray, self.center, self.extent, (from, length)) {
            let start = advance(g, ray, lo);
            let local = ProductRay {
                origin: g.normalize_point(self.to_chart.apply(start.origin)),
                dir: self.to_chart.apply_tangent(start.dir),
            };
            if let Some(mut hit) = self.first_triangle(g, &local, hi - lo) {
                hit.s += lo;
                hit.normal = self.placement.apply_tangent(hit.normal);
                return Some(hit);
            }
            from = hi.max(from) + 1e-12;
        }
        None
    }

    /// The nearest triangle the chart ray `local` meets within
    /// `[0, length]` (its normal in the chart's frame).
    fn first_triangle(&self, g: ProductGeometry, local: &ProductRay, length: f64) -> Option<MeshEntry> {
        let curve = ChartRay::new(g, local);
        let data = &self.mesh;
        let mut best: Option<(f64, u32, f64, f64)> = None;
        let mut i = 0;
        while let Some(node) = data.nodes.get(i) {
            let limit = best.map_or(length, |b| b.0);
            let met = curve.in_box(node_box(node), (0.0, limit)).is_some();
            if met && node.count > 0 {
                for t in node.first..node.first + node.count {
                    let tri = data.mesh.triangles[t as usize].map(|v| corner(data.mesh.positions[v as usize]));
                    let limit = best.map_or(length, |b| b.0);
                    if let Some((s, u, v)) = cross_triangle(&curve, tri, limit) {
                        best = Some((s, t, u, v));
                    }
                }
            }
            i = if met || node.count > 0 {
                i + 1
            } else {
                (data.skip[i] as usize).max(i + 1)
            };
        }
        let (s, triangle, u, v) = best?;
        let q = curve.at(s);
        let normals = &data.mesh.normals;
        let [a, b, c] = data.mesh.triangles[triangle as usize];
        let n = if normals.len() == data.mesh.positions.len() {
            let [na, nb, nc] = [a, b, c].map(|k| corner(normals[k as usize]));
            na * (1.0 - u - v) + nb * u + nc * v
        } else {
            let [pa, pb, pc] = [a, b, c].map(|k| corner(data.mesh.positions[k as usize]));
            (pb - pa).cross(pc - pa)
        };
        let normal = chart_normal(g, q, n);
        let dir = advance(g, local, s).dir;
        let normal = if g.dot(normal, dir) > 0.0 {
            ProductTangent::new(-normal.surface, -normal.height)
        } else {
            normal
        };
        Some(MeshEntry {
            s,
            triangle,
            u,
            v,
            normal,
        })
    }
}

/// Where the curve crosses the triangle `[a, b, c]` (chart points) within
/// `[0, limit]`: the plane's function `n . q(s) - n . a` changes sign on
/// the part of the curve in the triangle's box, its root found by Newton's
/// method kept in that bracket, and the root's barycentric weights
/// `(u, v)` (of `b` and `c`) checked. WGSL twin: `cross_triangle`.
fn cross_triangle(curve: &ChartRay, [a, b, c]: [DVec3; 3], limit: f64) -> Option<(f64, f64, f64)> {
    let (e1, e2) = (b - a, c - a);
    let n = e1.cross(e2);
    let scale = n.length();
    if scale.is_nan() || scale <= 0.0 {
        return None;
    }
    let n = n / scale;
    // The triangle's box, padded: a face flat across an axis has a flat
    // box, in which the plane's function has no room to change sign.
    let pad = DVec3::splat(BOX_PAD);
    let (lo, hi) = curve.in_box((a.min(b).min(c) - pad, a.max(b).max(c) + pad), (0.0, limit))?;
    let f = |s: f64| n.dot(curve.at(s) - a);
    let (mut lo, mut hi) = (lo, hi);
    let (f_lo, f_hi) = (f(lo), f(hi));
    if f_lo == 0.0 {
        hi = lo;
    } else if f_lo * f_hi > 0.0 {
        return None;
    }
    let rising = f_lo < 0.0;
    let mut s = lo;
    for _ in 0..MAX_ROOT_STEPS {
        if hi - lo <= 1e-15 * hi.abs().max(1.0) {
            break;
        }
        let value = f(s);
        if value.abs() < ON_PLANE {
            break;
        }
        if (value < 0.0) == rising {
            lo = s;
        } else {
            hi = s;
        }
        // Newton's step, bisection where it leaves the bracket.
        let next = s - value / curve.slope(s, n);
        s = if next > lo && next < hi { next } else { 0.5 * (lo + hi) };
    }
    let q = curve.at(s) - a;
    let (d00, d01, d11) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let (d20, d21) = (q.dot(e1), q.dot(e2));
    let denom = d00 * d11 - d01 * d01;
    let u = (d11 * d20 - d01 * d21) / denom;
    let v = (d00 * d21 - d01 * d20) / denom;
    (u >= -EDGE_SLACK && v >= -EDGE_SLACK && u + v <= 1.0 + EDGE_SLACK).then_some((s, u, v))
}

/// The next stretch of `[from, length]` of the ray whose height is within
/// `tall` of `center`'s and whose surface point is within `across` of
/// its (the mesh's bounding cylinder, as [`super::reach`]), one at a time: on
/// S2 a ray comes back within reach every turn round the sphere, and
/// each stretch must stay on the chart's side of it.
fn window(
    g: ProductGeometry,
    ray: &ProductRay,
    center: ProductPoint,
    (across, tall): (f64, f64),
    (from, length): (f64, f64),
) -> Option<(f64, f64)> {
    let (lo, hi) = height_window(ray, center.height, tall, length)?;
    let (lo, hi) = surface_window(g, ray, center.surface, across, (lo.max(from), hi))?;
    let speed = g.form(ray.dir.surface, ray.dir.surface).max(0.0).sqrt();
    if g == ProductGeometry::S2xR && speed > 0.0 {
        // This turn's stretch alone (at most 2 across of surface arc).
        return surface_window(g, ray, center.surface, across, (lo, hi.min(lo + 2.0 * across / speed)));
    }
    Some((lo, hi))
}
