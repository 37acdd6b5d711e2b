//! The images of each light in the cover that light the domain: the light
//! is a function on the manifold, so a point of the domain is lit by
//! every copy `g p` of a light at `p` (`g` in the pairing group), each
//! along its own geodesic (two arcs in S3), and a surface lit across a
//! face sees the same copies from both sides: no seam.
//!
//! The sum is made finite on purpose. In E3 and H3 it diverges without a
//! range: the number of images within `d` grows like the sphere's area
//! while each one's irradiance falls like its inverse, so each shell of
//! the cover adds about as much as the last (Olbers). Each light has a
//! range with a smooth cut-off (Bevy's window `(1 - (d/r)^4)^2`); at
//! most [`Lighting::images`] images of it are kept, nearest the domain
//! first, and when more lie within its range the range is cut to the
//! nearest image left out. So every image that can light any point of
//! the domain is kept, whichever point: the sum is exact for the light
//! as cut, and continuous across every face. Fog on the light's way
//! dims far images further ([`image_irradiance`]). In S3 quotients the
//! group is finite: all of it is kept when it fits, with both arcs.
//!
//! Worked out on the CPU when the scene changes; the GPU reads the
//! images as its lights (`FlatScene::lights`).

use super::flat::FlatLight;
use super::scene::{Light, Lighting};
use crate::geometry::{Geometry, Real};
use crate::space::Space;
use glam::{DMat4, DVec4};
use std::f64::consts::PI;

/// Most light images a scene holds: the GPU's uniform array of lights.
/// WGSL twin: `MAX_LIGHTS` in `shaders/bindings.wgsl`.
pub const MAX_LIGHT_IMAGES: usize = 256;

/// The irradiance floor of a point light: `intensity / area` is capped
/// at `intensity / MIN_AREA`, as before light images.
pub const MIN_AREA: f64 = 1e-4;

/// Each light of `lights` as the images of it that light the domain
/// under `lighting` (see the module): the light's copy in the domain
/// alone when `lighting.images` is 0. At most [`MAX_LIGHT_IMAGES`] in
/// all: each light keeps `min(images, MAX_LIGHT_IMAGES / lights)`; the
/// first [`super::MAX_LIGHTS`] lights only.
///
/// ```
/// use bevy_manifold_core::prelude::*;
/// use bevy_manifold_core::trace::light_images;
/// let space = catalog::torus(2.0);
/// let light = Light::point(glam::DVec4::W, 1.0, [1.0; 3]);
/// let lighting = Lighting { images: 32, shadows: false };
/// let images = light_images::<f64>(&space, &[light], lighting);
/// // The light and its 26 neighbours (across faces, edges and corners);
/// // the next ring would pass the budget, so the range stops short of it.
/// assert_eq!(images.len(), 27);
/// ```
#[must_use]
pub fn light_images<R: Real>(space: &Space, lights: &[Light], lighting: Lighting) -> Vec<FlatLight<R>> {
    let g = space.geometry();
    // Past MAX_LIGHTS a scene's lights are left out, as the GPU did
    // before light images.
    let lights = &lights[..lights.len().min(super::scene::MAX_LIGHTS)];
    if lighting.images == 0 {
        return lights
            .iter()
            .map(|l| flat_light(g, l, &DMat4::IDENTITY, f64::INFINITY, MIN_AREA))
            .collect();
    }
    let budget = (lighting.images as usize)
        .min(MAX_LIGHT_IMAGES / lights.len().max(1))
        .max(1);
    let mut out = Vec::new();
    for l in lights {
        let min_area = g.sphere_area::<f64>(l.radius.max(0.0)).max(MIN_AREA);
        let (images, range) = images_of(space, l, budget);
        out.extend(images.iter().map(|m| flat_light(g, l, m, range, min_area)));
    }
    out
}

