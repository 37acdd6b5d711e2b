//! A ray walking segment by segment through the manifold: the part of
//! Algorithm 1 shared by the tracer and by geodesic flow (objects aside).
//!
//! WGSL twin: `shaders/walk.wgsl` in `bevy_manifold_gpu` (`Walker`,
//! `walker_step`, and `walk_segment`). The last is the end of the loop of
//! [`super::trace_ray`], shared there by the tracer and the drift probe.

use super::flat::FaceTables;
use super::step::{Ray, exit_face, transport_or_raw};
use crate::geometry::Real;

/// Where a walking ray is: the start of its current segment, the face it
/// came in through, the cell it is in and how many faces it has crossed
/// (its levels). WGSL twin: `Walker` in `shaders/walk.wgsl`.
#[derive(Clone, Copy, Debug)]
pub struct Walker<R: Real> {
    /// Start of the current segment (inside the domain).
    pub ray: Ray<R>,
    /// The face it entered by (skipped when looking for the exit), or
    /// `usize::MAX`.
    pub entered: usize,
    /// The group element of the current cell: the ray's point in the cover
    /// is `cell * ray.origin`.
    pub cell: R::M4,
    /// Faces crossed so far (the paper's level).
    pub levels: u32,
}

impl<R: Real> Walker<R> {
    /// A walk starting at `ray` in the cell `cell`.
    #[must_use]
    pub fn new(ray: Ray<R>, cell: R::M4) -> Self {
        Walker {
            ray,
            entered: usize::MAX,
            cell,
            levels: 0,
        }
    }

    /// Where the current segment ends: the face it leaves through (none in
    /// S3 when no face is within a quarter turn) and the chart parameter.
    #[must_use]
    pub fn segment_end(&self, tables: &FaceTables<R>) -> (Option<usize>, R) {
        let t_cap = tables.geometry.max_chart_parameter::<R>();
        match exit_face(&tables.planes, &self.ray, self.entered) {
            Some((face, t)) if t < t_cap => (Some(face), t),
            _ => (None, t_cap),
        }
    }

    /// Starts the next segment from `end`, the end of the current one:
    /// through the pairing of `face` (moving to the neighbouring cell), or
    /// straight on when there is no face. `renormalize` is off only to
    /// measure drift.
    pub fn step(&mut self, tables: &FaceTables<R>, face: Option<usize>, end: Ray<R>, renormalize: bool) {
        let Some(face) = face else {
            self.ray = end;
            self.entered = usize::MAX;
            return;
        };
        let t = tables.pairings[face];
        self.ray = transport_or_raw(tables.geometry, t, &end, renormalize);
        self.entered = tables.partners[face];
        self.cell = self.cell * tables.crossings[face];
        self.levels += 1;
    }
}
