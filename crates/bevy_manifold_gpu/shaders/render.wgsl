// Algorithm 1 per pixel: the camera ray, the nearest object
// on each segment of its walk, and the shading at the hit.
//
// Rust twin: crates/bevy_manifold_core/src/trace/render.rs (camera_ray,
// trace_ray as trace_pixel, Hit, nearest_object, segment_layers,
// cone_layer, shade) and cull.rs (each_candidate, the walk over the
// objects in nearest_object here).
//
// Shader defs read: FOG (early stop, fog colour), BALLS, TUBES, MESHES
// (which objects are tested and shaded), CELL_COLORS, LIGHTS, CELL_RULES
// (hidden cells, walls), FOOTPRINT (cone tracing: footprint.wgsl),
// BALL_TREE (the test of the ball tree's leaves, BALL_LEAVES of them), MANY_UNKEYED_TUBES (the loop over
// the tubes with no edge bits past the first 32); GEOMETRY_*, TRANSLATIONS_ONLY,
// CELLS_* through the imports.
//
// Written for lavapipe too, which runs the body of every branch under a
// mask whether or not any SIMD lane takes it (only loops end early, once
// all lanes are done): what a scene does not need is left out by a def,
// and the shading is done once, after the walk, not inside it.
#define_import_path bevy_manifold::render

#import bevy_manifold::bindings::{params, groups, cached, cache_params, balls, tubes, lights, faces, face_count, Pixel, EDGE_ID, FLAG_NO_EARLY_STOP, FOG_CUT, LIGHT_AT_HIT, WALL_OBJECT, NO_JOINT}
#import bevy_manifold::geometry::{form, normalize_point, normalize_tangent, project_tangent, distance, chart_to_distance, sphere_area}
#import bevy_manifold::step::{Ray, normal_from, near_faces, may_hit}
#import bevy_manifold::cells::cell_id
#import bevy_manifold::walk::{walker_new, max_passes, segment_end, walk_segment}
#ifdef BALLS
#import bevy_manifold::step::hit_ball
#endif
#ifdef BALL_TREE
#import bevy_manifold::bindings::{ball_nodes, FLAG_NO_CULL}
#import bevy_manifold::bvh::{hit_box, safe_inverse}
#import bevy_manifold::ball_tree::{cache_leaves, leaf_lo, leaf_hi}
#endif
#ifdef TUBES
#import bevy_manifold::step::{hit_tube, foot_on_line}
#endif
#ifdef CELL_COLORS
#import bevy_manifold::cells::cell_color
#endif
#ifdef CELL_RULES
#import bevy_manifold::rules::{cell_visible, shade_wall, unknown_rules}
#endif
#ifdef MESHES
#import bevy_manifold::bindings::instances
#import bevy_manifold::bvh::MeshHit
#import bevy_manifold::mesh_hit::{hit_instance, mesh_normal, mesh_albedo}
#endif
#ifdef FOOTPRINT
#import bevy_manifold::step::on_edge
#import bevy_manifold::footprint::{Approach, Inflation, Layers, inflation_new, grow_k, grown_reach, radius_of, ball_approach, tube_approach, within, gap_of, coverage, side_by_side, shading_offset, normal_at_offset, spread, widest_spread, add_layer, layers_full, layers_over, BALL_GROWTH, SEGMENT_LAYERS}
#endif

// The view-space slopes of the direction through NDC (x, y): the
// symmetric frustum of tan_half_fov and the image's aspect, or the
// off-centre params.frustum (Rust: view_slopes).
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

// The ray of pixel (i, j) under params.projection (Rust: view_ray):
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

fn background() -> vec3<f32> {
#ifdef FOG
    return params.fog_color.xyz;
#else
    return vec3<f32>(0.0);
#endif
}

#ifdef FOOTPRINT
// The cone's layers so far (Rust: trace_ray's `layers`), and the first
// covering half the pixel or more (`front`), which names its object.
var<private> cone_layers: Layers;
var<private> cone_front: Pixel;
var<private> cone_has_front: bool;
#endif

