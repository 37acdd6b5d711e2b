//! Moving a placement through the manifold: the pure math behind the ECS
//! wrapping systems, free of the ECS.
//!
//! A placement is an isometry `M` of the model carrying the origin's frame
//! to an entity's position and frame inside the fundamental domain. After a
//! motion `M -> M'` whose position has left the domain, the chord from the
//! old position to the new one is walked as a ray walks (the same
//! [`Walker`]), face by face; the placement is carried back by the pairings
//! of the faces crossed, in order; the faces are reported so the caller
//! can update the entity's cell. Fast movers crossing many faces in one step therefore end
//! exactly where a finely stepped motion ends, with the same faces reported.
//!
//! ```
//! use bevy_manifold_core::motion::move_placement;
//! use bevy_manifold_core::space::catalog;
//! use bevy_manifold_core::trace::FaceTables;
//! use glam::{DMat4, DVec3};
//! let torus = catalog::torus(1.0);
//! let tables = FaceTables::<f64>::new(&torus);
//! let from = DMat4::IDENTITY;
//! let to = DMat4::from_translation(DVec3::new(2.25, 0.0, 0.0));
//! let moved = move_placement(&torus, &tables, from, to, 64);
//! assert_eq!(moved.faces, vec![0, 0]); // out through +x twice
//! assert!((moved.placement.w_axis.x - 0.25).abs() < 1e-12);
//! ```

use crate::geometry::isometry;
use crate::space::Space;
use crate::trace::FaceTables;
use crate::trace::Walker;
use crate::trace::step::{Ray, advance};
use glam::{DMat4, DVec3, DVec4};

/// The result of [`move_placement`].
#[derive(Clone, Debug, PartialEq)]
pub struct Moved {
    /// The placement, back inside the domain, re-orthonormalised.
    pub placement: DMat4,
    /// The faces crossed, in order (the entity's cell is the old cell times
    /// their [`Space::crossing`]s).
    pub faces: Vec<usize>,
}

/// Carries the placement `to`, reached by a motion from the placement
/// `from` (inside the domain), back into the domain through the faces the
/// motion crossed, at most `max_crossings` of them (then the nearest-face
/// rule finishes the job, so the result is always inside).
#[must_use]
pub fn move_placement(space: &Space, tables: &FaceTables<f64>, from: DMat4, to: DMat4, max_crossings: usize) -> Moved {
    let g = space.geometry();
    let p0 = g.normalize_point::<f64>(from.w_axis);
    let p1 = g.normalize_point::<f64>(to.w_axis);
    let mut faces = Vec::new();
    let mut left = g.distance::<f64>(p0, p1);
    let mut walk = Walker::new(
        Ray {
            origin: p0,
            dir: g.normalize_tangent::<f64>(p0, p1),
        },
        DMat4::IDENTITY,
    );
    if left > 0.0 && left.is_finite() {
        while faces.len() < max_crossings {
            let (face, t) = walk.segment_end(tables);
            let length = g.chart_to_distance::<f64>(t);
            if length >= left {
                break;
            }
            left -= length;
            let end = advance(g, &walk.ray, t);
            walk.step(tables, face, end, true);
            faces.extend(face);
        }
    }
    // T_fk ... T_f1 M' = (product of crossings)^-1 M'.
    let mut placement = isometry::orthonormalize(g, isometry::inverse(g, walk.cell) * to);
    // Rounding can leave the end a hair outside; the nearest-face rule
    // settles it (and finishes a motion that crossed more than
    // max_crossings).
    if space.outside_face(placement.w_axis, 1e-12).is_some() {
        placement = space.wrap_with(placement, 1000, &mut |f| faces.push(f)).0;
    }
    Moved { placement, faces }
}

/// Longest distance moved between two wraps. Longer motions are cut into
/// sub-steps: carried back after each, the placement never strays far from
/// the domain, where H3 isometries would have entries of size `e^distance`
/// and lose every digit when carried back.
pub const MAX_SUBSTEP: f64 = 0.5;

/// Most sub-steps one call of [`advance_placement`] takes (a motion longer
/// than `MAX_SUBSTEP * MAX_SUBSTEPS` is cut short: no velocity can stall a
/// frame).
pub const MAX_SUBSTEPS: usize = 100_000;

/// Moves a placement for time `dt` at constant velocity (`linear`,
/// `angular`, in its own frame) by the isometry exponential, wrapping it
/// back into the domain along the way. Returns the placement and the faces
/// crossed in order. `complete` is false when the motion
/// was cut at [`MAX_SUBSTEPS`].
#[must_use]
pub fn advance_placement(
    space: &Space,
    tables: &FaceTables<f64>,
    placement: DMat4,
    linear: DVec3,
    angular: DVec3,
    dt: f64,
) -> (Moved, bool) {
    let g = space.geometry();
    let wanted = (linear.length() * dt / MAX_SUBSTEP).ceil();
    let complete = wanted <= MAX_SUBSTEPS as f64;
    let n = if wanted.is_finite() {
        wanted.clamp(1.0, MAX_SUBSTEPS as f64) as usize
    } else {
        1
    };
    let h = dt / n as f64;
    let step = isometry::exp_twist(g, linear * h, angular * h);
    let mut out = Moved {
        placement,
        faces: Vec::new(),
    };
    for _ in 0..n {
        let moved = move_placement(space, tables, out.placement, out.placement * step, usize::MAX);
        out.placement = moved.placement;
        out.faces.extend(moved.faces);
    }
    (out, complete)
}

/// The chart position of a placement: `(x, y, z) / w`.
#[must_use]
pub fn chart_position(placement: &DMat4) -> glam::DVec3 {
    let p: DVec4 = placement.w_axis;
    p.truncate() / p.w
}
