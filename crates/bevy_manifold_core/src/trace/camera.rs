//! The camera's rays: the ray of each pixel, under the camera's
//! perspective (or off-centre frustum) or a 360-degree panorama, from the
//! camera's isometry in the domain.
//!
//! WGSL twin: `shaders/camera.wgsl` in `bevy_manifold_gpu` (the same
//! names).

use super::flat::FlatScene;
use super::footprint::pixel_half_angle;
use super::settings::{Projection, TraceSettings};
use super::step::Ray;
use crate::geometry::Real;

/// The view-space slopes `(x, y)` of the direction through normalised
/// device coordinates `(x, y)` (the direction is `(x, y, -1)`): the
/// symmetric frustum of `tan_half_fov` and the image's aspect, or the
/// scene's off-centre [`crate::trace::Frustum`].
///
/// WGSL twin: `view_slopes` in `shaders/camera.wgsl`.
#[must_use]
pub fn view_slopes<R: Real>(flat: &FlatScene<R>, x: R, y: R, w: u32, h: u32) -> (R, R) {
    match flat.frustum {
        None => {
            let aspect = R::of(f64::from(w) / f64::from(h));
            (x * flat.tan_half_fov * aspect, y * flat.tan_half_fov)
        }
        Some([hw, hh, cx, cy]) => (x * hw + cx, y * hh + cy),
    }
}

/// The ray through the centre of pixel `(i, j)` of a `w` x `h` image.
///
/// WGSL twin: `camera_ray` in `shaders/camera.wgsl` (with
/// `view_direction`).
#[must_use]
pub fn camera_ray<R: Real>(flat: &FlatScene<R>, i: u32, j: u32, w: u32, h: u32) -> Ray<R> {
    let one = R::of(1.0);
    let x = R::of(2.0 * (f64::from(i) + 0.5) / f64::from(w)) - one;
    let y = one - R::of(2.0 * (f64::from(j) + 0.5) / f64::from(h));
    let (sx, sy) = view_slopes(flat, x, y, w, h);
    let d = R::v4(sx, sy, -one, R::of(0.0));
    let d = d * (one / R::dot4(d, d).sqrt());
    let g = flat.faces.geometry;
    let o = g.normalize_point::<R>(flat.camera * g.origin::<R>());
    Ray {
        origin: o,
        dir: g.normalize_tangent::<R>(o, flat.camera * d),
    }
}

/// The ray of pixel `(i, j)` of a `w` x `h` image under `projection`
/// ([`camera_ray`] for the perspective).
///
/// WGSL twin: `view_ray` in `shaders/camera.wgsl`.
#[must_use]
pub fn view_ray<R: Real>(flat: &FlatScene<R>, projection: Projection, i: u32, j: u32, w: u32, h: u32) -> Ray<R> {
    let (kind, half_separation) = projection.words();
    if kind == 0 {
        return camera_ray(flat, i, j, w, h);
    }
    // ODS: the top half is the left eye, the bottom half the right.
    let (rows, row, side) = if kind == 2 {
        let half = (h / 2).max(1);
        if j < half {
            (half, j, -1.0)
        } else {
            (h - half, j - half, 1.0)
        }
    } else {
        (h, j, 0.0)
    };
    let tau = core::f64::consts::TAU;
    let lon = R::of(tau * ((f64::from(i) + 0.5) / f64::from(w) - 0.5));
    let lat = R::of(core::f64::consts::PI * (0.5 - (f64::from(row) + 0.5) / f64::from(rows)));
    let zero = R::of(0.0);
    let d = R::v4(lon.sin() * lat.cos(), lat.sin(), -(lon.cos() * lat.cos()), zero);
    let g = flat.faces.geometry;
    // The eye, along the geodesic from the camera perpendicular to the
    // longitude's direction (its right: (cos, 0, sin)).
    let right = R::v4(lon.cos(), zero, lon.sin(), zero);
    let (eye, _) = g.exp::<R>(g.origin::<R>(), right, R::of(side) * R::of(f64::from(half_separation)));
    let o = g.normalize_point::<R>(flat.camera * eye);
    Ray {
        origin: o,
        dir: g.normalize_tangent::<R>(o, flat.camera * d),
    }
}

/// The half-angle of the pixels' cones for the scene's camera
/// ([`pixel_half_angle`]): its frustum's half height, or
/// `tan_half_fov`, over the image's rows.
#[must_use]
pub fn pixel_half_angle_of<R: Real>(flat: &FlatScene<R>, settings: &TraceSettings) -> f64 {
    let half_height = flat.frustum.map_or(flat.tan_half_fov, |f| f[1]).f64();
    pixel_half_angle(settings.projection, half_height, settings.height)
}
