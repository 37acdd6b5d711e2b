// Cone tracing: each pixel is a thin cone, so a ball or an edge tube
// narrower than its footprint covers part of the pixel instead of
// flickering on and off. The cone's half-angle is params.cone.x; at
// distance D it is w = beta * spread(D) wide, at most
// params.footprint_cap. Objects are grown by the
// segment's widest footprint (Inflation); each one the ray's geodesic
// passes within the grown radius of (approach, within) covers part of
// the pixel (coverage) and is a layer, added front to back (Layers).
//
// Rust twin: crates/bevy_manifold_core/src/trace/footprint.rs (the same
// names; Rust's methods are functions here: Inflation::new is
// inflation_new, Approach::within is within, Approach::gap is gap_of,
// Layers::add is add_layer).
// cone.wgsl, nearest.wgsl and trace.wgsl use it under FOOTPRINT.
//
// Shader defs read: GEOMETRY_HYPERBOLIC / GEOMETRY_SPHERICAL /
// GEOMETRY_EUCLIDEAN.
#define_import_path bevy_manifold::footprint

#import bevy_manifold::geometry::form
#import bevy_manifold::step::Ray

// Most layers one pixel adds; then what is left sees the background.
const MAX_LAYERS: u32 = 16u;
// Most layers kept on one segment: the nearest.
const SEGMENT_LAYERS: u32 = 4u;
// Light left below which a layer takes the rest.
const LAYERS_CLEAR: f32 = 0.003921569;
// How many footprints balls are grown by (tubes by one).
const BALL_GROWTH: f32 = 3.5;

// How far apart two geodesics leaving a point at unit angle are after d:
// sinh d, d, |sin d| (they meet again at the antipode).
fn spread(d: f32) -> f32 {
#ifdef GEOMETRY_HYPERBOLIC
    return sinh(d);
#else ifdef GEOMETRY_SPHERICAL
    return abs(sin(d));
#else
    return d;
#endif
}

// The most spread between distances d0 and d1 >= d0: at d1 in E3 and H3;
// in S3 1 when a quarter turn (mod a half turn) lies between, else the
// more of the two ends.
fn widest_spread(d0: f32, d1: f32) -> f32 {
#ifdef GEOMETRY_SPHERICAL
    let pi = 3.141592653589793;
    let k = ceil((d0 - pi / 2.0) / pi);
    if k * pi + pi / 2.0 <= d1 {
        return 1.0;
    }
    return max(spread(d0), spread(d1));
#else
    return spread(d1);
#endif
}

// (cosh x, sinh x), (cos x, sin x) or (1, x): the trig of a growth.
fn growth_trig(x: f32) -> vec2<f32> {
#ifdef GEOMETRY_HYPERBOLIC
    return vec2<f32>(cosh(x), sinh(x));
#else ifdef GEOMETRY_SPHERICAL
    return vec2<f32>(cos(x), sin(x));
#else
    return vec2<f32>(1.0, x);
#endif
}

// Objects grown by a footprint w: tubes by w, balls by BALL_GROWTH w.
struct Inflation {
    w: f32,
    tube: vec2<f32>,
    ball: vec2<f32>,
}

fn inflation_new(w: f32) -> Inflation {
    return Inflation(w, growth_trig(w), growth_trig(w * BALL_GROWTH));
}

// The k (cosh r, cos r, r^2) of radius r + x from that of r and x's trig.
fn grow_k(k: f32, trig: vec2<f32>) -> f32 {
#ifdef GEOMETRY_HYPERBOLIC
    return k * trig.x + sqrt(max(k * k - 1.0, 0.0)) * trig.y;
#else ifdef GEOMETRY_SPHERICAL
    return max(k * trig.x - sqrt(max(1.0 - k * k, 0.0)) * trig.y, -1.0);
#else
    let r = sqrt(max(k, 0.0)) + trig.y;
    return r * r;
#endif
}

// near_faces' reach for objects grown by w: s(near_distance + w), before
// the space's near_scale.
fn grown_reach(near_distance: f32, w: f32) -> f32 {
    let r = near_distance + w;
#ifdef GEOMETRY_HYPERBOLIC
    return sinh(r);
#else ifdef GEOMETRY_SPHERICAL
    return select(3.0e38, sin(r), r < 1.5707963267948966);
#else
    return r;
#endif
}

// The radius whose k is k.
fn radius_of(k: f32) -> f32 {
#ifdef GEOMETRY_HYPERBOLIC
    return asinh(sqrt(max(k * k - 1.0, 0.0)));
#else ifdef GEOMETRY_SPHERICAL
    return atan2(sqrt(max(1.0 - k * k, 0.0)), k);
#else
    return sqrt(max(k, 0.0));
#endif
}

// x less its projection onto the span of the point a and the tangent e
// (zero for a point).
fn off_flat(x: vec4<f32>, a: vec4<f32>, e: vec4<f32>) -> vec4<f32> {
#ifdef GEOMETRY_HYPERBOLIC
    return x + a * form(x, a) - e * form(x, e);
#else ifdef GEOMETRY_SPHERICAL
    return x - a * form(x, a) - e * form(x, e);
#else
    let y = x - a * x.w;
    return y - e * form(y, e);
#endif
}

// Where the ray's geodesic comes nearest a flat: the least distance's
// sinh^2 / sin^2 / square, and the chart parameter there (the distance
// itself is gap_of, left until within has let the object through).
struct Approach {
    lambda: f32,
    t: f32,
}

