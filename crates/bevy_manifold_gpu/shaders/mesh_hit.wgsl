// Where a ray meets a mesh instance: the bounding ball first, then the ray
// carried into the mesh's own chart, where it is affine and bvh.wgsl's walk
// is ordinary; and the normal and albedo at the hit.
//
// Rust twin: crates/bevy_manifold_core/src/trace/mesh_hit.rs (meets_ball,
// InstanceHit, hit_instance, mesh_normal, normal_mapped, mesh_surface);
// the textures are read by texture.wgsl.
//
// Shader defs read: MESHES (the whole module), GEOMETRY_HYPERBOLIC /
// GEOMETRY_SPHERICAL (meets_ball, mesh_normal), MATERIALS (normal maps,
// emission, metallic and roughness); BALL_HITS through step (always on
// with MESHES).
#define_import_path bevy_manifold::mesh_hit

#ifdef MESHES
#import bevy_manifold::bindings::{Instance, mesh_data}
#import bevy_manifold::geometry::{form, normalize_tangent}
#import bevy_manifold::step::{Ray, hit_ball}
#import bevy_manifold::bvh::{MeshHit, data_vec3, hit_mesh}
#import bevy_manifold::texture::{NO_TEXTURE, texel_unorm, texture_rgb}

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

// The nearest triangle of an instance within [0, t_end] (with
// ALPHA_MASK, past transparent texels): re-based at the
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
// by the form, turned to face `towards`; with MATERIALS and a normal map,
// the normal first tilted by the map's texel at uv (normal_mapped).
fn mesh_normal(inst: Instance, h: MeshHit, uv: vec2<f32>, x: vec4<f32>, towards: vec4<f32>) -> vec4<f32> {
    let tri = mesh_data[inst.triangles + h.triangle];
    let w = vertex_weights(h);
    var p = vec3<f32>(0.0);
    var n = vec3<f32>(0.0);
    for (var k = 0u; k < 3u; k++) {
        p += w[k] * data_vec3(inst.vertices + 2u * tri[k]);
        n += w[k] * data_vec3(inst.vertices + 2u * tri[k] + 1u);
    }
#ifdef MATERIALS
    if inst.textures.w != NO_TEXTURE {
        n = normal_mapped(inst, tri, n, texel_unorm(inst.textures.w, uv));
    }
#endif
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

#ifdef MATERIALS
// Rust twin: normal_mapped. The local normal n tilted by a normal map's
// texel (xyz = 2 rgb - 1; x along increasing u, y up the image, z along
// n), the tangent frame from the triangle's texture coordinates.
fn normal_mapped(inst: Instance, tri: vec4<u32>, n_in: vec3<f32>, texel: vec4<f32>) -> vec3<f32> {
    let a = mesh_data[inst.vertices + 2u * tri.x];
    let b = mesh_data[inst.vertices + 2u * tri.y];
    let c = mesh_data[inst.vertices + 2u * tri.z];
    let uv0 = vec2<f32>(bitcast<f32>(a.w), bitcast<f32>(mesh_data[inst.vertices + 2u * tri.x + 1u].w));
    let uv1 = vec2<f32>(bitcast<f32>(b.w), bitcast<f32>(mesh_data[inst.vertices + 2u * tri.y + 1u].w));
    let uv2 = vec2<f32>(bitcast<f32>(c.w), bitcast<f32>(mesh_data[inst.vertices + 2u * tri.z + 1u].w));
    let p0 = bitcast<vec3<f32>>(a.xyz);
    let e1 = bitcast<vec3<f32>>(b.xyz) - p0;
    let e2 = bitcast<vec3<f32>>(c.xyz) - p0;
    let du = vec2<f32>(uv1.x - uv0.x, uv2.x - uv0.x);
    let dv = vec2<f32>(uv1.y - uv0.y, uv2.y - uv0.y);
    let det = du.x * dv.y - du.y * dv.x;
    let nl = length(n_in);
    if abs(det) < 1.0e-12 || nl == 0.0 {
        return n_in;
    }
    let n = n_in / nl;
    let dpdu = (e1 * dv.y - e2 * dv.x) / det;
    let dpdv = (e2 * du.x - e1 * du.y) / det;
    let tu = dpdu - n * dot(n, dpdu);
    if length(tu) == 0.0 {
        return n;
    }
    let t = normalize(tu);
    var bt = cross(n, t);
    // Up the image is along -dp/dv.
    if dot(bt, -dpdv) < 0.0 {
        bt = -bt;
    }
    let m = 2.0 * texel.xyz - 1.0;
    let out = t * m.x + bt * m.y + n * m.z;
    return select(n, normalize(out), length(out) > 0.0);
}
#endif

// Rust twin: mesh_surface. What a mesh hit is made of at uv: base colour
// (times its texture), and with MATERIALS emission (times its texture)
// and metallic and roughness (times the metallic-roughness texture's blue
// and green; metallic negative for the classic look).
struct Surface {
    albedo: vec3<f32>,
    emissive: vec3<f32>,
    metallic: f32,
    roughness: f32,
}

fn mesh_surface(inst: Instance, uv: vec2<f32>) -> Surface {
    var out = Surface(inst.color, vec3<f32>(0.0), -1.0, 0.0);
    if inst.textures.x != NO_TEXTURE {
        out.albedo *= texture_rgb(inst.textures.x, uv);
    }
#ifdef MATERIALS
    out.emissive = inst.emissive;
    if inst.textures.z != NO_TEXTURE {
        out.emissive *= texture_rgb(inst.textures.z, uv);
    }
    out.metallic = inst.metallic;
    out.roughness = inst.roughness;
    if inst.metallic >= 0.0 && inst.textures.y != NO_TEXTURE {
        let s = texel_unorm(inst.textures.y, uv);
        out.metallic *= s.z;
        out.roughness *= s.y;
    }
#endif
    return out;
}
#endif
