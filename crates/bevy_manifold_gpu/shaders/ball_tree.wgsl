// The ball tree's packed leaves, as the ball_nodes uniform holds them
// (bindings.wgsl): per leaf one word, its box's sides in 16-bit steps of
// the frame (BallTree::origin, BallTree::step) and its run of balls; and
// their boxes, decoded once per invocation into private arrays of
// BALL_LEAVES (cache_leaves). The test of a segment against them,
// ball_tree_leaves, is in cull.wgsl, next to the ball tests it calls.
//
// Rust twin: crates/bevy_manifold_core/src/trace/ball_tree.rs
// (BallTree::node_box; tree_leaves is ball_tree_leaves' twin). Checked
// against it on the GPU by crates/bevy_manifold_gpu/tests/ball_tree.rs.
#define_import_path bevy_manifold::ball_tree

#import bevy_manifold::step::Ray
#ifdef BALL_TREE
#import bevy_manifold::bindings::ball_nodes
#endif

// A segment of a ray, o + t dir for 0 <= t <= t_end, in the chart's
// coordinates x/w, where it is straight: its start `a` and the step `d` to
// its end; `ok` false when an end is not finite or at or past the chart's
// horizon (w <= 0, S3 only), and then the trees are not walked. Rust
// twin: chart_segment in crates/bevy_manifold_core/src/trace/ball_tree.rs.
struct ChartSegment {
    a: vec3<f32>,
    d: vec3<f32>,
    ok: bool,
}

fn chart_segment(ray: Ray, t_end: f32) -> ChartSegment {
    let o = ray.origin;
    let e = ray.origin + ray.dir * t_end;
    let a = o.xyz / o.w;
    let d = e.xyz / e.w - a;
    let finite = all(abs(a) < vec3<f32>(3.0e38)) && all(abs(d) < vec3<f32>(3.0e38));
    return ChartSegment(a, d, t_end < 3.0e38 && o.w > 0.0 && e.w > 0.0 && finite);
}

// The box of a packed leaf `word`, its least and greatest corners: each
// side a step wider than its 16-bit count, which covers the rounding of
// these f32 sums (a fused multiply-add or not), so it holds the leaf's
// own box.
fn tree_box(word: vec4<u32>, origin: vec3<f32>, step: vec3<f32>) -> array<vec3<f32>, 2> {
    let lo = origin + (vec3<f32>(word.xyz & vec3<u32>(0xffffu)) - 1.0) * step;
    let hi = origin + (vec3<f32>(word.xyz >> vec3<u32>(16u)) + 1.0) * step;
    return array<vec3<f32>, 2>(lo, hi);
}

#ifdef BALL_TREE
// The value def BALL_LEAVES (TraceDefs::ball_leaves): the leaves the
// pipeline tests, a constant, so that ball_tree_leaves' loops over them
// have constant trip counts, are unrolled, and read these arrays at
// constant indices (a plain load; a uniform read at a run-time index is a
// gather, lane by lane, and even at a constant index costs lavapipe
// several times a private read: bindings.wgsl's planes). Leaves past
// cached.ball_leaves (a pipeline compiled for more than this scene has)
// are decoded from whatever the uniform holds there, and
// ball_tree_leaves drops their bits. WGSL only: Rust reads
// BallTree::words.
var<private> leaf_lo: array<vec3<f32>, #{BALL_LEAVES}u>;
var<private> leaf_hi: array<vec3<f32>, #{BALL_LEAVES}u>;

// Fills leaf_lo and leaf_hi from ball_nodes, after cache_params. In
// chunks of 16 with constant bounds, as step.wgsl's FACE_CHUNK.
fn cache_leaves() {
    cache_leaves_in(0u, min(#{BALL_LEAVES}u, 16u));
    cache_leaves_in(16u, min(#{BALL_LEAVES}u, 32u));
    cache_leaves_in(32u, min(#{BALL_LEAVES}u, 48u));
    cache_leaves_in(48u, min(#{BALL_LEAVES}u, 64u));
}

// Leaves lo to hi - 1 of cache_leaves.
fn cache_leaves_in(lo: u32, hi: u32) {
    let origin = bitcast<vec3<f32>>(ball_nodes[0].xyz);
    let step = bitcast<vec3<f32>>(ball_nodes[1].xyz);
    for (var l = lo; l < hi; l++) {
        let box = tree_box(ball_nodes[2u + l], origin, step);
        leaf_lo[l] = box[0];
        leaf_hi[l] = box[1];
    }
}
#endif
