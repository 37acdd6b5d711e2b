//! The ball tree: a hierarchy over the chart boxes of the balls with no
//! face mask ([`super::FlatScene::ball_tree`]), and the walk that hands a
//! segment the leaves it may meet ([`tree_leaves`]). In the chart where
//! geodesics are straight (`x/w`, `y/w`, `z/w`) a segment of a ray is a
//! straight segment ([`chart_segment`]) and a ball's image fits a box
//! ([`ball_box`]), so the walk is a slab test per node, as for meshes.
//!
//! WGSL twin: `interior_balls` and `ball_tree_leaves` in
//! `bevy_manifold_gpu`'s `shaders/render.wgsl`, which read
//! [`BallTree::words`] from the `ball_nodes` uniform.

use super::step::Ray;
use crate::geometry::{Geometry, Real};
use crate::mesh::bvh::{BvhNode, hit_box, safe_inverse, skip_links};
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
/// WGSL twin: the start of `interior_balls` in `shaders/render.wgsl`.
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

/// Set in a packed node's link word ([`BallTree::words`]) for a leaf.
pub const LEAF_LINK: u32 = 1 << 31;

/// The steps a packed box side is counted in: 16 bits.
const STEPS: f32 = 65535.0;

/// A hierarchy over the chart boxes of balls ([`ball_box`]), walked
/// without a stack: `nodes` as [`crate::mesh::bvh`] flattens them (depth
/// first, an inner node's left child next to it), and per node `skip`,
/// the index just past its subtree, where a walk goes on when the node's
/// box is missed. The walk reads each node as one packed word of four
/// `u32` ([`BallTree::words`]): its box in 16-bit steps of the root's
/// ([`BallTree::node_box`]) and its link. The GPU walks it the same way
/// from a uniform array (a per-lane stack and per-lane storage reads cost
/// lavapipe more than the walk itself, and each word a lane reads is one
/// more gather: a node of two words took the 128-ball frames 5-12% longer,
/// BENCHMARKS.md, "Ball tree nodes in one word").
///
/// ```
/// use bevy_manifold_core::mesh::bvh::BvhNode;
/// use bevy_manifold_core::trace::{BallTree, LEAF_LINK};
/// let node = |first, count| BvhNode { min: [0.0; 3], first, max: [1.0; 3], count };
/// // A root whose left child (1) is a leaf and right child (2) an inner
/// // node over two leaves (3 and 4).
/// let tree = BallTree::new(vec![node(2, 0), node(0, 1), node(4, 0), node(1, 1), node(2, 1)]);
/// assert_eq!(tree.skip, [5, 2, 5, 4, 5]);
/// // An inner node's link is its skip; a leaf's, its balls.
/// assert_eq!(tree.words[2][3], 5);
/// assert_eq!(tree.words[3][3], LEAF_LINK | 1 | (1 << 16));
/// // Every box holds the unit cube it packs.
/// let (lo, hi) = tree.node_box(&tree.words[4]);
/// assert!(lo.iter().all(|&x| x <= 0.0) && hi.iter().all(|&x| x >= 1.0));
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BallTree {
    /// The nodes, as [`crate::mesh::bvh::build_over`] flattens them.
    pub nodes: Vec<BvhNode>,
    /// Per node, the index of the first node after its subtree.
    pub skip: Vec<u32>,
    /// The frame of the packed boxes: the root box's least corner...
    pub origin: [f32; 3],
    /// ...and one step per axis: a 65,535th of the root box's side, or
    /// 2^-20 of the frame's largest coordinate if that is more, so that
    /// `f32` rounding in [`BallTree::node_box`] stays below a step.
    pub step: [f32; 3],
    /// Per node, as the walk reads it (one `vec4<u32>` of the GPU's
    /// `ball_nodes`): for x, y and z, the box's least side in steps from
    /// `origin`, rounded down, in the low 16 bits and its greatest,
    /// rounded up, in the high 16; then the link: an inner node's `skip`,
    /// or [`LEAF_LINK`] with a leaf's first ball in the low 16 bits and
    /// its ball count in bits 16 to 30. Empty, and so no tree
    /// ([`BallTree::is_empty`]), when there are no nodes, the frame is not
    /// finite, or an index does not fit its bits.
    pub words: Vec<[u32; 4]>,
}

