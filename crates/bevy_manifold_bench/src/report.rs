//! `bench report`: every area's figures measured in one run and written
//! as `BENCHMARKS.md`, so the file always says what is true today. Each
//! area runs the benchmark that measures it as a child process of this
//! same binary (`bench <area> …`, the command a reader reruns), and the
//! file quotes its table under the area's method.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// One area of the report: what it measures, how, and the `bench`
/// command that does.
struct Area {
    title: &'static str,
    method: &'static str,
    args: &'static [&'static str],
}

/// The areas, in the order of the file. Sizes and runs are chosen so the
/// whole report takes about ten minutes on two cores with lavapipe;
/// each command's defaults measure more.
const AREAS: &[Area] = &[
    Area {
        title: "The CPU reference tracer",
        method: "Rays per second of the CPU reference (all cores, rayon) per catalog space at 4 and 16 levels, in f32 (the GPU's arithmetic) and f64 (the reference), the default scene (domain edges, a ball, a light). The best of the runs.",
        args: &["tracer", "--side", "128", "--runs", "2"],
    },
    Area {
        title: "The GPU tracer, and what specialisation saves",
        method: "Frame time of the WGSL tracer run headless (one compute dispatch and the read-back of colour and ids) per catalog space at 1, 3, 8 and 16 levels, fog off and on, with the pipeline specialised to the scene and with the generic shader (every def on). The ratio is generic over specialised.",
        args: &["gpu", "--width", "320", "--height", "180", "--runs", "2"],
    },
    Area {
        title: "Culling by near faces",
        method: "GPU and CPU f32 frame time with each segment testing every object, and testing only the objects near the faces it comes near (and in the ball tree's leaves it meets), per catalog space at 8 and 16 levels. Culling changes no pixel (the tests hold it to that); the ratio is what it saves.",
        args: &["cull", "--width", "320", "--height", "180", "--runs", "2"],
    },
    Area {
        title: "Frame time against face count",
        method: "GPU and CPU f32 frame time, 8 levels, with nothing to hit and with the default scene, for domains of 4 to 56 faces (lens spaces, the binary polyhedral spaces, the 12- and 52-face domains of the Seifert-Weber space).",
        args: &["faces", "--width", "320", "--height", "180", "--runs", "2"],
    },
    Area {
        title: "Frame time against ball count",
        method: "GPU and CPU f32 frame time for a swarm of small balls (1, 16 and 100) in the torus, Seifert-Weber and the Poincare sphere, culling off and on; the ratio is over the one-ball scene.",
        args: &["balls", "--counts", "16,100", "--runs", "2"],
    },
    Area {
        title: "Meshes",
        method: "Frame time against triangle count (Suzanne subdivided) at 3 and 8 levels, GPU and CPU, and the time to build each BVH.",
        args: &["meshes", "--width", "320", "--height", "180", "--runs", "1"],
    },
    Area {
        title: "Skinned meshes",
        method: "What a skinned mesh's new pose costs per triangle on the CPU (one thread): skinning its vertices as Bevy's vertex shader does, refitting the last pose's BVH to them, and building a new BVH, on sheets of 8,192 to 51,200 triangles bent by a joint; and how much looser (box area) the refitted tree is than a new one after a 60-degree bend.",
        args: &["skinning", "--runs", "3"],
    },
    Area {
        title: "Frame time against mesh instances",
        method: "GPU and CPU f32 frame time for a level of 100 to 10,000 props (instances of three small meshes at random places, turns and sizes) in the torus, Seifert-Weber and the Poincare sphere, 8 levels: with each face group of instances walked by its instance tree, and with every instance tested (up to 1,000). The last line is the culled GPU frame at 10,000 over the one at 100 (the goal: under 2x).",
        args: &["instances", "--runs", "2"],
    },
    Area {
        title: "The product geometries against Seifert-Weber",
        method: "GPU frame time of the product spaces' tracer (H2xR and S2xR: exact geodesics, faces crossed in closed form, geodesic balls by sphere tracing, and on the CPU in H2xR by Newton's method) in the five product spaces, each with its default scene (lit from the eye) lit by two point lights (32 images of each, with shadows, and without them), with the prism's edges drawn as tubes, and with two meshes (the airplane and a box, 156 triangles, traced in the product metric), over the main tracer's in Seifert-Weber's space with its default scene, at the same size and levels (the goal: within 1.5x); and the CPU f64 reference's frame.",
        args: &["product", "--runs", "3"],
    },
    Area {
        title: "Exact cell ids",
        method: "What exact ids cost: nanoseconds per face crossing by exact products, the growth and recentring of the cell table, GPU frame time with the table against hashed ids, and the share of hit pixels the table names.",
        args: &["cells", "--width", "320", "--height", "180", "--runs", "2"],
    },
    Area {
        title: "What change detection and specialisation save in the pass",
        method: "The render pass in a headless Bevy app: specialised against generic pipelines with and without fog and per-cell shading, and the bytes uploaded per frame with change detection against everything uploaded every frame.",
        args: &["specialise", "--width", "320", "--height", "180", "--runs", "2"],
    },
    Area {
        title: "The render pass",
        method: "The render pass's fragment path against the compute path on the same device (headless), then frame times of the pass in a headless Bevy app at 640x360 and 1280x720.",
        args: &["pass", "--runs", "2"],
    },
    Area {
        title: "Anti-aliasing: cones and accumulation",
        method: "PSNR (dB) against a 16-samples-per-pixel reference of one ray per pixel, of cone tracing, and of 4, 8 and 16 accumulated samples, per catalog space at 8 and 16 levels (CPU f64); and the frame-to-frame flicker of a slowly moving view, one ray against cones.",
        args: &["aa"],
    },
    Area {
        title: "Light images and shadows",
        method: "GPU and CPU f32 frame time of the paper's scene per catalog space, 8 levels, with each light's copy in the domain only (the lighting before light images), with its images (64 at most), and with its images and shadows; the ratios are over the first. Then run time against error: the paper's light with a range of two inradii (S3: none, both arcs), its images kept at budgets 1 to 256, against the brute-force sum over the group's elements closed from the face pairings, at 300 points of the domain; the error is the largest gap as a share of the nearest image's irradiance there. Writes `lights.csv` and `lights.png`.",
        args: &[
            "lights",
            "--width",
            "320",
            "--height",
            "180",
            "--runs",
            "2",
            "--out",
            "bench-out",
        ],
    },
    Area {
        title: "Reflections",
        method: "GPU and CPU f32 frame time of the paper's scene with the mirror ball of its Fig. 11 (a smooth metal at the domain's centre; Suzanne and the hands, of roughness 0.5, reflect nothing) per catalog space, 8 levels, with 0, 1 and 2 reflections a ray; the ratios are over none. `reflect` is the share of pixels whose path takes a reflection.",
        args: &["reflections", "--width", "320", "--height", "180", "--runs", "9"],
    },
    Area {
        title: "Path tracing: run time against error",
        method: "The paper's scene (its light given a radius of 0.15 inradii, shadows on) path traced at 6 bounces, 8 levels, 160x90, per catalog space: the mean of 1 to 16 samples (seed 2) against a reference of 128 GPU samples (seed 1), GPU (device clock) and CPU f32; the error is the relative RMS over every pixel and channel, the time the samples' (per-sample time times their number). Writes `paths.csv` and `paths.png`.",
        args: &[
            "paths",
            "--width",
            "160",
            "--height",
            "90",
            "--reference",
            "128",
            "--samples",
            "16",
            "--out",
            "bench-out",
        ],
    },
    Area {
        title: "Run time against error",
        method: "GPU frame time and image error against the CPU f64 reference for levels 1 to 32, renormalisation and the fog's early stop on and off, in the Seifert-Weber space; the Pareto front of time against error. Writes `accuracy.csv` and `accuracy.png` to the output folder.",
        args: &[
            "accuracy",
            "--space",
            "seifert-weber",
            "--width",
            "128",
            "--height",
            "72",
            "--runs",
            "1",
            "--out",
            "bench-out",
        ],
    },
    Area {
        title: "Numerical stability",
        method: "How far rays drift off the model (`<p,p>` and the direction's tangency) over up to 2,000 transports, GPU f32, CPU f32 and CPU f64, renormalised and not; a camera carried through 10^6 faces; degenerate rays. The test suite holds the same bounds at fewer transports. Writes `drift.csv` and `drift.png`.",
        args: &[
            "stability",
            "--transports",
            "2000",
            "--crossings",
            "1000000",
            "--out",
            "bench-out",
        ],
    },
];

