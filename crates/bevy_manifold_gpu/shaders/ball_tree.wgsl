// The ball tree's packed nodes, as the ball_nodes uniform holds them
// (bindings.wgsl): per node one word, its box's sides in 16-bit steps of
// the frame (BallTree::origin, BallTree::step) and its link. The walk
// itself, ball_tree_leaves, is in render.wgsl, next to the ball tests it
// calls.
//
// Rust twin: crates/bevy_manifold_core/src/trace/ball_tree.rs
// (BallTree::node_box; tree_leaves is ball_tree_leaves' twin). Checked
// against it on the GPU by crates/bevy_manifold_gpu/tests/ball_tree.rs.
#define_import_path bevy_manifold::ball_tree

// The box of a packed node `word`, its least and greatest corners: each
// side a step wider than its 16-bit count, which covers the rounding of
// these f32 sums (a fused multiply-add or not), so it holds the node's
// own box.
fn tree_box(word: vec4<u32>, origin: vec3<f32>, step: vec3<f32>) -> array<vec3<f32>, 2> {
    let lo = origin + (vec3<f32>(word.xyz & vec3<u32>(0xffffu)) - 1.0) * step;
    let hi = origin + (vec3<f32>(word.xyz >> vec3<u32>(16u)) + 1.0) * step;
    return array<vec3<f32>, 2>(lo, hi);
}
