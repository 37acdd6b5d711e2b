//! The ball tree's packed boxes as the GPU decodes them (`tree_box` in
//! `shaders/ball_tree.wgsl`) against the CPU's (`BallTree::node_box`) and
//! against the boxes they pack: each GPU box holds its leaf's box and is
//! the CPU's within a quarter step (the two may round differently, e.g.
//! by a fused multiply-add). The leaves' culling rests on the first: a box
//! that shrank on the GPU alone would drop the rays that graze its balls,
//! a few pixels no image comparison is sure to catch.
//!
//! Without a GPU adapter this test is listed as ignored; under CI (`CI`
//! set) a missing adapter is a failure.

use bevy_manifold_core::trace::BallTree;
use bevy_manifold_gpu::WgslModule;
use bevy_manifold_test_support::Rng;

mod probe;

/// Decodes every leaf after the two words of the frame.
const PROBE: WgslModule = WgslModule {
    path: "bevy_manifold/tests/ball_tree_probe.wgsl",
    source: "
#import bevy_manifold::ball_tree::tree_box

@group(0) @binding(0) var<storage, read> words: array<vec4<u32>>;
@group(0) @binding(1) var<storage, read_write> boxes: array<vec4<f32>>;

@compute @workgroup_size(64, 1, 1)
fn decode(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x + 2u >= arrayLength(&words) {
        return;
    }
    let origin = bitcast<vec3<f32>>(words[0].xyz);
    let step = bitcast<vec3<f32>>(words[1].xyz);
    let b = tree_box(words[id.x + 2u], origin, step);
    boxes[2u * id.x] = vec4<f32>(b[0], 0.0);
    boxes[2u * id.x + 1u] = vec4<f32>(b[1], 0.0);
}
",
};

/// The frames tried, as the core's test: (centre, spread, box size).
const FRAMES: [(f64, f64, f64); 4] = [
    (0.0, 0.8, 0.05),
    (0.3, 20.0, 1.5),
    (1000.0, 0.01, 0.001),
    (-3.0e4, 2.0, 0.02),
];

/// The GPU's boxes of `words` (the frame's two words, then the leaves').
fn decode_on_the_gpu(words: &[[u32; 4]]) -> Vec<[f32; 4]> {
    let leaves = words.len() - 2;
    let bytes = probe::run(
        PROBE,
        &[],
        "decode",
        &[(0, bytemuck::cast_slice(words))],
        (1, (leaves * 2 * 16) as u64),
        leaves as u32,
    );
    bytemuck::pod_collect_to_vec(&bytes)
}

fn the_gpu_decodes_packed_boxes_as_the_cpu_and_they_hold_their_leaves() {
    let mut rng = Rng(53);
    for (at, spread, size) in FRAMES {
        let items: Vec<([f32; 3], [f32; 3])> = (0..254)
            .map(|_| {
                let c = rng.in_box(spread).map(|x| x + at);
                let h = [0; 3].map(|_| size * (0.05 + rng.next_f64()));
                (
                    [0, 1, 2].map(|k| (c[k] - h[k]) as f32),
                    [0, 1, 2].map(|k| (c[k] + h[k]) as f32),
                )
            })
            .collect();
        let tree = BallTree::over(&items).0;
        assert!(!tree.is_empty(), "frame at {at}: packed");
        assert_eq!(tree.words.len(), 32, "frame at {at}: 254 balls in leaves of up to 8");
        let words: Vec<[u32; 4]> = [tree.origin, tree.step]
            .map(|v| [v[0].to_bits(), v[1].to_bits(), v[2].to_bits(), 0])
            .into_iter()
            .chain(tree.words.iter().copied())
            .collect();
        let gpu = decode_on_the_gpu(&words);
        for (i, (node, word)) in tree.leaves.iter().zip(&tree.words).enumerate() {
            let cpu = tree.node_box(word);
            let (lo, hi) = (gpu[2 * i], gpu[2 * i + 1]);
            for k in 0..3 {
                let quarter = 0.25 * tree.step[k];
                assert!(
                    lo[k] <= node.min[k] && hi[k] >= node.max[k],
                    "frame at {at}: leaf {i} axis {k}: the GPU's box {}..{} misses the leaf's {}..{}",
                    lo[k],
                    hi[k],
                    node.min[k],
                    node.max[k]
                );
                assert!(
                    (lo[k] - cpu.0[k]).abs() <= quarter && (hi[k] - cpu.1[k]).abs() <= quarter,
                    "frame at {at}: leaf {i} axis {k}: GPU {}..{}, CPU {}..{}",
                    lo[k],
                    hi[k],
                    cpu.0[k],
                    cpu.1[k]
                );
            }
        }
    }
}

bevy_manifold_test_support::test_main! {
    cpu: [],
    gpu: [the_gpu_decodes_packed_boxes_as_the_cpu_and_they_hold_their_leaves],
}
