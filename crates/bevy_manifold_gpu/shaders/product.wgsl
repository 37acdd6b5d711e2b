// The tracer of the product spaces (H2xR, S2xR) on the GPU, in f32.
// Rust twin: crates/bevy_manifold_core/src/trace/product/mod.rs (the walk
// through the faces and the balls' entries), its `view.rs` (the pixel)
// and its `light.rs` (the lights, their arcs and shadows); the geometry
// is the core's geometry/product.rs. A ray follows
// its exact geodesic through the prism, leaves through the nearest face
// (in closed form) and goes on from the gluing's image of its exit point.
// Balls are geodesic balls of the product metric, found by sphere
// tracing. The Rust side packs the inputs: `GpuProductScene::pack`.
// A ray counts the copy of the prism it is in as the core's exact cells
// do (space/product_cells.rs): an index in the table of cells around the
// camera for the surface part, its flip and steps up the line apart.
// Specialised on what a scene needs (`ProductShaderDefs`): PRODUCT_CELLS
// where a table of cells is bound (else every copy's id is
// BEYOND_TABLE), PRODUCT_LIGHTS where the scene has lights (else the
// balls are lit from the eye), PRODUCT_EDGES where it draws the prism's
// edges, PRODUCT_MESHES where it has meshes (Rust twin:
// trace/product/mesh.rs).

#import bevy_manifold::cell_tint::{hash32, cell_tint}

// Rust twin: `GpuProductParams`.
struct ProductParams {
    eye: vec4<f32>,
    forward: vec4<f32>,
    right: vec4<f32>,
    up: vec4<f32>,
    fog_color: vec4<f32>,
    frustum: vec4<f32>,
    edges: vec4<f32>,
    width: u32,
    height: u32,
    max_crossings: u32,
    side_count: u32,
    ball_count: u32,
    curvature: f32,
    half_height: f32,
    max_distance: f32,
    tan_half_fov: f32,
    fog: f32,
    origin_x: u32,
    origin_y: u32,
    tint_mode: u32,
    tint_a: u32,
    tint_b: u32,
    cell_count: u32,
    camera_steps: i32,
    camera_flip: i32,
    light_count: u32,
    shadows: u32,
    mesh_count: u32,
    pad_a: u32,
    pad_b: u32,
    pad_c: u32,
}

// Rust twin: `GpuProductFace`.
struct ProductFace {
    normal: vec4<f32>,
    corner: vec4<f32>,
    surface: mat3x3<f32>,
    flip: f32,
    shift: f32,
    partner: u32,
    cross_steps: i32,
}

// Rust twin: `GpuProductBall`.
struct ProductBall {
    center: vec4<f32>,
    color: vec4<f32>,
    radius: f32,
    id: u32,
    reach_trig: f32,
    pad: u32,
}

// One image of a light: its colour (rgb) and power (w), and a spot's
// cone (the cosines of its angles, its axis at the image; a zero axis for
// a point light). Rust twin: `GpuProductLight` (the core's
// `ProductLightImage`).
struct ProductLight {
    position: vec4<f32>,
    color: vec4<f32>,
    inv_range_sq: f32,
    min_area: f32,
    spot_inner: f32,
    spot_outer: f32,
    spot_axis: vec4<f32>,
}

// A mesh or one of its images through the faces: the isometry taking the
// prism to its chart (`to_chart`, `to_flip`, `to_shift`) and the surface
// part of its inverse (`placement`, for the normals), its chart's origin
// in the prism, how far it reaches from there (`across` the surface,
// `tall` up and down; `across_trig` cosh or cos of `across`), its
// colour, id, and its nodes and triangles in `mesh_data`. Rust twin:
// `GpuProductMesh` (the core's `ProductMeshImage`).
struct ProductMesh {
    to_chart: mat3x3<f32>,
    placement: mat3x3<f32>,
    center: vec4<f32>,
    color: vec4<f32>,
    to_flip: f32,
    to_shift: f32,
    across: f32,
    across_trig: f32,
    tall: f32,
    id: u32,
    nodes: u32,
    triangles: u32,
}

// Rust twin: `GpuProductPixel`.
struct ProductPixel {
    color: vec4<f32>,
    object: u32,
    crossings: u32,
    cell: vec2<u32>,
}

// The copy of the prism a ray is in, from the camera's: its surface
// part's index in the table (PRODUCT_OUTSIDE past it) and its line part.
// Rust twin: `ProductElement` (the walk's, before the camera's copy).
struct ProductCell {
    index: u32,
    steps: i32,
    flip: i32,
}

// A point (or tangent) is the surface's model point (xyz) and the height
// (w). Rust twin: `ProductRay`.
struct ProductRay {
    origin: vec4<f32>,
    dir: vec4<f32>,
}

@group(0) @binding(0) var<uniform> params: ProductParams;
@group(0) @binding(1) var<storage, read> faces: array<ProductFace>;
@group(0) @binding(2) var<storage, read> balls: array<ProductBall>;
@group(0) @binding(3) var<storage, read_write> pixels: array<ProductPixel>;
// The table of cells around the camera: `neighbours[k * faces + f]`, then
// each cell's tile seen from the camera (two words). Rust twin:
// `ProductCellTable` (its `neighbours` and `tiles_around`).
@group(0) @binding(4) var<storage, read> cells: array<u32>;
// The light images. Rust twin: `light_images` (packed by
// `GpuProductScene::pack_lights`).
@group(0) @binding(5) var<storage, read> lights: array<ProductLight>;
// The meshes and their images, and their BVHs and triangles (floats by
// their bits): per node two words of four (its box's min and its leaf's
// triangle count; its max and its first triangle, or for an inner node
// the node past its subtree), per triangle six (its corners, then their
// normals, xyz).
// Rust twin: `GpuProductScene::meshes` and `mesh_data`.
@group(0) @binding(6) var<storage, read> meshes: array<ProductMesh>;
@group(0) @binding(7) var<storage, read> mesh_data: array<vec4<u32>>;

// A neighbour not in the table. Rust twin: `OUTSIDE`.
const PRODUCT_OUTSIDE: u32 = 0xffffffffu;
// CellId::BEYOND_TABLE's words.
const BEYOND_TABLE: vec2<u32> = vec2<u32>(0u, 0x40000000u);

