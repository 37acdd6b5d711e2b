//! The ball tree: the balls with no face mask
//! ([`super::FlatScene::ball_tree`]) split in halves, and halves of
//! halves, into a power of two of leaves ([`leaf_count`]), and the test
//! that hands a segment the leaves it may meet ([`tree_leaves`]). In the
//! chart where geodesics are straight (`x/w`, `y/w`, `z/w`) a segment of a
//! ray is a straight segment ([`chart_segment`]) and a ball's image fits a
//! box ([`ball_box`]), so a leaf is met or not by a slab test of its box,
//! as a mesh's nodes are. Only the leaves are kept, and every segment
//! tests every leaf: the GPU tests them at constant indices, a plain
//! vector test each, where a walk down the tree read each node lane by
//! lane (docs/benchmarks/history.md, "The ball tree's leaves tested flat").
//!
//! WGSL twin: `interior_balls` and `ball_tree_leaves` in
//! `bevy_manifold_gpu`'s `shaders/cull.wgsl`, and `cache_leaves` in
//! `shaders/ball_tree.wgsl`, which reads the tree's words
//! ([`BallTree::words`]) from the `ball_nodes` uniform of
//! `shaders/bindings.wgsl`.

use super::step::Ray;
use crate::geometry::{Geometry, Real};
use crate::mesh::bvh::{Aabb, BvhNode, hit_box, safe_inverse};
use core::ops::Range;
use glam::DVec4;

/// Bigger than any chart coordinate of a domain: the box of a ball whose
/// chart image is unbounded (in S3, one reaching the chart's horizon)
/// spans the chart. Finite, so box areas and slab tests stay finite.
pub const UNBOUNDED: f32 = 1e18;

/// The box (least and greatest `x/w`, `y/w`, `z/w`) of the ball of centre
/// `c` (a normalised point) and `k` (`cosh r`, `cos r` or `r^2`, as
/// [`super::step::hit_ball`] takes it) in the chart where geodesics are
/// straight: the ball's image there is the ellipsoid
/// `X^T M X - 2 b.X + e <= 0` (`X` the chart point, `C` the centre's
/// `xyz`, `c_w` its `w`), with `M = k^2 I + s C C^T`, `b = c_w C` and
/// `e = s (c_w^2 - k^2)`: the squares of `(c_w - X.C)^2 <= k^2 (1 - |X|^2)`
/// in H3 (`s = 1`) and `(c_w + X.C)^2 >= k^2 (1 + |X|^2)` in S3 (`s = -1`),
/// and `|X - C|^2 <= k` in E3. Its box is centred on `M^-1 b`, with half-sides
/// `sqrt((b^T M^-1 b - e) (M^-1)_ii)`; `M^-1` by Sherman-Morrison. Rounded
/// outwards to `f32` and widened by a hair (`1e-5` of the size and of the
/// distance from the chart's origin), so an `f32` ray's hit on the ball
/// is never outside it. A ball whose image is not bounded gets
/// [`UNBOUNDED`] sides.
///
/// WGSL: the GPU reads these boxes (`GpuObjects::mesh_data`); it computes
/// none.
#[must_use]
pub fn ball_box(g: Geometry, c: DVec4, k: f64) -> ([f32; 3], [f32; 3]) {
    let big = ([-UNBOUNDED; 3], [UNBOUNDED; 3]);
    let cc = c.truncate();
    let (centre, half) = match g {
        Geometry::Euclidean => {
            let r = k.max(0.0).sqrt();
            (cc / c.w, glam::DVec3::splat(r))
        }
        Geometry::Hyperbolic | Geometry::Spherical => {
            let s = if g == Geometry::Hyperbolic { 1.0 } else { -1.0 };
            let k2 = k * k;
            // M C = (k^2 + s |C|^2) C.
            let along = k2 + s * cc.length_squared();
            if !(along > 0.0 && k2 > 0.0) {
                return big;
            }
            let centre = cc * (c.w / along);
            let e = if s > 0.0 { c.w * c.w - k2 } else { k2 - c.w * c.w };
            let level = (c.w * c.w * cc.length_squared() / along - e).max(0.0);
            let inv_diag = (glam::DVec3::ONE - s * cc * cc / along) / k2;
            (centre, (inv_diag.max(glam::DVec3::ZERO) * level).sqrt())
        }
    };
    let (lo, hi) = (centre - half, centre + half);
    if !(lo.is_finite() && hi.is_finite()) {
        return big;
    }
    let hair = 1e-5 * (half.max_element() + centre.abs().max_element() + 1.0);
    let down = |x: f64| {
        let f = (x - hair) as f32;
        if f64::from(f) > x - hair { f.next_down() } else { f }
    };
    let up = |x: f64| {
        let f = (x + hair) as f32;
        if f64::from(f) < x + hair { f.next_up() } else { f }
    };
    let clamp = |f: f32| f.clamp(-UNBOUNDED, UNBOUNDED);
    (
        [0, 1, 2].map(|i| clamp(down(lo[i]))),
        [0, 1, 2].map(|i| clamp(up(hi[i]))),
    )
}

