//! The instance tree: a hierarchy over the chart boxes ([`ball_box`]) of
//! the bounding balls of one face group's mesh instances (the instances
//! with no face mask, or those of one face's group, [`super::FaceGroups`]),
//! so that a segment tests only the instances in the leaves its chart
//! image meets ([`tree_instances`]): a level of thousands of props costs a
//! segment a walk down the tree, not a test of each.
//!
//! In the chart where geodesics are straight a segment of a ray is a
//! straight segment ([`super::chart_segment`]), so the walk is the mesh
//! hierarchy's ([`crate::mesh::bvh`]): a slab test per node, skip links in
//! place of a stack. Its nodes are kept in eight orders, one per octant of
//! the segment's direction, each with the nearer child of every node first
//! ([`InstanceTree::orders`]): a walk meets the nearest instances first,
//! and the nearest hit found so far ends the walk of every box beyond it
//! ([`chart_fraction`]).
//!
//! WGSL twin: `tree_instances` and `chart_fraction` in
//! `bevy_manifold_gpu`'s `shaders/instance_tree.wgsl`. The GPU reads the
//! orders' nodes where `GpuObjects::instance_trees` packs them.

use super::ball_tree::ball_box;
use super::flat::FlatInstance;
use super::step::Ray;
use crate::geometry::{Geometry, Real};
use crate::mesh::bvh::{BvhNode, build_over, hit_box, safe_inverse, skip_links};
use core::ops::Range;

/// The fewest instances a face group needs for a tree; a smaller group's
/// instances are each tested, as the few meshes of most scenes are.
pub const MIN_INSTANCE_TREE: usize = 8;

/// One order of an [`InstanceTree`]'s nodes: depth first, an inner node's
/// first child right after it and `first` its second child; a leaf's
/// `first` is its first instance in [`super::FlatScene::instances`].
/// `skip` is each node's skip link ([`skip_links`]), as a mesh's.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TreeOrder {
    /// The nodes, root first.
    pub nodes: Vec<BvhNode>,
    /// Per node, the index past its subtree.
    pub skip: Vec<u32>,
}

/// A hierarchy over one face group's instances, whose boxes are the chart
/// boxes of their bounding balls ([`ball_box`]), built with the mesh
/// hierarchy's surface-area heuristic ([`build_over`]). Empty (no orders)
/// for a group of fewer than [`MIN_INSTANCE_TREE`] instances.
///
/// ```
/// use bevy_manifold_core::trace::{InstanceTree, octant};
/// // Sixteen unit boxes along x, as if they were instances' boxes.
/// let boxes: Vec<_> = (0..16).map(|i| ([i as f32, 0.0, 0.0], [i as f32 + 1.0, 1.0, 1.0])).collect();
/// let (tree, order) = InstanceTree::over(&boxes, 100);
/// assert_eq!(tree.orders.len(), 8);
/// assert_eq!(order.len(), 16);
/// // Walking +x the leftmost leaf comes first, walking -x the rightmost.
/// let first_leaf = |o: usize| tree.orders[o].nodes.iter().find(|n| n.count > 0).unwrap().min[0];
/// assert_eq!(first_leaf(octant([1.0, 0.0, 0.0])), 0.0);
/// assert!(first_leaf(octant([-1.0, 0.0, 0.0])) >= 12.0);
/// // Leaves index the instances from the group's start, 100.
/// assert!(tree.orders[0].nodes.iter().filter(|n| n.count > 0).all(|n| n.first >= 100));
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct InstanceTree {
    /// The nodes in eight orders, order `o` for a segment whose chart
    /// direction's component `k` is negative where bit `k` of `o` is set
    /// ([`octant`]): of an inner node's two children, the one whose box
    /// centre is lower along the axis that separates their centres most
    /// comes first when the direction is positive along it. Empty when
    /// there is no tree.
    pub orders: Vec<TreeOrder>,
}

impl InstanceTree {
    /// The tree over `boxes` (least and greatest corners, one per
    /// instance of a group that starts at instance `start`), and the
    /// order its leaves want the group's instances in. No tree (and the
    /// instances as they are) for fewer than [`MIN_INSTANCE_TREE`] boxes.
    #[must_use]
    pub fn over(boxes: &[([f32; 3], [f32; 3])], start: u32) -> (Self, Vec<u32>) {
        if boxes.len() < MIN_INSTANCE_TREE {
            return (InstanceTree::default(), (0..boxes.len() as u32).collect());
        }
        let (mut nodes, order) = build_over(boxes);
        for n in nodes.iter_mut().filter(|n| n.count > 0) {
            n.first += start;
        }
        let orders = (0..8).map(|o| ordered(&nodes, o)).collect();
        (InstanceTree { orders }, order)
    }

    /// True when there is no tree (every instance of the group is tested).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.orders.is_empty()
    }
}

