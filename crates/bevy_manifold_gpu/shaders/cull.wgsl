// Culling: which objects a segment of a ray can hit (each_candidate).
// Of the objects near the domain's faces, only those whose faces the
// segment comes near, walked by the groups of the `groups` uniform
// (next_group), each edge tube only where both its edge's faces are near
// (the edge walk), with the vertex joint it carries (consider_edge); of
// the balls inside the domain, only those in the leaves of the ball tree
// the segment meets (interior_balls); of a group of many mesh instances,
// only those in the leaves of its tree the segment meets before the
// nearest hit (instance_tree.wgsl). Each is handed to consider_* in
// nearest.wgsl.
//
// Rust twin: crates/bevy_manifold_core/src/trace/cull.rs (each_candidate)
// and face_groups.rs (FaceGroups::ranges and FaceGroups::edge_walk, which
// next_group and the edge walk follow).
//
// Shader defs read: BALLS, TUBES, MESHES, FOOTPRINT (balls tested by
// their own near faces, tree boxes padded), BALL_TREE (the test of the
// ball tree's leaves, BALL_LEAVES of them), MANY_UNKEYED_TUBES (the loop
// over the tubes with no edge bits past the first 32), INSTANCE_TREE (a
// group of instances walked by its tree, instance_tree.wgsl).
#define_import_path bevy_manifold::cull

#import bevy_manifold::bindings::{params, cached, groups, tubes, face_count, FLAG_NO_CULL}
#import bevy_manifold::step::{Ray, may_hit}
#ifdef BALLS
#import bevy_manifold::bindings::balls
#import bevy_manifold::nearest::{consider_ball, meet_ball}
#endif
#ifdef BALL_TREE
#import bevy_manifold::bindings::ball_nodes
#import bevy_manifold::bvh::{hit_box, safe_inverse}
#import bevy_manifold::ball_tree::{leaf_lo, leaf_hi}
#endif
#ifdef TUBES
#import bevy_manifold::bindings::NO_JOINT
#import bevy_manifold::nearest::consider_tube
#endif
#ifdef MESHES
#import bevy_manifold::nearest::consider_instance
#endif
#ifdef INSTANCE_TREE
#import bevy_manifold::bindings::NO_INSTANCE_TREES
#import bevy_manifold::instance_tree::tree_instances
#endif
#import bevy_manifold::ball_tree::chart_segment
#ifdef SHADOWS
#import bevy_manifold::nearest::{best, shadow_ray}
#endif
#ifdef FOOTPRINT
#import bevy_manifold::footprint::BALL_GROWTH
#import bevy_manifold::cone::{cone_grow, near_balls}
#endif

// The near faces that have groups: those of `near` below the face count
// (at most 32).
fn near_groups(near: u32) -> u32 {
    let n = min(face_count(), 32u);
    return select(near & ((1u << n) - 1u), near, n == 32u);
}

// The index range of the group of the first face left in `rest`, which it
// takes out: kind 0 balls, 2 mesh instances (the x and z of groups).
// Rust twin: the ranges after the first of FaceGroups::ranges.
fn next_group(rest: ptr<function, u32>, kind: u32) -> vec2<u32> {
    let f = firstTrailingBit(*rest);
    *rest &= *rest - 1u;
    return vec2<u32>(groups[f][kind], groups[f + 1u][kind]);
}

// Where a walk of the tubes' edge table stands (Rust twin: the iterator
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
// with the loop, 182-187 with the bits; docs/benchmarks/history.md). Rust:
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

#ifdef BALLS
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
    let seg = chart_segment(ray, t_end);
    var pad = 0.0;
#ifdef FOOTPRINT
    pad = cone_grow.w * BALL_GROWTH * params.chart_stretch;
#endif
    if (cached.flags & FLAG_NO_CULL) != 0u || cached.ball_leaves == 0u || cached.ball_leaves > #{BALL_LEAVES}u || !seg.ok || !(pad < 3.0e38) {
        every_interior_ball(ray, t_end, near);
        return;
    }
    ball_tree_leaves(ray, t_end, near, seg.a, seg.d, pad);
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
// (docs/benchmarks/history.md, "The ball tree's leaves tested flat"). Rust twin:
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

// Hands each object a segment may meet to consider_* (nearest.wgsl),
// which keep the nearest hit on the ray within [0, t_end], or under
// FOOTPRINT the segment's layers, seen from the cell whose element takes the
// origin to `cell_point` (the copy of a camera-attached mesh that is the
// camera's own body from there is skipped). Objects whose faces the
// segment does not come near (`near`, from near_faces; under FOOTPRINT
// balls their own, near_balls) are not tested,
// nor balls with no face mask in the leaves of the ball tree the segment
// does not meet (interior_balls); a vertex joint a tube carries is tested
// after its tube (consider_edge). Rust twin: each_candidate.
fn each_candidate(ray: Ray, t_end: f32, cell_point: vec4<f32>, near: u32) {
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
#ifdef SHADOWS
    // A shadow ray wants any hit: once one is found, the rest (the mesh
    // BVHs above all) are not walked. Rust twin: segment_blocked's
    // visitor, which skips every test once blocked.
    if shadow_ray && best.kind != 0u {
        return;
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
    // Each group by its tree where it has one (instance_tree.wgsl), else
    // instance by instance. Group 0 holds the instances with no face
    // mask, group f + 1 face f's.
    var rest_meshes = grouped & cached.occupied.z;
    var meshes_range = vec2<u32>(0u, groups[0].z);
#ifdef INSTANCE_TREE
    // The segment in the chart, once for every group's tree, and the
    // trees' table; none with culling off or the segment past the
    // chart's horizon. Rust twin: the instances' part of each_candidate.
    let seg = chart_segment(ray, t_end);
    let trees = select(NO_INSTANCE_TREES, params.instance_trees, seg.ok && (cached.flags & FLAG_NO_CULL) == 0u);
    var group = 0u;
#endif
    loop {
        var walked = false;
#ifdef INSTANCE_TREE
        walked = trees != NO_INSTANCE_TREES && tree_instances(ray, t_end, cell_point, near, seg, trees + group);
#endif
        if !walked {
            for (var i = meshes_range.x; i < meshes_range.y; i++) {
#ifdef SHADOWS
                if shadow_ray && best.kind != 0u {
                    return;
                }
#endif
                consider_instance(ray, t_end, cell_point, near, i);
            }
        }
        if rest_meshes == 0u {
            break;
        }
#ifdef INSTANCE_TREE
        group = firstTrailingBit(rest_meshes) + 1u;
#endif
        meshes_range = next_group(&rest_meshes, 2u);
    }
#endif
}