/// The segment `o + t d`, `0 <= t <= t_end`, of a ray in the chart's
/// coordinates `x/w`, where it is straight: its start `a` and the step
/// `b - a` to its end, so its points are `a + s (b - a)`, `0 <= s <= 1`.
/// `None` when an end is not finite or at or past the chart's horizon
/// (`w <= 0`, S3 only): the caller then tests every ball.
/// WGSL twin: `chart_segment` in `shaders/ball_tree.wgsl`.
#[inline]
#[must_use]
pub fn chart_segment<R: Real>(ray: &Ray<R>, t_end: R) -> Option<([R; 3], [R; 3])> {
    let o = R::xyzw(ray.origin);
    let e = R::xyzw(ray.origin + ray.dir * t_end);
    let zero = R::of(0.0);
    if !(t_end.is_finite() && o[3] > zero && e[3] > zero) {
        return None;
    }
    let a = [o[0] / o[3], o[1] / o[3], o[2] / o[3]];
    let b = [e[0] / e[3], e[1] / e[3], e[2] / e[3]];
    let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    (a.iter().chain(&d).all(|x| x.is_finite())).then_some((a, d))
}

/// The most leaves a ball tree has: the GPU tests each leaf's box on
/// every segment, whether met or not, so more balls make fuller leaves
/// rather than more of them (`bevy_manifold_gpu`'s `ball_nodes` uniform
/// holds this many).
pub const MAX_BALL_LEAVES: usize = 64;

/// Balls a leaf is filled to, at most, while the tree has up to
/// [`SMALL_LEAVES`] leaves: up to 64 balls. Every leaf's box costs every
/// segment a slab test, and every ball of a met leaf a test whose words
/// are gathered lane by lane. `bench balls`, 320x180, 8 levels, GPU ms,
/// four alternated runs (docs/benchmarks/history.md, "The ball tree's leaves tested
/// flat"): with leaves of up to 4 rather than 8, Seifert-Weber's 64 balls
/// (16 leaves, not 8) took 18.9-19.6 against 21.6-23.3, and 32 balls
/// 17.2-17.5 against 19.4-21.0.
pub const BALL_LEAF_SIZE: usize = 4;

/// The leaves up to which they hold [`BALL_LEAF_SIZE`] balls; past them,
/// leaves fill to [`FULL_LEAF_SIZE`] before they double. At 100 balls,
/// 16 leaves of up to 8 took 14.1 ms in the torus, 19.6 in Seifert-Weber
/// and 17.1 in the Poincare sphere (median of six runs) against 15.7,
/// 19.2 and 16.6 with 32 leaves of up to 4; at 254 balls 64 leaves of 4
/// were slower than 32 of 8.
pub const SMALL_LEAVES: usize = 16;

/// Balls a leaf is filled to, at most, past [`SMALL_LEAVES`] leaves (up
/// to [`MAX_BALL_LEAVES`]; beyond that, fuller). Up to 16 (8 leaves at 100
/// balls) was slower in Seifert-Weber: 22.7-24.0 ms against 19.7-20.8.
pub const FULL_LEAF_SIZE: usize = 8;

