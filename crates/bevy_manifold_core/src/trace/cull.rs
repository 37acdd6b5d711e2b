//! Culling: which objects a segment of a ray can hit. Every object near
//! the domain's faces (an edge tube, a vertex joint, a ghost straddling a
//! face) carries a face mask, the faces whose planes all its points in the
//! domain lie near ([`face_mask`]); a segment tests it only when it comes
//! near all of them ([`super::step::near_faces`], [`super::step::may_hit`]),
//! and objects are kept in groups by their first face ([`FaceGroups`]) so
//! a segment walks only the groups of the faces it comes near.
//!
//! WGSL twin: `nearest_object` in `bevy_manifold_gpu`'s
//! `shaders/render.wgsl` walks the same groups (from `Params::groups`);
//! `near_faces` and `may_hit` are in `shaders/step.wgsl`.

use super::scene::Scene;
use crate::geometry::Geometry;
use crate::space::Space;
use glam::DVec4;

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

/// The faces (bits 0 to 31) of `space` whose planes every point of the
/// domain that an object reaches is within `reach` of, for an object
/// whose points lie within distance `radius` of `centers` (a ball: its
/// centre; a tube: its edge, given by its two ends): the depth inside a
/// plane grows by at most the distance moved, and along an edge it is
/// at most its ends' in E3 and H3 (convex), and 0 for a plane holding
/// both ends, the only planes an edge's reach (its radius and a hair, see
/// `cull_distance`) lets through in S3.
pub(super) fn face_mask(space: &Space, centers: &[DVec4], radius: f64, reach: f64) -> u32 {
    let g = space.geometry();
    let mut mask = 0;
    for (i, f) in space.faces().iter().enumerate().take(32) {
        let depth = centers
            .iter()
            .map(|&c| -crate::geometry::plane::signed_distance(g, f.plane, c))
            .fold(f64::NEG_INFINITY, f64::max);
        if depth + radius <= reach {
            mask |= 1 << i;
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
/// sorted by their mask's first face, unmasked ones first: the group of
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
}

impl FaceGroups {
    /// Sorts `items` (stably) by their mask's first face, unmasked first,
    /// and returns the group starts for a domain of `faces` faces: one per
    /// face up to 32, and then the count.
    pub fn sort<T>(items: &mut [T], faces: usize, mask: impl Fn(&T) -> u32) -> Vec<u32> {
        let key = |m: u32| if m == 0 { 0 } else { 1 + m.trailing_zeros() };
        items.sort_by_key(|x| key(mask(x)));
        let groups = faces.min(32) as u32;
        (0..=groups)
            .map(|f| items.iter().take_while(|x| key(mask(x)) <= f).count() as u32)
            .collect()
    }

    /// The index ranges of `starts` (a kind's group starts) a segment near
    /// the faces `near` walks: the unmasked objects, then the group of
    /// each near face, in order (so the objects come in the sorted order,
    /// as without culling).
    pub fn ranges(starts: &[u32], near: u32) -> impl Iterator<Item = core::ops::Range<usize>> + '_ {
        let unmasked = 0..starts.first().map_or(0, |&s| s as usize);
        let faces = starts.len().saturating_sub(1);
        core::iter::once(unmasked).chain(
            (0..faces)
                .filter(move |&f| near & (1 << f) != 0)
                .map(move |f| starts[f] as usize..starts[f + 1] as usize),
        )
    }
}
