//! Geodesic flow through the manifold: carry a point and direction a given
//! distance, crossing faces as a ray does. The tracer's walk without the
//! objects; entities moving along geodesics use the same steps.

use super::flat::FaceTables;
use super::step::{Ray, advance};
use super::walk::Walker;
use crate::geometry::Real;

/// Where a flowed ray ended.
#[derive(Clone, Copy, Debug)]
pub struct Flowed<R: Real> {
    /// The ray at the end, inside the domain.
    pub ray: Ray<R>,
    /// The group element of the cell it ended in: the point in the cover is
    /// `cell * ray.origin`.
    pub cell: R::M4,
    /// Faces crossed.
    pub levels: u32,
    /// False when `levels` ran out before the distance was covered.
    pub complete: bool,
}

/// Moves `ray` the distance `distance` along its geodesic through the
/// manifold, crossing at most `levels` faces.
#[must_use]
pub fn flow<R: Real>(tables: &FaceTables<R>, ray: Ray<R>, distance: R, levels: u32) -> Flowed<R> {
    let g = tables.geometry;
    let mut walk = Walker::new(ray, R::m4_of(glam::DMat4::IDENTITY));
    let mut left = distance;
    // Each pass crosses a face or (S3) covers a distance of 1, so the walk
    // ends: after levels faces, or when the distance is used up.
    loop {
        let (face, t_end) = walk.segment_end(tables);
        let length = g.chart_to_distance::<R>(t_end);
        let done = |ray, complete| Flowed {
            ray,
            cell: walk.cell,
            levels: walk.levels,
            complete,
        };
        if length >= left {
            return done(advance(g, &walk.ray, g.distance_to_chart::<R>(left)), true);
        }
        let end = advance(g, &walk.ray, t_end);
        if face.is_some() && walk.levels >= levels {
            return done(end, false);
        }
        left = left - length;
        walk.step(tables, face, end, true);
    }
}