// No face.
const NO_FACE: u32 = 0xffffffffu;
// The id a hit on an edge's tube reports. Rust twin: `EDGE_ID`.
const EDGE_ID: u32 = 0xfffffffeu;
// Smallest sphere-tracing step, and how near a surface counts as on it
// (f32: the CPU's `SURFACE` is 1e-12).
const SURFACE: f32 = 1e-5;
// Most sphere-tracing steps per ball and segment (the CPU's `MAX_STEPS`
// is 20,000; a graze past this counts as a miss).
const MAX_STEPS: u32 = 256u;

// The surface's form <u, v> = ux vx + uy vy + k uw vw. Rust twin:
// `ProductGeometry::form`.
fn form(u: vec3<f32>, v: vec3<f32>) -> f32 {
    return u.x * v.x + u.y * v.y + params.curvature * u.z * v.z;
}

// (cosh s, sinh s) on H2, (cos s, sin s) on S2. Rust twin:
// `ProductGeometry::trig`.
fn trig(s: f32) -> vec2<f32> {
    if params.curvature < 0.0 {
        return vec2<f32>(cosh(s), sinh(s));
    }
    return vec2<f32>(cos(s), sin(s));
}

// The distance on the surface, stable near and far. Rust twin:
// `ProductGeometry::surface_distance`.
fn surface_distance(p: vec3<f32>, q: vec3<f32>) -> f32 {
    let d = p - q;
    if params.curvature < 0.0 {
        return 2.0 * asinh(sqrt(max(form(d, d), 0.0)) * 0.5);
    }
    return 2.0 * atan2(length(d), length(p + q));
}

// Rust twin: `ProductGeometry::distance`.
fn product_distance(p: vec4<f32>, q: vec4<f32>) -> f32 {
    let s = surface_distance(p.xyz, q.xyz);
    let h = p.w - q.w;
    return sqrt(s * s + h * h);
}

// The ray moved s along its geodesic. Rust twin: `advance` (and
// `ProductGeometry::exp`).
fn advance(ray: ProductRay, s: f32) -> ProductRay {
    let speed = sqrt(max(form(ray.dir.xyz, ray.dir.xyz), 0.0));
    let height = ray.origin.w + ray.dir.w * s;
    if speed == 0.0 {
        return ProductRay(vec4<f32>(ray.origin.xyz, height), ray.dir);
    }
    let u = ray.dir.xyz / speed;
    let cs = trig(speed * s);
    let p = ray.origin.xyz;
    let surface = p * cs.x + u * cs.y;
    let along = (u * cs.x - p * (params.curvature * cs.y)) * speed;
    return ProductRay(vec4<f32>(surface, height), vec4<f32>(along, ray.dir.w));
}

// p put back on the surface's model. Rust twin:
// `ProductGeometry::normalize_point`.
fn normalize_point(p: vec4<f32>) -> vec4<f32> {
    let n = sqrt(abs(form(p.xyz, p.xyz) * params.curvature));
    return vec4<f32>(p.xyz / n, p.w);
}

// v made tangent at p and of unit length. Rust twin:
// `ProductGeometry::normalize_tangent`.
fn normalize_tangent(p: vec4<f32>, v: vec4<f32>) -> vec4<f32> {
    let s = v.xyz - p.xyz * (form(v.xyz, p.xyz) * params.curvature);
    return unit(vec4<f32>(s, v.w));
}

// Rust twin: `ProductTangent::unit`.
fn unit(v: vec4<f32>) -> vec4<f32> {
    return v / sqrt(max(form(v.xyz, v.xyz), 0.0) + v.w * v.w);
}

// The ray carried through face f: the gluing's image, put back on the
// model. Rust twin: `transport`.
fn transport(f: u32, ray: ProductRay) -> ProductRay {
    let m = faces[f];
    let origin = normalize_point(vec4<f32>(m.surface * ray.origin.xyz, m.flip * ray.origin.w + m.shift));
    let dir = normalize_tangent(origin, vec4<f32>(m.surface * ray.dir.xyz, m.flip * ray.dir.w));
    return ProductRay(origin, dir);
}

// The face the ray leaves through (NO_FACE for none) and the distance to
// it. Rust twin: `exit_face`.
struct Exit {
    face: u32,
    s: f32,
}

fn exit_face(ray: ProductRay, skip: u32) -> Exit {
    var best = Exit(NO_FACE, 0.0);
    let speed = sqrt(max(form(ray.dir.xyz, ray.dir.xyz), 0.0));
    if speed > 0.0 {
        for (var f = 0u; f < params.side_count; f++) {
            if f == skip {
                continue;
            }
            let n = faces[f].normal.xyz;
            let a = form(n, ray.origin.xyz);
            let b = form(n, ray.dir.xyz) / speed;
            var sigma = -1.0;
            if params.curvature < 0.0 {
                if b > 0.0 && -a < b {
                    sigma = atanh(-a / b);
                } else {
                    continue;
                }
            } else if b > 0.0 || a < 0.0 {
                sigma = atan2(-a, b);
            } else {
                continue;
            }
            let s = max(sigma / speed, 0.0);
            if best.face == NO_FACE || s < best.s {
                best = Exit(f, s);
            }
        }
    }
    let h = ray.origin.w;
    var vertical = NO_FACE;
    var s = 0.0;
    if ray.dir.w > 0.0 {
        vertical = params.side_count + 1u;
        s = (params.half_height - h) / ray.dir.w;
    } else if ray.dir.w < 0.0 {
        vertical = params.side_count;
        s = (-params.half_height - h) / ray.dir.w;
    }
    if vertical != NO_FACE && vertical != skip && (best.face == NO_FACE || s < best.s) {
        best = Exit(vertical, max(s, 0.0));
    }
    return best;
}

// How much farther than its radius a ball is looked for (f32 rounding;
// the CPU tracer's is 1e-9). Rust twin: `REACH_SLACK` (of the GPU crate's
// product.rs, which packs `reach_trig` with it).
const REACH_SLACK: f32 = 1e-3;

// The part (x, y) of the segment [0, length] in which the ray may come
// within `radius` of `center`: its height within `radius` of the centre's
// and its surface geodesic within `radius` of the centre's surface point,
// in closed form (a quadratic in e^t on H2, windows of the circle on S2).
// x > y where the segment never comes near. Rust twin: `reach`.
// `trig` is cosh (H2) or cos (S2) of the radius.
fn reach(ray: ProductRay, center: vec4<f32>, radius: f32, trig: f32, length: f32) -> vec2<f32> {
    let span = height_window(ray, center.w, radius, length);
    if span.x > span.y {
        return span;
    }
    return surface_window(ray, center.xyz, radius, trig, span);
}

