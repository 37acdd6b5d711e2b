// Where a ray meets a mesh instance: the bounding ball first, then the ray
// carried into the mesh's own chart, where it is affine and bvh.wgsl's walk
// is ordinary; and the normal and albedo at the hit.
//
// Rust twin: crates/bevy_manifold_core/src/trace/mesh_hit.rs (meets_ball,
// InstanceHit, hit_instance, mesh_normal, mesh_albedo); texel_index and
// srgb_to_linear are Texture::sample's in
// crates/bevy_manifold_core/src/mesh/mod.rs.
//
// Shader defs read: MESHES (the whole module), GEOMETRY_HYPERBOLIC /
// GEOMETRY_SPHERICAL (meets_ball, mesh_normal); BALL_HITS through step
// (always on with MESHES).
#define_import_path bevy_manifold::mesh_hit

#ifdef MESHES
#import bevy_manifold::bindings::{Instance, mesh_data}
#import bevy_manifold::geometry::{form, normalize_tangent}
#import bevy_manifold::step::{Ray, hit_ball}
#import bevy_manifold::bvh::{MeshHit, data_vec3, hit_mesh}

// From where the segment [0, t_end] is inside the ball (c, k): 0 when it
// starts inside, the entering root otherwise; -1 for a miss.
fn meets_ball(ray: Ray, c: vec4<f32>, k: f32, t_end: f32) -> f32 {
    let o = ray.origin;
#ifdef GEOMETRY_HYPERBOLIC
    let inside = -form(o, c) <= k;
#else ifdef GEOMETRY_SPHERICAL
    let inside = form(o, c) >= k;
#else
    let q = o - c;
    let inside = form(q, q) <= k;
#endif
    if inside {
        return 0.0;
    }
    let t = hit_ball(ray, c, k, 0.0);
    return select(-1.0, t, t >= 0.0 && t <= t_end);
}

// Rust twin: InstanceHit in crates/bevy_manifold_core/src/trace/mesh_hit.rs.
struct InstanceHit {
    t: f32,
    hit: MeshHit,
}

// The nearest triangle of an instance within [0, t_end]: re-based at the
// bounding ball, carried into the mesh's chart and made affine
// (mesh_hit.rs explains the change of parameter).
fn hit_instance(ray: Ray, inst: Instance, t_end: f32) -> InstanceHit {
    var out = InstanceHit(-1.0, MeshHit(-1.0, 0u, 0.0, 0.0));
    let t0 = meets_ball(ray, inst.center, inst.k, t_end);
    if t0 < 0.0 {
        return out;
    }
    let o = inst.to_local * (ray.origin + ray.dir * t0);
    let d = inst.to_local * ray.dir;
    if !(o.w > 0.0) {
        return out;
    }
    let origin = o.xyz / o.w;
    let dir = d.xyz - d.w * origin;
    let left = t_end - t0;
    let denom = o.w + left * d.w;
    let s_max = select(3.0e38, left / denom, denom > 0.0);
    let h = hit_mesh(inst, origin, dir, s_max);
    if h.s < 0.0 {
        return out;
    }
    out.t = t0 + h.s * o.w / (1.0 - h.s * d.w);
    out.hit = h;
    return out;
}

fn vertex_weights(h: MeshHit) -> vec3<f32> {
    return vec3<f32>(1.0 - h.u - h.v, h.u, h.v);
}

// The interpolated normal's plane carried to the world, its normal at x
// by the form, turned to face `towards`.
fn mesh_normal(inst: Instance, h: MeshHit, x: vec4<f32>, towards: vec4<f32>) -> vec4<f32> {
    let tri = mesh_data[inst.triangles + h.triangle];
    let w = vertex_weights(h);
    var p = vec3<f32>(0.0);
    var n = vec3<f32>(0.0);
    for (var k = 0u; k < 3u; k++) {
        p += w[k] * data_vec3(inst.vertices + 2u * tri[k]);
        n += w[k] * data_vec3(inst.vertices + 2u * tri[k] + 1u);
    }
    let plane = transpose(inst.to_local) * vec4<f32>(n, -dot(n, p));
#ifdef GEOMETRY_HYPERBOLIC
    let pole = vec4<f32>(plane.xyz, -plane.w);
#else ifdef GEOMETRY_SPHERICAL
    let pole = plane;
#else
    let pole = vec4<f32>(plane.xyz, 0.0);
#endif
    let normal = normalize_tangent(x, pole);
    return select(normal, -normal, form(normal, towards) < 0.0);
}

// Base colour times the texture (nearest texel, repeating).
fn mesh_albedo(inst: Instance, h: MeshHit) -> vec3<f32> {
    if inst.tex_width == 0u {
        return inst.color;
    }
    let tri = mesh_data[inst.triangles + h.triangle];
    let w = vertex_weights(h);
    var uv = vec2<f32>(0.0);
    for (var k = 0u; k < 3u; k++) {
        let a = mesh_data[inst.vertices + 2u * tri[k]];
        let b = mesh_data[inst.vertices + 2u * tri[k] + 1u];
        uv += w[k] * vec2<f32>(bitcast<f32>(a.w), bitcast<f32>(b.w));
    }
    let i = texel_index(uv.x, inst.tex_width);
    let j = texel_index(uv.y, inst.tex_height);
    let k = j * inst.tex_width + i;
    let c = mesh_data[inst.texture + k / 4u][k % 4u];
    let rgb = vec3<f32>(f32(c & 0xffu), f32((c >> 8u) & 0xffu), f32((c >> 16u) & 0xffu)) / 255.0;
    return inst.color * vec3<f32>(srgb_to_linear(rgb.x), srgb_to_linear(rgb.y), srgb_to_linear(rgb.z));
}

fn texel_index(x: f32, n: u32) -> u32 {
    let f = x - floor(x);
    return min(u32(f * f32(n)), max(n, 1u) - 1u);
}

fn srgb_to_linear(c: f32) -> f32 {
    return select(pow((c + 0.055) / 1.055, 2.4), c / 12.92, c <= 0.04045);
}
#endif
