//! The ball tree: its leaves split the balls evenly and by position; each
//! packed leaf holds its box, by a margin its decoding cannot round away,
//! and is only a few steps wider; and the test hands out every leaf a
//! segment meets. Checked against the boxes themselves, exact `f64`
//! arithmetic and a brute-force slab test, on boxes near the chart's
//! origin and far from it (where `f32` sums round coarsely).

use bevy_manifold_core::mesh::bvh::{hit_box, safe_inverse};
use bevy_manifold_core::trace::{BallTree, MAX_BALL_LEAVES, leaf_count, tree_leaves};
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
fn a_packed_leaf_holds_its_box_and_is_a_few_steps_wider() {
    let mut rng = Rng(41);
    for (at, spread, size) in FRAMES {
        for n in [16, 100, 254] {
            let items = boxes(&mut rng, n, at, spread, size);
            let (tree, _) = BallTree::over(&items);
            assert_eq!(tree.words.len(), tree.leaves.len(), "frame at {at}: every leaf packed");
            // The frame: the least and greatest corners of all the boxes.
            let min = [0, 1, 2].map(|k| items.iter().map(|b| b.0[k]).fold(f32::INFINITY, f32::min));
            let max = [0, 1, 2].map(|k| items.iter().map(|b| b.1[k]).fold(f32::NEG_INFINITY, f32::max));
            assert_eq!(tree.origin, min, "frame at {at}: the frame's origin");
            for (i, (leaf, word)) in tree.leaves.iter().zip(&tree.words).enumerate() {
                let (lo, hi) = tree.node_box(word);
                for k in 0..3 {
                    let step = f64::from(tree.step[k]);
                    let side = f64::from(max[k] - min[k]);
                    let magnitude = f64::from(min[k].abs().max(max[k].abs()));
                    // A step is small against the frame and the coordinates.
                    assert!(
                        step <= (side / 65000.0).max(magnitude / 500_000.0),
                        "frame at {at}: step {step} on axis {k} for a side of {side}"
                    );
                    // Exactly, the packed sides lie half a step or more
                    // outside the leaf's, so one or two roundings (a
                    // fused multiply-add or not) keep them outside.
                    let (q_lo, q_hi) = (f64::from(word[k] & 0xffff), f64::from(word[k] >> 16));
                    let exact_lo = f64::from(tree.origin[k]) + (q_lo - 1.0) * step;
                    let exact_hi = f64::from(tree.origin[k]) + (q_hi + 1.0) * step;
                    assert!(
                        exact_lo <= f64::from(leaf.min[k]) - 0.5 * step
                            && exact_hi >= f64::from(leaf.max[k]) + 0.5 * step,
                        "frame at {at}: leaf {i} axis {k}: {exact_lo}..{exact_hi} against {}..{}",
                        leaf.min[k],
                        leaf.max[k]
                    );
                    // node_box (the test's, in f32) is that, rounded.
                    assert!(
                        (f64::from(lo[k]) - exact_lo).abs() <= 0.25 * step
                            && (f64::from(hi[k]) - exact_hi).abs() <= 0.25 * step,
                        "frame at {at}: leaf {i} axis {k}: node_box {}..{} against {exact_lo}..{exact_hi}",
                        lo[k],
                        hi[k]
                    );
                    assert!(
                        lo[k] <= leaf.min[k] && hi[k] >= leaf.max[k],
                        "frame at {at}: leaf {i} axis {k}"
                    );
                    // And no more than three steps wider on each side.
                    assert!(
                        f64::from(leaf.min[k] - lo[k]) <= 3.0 * step && f64::from(hi[k] - leaf.max[k]) <= 3.0 * step,
                        "frame at {at}: leaf {i} axis {k} is loose: {}..{} for {}..{}",
                        lo[k],
                        hi[k],
                        leaf.min[k],
                        leaf.max[k]
                    );
                }
                // The run: its first ball and count.
                assert_eq!(
                    word[3],
                    leaf.first | (leaf.count << 16),
                    "frame at {at}: leaf {i}'s run"
                );
            }
        }
    }
}

