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
//   BALLS, TUBES       which object kinds the scene has
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
    max_level: u32,
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
    _pad0: u32,
    // CELLS_LATTICE: 1 / edge lengths of the box; CELLS_HASHED: 1 / grid
    // step in x, the f32 horizon (HASHED_HORIZON_F32) in y.
    cell_scale: vec4<f32>,
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
@group(0) @binding(6) var<storage, read_write> pixels: array<Pixel>;

const EDGE_ID: u32 = 255u;
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

fn transport(face: u32, ray: Ray) -> Ray {
#ifdef TRANSLATIONS_ONLY
    // A translation moves the point and leaves directions alone.
    return Ray(faces[face].pairing * ray.origin, ray.dir);
#else
    let o = normalize_point(faces[face].pairing * ray.origin);
    return Ray(o, normalize_tangent(o, faces[face].pairing * ray.dir));
#endif
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

#ifdef BALLS
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
fn cell_color(id: vec2<u32>) -> vec3<f32> {
    if id.x == 0u && id.y == 0u {
        return vec3<f32>(1.0);
    }
    let h = hash32(id.x ^ hash32(id.y));
    return 0.25 + 0.75 * vec3<f32>(f32(h & 0xffu), f32((h >> 8u) & 0xffu), f32((h >> 16u) & 0xffu)) / 255.0;
}
#endif

// ---- Algorithm 1 (src/trace/render.rs) ----

struct Hit {
    t: f32,
    // 0 none, 1 ball, 2 tube
    kind: u32,
    index: u32,
}

fn nearest_object(ray: Ray, t_end: f32) -> Hit {
    var best = Hit(-1.0, 0u, 0u);
#ifdef BALLS
    for (var i = 0u; i < params.ball_count; i++) {
        let t = hit_ball(ray, balls[i].center, balls[i].k, 0.0);
        if t >= 0.0 && t <= t_end && (best.kind == 0u || t < best.t) {
            best = Hit(t, 1u, i);
        }
    }
#endif
#ifdef TUBES
    for (var i = 0u; i < params.tube_count; i++) {
        let t = hit_tube(ray, tubes[i], params.tube_k, 0.0);
        if t >= 0.0 && t <= t_end && (best.kind == 0u || t < best.t) {
            best = Hit(t, 2u, i);
        }
    }
#endif
    return best;
}

fn shade(ray: Ray, hit: Hit, dist: f32, cell: vec2<u32>) -> vec3<f32> {
    let x = normalize_point(ray.origin + ray.dir * hit.t);
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
#ifdef CELL_COLORS
    albedo *= cell_color(cell);
#endif
    var rgb = albedo * 0.08;
#ifdef LIGHTS
    let view = -normalize_tangent(x, ray.dir);
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
    let max_passes = params.max_level + u32(min(params.max_distance, 1.0e4)) + 2u;
    for (var step = 0u; step < max_passes; step++) {
#ifdef FOG
        if params.fog_density * travelled > 5.5412712 { // ln 255
            break;
        }
#endif
        var exit = exit_face(ray, entered);
        if exit.face != NO_FACE && exit.t >= t_cap {
            exit.face = NO_FACE;
        }
        let t_end = select(exit.t, t_cap, exit.face == NO_FACE);
        let hit = nearest_object(ray, t_end);
        if hit.kind != 0u {
            let dist = travelled + chart_to_distance(hit.t);
            let cid = cell_id(cell, index);
            var object = EDGE_ID;
#ifdef BALLS
            if hit.kind == 1u {
                object = balls[hit.index].id;
            }
#endif
            return Pixel(vec4<f32>(shade(ray, hit, dist, cid), dist), object, levels, cid.x, cid.y);
        }
        let end = advance(ray, t_end);
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
        if levels >= params.max_level {
            break;
        }
        ray = transport(exit.face, end);
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