// The part (x, y) of [0, length] of the ray whose height is within
// `radius` of `height`; x > y for none. Rust twin: `height_window`.
fn height_window(ray: ProductRay, height: f32, radius: f32, length: f32) -> vec2<f32> {
    let none = vec2<f32>(1.0, -1.0);
    let dh = ray.origin.w - height;
    let v = ray.dir.w;
    var lo = 0.0;
    var hi = length;
    if v == 0.0 {
        if abs(dh) > radius {
            return none;
        }
    } else {
        let a = (-radius - dh) / v;
        let b = (radius - dh) / v;
        lo = max(lo, min(a, b));
        hi = min(hi, max(a, b));
    }
    if lo > hi {
        return none;
    }
    return vec2<f32>(lo, hi);
}

// The part of `span` of the ray whose surface geodesic comes within
// `radius` of the surface point q, in closed form; x > y for none. Rust
// twin: `surface_window`. `trig` is cosh (H2) or cos (S2) of the radius.
fn surface_window(ray: ProductRay, q: vec3<f32>, radius: f32, trig: f32, span: vec2<f32>) -> vec2<f32> {
    let none = vec2<f32>(1.0, -1.0);
    let lo = span.x;
    let hi = span.y;
    let p = ray.origin.xyz;
    let speed = sqrt(max(form(ray.dir.xyz, ray.dir.xyz), 0.0));
    if speed == 0.0 {
        if surface_distance(p, q) <= radius {
            return vec2<f32>(lo, hi);
        }
        return none;
    }
    let u = ray.dir.xyz / speed;
    var t = vec2<f32>(0.0, 0.0);
    if params.curvature < 0.0 {
        let a = -form(p, q);
        let b = -form(u, q);
        let c = trig;
        // (a + b) x^2 - 2 c x + (a - b) <= 0, x = e^t; a > |b|.
        let disc = c * c - (a * a - b * b);
        if disc < 0.0 {
            return none;
        }
        let root = sqrt(disc);
        t = vec2<f32>(log(max(c - root, 0.0) / (a + b)), log((c + root) / (a + b)));
    } else {
        let a = form(p, q);
        let b = form(u, q);
        let amp = sqrt(a * a + b * b);
        let c = trig;
        if amp < c {
            return none;
        }
        // cos(t - phi) >= c / amp: windows phi +- w, every turn.
        let w = acos(clamp(c / amp, -1.0, 1.0));
        let phi = atan2(b, a);
        let turn = 6.2831855;
        let k = ceil((speed * lo - phi - w) / turn);
        let start = phi - w + turn * k;
        var stop = start + 2.0 * w;
        // A later window within the segment: look on to its end.
        if start + turn <= speed * hi {
            stop = 3.4e38;
        }
        t = vec2<f32>(start, stop);
    }
    return vec2<f32>(max(lo, t.x / speed), min(hi, t.y / speed));
}

// The first distance in [span.x, span.y] (the segment's reach of the
// ball) at which the ray enters ball b from outside, by sphere tracing;
// -1 for none. Rust twin: `entries` (its first entry), which in H2xR
// finds it by Newton's method instead (`first_entry_convex`): in f64, to
// 1e-12, that takes a tenth of the steps; here, to SURFACE in f32, it
// measured no faster on lavapipe, and two loops slowed both.
fn first_entry(ray: ProductRay, b: u32, span: vec2<f32>) -> f32 {
    let center = balls[b].center;
    let radius = balls[b].radius;
    let end = span.y;
    var s = span.x;
    var f = product_distance(advance(ray, s).origin, center) - radius;
    var outside = f > SURFACE;
    for (var k = 0u; k < MAX_STEPS; k++) {
        if outside && f <= SURFACE {
            return s;
        }
        if !outside && f > SURFACE {
            outside = true;
        }
        s += max(abs(f), SURFACE);
        if s > end {
            return -1.0;
        }
        f = product_distance(advance(ray, s).origin, center) - radius;
    }
    return -1.0;
}

// The nearest ball the segment of `length` from the ray's origin enters:
// (its index, or NO_FACE, and the distance). Rust twin: `hits_in` (one
// segment's entries, the nearest kept).
struct Entry {
    ball: u32,
    s: f32,
}

fn nearest_entry(ray: ProductRay, length: f32) -> Entry {
    var best = Entry(NO_FACE, length);
    for (var b = 0u; b < params.ball_count; b++) {
        let span = reach(ray, balls[b].center, balls[b].radius + REACH_SLACK, balls[b].reach_trig, best.s);
        if span.x > span.y {
            continue;
        }
        let s = first_entry(ray, b, span);
        if s >= 0.0 && (best.ball == NO_FACE || s < best.s) {
            best = Entry(b, s);
        }
    }
    return best;
}

#ifdef PRODUCT_EDGES
// The point of edge e nearest p (a point of the prism): e below
// side_count the vertical edge over corner e, then each side at the
// bottom, then at the top (its foot where that falls between the side's
// corners, else the nearer corner). Rust twin: `ProductEdge::nearest`.
fn edge_point(e: u32, p: vec4<f32>) -> vec4<f32> {
    let n = params.side_count;
    if e < n {
        return vec4<f32>(faces[e].corner.xyz, p.w);
    }
    let i = (e - n) % n;
    let height = select(-params.half_height, params.half_height, e >= 2u * n);
    let a = faces[(i + n - 1u) % n].corner.xyz;
    let b = faces[i].corner.xyz;
    let normal = faces[i].normal.xyz;
    let q = p.xyz;
    let k = params.curvature;
    let between = form(q, b - a * (k * form(a, b))) >= 0.0 && form(q, a - b * (k * form(a, b))) >= 0.0;
    var foot = a;
    if between {
        foot = normalize_point(vec4<f32>(q - normal * form(q, normal), height)).xyz;
    } else if surface_distance(q, b) < surface_distance(q, a) {
        foot = b;
    }
    return vec4<f32>(foot, height);
}

// The ray's surface point at the start of span (xyz), and how far (as
// |<p, n>|, w) a line <n, p> = 0 may be from it for the ray's surface part
// to come within `radius` of it on span: sinh d = |<p, n>| (sin d on S2),
// and the ray moves speed (span.y - span.x) over the surface. Rust twin:
// `line_bound`.
fn line_bound(ray: ProductRay, radius: f32, span: vec2<f32>) -> vec4<f32> {
    let speed = sqrt(max(form(ray.dir.xyz, ray.dir.xyz), 0.0));
    let reach = radius + speed * (span.y - span.x);
    let p = advance(ray, span.x).origin.xyz;
    if params.curvature > 0.0 && reach >= 1.5707964 {
        return vec4<f32>(p, 3.4e38);
    }
    return vec4<f32>(p, trig(reach).y);
}