/// The leaves of a ball tree over `n` balls, a power of two from 1 to
/// [`MAX_BALL_LEAVES`]: the least that holds them in leaves of
/// [`BALL_LEAF_SIZE`], at most [`SMALL_LEAVES`], and at least the least
/// that holds them in leaves of [`FULL_LEAF_SIZE`]. So 4 balls a leaf up
/// to 64 balls, 16 leaves up to 128, 32 up to 256. A power of two, so the
/// GPU compiles one pipeline per doubling (its `BALL_LEAVES`), not one per
/// ball count.
///
/// ```
/// use bevy_manifold_core::trace::leaf_count;
/// assert_eq!(leaf_count(9), 4);
/// assert_eq!(leaf_count(64), 16);
/// assert_eq!(leaf_count(100), 16);
/// assert_eq!(leaf_count(254), 32);
/// assert_eq!(leaf_count(1000), 64);
/// ```
#[must_use]
pub fn leaf_count(n: usize) -> usize {
    let small = n.div_ceil(BALL_LEAF_SIZE).next_power_of_two().min(SMALL_LEAVES);
    let full = n.div_ceil(FULL_LEAF_SIZE).next_power_of_two();
    small.max(full).clamp(1, MAX_BALL_LEAVES)
}

/// The steps a packed box side is counted in: 16 bits.
const STEPS: f32 = 65535.0;

/// The ball tree's leaves, over the chart boxes of balls ([`ball_box`]):
/// `leaves`, each the box of a run of balls, in the balls' order, and the
/// same as the tests read them, one packed word of four `u32` each
/// ([`BallTree::words`]): the box in 16-bit steps of the frame of all of
/// them ([`BallTree::node_box`]) and the run of balls. Built by
/// [`BallTree::over`].
///
/// ```
/// use bevy_manifold_core::trace::BallTree;
/// // Sixteen unit boxes along x: four leaves of four.
/// let boxes: Vec<_> = (0..16).map(|i| ([i as f32, 0.0, 0.0], [i as f32 + 1.0, 1.0, 1.0])).collect();
/// let (tree, order) = BallTree::over(&boxes);
/// assert_eq!(tree.leaves.len(), 4);
/// // The balls in the leaves' order: left to right.
/// assert_eq!(order, (0..16).collect::<Vec<u32>>());
/// assert_eq!((tree.leaves[1].first, tree.leaves[1].count), (4, 4));
/// // A word's last entry is its run of balls, first and count.
/// assert_eq!(tree.words[1][3], 4 | (4 << 16));
/// // Every packed box holds the boxes of its leaf, and not much more.
/// let (lo, hi) = tree.node_box(&tree.words[1]);
/// assert!(lo[0] <= 4.0 && lo[0] > 3.99 && hi[0] >= 8.0 && hi[0] < 8.01);
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BallTree {
    /// The leaves, in the balls' order: each one's box, `first` ball and
    /// `count` of balls.
    pub leaves: Vec<BvhNode>,
    /// The frame of the packed boxes: the least corner of all leaves...
    pub origin: [f32; 3],
    /// ...and one step per axis: a 65,535th of the side of the box of all
    /// leaves, or 2^-20 of the frame's largest coordinate if that is more,
    /// so that `f32` rounding in [`BallTree::node_box`] stays below a
    /// step.
    pub step: [f32; 3],
    /// Per leaf, as the tests read it (one `vec4<u32>` of the GPU's
    /// `ball_nodes`): for x, y and z, the box's least side in steps from
    /// `origin`, rounded down, in the low 16 bits and its greatest,
    /// rounded up, in the high 16; then the leaf's first ball in the low
    /// 16 bits and its ball count in the high 16. Empty, and so no tree
    /// ([`BallTree::is_empty`]), when there are no leaves, the frame is
    /// not finite, or an index does not fit its bits.
    pub words: Vec<[u32; 4]>,
    /// The boxes of the tree above the leaves, for the CPU's test only:
    /// with a power of two of leaves, one less than the leaves, the root
    /// first and node `i`'s halves at `2i + 1` and `2i + 2` (the leaves
    /// after them, in order), each the least box holding its halves'
    /// packed boxes ([`BallTree::node_box`]), so a segment that meets a
    /// leaf meets every box above it, and [`tree_leaves`] skips a half
    /// whose box it misses without missing a leaf. Empty otherwise.
    pub inner: Vec<([f32; 3], [f32; 3])>,
}

