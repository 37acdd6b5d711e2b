//! `bench paths`: the path tracer's run time against its error. Per
//! catalog space, the paper's scene (its light at the eye given a radius
//! of 0.15 inradii, shadows on) path traced at 6 bounces: a reference of `reference` GPU samples (seed 1),
//! then the mean of N = 1, 2, 4, ... samples (seed 2), GPU and CPU f32
//! (the same paths: their random numbers hash the seed, the sample and
//! the pixel);
//! the error is the relative RMS of the mean against the reference
//! (over every pixel and channel), the time N times the per-sample time
//! (GPU: the device clock's median; CPU: the best). Both follow the same
//! paths, so at equal N their errors agree (up to f32 paths that part)
//! and the ratio of times is the speed-up at equal error. Writes
//! `paths.csv` and `paths.png`.

use crate::plot::{PALETTE, Panel, Series, draw, pareto_front};
use crate::{best_ms, trace_ms};
use bevy_manifold::prelude::*;
use bevy_manifold_gpu::GpuTracer;
use std::fmt::Write as _;
use std::path::Path;

/// The bounces of every path.
const DEPTH: u32 = 6;

/// The mean colour of `samples` path samples of `seed`.
fn mean(
    trace: &mut dyn FnMut(&TraceSettings) -> Result<TraceImage, String>,
    settings: &TraceSettings,
    seed: u32,
    samples: u32,
) -> Result<Vec<[f64; 3]>, String> {
    let mut sum = Vec::new();
    for k in 0..samples {
        let s = TraceSettings {
            seed,
            light_sample: k,
            ..settings.clone()
        };
        let img = trace(&s)?;
        if sum.is_empty() {
            sum = vec![[0.0; 3]; img.pixels.len()];
        }
        for (a, p) in sum.iter_mut().zip(&img.pixels) {
            for (a, c) in a.iter_mut().zip(p.color) {
                *a += f64::from(c);
            }
        }
    }
    Ok(sum.iter().map(|a| a.map(|v| v / f64::from(samples))).collect())
}

/// Relative RMS error of `x` against `reference`.
fn rel_rms(x: &[[f64; 3]], reference: &[[f64; 3]]) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for (a, r) in x.iter().zip(reference) {
        for c in 0..3 {
            num += (a[c] - r[c]).powi(2);
            den += r[c].powi(2);
        }
    }
    (num / den.max(1e-30)).sqrt()
}

/// Runs the table and plot for the catalog spaces whose name holds
/// `only`, writing into `out`.
///
/// # Errors
/// No GPU adapter, a space that does not build, or a file not written.
pub fn run(width: u32, height: u32, reference: u32, max_samples: u32, only: &str, out: &Path) -> Result<(), String> {
    let mut tracer = GpuTracer::new().map_err(|e| e.to_string())?;
    println!(
        "Path tracing, the paper's scene (a light of radius 0.15 inradii, shadows on), {width}x{height}, 8 levels, {DEPTH} bounces; reference {reference} GPU samples; GPU on {}, CPU f32 on {} threads; relative RMS error against ms",
        tracer.adapter_name(),
        rayon::current_num_threads()
    );
    println!(
        "{:<24} {:>7} {:>10} {:>10} {:>10} {:>10} {:>8}",
        "space", "samples", "GPU ms", "GPU error", "CPU ms", "CPU error", "CPU/GPU"
    );
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut csv = String::from("space,samples,gpu_ms,gpu_error,cpu_ms,cpu_error\n");
    let mut series = Vec::new();
    let mut all = Vec::new();
    let names: Vec<&str> = catalog::NAMES.iter().copied().filter(|n| n.contains(only)).collect();
    for (k, name) in names.iter().enumerate() {
        let space = catalog::resolve(name)?;
        let mut scene = Scene::paper_default(&space);
        scene.lighting.shadows = true;
        // A light of finite size: a point light's 1/d^2 near a bounce
        // gives the estimate an unbounded variance.
        for l in &mut scene.lights {
            l.radius = 0.15 * space.inradius();
        }
        let settings = TraceSettings {
            width,
            height,
            levels: 8,
            path_depth: DEPTH,
            ..TraceSettings::default()
        };
        let gpu_ms = trace_ms(&mut tracer, &space, &scene, &settings, 3)?;
        let cpu_ms = best_ms(2, || Ok(render::<f32>(&space, &scene, &settings)))?;
        let mut gpu_trace = |s: &TraceSettings| tracer.render(&space, &scene, s).map_err(|e| e.to_string());
        let truth = mean(&mut gpu_trace, &settings, 1, reference)?;
        let (mut gpu_pts, mut cpu_pts) = (Vec::new(), Vec::new());
        let mut n = 1;
        while n <= max_samples {
            let g = rel_rms(&mean(&mut gpu_trace, &settings, 2, n)?, &truth);
            let mut cpu_trace = |s: &TraceSettings| Ok(render::<f32>(&space, &scene, s));
            let c = rel_rms(&mean(&mut cpu_trace, &settings, 2, n)?, &truth);
            let (gt, ct) = (gpu_ms * f64::from(n), cpu_ms * f64::from(n));
            println!(
                "{name:<24} {n:>7} {gt:>10.1} {g:>10.4} {ct:>10.1} {c:>10.4} {:>7.2}x",
                ct / gt
            );
            let _ = writeln!(csv, "{name},{n},{gt},{g},{ct},{c}");
            gpu_pts.push((gt, g));
            cpu_pts.push((ct, c));
            n *= 2;
        }
        all.extend(gpu_pts.iter().chain(&cpu_pts).copied());
        let color = PALETTE[k % PALETTE.len()];
        series.push(Series {
            label: format!("{name} GPU"),
            color,
            points: gpu_pts,
            line: true,
        });
        series.push(Series {
            label: format!("{name} CPU"),
            color: (color.0 / 2, color.1 / 2, color.2 / 2),
            points: cpu_pts,
            line: true,
        });
    }
    let csv_path = out.join("paths.csv");
    std::fs::write(&csv_path, csv).map_err(|e| format!("{}: {e}", csv_path.display()))?;
    let png = out.join("paths.png");
    let panels = [Panel {
        title: "Path tracing: time against error".into(),
        x: "ms for the samples".into(),
        y: "relative RMS error against the reference".into(),
        series,
        front: pareto_front(&all),
    }];
    match draw(&png, &panels, 1, 1e-4) {
        Ok(()) => println!("\nwrote {} and {}", csv_path.display(), png.display()),
        Err(e) => println!("\nwrote {} ({e})", csv_path.display()),
    }
    Ok(())
}
