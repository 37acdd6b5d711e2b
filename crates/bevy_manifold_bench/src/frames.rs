//! `bench tracer` and `bench gpu`: frame times of the CPU reference and of
//! the GPU tracer run headless.

use crate::{best_ms, fog_for};
use bevy_manifold::prelude::*;
use bevy_manifold_gpu::{GpuTracer, TraceDefs};
use std::time::Instant;

/// GPU frame time (trace and readback) per space, levels and fog, and the
/// same with the generic shader (every def on) to show what specialising
/// saves.
pub fn gpu(width: u32, height: u32, runs: u32) -> Result<(), String> {
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
                scene.fog = Some(fog_for(&space));
            }
            for levels in [1, 3, 8, 16] {
                let settings = TraceSettings {
                    width,
                    height,
                    levels,
                    ..TraceSettings::default()
                };
                let mut time = |defs: TraceDefs| {
                    best_ms(runs, || {
                        tracer
                            .render_with(&space, &scene, &settings, defs)
                            .map_err(|e| e.to_string())
                    })
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

pub fn tracer(side: u32, runs: u32) -> Result<(), String> {
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
        // Exact ids: the table of cells around the camera grown first, as
        // the GPU's packing grows it in an app, so rays step through it by
        // index (`FlatScene::centred_table`) and multiply exactly only past it.
        if let bevy_manifold::space::cells::CellScheme::Exact(exact) = space.cells() {
            exact.table();
        }
        for levels in [4, 16] {
            let settings = TraceSettings {
                width: side,
                height: side,
                levels,
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
