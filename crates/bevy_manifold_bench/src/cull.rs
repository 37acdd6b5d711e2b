//! `bench cull`: what testing only the objects near a segment's faces
//! saves (`TraceSettings::cull`, `near_faces` in the tracer's step), side
//! by side in one run: the GPU tracer headless and the CPU f32 reference,
//! each with culling off and on, on the same scenes. The images are the
//! same either way (tests/tracer.rs and the GPU tests say so); only the
//! time differs.

use crate::{best_ms, trace_ms};
use bevy_manifold::prelude::*;
use bevy_manifold_gpu::GpuTracer;

/// One scene to time: a space, a scene in it, and how to trace it.
struct Case {
    label: String,
    space: Space,
    scene: Scene,
    settings: TraceSettings,
}

/// The cases: every catalog space with its default scene (a ball, the
/// edges, a light; 60 degrees) at 8 and 16 levels, then the wide view the
/// speed goals were set on (Seifert-Weber, 90 degrees, rays to distance
/// 17, 16 levels) with nothing to hit and with the default scene.
fn cases(width: u32, height: u32) -> Result<Vec<Case>, String> {
    let mut out = Vec::new();
    for name in catalog::NAMES {
        let space = catalog::resolve(name)?;
        for levels in [8, 16] {
            out.push(Case {
                label: format!("{name}, {levels} levels"),
                scene: Scene::default_for(&space),
                space: space.clone(),
                settings: TraceSettings {
                    width,
                    height,
                    levels,
                    ..TraceSettings::default()
                },
            });
        }
    }
    let space = catalog::resolve("seifert-weber")?;
    let full = Scene::default_for(&space);
    let mut ball_only = full.clone();
    ball_only.edge_radius = None;
    let mut edges_only = full.clone();
    edges_only.balls.clear();
    for (what, mut scene) in [
        ("nothing to hit", Scene::empty()),
        ("ball, light", ball_only),
        ("edges, light", edges_only),
        ("edges, ball, light", full),
    ] {
        scene.camera.fov_y_degrees = 90.0;
        out.push(Case {
            label: format!("seifert-weber 90 deg, d 17, 16 levels, {what}"),
            scene,
            space: space.clone(),
            settings: TraceSettings {
                width,
                height,
                levels: 16,
                max_distance: 17.0,
                ..TraceSettings::default()
            },
        });
    }
    Ok(out)
}

/// Prints, per case, GPU and CPU f32 frame times with culling off and on
/// and the ratios, best of `runs`, for the cases whose label holds `only`.
///
/// # Errors
/// No GPU adapter, or a space that does not build.
pub fn run(width: u32, height: u32, runs: u32, only: &str) -> Result<(), String> {
    let mut tracer = GpuTracer::new().map_err(|e| e.to_string())?;
    println!(
        "Culling by near faces, {width}x{height}; GPU on {} (the trace alone by the device's clock, median of {runs}), CPU f32 reference on {} threads (best of {runs}); ms",
        tracer.adapter_name(),
        rayon::current_num_threads()
    );
    println!(
        "{:<58} {:>9} {:>9} {:>7} {:>9} {:>9} {:>7} {:>9}",
        "case", "GPU all", "GPU cull", "saved", "CPU all", "CPU cull", "saved", "GPU/CPU"
    );
    for case in cases(width, height)?.into_iter().filter(|c| c.label.contains(only)) {
        let mut gpu = [0.0; 2];
        let mut cpu = [0.0; 2];
        for (k, cull) in [false, true].into_iter().enumerate() {
            let settings = TraceSettings {
                cull,
                ..case.settings.clone()
            };
            gpu[k] = trace_ms(&mut tracer, &case.space, &case.scene, &settings, runs)?;
            cpu[k] = best_ms(runs, || Ok(render::<f32>(&case.space, &case.scene, &settings)))?;
        }
        println!(
            "{:<58} {:>9.1} {:>9.1} {:>6.2}x {:>9.1} {:>9.1} {:>6.2}x {:>8.2}x",
            case.label,
            gpu[0],
            gpu[1],
            gpu[0] / gpu[1],
            cpu[0],
            cpu[1],
            cpu[0] / cpu[1],
            cpu[1] / gpu[1]
        );
    }
    Ok(())
}
