//! A bounding-volume hierarchy over a mesh's triangles, built on the CPU
//! with the surface-area heuristic (binned), flattened depth first with a
//! skip link per node ([`skip_links`]) so a walk needs no stack.
//! Traversal and the ray/triangle test here are the twins of `hit_box`,
//! `hit_triangle` and `hit_mesh` in `bevy_manifold_gpu`'s
//! `shaders/bvh.wgsl`.
//!
//! Rays are affine here: `o + s d` in the object's local chart, `s >= 0`
//! (the tracer converts its chart parameter, see `trace::mesh_ray`).

use super::{MeshData, TriMesh};
use crate::geometry::Real;

/// Most triangles in a leaf.
pub const LEAF_SIZE: usize = 4;
/// Deepest level the builder makes.
pub const MAX_DEPTH: usize = 40;
/// Bins per axis of the SAH sweep.
const BINS: usize = 12;

/// One node of the flattened hierarchy (two `vec4<u32>` of the shader's
/// mesh data): an axis-aligned box, and either two children (`count == 0`:
/// the left child is the next node, `first` is the right child) or a leaf
/// of `count` triangles starting at `first`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BvhNode {
    /// Box minimum.
    pub min: [f32; 3],
    /// Right child (inner node) or first triangle (leaf).
    pub first: u32,
    /// Box maximum.
    pub max: [f32; 3],
    /// Triangles in the leaf; 0 for an inner node.
    pub count: u32,
}

/// An axis-aligned box (the ball tree's leaves are joined with it too,
/// `trace::ball_tree`).
#[derive(Clone, Copy)]
pub(crate) struct Aabb {
    pub(crate) min: [f32; 3],
    pub(crate) max: [f32; 3],
}

impl Aabb {
    pub(crate) const EMPTY: Aabb = Aabb {
        min: [f32::INFINITY; 3],
        max: [f32::NEG_INFINITY; 3],
    };

    fn grow(&mut self, p: [f32; 3]) {
        for ((lo, hi), c) in self.min.iter_mut().zip(&mut self.max).zip(p) {
            *lo = lo.min(c);
            *hi = hi.max(c);
        }
    }

    /// Grows to hold `o`; an empty `o` (an empty bin of the SAH sweep)
    /// changes nothing (growing by its corners, infinite, would make
    /// every box joined after it infinite).
    pub(crate) fn join(&mut self, o: &Aabb) {
        if o.min.iter().zip(&o.max).any(|(lo, hi)| lo > hi) {
            return;
        }
        self.grow(o.min);
        self.grow(o.max);
    }

    fn area(&self) -> f32 {
        let e = [0, 1, 2].map(|k| (self.max[k] - self.min[k]).max(0.0));
        2.0 * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0])
    }
}

/// Builds the hierarchy of `mesh`: the flattened nodes (root first) and
/// the triangle order the leaves index into.
#[must_use]
pub fn build(mesh: &TriMesh) -> (Vec<BvhNode>, Vec<u32>) {
    let boxes: Vec<([f32; 3], [f32; 3])> = mesh
        .triangles
        .iter()
        .map(|t| {
            let mut b = Aabb::EMPTY;
            for &i in t {
                b.grow(mesh.positions[i as usize]);
            }
            (b.min, b.max)
        })
        .collect();
    build_over(&boxes)
}

/// Fits the boxes of `nodes` (built over `mesh`'s triangles, in the order
/// the leaves index) to `mesh`'s positions again, children before
/// parents: the hierarchy's shape is kept, so it stays right for every
/// ray, only less tight when the triangles moved far from where it was
/// built ([`surface_area`] says how much).
pub fn refit(nodes: &mut [BvhNode], mesh: &TriMesh) {
    // Root first with the left child right after its parent and the right
    // child further on: every child comes after its parent.
    for i in (0..nodes.len()).rev() {
        let node = nodes[i];
        let mut b = Aabb::EMPTY;
        if node.count > 0 {
            let first = node.first as usize;
            for t in &mesh.triangles[first..first + node.count as usize] {
                for &v in t {
                    b.grow(mesh.positions[v as usize]);
                }
            }
        } else if i + 1 < nodes.len() {
            for child in [i + 1, node.first as usize] {
                let c = nodes[child];
                b.join(&Aabb { min: c.min, max: c.max });
            }
        }
        nodes[i].min = b.min;
        nodes[i].max = b.max;
    }
}

