// How far a ray drifts off the model over many transports (`bench
// stability`, the stability tests): the camera ray walked as trace_ray
// walks it, by the same walker, objects and fog ignored.
//
// Rust twin: crates/bevy_manifold_core/src/trace/drift.rs (ray_drift,
// RayDrift).
//
// Shader defs read: none itself; GEOMETRY_*, TRANSLATIONS_ONLY, CELLS_FINITE
// through walk, MESHES through bindings.
#define_import_path bevy_manifold::drift

#import bevy_manifold::bindings::{params, cache_params, faces, Pixel, NO_FACE, face_count}
#import bevy_manifold::geometry::{point_error, tangent_error}
#import bevy_manifold::step::Ray
#import bevy_manifold::walk::{walker_new, max_passes, segment_end, walk_segment}

// The point and tangent errors of a ray, and how far outside the domain
// its origin is (the largest n . (p / w) over the faces).
fn ray_errors(ray: Ray) -> vec3<f32> {
    let c = ray.origin / ray.origin.w;
    var outside = -3.0e38;
    for (var i = 0u; i < face_count(); i++) {
        outside = max(outside, dot(faces[i].plane, c));
    }
    return vec3<f32>(point_error(ray.origin), tangent_error(ray.origin, ray.dir), outside);
}

// True when any component is NaN or infinite, by its exponent bits (which
// no compiler folds away, unlike x != x).
fn non_finite(v: vec4<f32>) -> bool {
    let e = bitcast<vec4<u32>>(v) & vec4<u32>(0x7f800000u);
    return any(e == vec4<u32>(0x7f800000u));
}

// The worst errors so far and those of `ray`: max() drops NaN, so a ray
// that left the numbers makes the point error NaN and keeps it there, as
// Rust's `note` in ray_drift does.
fn keep_worst(worst: vec3<f32>, ray: Ray) -> vec3<f32> {
    if non_finite(vec4<f32>(worst, 0.0)) {
        return worst;
    }
    if non_finite(ray.origin) || non_finite(ray.dir) {
        return vec3<f32>(bitcast<f32>(0x7fc00000u), worst.yz);
    }
    return max(worst, ray_errors(ray));
}

// Walks `ray` through params.levels transports (or max_distance) and returns
// the worst point and tangent errors over every segment end in color.xy,
// how far outside the domain any end was in color.z, the distance in
// color.w and the transports made in levels.
fn ray_drift(ray: Ray) -> Pixel {
    cache_params();
    var walk = walker_new(ray, params.camera_cell, params.camera_cell_index);
    var worst = keep_worst(vec3<f32>(0.0, 0.0, -3.0e38), walk.ray);
    let passes = max_passes();
    for (var pass_index = 0u; pass_index < passes; pass_index++) {
        let seg = segment_end(walk);
        let path = walk_segment(&walk, seg);
        worst = keep_worst(worst, path.end);
        if path.stop {
            break;
        }
        if seg.face != NO_FACE {
            // The start of the next segment, carried through the face.
            worst = keep_worst(worst, walk.ray);
        }
    }
    return Pixel(vec4<f32>(worst, walk.travelled), 0u, walk.levels, 0u, 0u);
}
