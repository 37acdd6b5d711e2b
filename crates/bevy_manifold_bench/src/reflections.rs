//! `bench reflections`: what reflections cost. Per catalog space, the
//! paper's scene with the mirror ball of its Fig. 11 (Suzanne on the
//! camera, the hands, the edges, the mirror at the domain's centre),
//! traced with 0, 1 and 2 reflections a ray (`TraceSettings::reflections`)
//! at 8 levels: the GPU's frame (device clock, median) and the CPU f32's
//! (best), and the ratios over no reflection. The share of pixels whose
//! path reflects at all is printed beside them.

use crate::{best_ms, times_and_ratios, trace_ms};
use bevy_manifold::prelude::*;
use bevy_manifold_core::trace::{FlatScene, PaperOptions, Projection, trace_path, view_ray};
use bevy_manifold_gpu::GpuTracer;

/// The reflections each space is traced with.
const REFLECTIONS: [u32; 3] = [0, 1, 2];

/// Runs the table for the catalog spaces whose name holds `only`.
///
/// # Errors
/// No GPU adapter, or a space that does not build.
pub fn run(width: u32, height: u32, runs: u32, only: &str) -> Result<(), String> {
    let mut tracer = GpuTracer::new().map_err(|e| e.to_string())?;
    println!(
        "Reflections, the paper's scene with the mirror ball (Fig. 11), {width}x{height}, 8 levels; GPU on {} (median of {runs}), CPU f32 on {} threads (best of {runs}); ms",
        tracer.adapter_name(),
        rayon::current_num_threads()
    );
    println!(
        "{:<24} {:>8} {:>9} {:>9} {:>9} {:>7} {:>7} {:>9} {:>9} {:>9} {:>7} {:>7}",
        "space", "reflect", "GPU 0", "1", "2", "ratio", "ratio", "CPU 0", "1", "2", "ratio", "ratio"
    );
    let options = PaperOptions {
        mirror: true,
        ..PaperOptions::default()
    };
    let names: Vec<&str> = catalog::NAMES.iter().copied().filter(|n| n.contains(only)).collect();
    for name in &names {
        let space = catalog::resolve(name)?;
        let scene = Scene::paper(&space, &options);
        let mut gpu = [0.0; 3];
        let mut cpu = [0.0; 3];
        for (k, &reflections) in REFLECTIONS.iter().enumerate() {
            let settings = TraceSettings {
                width,
                height,
                levels: 8,
                reflections,
                ..TraceSettings::default()
            };
            gpu[k] = trace_ms(&mut tracer, &space, &scene, &settings, runs)?;
            cpu[k] = best_ms(runs, || Ok(render::<f32>(&space, &scene, &settings)))?;
        }
        println!(
            "{name:<24} {:>7.1}% {} {}",
            100.0 * reflecting_share(&space, &scene, width, height),
            times_and_ratios(gpu, 2),
            times_and_ratios(cpu, 1)
        );
    }
    Ok(())
}

/// The share of pixels whose path takes a reflection (its first leg ends
/// on a surface with a material), from the CPU f32 tracer's legs.
fn reflecting_share(space: &Space, scene: &Scene, width: u32, height: u32) -> f64 {
    let settings = TraceSettings {
        width,
        height,
        levels: 8,
        reflections: 1,
        ..TraceSettings::default()
    };
    let flat = FlatScene::<f32>::new(space, scene);
    let mut reflecting = 0usize;
    for j in 0..height {
        for i in 0..width {
            let ray = view_ray(&flat, Projection::Perspective, i, j, width, height);
            let mut legs = 0;
            trace_path(space, &flat, ray, &settings, &mut |_| {}, &mut |_, _| legs += 1);
            reflecting += usize::from(legs > 1);
        }
    }
    reflecting as f64 / (f64::from(width) * f64::from(height))
}