// The first distance in span (the part of the ray within the radius of
// the edge's height) at which the ray enters the tube about edge e from
// outside, by sphere tracing; -1 for none. Past the ray's origin the span
// starts outside the tube (the height alone is the radius away). Rust
// twin: `traced_entry`. The same loop as first_entry's, kept apart: one
// loop for both (a branch a step between a ball and an edge) made frames
// with edges 1.2 to 1.5 times slower on lavapipe.
fn tube_entry(ray: ProductRay, e: u32, span: vec2<f32>) -> f32 {
    let radius = params.edges.w;
    var s = span.x;
    var x = advance(ray, s).origin;
    var f = product_distance(x, edge_point(e, x)) - radius;
    var outside = f > SURFACE || span.x > 0.0;
    for (var k = 0u; k < MAX_STEPS; k++) {
        if outside && f <= SURFACE {
            return s;
        }
        if !outside && f > SURFACE {
            outside = true;
        }
        s += max(abs(f), SURFACE);
        if s > span.y {
            return -1.0;
        }
        x = advance(ray, s).origin;
        f = product_distance(x, edge_point(e, x)) - radius;
    }
    return -1.0;
}

// The nearest edge tube the segment of `length` from the ray's origin
// enters: (its edge, or NO_FACE, and the distance). A vertical edge's
// tube in closed form (surface_window), a side's by tube_entry on the
// part of the ray near its height. Rust twin: `ProductTubes::entry`.
struct EdgeEntry {
    edge: u32,
    s: f32,
}

fn edge_entry(ray: ProductRay, length: f32) -> EdgeEntry {
    var best = EdgeEntry(NO_FACE, length);
    let radius = params.edges.w;
    let n = params.side_count;
    let k = params.curvature;
    let cos_r = trig(radius).x;
    for (var e = 0u; e < n; e++) {
        let corner = faces[e].corner.xyz;
        // cosh (H2) or cos (S2) of the distance to the corner: a ray that
        // starts inside the tube does not enter it.
        let c = k * form(ray.origin.xyz, corner);
        if (k < 0.0 && c <= cos_r) || (k > 0.0 && c >= cos_r) {
            continue;
        }
        let span = surface_window(ray, corner, radius, cos_r, vec2<f32>(0.0, best.s));
        if span.x <= span.y {
            best = EdgeEntry(e, span.x);
        }
    }
    for (var top = 0u; top < 2u; top++) {
        let height = select(-params.half_height, params.half_height, top == 1u);
        let span = height_window(ray, height, radius, best.s);
        if span.x > span.y {
            continue;
        }
        let bound = line_bound(ray, radius, span);
        for (var i = 0u; i < n; i++) {
            if abs(form(bound.xyz, faces[i].normal.xyz)) > bound.w {
                continue;
            }
            let e = n + top * n + i;
            let s = tube_entry(ray, e, vec2<f32>(span.x, min(span.y, best.s)));
            if s >= 0.0 && s <= best.s {
                best = EdgeEntry(e, s);
            }
        }
    }
    return best;
}
#endif

#ifdef PRODUCT_MESHES
// How much a triangle's box is padded (chart units; f32: the CPU's
// BOX_PAD is 1e-9). Rust twin: `BOX_PAD`.
const BOX_PAD: f32 = 1e-5;
// How near the plane Newton's method stops (the CPU's ON_PLANE is 1e-13),
// and its most steps (the CPU's MAX_ROOT_STEPS is 64).
const ON_PLANE: f32 = 1e-7;
const MAX_ROOT_STEPS: u32 = 24u;
// How far outside a triangle a hit on its plane still counts (the CPU's
// EDGE_SLACK is 1e-9).
const EDGE_SLACK: f32 = 1e-5;

// A ray's curve in a mesh's chart: its surface part K0 + lambda(s) D,
// lambda = S(t) / X_w(t) (t the surface arc length), its height h0 + v s.
// Rust twin: `ChartRay`.
struct ChartRay {
    p: vec3<f32>,
    u: vec3<f32>,
    speed: f32,
    k0: vec2<f32>,
    d: vec2<f32>,
    h0: f32,
    v: f32,
}

// Rust twin: `ChartRay::new`.
fn chart_ray(ray: ProductRay) -> ChartRay {
    let p = ray.origin.xyz;
    let speed = sqrt(max(form(ray.dir.xyz, ray.dir.xyz), 0.0));
    var u = vec3<f32>(0.0);
    if speed > 0.0 {
        u = ray.dir.xyz / speed;
    }
    let k0 = p.xy / p.z;
    return ChartRay(p, u, speed, k0, u.xy - k0 * u.z, ray.origin.w, ray.dir.w);
}

// tanh (H2) or tan (S2) of the surface arc length at s: lambda is
// tau / (P_w + U_w tau), one transcendental where S / X_w takes four
// (tan's pole is no trouble: lambda is 1 / U_w there, and f32 never
// lands on it). Rust twin: `ChartRay::tau`.
fn chart_tau(c: ChartRay, s: f32) -> f32 {
    if params.curvature < 0.0 {
        return tanh(c.speed * s);
    }
    return tan(c.speed * s);
}

// Rust twin: `ChartRay::lambda`.
fn chart_lambda(c: ChartRay, s: f32) -> f32 {
    let tau = chart_tau(c, s);
    return tau / (c.p.z + c.u.z * tau);
}

// Rust twin: `ChartRay::at`.
fn chart_at(c: ChartRay, s: f32) -> vec3<f32> {
    return vec3<f32>(c.k0 + c.d * chart_lambda(c, s), c.h0 + c.v * s);
}

// The derivative along the ray of n . q(s): lambda' = speed P_w (1 + k
// tau^2) / (P_w + U_w tau)^2. Rust twin: `ChartRay::slope`.
fn chart_slope(c: ChartRay, s: f32, n: vec3<f32>) -> f32 {
    let tau = chart_tau(c, s);
    let w = c.p.z + c.u.z * tau;
    return dot(n.xy, c.d) * c.speed * c.p.z * (1.0 + params.curvature * tau * tau) / (w * w) + n.z * c.v;
}