impl BallTree {
    /// The tree over `boxes` (least and greatest corners, one per ball),
    /// and the order of the balls its leaves index into: the boxes split
    /// at the median of their centres along the longest side of the
    /// centres' bounds, into halves of one or the other size, and each
    /// half again, until there are [`leaf_count`] leaves. None for no
    /// boxes.
    #[must_use]
    pub fn over(boxes: &[([f32; 3], [f32; 3])]) -> (Self, Vec<u32>) {
        let mut order: Vec<u32> = (0..boxes.len() as u32).collect();
        if boxes.is_empty() {
            return (BallTree::default(), order);
        }
        let mut leaves = Vec::with_capacity(leaf_count(boxes.len()));
        split(boxes, &mut order, 0, leaf_count(boxes.len()), &mut leaves);
        (BallTree::new(leaves), order)
    }

    /// The tree of `leaves` (each with its box, `first` ball and `count`),
    /// with each one's packed word.
    #[must_use]
    pub fn new(leaves: Vec<BvhNode>) -> Self {
        let mut tree = BallTree {
            leaves,
            ..BallTree::default()
        };
        tree.pack();
        tree
    }

    /// Fills `origin`, `step` and `words` from `leaves`, or leaves `words`
    /// empty where they do not fit.
    fn pack(&mut self) {
        if self.leaves.is_empty() || self.leaves.len() > 0xffff {
            return;
        }
        let (origin, top) = hull(self.leaves.iter().map(|l| (l.min, l.max)));
        let step: [f32; 3] = [0, 1, 2].map(|k| {
            let size = (top[k] - origin[k]) / STEPS;
            let magnitude = origin[k].abs().max(top[k].abs()) * (1.0 / 1_048_576.0);
            size.max(magnitude).max(f32::MIN_POSITIVE)
        });
        if !origin.iter().chain(&top).chain(&step).all(|x| x.is_finite()) {
            return;
        }
        let mut words = Vec::with_capacity(self.leaves.len());
        for leaf in &self.leaves {
            let side = |k: usize| {
                let lo = ((leaf.min[k] - origin[k]) / step[k]).floor().clamp(0.0, STEPS) as u32;
                let hi = ((leaf.max[k] - origin[k]) / step[k]).ceil().clamp(0.0, STEPS) as u32;
                lo | (hi << 16)
            };
            if leaf.first > 0xffff || leaf.count > 0xffff {
                return;
            }
            words.push([side(0), side(1), side(2), leaf.first | (leaf.count << 16)]);
        }
        self.origin = origin;
        self.step = step;
        self.words = words;
        let n = self.words.len();
        if n.is_power_of_two() {
            let mut boxes: Vec<_> = vec![([0.0; 3], [0.0; 3]); n - 1];
            boxes.extend(self.words.iter().map(|w| self.node_box(w)));
            for i in (0..n - 1).rev() {
                boxes[i] = hull([boxes[2 * i + 1], boxes[2 * i + 2]]);
            }
            boxes.truncate(n - 1);
            self.inner = boxes;
        }
    }

    /// The box of a packed leaf (one of [`BallTree::words`]): its sides
    /// widened by a step each way, which covers the rounding of the
    /// frame's `f32` sums, so it holds the box it packs. WGSL twin:
    /// `tree_box` in `shaders/ball_tree.wgsl`.
    #[must_use]
    pub fn node_box(&self, word: &[u32; 4]) -> ([f32; 3], [f32; 3]) {
        let lo = [0, 1, 2].map(|k| self.origin[k] + ((word[k] & 0xffff) as f32 - 1.0) * self.step[k]);
        let hi = [0, 1, 2].map(|k| self.origin[k] + ((word[k] >> 16) as f32 + 1.0) * self.step[k]);
        (lo, hi)
    }

    /// True when there is no tree to test (every ball is tested).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.words.is_empty()
    }
}

/// The least box holding `boxes` (least and greatest corners), by the
/// mesh hierarchy's [`Aabb::join`].
fn hull(boxes: impl IntoIterator<Item = ([f32; 3], [f32; 3])>) -> ([f32; 3], [f32; 3]) {
    let mut all = Aabb::EMPTY;
    for (min, max) in boxes {
        all.join(&Aabb { min, max });
    }
    (all.min, all.max)
}

