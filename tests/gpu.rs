//! The WGSL tracer on a real wgpu device (lavapipe in CI) against the CPU
//! reference: same scene, same view, pixel by pixel.
//!
//! Without any GPU adapter these tests say so and pass; under CI (`CI` set)
//! a missing adapter is a failure.

use bevy_manifold::prelude::*;
use bevy_manifold::render::GpuTracer;
use bevy_manifold::trace::TraceImage;

fn tracer() -> Option<GpuTracer> {
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

/// Fractions of pixels with the same object and cell id, and with every
/// colour channel within 2/255, of `a` against the reference `b`. A cell id
/// either side flags FAR (a hyperbolic copy beyond the horizon of its
/// precision, where ids are best effort) is not compared; the object is.
fn agreement(a: &TraceImage, b: &TraceImage) -> (f64, f64) {
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

#[test]
fn gpu_and_cpu_agree_in_every_space() {
    let Some(mut gpu) = tracer() else { return };
    for name in catalog::NAMES {
        let space = catalog::by_name(name).expect("catalog");
        for (fog, cells) in [(false, false), (true, true)] {
            let mut scene = Scene::default_for(&space);
            if fog {
                scene.fog = Some(Fog {
                    density: 0.4 / space.inradius(),
                    color: [0.7, 0.75, 0.8],
                });
            }
            let settings = TraceSettings {
                width: 256,
                height: 256,
                max_level: 8,
                cell_colors: cells,
                ..TraceSettings::default()
            };
            let g = gpu
                .render(&space, &scene, &settings)
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            let c32 = render::<f32>(&space, &scene, &settings);
            let c64 = render::<f64>(&space, &scene, &settings);
            let (ids32, col32) = agreement(&g, &c32);
            let (ids64, col64) = agreement(&g, &c64);
            let far = g
                .pixels
                .iter()
                .zip(&c64.pixels)
                .filter(|(p, q)| p.cell.is_far() || q.cell.is_far())
                .count();
            eprintln!(
                "{name:<22} fog {fog:<5} cells {cells:<5}: GPU vs CPU f32: ids {:.3}%, colour {:.3}%; vs CPU f64: ids {:.3}%, colour {:.3}% ({far} far-cell pixels)",
                ids32 * 100.0,
                col32 * 100.0,
                ids64 * 100.0,
                col64 * 100.0
            );
            if std::env::var_os("GPU_DIAG").is_some() {
                let mut obj = 0;
                let mut cell_only = 0;
                let mut hist = [0usize; 10];
                for (p, q) in g.pixels.iter().zip(&c64.pixels) {
                    if p.object != q.object {
                        obj += 1;
                        hist[q.levels.min(9) as usize] += 1;
                    } else if p.cell != q.cell && !q.cell.is_far() && !p.cell.is_far() {
                        cell_only += 1;
                        hist[q.levels.min(9) as usize] += 1;
                    }
                }
                eprintln!("  object differs {obj}, cell only {cell_only}, by reference level {hist:?}");
            }
            assert!(
                ids64 >= 0.995,
                "{name}: only {:.3}% of pixels have the f64 reference's object and cell",
                ids64 * 100.0
            );
            assert!(
                col64 >= 0.99,
                "{name}: only {:.3}% of pixels within 2/255 of the f64 reference",
                col64 * 100.0
            );
        }
    }
}
