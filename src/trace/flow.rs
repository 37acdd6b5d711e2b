//! Geodesic flow through the manifold: carry a point and direction a given
//! distance, crossing faces as a ray does. The tracer's loop without the
//! objects; entities moving along geodesics use the same steps.

use super::prepare::Prepared;
use super::step::{Ray, advance, exit_face, transport};
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
    pub crossings: u32,
    /// False when `max_crossings` ran out before the distance was covered.
    pub complete: bool,
}

/// Moves `ray` the distance `distance` along its geodesic through the
/// manifold, crossing at most `max_crossings` faces.
#[must_use]
pub fn flow<R: Real>(prep: &Prepared<R>, mut ray: Ray<R>, distance: R, max_crossings: u32) -> Flowed<R> {
    let g = prep.geometry;
    let t_cap = g.max_chart_parameter::<R>();
    let mut left = distance;
    let mut cell = R::m4_of(glam::DMat4::IDENTITY);
    let mut entered = usize::MAX;
    let mut crossings = 0;
    loop {
        let exit = exit_face(&prep.planes, &ray, entered).filter(|&(_, t)| t < t_cap);
        let t_end = exit.map_or(t_cap, |(_, t)| t);
        let length = g.chart_to_distance::<R>(t_end);
        if length >= left {
            let t = g.distance_to_chart::<R>(left);
            return Flowed {
                ray: advance(g, &ray, t),
                cell,
                crossings,
                complete: true,
            };
        }
        left = left - length;
        let end = advance(g, &ray, t_end);
        match exit {
            Some((face, _)) => {
                if crossings >= max_crossings {
                    return Flowed {
                        ray: end,
                        cell,
                        crossings,
                        complete: false,
                    };
                }
                ray = transport(g, prep.pairings[face], &end);
                entered = prep.partners[face];
                cell = cell * prep.crossings[face];
                crossings += 1;
            }
            None => {
                ray = end;
                entered = usize::MAX;
            }
        }
    }
}
