//! Comparing traced images pixel by pixel, the one place tests and
//! benchmarks do it: object and cell ids, colours within a tolerance,
//! PSNR.

use bevy_manifold_core::space::Space;
use bevy_manifold_core::trace::{Scene, TraceImage, TracePixel, TraceSettings, render, srgb8};

/// Fractions of pixels with the same object and cell id, and with every
/// colour channel within 2/255, of `a` against the reference `b`. A cell id
/// either side flags FAR (a hyperbolic copy beyond the horizon of its
/// precision, where ids are best effort) is not compared; the object is.
pub fn agreement(a: &TraceImage, b: &TraceImage) -> (f64, f64) {
    let n = a.pixels.len() as f64;
    let ids = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .filter(|(p, q)| p.object == q.object && (p.cell == q.cell || q.cell.is_far() || p.cell.is_far()))
        .count();
    let colors = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .filter(|(p, q)| {
            p.color
                .iter()
                .zip(&q.color)
                .all(|(x, y)| (x.clamp(0.0, 1.0) - y.clamp(0.0, 1.0)).abs() <= 2.0 / 255.0)
        })
        .count();
    (ids as f64 / n, colors as f64 / n)
}

/// The fraction of pixels of an RGBA8 image (as a render target stores
/// it, sRGB-encoded) whose three channels are within `tol` of the
/// reference image's colours, encoded the same way.
#[must_use]
pub fn rgba8_agreement(bytes: &[u8], reference: &TraceImage, tol: u8) -> f64 {
    let close = bytes
        .chunks_exact(4)
        .zip(&reference.pixels)
        .filter(|(px, q)| (0..3).all(|c| px[c].abs_diff(srgb8(q.color[c])) <= tol))
        .count();
    close as f64 / reference.pixels.len() as f64
}

/// Error of an image against the reference, pooled over views.
#[derive(Clone, Copy, Debug, Default)]
pub struct ImageErrors {
    /// Pixels compared.
    pub pixels: usize,
    /// Pixels whose object differs.
    pub object: usize,
    /// Object mismatches where either side shows an object fog has not
    /// hidden (all of them without fog).
    pub visible: usize,
    /// Pixels with the same object hit, in different cells.
    pub cell: usize,
    /// Pixels with the same object hit where either cell id is FAR (not
    /// compared).
    pub far: usize,
    /// Sum of the squared sRGB channel differences (in units of 1).
    pub squared: f64,
}

impl ImageErrors {
    /// Adds an image's errors; `fog` is the scene's density, if any.
    pub fn add(&mut self, img: &TraceImage, reference: &TraceImage, fog: Option<f64>) {
        // What fog leaves of an object's light at distance d: below one
        // 8-bit step it is invisible.
        let shows =
            |p: &TracePixel| p.object != 0 && fog.is_none_or(|k| (-k * f64::from(p.distance)).exp() > 1.0 / 255.0);
        for (p, q) in img.pixels.iter().zip(&reference.pixels) {
            self.pixels += 1;
            if p.object != q.object && (shows(p) || shows(q)) {
                self.visible += 1;
            }
            for c in 0..3 {
                let d = (f64::from(srgb8(p.color[c])) - f64::from(srgb8(q.color[c]))) / 255.0;
                self.squared += d * d;
            }
            // The cell of a pixel that hit nothing is only where its ray
            // gave up: cells are compared for hits alone.
            if p.object != q.object {
                self.object += 1;
            } else if p.object != 0 {
                if p.cell.is_far() || q.cell.is_far() {
                    self.far += 1;
                } else if p.cell != q.cell {
                    self.cell += 1;
                }
            }
        }
    }

    /// `n` as a fraction of the pixels compared.
    #[must_use]
    pub fn share(&self, n: usize) -> f64 {
        n as f64 / self.pixels.max(1) as f64
    }

    /// Object or cell id mismatch, as a fraction of the pixels.
    #[must_use]
    pub fn id_mismatch(&self) -> f64 {
        self.share(self.object + self.cell)
    }

    /// Id mismatch counting only objects fog leaves visible.
    #[must_use]
    pub fn visible_mismatch(&self) -> f64 {
        self.share(self.visible + self.cell)
    }

    /// Root-mean-square sRGB channel error (in units of 1).
    #[must_use]
    pub fn rmse(&self) -> f64 {
        (self.squared / (3 * self.pixels.max(1)) as f64).sqrt()
    }

    /// Peak signal-to-noise ratio in dB (infinite for equal images).
    #[must_use]
    pub fn psnr(&self) -> f64 {
        let r = self.rmse();
        if r > 0.0 { -20.0 * r.log10() } else { f64::INFINITY }
    }
}

/// Linear colours of a trace, row-major.
#[must_use]
pub fn colors(img: &TraceImage) -> Vec<[f32; 3]> {
    img.pixels.iter().map(|p| p.color).collect()
}

