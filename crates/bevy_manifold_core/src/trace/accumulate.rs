//! Anti-aliasing by accumulation: while nothing changes, each frame traces
//! the view again with the pixel grid moved by a sub-pixel offset
//! ([`sample_offset`], a low-discrepancy sequence whose first offset is
//! 0, so a moving view is exactly the plain trace) and keeps the running
//! mean. After `n` still frames every pixel is the mean of `n` rays
//! spread over its area: copies smaller than a pixel show at their
//! average colour instead of flickering on and off. The moved grid is an
//! off-centre frustum ([`Frustum::jittered`]), so neither tracer changes.
//!
//! The render pass's twin (`ManifoldAccumulation` in the `bevy_manifold`
//! crate, `src/render/upscale.rs`, and the `blend_in` entry of
//! `bevy_manifold_gpu`'s `shaders/upscale.wgsl`) blends each new trace
//! into its history with weight `1 / (k + 1)`; [`accumulate`] is the same
//! on the CPU.
//!
//! Shadows of lights with a radius soften the same way: the `k`-th trace
//! aims each shadow ray at the `k`-th point of the light's disc
//! ([`light_sample_point`], `TraceSettings::light_sample`), so the mean
//! of `n` still frames holds `n` shadows of the light's points, the
//! penumbra (the accumulation buffer's soft shadows, Haeberli and Akeley,
//! SIGGRAPH 1990).

use super::render::render;
use super::scene::{Frustum, Scene};
use super::settings::TraceSettings;
use crate::geometry::Real;
use crate::space::Space;

/// The `k`-th sub-pixel offset, in pixels, each coordinate in
/// `[-0.5, 0.5)`: Roberts' R2 sequence (the plastic number's powers),
/// which covers the square evenly at every length. `k = 0` is the centre.
///
/// ```
/// use bevy_manifold_core::trace::sample_offset;
/// assert_eq!(sample_offset(0), [0.0, 0.0]);
/// let [x, y] = sample_offset(5);
/// assert!((-0.5..0.5).contains(&x) && (-0.5..0.5).contains(&y));
/// ```
#[must_use]
pub fn sample_offset(k: u32) -> [f64; 2] {
    let k = f64::from(k);
    R2.map(|a| (0.5 + a * k).fract() - 0.5)
}

/// The `k`-th point of a light's disc a shadow ray aims at, in the unit
/// square: the same R2 sequence as [`sample_offset`] without its shift,
/// so `k = 0` is `[0, 0]`, the light's centre (hard shadows while the
/// view moves), and the first `n` points cover the square evenly (the
/// accumulated penumbra). See [`super::shadow::aim_at_light`].
///
/// ```
/// use bevy_manifold_core::trace::light_sample_point;
/// assert_eq!(light_sample_point(0), [0.0, 0.0]);
/// let [u, v] = light_sample_point(7);
/// assert!((0.0..1.0).contains(&u) && (0.0..1.0).contains(&v));
/// ```
#[must_use]
pub fn light_sample_point(k: u32) -> [f64; 2] {
    let k = f64::from(k);
    R2.map(|a| (a * k).fract())
}

/// 1/g and 1/g^2, g the plastic number (g^3 = g + 1): Roberts' R2
/// sequence.
const R2: [f64; 2] = [0.754_877_666_246_692_7, 0.569_840_290_998_053_3];

impl Frustum {
    /// The symmetric frustum of a vertical field of view (degrees) and an
    /// aspect (width over height): what a camera without a frustum sees.
    #[must_use]
    pub fn symmetric(fov_y_degrees: f64, aspect: f64) -> Self {
        let t = (fov_y_degrees.to_radians() / 2.0).tan();
        Frustum {
            left: -t * aspect,
            right: t * aspect,
            down: -t,
            up: t,
        }
    }

    /// The same view with every pixel of a `width` x `height` image moved
    /// by `offset` pixels (x right, y down): a pixel's ray then leaves
    /// through the point `offset` from its centre.
    #[must_use]
    pub fn jittered(&self, offset: [f64; 2], width: u32, height: u32) -> Self {
        let sx = (self.right - self.left) / f64::from(width.max(1)) * offset[0];
        let sy = (self.up - self.down) / f64::from(height.max(1)) * offset[1];
        Frustum {
            left: self.left + sx,
            right: self.right + sx,
            down: self.down - sy,
            up: self.up - sy,
        }
    }
}

/// The frustum of the `k`-th trace of an accumulating view of `scene`
/// at the size of `settings`: the camera's own (or the symmetric one of
/// its field of view) with every pixel moved by [`sample_offset`]`(k)`.
#[must_use]
pub fn sample_frustum(scene: &Scene, settings: &TraceSettings, k: u32) -> Frustum {
    let (w, h) = (settings.width, settings.height);
    let base = scene
        .camera
        .frustum
        .unwrap_or_else(|| Frustum::symmetric(scene.camera.fov_y_degrees, f64::from(w) / f64::from(h.max(1))));
    base.jittered(sample_offset(k), w, h)
}

/// The mean linear colour of `samples` traces of `scene`, the `k`-th with
/// its pixel grid moved by [`sample_offset`]`(k)`: the CPU twin of the
/// render pass's accumulation, row-major like [`render`]'s pixels.
#[must_use]
pub fn accumulate<R: Real>(space: &Space, scene: &Scene, settings: &TraceSettings, samples: u32) -> Vec<[f32; 3]> {
    let n = (settings.width * settings.height) as usize;
    let mut sum = vec![[0.0f64; 3]; n];
    let samples = samples.max(1);
    let mut moved = scene.clone();
    for k in 0..samples {
        moved.camera.frustum = Some(sample_frustum(scene, settings, k));
        let sampled = TraceSettings {
            light_sample: k,
            ..settings.clone()
        };
        let img = render::<R>(space, &moved, &sampled);
        for (s, p) in sum.iter_mut().zip(&img.pixels) {
            for (s, c) in s.iter_mut().zip(p.color) {
                *s += f64::from(c);
            }
        }
    }
    sum.iter().map(|s| s.map(|v| (v / f64::from(samples)) as f32)).collect()
}