// The arc length at which lambda is reached. Rust twin: `ChartRay::s_of`.
fn chart_s_of(c: ChartRay, lambda: f32) -> f32 {
    let y = lambda * c.p.z;
    let x = 1.0 - lambda * c.u.z;
    if params.curvature < 0.0 {
        return atanh(y / x) / c.speed;
    }
    return atan2(y, x) / c.speed;
}

// The part (x, y) of `span` in which the curve is in the box [mn, mx]: its
// height in the box's slab, then its lambda in the slabs across; x > y for
// none. Rust twin: `ChartRay::in_box`.
fn chart_box(c: ChartRay, mn: vec3<f32>, mx: vec3<f32>, span: vec2<f32>) -> vec2<f32> {
    let none = vec2<f32>(1.0, -1.0);
    var lo = span.x;
    var hi = span.y;
    if c.v == 0.0 {
        if c.h0 < mn.z || c.h0 > mx.z {
            return none;
        }
    } else {
        let e = (mn.z - c.h0) / c.v;
        let f = (mx.z - c.h0) / c.v;
        lo = max(lo, min(e, f));
        hi = min(hi, max(e, f));
    }
    if lo > hi {
        return none;
    }
    if c.speed == 0.0 {
        if any(c.k0 < mn.xy) || any(c.k0 > mx.xy) {
            return none;
        }
        return vec2<f32>(lo, hi);
    }
    let l0 = chart_lambda(c, lo);
    let l1 = chart_lambda(c, hi);
    var a = l0;
    var b = l1;
    for (var i = 0u; i < 2u; i++) {
        if c.d[i] == 0.0 {
            if c.k0[i] < mn[i] || c.k0[i] > mx[i] {
                return none;
            }
            continue;
        }
        let e = (mn[i] - c.k0[i]) / c.d[i];
        let f = (mx[i] - c.k0[i]) / c.d[i];
        a = max(a, min(e, f));
        b = min(b, max(e, f));
    }
    if a > b {
        return none;
    }
    if a > l0 {
        lo = max(chart_s_of(c, a), lo);
    }
    if b < l1 {
        hi = min(chart_s_of(c, b), hi);
    }
    if lo > hi {
        return none;
    }
    return vec2<f32>(lo, hi);
}

// Where the curve crosses the triangle (a, b, e) within [0, limit]: (s,
// u, v, 1), or w = 0 for none: the plane's function changes sign on the
// part of the curve in the triangle's padded box, its root found by
// Newton's method kept in that bracket, its barycentric weights checked.
// Rust twin: `cross_triangle`.
fn cross_triangle(c: ChartRay, a: vec3<f32>, b: vec3<f32>, e: vec3<f32>, limit: f32) -> vec4<f32> {
    let none = vec4<f32>(0.0);
    let e1 = b - a;
    let e2 = e - a;
    let raw = cross(e1, e2);
    let scale = length(raw);
    if scale <= 0.0 {
        return none;
    }
    let n = raw / scale;
    let pad = vec3<f32>(BOX_PAD);
    let span = chart_box(c, min(min(a, b), e) - pad, max(max(a, b), e) + pad, vec2<f32>(0.0, limit));
    if span.x > span.y {
        return none;
    }
    var lo = span.x;
    var hi = span.y;
    let f_lo = dot(n, chart_at(c, lo) - a);
    let f_hi = dot(n, chart_at(c, hi) - a);
    if f_lo == 0.0 {
        hi = lo;
    } else if f_lo * f_hi > 0.0 {
        return none;
    }
    let rising = f_lo < 0.0;
    var s = lo;
    for (var k = 0u; k < MAX_ROOT_STEPS; k++) {
        if hi - lo <= 1e-7 * max(abs(hi), 1.0) {
            break;
        }
        let value = dot(n, chart_at(c, s) - a);
        if abs(value) < ON_PLANE {
            break;
        }
        if (value < 0.0) == rising {
            lo = s;
        } else {
            hi = s;
        }
        let next = s - value / chart_slope(c, s, n);
        if next > lo && next < hi {
            s = next;
        } else {
            s = 0.5 * (lo + hi);
        }
    }
    let q = chart_at(c, s) - a;
    let d00 = dot(e1, e1);
    let d01 = dot(e1, e2);
    let d11 = dot(e2, e2);
    let d20 = dot(q, e1);
    let d21 = dot(q, e2);
    let denom = d00 * d11 - d01 * d01;
    let u = (d11 * d20 - d01 * d21) / denom;
    let v = (d00 * d21 - d01 * d20) / denom;
    if u >= -EDGE_SLACK && v >= -EDGE_SLACK && u + v <= 1.0 + EDGE_SLACK {
        return vec4<f32>(s, u, v, 1.0);
    }
    return none;
}

// The unit tangent at the chart point q normal to the chart's plane of
// normal covector n: J G^-1 n. Rust twin: `chart_normal`.
fn chart_normal(q: vec3<f32>, n: vec3<f32>) -> vec4<f32> {
    let k = params.curvature;
    let p = q.xy;
    let w2 = 1.0 / (1.0 + k * dot(p, p));
    let w = sqrt(w2);
    let m = (n.xy + p * (k * dot(p, n.xy))) / w2;
    let dw = -k * w * w2 * dot(p, m);
    return unit(vec4<f32>(w * m.x + q.x * dw, w * m.y + q.y * dw, dw, n.z));
}

// The three floats of mesh_data's word k.
fn mesh_point(k: u32) -> vec3<f32> {
    return bitcast<vec3<f32>>(mesh_data[k].xyz);
}

// A mesh entered: its index (NO_FACE for none), where, and the unit
// normal there in the prism, facing the ray. Rust twin: `MeshEntry`.
struct MeshEntry {
    mesh: u32,
    s: f32,
    normal: vec4<f32>,
}

