//! `bench instances`: frame time against the number of mesh instances in
//! a level of props (`stress::props`: instances of a cube, an octahedron
//! and a tetrahedron at random places, turns and sizes, with the default
//! scene's edges, ball and light), GPU headless and CPU f32 side by side
//! in one run: with culling, where each face group of eight instances or
//! more is walked by its instance tree (`FlatScene::instance_trees`), and
//! without, every instance tested on every segment. The images are the
//! same either way (tests/instances.rs, the GPU's tests/meshes.rs); only
//! the time differs.
//!
//! The untreed times stop at 1,000 instances: past that the CPU's take
//! minutes, and lavapipe ends an invocation's loops after 65,535
//! iterations between them, which testing every one of thousands of
//! instances on a few segments passes, so its time would be of a cut
//! trace. More instances also stop rays sooner; `seg/ray` is the mean
//! segments per ray (face crossings plus one, from the CPU image), and
//! `GPU tree/seg` the GPU time per segment over the smallest count's: what
//! a segment pays for the walk down a deeper tree and for shading the
//! hit it now ends on.
//!
//! The last line is the goal's ratio: the culled GPU frame at 10,000
//! instances over the one at 100, the largest over the spaces timed.

use crate::{best_ms, trace_ms};
use bevy_manifold::prelude::*;
use bevy_manifold_gpu::GpuTracer;
use bevy_manifold_test_support::stress::props;

/// Instance counts timed by default.
pub const COUNTS: [usize; 5] = [100, 300, 1_000, 3_000, 10_000];

/// Most instances timed without culling (see the module's notes).
const MAX_UNCULLED: usize = 1_000;

/// Each prop's bounding radius, as a share of the domain's inradius (0.7
/// to 1.3 times it).
const SIZE: f64 = 0.02;

/// Prints, per space and count, GPU and CPU f32 frame times without and
/// with culling, best (CPU) or median (GPU) of `runs`, for the spaces
/// whose name holds `only`; then the ratio of the culled GPU frame at
/// the largest count over the one at the smallest.
///
/// # Errors
/// No GPU adapter, or a space that does not build.
pub fn run(width: u32, height: u32, levels: u32, runs: u32, only: &str, counts: &[usize]) -> Result<(), String> {
    let mut tracer = GpuTracer::new().map_err(|e| e.to_string())?;
    println!(
        "Frame time against mesh instances (props of bounding radius {SIZE} of the inradius), {width}x{height}, {levels} levels; GPU on {} (the trace alone by the device's clock, median of {runs}), CPU f32 reference on {} threads (best of {runs}); ms; every instance tested only up to {MAX_UNCULLED}",
        tracer.adapter_name(),
        rayon::current_num_threads()
    );
    let (lo, hi) = (counts[0], counts[counts.len() - 1]);
    println!(
        "{:<16} {:>9} {:>9} {:>9} {:>9} {:>9} {:>11} {:>11} {:>7} {:>12}",
        "space",
        "instances",
        "GPU all",
        "GPU tree",
        "CPU all",
        "CPU tree",
        format!("GPU tree/{lo}"),
        format!("CPU tree/{lo}"),
        "seg/ray",
        "GPU tree/seg"
    );
    let mut worst: Option<(f64, String)> = None;
    let mut ratios = Vec::new();
    for name in ["torus", "seifert-weber", "poincare"]
        .into_iter()
        .filter(|n| n.contains(only))
    {
        let space = catalog::resolve(name)?;
        // The smallest count's GPU and CPU times and GPU time per segment.
        let mut first = [0.0; 3];
        for &n in counts {
            let scene = props(&space, n, SIZE, 17);
            let settings = |cull| TraceSettings {
                width,
                height,
                levels,
                cull,
                ..TraceSettings::default()
            };
            let gpu_tree = trace_ms(&mut tracer, &space, &scene, &settings(true), runs)?;
            let cpu_tree = best_ms(runs, || Ok(render::<f32>(&space, &scene, &settings(true))))?;
            let (gpu_all, cpu_all) = if n <= MAX_UNCULLED {
                (
                    format!("{:.1}", trace_ms(&mut tracer, &space, &scene, &settings(false), runs)?),
                    format!(
                        "{:.1}",
                        best_ms(runs, || Ok(render::<f32>(&space, &scene, &settings(false))))?
                    ),
                )
            } else {
                ("-".into(), "-".into())
            };
            let image = render::<f32>(&space, &scene, &settings(true));
            let seg =
                image.pixels.iter().map(|p| f64::from(p.levels + 1)).sum::<f64>() / image.pixels.len().max(1) as f64;
            if n == lo {
                first = [gpu_tree, cpu_tree, gpu_tree / seg];
            }
            println!(
                "{:<16} {:>9} {:>9} {:>9.1} {:>9} {:>9.1} {:>10.2}x {:>10.2}x {:>7.2} {:>11.2}x",
                name,
                n,
                gpu_all,
                gpu_tree,
                cpu_all,
                cpu_tree,
                gpu_tree / first[0],
                cpu_tree / first[1],
                seg,
                gpu_tree / seg / first[2]
            );
            if n == hi && hi != lo {
                let r = gpu_tree / first[0];
                ratios.push(format!("{name} {r:.2}x"));
                if worst.as_ref().is_none_or(|(w, _)| r > *w) {
                    worst = Some((r, name.to_string()));
                }
            }
        }
    }
    if let Some((r, _)) = worst {
        println!("{hi}/{lo}: {r:.2} x (GPU tree, the largest of: {})", ratios.join(", "));
    }
    Ok(())
}
