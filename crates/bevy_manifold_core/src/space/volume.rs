//! Volume of a convex polyhedron that contains the chart origin, in any of
//! the three geometries, by cones from the origin.
//!
//! Each face is flat in the chart; the cone from the origin over a small
//! patch `dA` of it at chart point `x` subtends the solid angle
//! `h dA / |x|^3` (`h` the chart distance of the face plane) and contains
//! the volume `F(R) dOmega`, with `R` the true distance from the origin to
//! `x` and `F(R)` the integral of the sphere-area density up to `R`:
//! `R^3/3` (E3), `(sinh 2R - 2R)/4` (H3), `(2R - sin 2R)/4` (S3). The face
//! integral is done by Gauss-Legendre quadrature on subdivided triangles;
//! the integrand is analytic on the face, so this converges fast (checked
//! against the exact volumes of the catalog spaces in the tests).

use crate::geometry::Geometry;
use glam::{DVec3, DVec4};

/// Area of the boundary of the polyhedron whose face `f` has the
/// vertices `face_vertices[f]` (cyclic, normalised points) among
/// `vertices`: each face a geodesic polygon, of area `(n - 2) pi - sum
/// of its angles` in H3, `sum - (n - 2) pi` in S3 (Gauss-Bonnet), its
/// fan of triangles in E3.
#[must_use]
pub fn polyhedron_area(g: Geometry, vertices: &[DVec4], face_vertices: &[Vec<usize>]) -> f64 {
    let mut total = 0.0;
    for ring in face_vertices {
        let n = ring.len();
        if n < 3 {
            continue;
        }
        let p = |i: usize| vertices[ring[i % n]];
        if g == Geometry::Euclidean {
            let c = (p(0) / p(0).w).truncate();
            total += (1..n - 1)
                .map(|i| {
                    let (a, b) = ((p(i) / p(i).w).truncate(), (p(i + 1) / p(i + 1).w).truncate());
                    0.5 * (a - c).cross(b - c).length()
                })
                .sum::<f64>();
            continue;
        }
        let angles: f64 = (0..n)
            .map(|i| {
                let v = p(i + n);
                let a = g.normalize_tangent::<f64>(v, p(i + n - 1));
                let b = g.normalize_tangent::<f64>(v, p(i + 1));
                g.form::<f64>(a, b).clamp(-1.0, 1.0).acos()
            })
            .sum();
        let flat = (n as f64 - 2.0) * core::f64::consts::PI;
        total += if g == Geometry::Hyperbolic {
            flat - angles
        } else {
            angles - flat
        };
    }
    total
}

/// Quadrature order per direction on each sub-triangle.
const ORDER: usize = 12;
/// Levels of 4-way triangle subdivision (64 sub-triangles per fan triangle).
const SUBDIVISIONS: u32 = 3;

/// Volume of the polyhedron with normalised face planes `planes`, whose face
/// `f` has the vertices `face_vertices[f]` (cyclic) among `vertices`.
#[must_use]
pub fn polyhedron_volume(g: Geometry, planes: &[DVec4], vertices: &[DVec4], face_vertices: &[Vec<usize>]) -> f64 {
    let (nodes, weights) = gauss_legendre(ORDER);
    let mut total = 0.0;
    for (f, ring) in face_vertices.iter().enumerate() {
        let n = planes[f];
        let h = -n.w / n.truncate().length();
        let pts: Vec<DVec3> = ring.iter().map(|&v| (vertices[v] / vertices[v].w).truncate()).collect();
        let centre = pts.iter().copied().sum::<DVec3>() / pts.len() as f64;
        for i in 0..pts.len() {
            let tri = [centre, pts[i], pts[(i + 1) % pts.len()]];
            total += triangle_integral(tri, SUBDIVISIONS, &nodes, &weights, &|x: DVec3| {
                let rc = x.length();
                let r = g.chart_to_distance::<f64>(rc);
                cone_content(g, r) * h / (rc * rc * rc)
            });
        }
    }
    total
}

/// The volume of the cone of unit solid angle out to distance `r`.
fn cone_content(g: Geometry, r: f64) -> f64 {
    match g {
        Geometry::Euclidean => r * r * r / 3.0,
        // For small r the closed forms cancel; the series is exact enough.
        Geometry::Hyperbolic if r < 1e-3 => r * r * r / 3.0 + r.powi(5) / 15.0,
        Geometry::Spherical if r < 1e-3 => r * r * r / 3.0 - r.powi(5) / 15.0,
        Geometry::Hyperbolic => ((2.0 * r).sinh() - 2.0 * r) / 4.0,
        Geometry::Spherical => (2.0 * r - (2.0 * r).sin()) / 4.0,
    }
}

fn triangle_integral(t: [DVec3; 3], depth: u32, nodes: &[f64], weights: &[f64], f: &dyn Fn(DVec3) -> f64) -> f64 {
    if depth > 0 {
        let [a, b, c] = t;
        let (ab, bc, ca) = ((a + b) / 2.0, (b + c) / 2.0, (c + a) / 2.0);
        return [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
            .into_iter()
            .map(|s| triangle_integral(s, depth - 1, nodes, weights, f))
            .sum();
    }
    // Collapsed coordinates: x = a + u((b - a) + v(c - b)), dA = 2 area u du dv.
    let [a, b, c] = t;
    let twice_area = (b - a).cross(c - b).length();
    let mut sum = 0.0;
    for (i, &u) in nodes.iter().enumerate() {
        for (j, &v) in nodes.iter().enumerate() {
            let x = a + ((b - a) + (c - b) * v) * u;
            sum += weights[i] * weights[j] * u * f(x);
        }
    }
    sum * twice_area
}

/// Gauss-Legendre nodes and weights on [0, 1], by Newton's method on the
/// Legendre polynomial.
#[must_use]
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut nodes = vec![0.0; n];
    let mut weights = vec![0.0; n];
    for i in 0..n {
        let mut x = (core::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 0.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
            let dx = p1 / dp;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        nodes[i] = 0.5 * (1.0 - x);
        weights[i] = 1.0 / ((1.0 - x * x) * dp * dp);
    }
    (nodes, weights)
}
