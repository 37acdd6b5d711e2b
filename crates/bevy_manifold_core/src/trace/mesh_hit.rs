//! Where a ray meets a mesh instance: the bounding ball first, then the
//! ray carried into the mesh's own chart, where it is an affine ray and
//! the BVH and the ray/triangle test are ordinary (see [`crate::geometry`]). The
//! WGSL twins (`meets_ball`, `hit_instance`, `mesh_normal`,
//! `normal_mapped`, `mesh_surface` in `bevy_manifold_gpu`'s
//! `shaders/mesh_hit.wgsl`; `hit_uv`, `mesh_alpha` in its
//! `shaders/texture.wgsl`) do the same arithmetic in the same order; what
//! a surface is made of is [`crate::material`].

use super::flat::{FlatInstance, FlatScene};
use super::step::{Ray, hit_ball};
use crate::geometry::{Geometry, Real};
use crate::material::Pbr;
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

/// The nearest triangle of `inst` on the ray within `[0, t_end]` (past
/// the transparent texels of an alpha-masked material). The ray
/// is re-based where it enters the bounding ball (`t0`), carried into the
/// mesh's chart (`o, d` homogeneous), and made affine: its points are
/// `O + s D` with `O = o.xyz / o.w`, `D = d.xyz - d.w O` and
/// `s = t' / (o.w + t' d.w)`, monotone in `t'` while the point stays in the
/// chart; so `t' = s o.w / (1 - s d.w)`.
#[must_use]
pub fn hit_instance<R: Real>(
    g: Geometry,
    flat: &FlatScene<R>,
    ray: &Ray<R>,
    inst: &FlatInstance<R>,
    t_end: R,
) -> Option<InstanceHit<R>> {
    let mesh = &flat.meshes[inst.mesh];
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
    let hit = match inst.alpha_mask {
        None => mesh.hit(origin, dir, s_max)?,
        Some((cutoff, alpha)) => {
            let keep = |h: &MeshHit<R>| mesh_alpha(flat, inst, hit_uv(mesh, h), alpha) >= cutoff;
            crate::mesh::bvh::hit_mesh_where(mesh, origin, dir, s_max, keep)?
        }
    };
    let t = t0 + hit.s * ow / (one - hit.s * dw);
    Some(InstanceHit { t, hit })
}

/// The alpha of a masked instance's surface at `uv`: the base alpha
/// factor times its base texture's alpha. WGSL twin: `mesh_alpha` in
/// `shaders/texture.wgsl`.
#[must_use]
pub fn mesh_alpha<R: Real>(flat: &FlatScene<R>, inst: &FlatInstance<R>, uv: [f32; 2], alpha: f32) -> f32 {
    match inst.textures.base {
        Some(t) => alpha * flat.textures[t].sample_unorm(uv)[3],
        None => alpha,
    }
}

/// The texture coordinates of a mesh hit, interpolated from its
/// triangle's corners. WGSL twin: `hit_uv` in `shaders/texture.wgsl`.
#[must_use]
pub fn hit_uv<R: Real>(mesh: &MeshData, hit: &MeshHit<R>) -> [f32; 2] {
    let m = &mesh.mesh;
    let tri = m.triangles[hit.triangle as usize];
    let (u, v) = (hit.u.f64() as f32, hit.v.f64() as f32);
    let w = [1.0 - u - v, u, v];
    let mut uv = [0.0f32; 2];
    for (k, &i) in tri.iter().enumerate() {
        for (acc, c) in uv.iter_mut().zip(m.uvs[i as usize]) {
            *acc += w[k] * c;
        }
    }
    uv
}

