//! `bench balls`: frame time against the number of traced balls (a swarm
//! of small glowing balls, as the shooter's shots, no edges), GPU headless
//! and CPU f32 reference side by side in one run, each with culling off
//! (every ball tested on every segment) and on (the ball tree:
//! `FlatScene::ball_tree`, `tree_leaves` in the tracer's ball_tree module). The
//! images are the same either way (tests/cull.rs, the GPU tests); only the
//! time differs. The last columns give each culled time over the one-ball
//! culled time of the same space (the goal: 100 balls under 2x one).
//!
//! More balls also stop more rays early (a ray ends on the first ball it
//! hits), so a frame of many balls traces fewer segments. The `seg/ray`
//! column is the mean number of segments per ray (face crossings plus one,
//! from the CPU image) and the `/seg` columns divide that out: the cost of one segment
//! against the one-ball scene's, which is what the ball tests add.

use crate::{best_ms, trace_ms};
use bevy_manifold::prelude::*;
use bevy_manifold_gpu::GpuTracer;
use bevy_manifold_test_support::stress::swarm;

/// Ball counts timed by default: 1 to 254 (the scene's ids stop at 254),
/// with 100, the count of the goal.
pub const COUNTS: [usize; 10] = [1, 2, 4, 8, 16, 32, 64, 100, 128, 254];

/// The swarm of `n` balls in `space`: the default scene's light and
/// camera, no edges, its one ball and `n - 1` more.
fn scene(space: &Space, n: usize) -> Scene {
    let mut scene = swarm(space, n.saturating_sub(1), 11);
    scene.edge_radius = None;
    scene
}

/// Prints, per space and ball count, GPU and CPU f32 frame times with
/// culling off and on, best of `runs`, for the spaces whose name holds
/// `only`, for each of `counts` (ascending, from 1).
///
/// # Errors
/// No GPU adapter, or a space that does not build.
pub fn run(width: u32, height: u32, levels: u32, runs: u32, only: &str, counts: &[usize]) -> Result<(), String> {
    let mut tracer = GpuTracer::new().map_err(|e| e.to_string())?;
    println!(
        "Frame time against traced balls, {width}x{height}, {levels} levels; GPU on {} (the trace alone by the device's clock, median of {runs}), CPU f32 reference on {} threads (best of {runs}); ms",
        tracer.adapter_name(),
        rayon::current_num_threads()
    );
    println!(
        "{:<16} {:>5} {:>9} {:>9} {:>9} {:>9} {:>10} {:>10} {:>7} {:>11} {:>11} {:>11}",
        "space",
        "balls",
        "GPU all",
        "GPU cull",
        "CPU all",
        "CPU cull",
        "GPU cull/1",
        "CPU cull/1",
        "seg/ray",
        "GPU all/seg",
        "GPU cull/seg",
        "CPU cull/seg"
    );
    for name in ["torus", "seifert-weber", "poincare"]
        .into_iter()
        .filter(|n| n.contains(only))
    {
        let space = catalog::resolve(name)?;
        let mut one = [0.0; 2];
        // Per segment: GPU all, GPU cull, CPU cull; of the one-ball scene.
        let mut one_per_segment = [0.0; 3];
        for &n in counts {
            let scene = scene(&space, n);
            let mut gpu = [0.0; 2];
            let mut cpu = [0.0; 2];
            for (k, cull) in [false, true].into_iter().enumerate() {
                let settings = TraceSettings {
                    width,
                    height,
                    levels,
                    cull,
                    ..TraceSettings::default()
                };
                gpu[k] = trace_ms(&mut tracer, &space, &scene, &settings, runs)?;
                cpu[k] = best_ms(runs, || Ok(render::<f32>(&space, &scene, &settings)))?;
            }
            let settings = TraceSettings {
                width,
                height,
                levels,
                ..TraceSettings::default()
            };
            let image = render::<f32>(&space, &scene, &settings);
            let seg =
                image.pixels.iter().map(|p| f64::from(p.levels + 1)).sum::<f64>() / image.pixels.len().max(1) as f64;
            let per_segment = [gpu[0] / seg, gpu[1] / seg, cpu[1] / seg];
            if n == 1 {
                one = [gpu[1], cpu[1]];
                one_per_segment = per_segment;
            }
            println!(
                "{:<16} {:>5} {:>9.1} {:>9.1} {:>9.1} {:>9.1} {:>9.2}x {:>9.2}x {:>7.2} {:>10.2}x {:>10.2}x {:>10.2}x",
                name,
                scene.balls.len(),
                gpu[0],
                gpu[1],
                cpu[0],
                cpu[1],
                gpu[1] / one[0],
                cpu[1] / one[1],
                seg,
                per_segment[0] / one_per_segment[1],
                per_segment[1] / one_per_segment[1],
                per_segment[2] / one_per_segment[2]
            );
        }
    }
    Ok(())
}
