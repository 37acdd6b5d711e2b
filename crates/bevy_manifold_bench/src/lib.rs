//! The benchmarks behind `BENCHMARKS.md`, run as `bevy_manifold bench …`
//! (`cargo run --release -- bench gpu`): measurements anyone can rerun,
//! ratios measured side by side in one run. Unpublished.

mod aa;
mod accuracy;
mod balls;
mod cells;
mod compare;
mod cull;
mod faces;
mod frames;
mod instances;
mod lights;
mod meshes;
mod pass;
mod paths;
mod plot;
mod product;
mod reflections;
mod report;
mod skinning;
mod specialise;
mod stability;
mod stereo;

use bevy_manifold::prelude::*;
use clap::Subcommand;
use std::time::Instant;

/// The `bench` subcommands.
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
    /// The render pass's path against the compute path on the same device
    /// (8 levels, headless), then frame times of the pass in a headless
    /// Bevy app at 640x360 and 1280x720.
    Pass {
        /// Runs per setting; the best is reported.
        #[arg(long, default_value_t = 3)]
        runs: u32,
    },
    /// Run time against error: GPU frame time and image error against a
    /// CPU f64 reference for levels 1-32, renormalisation and the fog early
    /// stop on/off, per space; CSV, table and a PNG plot with the Pareto
    /// front.
    Accuracy(accuracy::AccuracyArgs),
    /// The long stability soak: drift curves over up to 10^4 transports,
    /// far travel through 10^8 faces, degenerate rays; CSV and PNG.
    Stability(stability::StabilityArgs),
    /// Frame time against triangle count (Suzanne subdivided to 35k and
    /// 394k triangles) at 3 and 8 levels, and BVH build times.
    Meshes {
        /// Image width.
        #[arg(long, default_value_t = 640)]
        width: u32,
        /// Image height.
        #[arg(long, default_value_t = 360)]
        height: u32,
        /// Runs per setting; the best is reported.
        #[arg(long, default_value_t = 2)]
        runs: u32,
    },
    /// What skipping saves: specialised against generic pipelines with and
    /// without fog and per-cell shading, and uploads with and without
    /// change detection in the render pass.
    Specialise(specialise::SpecialiseArgs),
    /// What exact cell ids cost: ns per face crossing, the table's growth
    /// and recentring, GPU frame time with the table against hashed ids,
    /// and the share of hit pixels the table covers at 8 and 16 levels.
    Cells {
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
    /// Frame time against the domain's face count (4 to 56 faces), GPU and
    /// CPU f32, with nothing to hit and with the default scene, 8 levels.
    Faces {
        /// Image width.
        #[arg(long, default_value_t = 640)]
        width: u32,
        /// Image height.
        #[arg(long, default_value_t = 360)]
        height: u32,
        /// Runs per setting; the best is reported.
        #[arg(long, default_value_t = 3)]
        runs: u32,
        /// Only the spaces whose name holds this (`seifert-weber/`: the
        /// 12- and 52-face domains of one manifold).
        #[arg(long, default_value = "")]
        only: String,
    },
    /// What culling by near faces saves: GPU and CPU f32, each with
    /// culling off and on, per catalog space at 8 and 16 levels, and the
    /// wide Seifert-Weber view of the speed goals (90 degrees, 16 levels).
    Cull {
        /// Image width.
        #[arg(long, default_value_t = 640)]
        width: u32,
        /// Image height.
        #[arg(long, default_value_t = 360)]
        height: u32,
        /// Runs per setting; the best is reported.
        #[arg(long, default_value_t = 3)]
        runs: u32,
        /// Only the cases whose label holds this.
        #[arg(long, default_value = "")]
        only: String,
    },
    /// Light images and shadows: frame time of the paper's scene per
    /// catalog space with each light's copy in the domain, its images,
    /// and its images and shadows; and run time against the error of the
    /// light sum (budgets 1 to 256) against brute force per space.
    Lights {
        /// Image width.
        #[arg(long, default_value_t = 640)]
        width: u32,
        /// Image height.
        #[arg(long, default_value_t = 360)]
        height: u32,
        /// Runs per setting; the median (GPU) and best (CPU) are reported.
        #[arg(long, default_value_t = 3)]
        runs: u32,
        /// Only the spaces whose name holds this.
        #[arg(long, default_value = "")]
        only: String,
        /// Folder for `lights.csv` and `lights.png`.
        #[arg(long, default_value = "bench-out")]
        out: std::path::PathBuf,
    },
    /// The path tracer's run time against its error per catalog space:
    /// the mean of 1, 2, 4, ... samples against a reference of many,
    /// GPU and CPU f32. Writes `paths.csv` and `paths.png`.
    Paths {
        /// Image width.
        #[arg(long, default_value_t = 160)]
        width: u32,
        /// Image height.
        #[arg(long, default_value_t = 90)]
        height: u32,
        /// GPU samples of the reference.
        #[arg(long, default_value_t = 512)]
        reference: u32,
        /// The most samples of a mean (doubling from 1).
        #[arg(long, default_value_t = 32)]
        samples: u32,
        /// Only the spaces whose name holds this.
        #[arg(long, default_value = "")]
        only: String,
        /// Folder for `paths.csv` and `paths.png`.
        #[arg(long, default_value = "bench-out")]
        out: std::path::PathBuf,
    },
    /// Frame time of the paper's scene with the mirror ball (Fig. 11)
    /// with 0, 1 and 2 reflections a ray, GPU and CPU f32, per catalog
    /// space.
    Reflections {
        /// Image width.
        #[arg(long, default_value_t = 640)]
        width: u32,
        /// Image height.
        #[arg(long, default_value_t = 360)]
        height: u32,
        /// Runs per setting; the median (GPU) and best (CPU) are reported.
        #[arg(long, default_value_t = 3)]
        runs: u32,
        /// Only the spaces whose name holds this.
        #[arg(long, default_value = "")]
        only: String,
    },
    /// Frame time against the number of traced balls (1 to 254, a swarm
    /// of small balls), GPU and CPU f32, culling off and on, in the torus,
    /// Seifert-Weber and the Poincare sphere.
    Balls {
        /// Image width.
        #[arg(long, default_value_t = 320)]
        width: u32,
        /// Image height.
        #[arg(long, default_value_t = 180)]
        height: u32,
        /// Most transports per ray.
        #[arg(long, default_value_t = 8)]
        levels: u32,
        /// Runs per setting; the best is reported.
        #[arg(long, default_value_t = 3)]
        runs: u32,
        /// Only the spaces whose name holds this.
        #[arg(long, default_value = "")]
        only: String,
        /// Only these ball counts (comma-separated; each from 1 to 254),
        /// instead of 1 to 254 in doublings and 100. The ratios are over
        /// the one-ball scene, which is always timed.
        #[arg(long, value_delimiter = ',')]
        counts: Vec<usize>,
    },
    /// Frame time against the number of mesh instances (100 to 10,000
    /// props of three meshes), GPU and CPU f32, with the instance trees
    /// and with every instance tested, in the torus, Seifert-Weber and the
    /// Poincare sphere; the last line is the 10,000/100 ratio.
    Instances {
        /// Image width.
        #[arg(long, default_value_t = 320)]
        width: u32,
        /// Image height.
        #[arg(long, default_value_t = 180)]
        height: u32,
        /// Most transports per ray.
        #[arg(long, default_value_t = 8)]
        levels: u32,
        /// Runs per setting; the median (GPU) and best (CPU) are reported.
        #[arg(long, default_value_t = 3)]
        runs: u32,
        /// Only the spaces whose name holds this.
        #[arg(long, default_value = "")]
        only: String,
        /// Only these instance counts (comma-separated, each from 1 to
        /// 100,000), instead of 100 to 10,000; the ratios are over the
        /// smallest.
        #[arg(long, value_delimiter = ',')]
        counts: Vec<usize>,
    },
    /// The product spaces (H2xR, S2xR) against Seifert-Weber: GPU frame
    /// time of the product tracer over the main tracer's at the same size
    /// and levels, and the CPU f64 reference's.
    Product {
        /// Image width.
        #[arg(long, default_value_t = 320)]
        width: u32,
        /// Image height.
        #[arg(long, default_value_t = 180)]
        height: u32,
        /// Most faces a ray crosses.
        #[arg(long, default_value_t = 8)]
        levels: u32,
        /// Runs per setting; the median (GPU) and best (CPU) are reported.
        #[arg(long, default_value_t = 3)]
        runs: u32,
    },
    /// What a skinned mesh's new pose costs per triangle: skinning,
    /// refitting the BVH and building a new one, on meshes of 8,192 to
    /// 51,200 triangles (CPU).
    Skinning {
        /// Runs per size; the best is reported.
        #[arg(long, default_value_t = 3)]
        runs: u32,
    },
    /// Anti-aliasing by accumulation: PSNR of 1, 4, 8, 16 accumulated
    /// samples against a 16-samples-per-pixel reference per space at 8
    /// and 16 levels, and frame-to-frame flicker moving slowly (CPU f64).
    Aa {
        /// Image width.
        #[arg(long, default_value_t = 160)]
        width: u32,
        /// Image height.
        #[arg(long, default_value_t = 90)]
        height: u32,
        /// Frames of slow motion for the flicker.
        #[arg(long, default_value_t = 8)]
        frames: u32,
    },
    /// The CPU reference, the GPU headless and the pass in a headless Bevy
    /// app, interleaved on the same scenes: frame time against levels,
    /// faces, balls and triangles, with ratios; CSV and PNG.
    Compare(compare::CompareArgs),
    /// Every area's figures in one run, written as `BENCHMARKS.md`: each
    /// area's benchmark run as `bench <area> …`, its table quoted under
    /// its method.
    Report {
        /// The file written.
        #[arg(long, default_value_os_t = report::default_out())]
        out: std::path::PathBuf,
        /// Only this area (its `bench` command's name: `tracer`, `gpu`, …).
        #[arg(long, default_value = "")]
        only: String,
    },
    /// Stereo, as a headset asks: two eyes with off-centre frusta, each
    /// placed along a geodesic, at 2x1512x1680 times each render scale,
    /// per catalog space (the paper's scene) at 1, 3 and 8 levels, timed
    /// on the device; cone tracing and the whole headless render at the
    /// first scale; the CPU reference's rays/s at the last.
    Stereo {
        /// Per-eye render scales (1: 1512x1680 an eye).
        #[arg(long, value_delimiter = ',', default_value = "1,0.5,0.25")]
        scales: Vec<f64>,
        /// Traces per setting; the median is reported.
        #[arg(long, default_value_t = 3)]
        runs: u32,
        /// Only the spaces whose name holds this.
        #[arg(long, default_value = "")]
        only: String,
    },
}

