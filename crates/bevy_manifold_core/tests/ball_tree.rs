//! The ball tree's packed nodes: each holds its node's box, by a margin
//! its decoding cannot round away, and is only a few steps wider; and the
//! walk over them hands out every leaf a segment meets. Checked against
//! exact `f64` arithmetic and a brute-force slab test, on boxes near the
//! chart's origin and far from it (where `f32` sums round coarsely).

use bevy_manifold_core::mesh::bvh::build_over_with;
use bevy_manifold_core::trace::{BallTree, LEAF_LINK, tree_leaves};
use bevy_manifold_test_support::Rng;

/// `n` boxes of sides up to `size`, centred within `spread` of `at`.
fn boxes(rng: &mut Rng, n: usize, at: f64, spread: f64, size: f64) -> Vec<([f32; 3], [f32; 3])> {
    (0..n)
        .map(|_| {
            let c = rng.in_box(spread).map(|x| x + at);
            let h = [0; 3].map(|_| size * (0.05 + rng.next_f64()));
            (
                [0, 1, 2].map(|k| (c[k] - h[k]) as f32),
                [0, 1, 2].map(|k| (c[k] + h[k]) as f32),
            )
        })
        .collect()
}

/// The frames tried: (centre, spread, box size); the last two far from
/// the origin against their size, where a step of a 65,535th of the root
/// is below an `f32` ulp of the coordinates.
const FRAMES: [(f64, f64, f64); 4] = [
    (0.0, 0.8, 0.05),
    (0.3, 20.0, 1.5),
    (1000.0, 0.01, 0.001),
    (-3.0e4, 2.0, 0.02),
];

#[test]
fn a_packed_node_holds_its_box_and_is_a_few_steps_wider() {
    let mut rng = Rng(41);
    for (at, spread, size) in FRAMES {
        for n in [16, 100, 254] {
            let (nodes, _) = build_over_with(&boxes(&mut rng, n, at, spread, size), 8);
            let tree = BallTree::new(nodes);
            assert_eq!(tree.words.len(), tree.nodes.len(), "frame at {at}: every node packed");
            let root = &tree.nodes[0];
            for (i, (node, word)) in tree.nodes.iter().zip(&tree.words).enumerate() {
                let (lo, hi) = tree.node_box(word);
                for k in 0..3 {
                    let step = f64::from(tree.step[k]);
                    let side = f64::from(root.max[k] - root.min[k]);
                    let magnitude = f64::from(root.min[k].abs().max(root.max[k].abs()));
                    // A step is small against the root and the coordinates.
                    assert!(
                        step <= (side / 65000.0).max(magnitude / 500_000.0),
                        "frame at {at}: step {step} on axis {k} for a side of {side}"
                    );
                    // Exactly, the packed sides lie half a step or more
                    // outside the node's, so one or two roundings (a
                    // fused multiply-add or not) keep them outside.
                    let (q_lo, q_hi) = (f64::from(word[k] & 0xffff), f64::from(word[k] >> 16));
                    let exact_lo = f64::from(tree.origin[k]) + (q_lo - 1.0) * step;
                    let exact_hi = f64::from(tree.origin[k]) + (q_hi + 1.0) * step;
                    assert!(
                        exact_lo <= f64::from(node.min[k]) - 0.5 * step
                            && exact_hi >= f64::from(node.max[k]) + 0.5 * step,
                        "frame at {at}: node {i} axis {k}: {exact_lo}..{exact_hi} against {}..{}",
                        node.min[k],
                        node.max[k]
                    );
                    // node_box (the walk's, in f32) is that, rounded.
                    assert!(
                        (f64::from(lo[k]) - exact_lo).abs() <= 0.25 * step
                            && (f64::from(hi[k]) - exact_hi).abs() <= 0.25 * step,
                        "frame at {at}: node {i} axis {k}: node_box {}..{} against {exact_lo}..{exact_hi}",
                        lo[k],
                        hi[k]
                    );
                    assert!(
                        lo[k] <= node.min[k] && hi[k] >= node.max[k],
                        "frame at {at}: node {i} axis {k}"
                    );
                    // And no more than three steps wider on each side.
                    assert!(
                        f64::from(node.min[k] - lo[k]) <= 3.0 * step && f64::from(hi[k] - node.max[k]) <= 3.0 * step,
                        "frame at {at}: node {i} axis {k} is loose: {}..{} for {}..{}",
                        lo[k],
                        hi[k],
                        node.min[k],
                        node.max[k]
                    );
                }
                // The link: a leaf's balls, an inner node's skip.
                let link = if node.count > 0 {
                    LEAF_LINK | node.first | (node.count << 16)
                } else {
                    tree.skip[i]
                };
                assert_eq!(word[3], link, "frame at {at}: node {i}'s link");
            }
        }
    }
}

