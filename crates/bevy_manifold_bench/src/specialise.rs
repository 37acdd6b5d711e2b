//! `bench specialise`: what skipping saves. Frame time with the pipeline
//! specialised to the scene against the generic pipeline (every def on),
//! per space, with and without fog, per-cell shading and meshes; then, in
//! the render pass, the cost of uploads with change
//! detection (a still scene uploads nothing) against re-uploading every
//! buffer every frame.

use crate::{best_ms, fog_for};
use bevy_manifold::prelude::*;
use bevy_manifold_gpu::{GpuTracer, TraceDefs};
use clap::Args;

/// Arguments of `bench specialise`.
#[derive(Args, Clone, Debug)]
pub struct SpecialiseArgs {
    /// Image width.
    #[arg(long, default_value_t = 640)]
    width: u32,
    /// Image height.
    #[arg(long, default_value_t = 360)]
    height: u32,
    /// Most transports per ray.
    #[arg(long, default_value_t = 8)]
    levels: u32,
    /// Timed runs per setting; the best counts.
    #[arg(long, default_value_t = 2)]
    runs: u32,
}

pub fn run(args: &SpecialiseArgs) -> Result<(), String> {
    let mut gpu = GpuTracer::new().map_err(|e| e.to_string())?;
    let runs = args.runs.max(1);
    println!(
        "specialised against generic shader, default scene, {}x{}, {} levels, trace + readback, best of {runs}, on {}",
        args.width,
        args.height,
        args.levels,
        gpu.adapter_name()
    );
    println!(
        "{:<22} {:>5} {:>6} {:>7} {:>14} {:>11} {:>7}  defs",
        "space", "fog", "cells", "meshes", "specialised ms", "generic ms", "ratio"
    );
    let settings = |cells| TraceSettings {
        width: args.width.max(1),
        height: args.height.max(1),
        levels: args.levels,
        cell_colors: cells,
        ..TraceSettings::default()
    };
    let mut ratios = Vec::new();
    for name in catalog::NAMES {
        let space = catalog::by_name(name).ok_or("catalog")?;
        for (fog, cells, meshes) in [
            (false, false, false),
            (true, false, false),
            (false, true, false),
            (false, false, true),
            (true, true, true),
        ] {
            let mut scene = Scene::default_for(&space);
            scene.fog = fog.then(|| fog_for(&space));
            if meshes {
                // The paper's Suzanne and hands beside the ball.
                scene.meshes = Scene::paper_default(&space).meshes;
            }
            let settings = settings(cells);
            let defs = TraceDefs::for_scene(&space, &scene, cells);
            let mut time = |defs: TraceDefs| {
                best_ms(runs, || {
                    gpu.render_with(&space, &scene, &settings, defs)
                        .map_err(|e| e.to_string())
                })
            };
            let special = time(defs)?;
            let generic = time(TraceDefs::generic(space.geometry()))?;
            ratios.push(generic / special);
            let yes = |b: bool| if b { "on" } else { "off" };
            println!(
                "{name:<22} {:>5} {:>6} {:>7} {special:>14.1} {generic:>11.1} {:>7.2}  {}",
                yes(fog),
                yes(cells),
                yes(meshes),
                generic / special,
                defs.names().join(" ")
            );
        }
    }
    let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
    let (lo, hi) = ratios
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), r| (lo.min(*r), hi.max(*r)));
    println!("generic / specialised: mean {mean:.2}, range {lo:.2} to {hi:.2}");
    uploads(args, runs)
}

/// The pass in a headless Bevy app, a still camera in a still scene: frame
/// time and bytes uploaded per frame with change detection, and with every
/// view's buffers dropped before each frame (everything uploaded again).
fn uploads(args: &SpecialiseArgs, runs: u32) -> Result<(), String> {
    use crate::pass::frame_ms;
    use bevy::prelude::*;
    use bevy::render::{Render, RenderApp, RenderSystems};
    use bevy_manifold::render::{ManifoldBufferCache, ManifoldUploads, offscreen};
    fn drop_buffers(mut cache: ResMut<ManifoldBufferCache>) {
        cache.invalidate();
    }
    println!(
        "\nuploads in the render pass, {}x{}, {} levels, still camera and scene (best of {runs})",
        args.width, args.height, args.levels
    );
    println!(
        "{:<22} {:>20} {:>20} {:>9}",
        "space", "on change: ms, B/fr", "every frame: ms, B/fr", "ratio"
    );
    for name in catalog::NAMES {
        let space = catalog::by_name(name).ok_or("catalog")?;
        let scene = Scene::default_for(&space);
        let measure = |every_frame: bool| -> Result<(f64, f64), String> {
            let mut app = offscreen::app(true);
            if every_frame {
                app.sub_app_mut(RenderApp).add_systems(
                    Render,
                    drop_buffers
                        .in_set(RenderSystems::PrepareResources)
                        .before(bevy_manifold::render::ManifoldPrepareSystems::Buffers),
                );
            }
            let image = offscreen::target(&mut app, args.width, args.height);
            let camera = ManifoldCamera {
                levels: args.levels,
                ..default()
            };
            offscreen::spawn_view(&mut app, &space, &scene, &image, camera);
            let bytes = |app: &App| app.sub_app(RenderApp).world().resource::<ManifoldUploads>().bytes;
            offscreen::wait_for_pipelines(&mut app)?;
            let before = bytes(&app);
            for _ in 0..10 {
                app.update();
            }
            let per_frame = (bytes(&app) - before) as f64 / 10.0;
            Ok((frame_ms(&mut app, &image, runs)?, per_frame))
        };
        let (cached, cached_bytes) = measure(false)?;
        let (always, always_bytes) = measure(true)?;
        println!(
            "{name:<22} {:>20} {:>20} {:>9.3}",
            format!("{cached:.1}, {cached_bytes:.0}"),
            format!("{always:.1}, {always_bytes:.0}"),
            always / cached
        );
    }
    Ok(())
}