/// Runs one benchmark, printing its table (and writing its files).
///
/// # Errors
/// When the GPU or a file it writes fails, with the reason.
pub fn run(cmd: &BenchCommand) -> Result<(), String> {
    match *cmd {
        BenchCommand::Tracer { side, runs } => frames::tracer(side.max(1), runs.max(1)),
        BenchCommand::Gpu { width, height, runs } => frames::gpu(width.max(1), height.max(1), runs.max(1)),
        BenchCommand::Pass { runs } => pass::pass(runs.max(1)),
        BenchCommand::Accuracy(ref args) => accuracy::run(args),
        BenchCommand::Stability(ref args) => stability::run(args),
        BenchCommand::Specialise(ref args) => specialise::run(args),
        BenchCommand::Meshes { width, height, runs } => meshes::run(width.max(1), height.max(1), runs.max(1)),
        BenchCommand::Cells { width, height, runs } => cells::run(width.max(1), height.max(1), runs.max(1)),
        BenchCommand::Faces {
            width,
            height,
            runs,
            ref only,
        } => faces::run(width.max(1), height.max(1), runs.max(1), only),
        BenchCommand::Cull {
            width,
            height,
            runs,
            ref only,
        } => cull::run(width.max(1), height.max(1), runs.max(1), only),
        BenchCommand::Lights {
            width,
            height,
            runs,
            ref only,
            ref out,
        } => lights::run(width.max(1), height.max(1), runs.max(1), only, out),
        BenchCommand::Paths {
            width,
            height,
            reference,
            samples,
            ref only,
            ref out,
        } => paths::run(width.max(1), height.max(1), reference.max(1), samples.max(1), only, out),
        BenchCommand::Reflections {
            width,
            height,
            runs,
            ref only,
        } => reflections::run(width.max(1), height.max(1), runs.max(1), only),
        BenchCommand::Balls {
            width,
            height,
            levels,
            runs,
            ref only,
            ref counts,
        } => balls::run(
            width.max(1),
            height.max(1),
            levels.clamp(1, 64),
            runs.max(1),
            only,
            &ball_counts(counts)?,
        ),
        BenchCommand::Instances {
            width,
            height,
            levels,
            runs,
            ref only,
            ref counts,
        } => instances::run(
            width.max(1),
            height.max(1),
            levels.clamp(1, 64),
            runs.max(1),
            only,
            &instance_counts(counts)?,
        ),
        BenchCommand::Skinning { runs } => skinning::run(runs.max(1)),
        BenchCommand::Product {
            width,
            height,
            levels,
            runs,
        } => product::run(width.max(1), height.max(1), levels.clamp(1, 64), runs.max(1)),
        BenchCommand::Compare(ref args) => compare::run(args),
        BenchCommand::Aa { width, height, frames } => aa::run(width.max(1), height.max(1), frames.max(1)),
        BenchCommand::Report { ref out, ref only } => report::run(out, only),
        BenchCommand::Stereo {
            ref scales,
            runs,
            ref only,
        } => {
            if scales.is_empty() || scales.iter().any(|s| !(s.is_finite() && *s > 0.0 && *s <= 2.0)) {
                return Err(format!("--scales: each must be in (0, 2], got {scales:?}"));
            }
            stereo::run(scales, runs.max(1), only)
        }
    }
}

