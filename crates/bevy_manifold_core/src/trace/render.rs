//! A whole image: every pixel's ray traced ([`render`]), in parallel
//! over pixels, into a [`TraceImage`] of [`TracePixel`]s (colour and ids).
//!
//! WGSL twin: `shaders/render.wgsl` in `bevy_manifold_gpu`, the entry
//! points: `trace` (compute, every pixel into a buffer), `fragment` (the
//! render pass) and `drift` (the drift probe).

use super::camera::view_ray;
use super::flat::FlatScene;
use super::path::path_sample;
use super::scene::Scene;
use super::settings::TraceSettings;
use super::trace::{TracePixel, trace_ray};
use crate::geometry::Real;
use crate::space::Space;
#[cfg(feature = "parallel")]
use rayon::prelude::*;

/// A traced image with its id buffer.
#[derive(Clone, Debug)]
pub struct TraceImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major pixels, top row first.
    pub pixels: Vec<TracePixel>,
}

impl TraceImage {
    /// The pixel at column `i`, row `j`.
    #[must_use]
    pub fn at(&self, i: u32, j: u32) -> &TracePixel {
        &self.pixels[(j * self.width + i) as usize]
    }
}

/// Renders `scene` in `space`: one ray per pixel ([`view_ray`], then
/// [`trace_ray`], or with [`TraceSettings::path_depth`] one path sample,
/// [`super::path_sample`]), in parallel. WGSL twin: the `trace` entry point of
/// `shaders/render.wgsl`.
#[must_use]
pub fn render<R: Real>(space: &Space, scene: &Scene, settings: &TraceSettings) -> TraceImage {
    let flat = FlatScene::<R>::new(space, scene);
    let (w, h) = (settings.width, settings.height);
    #[cfg(feature = "parallel")]
    let indices = (0..w * h).into_par_iter();
    #[cfg(not(feature = "parallel"))]
    let indices = 0..w * h;
    let pixels = indices
        .map(|k| {
            let ray = view_ray(&flat, settings.projection, k % w, k / w, w, h);
            if settings.path_depth > 0 {
                path_sample(space, &flat, ray, settings, k)
            } else {
                trace_ray(space, &flat, ray, settings, &mut |_| {}).0
            }
        })
        .collect();
    TraceImage {
        width: w,
        height: h,
        pixels,
    }
}
