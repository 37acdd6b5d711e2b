//! What lies near the domain's faces. Every object near the faces (an
//! edge tube, a vertex joint, a ghost straddling a face) carries a face
//! mask, the faces whose planes all its points in the domain lie near
//! ([`face_mask`]); a segment tests it only when it comes near all of
//! them ([`super::step::near_faces`], [`super::step::may_hit`]). Objects
//! are kept in groups by their first face ([`FaceGroups`]), so a segment
//! walks only the groups of the faces it comes near
//! ([`super::cull::each_candidate`]).
//!
//! WGSL twin: the `groups` uniform (`shaders/bindings.wgsl`), walked by
//! `next_group` and the edge walk (`edge_walk_new`, `edge_walk_next`,
//! `edge_walk_tube`) in `shaders/cull.wgsl`.

use super::scene::Scene;
use crate::geometry::Geometry;
use crate::space::Space;
use glam::DVec4;
use std::collections::HashSet;

/// `s(r)` of [`super::FaceTables::near_scale`] for the distance `r`: `sinh r`,
/// `sin r` (infinite from a quarter turn on) or `r`.
#[must_use]
pub fn near_reach(g: Geometry, r: f64) -> f64 {
    match g {
        Geometry::Euclidean => r,
        Geometry::Hyperbolic => r.sinh(),
        Geometry::Spherical if r < core::f64::consts::FRAC_PI_2 => r.sin(),
        Geometry::Spherical => f64::INFINITY,
    }
}

/// The faces of `space` whose planes every point of the domain that an
/// object reaches is within `reach` of, face `i` as bit `i % 32` (a domain
/// of more than 32 faces folds them: a bit stands for any of its faces,
/// which [`super::step::near_faces`] folds alike, so an object is still
/// tested on every segment that comes near all of its faces), for an object
/// whose points lie within distance `radius` of `centers` (a ball: its
/// centre; a tube: its edge, given by its two ends): the depth inside a
/// plane grows by at most the distance moved, and along an edge it is
/// at most its ends' in E3 and H3 (convex), and 0 for a plane holding
/// both ends, the only planes an edge's reach (its radius and a hair, see
/// `cull_distance`) lets through in S3.
pub(super) fn face_mask(space: &Space, centers: &[DVec4], radius: f64, reach: f64) -> u32 {
    let g = space.geometry();
    let mut mask = 0;
    for (i, f) in space.faces().iter().enumerate() {
        let depth = centers
            .iter()
            .map(|&c| -crate::geometry::plane::signed_distance(g, f.plane, c))
            .fold(f64::NEG_INFINITY, f64::max);
        if depth + radius <= reach {
            mask |= 1 << (i % 32);
        }
    }
    mask
}

/// [`super::FaceTables::near_scale`] in `f64`.
pub(super) fn near_scale(space: &Space) -> f64 {
    let g = space.geometry();
    let least_w = match g {
        // No vertices (a hemisphere): no bound, no culling.
        Geometry::Spherical if space.vertices().is_empty() => 0.0,
        Geometry::Spherical => space
            .vertices()
            .iter()
            .map(|v| g.normalize_point::<f64>(v.point).w)
            .fold(f64::INFINITY, f64::min),
        _ => 1.0,
    };
    if least_w > 1e-6 { 1.0 / least_w } else { f64::INFINITY }
}

/// The distance within which objects carry face masks
/// ([`super::FlatScene::near_reach`]): the edge radius and a hair (the planes of
/// an edge hold its ends to rounding), else twice the smallest radius of a
/// ball or mesh, so the smallest straddling a face are culled; 0 for an
/// empty scene.
pub(super) fn cull_distance(g: Geometry, scene: &Scene) -> f64 {
    if let Some(r) = scene.edge_radius {
        return r + 1e-8;
    }
    let smallest = scene
        .balls
        .iter()
        .map(|b| b.radius)
        .chain(scene.meshes.iter().filter_map(|m| m.bounding_radius(g)))
        .fold(f64::INFINITY, f64::min);
    if smallest.is_finite() { 2.0 * smallest } else { 0.0 }
}

