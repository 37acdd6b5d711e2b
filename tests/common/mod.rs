//! Helpers shared by the GPU test files.

#![allow(dead_code, reason = "each test file uses its own part")]

use bevy_manifold::render::GpuTracer;
use bevy_manifold::trace::TraceImage;

/// The GPU tracer, or `None` (with a line saying why) when there is no
/// adapter outside CI; under CI (`CI` set) a missing adapter is a failure.
pub fn tracer() -> Option<GpuTracer> {
    match GpuTracer::new() {
        Ok(t) => {
            eprintln!("GPU adapter: {}", t.adapter_name());
            Some(t)
        }
        Err(e) if std::env::var_os("CI").is_none() => {
            eprintln!("SKIPPED: no GPU to test on: {e}");
            None
        }
        Err(e) => panic!("CI must have a GPU adapter (lavapipe): {e}"),
    }
}

/// Whether there is a GPU adapter to test on: false (with a line saying
/// so) outside CI; under CI (`CI` set) a missing adapter is a failure.
pub fn gpu_available() -> bool {
    match bevy_manifold::render::probe_adapter() {
        Ok(a) => {
            eprintln!("GPU adapter: {a}");
            true
        }
        Err(e) if std::env::var_os("CI").is_none() => {
            eprintln!("SKIPPED: no GPU to test on: {e}");
            false
        }
        Err(e) => panic!("CI must have a GPU adapter (lavapipe): {e}"),
    }
}

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

/// A small deterministic random source (an LCG) for test inputs.
pub struct Rng(pub u64);

impl Rng {
    /// Uniform in [0, 1).
    pub fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A random unit vector.
    pub fn unit(&mut self) -> glam::DVec3 {
        loop {
            let v = glam::DVec3::new(self.next(), self.next(), self.next()) * 2.0 - 1.0;
            let l = v.length();
            if l > 0.05 && l <= 1.0 {
                return v / l;
            }
        }
    }

    /// A point of the cube `[-h, h]^3`.
    pub fn in_box(&mut self, h: f64) -> [f64; 3] {
        [0; 3].map(|_| (self.next() * 2.0 - 1.0) * h)
    }
}