/// The summed surface area of the hierarchy's boxes: what a ray pays to
/// walk it, in proportion (the surface-area heuristic's measure). A
/// refitted hierarchy whose area grew far past the one built for the
/// same triangles is worth building again.
#[must_use]
pub fn surface_area(nodes: &[BvhNode]) -> f32 {
    nodes.iter().map(|n| Aabb { min: n.min, max: n.max }.area()).sum()
}

/// Builds a hierarchy over any items given by their boxes (min, max):
/// the flattened nodes (root first) and the item order the leaves index
/// into, with leaves of up to [`LEAF_SIZE`] items. The mesh's triangles
/// use it.
#[must_use]
pub fn build_over(items: &[([f32; 3], [f32; 3])]) -> (Vec<BvhNode>, Vec<u32>) {
    let boxes: Vec<Aabb> = items.iter().map(|&(min, max)| Aabb { min, max }).collect();
    let centres: Vec<[f32; 3]> = boxes
        .iter()
        .map(|b| [0, 1, 2].map(|k| 0.5 * (b.min[k] + b.max[k])))
        .collect();
    let mut order: Vec<u32> = (0..items.len() as u32).collect();
    let mut nodes = Vec::new();
    // No items: one empty root (min > max), which no ray meets.
    split(&boxes, &centres, &mut order, 0, &mut nodes, (0, LEAF_SIZE));
    (nodes, order)
}

/// Builds the subtree over `order[..]` (triangles `offset..`), pushing its
/// nodes; returns the subtree root's index.
fn split(
    boxes: &[Aabb],
    centres: &[[f32; 3]],
    order: &mut [u32],
    offset: usize,
    nodes: &mut Vec<BvhNode>,
    (depth, leaf_size): (usize, usize),
) -> u32 {
    let mut bounds = Aabb::EMPTY;
    let mut cbounds = Aabb::EMPTY;
    for &t in order.iter() {
        bounds.join(&boxes[t as usize]);
        cbounds.grow(centres[t as usize]);
    }
    let index = nodes.len() as u32;
    nodes.push(BvhNode {
        min: bounds.min,
        first: offset as u32,
        max: bounds.max,
        count: order.len() as u32,
    });
    if order.len() <= leaf_size || depth + 1 >= MAX_DEPTH {
        return index;
    }
    let Some((axis, cut)) = best_split(boxes, centres, order, &bounds, &cbounds) else {
        return index;
    };
    // Partition by the chosen plane (a median split when all centres
    // coincide on the axis is not needed: best_split declines then).
    let mut i = 0;
    for j in 0..order.len() {
        if centres[order[j] as usize][axis] < cut {
            order.swap(i, j);
            i += 1;
        }
    }
    if i == 0 || i == order.len() {
        return index;
    }
    let (left, right) = order.split_at_mut(i);
    // The left subtree follows its parent; the parent keeps the right's
    // index.
    split(boxes, centres, left, offset, nodes, (depth + 1, leaf_size));
    let r = split(boxes, centres, right, offset + i, nodes, (depth + 1, leaf_size));
    let node = &mut nodes[index as usize];
    node.count = 0;
    node.first = r;
    index
}

/// The SAH-best split plane over binned centroids, if splitting beats a
/// leaf.
#[expect(clippy::needless_range_loop, reason = "the axis indexes boxes and centres alike")]
fn best_split(
    boxes: &[Aabb],
    centres: &[[f32; 3]],
    order: &[u32],
    bounds: &Aabb,
    cbounds: &Aabb,
) -> Option<(usize, f32)> {
    let leaf_cost = order.len() as f32;
    let mut best: Option<(f32, usize, f32)> = None;
    for axis in 0..3 {
        let (lo, hi) = (cbounds.min[axis], cbounds.max[axis]);
        if hi - lo <= 0.0 {
            continue;
        }
        let scale = BINS as f32 / (hi - lo);
        let bin_of = |c: f32| (((c - lo) * scale) as usize).min(BINS - 1);
        let mut bin_box = [Aabb::EMPTY; BINS];
        let mut bin_count = [0usize; BINS];
        for &t in order {
            let b = bin_of(centres[t as usize][axis]);
            bin_box[b].join(&boxes[t as usize]);
            bin_count[b] += 1;
        }
        // Sweep: areas and counts to the left of each cut, then the right.
        let mut left_area = [0.0f32; BINS];
        let mut left_count = [0usize; BINS];
        let (mut acc, mut n) = (Aabb::EMPTY, 0);
        for k in 0..BINS - 1 {
            acc.join(&bin_box[k]);
            n += bin_count[k];
            left_area[k] = acc.area();
            left_count[k] = n;
        }
        let (mut acc, mut n) = (Aabb::EMPTY, 0);
        for k in (1..BINS).rev() {
            acc.join(&bin_box[k]);
            n += bin_count[k];
            let (nl, nr) = (left_count[k - 1], n);
            if nl == 0 || nr == 0 {
                continue;
            }
            let cost =
                0.5 + (left_area[k - 1] * nl as f32 + acc.area() * nr as f32) / bounds.area().max(f32::MIN_POSITIVE);
            if best.is_none_or(|(c, ..)| cost < c) {
                best = Some((cost, axis, lo + k as f32 / scale));
            }
        }
    }
    best.filter(|(cost, ..)| *cost < leaf_cost)
        .map(|(_, axis, cut)| (axis, cut))
}

