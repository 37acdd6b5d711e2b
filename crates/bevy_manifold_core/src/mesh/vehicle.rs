//! The vehicle: a small airplane made in code (no model file), the paper's
//! "virtual user body attached to an object, an airplane for example".
//! One unit long, nose along -z (the way a camera looks), wings along x,
//! the fin up (+y); flat-shaded, every face wound outward.
//!
//! ```
//! use bevy_manifold_core::mesh::vehicle;
//! let plane = vehicle::airplane();
//! let (lo, hi) = vehicle::bounds(&plane.mesh);
//! assert!((hi[2] - lo[2] - 1.0).abs() < 1e-6); // one unit nose to tail
//! assert!(hi[0] - lo[0] > 1.0); // the wings are wider than it is long
//! ```

use super::{MeshData, TriMesh};
use std::sync::{Arc, OnceLock};

/// The airplane, built once (about 200 triangles).
///
/// # Panics
/// Never: the mesh is made of finite numbers and in-range indices (the
/// tests check it).
#[must_use]
pub fn airplane() -> Arc<MeshData> {
    static M: OnceLock<Arc<MeshData>> = OnceLock::new();
    M.get_or_init(|| MeshData::shared(airplane_mesh())).clone()
}

/// The smallest and largest coordinates of `mesh`'s vertices.
#[must_use]
pub fn bounds(mesh: &TriMesh) -> ([f32; 3], [f32; 3]) {
    mesh.positions
        .iter()
        .fold(([f32::MAX; 3], [f32::MIN; 3]), |(lo, hi), p| {
            (
                [lo[0].min(p[0]), lo[1].min(p[1]), lo[2].min(p[2])],
                [hi[0].max(p[0]), hi[1].max(p[1]), hi[2].max(p[2])],
            )
        })
}

/// Triangles with their own vertices (flat shading), each wound so its
/// normal points away from a centre the part gives.
#[derive(Default)]
struct Builder {
    positions: Vec<[f32; 3]>,
    triangles: Vec<[u32; 3]>,
}

type P = [f32; 3];

fn sub(a: P, b: P) -> P {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: P, b: P) -> P {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn dot(a: P, b: P) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl Builder {
    /// The triangle `a b c`, turned to face away from `inside`.
    fn tri(&mut self, a: P, b: P, c: P, inside: P) {
        let n = cross(sub(b, a), sub(c, a));
        let mid = [
            (a[0] + b[0] + c[0]) / 3.0,
            (a[1] + b[1] + c[1]) / 3.0,
            (a[2] + b[2] + c[2]) / 3.0,
        ];
        let (b, c) = if dot(n, sub(mid, inside)) >= 0.0 {
            (b, c)
        } else {
            (c, b)
        };
        let i = self.positions.len() as u32;
        self.positions.extend([a, b, c]);
        self.triangles.push([i, i + 1, i + 2]);
    }

    fn quad(&mut self, a: P, b: P, c: P, d: P, inside: P) {
        self.tri(a, b, c, inside);
        self.tri(a, c, d, inside);
    }

    /// A convex polygon `outline` (points `(u, v)`) extruded to `±half`
    /// along the remaining axis; `place(u, v, w)` puts a point in 3D.
    fn slab(&mut self, outline: &[[f32; 2]], half: f32, place: impl Fn(f32, f32, f32) -> P) {
        let n = outline.len() as f32;
        let (cu, cv) = outline
            .iter()
            .fold((0.0, 0.0), |(u, v), p| (u + p[0] / n, v + p[1] / n));
        let centre = place(cu, cv, 0.0);
        for (i, p) in outline.iter().enumerate() {
            let q = outline[(i + 1) % outline.len()];
            for w in [-half, half] {
                self.tri(place(cu, cv, w), place(p[0], p[1], w), place(q[0], q[1], w), centre);
            }
            self.quad(
                place(p[0], p[1], -half),
                place(q[0], q[1], -half),
                place(q[0], q[1], half),
                place(p[0], p[1], half),
                centre,
            );
        }
    }
}

fn airplane_mesh() -> TriMesh {
    let mut b = Builder::default();
    // The fuselage: octagonal rings along z, a point at each end.
    let rings: [(f32, f32); 5] = [(-0.5, 0.0), (-0.38, 0.065), (-0.1, 0.08), (0.3, 0.055), (0.5, 0.015)];
    let sides = 8;
    let ring = |z: f32, r: f32, k: usize| {
        let a = std::f32::consts::TAU * k as f32 / sides as f32;
        [r * a.cos(), r * a.sin() * 0.9, z]
    };
    for w in rings.windows(2) {
        let ((z0, r0), (z1, r1)) = (w[0], w[1]);
        let inside = [0.0, 0.0, 0.5 * (z0 + z1)];
        for k in 0..sides {
            let (a, bb) = (ring(z0, r0, k), ring(z0, r0, k + 1));
            let (c, d) = (ring(z1, r1, k + 1), ring(z1, r1, k));
            if r0 == 0.0 {
                b.tri(a, c, d, inside);
            } else {
                b.quad(a, bb, c, d, inside);
            }
        }
    }
    let (z_tail, r_tail) = rings[rings.len() - 1];
    for k in 0..sides {
        b.tri(
            [0.0, 0.0, z_tail],
            ring(z_tail, r_tail, k),
            ring(z_tail, r_tail, k + 1),
            [0.0, 0.0, 0.0],
        );
    }
    // The wings: swept back, tapering to the tips; (x, z) outline.
    let wing = |x: f32| [[0.0, -0.16], [x, 0.02], [x, 0.1], [0.0, 0.08]];
    for side in [-0.62, 0.62f32] {
        b.slab(&wing(side), 0.012, |u, v, w| [u, w - 0.02, v]);
    }
    // The tailplane, and the fin up from the tail.
    for side in [-0.22, 0.22f32] {
        b.slab(
            &[[0.0, 0.3], [side, 0.42], [side, 0.48], [0.0, 0.47]],
            0.008,
            |u, v, w| [u, w, v],
        );
    }
    b.slab(
        &[[0.28, 0.03], [0.48, 0.03], [0.5, 0.22], [0.43, 0.22]],
        0.008,
        |u, v, w| [w, v, u],
    );
    TriMesh::new(b.positions, None, None, b.triangles).expect("the airplane is a valid mesh")
}