/// The ball counts `bench balls --counts` asks for, ascending, with the
/// one-ball scene the ratios divide by; [`balls::COUNTS`] when none.
///
/// # Errors
/// A count outside 1 to 254 (the swarm's ids stop at 254).
fn ball_counts(counts: &[usize]) -> Result<Vec<usize>, String> {
    if let Some(n) = counts.iter().find(|&&n| !(1..=254).contains(&n)) {
        return Err(format!("--counts: each must be from 1 to 254, got {n}"));
    }
    let mut out = if counts.is_empty() {
        balls::COUNTS.to_vec()
    } else {
        counts.to_vec()
    };
    out.push(1);
    out.sort_unstable();
    out.dedup();
    Ok(out)
}

/// The instance counts `bench instances` times: `counts` sorted, or
/// [`instances::COUNTS`] when empty; each from 1 to 100,000.
fn instance_counts(counts: &[usize]) -> Result<Vec<usize>, String> {
    if let Some(n) = counts.iter().find(|&&n| !(1..=100_000).contains(&n)) {
        return Err(format!("--counts: each must be from 1 to 100000, got {n}"));
    }
    let mut out = if counts.is_empty() {
        instances::COUNTS.to_vec()
    } else {
        counts.to_vec()
    };
    out.sort_unstable();
    out.dedup();
    Ok(out)
}