/// Where each face's group of objects starts, per kind. Objects are
/// sorted by their mask's first face (tubes: their edge bits'), unmasked
/// ones first: the group of
/// face `f` is `starts[f]..starts[f + 1]` (faces 0 to 31, or fewer), and
/// the unmasked objects, tested on every segment, are `0..starts[0]`.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FaceGroups {
    /// Group starts in the balls.
    pub balls: Vec<u32>,
    /// Group starts in the tubes.
    pub tubes: Vec<u32>,
    /// Group starts in the mesh instances.
    pub instances: Vec<u32>,
    /// The edge table of the tubes, which are grouped by their edge's
    /// faces ([`super::FlatTube::edge`]) rather than their mask: per face
    /// `f` (up to 32), bit `g` set where `f`'s group holds the tube of
    /// the edge of faces `f` and `g` (`g == f` where two faces fold onto
    /// one bit). A group is sorted by `g`, so that tube is the one after
    /// as many as `f`'s bits below `g` ([`FaceGroups::edge_walk`]).
    pub edges: Vec<u32>,
}

impl FaceGroups {
    /// Sorts `items` (stably) by their mask's first face, unmasked first,
    /// then by the mask, and returns the group starts for a domain of
    /// `faces` faces: one per face up to 32, and then the count.
    pub fn sort<T>(items: &mut [T], faces: usize, mask: impl Fn(&T) -> u32) -> Vec<u32> {
        let key = |m: u32| if m == 0 { 0 } else { 1 + m.trailing_zeros() };
        items.sort_by_key(|x| (key(mask(x)), mask(x)));
        let groups = faces.min(32) as u32;
        (0..=groups)
            .map(|f| items.iter().take_while(|x| key(mask(x)) <= f).count() as u32)
            .collect()
    }

    /// [`FaceGroups::edges`] of tubes whose edge bits, in their sorted
    /// order, are `keys`, in a domain of `faces` faces.
    pub fn edge_table(keys: impl Iterator<Item = u32>, faces: usize) -> Vec<u32> {
        let mut out = vec![0; faces.min(32)];
        for k in keys.filter(|&k| k != 0) {
            out[k.trailing_zeros() as usize] |= 1 << (31 - k.leading_zeros());
        }
        out
    }

    /// The tubes (their indices) a segment near the faces `near` walks,
    /// given the tubes' group starts and [`FaceGroups::edges`]: those
    /// with no edge bits, then for each near face `f` in order the tube of
    /// each edge it shares with a near face `g`, in the order of `g`. So
    /// only the tubes whose edge's two faces are near, in their sorted
    /// order.
    ///
    /// ```
    /// use bevy_manifold_core::trace::FaceGroups;
    /// // Three faces; tubes on edges {0, 1}, {0, 2}, {1, 2}, sorted.
    /// let starts = [0, 2, 3, 3];
    /// let edges = [0b110, 0b100, 0];
    /// let walk = |near| FaceGroups::edge_walk(&starts, &edges, near).collect::<Vec<_>>();
    /// assert_eq!(walk(0b111), [0, 1, 2]);
    /// assert_eq!(walk(0b101), [1]);
    /// assert_eq!(walk(0b110), [2]);
    /// assert!(walk(0b001).is_empty());
    /// ```
    pub fn edge_walk<'a>(starts: &'a [u32], edges: &'a [u32], near: u32) -> impl Iterator<Item = usize> + 'a {
        let unmasked = 0..starts.first().map_or(0, |&s| s as usize);
        let pairs = edges
            .iter()
            .enumerate()
            .filter(move |&(f, _)| near & (1 << f) != 0)
            .flat_map(move |(f, &e)| {
                bits(e & near).map(move |g| starts[f] as usize + (e & ((1u32 << g) - 1)).count_ones() as usize)
            });
        unmasked.chain(pairs)
    }

    /// The index ranges of `starts` (a kind's group starts) a segment near
    /// the faces `near` walks: the unmasked objects, then the group of
    /// each near face, in order (so the objects come in the sorted order,
    /// as without culling).
    pub fn ranges(starts: &[u32], near: u32) -> impl Iterator<Item = core::ops::Range<usize>> + '_ {
        Self::groups(starts, near).map(|(_, range)| range)
    }

    /// [`FaceGroups::ranges`] with each range's group: 0 for the
    /// unmasked objects, `f + 1` for face `f`'s (as
    /// [`super::FlatScene::instance_trees`] are numbered).
    pub fn groups(starts: &[u32], near: u32) -> impl Iterator<Item = (usize, core::ops::Range<usize>)> + '_ {
        let unmasked = 0..starts.first().map_or(0, |&s| s as usize);
        let faces = starts.len().saturating_sub(1);
        core::iter::once((0, unmasked)).chain(
            (0..faces)
                .filter(move |&f| near & (1 << f) != 0)
                .map(move |f| (f + 1, starts[f] as usize..starts[f + 1] as usize)),
        )
    }
}