impl BallTree {
    /// The tree of `nodes`, with each node's skip link and packed word.
    #[must_use]
    pub fn new(nodes: Vec<BvhNode>) -> Self {
        let skip = skip_links(&nodes);
        let mut tree = BallTree {
            nodes,
            skip,
            ..BallTree::default()
        };
        tree.pack();
        tree
    }

    /// Fills `origin`, `step` and `words` from `nodes` and `skip`, or
    /// leaves `words` empty where they do not fit.
    fn pack(&mut self) {
        let Some(root) = self.nodes.first() else { return };
        let origin = root.min;
        let step: [f32; 3] = [0, 1, 2].map(|k| {
            let size = (root.max[k] - root.min[k]) / STEPS;
            let magnitude = root.min[k].abs().max(root.max[k].abs()) * (1.0 / 1_048_576.0);
            size.max(magnitude).max(f32::MIN_POSITIVE)
        });
        if !origin.iter().chain(&step).all(|x| x.is_finite()) || self.nodes.len() > 0xffff {
            return;
        }
        let mut words = Vec::with_capacity(self.nodes.len());
        for (node, &skip) in self.nodes.iter().zip(&self.skip) {
            let side = |k: usize| {
                let lo = ((node.min[k] - origin[k]) / step[k]).floor().clamp(0.0, STEPS) as u32;
                let hi = ((node.max[k] - origin[k]) / step[k]).ceil().clamp(0.0, STEPS) as u32;
                lo | (hi << 16)
            };
            let link = if node.count > 0 {
                if node.first > 0xffff || node.count > 0x7fff {
                    return;
                }
                LEAF_LINK | node.first | (node.count << 16)
            } else {
                skip
            };
            words.push([side(0), side(1), side(2), link]);
        }
        self.origin = origin;
        self.step = step;
        self.words = words;
    }

    /// The box of a packed node (one of [`BallTree::words`]): its sides
    /// widened by a step each way, which covers the rounding of the
    /// frame's `f32` sums, so it holds the box it packs. WGSL twin:
    /// `tree_box` in `shaders/ball_tree.wgsl`.
    #[must_use]
    pub fn node_box(&self, word: &[u32; 4]) -> ([f32; 3], [f32; 3]) {
        let lo = [0, 1, 2].map(|k| self.origin[k] + ((word[k] & 0xffff) as f32 - 1.0) * self.step[k]);
        let hi = [0, 1, 2].map(|k| self.origin[k] + ((word[k] >> 16) as f32 + 1.0) * self.step[k]);
        (lo, hi)
    }

    /// True when there is no tree to walk (every ball is tested).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.words.is_empty()
    }
}

/// Calls `visit` with the ball range of every leaf of `tree` (a hierarchy
/// over chart boxes, [`super::FlatScene::ball_tree`]) whose packed box
/// ([`BallTree::node_box`]), and its parents', grown by `pad` on every
/// side (cone tracing's growth, 0 for a ray), the chart segment
/// `a + s d`, `0 <= s <= 1`, meets (the slab test, `mesh::bvh::hit_box`).
/// Depth first, left child first: into the next node after a leaf or an
/// inner node whose box is met, to the inner node's skip link otherwise
/// (always forward, so at most one pass). Two loops, as on the GPU: down
/// to the next met leaf, then its balls (there, lanes that found a leaf
/// wait for the others and test their leaves together). WGSL twin:
/// `ball_tree_leaves` in `shaders/render.wgsl`.
pub fn tree_leaves<R: Real>(tree: &BallTree, a: [R; 3], d: [R; 3], pad: f32, mut visit: impl FnMut(Range<usize>)) {
    let inv_d = safe_inverse(d);
    let mut i = 0;
    loop {
        // Down to the next met leaf: its balls, or none past the end.
        let mut balls = None;
        while let Some(word) = tree.words.get(i) {
            let (lo, hi) = tree.node_box(word);
            let met = hit_box(a, inv_d, lo.map(|x| x - pad), hi.map(|x| x + pad), R::of(1.0)).is_some();
            let leaf = word[3] & LEAF_LINK != 0;
            i = if met || leaf {
                i + 1
            } else {
                ((word[3] & 0xffff) as usize).max(i + 1)
            };
            if met && leaf {
                let (first, count) = (word[3] & 0xffff, (word[3] >> 16) & 0x7fff);
                balls = Some(first as usize..(first + count) as usize);
                break;
            }
        }
        // Then its balls.
        let Some(balls) = balls else { break };
        visit(balls);
    }
}
