// The camera's rays: the ray of each pixel, under the camera's
// perspective (or off-centre frustum) or a 360-degree panorama, from the
// camera's isometry in the domain.
//
// Rust twin: crates/bevy_manifold_core/src/trace/camera.rs (the same
// names; view_direction is the start of camera_ray there).
//
// Shader defs read: GEOMETRY_* (eye_point).
#define_import_path bevy_manifold::camera

#import bevy_manifold::bindings::params
#import bevy_manifold::geometry::{normalize_point, normalize_tangent}
#import bevy_manifold::step::Ray

// The view-space slopes of the direction through NDC (x, y): the
// symmetric frustum of tan_half_fov and the image's aspect, or the
// off-centre params.frustum. Rust twin: view_slopes.
fn view_slopes(x: f32, y: f32, w: f32, h: f32) -> vec2<f32> {
    if params.frustum.x == 0.0 {
        return vec2<f32>(x * params.tan_half_fov * (w / h), y * params.tan_half_fov);
    }
    return vec2<f32>(x * params.frustum.x + params.frustum.z, y * params.frustum.y + params.frustum.w);
}

// The pixel's view direction in the camera's frame (unit, -z forward).
fn view_direction(i: u32, j: u32) -> vec4<f32> {
    let w = f32(params.width);
    let h = f32(params.height);
    let x = 2.0 * (f32(i) + 0.5) / w - 1.0;
    let y = 1.0 - 2.0 * (f32(j) + 0.5) / h;
    let s = view_slopes(x, y, w, h);
    let d = vec4<f32>(s.x, s.y, -1.0, 0.0);
    return d * (1.0 / sqrt(dot(d, d)));
}

// The ray through the centre of pixel (i, j). Rust twin: camera_ray.
fn camera_ray(i: u32, j: u32) -> Ray {
    let d = view_direction(i, j);
    let o = normalize_point(params.camera * vec4<f32>(0.0, 0.0, 0.0, 1.0));
    return Ray(o, normalize_tangent(o, params.camera * d));
}

// The point at distance s from the origin along the unit tangent u (Rust:
// Geometry::exp from the origin).
fn eye_point(u: vec4<f32>, s: f32) -> vec4<f32> {
#ifdef GEOMETRY_HYPERBOLIC
    return vec4<f32>(u.xyz * sinh(s), cosh(s));
#else ifdef GEOMETRY_SPHERICAL
    return vec4<f32>(u.xyz * sin(s), cos(s));
#else
    return vec4<f32>(u.xyz * s, 1.0);
#endif
}

// The ray of pixel (i, j) under params.projection (Rust twin: view_ray):
// camera_ray for the perspective, else an equirectangular panorama, mono
// or top-bottom stereo (the top half the left eye), each eye off the
// camera along the geodesic perpendicular to its longitude.
fn view_ray(i: u32, j: u32) -> Ray {
    if params.projection == 0u {
        return camera_ray(i, j);
    }
    var rows = params.height;
    var row = j;
    var side = 0.0;
    if params.projection == 2u {
        let half = max(params.height / 2u, 1u);
        if j < half {
            rows = half;
            side = -1.0;
        } else {
            rows = params.height - half;
            row = j - half;
            side = 1.0;
        }
    }
    let lon = 6.283185307179586 * ((f32(i) + 0.5) / f32(params.width) - 0.5);
    let lat = 3.141592653589793 * (0.5 - (f32(row) + 0.5) / f32(rows));
    let d = vec4<f32>(sin(lon) * cos(lat), sin(lat), -(cos(lon) * cos(lat)), 0.0);
    let right = vec4<f32>(cos(lon), 0.0, sin(lon), 0.0);
    let o = normalize_point(params.camera * eye_point(right, side * params.eye_offset));
    return Ray(o, normalize_tangent(o, params.camera * d));
}