// The nearest triangle of mesh m the chart ray `local` meets within
// [0, length], by the skip links with the exact box test, and its normal
// in the prism. Rust twin: `ProductMeshImage::first_triangle`.
fn first_triangle(m: u32, local: ProductRay, length: f32) -> MeshEntry {
    let c = chart_ray(local);
    let base = meshes[m].nodes;
    let count = meshes[m].triangles - base;
    let tris = meshes[m].triangles;
    var best = vec4<f32>(length, 0.0, 0.0, 0.0);
    var best_t = NO_FACE;
    var i = 0u;
    loop {
        if 2u * i >= count {
            break;
        }
        let a = mesh_data[base + 2u * i];
        let b = mesh_data[base + 2u * i + 1u];
        let leaf = a.w;
        let link = b.w;
        let span = chart_box(c, bitcast<vec3<f32>>(a.xyz), bitcast<vec3<f32>>(b.xyz), vec2<f32>(0.0, best.x));
        let met = span.x <= span.y;
        if met && leaf > 0u {
            for (var t = link; t < link + leaf; t++) {
                let at = tris + 6u * t;
                let hit = cross_triangle(c, mesh_point(at), mesh_point(at + 1u), mesh_point(at + 2u), best.x);
                if hit.w > 0.0 {
                    best = hit;
                    best_t = t;
                }
            }
        }
        if met || leaf > 0u {
            i++;
        } else {
            i = max(link, i + 1u);
        }
    }
    if best_t == NO_FACE {
        return MeshEntry(NO_FACE, length, vec4<f32>(0.0));
    }
    let at = tris + 6u * best_t;
    let n = mesh_point(at + 3u) * (1.0 - best.y - best.z) + mesh_point(at + 4u) * best.y + mesh_point(at + 5u) * best.z;
    var normal = chart_normal(chart_at(c, best.x), n);
    if dot4(normal, advance(local, best.x).dir) > 0.0 {
        normal = -normal;
    }
    return MeshEntry(m, best.x, normal);
}

// The next stretch (x, y) of [after, length] of the ray within the mesh's
// reach (its height within `tall`, its surface point within `across`),
// one turn round the sphere at a time; x > y for none. Rust twin:
// `window` (of mesh.rs).
fn mesh_window(ray: ProductRay, m: u32, after: f32, length: f32) -> vec2<f32> {
    let center = meshes[m].center;
    var span = height_window(ray, center.w, meshes[m].tall, length);
    if span.x > span.y {
        return span;
    }
    span.x = max(span.x, after);
    let across = meshes[m].across;
    let trig_across = meshes[m].across_trig;
    span = surface_window(ray, center.xyz, across, trig_across, span);
    let speed = sqrt(max(form(ray.dir.xyz, ray.dir.xyz), 0.0));
    if span.x <= span.y && params.curvature > 0.0 && speed > 0.0 {
        span = surface_window(ray, center.xyz, across, trig_across, vec2<f32>(span.x, min(span.y, span.x + 2.0 * across / speed)));
    }
    return span;
}

// The nearest mesh the segment of `length` from the ray's origin enters:
// for each stretch of the ray within a mesh's reach, the ray taken into
// its chart. Rust twin: `ProductMeshImage::entry` (the nearest kept, as
// `hits_in` sorts them).
fn mesh_entry(ray: ProductRay, length: f32) -> MeshEntry {
    var best = MeshEntry(NO_FACE, length, vec4<f32>(0.0));
    for (var first = 0u; first < params.mesh_count; first += 32u) {
        // The images of this run of 32 whose reach the segment enters, as
        // bits: only those are walked. (lavapipe runs a loop's body for
        // all its lanes while any lane is in it, each lane masked: a walk
        // per image would cost every pixel the walk's code per image.)
        var near = 0u;
        let last = min(first + 32u, params.mesh_count);
        for (var m = first; m < last; m++) {
            let span = mesh_window(ray, m, 0.0, best.s);
            if span.x <= span.y {
                near |= 1u << (m - first);
            }
        }
        while near != 0u {
            let m = first + firstTrailingBit(near);
            near &= near - 1u;
            var after = 0.0;
            for (var turn = 0u; turn < 8u; turn++) {
                let span = mesh_window(ray, m, after, best.s);
                if span.x > span.y {
                    break;
                }
                let start = advance(ray, span.x);
                let mesh = meshes[m];
                let origin = normalize_point(vec4<f32>(mesh.to_chart * start.origin.xyz, mesh.to_flip * start.origin.w + mesh.to_shift));
                let local = ProductRay(origin, vec4<f32>(mesh.to_chart * start.dir.xyz, mesh.to_flip * start.dir.w));
                let hit = first_triangle(m, local, span.y - span.x);
                if hit.mesh != NO_FACE {
                    let normal = vec4<f32>(mesh.placement * hit.normal.xyz, mesh.to_flip * hit.normal.w);
                    best = MeshEntry(m, span.x + hit.s, normal);
                    break;
                }
                after = span.y + 1e-6;
            }
        }
    }
    return best;
}
#endif

// What the pixel's ray sees: walked through the faces to its first ball,
// lit from the eye, fogged by its distance. Rust twin: `pixel` (of the
// core's trace/product/view.rs).
fn pixel(start: ProductRay) -> ProductPixel {
    var ray = start;
    var travelled = 0.0;
    var skip = NO_FACE;
    var crossings = 0u;
    var cell = ProductCell(0u, 0, 1);
    loop {
        let exit = exit_face(ray, skip);
        let leaves = exit.face != NO_FACE && travelled + exit.s < params.max_distance;
        var length = params.max_distance - travelled;
        if leaves {
            length = exit.s;
        }
        let hit = nearest_entry(ray, length);
        var nearest = hit.s;
#ifdef PRODUCT_EDGES
        let edge = edge_entry(ray, nearest);
        nearest = edge.s;
#endif
#ifdef PRODUCT_MESHES
        let mesh = mesh_entry(ray, nearest);
        if mesh.mesh != NO_FACE {
            let seen = Seen(mesh.normal, meshes[mesh.mesh].color.rgb, meshes[mesh.mesh].id);
            return shade(advance(ray, mesh.s), seen, travelled + mesh.s, crossings, seen_id(cell));
        }
#endif
#ifdef PRODUCT_EDGES
        if edge.edge != NO_FACE {
            let at = advance(ray, edge.s);
            let seen = Seen(away(at, edge_point(edge.edge, at.origin)), params.edges.rgb, EDGE_ID);
            return shade(at, seen, travelled + edge.s, crossings, seen_id(cell));
        }
#endif
        if hit.ball != NO_FACE {
            let at = advance(ray, hit.s);
            let seen = Seen(away(at, balls[hit.ball].center), balls[hit.ball].color.rgb, balls[hit.ball].id);
            return shade(at, seen, travelled + hit.s, crossings, seen_id(cell));
        }
        if !leaves || crossings >= params.max_crossings {
            break;
        }
        ray = transport(exit.face, advance(ray, exit.s));
#ifdef PRODUCT_CELLS
        cell = cross_cell(cell, exit.face);
#endif
        travelled += exit.s;
        skip = faces[exit.face].partner;
        crossings++;
    }
    return ProductPixel(vec4<f32>(params.fog_color.rgb, -1.0), 0u, 0u, BEYOND_TABLE);
}

