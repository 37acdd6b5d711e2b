//! What a segment of a ray meets: the object hit ([`Hit`]), and what is
//! kept of the objects [`super::cull::each_candidate`] hands out, the
//! nearest hit for a ray, the nearest layers for a pixel's cone
//! ([`Nearest`]).
//!
//! WGSL twin: `shaders/nearest.wgsl` in `bevy_manifold_gpu` (`Hit`,
//! `best` and the layers `met_t`, `met_id`, and `consider_ball`,
//! `consider_tube`, `consider_instance`). The last three are the arms of
//! the visitors that `nearest_object` and `segment_layers` (in `trace.rs`)
//! hand the walk, which WGSL, having no closures, writes as functions the
//! walk calls.

use super::flat::{EDGE_ID, FlatInstance, FlatScene};
use super::footprint::SEGMENT_LAYERS;
use super::step::may_hit;
use crate::geometry::Real;
use crate::mesh::MeshHit;

/// Which object a ray hit. WGSL twin: `Hit` in `shaders/nearest.wgsl`.
#[derive(Clone, Copy, Debug)]
pub(super) enum Hit<R: Real> {
    Ball(usize),
    Tube(usize),
    Mesh(usize, MeshHit<R>),
}

impl<R: Real> Hit<R> {
    /// The object's id, as [`super::TracePixel::object`] gives it. WGSL
    /// twin: `hit_id`.
    pub(super) fn id(self, flat: &FlatScene<R>) -> u32 {
        match self {
            Hit::Ball(i) => flat.balls[i].id,
            Hit::Tube(_) => EDGE_ID,
            Hit::Mesh(i, _) => flat.instances[i].id,
        }
    }
}

/// True when a mesh instance can be hit on a segment near `near` seen
/// from the cell of `cell_point` (not the camera's own body there).
/// WGSL twin: the test at the start of `consider_instance`.
pub(super) fn instance_shown<R: Real>(inst: &FlatInstance<R>, near: u32, cell_point: R::V4) -> bool {
    may_hit(inst.face_mask, near) && !inst.home.is_some_and(|home| same_cell_point::<R>(home, cell_point))
}

/// True when two cell points `g o` name the same copy of the domain:
/// copies' centres are at least twice the inradius apart, so a tolerance
/// of a thousandth of their size tells them apart in f32 as in f64.
/// WGSL twin: `same_cell_point` in `shaders/nearest.wgsl`.
#[must_use]
pub fn same_cell_point<R: Real>(a: R::V4, b: R::V4) -> bool {
    let d = a - b;
    let size = R::dot4(a, a).max(R::of(1.0));
    R::dot4(d, d) <= R::of(1e-6) * size
}

/// A thing met on a segment: where, what, and for a cone's layer what
/// it covers (`C`: [`super::cone::Cover`]).
pub(super) type Met<R, C> = (R, Hit<R>, Option<C>);

/// Up to [`SEGMENT_LAYERS`] layers met on one segment, nearest first,
/// and the nearest thing hit whole (a mesh for a cone; anything for a
/// ray), which hides what is behind it. WGSL twin: `met_t`, `met_id` and
/// `best` in `shaders/nearest.wgsl`.
pub(super) struct Nearest<R: Real, C: Copy> {
    met: [Option<Met<R, C>>; SEGMENT_LAYERS],
    count: usize,
    /// The nearest thing hit whole.
    pub(super) whole: Option<Met<R, C>>,
}

impl<R: Real, C: Copy> Default for Nearest<R, C> {
    fn default() -> Self {
        Nearest {
            met: [None; SEGMENT_LAYERS],
            count: 0,
            whole: None,
        }
    }
}

impl<R: Real, C: Copy> Nearest<R, C> {
    /// The farthest still wanted: `t_end`, or once full the farthest
    /// layer kept; never past the whole hit. WGSL twin: `met_limit`.
    pub(super) fn limit(&self, t_end: R) -> R {
        let layers = match self.count {
            SEGMENT_LAYERS => self.met[SEGMENT_LAYERS - 1].map_or(t_end, |m| m.0),
            _ => t_end,
        };
        self.whole.map_or(layers, |m| m.0.min(layers))
    }

    /// Keeps the layer `m` in order, dropping the farthest when full
    /// (a tie stays ahead). WGSL twin: `keep_met`.
    pub(super) fn keep(&mut self, m: Met<R, C>) {
        let mut at = self.count.min(SEGMENT_LAYERS - 1);
        self.met[at] = Some(m);
        while at > 0 && self.met[at - 1].is_some_and(|p| p.0 > m.0) {
            self.met.swap(at - 1, at);
            at -= 1;
        }
        self.count = (self.count + 1).min(SEGMENT_LAYERS);
    }

    /// What was met, nearest first: the layers before the whole hit (or
    /// level with it), then the whole hit.
    pub(super) fn iter(&self) -> impl Iterator<Item = &Met<R, C>> {
        let whole = self.whole;
        self.met[..self.count]
            .iter()
            .flatten()
            .take_while(move |m| whole.is_none_or(|h| h.0 >= m.0))
            .chain(self.whole.iter())
    }
}