// The pixel that ends the walk, `behind` seen through the cone's layers
// (Rust: trace_ray's `finish`); `behind` itself for a ray.
fn finish(behind: Pixel) -> Pixel {
#ifdef FOOTPRINT
    var p = behind;
    if cone_has_front {
        p = cone_front;
    }
    p.color = vec4<f32>(layers_over(cone_layers, behind.color.xyz), p.color.w);
    return p;
#else
    return behind;
#endif
}

// The object id of a hit (Rust: Hit::id).
fn object_id(hit: Hit) -> u32 {
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

// Algorithm 1 for the pixel (i, j) of the view (Rust: trace_ray): on each
// segment the nearest object, else walk on through the exit face. Under
// FOOTPRINT each segment's layers, front to back.
fn trace_pixel(i: u32, j: u32) -> Pixel {
    cache_params();
#ifdef BALL_TREE
    cache_leaves();
#endif
    var walk = walker_new(view_ray(i, j), params.camera_cell, params.camera_cell_index);
#ifdef FOOTPRINT
    cone_layers = Layers(vec3<f32>(0.0), 1.0, 0u);
    cone_has_front = false;
#endif
    let passes = max_passes();
#ifndef FOOTPRINT
    var hit = Hit(-1.0, 0u, 0u, 0u, 0.0, 0.0);
#endif
    for (var pass_index = 0u; pass_index < passes; pass_index++) {
#ifdef FOG
        let early_stop = (cached.flags & FLAG_NO_EARLY_STOP) == 0u;
        if early_stop && cached.fog_density * walk.travelled > FOG_CUT {
            break;
        }
#endif
        let seg = segment_end(walk);
        var shown = true;
#ifdef CELL_RULES
        // Objects in an off cell are not there (Rust: CellRule::visible).
        shown = cell_visible(cell_id(walk.cell, walk.index));
#endif
#ifdef FOOTPRINT
        // Objects grow by the segment's widest footprint, at most the cap.
        let w = min(params.cone.x * widest_spread(walk.travelled, walk.travelled + chart_to_distance(seg.t)), params.footprint_cap);
        cone_grow = inflation_new(w);
        cone_travelled = walk.travelled;
        met_count = 0u;
        if shown {
            // The faces the segment comes near for balls (grown
            // BALL_GROWTH footprints) and for tubes and meshes (one).
            near_balls = near_faces(walk.ray, seg.t, params.cone.z * grown_reach(params.cone.y, w * BALL_GROWTH));
            nearest_object(walk.ray, seg.t, walk.cell[3], near_faces(walk.ray, seg.t, params.cone.z * grown_reach(params.cone.y, w)));
        }
        // The layers in order, then the mesh hit, whole (Rust:
        // Nearest::iter).
        for (var k = 0u; k < met_count; k++) {
            if best.kind != 0u && best.t < met_t[k] {
                break;
            }
            let kind = met_id[k] >> 30u;
            let index = met_id[k] & 0x3fffffffu;
            let layer = cone_layer(walk.ray, kind, index, kept_cover(walk.ray, kind, index, seg.t), seg.t);
            let hit = Hit(layer.t, kind, index, 0u, 0.0, 0.0);
            let dist = walk.travelled + chart_to_distance(layer.t);
            let cid = cell_id(walk.cell, walk.index);
            let color = shade(walk.ray, hit, layer.normal, dist, cid);
            let here = Pixel(vec4<f32>(color, dist), object_id(hit), walk.levels, cid.x, cid.y);
            if layer.part >= 0.5 && !cone_has_front {
                cone_front = here;
                cone_has_front = true;
            }
            if add_layer(&cone_layers, color, layer.part) {
                return finish(here);
            }
            if layers_full(cone_layers) {
                return finish(Pixel(vec4<f32>(background(), walk.travelled), 0u, walk.levels, cid.x, cid.y));
            }
        }
        if best.kind != 0u {
            let dist = walk.travelled + chart_to_distance(best.t);
            let cid = cell_id(walk.cell, walk.index);
            let color = shade(walk.ray, best, vec4<f32>(0.0), dist, cid);
            let here = Pixel(vec4<f32>(color, dist), object_id(best), walk.levels, cid.x, cid.y);
            if !cone_has_front {
                cone_front = here;
                cone_has_front = true;
            }
            add_layer(&cone_layers, color, 1.0);
            return finish(here);
        }
#else
        if shown {
            hit = nearest_object(walk.ray, seg.t, walk.cell[3], near_faces(walk.ray, seg.t, cached.near_reach));
        }
        // Shaded after the loop (Rust shades and returns here): lavapipe
        // runs a branch's body, under a mask, whether or not any lane
        // takes it, so shading here cost every pass of every ray.
        if hit.kind != 0u {
            break;
        }
#endif
        let segment_start = walk.ray;
        let step = walk_segment(&walk, seg);
#ifdef CELL_RULES
        if step.wall == 1u {
            let cid = cell_id(walk.cell, walk.index);
            let color = shade_wall(faces[seg.face].plane, segment_start, walk.travelled);
#ifdef FOOTPRINT
            add_layer(&cone_layers, color, 1.0);
#endif
            return finish(Pixel(vec4<f32>(color, walk.travelled), WALL_OBJECT, walk.levels, cid.x, cid.y));
        }
        if step.wall == 2u {
            // Beyond the table the rules are unknown: CellTint::UNKNOWN's
            // grey, in fog, and the cell CellId::BEYOND_TABLE.
            return finish(Pixel(vec4<f32>(unknown_rules(walk.travelled), walk.travelled), 0u, walk.levels, 0u, 0x40000000u));
        }
#endif
        if step.stop {
            break;
        }
    }
#ifndef FOOTPRINT
    if hit.kind != 0u {
        let dist = walk.travelled + chart_to_distance(hit.t);
        let cid = cell_id(walk.cell, walk.index);
        return Pixel(vec4<f32>(shade(walk.ray, hit, vec4<f32>(0.0), dist, cid), dist), object_id(hit), walk.levels, cid.x, cid.y);
    }
#endif
    let cid = cell_id(walk.cell, walk.index);
    return finish(Pixel(vec4<f32>(background(), walk.travelled), 0u, walk.levels, cid.x, cid.y));
}

// Which object a ray hit (Rust: the enum Hit).
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

// The near faces that have groups: those of `near` below the face count
// (at most 32).
fn near_groups(near: u32) -> u32 {
    let n = min(face_count(), 32u);
    return select(near & ((1u << n) - 1u), near, n == 32u);
}

// The index range of the group of the first face left in `rest`, which it
// takes out: kind 0 balls, 2 mesh instances (the x and z of groups).
// Rust: the ranges after the first of FaceGroups::ranges.
fn next_group(rest: ptr<function, u32>, kind: u32) -> vec2<u32> {
    let f = firstTrailingBit(*rest);
    *rest &= *rest - 1u;
    return vec2<u32>(groups[f][kind], groups[f + 1u][kind]);
}

// Where a walk of the tubes' edge table stands (Rust: the iterator
// FaceGroups::edge_walk returns): the face f whose edges it walks (or
// UNMASKED_TUBES first), the near faces g it has still to take across
// them (bits; for UNMASKED_TUBES the tubes themselves), and the near
// faces after f whose groups hold tubes.
struct EdgeWalk {
    f: u32,
    pending: u32,
    rest: u32,
}

// EdgeWalk::f while the walk takes the tubes with no edge bits (those
// before groups[0].y), from a bit per tube.
const UNMASKED_TUBES: u32 = 32u;

// A walk that first takes the tubes with no edge bits whose faces are all
// in `near` (of the first 32; MANY_UNKEYED_TUBES tests the others each
// in turn), then the tubes of the near faces in `rest`. A bit per tube
// rather than a loop over them: lavapipe runs a tube's test for every
// lane when any lane takes it, and a loop's body whatever its count
// (Seifert-Weber's 52-face domain has 5 such tubes: 228-238 ms a frame
// with the loop, 182-187 with the bits; BENCHMARKS.md). Rust:
// each_candidate leaves them out alike.
fn edge_walk_new(near: u32, rest: u32) -> EdgeWalk {
    var unmasked = 0u;
    let n = min(groups[0].y, 32u);
    for (var i = 0u; i < n; i++) {
        unmasked |= select(0u, 1u << i, may_hit(tubes[i].face_mask, near));
    }
    return EdgeWalk(UNMASKED_TUBES, unmasked, rest);
}

// Moves the walk on to the next face with an edge to a near face, if f has
// none left; true when there is one. Rust: the iterator's next.
fn edge_walk_next(walk: ptr<function, EdgeWalk>, near: u32) -> bool {
    loop {
        if (*walk).pending != 0u || (*walk).rest == 0u {
            break;
        }
        (*walk).f = firstTrailingBit((*walk).rest);
        (*walk).rest &= (*walk).rest - 1u;
        (*walk).pending = groups[(*walk).f].w & near;
    }
    return (*walk).pending != 0u;
}

// The tube of the walk's next edge, f to the lowest g pending, which it
// takes out: in f's group, after as many tubes as f has edge bits below g
// (for UNMASKED_TUBES, tube g).
fn edge_walk_tube(walk: ptr<function, EdgeWalk>) -> u32 {
    let g = firstTrailingBit((*walk).pending);
    (*walk).pending &= (*walk).pending - 1u;
    let edges = groups[(*walk).f].w;
    return select(groups[(*walk).f].y + countOneBits(edges & ((1u << g) - 1u)), g, (*walk).f == UNMASKED_TUBES);
}

// True when two cell points g o name the same copy of the domain.
// Rust twin: same_cell_point in crates/bevy_manifold_core/src/trace/flat.rs.
fn same_cell_point(a: vec4<f32>, b: vec4<f32>) -> bool {
    let d = a - b;
    let size = max(dot(a, a), 1.0);
    return dot(d, d) <= 1.0e-6 * size;
}

// What the walk over a segment's objects keeps (Rust: the closures
// nearest_object and segment_layers hand each_candidate): a ray's
// nearest hit, or under FOOTPRINT the cone's nearest layers.
var<private> best: Hit;

#ifdef FOOTPRINT
// What a ball or tube met by a pixel's cone covers (Rust: Cover): where
// the ray passes nearest it, the footprint there, its radius and the part
// of the pixel it covers (0: none).
struct Cover {
    near: Approach,
    gap: f32,
    w: f32,
    r: f32,
    part: f32,
}

// The segment's layers, nearest first (Rust: Nearest): where the ray
// passes each, and which it is (kind << 30 | index). Only these two
// words are kept and moved; the cover is worked out again for the few
// kept (an array of whole layers indexed at run time doubled the cone
// pass's time on lavapipe). A mesh hit, whole, is `best`.
var<private> met_t: array<f32, SEGMENT_LAYERS>;
var<private> met_id: array<u32, SEGMENT_LAYERS>;
var<private> met_count: u32;
var<private> cone_grow: Inflation;
var<private> cone_travelled: f32;
// The faces the segment comes near for grown balls (Rust: each_candidate's
// near_balls); the walk's `near` serves tubes and meshes.
var<private> near_balls: u32;

// The farthest still wanted (Rust: Nearest::limit): t_end, or once full
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
// ahead (Rust: Nearest::keep).
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

// What the ball (kind 1) or tube (kind 2) `index` covers when the ray's
// approach `near` to it lies in [0, end] within the grown radius (`k`
// grown to `grown`); part 0 otherwise (Rust: segment_layers' cover).
fn cover(kind: u32, index: u32, near: Approach, end: f32, grown: f32, k: f32) -> Cover {
    var c = Cover(near, 0.0, 0.0, 0.0, 0.0);
    if !(near.t >= 0.0 && near.t <= end && within(near, grown)) {
        return c;
    }
    // Never wider than the segment's growth (the cap).
    c.w = min(params.cone.x * spread(cone_travelled + chart_to_distance(near.t)), cone_grow.w);
    c.r = radius_of(k);
    let ball = kind == 1u;
    var length = 0.0;
#ifdef TUBES
    if !ball {
        length = distance(tubes[index].a, tubes[index].b);
    }
#endif
    c.gap = gap_of(near.lambda);
    c.part = min(coverage(ball, c.gap, c.r, length, c.w) * side_by_side(c.w, params.cone.w), 1.0);
    return c;
}

// The cover of a kept layer (its id from met_id), worked out again as
// consider_ball and consider_tube did.
fn kept_cover(ray: Ray, kind: u32, index: u32, t_end: f32) -> Cover {
#ifdef BALLS
    if kind == 1u {
        return cover(1u, index, ball_approach(ray, balls[index].center), t_end, grow_k(balls[index].k, cone_grow.ball), balls[index].k);
    }
#endif
#ifdef TUBES
    if kind == 2u {
        return cover(2u, index, tube_approach(ray, tubes[index].a, tubes[index].e), t_end, grow_k(cached.tube_k, cone_grow.tube), cached.tube_k);
    }
#endif
    return Cover(Approach(0.0, 0.0), 0.0, 0.0, 0.0, 0.0);
}
#endif

#ifdef BALLS
// Ball i against what the walk keeps: for a ray, `best` if ball i is not
// hit on [0, t_end] nearer (ties to the lower index, as in the array's
// order); under FOOTPRINT, its layer if it makes one. Rust: the ball arm
// of nearest_object's and segment_layers' closures.
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
// the ball tree costs (BENCHMARKS.md, "Face planes and the ball ratio").
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

// The balls with no face mask (0..groups[0].x): only those in the
// leaves of the ball tree (ball_nodes) whose boxes,
// padded by the balls' growth under FOOTPRINT, the segment's chart image,
// from a = o/o_w to e/e_w, meets; every one when culling is off, an end
// is at the chart's horizon, or there is no tree (fewer than
// MIN_BALL_TREE such balls, Rust's flat.rs; not compiled at all without
// BALL_TREE), or more leaves than the pipeline's BALL_LEAVES (one compiled
// for an earlier scene). Rust twin: chart_segment and tree_leaves in
// crates/bevy_manifold_core/src/trace/ball_tree.rs, as each_candidate
// (cull.rs) calls them.
fn interior_balls(ray: Ray, t_end: f32, near: u32) {
#ifdef BALL_TREE
    let o = ray.origin;
    let e = ray.origin + ray.dir * t_end;
    let a = o.xyz / o.w;
    let d = e.xyz / e.w - a;
    let finite = all(abs(a) < vec3<f32>(3.0e38)) && all(abs(d) < vec3<f32>(3.0e38));
    var pad = 0.0;
#ifdef FOOTPRINT
    pad = cone_grow.w * BALL_GROWTH * params.chart_stretch;
#endif
    if (cached.flags & FLAG_NO_CULL) != 0u || cached.ball_leaves == 0u || cached.ball_leaves > #{BALL_LEAVES}u || !(t_end < 3.0e38) || !(o.w > 0.0) || !(e.w > 0.0) || !finite || !(pad < 3.0e38) {
        every_interior_ball(ray, t_end, near);
        return;
    }
    ball_tree_leaves(ray, t_end, near, a, d, pad);
#else
    every_interior_ball(ray, t_end, near);
#endif
}