fn approach(ray: Ray, a: vec4<f32>, e: vec4<f32>) -> Approach {
    let po = off_flat(ray.origin, a, e);
    let pd = off_flat(ray.dir, a, e);
    let p = form(po, po);
    let m = form(po, pd);
    let q = form(pd, pd);
    let det = max(p * q - m * m, 0.0);
#ifdef GEOMETRY_HYPERBOLIC
    let s = sqrt(max((p + q) * (p + q) - 4.0 * m * m, 0.0));
    var lambda = 0.0;
    if p >= q {
        lambda = (p - q + s) / 2.0;
    } else if s - (p - q) > 0.0 {
        lambda = 2.0 * det / (s - (p - q));
    }
    let lead = q + lambda;
#else ifdef GEOMETRY_SPHERICAL
    let s = sqrt(max((p - q) * (p - q) + 4.0 * m * m, 0.0));
    let lambda = select(0.0, 2.0 * det / (p + q + s), p + q + s > 0.0);
    let lead = q - lambda;
#else
    let lambda = select(p, det / q, q > 0.0);
    let lead = q;
#endif
    // As Rust: where the touching quadratic cannot place the least value,
    // the start's own value, at the start.
    let placed = abs(lead) > 1.1920929e-7;
    return Approach(select(p, lambda, placed), select(0.0, -m / lead, placed));
}

// The least distance of an approach (Rust twin: Approach::gap).
fn gap_of(lambda: f32) -> f32 {
    let root = sqrt(max(lambda, 0.0));
#ifdef GEOMETRY_HYPERBOLIC
    return asinh(root);
#else ifdef GEOMETRY_SPHERICAL
    return atan2(min(root, 1.0), sqrt(max(1.0 - lambda, 0.0)));
#else
    return root;
#endif
}

fn ball_approach(ray: Ray, c: vec4<f32>) -> Approach {
    return approach(ray, c, vec4<f32>(0.0));
}

fn tube_approach(ray: Ray, a: vec4<f32>, e: vec4<f32>) -> Approach {
    return approach(ray, a, e);
}

// True when the approach is within the radius whose k is k.
fn within(near: Approach, k: f32) -> bool {
#ifdef GEOMETRY_HYPERBOLIC
    return near.lambda <= k * k - 1.0;
#else ifdef GEOMETRY_SPHERICAL
    return near.lambda <= 1.0 - k * k;
#else
    return near.lambda <= k;
#endif
}

// What a strip from delta - r to delta + r covers of a pixel of
// half-width w.
fn strip(delta: f32, r: f32, w: f32) -> f32 {
    if !(w > 0.0) {
        return select(0.0, 1.0, delta <= r);
    }
    let covered = min(delta + r, w) - max(delta - r, -w);
    return clamp(covered / (w + w), 0.0, 1.0);
}

// What a disc of radius r, delta from the pixel's centre, covers of a
// pixel of half-width w: a Gaussian under a pixel, the strip across the
// rim of a wide one, blended in between.
fn disc(delta: f32, r: f32, w: f32) -> f32 {
    if !(w > 0.0) {
        return select(0.0, 1.0, delta <= r);
    }
    if delta > r + BALL_GROWTH * w {
        return 0.0;
    }
    let spread2 = 3.0 * w * w;
    let gauss = r * r / spread2 * exp(-(delta * delta) / spread2);
    let rim = strip(delta, r, w);
    let blend = clamp((r / w - 1.5) / 1.5, 0.0, 1.0);
    return clamp(gauss + blend * (rim - gauss), 0.0, 1.0);
}

// What a ball (disc) or a tube of the given length (strip, at most its
// length over the pixel's width) covers.
fn coverage(ball: bool, delta: f32, r: f32, length: f32, w: f32) -> f32 {
    if ball {
        return disc(delta, r, w);
    }
    if w > 0.0 {
        return strip(delta, r, w) * min(length / (w + w), 1.0);
    }
    return strip(delta, r, w);
}

// Copies of the domain side by side across a cross-section 4 w^2.
fn side_by_side(w: f32, cell_shadow: f32) -> f32 {
    return max(4.0 * w * w / cell_shadow, 1.0);
}

// The offset, as a fraction of r, at which a layer is shaded.
fn shading_offset(ball: bool, gap: f32, r: f32, w: f32) -> f32 {
    let thin = select(0.5, 0.33333334, ball);
    let cap = 1.0 - thin * min(w / r, 1.0);
    return max(min(gap / r, cap), 0.0);
}

// The normal at offset s across a round object seen along view.
fn normal_at_offset(n0: vec4<f32>, view: vec4<f32>, s: f32) -> vec4<f32> {
    let across = n0 - view * form(n0, view);
    let len = sqrt(max(form(across, across), 0.0));
    let up = sqrt(max(1.0 - s * s, 0.0));
    if len > 1.0e-12 {
        return view * up + across * (s / len);
    }
    return view;
}

// The layers met so far: colour, light left, count.
struct Layers {
    color: vec3<f32>,
    left: f32,
    count: u32,
}

// Adds a layer to the private `layers` (cone.wgsl's cone_layers); true
// when it takes all the light left.
fn add_layer(layers: ptr<private, Layers>, color: vec3<f32>, part_in: f32) -> bool {
    (*layers).count += 1u;
    let part = clamp(part_in, 0.0, 1.0);
    let last = part >= 1.0 || (*layers).left * (1.0 - part) < LAYERS_CLEAR;
    let take = select((*layers).left * part, (*layers).left, last);
    (*layers).color += take * color;
    (*layers).left -= take;
    return last;
}

fn layers_full(layers: Layers) -> bool {
    return layers.count >= MAX_LAYERS;
}

fn layers_over(layers: Layers, behind: vec3<f32>) -> vec3<f32> {
    return layers.color + layers.left * behind;
}