/// Runs every area and writes the report to `out`.
///
/// # Errors
/// A benchmark that fails (its output names why), or the file.
pub fn run(out: &Path, only: &str) -> Result<(), String> {
    let exe = std::env::current_exe().map_err(|e| format!("this program's path: {e}"))?;
    let started = Instant::now();
    let mut sections = String::new();
    let areas: Vec<&Area> = AREAS.iter().filter(|a| only.is_empty() || a.args[0] == only).collect();
    if areas.is_empty() {
        return Err(format!("--only {only}: no such area"));
    }
    for (k, area) in areas.iter().enumerate() {
        eprintln!("[{}/{}] bench {}", k + 1, areas.len(), area.args.join(" "));
        let t = Instant::now();
        let output = Command::new(&exe)
            .arg("bench")
            .args(area.args)
            .output()
            .map_err(|e| format!("bench {}: {e}", area.args[0]))?;
        let stdout = String::from_utf8_lossy(&output.stdout);
        if !output.status.success() {
            return Err(format!(
                "bench {} failed:\n{}{}",
                area.args.join(" "),
                stdout,
                String::from_utf8_lossy(&output.stderr)
            ));
        }
        let _ = write!(
            sections,
            "\n## {}\n\n{}\n\n`cargo run --release -- bench {}` ({:.0} s):\n\n```text\n{}\n```\n",
            area.title,
            wrap(area.method, 76),
            area.args.join(" "),
            t.elapsed().as_secs_f64(),
            stdout.trim_end()
        );
    }
    let mut text = String::new();
    let _ = write!(
        text,
        "# Benchmarks\n\n{}\n\n{}\n\n{}\n",
        wrap(
            "What bevy_manifold costs and how accurate it is, per area, as one run of `cargo run --release -- bench report` measured it (the command writes this file; `--only AREA` reruns one area into a file of its own). Speed is shown here, never by timed tests. Each area says what it measures and the command that measures it; ratios are measured side by side in the same run, so compare figures within a table, not across machines.",
            76
        ),
        wrap(&machine(), 76),
        wrap(
            "The experiments behind the design (what each optimisation saved when it was made, what was tried and not kept) and the figures measured on a real GPU, each with its date and machine, are in `docs/benchmarks/history.md`.",
            76
        ),
    );
    let _ = write!(
        text,
        "{sections}\nThe whole report took {:.0} s.\n",
        started.elapsed().as_secs_f64()
    );
    std::fs::write(out, text).map_err(|e| format!("{}: {e}", out.display()))?;
    eprintln!("wrote {}", out.display());
    Ok(())
}

