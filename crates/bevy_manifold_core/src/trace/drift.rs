//! How far a ray drifts off the model over many transports, for the
//! stability tests and `bench stability`.
//!
//! WGSL twin: `shaders/drift.wgsl` in `bevy_manifold_gpu` (`ray_drift`,
//! run by the `drift` entry of `shaders/render.wgsl`).

use super::flat::FlatScene;
use super::scene::Scene;
use super::settings::TraceSettings;
use super::step::Ray;
use super::trace::trace_ray;
use crate::geometry::Real;
use crate::space::Space;

/// The worst normalisation errors seen along one ray's walk.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RayDrift {
    /// Largest [`crate::geometry::Geometry::point_error`] of any segment
    /// end (`|<p,p> -+ 1|`, or `|w - 1|` in E3).
    pub point_error: f64,
    /// Largest [`crate::geometry::Geometry::tangent_error`] of any segment
    /// end (`|<p,d>|` or `|<d,d> - 1|`).
    pub tangent_error: f64,
    /// How far outside the domain any segment end was: the largest
    /// `n . (p / w)` over the faces (chart units; `<= 0` is inside).
    pub outside: f64,
    /// Transports made.
    pub levels: u32,
    /// Distance travelled.
    pub distance: f64,
}

impl RayDrift {
    /// The larger of the two errors; infinite when either is not finite
    /// (the walk diverged).
    #[must_use]
    pub fn worst(&self) -> f64 {
        let w = self.point_error.max(self.tangent_error);
        if self.point_error.is_finite() && self.tangent_error.is_finite() {
            w
        } else {
            f64::INFINITY
        }
    }
}

/// Walks `ray` as the tracer does, with no objects, through
/// `settings.levels` transports (or `settings.max_distance`),
/// renormalising or not as `settings.renormalize` says, and returns the
/// worst errors over every segment's start and end.
#[must_use]
pub fn ray_drift<R: Real>(space: &Space, ray: Ray<R>, settings: &TraceSettings) -> RayDrift {
    let flat = FlatScene::<R>::new(space, &Scene::empty());
    let g = space.geometry();
    let mut drift = RayDrift {
        outside: f64::NEG_INFINITY,
        ..RayDrift::default()
    };
    let mut note = |r: &Ray<R>| {
        drift.point_error = drift.point_error.max(g.point_error::<R>(r.origin).f64());
        drift.tangent_error = drift.tangent_error.max(g.tangent_error::<R>(r.origin, r.dir).f64());
        let c = R::v4_f64(r.origin);
        let c = c / c.w;
        for f in space.faces() {
            drift.outside = drift.outside.max(f.plane.dot(c));
        }
        // max() drops NaN: keep it, so a diverged walk shows.
        if !(R::v4_f64(r.origin).is_finite() && R::v4_f64(r.dir).is_finite()) {
            drift.point_error = f64::NAN;
        }
    };
    let (pixel, _) = trace_ray(space, &flat, ray, settings, &mut |st| {
        note(&st.start);
        note(&st.end);
    });
    drift.levels = pixel.levels;
    drift.distance = f64::from(pixel.distance);
    drift
}
