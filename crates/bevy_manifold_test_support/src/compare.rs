//! Comparing two traced images pixel by pixel.

use bevy_manifold_core::trace::TraceImage;

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
