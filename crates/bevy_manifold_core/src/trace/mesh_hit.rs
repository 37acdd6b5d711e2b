//! Where a ray meets a mesh instance: the bounding ball first, then the
//! ray carried into the mesh's own chart, where it is an affine ray and
//! the BVH and the ray/triangle test are ordinary (see [`crate::geometry`]). The
//! WGSL twins (`meets_ball`, `hit_instance`, `mesh_normal`, `mesh_albedo`
//! in `bevy_manifold_gpu`'s `shaders/mesh_hit.wgsl`) do the same
//! arithmetic in the same order.

use super::flat::{FlatInstance, FlatScene};
use super::step::{Ray, hit_ball};
use crate::geometry::{Geometry, Real};
use crate::mesh::{MeshData, MeshHit};

/// The chart parameter from which the segment `[0, t_end]` of the ray is
/// inside the ball `(c, k)`: 0 when it starts inside, the entering root
/// otherwise; `None` when it misses the ball.
#[inline]
#[must_use]
pub fn meets_ball<R: Real>(g: Geometry, ray: &Ray<R>, c: R::V4, k: R, t_end: R) -> Option<R> {
    let zero = R::of(0.0);
    let o = ray.origin;
    let inside = match g {
        Geometry::Euclidean => {
            let q = o - c;
            g.form::<R>(q, q) <= k
        }
        Geometry::Hyperbolic => -g.form::<R>(o, c) <= k,
        Geometry::Spherical => g.form::<R>(o, c) >= k,
    };
    if inside {
        return Some(zero);
    }
    hit_ball(g, ray, c, k, zero).filter(|&t| t <= t_end)
}

/// A mesh hit in the tracer's terms: chart parameter on the world ray and
/// the triangle with its barycentrics. WGSL twin: `InstanceHit` in
/// `shaders/mesh_hit.wgsl`.
#[derive(Clone, Copy, Debug)]
pub struct InstanceHit<R> {
    /// Chart parameter of the hit on the world ray.
    pub t: R,
    /// The hit on the mesh.
    pub hit: MeshHit<R>,
}

/// The nearest triangle of `inst` on the ray within `[0, t_end]`. The ray
/// is re-based where it enters the bounding ball (`t0`), carried into the
/// mesh's chart (`o, d` homogeneous), and made affine: its points are
/// `O + s D` with `O = o.xyz / o.w`, `D = d.xyz - d.w O` and
/// `s = t' / (o.w + t' d.w)`, monotone in `t'` while the point stays in the
/// chart; so `t' = s o.w / (1 - s d.w)`.
#[must_use]
pub fn hit_instance<R: Real>(
    g: Geometry,
    ray: &Ray<R>,
    inst: &FlatInstance<R>,
    mesh: &MeshData,
    t_end: R,
) -> Option<InstanceHit<R>> {
    let t0 = meets_ball(g, ray, inst.center, inst.k, t_end)?;
    let one = R::of(1.0);
    let o = inst.to_local * (ray.origin + ray.dir * t0);
    let d = inst.to_local * ray.dir;
    let [ox, oy, oz, ow] = R::xyzw(o);
    let [dx, dy, dz, dw] = R::xyzw(d);
    // Not in front of the mesh's chart (or NaN): no hit.
    if ow.partial_cmp(&R::of(0.0)) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let origin = [ox / ow, oy / ow, oz / ow];
    let dir = [dx - dw * origin[0], dy - dw * origin[1], dz - dw * origin[2]];
    let left = t_end - t0;
    let denom = ow + left * dw;
    let s_max = if denom > R::of(0.0) {
        left / denom
    } else {
        R::of(f64::MAX)
    };
    let hit = mesh.hit(origin, dir, s_max)?;
    let t = t0 + hit.s * ow / (one - hit.s * dw);
    Some(InstanceHit { t, hit })
}

/// The shading normal at the world point `x` (normalised) of a mesh hit:
/// the triangle's interpolated vertex normal `n` at its local point `P`
/// is the plane `(n, -n . P)` of the mesh's chart; carried to the world
/// (`to_local` transposed) it is a plane whose normal at `x` the form gives.
/// Faces the viewer (`towards`, the reversed ray direction).
#[must_use]
pub fn mesh_normal<R: Real>(
    g: Geometry,
    inst: &FlatInstance<R>,
    mesh: &MeshData,
    hit: &MeshHit<R>,
    x: R::V4,
    towards: R::V4,
) -> R::V4 {
    let m = &mesh.mesh;
    let tri = m.triangles[hit.triangle as usize];
    let w = [R::of(1.0) - hit.u - hit.v, hit.u, hit.v];
    let mut p = [R::of(0.0); 3];
    let mut n = [R::of(0.0); 3];
    for (k, &i) in tri.iter().enumerate() {
        for c in 0..3 {
            p[c] = p[c] + w[k] * R::of(f64::from(m.positions[i as usize][c]));
            n[c] = n[c] + w[k] * R::of(f64::from(m.normals[i as usize][c]));
        }
    }
    let plane_local = R::v4(n[0], n[1], n[2], -(n[0] * p[0] + n[1] * p[1] + n[2] * p[2]));
    let plane = R::transpose_mul(inst.to_local, plane_local);
    let pole = match g {
        Geometry::Euclidean => {
            let [a, b, c, _] = R::xyzw(plane);
            R::v4(a, b, c, R::of(0.0))
        }
        Geometry::Hyperbolic => {
            let [a, b, c, e] = R::xyzw(plane);
            R::v4(a, b, c, -e)
        }
        Geometry::Spherical => plane,
    };
    let normal = g.normalize_tangent::<R>(x, pole);
    if g.form::<R>(normal, towards) < R::of(0.0) {
        -normal
    } else {
        normal
    }
}

/// The albedo of a mesh hit: the instance's base colour times its
/// texture at the interpolated texture coordinates.
#[must_use]
pub fn mesh_albedo<R: Real>(flat: &FlatScene<R>, inst: &FlatInstance<R>, hit: &MeshHit<R>) -> [f32; 3] {
    let Some(t) = inst.texture else { return inst.color };
    let m = &flat.meshes[inst.mesh].mesh;
    let tri = m.triangles[hit.triangle as usize];
    let (u, v) = (hit.u.f64() as f32, hit.v.f64() as f32);
    let w = [1.0 - u - v, u, v];
    let mut uv = [0.0f32; 2];
    for (k, &i) in tri.iter().enumerate() {
        for (acc, c) in uv.iter_mut().zip(m.uvs[i as usize]) {
            *acc += w[k] * c;
        }
    }
    let s = flat.textures[t].sample(uv);
    [inst.color[0] * s[0], inst.color[1] * s[1], inst.color[2] * s[2]]
}
