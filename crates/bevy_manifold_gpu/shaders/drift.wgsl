// How far a ray drifts off the model over many transports (`bench
// stability`, the stability tests): the camera ray walked as trace_pixel
// walks it, by the same walker, objects and fog ignored.
//
// Rust twin: crates/bevy_manifold_core/src/trace/drift.rs (ray_drift,
// RayDrift).
//
// Shader defs read: none itself; GEOMETRY_*, TRANSLATIONS_ONLY, CELLS_FINITE
// through walk, MESHES through bindings.
#define_import_path bevy_manifold::drift

#import bevy_manifold::bindings::{params, faces, Pixel, NO_FACE}
#import bevy_manifold::geometry::{point_error, tangent_error}
#import bevy_manifold::step::Ray
#import bevy_manifold::walk::{walker_new, max_passes, segment_end, walk_segment}

// The point and tangent errors of a ray, and how far outside the domain
// its origin is (the largest n . (p / w) over the faces).
fn ray_errors(ray: Ray) -> vec3<f32> {
    let c = ray.origin / ray.origin.w;
    var outside = -3.0e38;
    for (var i = 0u; i < params.face_count; i++) {
        outside = max(outside, dot(faces[i].plane, c));
    }
    return vec3<f32>(point_error(ray.origin), tangent_error(ray.origin, ray.dir), outside);
}

// Walks `ray` through params.levels transports (or max_distance) and returns
// the worst point and tangent errors over every segment end in color.xy,
// how far outside the domain any end was in color.z, the distance in
// color.w and the transports made in levels.
fn ray_drift(ray: Ray) -> Pixel {
    var walk = walker_new(ray, params.camera_cell, params.camera_cell_index);
    var worst = ray_errors(walk.ray);
    let passes = max_passes();
    for (var pass_index = 0u; pass_index < passes; pass_index++) {
        let seg = segment_end(walk);
        let path = walk_segment(&walk, seg);
        worst = max(worst, ray_errors(path.end));
        if path.stop {
            break;
        }
        if seg.face != NO_FACE {
            // The start of the next segment, carried through the face.
            worst = max(worst, ray_errors(walk.ray));
        }
    }
    return Pixel(vec4<f32>(worst, walk.travelled), 0u, walk.levels, 0u, 0u);
}
