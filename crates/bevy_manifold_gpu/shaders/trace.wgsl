// The manifold ray tracer: Algorithm 1 of Velho, da Silva, Novello (GI 2020)
// as DESIGN.md §2 spells it out. The WGSL twin of src/trace/: every function
// here has a Rust namesake (step.rs, walk.rs, render.rs, cell.rs) doing the
// same arithmetic in the same order, so the CPU reference in f32 and this
// shader can be compared pixel by pixel.
//
// Shader defs (the pipeline is specialised on the scene; see
// src/render/shader_defs.rs, which picks them):
//   GEOMETRY_EUCLIDEAN | GEOMETRY_HYPERBOLIC | GEOMETRY_SPHERICAL  exactly one
//   TRANSLATIONS_ONLY  every pairing is a Euclidean translation: transport
//                      moves the point, the direction is unchanged
//   CELLS_LATTICE | CELLS_FINITE | CELLS_HASHED  how cell ids are made
//                      (cell.rs): box lattice, Cayley-table index, hash of
//                      the copy's rounded centre
//   CELL_COLORS        per-cell shading
//   FOG                exponential fog and the early stop it allows
//   BALLS, TUBES, MESHES  which object kinds the scene has
//   BALL_HITS          derived: BALLS or MESHES (ball tests, also of the
//                      meshes' bounding balls)
//   LIGHTS             point lights (else ambient only)
//   ENCODE_SRGB        the render pass's target stores sRGB-encoded bytes
//                      without doing the encoding itself (Bevy's
//                      CompositingSpace::Srgb): the fragment entry encodes
//
// Entry points: `trace` (compute) writes every pixel with its ids to a
// storage buffer (headless renders, the agreement tests); `fragment` is the
// Bevy render pass's full-screen trace into a camera's view target, with
// depth. Both call `trace_pixel`, so they cannot disagree.

struct Params {
    camera: mat4x4<f32>,
    camera_cell: mat4x4<f32>,
    fog_color: vec4<f32>,
    width: u32,
    height: u32,
    levels: u32,
    face_count: u32,
    ball_count: u32,
    tube_count: u32,
    light_count: u32,
    camera_cell_index: u32,
    tan_half_fov: f32,
    max_distance: f32,
    fog_density: f32,
    tube_k: f32,
    // The render pass: the viewport's top-left pixel in the target, and the
    // camera's near plane (Bevy's reverse-z depth is near / view depth).
    origin_x: u32,
    origin_y: u32,
    near: f32,
    // FLAG_NO_EARLY_STOP, FLAG_NO_RENORMALIZE: measurement switches
    // (TraceSettings::fog_early_stop, ::renormalize), both off by default.
    flags: u32,
    // CELLS_LATTICE: 1 / edge lengths of the box; CELLS_HASHED: 1 / grid
    // step in x, the f32 horizon (HASHED_HORIZON_F32) in y.
    cell_scale: vec4<f32>,
    instance_count: u32,
    // CELL_COLORS: the tint (CellTint::words): mode 0 by cell, 1 highlight
    // the cell (cell_a, cell_b), 2 on/off pattern with threshold cell_a.
    cell_mode: u32,
    cell_a: u32,
    cell_b: u32,
}

