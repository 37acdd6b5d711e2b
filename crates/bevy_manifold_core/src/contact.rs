//! Contacts through the face pairings: which images of one point lie near
//! another, and where two balls touch.
//!
//! In a manifold an object is seen, and touched, in every copy of the
//! domain: a ball near a face touches what lies just beyond the partner
//! face. Two points of the domain are as near as their nearest images,
//! `min_h d(p, h q)` over the group, and the route between them (the
//! geodesic to that image) crosses the faces on the way. The images within
//! a distance `r` of a point of the domain lie in the copies of the domain
//! that the ball of radius `r` around it meets; the walk behind
//! [`images_within`] and [`nearest_images`] goes through copies nearest
//! first and stops where the distance asked for ends, so nothing here
//! enumerates more of the group than that distance needs.
//!
//! ```
//! use bevy_manifold_core::contact;
//! use bevy_manifold_core::space::catalog;
//! use glam::DVec4;
//! // In the unit 3-torus, x = -0.4 and x = 0.4 are 0.2 apart through the
//! // face x = 1/2, 0.8 apart across the cube.
//! let torus = catalog::torus(1.0);
//! let (p, q) = (DVec4::new(-0.4, 0.0, 0.0, 1.0), DVec4::new(0.4, 0.0, 0.0, 1.0));
//! let near = contact::nearest_image(&torus, p, q).unwrap();
//! assert!((near.distance - 0.2).abs() < 1e-12);
//! assert!((near.direction - DVec4::new(-1.0, 0.0, 0.0, 0.0)).length() < 1e-12);
//! // Two balls of radius 0.15 touch there, 0.1 deep.
//! let touch = contact::ball_contacts(&torus, (p, 0.15), (q, 0.15));
//! assert_eq!(touch.len(), 1);
//! assert!((touch[0].depth - 0.1).abs() < 1e-12);
//! ```

use crate::geometry::{isometry, plane};
use crate::space::Space;
use crate::space::cells::CellId;
use core::cmp::Reverse;
use glam::{DMat4, DVec4};
use std::collections::{BinaryHeap, HashSet};

/// One image `h q` of a point `q`, seen from a point `p`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Image {
    /// The group element `h` that carries `q` to this image.
    pub element: DMat4,
    /// The image `h q`, normalised (in the chart of the domain, maybe
    /// outside the domain).
    pub point: DVec4,
    /// The unit tangent at `p` pointing along the geodesic to the image;
    /// zero when the image is `p` itself.
    pub direction: DVec4,
    /// The distance from `p` to the image.
    pub distance: f64,
}

/// Where two balls overlap, through one image of the second.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// The image of the second ball's centre that touches the first.
    pub image: Image,
    /// How far the balls overlap: the radii's sum less the distance
    /// (positive when they overlap).
    pub depth: f64,
    /// The point midway through the overlap, on the geodesic between the
    /// centres: the contact point.
    pub point: DVec4,
}

/// Most copies of the domain one query walks (a reach far larger than the
/// domain, in H3, meets exponentially many): past it the list holds what
/// the walk reached, nearest copies first.
pub const MAX_CELLS_WALKED: usize = 4096;

/// Every image of `target` within `reach` of `from`, nearest first. Both
/// points are in the domain (as placements are, once wrapped); the list
/// is complete within `reach` (up to [`MAX_CELLS_WALKED`] copies).
#[must_use]
pub fn images_within(space: &Space, from: DVec4, target: DVec4, reach: f64) -> Vec<Image> {
    if reach.is_nan() || reach < 0.0 {
        return Vec::new();
    }
    let mut images = walk(space, from, target, reach, usize::MAX);
    images.retain(|i| i.distance <= reach);
    images
}

/// The `count` images of `target` nearest to `from` (both in the domain),
/// nearest first: fewer only in a finite group with fewer elements, or
/// past [`MAX_CELLS_WALKED`].
#[must_use]
pub fn nearest_images(space: &Space, from: DVec4, target: DVec4, count: usize) -> Vec<Image> {
    let mut images = walk(space, from, target, f64::INFINITY, count);
    images.truncate(count);
    images
}

/// The copies `h D` of the domain that may come within `reach` of the
/// point `from`, nearest first by a lower bound of their distance from
/// `from` (the largest distance of `h^-1 from` outside one of the
/// domain's faces, 0 inside): each as its element `h` and that bound. The
/// walk goes from face to face and stops where the bound passes `reach`
/// (or after [`MAX_CELLS_WALKED`] copies). A geodesic from `from` to a
/// point of a copy crosses only copies whose bound is at most its length
/// (an open path can avoid the edges), so every copy that a ball of
/// radius `reach` about `from` meets is here.
///
/// ```
/// use bevy_manifold_core::contact;
/// use bevy_manifold_core::space::catalog;
/// use glam::DVec4;
/// // Near a corner of the unit 3-torus, a ball of radius 0.1 meets the
/// // eight cubes around the corner.
/// let torus = catalog::torus(1.0);
/// let copies = contact::copies_within(&torus, DVec4::new(0.45, 0.45, 0.45, 1.0), 0.1);
/// assert_eq!(copies.len(), 8);
/// assert_eq!(copies[0].1, 0.0);
/// ```
#[must_use]
pub fn copies_within(space: &Space, from: DVec4, reach: f64) -> Vec<(DMat4, f64)> {
    if reach.is_nan() || reach < 0.0 || !from.is_finite() {
        return Vec::new();
    }
    Copies::new(space, from, reach).collect()
}