/// The set bits of `x`, lowest first.
fn bits(mut x: u32) -> impl Iterator<Item = u32> {
    core::iter::from_fn(move || {
        (x != 0).then(|| {
            let b = x.trailing_zeros();
            x &= x - 1;
            b
        })
    })
}

/// The face masks ([`super::FlatTube::face_mask`]) of the tubes of radius `r`
/// along the edges of `space`, in the edges' order, for masks of `reach`.
pub(super) fn edge_masks(space: &Space, r: f64, reach: f64) -> Vec<u32> {
    let point = |v: usize| space.vertices()[v].point;
    space
        .edges()
        .iter()
        .map(|e| face_mask(space, &[point(e.vertices[0]), point(e.vertices[1])], r, reach))
        .collect()
}

/// The edge bits ([`super::FlatTube::edge`]) of tubes along the edges of
/// `space` with face masks `masks`: each key once. A tube whose edge
/// bits an earlier one took (two edges folded onto the same bits) is
/// found by one of them alone, if that is free, else it has none.
pub(super) fn edge_keys(space: &Space, masks: &[u32]) -> Vec<u32> {
    let mut keys = HashSet::new();
    space
        .edges()
        .iter()
        .zip(masks)
        .map(|(edge, &mask)| {
            let own: u32 = (1 << (edge.faces[0] % 32)) | (1 << (edge.faces[1] % 32));
            let alone = [1 << own.trailing_zeros(), 1 << (31 - own.leading_zeros())];
            core::iter::once(own)
                .chain(alone)
                .find(|&k| k & !mask == 0 && keys.insert(k))
                .unwrap_or(0)
        })
        .collect()
}

/// Which tube carries each vertex joint ([`super::FlatTube::joint`]), for
/// tubes along edges with ends `ends` (vertex indices) and face masks
/// `tube_masks`, and joints (one per vertex) with face masks `masks`: a tube
/// may carry a joint at one of its ends whose mask is not 0 and holds the
/// tube's (so its edge bits too: a segment near all of the joint's faces
/// walks the tube, keyed or not). At most one joint a tube: a matching of joints to tubes,
/// grown by augmenting paths (Kuhn), so that every joint is carried where
/// any matching carries them all (a vertex of a convex polyhedron has
/// three edges or more, a tube two ends: Hall's condition holds when the
/// masks do not exclude a tube). `None` for a joint left to the groups.
pub(super) fn joint_carriers(ends: &[[usize; 2]], tube_masks: &[u32], masks: &[u32]) -> Vec<Option<usize>> {
    let mut tubes_at = vec![Vec::new(); masks.len()];
    for (t, (e, &tube)) in ends.iter().zip(tube_masks).enumerate() {
        for &v in e {
            if masks.get(v).is_some_and(|&m| m != 0 && tube & !m == 0) && !tubes_at[v].contains(&t) {
                tubes_at[v].push(t);
            }
        }
    }
    let mut joint_on = vec![None; ends.len()];
    for v in 0..masks.len() {
        let mut seen = vec![false; ends.len()];
        augment(v, &tubes_at, &mut joint_on, &mut seen);
    }
    let mut carrier = vec![None; masks.len()];
    for (t, v) in joint_on.iter().enumerate() {
        if let Some(v) = *v {
            carrier[v] = Some(t);
        }
    }
    carrier
}

/// One augmenting path from joint `v` for [`joint_carriers`]: true when
/// `v` found a tube, freeing one taken if need be.
fn augment(v: usize, tubes_at: &[Vec<usize>], joint_on: &mut [Option<usize>], seen: &mut [bool]) -> bool {
    for &t in &tubes_at[v] {
        if seen[t] {
            continue;
        }
        seen[t] = true;
        if joint_on[t].is_none_or(|w| augment(w, tubes_at, joint_on, seen)) {
            joint_on[t] = Some(v);
            return true;
        }
    }
    false
}
