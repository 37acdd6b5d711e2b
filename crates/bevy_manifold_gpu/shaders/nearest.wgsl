// What a segment of a ray meets: the object hit (Hit), and what the walk
// keeps of the objects each_candidate (cull.wgsl) hands it: for a ray the
// nearest hit (`best`); under FOOTPRINT the cone's nearest layers
// (`met_t`, `met_id`) and the mesh hit, whole (`best`).
//
// Rust twin: crates/bevy_manifold_core/src/trace/nearest.rs (Hit,
// Hit::id as hit_id, Nearest, same_cell_point). WGSL has no closures, so
// the arms of the visitors that nearest_object and segment_layers (Rust's
// trace.rs) hand each_candidate are functions here, which the walk
// calls: consider_ball, consider_tube and consider_instance; under
// FOOTPRINT they keep layers by cone.wgsl's cover.
//
// Shader defs read: BALLS, TUBES, MESHES (which objects there are),
// FOOTPRINT (layers, not a hit), GEOMETRY_HYPERBOLIC (ball_center).
#define_import_path bevy_manifold::nearest

#import bevy_manifold::bindings::{cached, EDGE_ID}
#import bevy_manifold::step::{Ray, may_hit}
#ifdef BALLS
#import bevy_manifold::bindings::balls
#import bevy_manifold::step::hit_ball
#endif
#ifdef TUBES
#import bevy_manifold::bindings::tubes
#import bevy_manifold::step::hit_tube
#endif
#ifdef MESHES
#import bevy_manifold::bindings::instances
#import bevy_manifold::mesh_hit::hit_instance
#endif
#ifdef FOOTPRINT
#import bevy_manifold::footprint::{SEGMENT_LAYERS, ball_approach, tube_approach, grow_k}
#import bevy_manifold::cone::{cover, cone_grow}
#ifdef TUBES
#import bevy_manifold::step::on_edge
#endif
#endif

// Which object a ray hit. Rust twin: the enum Hit.
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

// The object id of a hit. Rust twin: Hit::id.
fn hit_id(hit: Hit) -> u32 {
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
    return object;
}

// True when two cell points g o name the same copy of the domain.
// Rust twin: same_cell_point.
fn same_cell_point(a: vec4<f32>, b: vec4<f32>) -> bool {
    let d = a - b;
    let size = max(dot(a, a), 1.0);
    return dot(d, d) <= 1.0e-6 * size;
}

// What the walk over a segment's objects keeps (Rust twin: Nearest's
// `whole`): a ray's nearest hit, or under FOOTPRINT the mesh hit, whole,
// in front of the cone's layers.
var<private> best: Hit;

#ifdef SHADOWS
// True while shade.wgsl walks shadow rays (shadow.wgsl's shadow_step): the arms
// below then keep any hit on [0, t_end] in `best` (under FOOTPRINT too),
// and glowing balls are not hit. Rust twin: segment_blocked's visitor.
var<private> shadow_ray: bool;
#endif

#ifdef FOOTPRINT
// The segment's layers, nearest first (Rust twin: Nearest's `met`): where the ray
// passes each, and which it is (kind << 30 | index). Only these two
// words are kept and moved; the cover is worked out again for the few
// kept (an array of whole layers indexed at run time doubled the cone
// pass's time on lavapipe). A mesh hit, whole, is `best`.
var<private> met_t: array<f32, SEGMENT_LAYERS>;
var<private> met_id: array<u32, SEGMENT_LAYERS>;
var<private> met_count: u32;

// The farthest still wanted (Rust twin: Nearest::limit): t_end, or once full
// the farthest layer kept; never past the mesh hit.
fn met_limit(t_end: f32) -> f32 {
    var limit = t_end;
    if met_count == SEGMENT_LAYERS {
        limit = met_t[SEGMENT_LAYERS - 1u];
    }
    if best.kind != 0u {
        limit = min(best.t, limit);
    }
    return limit;
}

// Keeps a layer in order, dropping the farthest when full, a tie staying
// ahead (Rust twin: Nearest::keep).
fn keep_met(t: f32, id: u32) {
    var at = min(met_count, SEGMENT_LAYERS - 1u);
    met_t[at] = t;
    met_id[at] = id;
    for (var guard = 0u; guard < SEGMENT_LAYERS && at > 0u && met_t[at - 1u] > t; guard++) {
        met_t[at] = met_t[at - 1u];
        met_id[at] = met_id[at - 1u];
        met_t[at - 1u] = t;
        met_id[at - 1u] = id;
        at -= 1u;
    }
    met_count = min(met_count + 1u, SEGMENT_LAYERS);
}
#endif

#ifdef BALLS
// Ball i against what the walk keeps: for a ray, `best` if ball i is not
// hit on [0, t_end] nearer (ties to the lower index, as in the array's
// order); under FOOTPRINT, its layer if it makes one. Rust twin: the ball
// arm of the visitors of nearest_object and segment_layers (trace.rs).
fn consider_ball(ray: Ray, t_end: f32, near: u32, i: u32) {
    if !may_hit(balls[i].face_mask, near) {
        return;
    }
    meet_ball(ray, t_end, i);
}