/// The shading normal at the world point `x` (normalised) of a mesh hit:
/// the triangle's interpolated vertex normal `n` at its local point `P`
/// is the plane `(n, -n . P)` of the mesh's chart; carried to the world
/// (`to_local` transposed) it is a plane whose normal at `x` the form gives.
/// With a normal map, the interpolated normal is first tilted by the
/// map's texel at `uv` ([`normal_mapped`]). Faces the viewer (`towards`,
/// the reversed ray direction).
#[must_use]
pub fn mesh_normal<R: Real>(
    g: Geometry,
    flat: &FlatScene<R>,
    inst: &FlatInstance<R>,
    (hit, uv): (&MeshHit<R>, [f32; 2]),
    x: R::V4,
    towards: R::V4,
) -> R::V4 {
    let m = &flat.meshes[inst.mesh].mesh;
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
    if let Some(t) = inst.textures.normal {
        let corner = |k: usize| m.positions[tri[k] as usize].map(f64::from);
        let uvs = tri.map(|i| m.uvs[i as usize]);
        let texel = flat.textures[t].sample_unorm(uv);
        let tilted = normal_mapped([corner(0), corner(1), corner(2)], uvs, n.map(|c| c.f64()), texel);
        n = tilted.map(R::of);
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

/// The local normal `n` (interpolated, of the triangle with corners
/// `p` and texture coordinates `uv`) tilted by a normal map's texel
/// (`xyz = 2 rgb - 1`, glTF's convention: x along increasing `u`, y up
/// the image, that is along decreasing `v`, z along `n`). The tangent
/// frame comes from the triangle's own texture coordinates (tangent along
/// `dp/du`, kept square to `n`); a triangle whose texture coordinates do
/// not span a plane keeps `n`. WGSL twin: `normal_mapped` in
/// `shaders/mesh_hit.wgsl`.
#[must_use]
pub fn normal_mapped(p: [[f64; 3]; 3], uv: [[f32; 2]; 3], n: [f64; 3], texel: [f32; 4]) -> [f64; 3] {
    let v3 = |a: [f64; 3]| glam::DVec3::from(a);
    let (e1, e2) = (v3(p[1]) - v3(p[0]), v3(p[2]) - v3(p[0]));
    let du = [f64::from(uv[1][0] - uv[0][0]), f64::from(uv[2][0] - uv[0][0])];
    let dv = [f64::from(uv[1][1] - uv[0][1]), f64::from(uv[2][1] - uv[0][1])];
    let det = du[0] * dv[1] - du[1] * dv[0];
    let n = v3(n).normalize_or_zero();
    if det.abs() < 1e-12 || n == glam::DVec3::ZERO {
        return n.to_array();
    }
    // dp/du and dp/dv from the two edges.
    let dpdu = (e1 * dv[1] - e2 * dv[0]) / det;
    let dpdv = (e2 * du[0] - e1 * du[1]) / det;
    let t = (dpdu - n * n.dot(dpdu)).normalize_or_zero();
    if t == glam::DVec3::ZERO {
        return n.to_array();
    }
    let mut b = n.cross(t);
    // Up the image is along -dp/dv.
    if b.dot(-dpdv) < 0.0 {
        b = -b;
    }
    let m = texel.map(|c| 2.0 * f64::from(c) - 1.0);
    (t * m[0] + b * m[1] + n * m[2]).normalize_or(n).to_array()
}

/// What a mesh hit is made of at texture coordinates `uv`: base colour
/// (times its texture), emission (times its texture), and metallic and
/// roughness (times the metallic-roughness texture's blue and green).
/// WGSL twin: `mesh_surface` in `shaders/mesh_hit.wgsl`.
#[must_use]
pub fn mesh_surface<R: Real>(
    flat: &FlatScene<R>,
    inst: &FlatInstance<R>,
    uv: [f32; 2],
) -> ([f32; 3], [f32; 3], Option<Pbr>) {
    let times = |a: [f32; 3], b: [f32; 3]| [a[0] * b[0], a[1] * b[1], a[2] * b[2]];
    let t = &inst.textures;
    let albedo = t
        .base
        .map_or(inst.color, |i| times(inst.color, flat.textures[i].sample(uv)));
    let emissive = t
        .emissive
        .map_or(inst.emissive, |i| times(inst.emissive, flat.textures[i].sample(uv)));
    let pbr = inst.pbr.map(|p| match t.metallic_roughness {
        Some(i) => {
            let s = flat.textures[i].sample_unorm(uv);
            Pbr {
                metallic: p.metallic * s[2],
                roughness: p.roughness * s[1],
            }
        }
        None => p,
    });
    (albedo, emissive, pbr)
}