// The id of the copy `cell` a hit is seen in: from the table with
// PRODUCT_CELLS, else BEYOND_TABLE. Rust twin: `pixel`'s cell.
fn seen_id(cell: ProductCell) -> vec2<u32> {
#ifdef PRODUCT_CELLS
    return product_cell_id(cell);
#else
    return BEYOND_TABLE;
#endif
}

#ifdef PRODUCT_CELLS
// The copy across `face`: the table's neighbour, the line's steps and
// flip counted exactly. Rust twin: `ProductCells::cross`.
fn cross_cell(cell: ProductCell, face: u32) -> ProductCell {
    var index = PRODUCT_OUTSIDE;
    if cell.index != PRODUCT_OUTSIDE && cell.index < params.cell_count {
        index = cells[cell.index * (params.side_count + 2u) + face];
    }
    let flip = select(1, -1, faces[face].flip < 0.0);
    return ProductCell(index, cell.steps + cell.flip * faces[face].cross_steps, cell.flip * flip);
}

// The id of the copy `cell` names from the camera's: its tile (from the
// table) and its steps up the line. Rust twins: `ProductCells::id` and
// `product_cell_id`.
fn product_cell_id(cell: ProductCell) -> vec2<u32> {
    if cell.index == PRODUCT_OUTSIDE || cell.index >= params.cell_count {
        return BEYOND_TABLE;
    }
    let at = params.cell_count * (params.side_count + 2u) + 2u * cell.index;
    let tile = vec2<u32>(cells[at], cells[at + 1u]);
    if tile.x == 0xffffffffu && tile.y == 0xffffffffu {
        return BEYOND_TABLE;
    }
    let steps = params.camera_steps + params.camera_flip * cell.steps;
    if tile.x == 0u && tile.y == 0u && steps == 0 {
        return vec2<u32>(0u);
    }
    let s = bitcast<u32>(steps);
    return vec2<u32>(tile.x ^ hash32(s), (tile.y ^ hash32(s ^ 0x9e3779b9u)) & 0x3fffffffu);
}
#endif

// The ambient light of a lit scene. Rust twin: `AMBIENT`.
const AMBIENT: f32 = 0.08;
// How far a shadow ray starts off the surface. Rust twin: `SHADOW_OFFSET`.
const SHADOW_OFFSET: f32 = 1e-4;
// The dim light a hit takes at half without walking its shadows, per
// channel. Rust twin: `DIM_LIGHT`.
const DIM_LIGHT: f32 = 2.0 / 255.0;

// The product metric on tangents. Rust twin: `ProductGeometry::dot`.
fn dot4(u: vec4<f32>, v: vec4<f32>) -> f32 {
    return form(u.xyz, v.xyz) + u.w * v.w;
}

// The unit tangent at p towards q, scaled by the distance (zero for
// q = p). Rust twin: `ProductGeometry::log`.
fn log_map(p: vec4<f32>, q: vec4<f32>) -> vec4<f32> {
    let t = q.xyz - p.xyz * (form(q.xyz, p.xyz) * params.curvature);
    let n = sqrt(max(form(t, t), 0.0));
    let ds = surface_distance(p.xyz, q.xyz);
    var surface = vec3<f32>(0.0);
    if n > 1e-30 && ds > 0.0 {
        surface = t * (ds / n);
    }
    return vec4<f32>(surface, q.w - p.w);
}

#ifdef PRODUCT_LIGHTS
// The area a light's power spreads over at distance d along a geodesic
// whose surface part is `surface` long. Rust twin:
// `ProductGeometry::light_area`.
fn light_area(d: f32, surface: f32) -> f32 {
    var spread = 1.0;
    if abs(surface) > 1e-6 {
        spread = abs(trig(surface).y) / abs(surface);
    }
    return 4.0 * 3.14159265 * d * d * spread;
}

// A light image's irradiance along an arc of `length` whose surface part
// is `surface` long. Rust twin: `arc_irradiance`.
fn arc_irradiance(l: u32, length: f32, surface: f32) -> f32 {
    let f = length * length * lights[l].inv_range_sq;
    let window = clamp(1.0 - f * f, 0.0, 1.0);
    let area = max(light_area(length, surface), lights[l].min_area);
    return lights[l].color.w * window * window / area * exp(-params.fog * length);
}

// The share of spot image l's light reaching x along the unit tangent
// `dir` for `length`: the geodesic followed to the light, the tangent it
// arrives with turned back against the axis, smoothstep between the
// outer and inner cosines. Rust twins: `spot_share` and
// `ProductSpot::share`.
fn spot_share(l: u32, x: vec4<f32>, dir: vec4<f32>, length: f32) -> f32 {
    let arriving = advance(ProductRay(x, dir), length).dir;
    let c = -dot4(arriving, lights[l].spot_axis);
    let inner = lights[l].spot_inner;
    let outer = lights[l].spot_outer;
    if inner <= outer {
        return select(0.0, 1.0, c >= outer);
    }
    return smoothstep(outer, inner, c);
}

// Whether a ball, an edge's tube or a mesh stands on the way from x (unit normal `normal`) along
// the unit tangent `dir` for `length`, walked through the faces from
// SHADOW_OFFSET off the surface. Rust twin: `shadowed`.
fn shadowed(x: vec4<f32>, normal: vec4<f32>, dir: vec4<f32>, length: f32) -> bool {
    let start = normalize_point(advance(ProductRay(x, normal), SHADOW_OFFSET).origin);
    var ray = ProductRay(start, normalize_tangent(start, dir));
    var travelled = 0.0;
    var skip = NO_FACE;
    var crossings = 0u;
    loop {
        let exit = exit_face(ray, skip);
        let leaves = exit.face != NO_FACE && travelled + exit.s < length;
        var segment = length - travelled;
        if leaves {
            segment = exit.s;
        }
        if nearest_entry(ray, segment).ball != NO_FACE {
            return true;
        }
#ifdef PRODUCT_EDGES
        if edge_entry(ray, segment).edge != NO_FACE {
            return true;
        }
#endif
#ifdef PRODUCT_MESHES
        if mesh_entry(ray, segment).mesh != NO_FACE {
            return true;
        }
#endif
        if !leaves || crossings >= params.max_crossings {
            return false;
        }
        ray = transport(exit.face, advance(ray, exit.s));
        travelled += exit.s;
        skip = faces[exit.face].partner;
        crossings++;
    }
    return false;
}