/// The CPU f64 trace of `settings` at `k` times its size, each pixel the
/// mean of its `k` x `k` block: `k^2` samples per pixel, box-filtered
/// over the pixel, each a ray (cone tracing off). The reference the
/// anti-aliasing tests and `bench aa` measure against.
#[must_use]
pub fn supersampled(space: &Space, scene: &Scene, settings: &TraceSettings, k: u32) -> Vec<[f32; 3]> {
    let big = render::<f64>(
        space,
        scene,
        &TraceSettings {
            width: settings.width * k,
            height: settings.height * k,
            footprint: false,
            ..settings.clone()
        },
    );
    let (w, h) = (settings.width, settings.height);
    let n = (k * k) as f32;
    (0..w * h)
        .map(|p| {
            let (i, j) = (p % w, p / w);
            let mut sum = [0.0f32; 3];
            for dy in 0..k {
                for dx in 0..k {
                    let c = big.pixels[((j * k + dy) * w * k + i * k + dx) as usize].color;
                    for (s, c) in sum.iter_mut().zip(c) {
                        *s += c / n;
                    }
                }
            }
            sum
        })
        .collect()
}

/// PSNR (dB) of two images of linear colours, compared as sRGB bytes
/// (infinite for equal images).
#[must_use]
pub fn psnr_of(a: &[[f32; 3]], b: &[[f32; 3]]) -> f64 {
    let sq: f64 = a
        .iter()
        .zip(b)
        .flat_map(|(x, y)| (0..3).map(move |c| (f64::from(srgb8(x[c])) - f64::from(srgb8(y[c]))).powi(2)))
        .sum();
    let rmse = (sq / (3 * a.len().max(1)) as f64).sqrt() / 255.0;
    if rmse > 0.0 {
        -20.0 * rmse.log10()
    } else {
        f64::INFINITY
    }
}

/// The mean absolute change per channel between two images of linear
/// colours, in sRGB bytes: one frame's flicker against the last.
#[must_use]
pub fn change(a: &[[f32; 3]], b: &[[f32; 3]]) -> f64 {
    let sum: f64 = a
        .iter()
        .zip(b)
        .flat_map(|(x, y)| (0..3).map(move |c| f64::from(srgb8(x[c]).abs_diff(srgb8(y[c])))))
        .sum();
    sum / (3 * a.len().max(1)) as f64
}

/// A picture of a scene: what [`creeping_flicker`] traces each frame.
pub type Picture<'a> = &'a dyn Fn(&Scene) -> Vec<[f32; 3]>;

/// Flicker while the camera creeps forward: for each of `pictures`, the
/// mean [`change`] from one frame to the next over `frames` frames, the
/// camera moving `step` along its view (`-z`) each frame. `first` holds
/// each picture of `scene` as it is (already made for other measures).
#[must_use]
pub fn creeping_flicker(
    space: &Space,
    scene: &Scene,
    (step, frames): (f64, u32),
    first: Vec<Vec<[f32; 3]>>,
    pictures: &[Picture<'_>],
) -> Vec<f64> {
    let forward = bevy_manifold_core::geometry::isometry::translation(space.geometry(), glam::DVec3::NEG_Z * step);
    let mut moving = scene.clone();
    let mut last = first;
    let mut sums = vec![0.0; pictures.len()];
    for _ in 0..frames {
        moving.camera.isometry *= forward;
        for ((picture, last), sum) in pictures.iter().zip(&mut last).zip(&mut sums) {
            let now = picture(&moving);
            *sum += change(&now, last);
            *last = now;
        }
    }
    sums.into_iter().map(|s| s / f64::from(frames.max(1))).collect()
}

/// One view traced three ways on the CPU in f64, one ray a pixel, one cone
/// a pixel (`TraceSettings::footprint`) and [`supersampled`] at `k` x `k`
/// samples a pixel (the reference), with each way's [`creeping_flicker`]:
/// what `bench aa` tabulates and the cone tests assert on.
pub struct ConeComparison {
    /// One ray a pixel.
    pub plain: Vec<[f32; 3]>,
    /// One cone a pixel.
    pub cone: Vec<[f32; 3]>,
    /// `k` x `k` rays a pixel, box-filtered.
    pub reference: Vec<[f32; 3]>,
    /// The flicker of the plain, cone and reference pictures, in that
    /// order, while the camera creeps forward.
    pub flicker: [f64; 3],
}

/// [`ConeComparison`] of `scene` at `settings` (cones off in them), the
/// reference at `k` x `k` samples a pixel, the flicker over `frames`
/// frames moving `step` each.
#[must_use]
pub fn compare_cones(
    space: &Space,
    scene: &Scene,
    settings: &TraceSettings,
    k: u32,
    (step, frames): (f64, u32),
) -> ConeComparison {
    let cone_settings = TraceSettings {
        footprint: true,
        ..settings.clone()
    };
    let (plain_of, cone_of, reference_of) = (
        |s: &Scene| colors(&render::<f64>(space, s, settings)),
        |s: &Scene| colors(&render::<f64>(space, s, &cone_settings)),
        |s: &Scene| supersampled(space, s, settings, k),
    );
    let (plain, cone, reference) = (plain_of(scene), cone_of(scene), reference_of(scene));
    let flicker = creeping_flicker(
        space,
        scene,
        (step, frames),
        vec![plain.clone(), cone.clone(), reference.clone()],
        &[&plain_of, &cone_of, &reference_of],
    );
    ConeComparison {
        plain,
        cone,
        reference,
        flicker: [flicker[0], flicker[1], flicker[2]],
    }
}