/// The machine and GPU adapter the figures come from.
fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(':'))
                .map(|(_, m)| m.trim().to_owned())
        })
        .unwrap_or_else(|| "an unknown CPU".into());
    let cores = std::thread::available_parallelism().map_or(1, std::num::NonZero::get);
    let memory = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|s| {
            let kb: f64 = s.lines().next()?.split_whitespace().nth(1)?.parse().ok()?;
            Some(format!(", {:.0} GiB", kb / 1024.0 / 1024.0))
        })
        .unwrap_or_default();
    let adapter = bevy_manifold_gpu::GpuTracer::new().map_or_else(|e| format!("none ({e})"), |g| g.adapter_name());
    format!(
        "Measured on {cpu}, {cores} cores{memory}; GPU adapter: {adapter}. Where the adapter is Mesa's lavapipe (llvmpipe), every GPU figure is the same CPU cores running the shader."
    )
}

/// `text` wrapped at `width` columns.
fn wrap(text: &str, width: usize) -> String {
    let mut out = String::new();
    let mut line = 0;
    for word in text.split_whitespace() {
        if line > 0 && line + 1 + word.len() > width {
            out.push('\n');
            line = 0;
        } else if line > 0 {
            out.push(' ');
            line += 1;
        }
        out.push_str(word);
        line += word.len();
    }
    out
}

/// The default report file.
#[must_use]
pub fn default_out() -> PathBuf {
    PathBuf::from("BENCHMARKS.md")
}

#[cfg(test)]
mod tests {
    use super::{AREAS, wrap};

    #[test]
    fn wrapped_lines_keep_every_word_and_fit() {
        let text = "a bb ccc dddd eeeee ffffff";
        let w = wrap(text, 8);
        assert_eq!(w.split_whitespace().collect::<Vec<_>>().join(" "), text);
        assert!(w.lines().all(|l| l.len() <= 8), "{w}");
    }

    #[test]
    fn every_area_names_a_bench_command() {
        use clap::Parser;
        #[derive(Parser)]
        struct Cli {
            #[command(subcommand)]
            bench: crate::BenchCommand,
        }
        for area in AREAS {
            let args = std::iter::once("bench").chain(area.args.iter().copied());
            assert!(Cli::try_parse_from(args).is_ok(), "bench {}", area.args.join(" "));
        }
    }
}
