// Shadows through the faces: a light image lights a hit only if the
// geodesic between them is free. The shadow ray walks through the faces
// as a camera ray does (walk.wgsl's segment_end and walker_step), and on
// each segment meets the same objects (cull.wgsl's each_candidate, its
// consider_* arms under `shadow_ray`): balls (glowing ones, the lamps,
// cast no shadow), edge tubes and meshes, ghost copies straddling a face
// included. It stops at the light.
//
// A light with a radius is a ball: each trace aims its shadow rays at one
// point of the disc the ball shows the hit (aim_at_light, under
// SOFT_SHADOWS), params.light_sample, so that the traces of a still view
// add up to the penumbra.
//
// Rust twin: crates/bevy_manifold_core/src/trace/shadow.rs (the same
// names).
//
// Compiled under SHADOWS only (shade.wgsl imports it there).
#define_import_path bevy_manifold::shadow

#import bevy_manifold::bindings::cached
#import bevy_manifold::geometry::{normalize_point, normalize_tangent, chart_to_distance, distance_to_chart}
#ifdef SOFT_SHADOWS
#import bevy_manifold::geometry::{form, project_tangent, sphere_area, PI}
#endif
#import bevy_manifold::step::{Ray, near_faces, advance}
#import bevy_manifold::walk::{Walker, walker_new, segment_end, walker_step}
#import bevy_manifold::cull::each_candidate
#import bevy_manifold::nearest::{Hit, best}
#ifdef FOOTPRINT
#import bevy_manifold::cone::near_balls
#endif

// How far off the surface a shadow ray starts, along the normal, so that
// the surface it leaves does not shadow itself. Rust twin: SHADOW_OFFSET.
const SHADOW_OFFSET: f32 = 1.0e-4;

// Most faces a shadow ray crosses; past them the light is taken as seen.
// Rust twin: SHADOW_LEVELS.
const SHADOW_LEVELS: u32 = 24u;

#ifdef SOFT_SHADOWS
// A shadow ray's unit tangent and length (aim_at_light).
struct Aim {
    dir: vec4<f32>,
    length: f32,
}

// The shadow ray's unit tangent and length from the hit x towards the
// point u (light_sample_point) of the disc a light of radius `radius`
// shows it, its centre at arc length s along the unit tangent dir: dir
// and s themselves for a point light, u = [0, 0], or x inside the light.
// The cone of half-angle a, sin a = sin_k(radius) / sin_k(s), sampled
// evenly in solid angle: cos t = 1 - u0 (1 - cos a), at the angle 2 pi u1
// around dir. Rust twin: aim_at_light.
fn aim_at_light(x: vec4<f32>, dir: vec4<f32>, s: f32, radius: f32, u: vec2<f32>) -> Aim {
    if radius <= 0.0 || u.x <= 0.0 {
        return Aim(dir, s);
    }
    let sin_a2 = sphere_area(radius) / sphere_area(s);
    if !(sin_a2 < 1.0) {
        return Aim(dir, s);
    }
    let cos_a = sqrt(1.0 - sin_a2);
    let cos_t = 1.0 - u.x * (1.0 - cos_a);
    let sin_t = sqrt(max(1.0 - cos_t * cos_t, 0.0));
    let b = longest_perpendicular(x, dir, vec4<f32>(0.0));
    let c = longest_perpendicular(x, dir, b);
    let phi = 2.0 * PI * u.y;
    let out = dir * cos_t + (b * cos(phi) + c * sin(phi)) * sin_t;
    return Aim(out, arc_to_sphere(s, cos_t, radius));
}

// The tangent part at x of the longest of the axes x, y, z once made
// perpendicular to the unit tangent a and to `other` (zero, or a unit
// tangent perpendicular to a), normalised: twice, a frame about a.
// Rust twin: longest_perpendicular.
fn longest_perpendicular(x: vec4<f32>, a: vec4<f32>, other: vec4<f32>) -> vec4<f32> {
    var longest = vec4<f32>(0.0);
    var longest_n = 0.0;
    for (var i = 0u; i < 3u; i++) {
        var e = vec4<f32>(0.0);
        e[i] = 1.0;
        var t = project_tangent(x, e);
        t -= a * form(t, a);
        t -= other * form(t, other);
        let n = form(t, t);
        if n > longest_n {
            longest = t;
            longest_n = n;
        }
    }
    return longest / sqrt(longest_n);
}