/// The images of light `l` that light the domain, at most `budget`, and
/// the range they are complete to (infinite: no cut-off).
fn images_of(space: &Space, l: &Light, budget: usize) -> (Vec<DMat4>, f64) {
    let g = space.geometry();
    let rc = space.circumradius();
    // An image within r of the domain lies within r + rc of o, and its
    // cell's centre within r + rc + d(o, p).
    let slack = rc + g.distance::<f64>(DVec4::W, l.position);
    let requested = l.range.filter(|r| r.is_finite() && *r > 0.0).unwrap_or(f64::INFINITY);
    let at = |m: &glam::DMat4| g.normalize_point::<f64>(*m * l.position);
    // S3 quotients: the whole group when it fits, both arcs of each.
    if g == Geometry::Spherical
        && let Some(order) = space.group_order()
        && order <= budget
    {
        let cover = space.cover_within(std::f64::consts::PI + slack);
        let range = if requested >= std::f64::consts::TAU {
            f64::INFINITY
        } else {
            requested
        };
        return (cover.elements.iter().map(|(m, _)| *m).collect(), range);
    }
    // The images sorted by how near the domain they can come; complete
    // up to `complete`.
    let mut reach = requested.min(space.inradius());
    for _ in 0..12 {
        let cover = space.cover_within(reach + slack);
        let complete = cover.complete_to - slack;
        let mut images: Vec<(f64, DMat4)> = cover
            .elements
            .iter()
            .map(|(m, _)| (space.distance_outside(at(m)), *m))
            .collect();
        images.sort_by(|a, b| a.0.total_cmp(&b.0));
        let within = |r: f64| images.partition_point(|i| i.0 < r);
        let range = if requested <= complete && within(requested) <= budget {
            Some(requested)
        } else if within(complete) > budget {
            Some(images[budget].0)
        } else if cover.complete_to < reach + slack || reach >= requested {
            // The walk stopped at its cap, or nothing more is wanted.
            Some(complete.max(0.0).min(requested))
        } else {
            None
        };
        if let Some(mut range) = range {
            // In S3, past a half turn the long way round is shorter.
            if g == Geometry::Spherical {
                range = range.min(std::f64::consts::PI);
            }
            if range <= 0.0 {
                return (Vec::new(), 0.0);
            }
            let n = within(range);
            return (images[..n].iter().map(|i| i.1).collect(), range);
        }
        reach = (reach * 1.6).min(requested);
    }
    (Vec::new(), 0.0)
}

fn flat_light<R: Real>(g: Geometry, l: &Light, m: &DMat4, range: f64, min_area: f64) -> FlatLight<R> {
    let image = g.normalize_point::<f64>(*m * l.position);
    let spot = l.spot.and_then(|s| {
        let axis = g.project_tangent::<f64>(l.position, s.direction);
        let len = g.form::<f64>(axis, axis).abs().sqrt();
        (len > 1e-12 && s.inner.is_finite() && s.outer.is_finite()).then(|| {
            let (inner, outer) = (s.inner.clamp(0.0, PI), s.outer.clamp(0.0, PI));
            let (ci, co) = (inner.min(outer).cos(), outer.cos());
            let scale = 1.0 / (ci - co).max(1e-4);
            let axis = g.normalize_tangent::<f64>(image, *m * (axis / len));
            (axis, scale, -co * scale)
        })
    });
    let (spot_dir, spot_scale, spot_offset) = spot.unwrap_or((DVec4::ZERO, 0.0, 1.0));
    FlatLight {
        spot_dir: R::v4_of(spot_dir),
        spot_scale: R::of(spot_scale),
        spot_offset: R::of(spot_offset),
        position: R::v4_of(image),
        intensity: R::of(l.intensity),
        color: l.color,
        inv_range_sq: R::of(if range.is_finite() { 1.0 / (range * range) } else { 0.0 }),
        min_area: R::of(min_area),
        radius: R::of(if l.radius.is_finite() { l.radius.max(0.0) } else { 0.0 }),
    }
}

/// The irradiance one image of a light gives at arc length `s` from it
/// (the light's surface facing the point): `intensity / max(area(s),
/// min_area)`, times the range's smooth window `(1 - (s^2 / range^2)^2)^2`,
/// times `exp(-density s)` for fog of that density on the way (0: none).
/// A spot's cone is [`spot_factor`], apart.
/// WGSL twin: `image_irradiance` in `shaders/shade.wgsl`.
#[must_use]
pub fn image_irradiance<R: Real>(g: Geometry, l: &FlatLight<R>, s: R, fog_density: R) -> R {
    let zero = R::of(0.0);
    let f = s * s * l.inv_range_sq;
    let window = (R::of(1.0) - f * f).max(zero).min(R::of(1.0));
    let area = g.sphere_area::<R>(s).max(l.min_area);
    l.intensity * window * window / area * (-(fog_density * s)).exp()
}

/// How much of a light image's light leaves along `from_light` (a unit
/// tangent at the image, pointing at the lit point): 1 for a light in
/// every direction, a spot's `clamp(cos a * scale + offset, 0, 1)^2`.
/// WGSL twin: `spot_factor` in `shaders/shade.wgsl`.
#[must_use]
pub fn spot_factor<R: Real>(g: Geometry, l: &FlatLight<R>, from_light: R::V4) -> R {
    if l.spot_scale == R::of(0.0) {
        return R::of(1.0);
    }
    let f = (g.form::<R>(from_light, l.spot_dir) * l.spot_scale + l.spot_offset)
        .max(R::of(0.0))
        .min(R::of(1.0));
    f * f
}