// The light a surface point x (unit normal, seen along `view`, of colour
// `albedo`) receives from every light image along each of its arcs (in
// S2xR also the long way round): Lambert plus a Blinn lobe, each arc's
// light only where its way is free when shadows are on (but for the
// DIM_LIGHT, taken at half). Rust twins: `direct` and `light_arcs`.
fn direct(x: vec4<f32>, normal: vec4<f32>, view: vec4<f32>, albedo: vec3<f32>) -> vec3<f32> {
    var rgb = vec3<f32>(0.0);
    var dim = DIM_LIGHT;
    for (var l = 0u; l < params.light_count; l++) {
        let v = log_map(x, lights[l].position);
        let length = sqrt(max(dot4(v, v), 0.0));
        if length <= 0.0 {
            continue;
        }
        let surface = surface_distance(x.xyz, lights[l].position.xyz);
        let speed = sqrt(max(form(v.xyz, v.xyz), 0.0));
        var arcs = 1u;
        if params.curvature > 0.0 && speed > 1e-6 {
            arcs = 2u;
        }
        for (var a = 0u; a < arcs; a++) {
            var dir = v / length;
            var s = length;
            var along = surface;
            if a == 1u {
                along = 6.2831855 - surface;
                s = sqrt(along * along + v.w * v.w);
                dir = vec4<f32>(-v.xyz / speed * (along / s), v.w / s);
            }
            let nl = dot4(normal, dir);
            if nl <= 0.0 {
                continue;
            }
            var e = arc_irradiance(l, s, along);
            if any(lights[l].spot_axis != vec4<f32>(0.0)) {
                e *= spot_share(l, x, dir, s);
            }
            if e <= 0.0 {
                continue;
            }
            let half = dir + view;
            let hl = sqrt(max(dot4(half, half), 0.0));
            var nh = 0.0;
            if hl > 1e-6 {
                nh = max(dot4(normal, half) / hl, 0.0);
            }
            let spec = pow(nh, 32.0) * 0.35;
            let light = (albedo * nl + vec3<f32>(spec)) * e * lights[l].color.rgb;
            var share = 1.0;
            if params.shadows != 0u {
                let most = max(light.r, max(light.g, light.b));
                if most < dim {
                    dim -= most;
                    share = 0.5;
                } else if shadowed(x, normal, dir, s) {
                    continue;
                }
            }
            rgb += light * share;
        }
    }
    return rgb;
}
#endif

// What a ray met: the unit normal there (facing the ray), its colour and
// the id it reports.
struct Seen {
    normal: vec4<f32>,
    color: vec3<f32>,
    id: u32,
}

// The unit normal at `at` of a ball about `center` (a tube about its
// edge's point `center`): away from it, or back along the ray at it. Rust
// twin: `hits_in`'s normal.
fn away(at: ProductRay, center: vec4<f32>) -> vec4<f32> {
    let inward = log_map(at.origin, center);
    let d = sqrt(max(dot4(inward, inward), 0.0));
    if d > 0.0 {
        return -inward / d;
    }
    return -at.dir;
}

// The seen colour, tinted by its cell's, lit by the light images (from
// the eye where there are none: the cosine between the normal and the
// way back along the ray), fogged. Rust twin: `pixel`'s shading.
fn shade(at: ProductRay, seen: Seen, distance: f32, crossings: u32, cell: vec2<u32>) -> ProductPixel {
    let p = at.origin;
    var base = seen.color;
    if params.tint_mode != 0u {
        base *= cell_tint(cell, params.tint_mode - 1u, params.tint_a, params.tint_b);
    }
#ifdef PRODUCT_LIGHTS
    let rgb = base * AMBIENT + direct(p, seen.normal, -at.dir, base);
#else
    let lamp = clamp(-dot4(seen.normal, at.dir), 0.0, 1.0);
    let rgb = base * (0.25 + 0.75 * lamp);
#endif
    let fog = exp(-params.fog * distance);
    let color = rgb * fog + params.fog_color.rgb * (1.0 - fog);
    return ProductPixel(vec4<f32>(color, distance), seen.id, crossings, cell);
}

// The pixel's ray: the unit tangent forward + x right + y up at the eye,
// the slopes x, y from the symmetric frustum of tan_half_fov and the
// image's aspect, or from the off-centre params.frustum. Rust twins:
// `ProductView::slopes` and `pixel`'s ray (of `render`).
fn camera_ray(i: u32, j: u32) -> ProductRay {
    let w = f32(params.width);
    let h = f32(params.height);
    let ndc_x = (f32(i) + 0.5) / w * 2.0 - 1.0;
    let ndc_y = 1.0 - (f32(j) + 0.5) / h * 2.0;
    var x = ndc_x * params.tan_half_fov * w / max(h, 1.0);
    var y = ndc_y * params.tan_half_fov;
    if params.frustum.x != 0.0 {
        x = ndc_x * params.frustum.x + params.frustum.z;
        y = ndc_y * params.frustum.y + params.frustum.w;
    }
    let dir = unit(params.forward + params.right * x + params.up * y);
    return ProductRay(params.eye, dir);
}

// The render pass's entry: the pixel under the fragment, in the view's
// viewport (from its origin), as linear colour, or sRGB-encoded where the
// target stores encoded values (ENCODE_SRGB). Rust twin: `product_pass`.
@fragment
fn product_fragment(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let i = u32(max(position.x - f32(params.origin_x), 0.0));
    let j = u32(max(position.y - f32(params.origin_y), 0.0));
    var rgb = pixel(camera_ray(i, j)).color.rgb;
#ifdef ENCODE_SRGB
    rgb = encode_srgb(rgb);
#endif
    return vec4<f32>(rgb, 1.0);
}

#ifdef ENCODE_SRGB
// The sRGB encoding, as output.wgsl's (this module imports the tint only).
// Rust twin: `srgb8` (before its rounding to a byte).
fn encode_srgb(c: vec3<f32>) -> vec3<f32> {
    let x = clamp(c, vec3<f32>(0.0), vec3<f32>(1.0));
    return select(1.055 * pow(x, vec3<f32>(1.0 / 2.4)) - 0.055, 12.92 * x, x <= vec3<f32>(0.0031308));
}
#endif

@compute @workgroup_size(8, 8, 1)
fn product_trace(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.width || id.y >= params.height {
        return;
    }
    pixels[id.y * params.width + id.x] = pixel(camera_ray(id.x, id.y));
}