/// The trees of a scene's face groups of instances, and the instances in
/// their leaves' order: group 0 holds the instances with no face mask,
/// group `f + 1` face `f`'s ([`super::FaceGroups::instances`]).
pub(super) fn trees_over<R: Real>(g: Geometry, instances: &mut [FlatInstance<R>], starts: &[u32]) -> Vec<InstanceTree> {
    let bounds = core::iter::once(0).chain(starts.iter().copied()).collect::<Vec<u32>>();
    bounds
        .windows(2)
        .map(|w| {
            let group = &mut instances[w[0] as usize..w[1] as usize];
            let boxes: Vec<_> = group
                .iter()
                .map(|i| ball_box(g, R::v4_f64(i.center), i.k.f64()))
                .collect();
            let (tree, order) = InstanceTree::over(&boxes, w[0]);
            if !tree.is_empty() {
                let sorted: Vec<FlatInstance<R>> = order.iter().map(|&i| group[i as usize]).collect();
                group.copy_from_slice(&sorted);
            }
            tree
        })
        .collect()
}

/// The order of a segment whose chart direction is `d`: bit `k` set when
/// `d[k]` is negative. WGSL twin: the start of `tree_instances`.
#[must_use]
pub fn octant<R: Real>(d: [R; 3]) -> usize {
    let zero = R::of(0.0);
    (0..3).filter(|&k| d[k] < zero).map(|k| 1 << k).sum()
}

/// `nodes` (root first, an inner node's left child next and `first` its
/// right) emitted depth first in the order of octant `o`.
fn ordered(nodes: &[BvhNode], o: usize) -> TreeOrder {
    let mut out = Vec::with_capacity(nodes.len());
    emit(nodes, 0, o, &mut out);
    let skip = skip_links(&out);
    TreeOrder { nodes: out, skip }
}

/// Pushes node `i` of `nodes` and its subtree, the nearer child first
/// for octant `o`; returns where node `i` went.
fn emit(nodes: &[BvhNode], i: usize, o: usize, out: &mut Vec<BvhNode>) -> u32 {
    let at = out.len();
    let node = nodes[i];
    out.push(node);
    if node.count > 0 || i + 1 >= nodes.len() {
        return at as u32;
    }
    let (left, right) = (i + 1, node.first as usize);
    let centre = |n: usize| [0, 1, 2].map(|k| 0.5 * nodes[n].min[k] + 0.5 * nodes[n].max[k]);
    let (cl, cr) = (centre(left), centre(right));
    let axis = (0..3)
        .max_by(|&a, &b| (cr[a] - cl[a]).abs().total_cmp(&(cr[b] - cl[b]).abs()))
        .unwrap_or(0);
    let low_first = (o >> axis) & 1 == 0;
    let (first, second) = if (cl[axis] <= cr[axis]) == low_first {
        (left, right)
    } else {
        (right, left)
    };
    emit(nodes, first, o, out);
    let second_at = emit(nodes, second, o, out);
    out[at].first = second_at;
    at as u32
}

/// Where along the chart segment of `ray` up to `t_end` (as
/// [`super::chart_segment`] makes it, `0` at the start and `1` at the
/// end) the point of chart parameter `t` lies: with `w_0` and `w_1` the
/// ends' `w`, `s = l w_1 / ((1 - l) w_0 + l w_1)` for `l = t / t_end`,
/// made a little larger (a ten-thousandth and a millionth) so that `f32`
/// rounding never makes it fall short of a box the ray meets before `t`.
/// WGSL twin: `chart_fraction` in `shaders/instance_tree.wgsl`.
#[must_use]
pub fn chart_fraction<R: Real>(ray: &Ray<R>, t_end: R, t: R) -> R {
    let one = R::of(1.0);
    // At or past the end, or NaN: the whole segment.
    if t.partial_cmp(&t_end) != Some(core::cmp::Ordering::Less) {
        return one;
    }
    let w0 = R::xyzw(ray.origin)[3];
    let w1 = R::xyzw(ray.origin + ray.dir * t_end)[3];
    let l = (t / t_end).max(R::of(0.0));
    let s = l * w1 / ((one - l) * w0 + l * w1);
    (s * R::of(1.0001) + R::of(1e-6)).min(one)
}

/// Calls `visit` with the instance range of every leaf of `tree` whose
/// box the chart segment `a + s d` (from [`super::chart_segment`] of
/// `ray` up to `t_end`) meets before the limit, in the order of the
/// segment's octant (the nearer leaves first). `visit` returns the chart
/// parameter past which a hit no longer matters (the nearest hit so far,
/// or `t_end`), which [`chart_fraction`] turns into the limit on the
/// segment: a box the segment meets only beyond it holds no instance
/// that can be hit before it (an instance's hits lie in its bounding
/// ball, which its box holds). WGSL twin: `tree_instances` in
/// `shaders/instance_tree.wgsl`.
pub fn tree_instances<R: Real>(
    tree: &InstanceTree,
    (ray, t_end): (&Ray<R>, R),
    (a, d): ([R; 3], [R; 3]),
    mut visit: impl FnMut(Range<usize>) -> R,
) {
    let Some(order) = tree.orders.get(octant(d)) else {
        return;
    };
    let inv_d = safe_inverse(d);
    let mut s_max = R::of(1.0);
    let mut i = 0;
    while i < order.nodes.len() {
        let node = &order.nodes[i];
        let met = hit_box(a, inv_d, node.min, node.max, s_max).is_some();
        let leaf = node.count > 0;
        if met && leaf {
            let first = node.first as usize;
            let limit = visit(first..first + node.count as usize);
            s_max = chart_fraction(ray, t_end, limit);
        }
        i = if met || leaf { i + 1 } else { order.skip[i] as usize };
    }
}