/// Best wall time of `runs` calls of `f`, in ms, after one untimed call
/// (which compiles pipelines).
pub fn best_ms<T>(runs: u32, mut f: impl FnMut() -> Result<T, String>) -> Result<f64, String> {
    std::hint::black_box(f()?);
    let mut best = f64::INFINITY;
    for _ in 0..runs {
        let t = Instant::now();
        std::hint::black_box(f()?);
        best = best.min(t.elapsed().as_secs_f64());
    }
    Ok(best * 1e3)
}

/// The GPU's time for one trace of `scene` once uploaded, in ms: the
/// device's own clock where it has timestamps, else the wall time to idle;
/// the median of `runs` ([`GpuTracer::time_trace`]). What the packing,
/// upload and read-back of a whole [`GpuTracer::render`] add is left out:
/// the render pass pays them once, not per frame.
///
/// # Errors
/// As [`GpuTracer::render`].
pub fn trace_ms(
    tracer: &mut bevy_manifold_gpu::GpuTracer,
    space: &Space,
    scene: &Scene,
    settings: &TraceSettings,
    runs: u32,
) -> Result<f64, String> {
    let t = tracer
        .time_trace(space, scene, settings, runs)
        .map_err(|e| e.to_string())?;
    Ok(t.device_ms.unwrap_or(t.wall_ms))
}

