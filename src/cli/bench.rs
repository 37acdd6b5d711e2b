//! `bench`: measurements anyone can rerun.

use bevy_manifold::prelude::*;
use bevy_manifold::render::{GpuTracer, TraceDefs};
use clap::Subcommand;
use std::time::Instant;

#[derive(Subcommand)]
pub enum BenchCommand {
    /// CPU tracer throughput (rays/s) per space at 4 and 16 levels, f32 and f64.
    Tracer {
        /// Image side in pixels (side x side rays per run).
        #[arg(long, default_value_t = 256)]
        side: u32,
        /// Runs per setting; the best is reported.
        #[arg(long, default_value_t = 3)]
        runs: u32,
    },
    /// GPU tracer frame time per space, levels 1/3/8/16, fog off/on,
    /// specialised against the generic shader.
    Gpu {
        /// Image width.
        #[arg(long, default_value_t = 640)]
        width: u32,
        /// Image height.
        #[arg(long, default_value_t = 360)]
        height: u32,
        /// Runs per setting; the best is reported.
        #[arg(long, default_value_t = 3)]
        runs: u32,
    },
}

pub fn run(cmd: &BenchCommand) -> Result<(), String> {
    match *cmd {
        BenchCommand::Tracer { side, runs } => tracer(side.max(1), runs.max(1)),
        BenchCommand::Gpu { width, height, runs } => gpu(width.max(1), height.max(1), runs.max(1)),
    }
}

/// GPU frame time (trace and readback) per space, levels and fog, and the
/// same with the generic shader (every def on) to show what specialising
/// saves.
fn gpu(width: u32, height: u32, runs: u32) -> Result<(), String> {
    let mut tracer = GpuTracer::new().map_err(|e| e.to_string())?;
    println!(
        "GPU tracer, default scene, {width}x{height}, trace + readback, best of {runs}, on {}",
        tracer.adapter_name()
    );
    println!(
        "{:<22} {:>6} {:>5} {:>14} {:>14} {:>8}",
        "space", "levels", "fog", "specialised ms", "generic ms", "ratio"
    );
    for name in catalog::NAMES {
        let space = catalog::by_name(name).ok_or_else(|| format!("no space {name}"))?;
        for fog in [false, true] {
            let mut scene = Scene::default_for(&space);
            if fog {
                scene.fog = Some(Fog {
                    density: 0.4 / space.inradius(),
                    color: [0.7, 0.75, 0.8],
                });
            }
            for levels in [1, 3, 8, 16] {
                let settings = TraceSettings {
                    width,
                    height,
                    max_level: levels,
                    ..TraceSettings::default()
                };
                let mut time = |defs: TraceDefs| -> Result<f64, String> {
                    // The first run compiles the pipeline; not timed.
                    tracer
                        .render_with(&space, &scene, &settings, defs)
                        .map_err(|e| e.to_string())?;
                    let mut best = f64::INFINITY;
                    for _ in 0..runs {
                        let t = Instant::now();
                        let img = tracer
                            .render_with(&space, &scene, &settings, defs)
                            .map_err(|e| e.to_string())?;
                        std::hint::black_box(&img);
                        best = best.min(t.elapsed().as_secs_f64());
                    }
                    Ok(best * 1e3)
                };
                let special = time(TraceDefs::for_scene(&space, &scene, false))?;
                let generic = time(TraceDefs::generic(space.geometry()))?;
                println!(
                    "{name:<22} {levels:>6} {:>5} {special:>14.1} {generic:>14.1} {:>8.2}",
                    if fog { "on" } else { "off" },
                    generic / special
                );
            }
        }
    }
    Ok(())
}

fn tracer(side: u32, runs: u32) -> Result<(), String> {
    println!(
        "CPU reference tracer, default scene, {side}x{side} rays, best of {runs}, {} threads",
        rayon::current_num_threads()
    );
    println!(
        "{:<22} {:>6} {:>6} {:>14} {:>12}",
        "space", "levels", "float", "rays/s", "ms/frame"
    );
    for name in catalog::NAMES {
        let space = catalog::by_name(name).ok_or_else(|| format!("no space {name}"))?;
        let scene = Scene::default_for(&space);
        for levels in [4, 16] {
            let settings = TraceSettings {
                width: side,
                height: side,
                max_level: levels,
                ..TraceSettings::default()
            };
            for f in ["f32", "f64"] {
                let mut best = f64::INFINITY;
                for _ in 0..runs {
                    let t = Instant::now();
                    let img = if f == "f32" {
                        render::<f32>(&space, &scene, &settings)
                    } else {
                        render::<f64>(&space, &scene, &settings)
                    };
                    std::hint::black_box(&img);
                    best = best.min(t.elapsed().as_secs_f64());
                }
                let rays = f64::from(side * side);
                println!(
                    "{name:<22} {levels:>6} {f:>6} {:>14.0} {:>12.1}",
                    rays / best,
                    best * 1e3
                );
            }
        }
    }
    Ok(())
}