struct Face {
    plane: vec4<f32>,
    pairing: mat4x4<f32>,
    // T_i^-1: what the ray's cell element is right-multiplied by.
    crossing: mat4x4<f32>,
    partner: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

struct Ball {
    center: vec4<f32>,
    color: vec3<f32>,
    // cosh r (H3), cos r (S3), r^2 (E3)
    k: f32,
    id: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

struct Tube {
    a: vec4<f32>,
    e: vec4<f32>,
    b: vec4<f32>,
    e_b: vec4<f32>,
    color: vec4<f32>,
}

// A mesh instance (gpu.rs GpuInstance): offsets into mesh_data.
struct Instance {
    // World chart to the mesh's own coordinates.
    to_local: mat4x4<f32>,
    // Bounding ball.
    center: vec4<f32>,
    color: vec3<f32>,
    k: f32,
    nodes: u32,
    vertices: u32,
    triangles: u32,
    id: u32,
    // Texels' offset, and size (width 0: no texture).
    texture: u32,
    tex_width: u32,
    tex_height: u32,
    node_count: u32,
    // 1: the home copy of a mesh attached to the camera, not drawn before
    // the first transport.
    attached: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

struct Light {
    position: vec4<f32>,
    color: vec3<f32>,
    intensity: f32,
}

// What one pixel saw: colour, then object id, levels, cell id (two words).
struct Pixel {
    color: vec4<f32>,
    object: u32,
    levels: u32,
    cell_lo: u32,
    cell_hi: u32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> faces: array<Face>;
@group(0) @binding(2) var<storage, read> balls: array<Ball>;
@group(0) @binding(3) var<storage, read> tubes: array<Tube>;
@group(0) @binding(4) var<storage, read> lights: array<Light>;
// CELLS_FINITE: table[k * face_count + f] = index of element k * T_f.
@group(0) @binding(5) var<storage, read> cell_table: array<u32>;
#ifdef MESHES
@group(0) @binding(6) var<storage, read> instances: array<Instance>;
@group(0) @binding(7) var<storage, read> mesh_data: array<vec4<u32>>;
#endif
// The compute entries' output.
@group(0) @binding(8) var<storage, read_write> pixels: array<Pixel>;

const EDGE_ID: u32 = 255u;
const FLAG_NO_EARLY_STOP: u32 = 1u;
const FLAG_NO_RENORMALIZE: u32 = 2u;
const NO_FACE: u32 = 0xffffffffu;
const PI: f32 = 3.14159265358979;

// ---- the geometry (src/geometry/mod.rs) ----

fn form(u: vec4<f32>, v: vec4<f32>) -> f32 {
    let s = u.x * v.x + u.y * v.y + u.z * v.z;
#ifdef GEOMETRY_HYPERBOLIC
    return s - u.w * v.w;
#else ifdef GEOMETRY_SPHERICAL
    return s + u.w * v.w;
#else
    return s;
#endif
}

fn normalize_point(p: vec4<f32>) -> vec4<f32> {
#ifdef GEOMETRY_HYPERBOLIC
    let n = sqrt(abs(-form(p, p)));
    return p * (1.0 / select(n, -n, p.w < 0.0));
#else ifdef GEOMETRY_SPHERICAL
    return p * (1.0 / sqrt(dot(p, p)));
#else
    return p * (1.0 / p.w);
#endif
}

fn project_tangent(p: vec4<f32>, v: vec4<f32>) -> vec4<f32> {
#ifdef GEOMETRY_HYPERBOLIC
    return v + p * form(v, p);
#else ifdef GEOMETRY_SPHERICAL
    return v - p * form(v, p);
#else
    return v - p * v.w;
#endif
}

fn normalize_tangent(p: vec4<f32>, v: vec4<f32>) -> vec4<f32> {
    let t = project_tangent(p, v);
    return t * (1.0 / sqrt(abs(form(t, t))));
}

fn distance(p: vec4<f32>, q: vec4<f32>) -> f32 {
    let d = p - q;
#ifdef GEOMETRY_HYPERBOLIC
    return 2.0 * asinh(sqrt(max(form(d, d), 0.0)) * 0.5);
#else ifdef GEOMETRY_SPHERICAL
    let s = p + q;
    return 2.0 * atan2(sqrt(dot(d, d)), sqrt(dot(s, s)));
#else
    return sqrt(form(d, d));
#endif
}

fn chart_to_distance(t: f32) -> f32 {
#ifdef GEOMETRY_HYPERBOLIC
    return atanh(t);
#else ifdef GEOMETRY_SPHERICAL
    return atan(t);
#else
    return t;
#endif
}

fn max_chart_parameter() -> f32 {
#ifdef GEOMETRY_HYPERBOLIC
    return 1.0;
#else ifdef GEOMETRY_SPHERICAL
    return 1.5574077; // tan 1
#else
    return 3.0e38;
#endif
}

// How far a point is from being normalised, and a vector from being a
// unit tangent there (the stability checks).
fn point_error(p: vec4<f32>) -> f32 {
#ifdef GEOMETRY_HYPERBOLIC
    return abs(form(p, p) + 1.0);
#else ifdef GEOMETRY_SPHERICAL
    return abs(form(p, p) - 1.0);
#else
    return abs(p.w - 1.0);
#endif
}

fn tangent_error(p: vec4<f32>, v: vec4<f32>) -> f32 {
#ifdef GEOMETRY_EUCLIDEAN
    let along = abs(v.w);
#else
    let along = abs(form(p, v));
#endif
    return max(along, abs(form(v, v) - 1.0));
}

fn sphere_area(d: f32) -> f32 {
#ifdef GEOMETRY_HYPERBOLIC
    return 4.0 * PI * sinh(d) * sinh(d);
#else ifdef GEOMETRY_SPHERICAL
    return 4.0 * PI * sin(d) * sin(d);
#else
    return 4.0 * PI * d * d;
#endif
}

// ---- one ray (src/trace/step.rs) ----

struct Ray {
    origin: vec4<f32>,
    dir: vec4<f32>,
}

// Where a ray crosses a face: the nearest face it leaves through
// (n . d > 0), skipping the face it just entered; t = -(n . o) / (n . d),
// clamped at 0 so a point a hair outside leaves at once.
struct Exit {
    face: u32,
    t: f32,
}

fn exit_face(ray: Ray, skip: u32) -> Exit {
    var best = Exit(NO_FACE, 0.0);
    for (var i = 0u; i < params.face_count; i++) {
        if i == skip {
            continue;
        }
        let n = faces[i].plane;
        let nd = dot(n, ray.dir);
        if nd > 0.0 {
            let t = max(-dot(n, ray.origin) / nd, 0.0);
            if best.face == NO_FACE || t < best.t {
                best = Exit(i, t);
            }
        }
    }
    return best;
}

fn advance(ray: Ray, t: f32) -> Ray {
    let p = normalize_point(ray.origin + ray.dir * t);
    return Ray(p, normalize_tangent(p, ray.dir));
}

// advance without renormalisation (measuring drift only): the factors
// that are exact for a normalised ray, not measured from the vectors.
fn advance_raw(ray: Ray, t: f32) -> Ray {
    let o = ray.origin;
    let d = ray.dir;
#ifdef GEOMETRY_HYPERBOLIC
    let s = 1.0 / sqrt(1.0 - t * t);
    return Ray((o + d * t) * s, (o * t + d) * s);
#else ifdef GEOMETRY_SPHERICAL
    let s = 1.0 / sqrt(1.0 + t * t);
    return Ray((o + d * t) * s, (d - o * t) * s);
#else
    return Ray(o + d * t, d);
#endif
}

fn renormalize() -> bool {
    return (params.flags & FLAG_NO_RENORMALIZE) == 0u;
}

fn transport(face: u32, ray: Ray) -> Ray {
#ifdef TRANSLATIONS_ONLY
    // A translation moves the point and leaves directions alone.
    return Ray(faces[face].pairing * ray.origin, ray.dir);
#else
    let o = normalize_point(faces[face].pairing * ray.origin);
    return Ray(o, normalize_tangent(o, faces[face].pairing * ray.dir));
#endif
}

// transport without renormalisation (measuring drift only).
fn transport_raw(face: u32, ray: Ray) -> Ray {
    return Ray(faces[face].pairing * ray.origin, faces[face].pairing * ray.dir);
}

// advance, or advance_raw when FLAG_NO_RENORMALIZE is set.
fn advance_or_raw(ray: Ray, t: f32) -> Ray {
    if renormalize() {
        return advance(ray, t);
    }
    return advance_raw(ray, t);
}

// transport, or transport_raw when FLAG_NO_RENORMALIZE is set.
fn transport_or_raw(face: u32, ray: Ray) -> Ray {
    if renormalize() {
        return transport(face, ray);
    }
    return transport_raw(face, ray);
}

// Smallest t >= t_min where a t^2 + 2 b t + c goes from positive to
// non-positive; -1 when none.
fn entering_root(a: f32, b: f32, c: f32, t_min: f32) -> f32 {
    let disc = b * b - a * c;
    if disc < 0.0 {
        return -1.0;
    }
    let s = sqrt(disc);
    let q = select(-(b + s), s - b, b < 0.0);
    var best = -1.0;
    if q != 0.0 {
        let t = c / q;
        if t >= t_min && a * t + b < 0.0 {
            best = t;
        }
    }
    if abs(a) > 1.1920929e-7 * (abs(b) + abs(c)) {
        let t = q / a;
        if t >= t_min && a * t + b < 0.0 && (best < 0.0 || t < best) {
            best = t;
        }
    }
    return best;
}

#ifdef BALL_HITS
// Balls, and the bounding balls of mesh instances.
fn hit_ball(ray: Ray, c: vec4<f32>, k: f32, t_min: f32) -> f32 {
    let o = ray.origin;
    let d = ray.dir;
#ifdef GEOMETRY_HYPERBOLIC
    let a0 = form(o, c);
    let b0 = form(d, c);
    let t = entering_root(b0 * b0 + k * k, a0 * b0, a0 * a0 - k * k, t_min);
    return select(-1.0, t, t >= 0.0 && a0 + t * b0 < 0.0);
#else ifdef GEOMETRY_SPHERICAL
    let a0 = form(o, c);
    let b0 = form(d, c);
    let t = entering_root(k * k - b0 * b0, -(a0 * b0), k * k - a0 * a0, t_min);
    return select(-1.0, t, t >= 0.0 && a0 + t * b0 > 0.0);
#else
    let q = o - c;
    let b = form(q, d);
    return entering_root(form(d, d), b, form(q, q) - k, t_min);
#endif
}
#endif

#ifdef TUBES
fn hit_tube(ray: Ray, seg: Tube, k: f32, t_min: f32) -> f32 {
    let o = ray.origin;
    let d = ray.dir;
#ifdef GEOMETRY_HYPERBOLIC
    let a1 = form(o, seg.a);
    let b1 = form(d, seg.a);
    let a2 = form(o, seg.e);
    let b2 = form(d, seg.e);
    let t = entering_root(b1 * b1 - b2 * b2 + k * k, a1 * b1 - a2 * b2, a1 * a1 - a2 * a2 - k * k, t_min);
#else ifdef GEOMETRY_SPHERICAL
    let a1 = form(o, seg.a);
    let b1 = form(d, seg.a);
    let a2 = form(o, seg.e);
    let b2 = form(d, seg.e);
    let t = entering_root(k * k - b1 * b1 - b2 * b2, -(a1 * b1 + a2 * b2), k * k - a1 * a1 - a2 * a2, t_min);
#else
    let q = o - seg.a;
    let qe = form(q, seg.e);
    let de = form(d, seg.e);
    let t = entering_root(1.0 - de * de, form(q, d) - qe * de, form(q, q) - qe * qe - k, t_min);
#endif
    if t < 0.0 {
        return -1.0;
    }
    let p = o + d * t;
#ifdef GEOMETRY_EUCLIDEAN
    let along_a = form(p - seg.a, seg.e);
    let along_b = form(p - seg.b, seg.e_b);
#else
    let along_a = form(p, seg.e);
    let along_b = form(p, seg.e_b);
#endif
    return select(-1.0, t, along_a >= 0.0 && along_b <= 0.0);
}

fn foot_on_line(x: vec4<f32>, seg: Tube) -> vec4<f32> {
#ifdef GEOMETRY_HYPERBOLIC
    return seg.e * form(x, seg.e) - seg.a * form(x, seg.a);
#else ifdef GEOMETRY_SPHERICAL
    return seg.a * form(x, seg.a) + seg.e * form(x, seg.e);
#else
    return seg.a + seg.e * form(x - seg.a, seg.e);
#endif
}
#endif

fn normal_from(x: vec4<f32>, c: vec4<f32>) -> vec4<f32> {
    return normalize_tangent(x, -c);
}

// ---- cells (src/cell.rs) ----

fn hash32(x: u32) -> u32 {
    let state = x * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

fn hash_key(key: vec4<i32>, seed: u32) -> u32 {
    var h = seed;
    h = hash32(h ^ bitcast<u32>(key.x));
    h = hash32(h ^ bitcast<u32>(key.y));
    h = hash32(h ^ bitcast<u32>(key.z));
    h = hash32(h ^ bitcast<u32>(key.w));
    return h;
}

// The cell id as (lo, hi) words of CellId, from the cell's group element
// (and, for finite groups, its table index).
fn cell_id(cell: mat4x4<f32>, index: u32) -> vec2<u32> {
#ifdef CELLS_FINITE
    return vec2<u32>(index, 0u);
#else ifdef CELLS_LATTICE
    let c = cell[3].xyz / cell[3].w * params.cell_scale.xyz;
    let l = vec3<i32>(round(c));
    if all(l == vec3<i32>(0)) {
        return vec2<u32>(0u);
    }
    // 21 bits per coordinate, tag bit 63 (CellId::from_lattice).
    let m = 0x1fffffu;
    let x = bitcast<u32>(l.x) & m;
    let y = bitcast<u32>(l.y) & m;
    let z = bitcast<u32>(l.z) & m;
    let lo = x | (y << 21u);
    let hi = (y >> 11u) | (z << 10u) | 0x80000000u;
    return vec2<u32>(lo, hi);
#else
    let c = cell[3];
    let key = vec4<i32>(round(c * params.cell_scale.x));
    let origin = vec4<i32>(round(vec4<f32>(0.0, 0.0, 0.0, 1.0) * params.cell_scale.x));
    if all(key == origin) {
        return vec2<u32>(0u);
    }
    let lo = hash_key(key, 0x9e3779b9u);
    var hi = hash_key(key, 0x85ebca6bu) & 0x3fffffffu;
    if abs(c.w) >= params.cell_scale.y {
        hi |= 0x40000000u; // CellId::FAR, past the f32 horizon
    }
    return vec2<u32>(select(lo, 1u, lo == 0u && hi == 0u), hi);
#endif
}

#ifdef CELL_COLORS
// CellId::hash
fn cell_hash(id: vec2<u32>) -> u32 {
    return hash32(id.x ^ hash32(id.y));
}

// CellTint::tint
fn cell_color(id: vec2<u32>) -> vec3<f32> {
    let origin = id.x == 0u && id.y == 0u;
    if params.cell_mode == 1u {
        return select(vec3<f32>(1.0), vec3<f32>(1.0, 0.55, 0.15), id.x == params.cell_a && id.y == params.cell_b);
    }
    if params.cell_mode == 2u {
        return vec3<f32>(select(0.12, 1.0, origin || (cell_hash(id) >> 8u) < params.cell_a));
    }
    if origin {
        return vec3<f32>(1.0);
    }
    let h = cell_hash(id);
    return 0.25 + 0.75 * vec3<f32>(f32(h & 0xffu), f32((h >> 8u) & 0xffu), f32((h >> 16u) & 0xffu)) / 255.0;
}
#endif

// ---- meshes (src/mesh/bvh.rs, src/trace/mesh_hit.rs) ----
#ifdef MESHES

// mesh_data holds, per mesh: BVH nodes (two words each: min.xyz and
// first, max.xyz and count; an inner node's left child is the next node,
// `first` its right child), vertices (two words: position.xyz and u,
// normal.xyz and v), triangles (one word: three vertex indices) and
// texels (four RGBA8 per word). Floats are stored as their bits.
fn data_vec3(i: u32) -> vec3<f32> {
    return bitcast<vec3<f32>>(mesh_data[i].xyz);
}

// 1 / c, with |c| kept above 1e-20 so the slab test meets no infinity.
fn safe_inverse(c: vec3<f32>) -> vec3<f32> {
    let small = abs(c) < vec3<f32>(1.0e-20);
    return 1.0 / select(c, select(vec3<f32>(1.0e-20), vec3<f32>(-1.0e-20), c < vec3<f32>(0.0)), small);
}

// Entering s of o + s d into the box within [0, s_max]; -1 for a miss.
fn hit_box(o: vec3<f32>, inv_d: vec3<f32>, lo: vec3<f32>, hi: vec3<f32>, s_max: f32) -> f32 {
    let t0 = (lo - o) * inv_d;
    let t1 = (hi - o) * inv_d;
    let near = min(t0, t1);
    let far = max(t0, t1);
    let enter = max(max(near.x, near.y), max(near.z, 0.0));
    let leave = min(min(far.x, far.y), min(far.z, s_max));
    return select(-1.0, enter, enter <= leave);
}

// Moller-Trumbore, either side: (s, u, v), s = -1 for a miss.
fn hit_triangle(o: vec3<f32>, d: vec3<f32>, a: vec3<f32>, b: vec3<f32>, c: vec3<f32>) -> vec3<f32> {
    let miss = vec3<f32>(-1.0, 0.0, 0.0);
    let e1 = b - a;
    let e2 = c - a;
    let p = cross(d, e2);
    let det = dot(e1, p);
    if det == 0.0 {
        return miss;
    }
    let inv = 1.0 / det;
    let q = o - a;
    let u = dot(q, p) * inv;
    if u < 0.0 || u > 1.0 {
        return miss;
    }
    let r = cross(q, e1);
    let v = dot(d, r) * inv;
    if v < 0.0 || u + v > 1.0 {
        return miss;
    }
    let s = dot(e2, r) * inv;
    return select(miss, vec3<f32>(s, u, v), s >= 0.0);
}

struct MeshHit {
    s: f32,
    triangle: u32,
    u: f32,
    v: f32,
}

const BVH_STACK: u32 = 40u; // bvh.rs MAX_DEPTH

fn triangle_corner(inst: Instance, tri: vec4<u32>, k: u32) -> vec3<f32> {
    return data_vec3(inst.vertices + 2u * tri[k]);
}

// The nearest hit through the hierarchy, nearer child first.
fn hit_mesh(inst: Instance, o: vec3<f32>, d: vec3<f32>, s_max: f32) -> MeshHit {
    let inv_d = safe_inverse(d);
    var best = MeshHit(-1.0, 0u, 0.0, 0.0);
    var limit = s_max;
    var stack: array<u32, 40>;
    var top = 1u;
    stack[0] = 0u;
    // Every node is visited at most once: a hard bound on the loop.
    for (var guard = 0u; guard < inst.node_count && top > 0u; guard++) {
        top -= 1u;
        let index = stack[top];
        let w0 = mesh_data[inst.nodes + 2u * index];
        let w1 = mesh_data[inst.nodes + 2u * index + 1u];
        if hit_box(o, inv_d, bitcast<vec3<f32>>(w0.xyz), bitcast<vec3<f32>>(w1.xyz), limit) < 0.0 {
            continue;
        }
        if w1.w > 0u {
            for (var t = w0.w; t < w0.w + w1.w; t++) {
                let tri = mesh_data[inst.triangles + t];
                let h = hit_triangle(o, d, triangle_corner(inst, tri, 0u), triangle_corner(inst, tri, 1u), triangle_corner(inst, tri, 2u));
                if h.x >= 0.0 && h.x <= limit {
                    limit = h.x;
                    best = MeshHit(h.x, t, h.y, h.z);
                }
            }
            continue;
        }
        let l = index + 1u;
        let r = w0.w;
        let lw0 = mesh_data[inst.nodes + 2u * l];
        let lw1 = mesh_data[inst.nodes + 2u * l + 1u];
        let rw0 = mesh_data[inst.nodes + 2u * r];
        let rw1 = mesh_data[inst.nodes + 2u * r + 1u];
        let nl = hit_box(o, inv_d, bitcast<vec3<f32>>(lw0.xyz), bitcast<vec3<f32>>(lw1.xyz), limit);
        let nr = hit_box(o, inv_d, bitcast<vec3<f32>>(rw0.xyz), bitcast<vec3<f32>>(rw1.xyz), limit);
        if nl >= 0.0 && nr >= 0.0 {
            let first = select(r, l, nl <= nr);
            let second = select(l, r, nl <= nr);
            if top < BVH_STACK {
                stack[top] = second;
                top += 1u;
            }
            if top < BVH_STACK {
                stack[top] = first;
                top += 1u;
            }
        } else if nl >= 0.0 {
            if top < BVH_STACK {
                stack[top] = l;
                top += 1u;
            }
        } else if nr >= 0.0 {
            if top < BVH_STACK {
                stack[top] = r;
                top += 1u;
            }
        }
    }
    return best;
}

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

fn srgb_to_linear(c: f32) -> f32 {
    return select(pow((c + 0.055) / 1.055, 2.4), c / 12.92, c <= 0.04045);
}

fn texel_index(x: f32, n: u32) -> u32 {
    let f = x - floor(x);
    return min(u32(f * f32(n)), n - 1u);
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
#endif

// ---- Algorithm 1 (src/trace/render.rs) ----

struct Hit {
    t: f32,
    // 0 none, 1 ball, 2 tube, 3 mesh instance
    kind: u32,
    index: u32,
    // A mesh hit: triangle and barycentrics.
    triangle: u32,
    u: f32,
    v: f32,
}

// The nearest object on the ray within [0, t_end], at `level` transports
// (a mesh attached to the camera is skipped at 0).
fn nearest_object(ray: Ray, t_end: f32, level: u32) -> Hit {
    var best = Hit(-1.0, 0u, 0u, 0u, 0.0, 0.0);
#ifdef BALLS
    for (var i = 0u; i < params.ball_count; i++) {
        let t = hit_ball(ray, balls[i].center, balls[i].k, 0.0);
        if t >= 0.0 && t <= t_end && (best.kind == 0u || t < best.t) {
            best = Hit(t, 1u, i, 0u, 0.0, 0.0);
        }
    }
#endif
#ifdef TUBES
    for (var i = 0u; i < params.tube_count; i++) {
        let t = hit_tube(ray, tubes[i], params.tube_k, 0.0);
        if t >= 0.0 && t <= t_end && (best.kind == 0u || t < best.t) {
            best = Hit(t, 2u, i, 0u, 0.0, 0.0);
        }
    }
#endif
#ifdef MESHES
    for (var i = 0u; i < params.instance_count; i++) {
        if instances[i].attached != 0u && level == 0u {
            continue;
        }
        let limit = select(t_end, best.t, best.kind != 0u);
        let h = hit_instance(ray, instances[i], limit);
        if h.t >= 0.0 && h.t <= limit {
            best = Hit(h.t, 3u, i, h.hit.triangle, h.hit.u, h.hit.v);
        }
    }
#endif
    return best;
}

fn shade(ray: Ray, hit: Hit, dist: f32, cell: vec2<u32>) -> vec3<f32> {
    let x = normalize_point(ray.origin + ray.dir * hit.t);
    let view = -normalize_tangent(x, ray.dir);
    var normal = vec4<f32>(0.0);
    var albedo = vec3<f32>(1.0);
#ifdef BALLS
    if hit.kind == 1u {
        normal = normal_from(x, balls[hit.index].center);
        albedo = balls[hit.index].color;
    }
#endif
#ifdef TUBES
    if hit.kind == 2u {
        let seg = tubes[hit.index];
        normal = normal_from(x, foot_on_line(x, seg));
        albedo = seg.color.xyz;
    }
#endif
#ifdef MESHES
    if hit.kind == 3u {
        let inst = instances[hit.index];
        let h = MeshHit(0.0, hit.triangle, hit.u, hit.v);
        normal = mesh_normal(inst, h, x, view);
        albedo = mesh_albedo(inst, h);
    }
#endif
#ifdef CELL_COLORS
    albedo *= cell_color(cell);
#endif
    var rgb = albedo * 0.08;
#ifdef LIGHTS
    for (var i = 0u; i < params.light_count; i++) {
        let l = lights[i];
        let d = distance(x, l.position);
        let to_light = normalize_tangent(x, l.position);
        let irradiance = l.intensity / max(sphere_area(d), 1.0e-4);
        let lambert = max(form(normal, to_light), 0.0);
        let half = to_light + view;
        let hl = sqrt(form(half, half));
        var spec = 0.0;
        if hl > 1.0e-12 {
            spec = pow(max(form(normal, half) / hl, 0.0), 32.0) * 0.35;
        }
        rgb += (albedo * lambert + spec) * irradiance * l.color;
    }
#endif
#ifdef FOG
    let tr = exp(-(params.fog_density * dist));
    rgb = rgb * tr + params.fog_color.xyz * (1.0 - tr);
#endif
    return rgb;
}

// The pixel's view direction in the camera's frame (unit, -z forward).
fn view_direction(i: u32, j: u32) -> vec4<f32> {
    let w = f32(params.width);
    let h = f32(params.height);
    let x = 2.0 * (f32(i) + 0.5) / w - 1.0;
    let y = 1.0 - 2.0 * (f32(j) + 0.5) / h;
    let d = vec4<f32>(x * params.tan_half_fov * (w / h), y * params.tan_half_fov, -1.0, 0.0);
    return d * (1.0 / sqrt(dot(d, d)));
}

fn camera_ray(i: u32, j: u32) -> Ray {
    let d = view_direction(i, j);
    let o = normalize_point(params.camera * vec4<f32>(0.0, 0.0, 0.0, 1.0));
    return Ray(o, normalize_tangent(o, params.camera * d));
}

fn background() -> vec3<f32> {
#ifdef FOG
    return params.fog_color.xyz;
#else
    return vec3<f32>(0.0);
#endif
}

// Algorithm 1 for the pixel (i, j) of the view.
fn trace_pixel(i: u32, j: u32) -> Pixel {
    var ray = camera_ray(i, j);
    var cell = params.camera_cell;
    var index = params.camera_cell_index;
    var entered = NO_FACE;
    var levels = 0u;
    var travelled = 0.0;
    let t_cap = max_chart_parameter();
    // The same hard bound as the CPU: transports, plus (S3) unit advances.
    let max_passes = params.levels + u32(min(params.max_distance, 1.0e4)) + 2u;
    for (var step = 0u; step < max_passes; step++) {
#ifdef FOG
        let early_stop = (params.flags & FLAG_NO_EARLY_STOP) == 0u;
        if early_stop && params.fog_density * travelled > 5.5412712 { // ln 255
            break;
        }
#endif
        var exit = exit_face(ray, entered);
        if exit.face != NO_FACE && exit.t >= t_cap {
            exit.face = NO_FACE;
        }
        let t_end = select(exit.t, t_cap, exit.face == NO_FACE);
        let hit = nearest_object(ray, t_end, levels);
        if hit.kind != 0u {
            let dist = travelled + chart_to_distance(hit.t);
            let cid = cell_id(cell, index);
            var object = EDGE_ID;
#ifdef BALLS
            if hit.kind == 1u {
                object = balls[hit.index].id;
            }
#endif
#ifdef MESHES
            if hit.kind == 3u {
                object = instances[hit.index].id;
            }
#endif
            return Pixel(vec4<f32>(shade(ray, hit, dist, cid), dist), object, levels, cid.x, cid.y);
        }
        let end = advance_or_raw(ray, t_end);
        travelled += chart_to_distance(t_end);
        if travelled > params.max_distance {
            break;
        }
        if exit.face == NO_FACE {
            // S3 only: no face within a quarter turn; go on from here.
            ray = end;
            entered = NO_FACE;
            continue;
        }
        if levels >= params.levels {
            break;
        }
        ray = transport_or_raw(exit.face, end);
        entered = faces[exit.face].partner;
        cell = cell * faces[exit.face].crossing;
#ifdef CELLS_FINITE
        index = cell_table[index * params.face_count + faces[exit.face].partner];
#endif
        levels++;
    }
    let cid = cell_id(cell, index);
    return Pixel(vec4<f32>(background(), travelled), 0u, levels, cid.x, cid.y);
}

@compute @workgroup_size(8, 8, 1)
fn trace(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.width || id.y >= params.height {
        return;
    }
    pixels[id.y * params.width + id.x] = trace_pixel(id.x, id.y);
}

// The drift probe (`bench stability`, tests/stability.rs), twin of
// trace::ray_drift: the camera ray of the pixel walked as trace_pixel walks
// it, objects ignored, through levels transports. Writes the worst point
// and tangent errors over every segment end to color.xy, how far outside
// the domain any end was to color.z, the distance to color.w and the
// transports made to levels.
fn ray_errors(ray: Ray) -> vec3<f32> {
    let c = ray.origin / ray.origin.w;
    var outside = -3.0e38;
    for (var i = 0u; i < params.face_count; i++) {
        outside = max(outside, dot(faces[i].plane, c));
    }
    return vec3<f32>(point_error(ray.origin), tangent_error(ray.origin, ray.dir), outside);
}

@compute @workgroup_size(8, 8, 1)
fn drift(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.width || id.y >= params.height {
        return;
    }
    var ray = camera_ray(id.x, id.y);
    var entered = NO_FACE;
    var levels = 0u;
    var travelled = 0.0;
    var worst = ray_errors(ray);
    let t_cap = max_chart_parameter();
    let max_passes = params.levels + u32(min(params.max_distance, 1.0e4)) + 2u;
    for (var step = 0u; step < max_passes; step++) {
        var exit = exit_face(ray, entered);
        if exit.face != NO_FACE && exit.t >= t_cap {
            exit.face = NO_FACE;
        }
        let t_end = select(exit.t, t_cap, exit.face == NO_FACE);
        let end = advance_or_raw(ray, t_end);
        travelled += chart_to_distance(t_end);
        worst = max(worst, ray_errors(end));
        if travelled > params.max_distance {
            break;
        }
        if exit.face == NO_FACE {
            ray = end;
            entered = NO_FACE;
            continue;
        }
        if levels >= params.levels {
            break;
        }
        ray = transport_or_raw(exit.face, end);
        entered = faces[exit.face].partner;
        levels++;
        worst = max(worst, ray_errors(ray));
    }
    pixels[id.y * params.width + id.x] = Pixel(vec4<f32>(worst, travelled), 0u, levels, 0u, 0u);
}

#ifdef ENCODE_SRGB
fn encode_srgb(c: vec3<f32>) -> vec3<f32> {
    let x = clamp(c, vec3<f32>(0.0), vec3<f32>(1.0));
    return select(1.055 * pow(x, vec3<f32>(1.0 / 2.4)) - 0.055, 12.92 * x, x <= vec3<f32>(0.0031308));
}
#endif

struct FragmentOutput {
    @location(0) color: vec4<f32>,
    @builtin(frag_depth) depth: f32,
}

@fragment
fn fragment(@builtin(position) position: vec4<f32>) -> FragmentOutput {
    let i = u32(position.x) - params.origin_x;
    let j = u32(position.y) - params.origin_y;
    let p = trace_pixel(i, j);
    var rgb = p.color.xyz;
#ifdef ENCODE_SRGB
    rgb = encode_srgb(rgb);
#endif
    // Reverse-z depth of the hit along the view axis, so ordinary Bevy
    // meshes drawn after the trace (overlays, a HUD) sort against it;
    // 0 (infinitely far) where nothing was hit.
    var depth = 0.0;
    if p.object != 0u {
        let along = p.color.w * -view_direction(i, j).z;
        depth = params.near / max(along, params.near);
    }
    return FragmentOutput(vec4<f32>(rgb, 1.0), depth);
}