/// Three times of one table row and the ratios of the last two over the
/// first, as `bench lights` and `bench reflections` print them for the
/// GPU and again for the CPU: `t0 t1 t2 t1/t0 t2/t0`, the times with
/// `decimals` decimals.
#[must_use]
pub fn times_and_ratios(t: [f64; 3], decimals: usize) -> String {
    format!(
        "{:>9.d$} {:>9.d$} {:>9.d$} {:>6.2}x {:>6.2}x",
        t[0],
        t[1],
        t[2],
        t[1] / t[0],
        t[2] / t[0],
        d = decimals
    )
}

/// The benchmarks' fog: density 0.4 per inradius, so about half a domain
/// away light keeps 80% and fog hides what lies past 14 inradii.
#[must_use]
pub fn fog_for(space: &Space) -> Fog {
    Fog {
        density: 0.4 / space.inradius(),
        color: [0.7, 0.75, 0.8],
    }
}

/// A progress bar on stderr for the long benchmarks: `[=====>    ] 42/270 what`.
pub struct Progress {
    done: usize,
    total: usize,
    start: Instant,
}

impl Progress {
    /// A bar for `total` steps.
    #[must_use]
    pub fn new(total: usize) -> Self {
        Progress {
            done: 0,
            total: total.max(1),
            start: Instant::now(),
        }
    }

    /// One more step done, `what` naming the next.
    pub fn step(&mut self, what: &str) {
        use std::io::Write;
        self.done = (self.done + 1).min(self.total);
        let width = 30;
        let filled = self.done * width / self.total;
        let elapsed = self.start.elapsed().as_secs_f64();
        let left = elapsed / self.done as f64 * (self.total - self.done) as f64;
        eprint!(
            "\r[{}{}] {}/{} {:.0}s left  {what:<40}",
            "=".repeat(filled),
            " ".repeat(width - filled),
            self.done,
            self.total,
            left
        );
        if self.done == self.total {
            eprintln!();
        }
        let _ = std::io::stderr().flush();
    }
}

#[cfg(test)]
mod tests {
    use super::{ball_counts, instance_counts, instances};

    #[test]
    fn a_row_gives_the_times_and_their_ratios_over_the_first() {
        assert_eq!(
            super::times_and_ratios([2.0, 3.0, 5.0], 1),
            "      2.0       3.0       5.0   1.50x   2.50x"
        );
    }

    #[test]
    fn instance_counts_sort_and_refuse_out_of_range() {
        assert_eq!(instance_counts(&[1000, 100, 1000]), Ok(vec![100, 1000]));
        assert_eq!(instance_counts(&[]).expect("default"), instances::COUNTS.to_vec());
        for bad in [0, 100_001] {
            let e = instance_counts(&[16, bad]).expect_err("out of range");
            assert!(e.contains("--counts") && e.contains(&bad.to_string()), "{e}");
        }
    }

    #[test]
    fn ball_counts_add_the_one_ball_scene_in_order_and_refuse_out_of_range() {
        assert_eq!(ball_counts(&[100, 16, 100]), Ok(vec![1, 16, 100]));
        assert_eq!(ball_counts(&[1]), Ok(vec![1]));
        assert_eq!(ball_counts(&[]).expect("default").len(), 10);
        for bad in [0, 255] {
            let e = ball_counts(&[16, bad]).expect_err("out of range");
            assert!(e.contains("--counts") && e.contains(&bad.to_string()), "{e}");
        }
    }
}
