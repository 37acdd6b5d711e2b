//! Contacts between balls in the product spaces: two balls touch where
//! any image of one overlaps the other, through the faces, as the tracer
//! shows every image.
//!
//! ```
//! use bevy_manifold_core::geometry::product::ProductPoint;
//! use bevy_manifold_core::space::product::ProductSpace;
//! use bevy_manifold_core::trace::product::{ProductBall, contact::contacts};
//! use glam::DVec3;
//! // S2 x S1 of circle 2: balls at heights 0.9 and -0.9 on the pole are
//! // 1.8 apart inside the prism, 0.2 apart through its top.
//! let space = ProductSpace::s2_x_s1(2.0);
//! let ball = |h: f64| ProductBall { center: ProductPoint::new(DVec3::Z, h), radius: 0.3, id: 1 };
//! let touch = contacts(&space, &ball(0.9), &ball(-0.9));
//! assert_eq!(touch.len(), 1);
//! assert!((touch[0].depth - 0.4).abs() < 1e-12);
//! ```

use super::{ProductBall, image_isometries};
use crate::geometry::product::ProductTangent;
use crate::space::product::ProductSpace;

/// Where an image of one ball overlaps another.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProductContact {
    /// How far they overlap: the sum of the radii less the distance
    /// between the centres.
    pub depth: f64,
    /// The distance between the centres.
    pub distance: f64,
    /// The unit tangent at the first ball's centre towards the image of
    /// the second (the way to push the first out: its opposite); `None`
    /// where the centres coincide.
    pub normal: Option<ProductTangent>,
}

/// Every image of `b` that overlaps `a` (a ball in the prism), deepest
/// first: the images of `b` within `r_a + r_b` of `a`'s centre are those
/// whose balls of that radius meet the prism, which holds that centre
/// ([`super::images`]' walk over the gluings).
#[must_use]
pub fn contacts(space: &ProductSpace, a: &ProductBall, b: &ProductBall) -> Vec<ProductContact> {
    let g = space.geometry;
    let reach = a.radius + b.radius;
    if !(reach.is_finite() && reach > 0.0) {
        return Vec::new();
    }
    let mut out: Vec<ProductContact> = image_isometries(space, b.center, reach)
        .into_iter()
        .map(|m| g.normalize_point(m.apply(b.center)))
        .filter_map(|image| {
            let distance = g.distance(a.center, image);
            (distance < reach).then(|| ProductContact {
                depth: reach - distance,
                distance,
                normal: g.log(a.center, image).map(|(v, _)| v),
            })
        })
        .collect();
    out.sort_by(|x, y| y.depth.total_cmp(&x.depth));
    out
}