// Every ball with no face mask, in order.
fn every_interior_ball(ray: Ray, t_end: f32, near: u32) {
    let interior = groups[0].x;
    for (var i = 0u; i < interior; i++) {
        consider_ball(ray, t_end, near, i);
    }
}

#ifdef BALL_TREE
// The test of the ball tree for interior_balls, compiled only under
// BALL_TREE (a scene with MIN_BALL_TREE balls or more): lavapipe runs a
// branch's body, under a mask, whether or not any lane takes it, so with
// it compiled into every scene it cost every segment of every frame. First
// every leaf's box (cache_leaves' private arrays, at constant indices once
// the chunks are unrolled: a plain vector test each, no gather), each met
// leaf a bit of `met`; then the met leaves' balls, lowest leaf first, in a
// loop that ends when every lane's leaves are done. A walk down the tree
// from the uniform read each node lane by lane: at 320x180, 8 levels,
// median of six alternated runs, 100 balls took 21.8 ms walked and 20.0
// with the leaves tested flat in Seifert-Weber, 15.6 and 14.9 in the
// torus; 254 balls (32 fuller leaves) 21.1 and 25.5 in Seifert-Weber
// (BENCHMARKS.md, "The ball tree's leaves tested flat"). Rust twin:
// tree_leaves in crates/bevy_manifold_core/src/trace/ball_tree.rs (which
// skips halves of the tree by their boxes, handing out the same leaves).
fn ball_tree_leaves(ray: Ray, t_end: f32, near: u32, a: vec3<f32>, d: vec3<f32>, pad: f32) {
    let inv_d = safe_inverse(d);
    var met = vec2<u32>(0u);
    met = leaves_met(a, inv_d, pad, met, 0u, min(#{BALL_LEAVES}u, 16u));
    met = leaves_met(a, inv_d, pad, met, 16u, min(#{BALL_LEAVES}u, 32u));
    met = leaves_met(a, inv_d, pad, met, 32u, min(#{BALL_LEAVES}u, 48u));
    met = leaves_met(a, inv_d, pad, met, 48u, min(#{BALL_LEAVES}u, 64u));
    // Only the leaves the scene has (a pipeline compiled for more decodes
    // the rest from whatever the uniform holds).
    let sent = cached.ball_leaves;
    met.x &= select(0xffffffffu, (1u << sent) - 1u, sent < 32u);
    met.y &= select(select(0u, (1u << (sent - 32u)) - 1u, sent > 32u), 0xffffffffu, sent >= 64u);
    loop {
        if met.x == 0u && met.y == 0u {
            break;
        }
        // The lowest met leaf, cleared.
        var l = 0u;
        if met.x != 0u {
            l = firstTrailingBit(met.x);
            met.x &= met.x - 1u;
        } else {
            l = 32u + firstTrailingBit(met.y);
            met.y &= met.y - 1u;
        }
        let run = ball_nodes[2u + l].w;
        let first = run & 0xffffu;
        for (var b = first; b < first + (run >> 16u); b++) {
            meet_ball(ray, t_end, b);
        }
    }
}

// Leaves lo to hi - 1 of ball_tree_leaves' test, their bits set in `met`
// (leaf l: bit l of x below 32, bit l - 32 of y above) where the segment
// a + s d, 0 <= s <= 1, meets its box grown by pad.
fn leaves_met(a: vec3<f32>, inv_d: vec3<f32>, pad: f32, met_in: vec2<u32>, lo: u32, hi: u32) -> vec2<u32> {
    var met = met_in;
    for (var l = lo; l < hi; l++) {
        let m = hit_box(a, inv_d, leaf_lo[l] - pad, leaf_hi[l] + pad, 1.0) >= 0.0;
        if l < 32u {
            met.x |= select(0u, 1u << l, m);
        } else {
            met.y |= select(0u, 1u << (l - 32u), m);
        }
    }
    return met;
}
#endif
#endif

#ifdef TUBES
// Tube i against what the walk keeps (Rust: the tube arms).
fn consider_tube(ray: Ray, t_end: f32, near: u32, i: u32) {
    if !may_hit(tubes[i].face_mask, near) {
        return;
    }
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

// Tube i (near the faces `near`), then the vertex joint it carries (near
// `ball_near`; FlatTube::joint). Rust: the tube and ball arms, as
// each_candidate hands them out.
fn consider_edge(ray: Ray, t_end: f32, near: u32, ball_near: u32, i: u32) {
    consider_tube(ray, t_end, near, i);
#ifdef BALLS
    let joint = tubes[i].joint;
    if joint != NO_JOINT {
        consider_ball(ray, t_end, ball_near, joint);
    }
#endif
}
#endif

#ifdef MESHES
// Mesh instance i against what the walk keeps, hit whole (Rust: the
// instance arms).
fn consider_instance(ray: Ray, t_end: f32, cell_point: vec4<f32>, near: u32, i: u32) {
    if !may_hit(instances[i].face_mask, near) || (instances[i].attached != 0u && same_cell_point(instances[i].home, cell_point)) {
        return;
    }
#ifdef FOOTPRINT
    let limit = met_limit(t_end);
#else
    let limit = select(t_end, best.t, best.kind != 0u);
#endif
    let h = hit_instance(ray, instances[i], limit);
    if h.t >= 0.0 && h.t <= limit {
        best = Hit(h.t, 3u, i, h.hit.triangle, h.hit.u, h.hit.v);
    }
}
#endif

// The objects a segment may meet, each handed to consider_*: the nearest
// hit on the ray within [0, t_end] (returned), or under FOOTPRINT the
// segment's layers (in met), seen from the cell whose element takes the
// origin to `cell_point` (the copy of a camera-attached mesh that is the
// camera's own body from there is skipped). Objects whose faces the
// segment does not come near (`near`, from near_faces; under FOOTPRINT
// balls their own, near_balls) are not tested,
// nor balls with no face mask in the leaves of the ball tree the segment
// does not meet (interior_balls); a vertex joint a tube carries is tested
// after its tube (consider_edge). Rust: each_candidate (cull.rs), and
// nearest_object or segment_layers.
fn nearest_object(ray: Ray, t_end: f32, cell_point: vec4<f32>, near: u32) -> Hit {
    best = Hit(-1.0, 0u, 0u, 0u, 0.0, 0.0);
    // Balls and mesh instances: the groups walked (Rust: FaceGroups::
    // ranges), the unmasked objects, then the group of each near face, in
    // order. Each kind's loop runs over the ranges next_group hands out;
    // `rest_*` holds the near faces not yet walked whose group is not
    // empty (cached.occupied: an empty group's range is two reads for
    // nothing; Rust's empty ranges cost nothing, so it has no twin).
    // Tubes: the edge walk.
    let grouped = near_groups(near);
#ifdef BALLS
    // A cone grows balls further: their own near faces.
    var ball_near = near;
#ifdef FOOTPRINT
    ball_near = near_balls;
#endif
    interior_balls(ray, t_end, ball_near);
    var rest_balls = near_groups(ball_near) & cached.occupied.x;
    loop {
        if rest_balls == 0u {
            break;
        }
        let balls_range = next_group(&rest_balls, 0u);
        for (var i = balls_range.x; i < balls_range.y; i++) {
            consider_ball(ray, t_end, ball_near, i);
        }
    }
#endif
#ifdef TUBES
    // The tubes with no edge bits whose faces are near, then for each near
    // face f the tube of each edge it shares with a near face g (Rust: FaceGroups::
    // edge_walk; the edge table is groups[f].w). One pass a tube, the
    // test after the body: the loop lasts as long as its SIMD group's
    // longest walk.
    // Walked by the balls' near faces, which hold `near`, for the
    // joints the tubes carry.
    var edge_near = near;
#ifdef FOOTPRINT
    edge_near = near_balls;
#endif
#ifdef MANY_UNKEYED_TUBES
    // Past the first 32 tubes with no edge bits (a domain of many more
    // faces than 32), each in turn. Compiled only where there are such
    // tubes: the loop cost the 12- and 52-face frames 10 ms each even
    // where it took no pass.
    let unmasked_tubes = groups[0].y;
    for (var i = 32u; i < unmasked_tubes; i++) {
        consider_edge(ray, t_end, near, edge_near, i);
    }
#endif
    var edge_walk = edge_walk_new(edge_near, near_groups(edge_near) & cached.occupied.y);
    var more_tubes = edge_walk_next(&edge_walk, edge_near);
    loop {
        if more_tubes {
            consider_edge(ray, t_end, near, edge_near, edge_walk_tube(&edge_walk));
        }
        more_tubes = edge_walk_next(&edge_walk, edge_near);
        continuing {
            break if !more_tubes;
        }
    }
#endif
#ifdef MESHES
    var rest_meshes = grouped & cached.occupied.z;
    var meshes_range = vec2<u32>(0u, groups[0].z);
    loop {
        for (var i = meshes_range.x; i < meshes_range.y; i++) {
            consider_instance(ray, t_end, cell_point, near, i);
        }
        if rest_meshes == 0u {
            break;
        }
        meshes_range = next_group(&rest_meshes, 2u);
    }
#endif
    return best;
}

#ifdef FOOTPRINT
// Where a layer is shaded (Rust: ConeLayer): the part of the pixel, the
// chart parameter, and the normal there (zero: the object's own).
struct ConeLayer {
    part: f32,
    t: f32,
    normal: vec4<f32>,
}

// Rust twin: cone_layer. At the ray's own hit when shading_offset puts
// the shading there, else where the ray passes nearest, with the normal
// of that offset.
fn cone_layer(ray: Ray, kind: u32, index: u32, c: Cover, t_end: f32) -> ConeLayer {
    let ball = kind == 1u;
    var own = -1.0;
    var n0 = vec4<f32>(0.0);
    let x = normalize_point(ray.origin + ray.dir * c.near.t);
    let view = -normalize_tangent(x, ray.dir);
#ifdef BALLS
    if ball {
        own = hit_ball(ray, balls[index].center, balls[index].k, 0.0);
        n0 = normal_from(x, balls[index].center);
    }
#endif
#ifdef TUBES
    if kind == 2u {
        own = hit_tube(ray, tubes[index], cached.tube_k, 0.0);
        n0 = normal_from(x, foot_on_line(x, tubes[index]));
    }
#endif
    let s = shading_offset(ball, c.gap, c.r, c.w);
    if own >= 0.0 && own <= t_end && c.gap <= s * c.r {
        return ConeLayer(c.part, own, vec4<f32>(0.0));
    }
    return ConeLayer(c.part, c.near.t, normal_at_offset(n0, view, s));
}
#endif

// The unit tangent at x towards the light at l; the normal when the light
// is on x (or, in S3, at its antipode), where the direction is 0 / 0.
// Rust twin: toward_light in crates/bevy_manifold_core/src/trace/render.rs.
fn toward_light(x: vec4<f32>, l: vec4<f32>, normal: vec4<f32>) -> vec4<f32> {
    let t = project_tangent(x, l);
    let len2 = abs(form(t, t));
    if len2 > LIGHT_AT_HIT {
        return t / sqrt(len2);
    }
    return normal;
}

// Lambert + Blinn shading at the hit, lights with geometry-correct
// fall-off (1 / area of the sphere of radius d), per-cell colour, fog.
// The hit's chart parameter is where it is shaded; `normal_at`, when not
// zero, the normal there in place of the object's own (a cone's layer,
// Rust: shade's `normal_at`).
fn shade(ray: Ray, hit: Hit, normal_at: vec4<f32>, dist: f32, cell: vec2<u32>) -> vec3<f32> {
    let x = normalize_point(ray.origin + ray.dir * hit.t);
    let view = -normalize_tangent(x, ray.dir);
    var normal = vec4<f32>(0.0);
    var albedo = vec3<f32>(1.0);
    var glow = 0.0;
#ifdef BALLS
    if hit.kind == 1u {
        normal = normal_from(x, balls[hit.index].center);
        albedo = balls[hit.index].color;
        glow = balls[hit.index].glow;
    }
#endif
#ifdef TUBES
    if hit.kind == 2u {
        let seg = tubes[hit.index];
        normal = normal_from(x, foot_on_line(x, seg));
        albedo = seg.color;
    }
#endif
#ifdef MESHES
    if hit.kind == 3u {
        let inst = instances[hit.index];
        let h = MeshHit(0.0, hit.triangle, hit.u, hit.v);
        normal = mesh_normal(inst, h, x, view);
        albedo = mesh_albedo(inst, h);
    }
#endif
    if any(normal_at != vec4<f32>(0.0)) {
        normal = normal_at;
    }
#ifdef CELL_COLORS
    albedo *= cell_color(cell);
#endif
    // Ambient light and the object's own glow. Rust twin: `shade` in
    // bevy_manifold_core's trace/render.rs.
    var rgb = albedo * (0.08 + glow);
#ifdef LIGHTS
    for (var i = 0u; i < params.light_count; i++) {
        let l = lights[i];
        let d = distance(x, l.position);
        let to_light = toward_light(x, l.position, normal);
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
    let tr = exp(-(cached.fog_density * dist));
    rgb = rgb * tr + params.fog_color.xyz * (1.0 - tr);
#endif
    return rgb;
}