/// The walk through the copies behind [`copies_within`], [`images_within`]
/// and [`nearest_images`]: a best-first search on the lower bound.
struct Copies<'a> {
    space: &'a Space,
    from: DVec4,
    reach: f64,
    seen: HashSet<CellId>,
    // Min-heap on the bound (non-negative, so its bits order as it does).
    heap: BinaryHeap<(Reverse<u64>, usize)>,
    elements: Vec<DMat4>,
}

impl<'a> Copies<'a> {
    fn new(space: &'a Space, from: DVec4, reach: f64) -> Self {
        let from = space.geometry().normalize_point::<f64>(from);
        let mut walk = Copies {
            space,
            from,
            reach,
            seen: HashSet::from([space.cell_id(&DMat4::IDENTITY)]),
            heap: BinaryHeap::new(),
            elements: Vec::new(),
        };
        walk.push(DMat4::IDENTITY);
        walk
    }

    /// The lower bound of the distance from `from` to the copy `h D`.
    fn bound(&self, h: &DMat4) -> f64 {
        let g = self.space.geometry();
        let seen_from = g.normalize_point::<f64>(isometry::inverse(g, *h) * self.from);
        self.space
            .faces()
            .iter()
            .map(|face| plane::signed_distance(g, face.plane, seen_from))
            .fold(0.0f64, f64::max)
    }

    fn push(&mut self, h: DMat4) {
        let b = self.bound(&h);
        if b <= self.reach + 1e-9 {
            self.heap.push((Reverse(b.to_bits()), self.elements.len()));
            self.elements.push(h);
        }
    }
}

impl Iterator for Copies<'_> {
    type Item = (DMat4, f64);

    fn next(&mut self) -> Option<(DMat4, f64)> {
        let (Reverse(bits), index) = self.heap.pop()?;
        let h = self.elements[index];
        let g = self.space.geometry();
        for f in self.space.faces() {
            // The copy across face `f` of `h D` is `h T_f D`.
            let next = isometry::orthonormalize(g, h * f.pairing);
            if self.seen.len() >= MAX_CELLS_WALKED || !self.seen.insert(self.space.cell_id(&next)) {
                continue;
            }
            self.push(next);
        }
        Some((h, f64::from_bits(bits)))
    }
}

/// The images behind [`images_within`] and [`nearest_images`]: one for
/// each copy of the walk, until the next copy's bound passes `reach` or
/// the `count`-th image found so far.
fn walk(space: &Space, from: DVec4, target: DVec4, reach: f64, count: usize) -> Vec<Image> {
    let g = space.geometry();
    if count == 0 || !from.is_finite() || !target.is_finite() {
        return Vec::new();
    }
    let from = g.normalize_point::<f64>(from);
    let target = g.normalize_point::<f64>(target);
    let mut images: Vec<Image> = Vec::new();
    for (h, lower) in Copies::new(space, from, reach) {
        let kth = if images.len() >= count {
            images[count - 1].distance
        } else {
            f64::INFINITY
        };
        if lower > kth + 1e-9 {
            break;
        }
        let point = g.normalize_point::<f64>(h * target);
        let distance = g.distance::<f64>(from, point);
        let at = images.partition_point(|i| i.distance <= distance);
        images.insert(
            at,
            Image {
                element: h,
                point,
                direction: g.log::<f64>(from, point).map_or(DVec4::ZERO, |(d, _)| d),
                distance,
            },
        );
    }
    images
}

/// The image of `target` nearest to `from` (both in the domain): the
/// shortest route between them through the faces. `None` only for points
/// that are not finite.
#[must_use]
pub fn nearest_image(space: &Space, from: DVec4, target: DVec4) -> Option<Image> {
    nearest_images(space, from, target, 1).into_iter().next()
}

/// The contacts of the ball `(a, ra)` with the images of the ball
/// `(b, rb)` (centres in the domain, radii in the space's distance): one
/// per image that overlaps, deepest first. In a small domain a ball can
/// touch several images of another, or of itself.
#[must_use]
pub fn ball_contacts(space: &Space, a: (DVec4, f64), b: (DVec4, f64)) -> Vec<Contact> {
    let g = space.geometry();
    let ((pa, ra), (pb, rb)) = (a, b);
    let sum = ra + rb;
    images_within(space, pa, pb, sum)
        .into_iter()
        .filter(|image| image.distance < sum)
        .map(|image| {
            let depth = sum - image.distance;
            // Midway through the overlap: ra - depth / 2 from a's centre.
            let along = ra - 0.5 * depth;
            let (point, _) = g.exp::<f64>(g.normalize_point::<f64>(pa), image.direction, along);
            Contact { image, depth, point }
        })
        .collect()
}