// The arc length from a point to the near surface of a ball of radius
// `radius` whose centre lies at arc length s, along a geodesic at angle t
// (cos_t) from the centre's direction: the geometry's law of cosines
// solved for the nearer root. Rust twin: arc_to_sphere.
fn arc_to_sphere(s: f32, cos_t: f32, radius: f32) -> f32 {
#ifdef GEOMETRY_EUCLIDEAN
    let sin2 = max(1.0 - cos_t * cos_t, 0.0);
    return s * cos_t - sqrt(max(radius * radius - s * s * sin2, 0.0));
#endif
#ifdef GEOMETRY_SPHERICAL
    let a = cos(s);
    let b = sin(s) * cos_t;
    let len = sqrt(a * a + b * b);
    var phi = atan2(b, a);
    if phi < 0.0 {
        phi += 2.0 * PI;
    }
    let c = min(cos(radius) / len, 1.0);
    return phi - atan2(sqrt(max(1.0 - c * c, 0.0)), c);
#endif
#ifdef GEOMETRY_HYPERBOLIC
    let a = cosh(s);
    let b = sinh(s) * cos_t;
    let len = sqrt(max(a * a - b * b, 1.0e-12));
    let c = max(cosh(radius) / len, 1.0);
    return atanh(b / a) - asinh(sqrt(c * c - 1.0));
#endif
}
#endif

// A shadow ray on its way, taken a segment at a time (shadow_step) so
// that shade.wgsl can walk each lane's own rays side by side (the Rust
// twin's light_blocked walks one to its end). Rust twin: ShadowWalk.
struct ShadowWalk {
    walk: Walker,
    // The distance left to the light.
    left: f32,
    // Segments walked.
    level: u32,
}

// What shadow_step found: the ray goes on, met something, reached the
// light (or ran out of levels): what ShadowWalk::step returns, in
// words.
const SHADOW_ON: u32 = 0u;
const SHADOW_BLOCKED: u32 = 1u;
const SHADOW_FREE: u32 = 2u;

// The walk of the geodesic leaving the hit x (normal `normal`, in the
// cell `cell`) along the unit tangent dir for distance `length`, the arc
// to a light image. Rust twin: ShadowWalk::new.
fn shadow_walk_new(x: vec4<f32>, normal: vec4<f32>, dir: vec4<f32>, length: f32, cell: mat4x4<f32>) -> ShadowWalk {
    let origin = normalize_point(x + normal * SHADOW_OFFSET);
    return ShadowWalk(walker_new(Ray(origin, normalize_tangent(origin, dir)), cell, 0u), length - SHADOW_OFFSET, 0u);
}

// One segment of the walk: SHADOW_BLOCKED when it meets an object that
// casts shadows, SHADOW_FREE when it reaches the light (or has crossed
// SHADOW_LEVELS faces), else SHADOW_ON, the walk moved across the face.
// Run with shadow_ray set; it overwrites `best` (and a cone's
// near_balls). Rust twin: ShadowWalk::step.
fn shadow_step(w: ptr<function, ShadowWalk>) -> u32 {
    if (*w).left <= 0.0 || (*w).level > SHADOW_LEVELS {
        return SHADOW_FREE;
    }
    var walk = (*w).walk;
    let left = (*w).left;
    let seg = segment_end(walk);
    let seg_len = chart_to_distance(seg.t);
    let last = left <= seg_len;
    let t_stop = select(seg.t, distance_to_chart(left), last);
    if segment_blocked(walk.ray, t_stop, walk.cell[3]) {
        return SHADOW_BLOCKED;
    }
    if last {
        return SHADOW_FREE;
    }
    walker_step(&walk, seg.face, advance(walk.ray, seg.t));
    *w = ShadowWalk(walk, left - seg_len, (*w).level + 1u);
    return SHADOW_ON;
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