// Ball i's centre for its hit test. In H3 it is read in three words, its
// w made from them as Rust's FlatScene stored it (w = sqrt(1 + x^2 + y^2
// + z^2), on the hyperboloid): each word a lane reads from `balls` is a
// gather, and gathering a ball's words, not testing it, is most of what
// the ball tree costs (docs/benchmarks/history.md, "Face planes and the ball ratio").
// In E3 the form leaves w out, so it is never read. Rust twin:
// ball_center in crates/bevy_manifold_core/src/trace/flat.rs.
fn ball_center(i: u32) -> vec4<f32> {
#ifdef GEOMETRY_HYPERBOLIC
    let c = balls[i].center.xyz;
    return vec4<f32>(c, sqrt(1.0 + (c.x * c.x + c.y * c.y + c.z * c.z)));
#else
    return balls[i].center;
#endif
}

// consider_ball for a ball with no face mask (one the ball tree hands
// out), which every segment may hit, without reading its mask
// (Rust's visitor checks the empty mask): 128 balls in the torus at
// 320x180, 8 levels, took 23.4 ms with the read and 21.9 without.
fn meet_ball(ray: Ray, t_end: f32, i: u32) {
#ifdef SHADOWS
    if shadow_ray {
        if balls[i].glow <= 0.0 {
            let t = hit_ball(ray, ball_center(i), balls[i].k, 0.0);
            if t >= 0.0 && t <= t_end {
                best = Hit(t, 1u, i, 0u, 0.0, 0.0);
            }
        }
        return;
    }
#endif
#ifdef FOOTPRINT
    let c = cover(1u, i, ball_approach(ray, balls[i].center), met_limit(t_end), grow_k(balls[i].k, cone_grow.ball), balls[i].k);
    if c.part > 0.0 {
        keep_met(c.near.t, (1u << 30u) | i);
    }
#else
    let t = hit_ball(ray, ball_center(i), balls[i].k, 0.0);
    if t >= 0.0 && t <= t_end && (best.kind == 0u || t < best.t || (t == best.t && i < best.index)) {
        best = Hit(t, 1u, i, 0u, 0.0, 0.0);
    }
#endif
}
#endif

#ifdef TUBES
// Tube i against what the walk keeps. Rust twin: the tube arm of the
// visitors of nearest_object and segment_layers (trace.rs).
fn consider_tube(ray: Ray, t_end: f32, near: u32, i: u32) {
    if !may_hit(tubes[i].face_mask, near) {
        return;
    }
#ifdef SHADOWS
    if shadow_ray {
        let t = hit_tube(ray, tubes[i], cached.tube_k, 0.0);
        if t >= 0.0 && t <= t_end {
            best = Hit(t, 2u, i, 0u, 0.0, 0.0);
        }
        return;
    }
#endif
#ifdef FOOTPRINT
    let a = tube_approach(ray, tubes[i].a, tubes[i].e);
    if on_edge(ray.origin + ray.dir * a.t, tubes[i]) {
        let c = cover(2u, i, a, met_limit(t_end), grow_k(cached.tube_k, cone_grow.tube), cached.tube_k);
        if c.part > 0.0 {
            keep_met(a.t, (2u << 30u) | i);
        }
    }
#else
    let t = hit_tube(ray, tubes[i], cached.tube_k, 0.0);
    if t >= 0.0 && t <= t_end && (best.kind == 0u || t < best.t) {
        best = Hit(t, 2u, i, 0u, 0.0, 0.0);
    }
#endif
}
#endif

#ifdef MESHES
// Mesh instance i against what the walk keeps, hit whole. Rust twin:
// the instance arm of the visitors of nearest_object and segment_layers
// (trace.rs), and instance_shown.
fn consider_instance(ray: Ray, t_end: f32, cell_point: vec4<f32>, near: u32, i: u32) {
    if !may_hit(instances[i].face_mask, near) || (instances[i].attached != 0u && same_cell_point(instances[i].home, cell_point)) {
        return;
    }
    var limit = nearest_so_far(t_end);
#ifdef SHADOWS
    if shadow_ray {
        limit = t_end;
    }
#endif
    let h = hit_instance(ray, instances[i], limit);
    if h.t >= 0.0 && h.t <= limit {
        best = Hit(h.t, 3u, i, h.hit.triangle, h.hit.u, h.hit.v);
    }
}

// The nearest hit so far whole (under FOOTPRINT, met_limit: the layers
// too), or t_end.
fn nearest_so_far(t_end: f32) -> f32 {
#ifdef FOOTPRINT
    return met_limit(t_end);
#else
    return select(t_end, best.t, best.kind != 0u);
#endif
}

// How far along the ray a hit still matters once the objects so far are
// considered: the nearest hit (under FOOTPRINT, met_limit), or t_end; for
// a shadow ray 0 once anything blocks it. The instance tree's walk
// (instance_tree.wgsl) skips boxes beyond it. Rust twin: what the
// visitors of nearest_object, segment_layers (trace.rs) and
// segment_blocked (shadow.rs) return to each_candidate.
fn still_wanted(t_end: f32) -> f32 {
    var limit = nearest_so_far(t_end);
#ifdef SHADOWS
    if shadow_ray {
        limit = select(t_end, 0.0, best.kind != 0u);
    }
#endif
    return limit;
}
#endif