/// The leaves split the balls as a median split must: a power of two of
/// them ([`leaf_count`]), runs that follow one another and cover every
/// ball once, sizes within one of each other, each leaf's box the least
/// that holds its balls' boxes, and the two halves of each split apart
/// along some axis (no ball of the left half's centre past the right
/// half's on the axis the split chose): checked against the boxes
/// themselves, for ball counts from the tree's least to past its most
/// leaves.
#[test]
fn the_balls_split_into_a_power_of_two_of_even_leaves() {
    let mut rng = Rng(42);
    // Leaves of up to 4 while there are up to 16 of them, then of up to
    // 8 (16 leaves up to 128 balls, 32 up to 256), then 64.
    let want = [
        (1, 1),
        (4, 1),
        (5, 2),
        (8, 2),
        (9, 4),
        (16, 4),
        (17, 8),
        (64, 16),
        (65, 16),
        (128, 16),
        (129, 32),
        (256, 32),
        (257, 64),
        (100_000, 64),
    ];
    for (n, k) in want {
        assert_eq!(leaf_count(n), k, "{n} balls");
    }
    assert_eq!(MAX_BALL_LEAVES, 64);
    for n in [9, 16, 17, 100, 254, 1000] {
        let items = boxes(&mut rng, n, 0.0, 1.0, 0.05);
        let (tree, order) = BallTree::over(&items);
        let k = tree.leaves.len();
        assert_eq!(k, leaf_count(n), "{n} balls");
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..n as u32).collect::<Vec<_>>(), "{n} balls: each ball once");
        let (least, most) = (n / k, n.div_ceil(k));
        let mut next = 0;
        for (i, leaf) in tree.leaves.iter().enumerate() {
            assert_eq!(leaf.first as usize, next, "{n} balls: leaf {i} follows the last");
            assert!(
                (least..=most).contains(&(leaf.count as usize)),
                "{n} balls: leaf {i} of {}",
                leaf.count
            );
            next += leaf.count as usize;
            let run = &order[leaf.first as usize..next];
            for axis in 0..3 {
                let lo = run
                    .iter()
                    .map(|&b| items[b as usize].0[axis])
                    .fold(f32::INFINITY, f32::min);
                let hi = run
                    .iter()
                    .map(|&b| items[b as usize].1[axis])
                    .fold(f32::NEG_INFINITY, f32::max);
                assert_eq!((leaf.min[axis], leaf.max[axis]), (lo, hi), "{n} balls: leaf {i}'s box");
            }
        }
        assert_eq!(next, n);
        // Every split, the halves of the root first, parts along an axis.
        let centre = |b: u32, axis: usize| {
            let (lo, hi) = items[b as usize];
            0.5 * lo[axis] + 0.5 * hi[axis]
        };
        let mut width = k;
        while width > 1 {
            for part in (0..k).step_by(width) {
                let span = |from: usize, to: usize| {
                    let first = tree.leaves[from].first as usize;
                    let last = tree.leaves[to - 1].first as usize + tree.leaves[to - 1].count as usize;
                    &order[first..last]
                };
                let (left, right) = (span(part, part + width / 2), span(part + width / 2, part + width));
                let apart = (0..3).any(|axis| {
                    let left_max = left.iter().map(|&b| centre(b, axis)).fold(f32::NEG_INFINITY, f32::max);
                    let right_min = right.iter().map(|&b| centre(b, axis)).fold(f32::INFINITY, f32::min);
                    left_max <= right_min
                });
                assert!(
                    apart,
                    "{n} balls: the split of leaves {part}..{} parts no axis",
                    part + width
                );
            }
            width /= 2;
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

/// The test hands out each leaf a segment meets, once, in order, and
/// only those whose packed box the segment meets in `f32` (the GPU's
/// rule, tested leaf by leaf): the boxes above the leaves (`inner`, which
/// the CPU skips by) drop none. And every leaf the segment meets exactly
/// is handed out.
#[test]
fn the_test_hands_out_every_leaf_a_segment_meets_once() {
    let mut rng = Rng(43);
    for (at, spread, size) in FRAMES {
        for n in [100, 254] {
            let (tree, _) = BallTree::over(&boxes(&mut rng, n, at, spread, size));
            assert_eq!(
                tree.inner.len() + 1,
                tree.words.len(),
                "frame at {at}: a whole tree above the leaves"
            );
            let (mut met, mut handed) = (0, 0);
            for pad in [0.0f32, 0.05 * size as f32] {
                for _ in 0..2000 {
                    let a = rng.in_box(spread * 1.2).map(|x| x + at);
                    let b = rng.in_box(spread * 1.2).map(|x| x + at);
                    let d = [0, 1, 2].map(|k| b[k] - a[k]);
                    let mut seen = Vec::new();
                    tree_leaves(&tree, a, d, pad, |range| seen.push(range));
                    // Leaf by leaf, as the GPU tests them.
                    let inv_d = safe_inverse(d);
                    let flat: Vec<_> = tree
                        .leaves
                        .iter()
                        .zip(&tree.words)
                        .filter(|(_, w)| {
                            let (lo, hi) = tree.node_box(w);
                            hit_box(a, inv_d, lo.map(|x| x - pad), hi.map(|x| x + pad), 1.0).is_some()
                        })
                        .map(|(l, _)| l.first as usize..(l.first + l.count) as usize)
                        .collect();
                    assert_eq!(seen, flat, "frame at {at}: the tree's leaves against each leaf's test");
                    for leaf in &tree.leaves {
                        let grown = (leaf.min.map(|x| x - pad), leaf.max.map(|x| x + pad));
                        if meets(a, d, grown.0, grown.1) {
                            met += 1;
                            let range = leaf.first as usize..(leaf.first + leaf.count) as usize;
                            assert!(
                                seen.contains(&range),
                                "frame at {at}: the segment meets leaf {range:?} but it is not handed out"
                            );
                        }
                    }
                    handed += seen.len();
                }
            }
            // Culling, near the chart's origin (where domains are): few
            // more leaves are handed out than the segments meet (a few
            // steps of packing). Far from it a step is 2^-20 of the
            // coordinates, as wide as these boxes: right, but it culls
            // less.
            assert!(met > 0, "frame at {at}: no segment met a leaf");
            assert!(
                at.abs() > 100.0 || handed <= met + met / 10 + 20,
                "frame at {at}: {handed} leaves handed out for {met} met"
            );
        }
    }
}

#[test]
fn a_tree_whose_frame_is_not_finite_hands_out_no_leaf() {
    let mut rng = Rng(47);
    let mut items = boxes(&mut rng, 20, 0.0, 1.0, 0.1);
    items[3].1[0] = f32::INFINITY;
    let (tree, _) = BallTree::over(&items);
    assert!(!tree.leaves.is_empty());
    assert!(tree.is_empty(), "no words, so every ball is tested");
    let mut handed = 0;
    tree_leaves(&tree, [0.0f64; 3], [1.0, 0.0, 0.0], 0.0, |_| handed += 1);
    assert_eq!(handed, 0);
}