/// A ray's hit on a mesh: affine parameter, triangle (in BVH order) and
/// barycentric coordinates of vertices 1 and 2. WGSL twin: `MeshHit` in
/// `shaders/bvh.wgsl`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshHit<R> {
    /// `s` of the hit on `o + s d`.
    pub s: R,
    /// The triangle's index in [`MeshData::mesh`]'s (reordered) list.
    pub triangle: u32,
    /// Barycentric weight of the triangle's second vertex.
    pub u: R,
    /// Barycentric weight of its third vertex.
    pub v: R,
}

fn sub<R: Real>(a: [R; 3], b: [R; 3]) -> [R; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot<R: Real>(a: [R; 3], b: [R; 3]) -> R {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross<R: Real>(a: [R; 3], b: [R; 3]) -> [R; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn of<R: Real>(p: [f32; 3]) -> [R; 3] {
    p.map(|c| R::of(f64::from(c)))
}

/// Where the ray `o + s d` meets triangle `(a, b, c)` (either side), with
/// barycentrics: Moller-Trumbore. `None` for a miss, a parallel ray or
/// `s < 0`.
#[inline]
#[must_use]
pub fn hit_triangle<R: Real>(o: [R; 3], d: [R; 3], a: [R; 3], b: [R; 3], c: [R; 3]) -> Option<(R, R, R)> {
    let zero = R::of(0.0);
    let (e1, e2) = (sub(b, a), sub(c, a));
    let p = cross(d, e2);
    let det = dot(e1, p);
    if det == zero {
        return None;
    }
    let inv = R::of(1.0) / det;
    let q = sub(o, a);
    let u = dot(q, p) * inv;
    if u < zero || u > R::of(1.0) {
        return None;
    }
    let r = cross(q, e1);
    let v = dot(d, r) * inv;
    if v < zero || u + v > R::of(1.0) {
        return None;
    }
    let s = dot(e2, r) * inv;
    (s >= zero).then_some((s, u, v))
}

/// The entering parameter of the ray (with `inv_d` from
/// [`safe_inverse`]) into a box, if it meets the box within `[0, s_max]`:
/// the slab test.
#[inline]
#[must_use]
pub fn hit_box<R: Real>(o: [R; 3], inv_d: [R; 3], min: [f32; 3], max: [f32; 3], s_max: R) -> Option<R> {
    let mut enter = R::of(0.0);
    let mut leave = s_max;
    for k in 0..3 {
        let t0 = (R::of(f64::from(min[k])) - o[k]) * inv_d[k];
        let t1 = (R::of(f64::from(max[k])) - o[k]) * inv_d[k];
        enter = enter.max(t0.min(t1));
        leave = leave.min(t0.max(t1));
    }
    (enter <= leave).then_some(enter)
}

/// `1 / c` per component, with `|c|` kept above `1e-20` so the slab test
/// meets no infinity (the shader's `safe_inverse`).
#[inline]
#[must_use]
pub fn safe_inverse<R: Real>(d: [R; 3]) -> [R; 3] {
    let tiny = R::of(1e-20);
    d.map(|c| {
        let c = if c.abs() < tiny {
            if c < R::of(0.0) { -tiny } else { tiny }
        } else {
            c
        };
        R::of(1.0) / c
    })
}

/// Per node of a flattened hierarchy (depth first, an inner node's left
/// child next to it and `first` its right child), the index of the first
/// node after its subtree: where a walk goes on when the node's box is
/// missed. A leaf's is the next node.
///
/// ```
/// use bevy_manifold_core::mesh::bvh::{BvhNode, skip_links};
/// let node = |first, count| BvhNode { min: [0.0; 3], first, max: [1.0; 3], count };
/// // A root whose left child (1) is a leaf and right child (2) an inner
/// // node over two leaves (3 and 4).
/// let nodes = [node(2, 0), node(0, 1), node(4, 0), node(1, 1), node(2, 1)];
/// assert_eq!(skip_links(&nodes), [5, 2, 5, 4, 5]);
/// ```
#[must_use]
pub fn skip_links(nodes: &[BvhNode]) -> Vec<u32> {
    let mut skip = vec![nodes.len() as u32; nodes.len()];
    // (node, the index past its subtree): a left child's is its right
    // sibling, a right child's its parent's.
    let mut todo = vec![(0usize, nodes.len() as u32)];
    while let Some((i, past)) = todo.pop() {
        let Some(node) = nodes.get(i) else { continue };
        skip[i] = past;
        if node.count == 0 && i + 1 < nodes.len() && (node.first as usize) > i {
            todo.push((i + 1, node.first));
            todo.push((node.first as usize, past));
        }
    }
    skip
}

/// The nearest hit through the hierarchy, by the skip links
/// ([`MeshData::skip`]), without a stack: down to the next leaf whose box
/// the ray meets within the nearest hit so far, then that leaf's
/// triangles, in the nodes' order (depth first, left child first). Two
/// loops, as on the GPU, where lanes that found a leaf wait for the
/// others and test their leaves together; a per-lane stack costs lavapipe
/// a gather and a scatter a push (docs/benchmarks/history.md, "Meshes by skip links").
/// On a tie the later triangle in that order is kept.
#[must_use]
pub fn hit_mesh<R: Real>(mesh: &MeshData, o: [R; 3], d: [R; 3], s_max: R) -> Option<MeshHit<R>> {
    hit_mesh_where(mesh, o, d, s_max, |_| true)
}

/// [`hit_mesh`] counting only the hits `keep` accepts (an alpha mask:
/// a triangle's transparent texels let the ray through to what lies
/// behind). WGSL twin: `hit_mesh` in `shaders/bvh.wgsl` (its `ALPHA_MASK`
/// part).
#[must_use]
pub fn hit_mesh_where<R: Real>(
    mesh: &MeshData,
    o: [R; 3],
    d: [R; 3],
    s_max: R,
    keep: impl Fn(&MeshHit<R>) -> bool,
) -> Option<MeshHit<R>> {
    let inv_d = safe_inverse(d);
    let mut best: Option<MeshHit<R>> = None;
    let mut limit = s_max;
    let mut i = 0;
    loop {
        // Down to the next met leaf: its triangles, or none past the end.
        let mut leaf = None;
        while let Some(node) = mesh.nodes.get(i) {
            let met = hit_box(o, inv_d, node.min, node.max, limit).is_some();
            let is_leaf = node.count > 0;
            i = if met || is_leaf {
                i + 1
            } else {
                (mesh.skip[i] as usize).max(i + 1)
            };
            if met && is_leaf {
                leaf = Some(node.first..node.first + node.count);
                break;
            }
        }
        // Then its triangles.
        let Some(triangles) = leaf else { break };
        for t in triangles {
            let [a, b, c] = mesh.mesh.triangles[t as usize].map(|i| of::<R>(mesh.mesh.positions[i as usize]));
            if let Some((s, u, v)) = hit_triangle(o, d, a, b, c)
                && s <= limit
            {
                let hit = MeshHit { s, triangle: t, u, v };
                if keep(&hit) {
                    limit = s;
                    best = Some(hit);
                }
            }
        }
    }
    best
}

/// The nearest hit by testing every triangle (for tests).
#[must_use]
pub fn hit_brute_force<R: Real>(mesh: &MeshData, o: [R; 3], d: [R; 3], s_max: R) -> Option<MeshHit<R>> {
    let mut best: Option<MeshHit<R>> = None;
    for (t, tri) in mesh.mesh.triangles.iter().enumerate() {
        let [a, b, c] = tri.map(|i| of::<R>(mesh.mesh.positions[i as usize]));
        if let Some((s, u, v)) = hit_triangle(o, d, a, b, c)
            && s <= s_max
            && best.is_none_or(|h| s < h.s)
        {
            best = Some(MeshHit {
                s,
                triangle: t as u32,
                u,
                v,
            });
        }
    }
    best
}
