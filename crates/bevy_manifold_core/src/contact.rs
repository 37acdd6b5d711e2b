//! Contacts through the face pairings: which images of one point lie near
//! another, and where two balls touch.
//!
//! In a manifold an object is seen, and touched, in every copy of the
//! domain: a ball near a face touches what lies just beyond the partner
//! face. Two points of the domain are as near as their nearest images,
//! `min_h d(p, h q)` over the group, and the route between them (the
//! geodesic to that image) crosses the faces on the way. The images within
//! a distance `r` of a point of the domain are among those whose ball of
//! radius `r` reaches into the domain, which [`ghost_elements`] walks (the
//! tracer's ghost copies), so nothing here enumerates more of the group
//! than the distance asks for.
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

use crate::space::Space;
use crate::trace::ghost_elements;
use glam::{DMat4, DVec4};

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

/// Every image of `target` within `reach` of `from`, nearest first. Both
/// points are in the domain (as placements are, once wrapped); the list
/// is complete within `reach`.
#[must_use]
pub fn images_within(space: &Space, from: DVec4, target: DVec4, reach: f64) -> Vec<Image> {
    let g = space.geometry();
    if reach.is_nan() || reach < 0.0 || !from.is_finite() || !target.is_finite() {
        return Vec::new();
    }
    let from = g.normalize_point::<f64>(from);
    let target = g.normalize_point::<f64>(target);
    let mut images: Vec<Image> = ghost_elements(space, target, reach)
        .into_iter()
        .filter_map(|h| {
            let point = g.normalize_point::<f64>(h * target);
            let distance = g.distance::<f64>(from, point);
            (distance <= reach).then(|| Image {
                element: h,
                point,
                direction: g.log::<f64>(from, point).map_or(DVec4::ZERO, |(d, _)| d),
                distance,
            })
        })
        .collect();
    images.sort_by(|a, b| a.distance.total_cmp(&b.distance));
    images
}

/// The image of `target` nearest to `from` (both in the domain): the
/// shortest route between them through the faces. `None` only for points
/// that are not finite.
#[must_use]
pub fn nearest_image(space: &Space, from: DVec4, target: DVec4) -> Option<Image> {
    // Every point of the domain is within its diameter of every other,
    // so the nearest image is within twice the circumradius.
    images_within(space, from, target, 2.0 * space.circumradius() + 1e-9)
        .into_iter()
        .next()
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
