//! `bench`: measurements anyone can rerun.

use bevy_manifold::prelude::*;
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
}

pub fn run(cmd: &BenchCommand) -> Result<(), String> {
    match *cmd {
        BenchCommand::Tracer { side, runs } => tracer(side.max(1), runs.max(1)),
    }
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
