// The metric of the three geometries in the projective chart: the form,
// normalisation, distances. Everything else in the tracer is
// geometry-neutral and calls these.
//
// Rust twin: crates/bevy_manifold_core/src/geometry/mod.rs (the methods of
// `Geometry`, same names, same arithmetic in the same order).
//
// Shader defs read: GEOMETRY_HYPERBOLIC, GEOMETRY_SPHERICAL,
// GEOMETRY_EUCLIDEAN (exactly one is set; the E3 code is each `#else`).
#define_import_path bevy_manifold::geometry

const PI: f32 = 3.14159265358979;

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

fn normalize_tangent(p: vec4<f32>, v: vec4<f32>) -> vec4<f32> {
    let t = project_tangent(p, v);
    return t * (1.0 / sqrt(abs(form(t, t))));
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

// The inverse of chart_to_distance.
fn distance_to_chart(s: f32) -> f32 {
#ifdef GEOMETRY_HYPERBOLIC
    return tanh(s);
#else ifdef GEOMETRY_SPHERICAL
    return tan(s);
#else
    return s;
#endif
}

// Rust returns +inf for E3; WGSL has no infinity literal, and 3e38 is past
// any chart parameter a face gives.
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
