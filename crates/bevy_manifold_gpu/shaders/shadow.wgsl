// Shadows through the faces: a light image lights a hit only if the
// geodesic between them is free. The shadow ray walks through the faces
// as a camera ray does (walk.wgsl's segment_end and walker_step), and on
// each segment meets the same objects (cull.wgsl's each_candidate, its
// consider_* arms under `shadow_ray`): balls (glowing ones, the lamps,
// cast no shadow), edge tubes and meshes, ghost copies straddling a face
// included. It stops at the light.
//
// Rust twin: crates/bevy_manifold_core/src/trace/shadow.rs (the same
// names).
//
// Compiled under SHADOWS only (shade.wgsl imports it there).
#define_import_path bevy_manifold::shadow

#import bevy_manifold::bindings::cached
#import bevy_manifold::geometry::{normalize_point, normalize_tangent, chart_to_distance, distance_to_chart}
#import bevy_manifold::step::{Ray, near_faces, advance}
#import bevy_manifold::walk::{walker_new, segment_end, walker_step}
#import bevy_manifold::cull::each_candidate
#import bevy_manifold::nearest::{Hit, best, shadow_ray}
#ifdef FOOTPRINT
#import bevy_manifold::cone::near_balls
#endif

// How far off the surface a shadow ray starts, along the normal, so that
// the surface it leaves does not shadow itself. Rust twin: SHADOW_OFFSET.
const SHADOW_OFFSET: f32 = 1.0e-4;

// Most faces a shadow ray crosses; past them the light is taken as seen.
// Rust twin: SHADOW_LEVELS.
const SHADOW_LEVELS: u32 = 24u;

// True when something lies on the geodesic leaving the hit x (normal
// `normal`, in the cell `cell`) along the unit tangent dir within
// distance `length`, the arc to a light image. The walk's `best` (and a
// cone's near_balls) are kept as they were. Rust twin: light_blocked.
fn light_blocked(x: vec4<f32>, normal: vec4<f32>, dir: vec4<f32>, length: f32, cell: mat4x4<f32>) -> bool {
    let origin = normalize_point(x + normal * SHADOW_OFFSET);
    var walk = walker_new(Ray(origin, normalize_tangent(origin, dir)), cell, 0u);
    var left = length - SHADOW_OFFSET;
    let kept = best;
#ifdef FOOTPRINT
    let kept_near = near_balls;
#endif
    shadow_ray = true;
    var blocked = false;
    for (var i = 0u; i <= SHADOW_LEVELS; i++) {
        if left <= 0.0 {
            break;
        }
        let seg = segment_end(walk);
        let seg_len = chart_to_distance(seg.t);
        let last = left <= seg_len;
        let t_stop = select(seg.t, distance_to_chart(left), last);
        if segment_blocked(walk.ray, t_stop, walk.cell[3]) {
            blocked = true;
            break;
        }
        if last {
            break;
        }
        walker_step(&walk, seg.face, advance(walk.ray, seg.t));
        left -= seg_len;
    }
    shadow_ray = false;
    best = kept;
#ifdef FOOTPRINT
    near_balls = kept_near;
#endif
    return blocked;
}

// True when the segment of `ray` up to t_end meets an object that casts
// shadows. Rust twin: segment_blocked.
fn segment_blocked(ray: Ray, t_end: f32, cell_point: vec4<f32>) -> bool {
    let near = near_faces(ray, t_end, cached.near_reach);
#ifdef FOOTPRINT
    near_balls = near;
#endif
    best = Hit(-1.0, 0u, 0u, 0u, 0.0, 0.0);
    each_candidate(ray, t_end, cell_point, near);
    return best.kind != 0u;
}