/// Splits `order` (balls `first..` of the tree) into `leaves` leaves
/// (a power of two) at the median of their boxes' centres along the
/// longest side of the centres' bounds, pushing the leaves in order.
fn split(boxes: &[([f32; 3], [f32; 3])], order: &mut [u32], first: usize, leaves: usize, out: &mut Vec<BvhNode>) {
    let centre = |i: u32, k: usize| {
        let (lo, hi) = boxes[i as usize];
        0.5 * lo[k] + 0.5 * hi[k]
    };
    if leaves <= 1 || order.len() <= 1 {
        let (min, max) = hull(order.iter().map(|&i| boxes[i as usize]));
        out.push(BvhNode {
            min,
            first: first as u32,
            max,
            count: order.len() as u32,
        });
        return;
    }
    let axis = (0..3)
        .map(|k| {
            let (lo, hi) = order.iter().fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &i| {
                (lo.min(centre(i, k)), hi.max(centre(i, k)))
            });
            (k, hi - lo)
        })
        .fold(
            (0, f32::NEG_INFINITY),
            |best, (k, side)| if side > best.1 { (k, side) } else { best },
        )
        .0;
    let half = order.len() / 2;
    order.select_nth_unstable_by(half, |&a, &b| {
        centre(a, axis).total_cmp(&centre(b, axis)).then(a.cmp(&b))
    });
    let (left, right) = order.split_at_mut(half);
    left.sort_unstable();
    right.sort_unstable();
    split(boxes, left, first, leaves / 2, out);
    split(boxes, right, first + half, leaves / 2, out);
}

/// Calls `visit` with the ball range of every leaf of `tree` (over chart
/// boxes, [`super::FlatScene::ball_tree`]) whose packed box
/// ([`BallTree::node_box`]), grown by `pad` on every side (cone tracing's
/// growth, 0 for a ray), the chart segment `a + s d`, `0 <= s <= 1`,
/// meets (the slab test, `mesh::bvh::hit_box`), in the leaves' order.
/// The GPU tests every leaf's box before it tests a ball; here a half of
/// the tree whose box ([`BallTree::inner`]) the segment misses is skipped,
/// which skips only leaves it misses (the boxes above a leaf hold it, and
/// the slab test in `f32` meets a box that holds a met one), so the same
/// leaves come out in the same order as from a test of each leaf. (The
/// GPU decodes each box within a quarter step of [`BallTree::node_box`],
/// and holding the leaf's balls either way, so a grazing segment may meet
/// a leaf on one side only; no ball hit is lost.) WGSL twin:
/// `ball_tree_leaves` in `shaders/cull.wgsl`.
pub fn tree_leaves<R: Real>(tree: &BallTree, a: [R; 3], d: [R; 3], pad: f32, mut visit: impl FnMut(Range<usize>)) {
    let inv_d = safe_inverse(d);
    let met = |(lo, hi): ([f32; 3], [f32; 3])| {
        hit_box(a, inv_d, lo.map(|x| x - pad), hi.map(|x| x + pad), R::of(1.0)).is_some()
    };
    // A leaf: its balls, if its box is met.
    let mut leaf = |word: &[u32; 4]| {
        if met(tree.node_box(word)) {
            let (first, count) = ((word[3] & 0xffff) as usize, (word[3] >> 16) as usize);
            visit(first..first + count);
        }
    };
    let n = tree.words.len();
    if tree.inner.len() + 1 != n {
        tree.words.iter().for_each(leaf);
        return;
    }
    // Depth first, left half first, by a stack of node indices: at most
    // one pending half a level and the node at hand, 16 for the most
    // leaves `pack` keeps (2^15).
    let mut stack = [0usize; 17];
    let mut top = 1;
    while top > 0 {
        top -= 1;
        let node = stack[top];
        if node < n - 1 {
            if met(tree.inner[node]) {
                stack[top] = 2 * node + 2;
                stack[top + 1] = 2 * node + 1;
                top += 2;
            }
        } else {
            leaf(&tree.words[node - (n - 1)]);
        }
    }
}