/// Whether the chart segment `a + s d`, `0 <= s <= 1`, meets the box, in
/// `f64`, by the parameter intervals of its three slabs.
fn meets(a: [f64; 3], d: [f64; 3], lo: [f32; 3], hi: [f32; 3]) -> bool {
    let (mut enter, mut leave) = (0.0f64, 1.0f64);
    for k in 0..3 {
        let (l, h) = (f64::from(lo[k]), f64::from(hi[k]));
        if d[k] == 0.0 {
            if a[k] < l || a[k] > h {
                return false;
            }
            continue;
        }
        let (s0, s1) = ((l - a[k]) / d[k], (h - a[k]) / d[k]);
        enter = enter.max(s0.min(s1));
        leave = leave.min(s0.max(s1));
    }
    enter <= leave
}

#[test]
fn the_walk_hands_out_every_leaf_a_segment_meets_once() {
    let mut rng = Rng(43);
    for (at, spread, size) in FRAMES {
        let (nodes, _) = build_over_with(&boxes(&mut rng, 128, at, spread, size), 8);
        let tree = BallTree::new(nodes);
        let leaves: Vec<_> = tree.nodes.iter().filter(|n| n.count > 0).collect();
        let (mut met, mut handed) = (0, 0);
        for _ in 0..2000 {
            let a = rng.in_box(spread * 1.2).map(|x| x + at);
            let b = rng.in_box(spread * 1.2).map(|x| x + at);
            let d = [0, 1, 2].map(|k| b[k] - a[k]);
            let mut seen = Vec::new();
            tree_leaves(&tree, a, d, 0.0, |range| seen.push(range));
            for leaf in &leaves {
                let range = leaf.first as usize..(leaf.first + leaf.count) as usize;
                let n = seen.iter().filter(|&r| *r == range).count();
                assert!(n <= 1, "frame at {at}: leaf {range:?} handed out {n} times");
                if meets(a, d, leaf.min, leaf.max) {
                    met += 1;
                    assert_eq!(
                        n, 1,
                        "frame at {at}: the segment meets leaf {range:?} but it is not walked"
                    );
                }
            }
            handed += seen.len();
        }
        // Culling, near the chart's origin (where domains are): the walk
        // hands out few more leaves than the segments meet (a few steps
        // of packing). Far from it a step is 2^-20 of the coordinates, as
        // wide as these boxes: the walk is right but culls less.
        assert!(met > 0, "frame at {at}: no segment met a leaf");
        assert!(
            at.abs() > 100.0 || handed <= met + met / 10 + 20,
            "frame at {at}: {handed} leaves handed out for {met} met"
        );
    }
}

#[test]
fn a_tree_whose_frame_is_not_finite_is_not_walked() {
    let mut rng = Rng(47);
    let mut items = boxes(&mut rng, 20, 0.0, 1.0, 0.1);
    items[3].1[0] = f32::INFINITY;
    let (nodes, _) = build_over_with(&items, 8);
    let tree = BallTree::new(nodes);
    assert!(!tree.nodes.is_empty());
    assert!(tree.is_empty(), "no words, so every ball is tested");
    let mut walked = 0;
    tree_leaves(&tree, [0.0f64; 3], [1.0, 0.0, 0.0], 0.0, |_| walked += 1);
    assert_eq!(walked, 0);
}
