//! `bench stability`: the long versions of tests/stability.rs. Drift of
//! `<p,p>` and of the direction's tangency over up to 10^4 transports (GPU
//! f32, CPU f32, CPU f64; renormalisation on and off) as curves; far travel
//! through 10^8 faces; the degenerate rays at 1000 transports. Writes
//! `drift.csv` and `drift.png`.

use crate::Progress;
use crate::plot::{PALETTE, Panel, Series, draw};
use bevy_manifold::prelude::*;
use bevy_manifold_gpu::GpuTracer;
use bevy_manifold_test_support::stress;
use bevy_manifold_test_support::stress::{cpu_drift, empty_view, walk_settings, worst};
use clap::Args;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `bench stability`.
#[derive(Args, Clone, Debug)]
pub struct StabilityArgs {
    /// Longest walk, in transports.
    #[arg(long, default_value_t = 10_000)]
    transports: u32,
    /// Faces the far-travelling camera crosses.
    #[arg(long, default_value_t = 100_000_000)]
    crossings: u64,
    /// Folder for `drift.csv` and `drift.png`.
    #[arg(long, default_value = "bench-out")]
    out: PathBuf,
}

/// Rays per walk: a 16x16 grid of the default camera's view.
const SIDE: u32 = 16;

const SIDES: [&str; 3] = ["GPU f32", "CPU f32", "CPU f64"];

pub fn run(args: &StabilityArgs) -> Result<(), String> {
    std::fs::create_dir_all(&args.out).map_err(|e| format!("{}: {e}", args.out.display()))?;
    let mut gpu = GpuTracer::new().map_err(|e| e.to_string())?;
    let lengths: Vec<u32> = [10, 30, 100, 300, 1000, 3000, 10_000]
        .into_iter()
        .filter(|&n| n <= args.transports.max(10))
        .collect();
    println!(
        "drift: worst |<p,p> -+ 1| or tangency error over {} rays after N transports, on {}",
        SIDE * SIDE,
        gpu.adapter_name()
    );
    let mut csv = String::from("space,precision,renormalize,transports,worst_error\n");
    let mut panels = Vec::new();
    let mut progress = Progress::new(catalog::NAMES.len() * lengths.len() * 2);
    let mut lines = Vec::new();
    for name in catalog::NAMES {
        let space = catalog::by_name(name).ok_or("catalog")?;
        let scene = empty_view(Scene::default_for(&space).camera.isometry);
        // curves[side][renormalize off?] = points
        let mut curves = vec![vec![Vec::new(); 2]; 3];
        for (j, renormalize) in [true, false].into_iter().enumerate() {
            for &n in &lengths {
                progress.step(&format!("{name}: {n} transports, renormalise {renormalize}"));
                let settings = walk_settings(n, renormalize, SIDE);
                let values = [
                    worst(&gpu.drift(&space, &scene, &settings).map_err(|e| e.to_string())?),
                    worst(&cpu_drift::<f32>(&space, &scene, &settings)),
                    worst(&cpu_drift::<f64>(&space, &scene, &settings)),
                ];
                for (k, v) in values.into_iter().enumerate() {
                    curves[k][j].push((f64::from(n), v));
                    let _ = writeln!(csv, "{name},{},{renormalize},{n},{v:e}", SIDES[k]);
                }
            }
        }
        let mut series = Vec::new();
        for (k, side) in SIDES.iter().enumerate() {
            for (j, what) in ["renormalised", "not renormalised"].iter().enumerate() {
                let points = curves[k][j].clone();
                lines.push(format!(
                    "{name:<22} {side:<8} {what:<17} {}",
                    points
                        .iter()
                        .map(|(_, v)| format!("{v:>9.1e}"))
                        .collect::<Vec<_>>()
                        .join(" ")
                ));
                series.push(Series {
                    label: format!("{side}, {what}"),
                    color: PALETTE[k * 2 + j],
                    points,
                    line: true,
                });
            }
        }
        panels.push(Panel {
            title: name.to_string(),
            x: "transports".into(),
            y: "worst normalisation error".into(),
            series,
            front: Vec::new(),
        });
    }
    println!(
        "{:<22} {:<8} {:<17} {}",
        "space",
        "",
        "",
        lengths.iter().map(|n| format!("{n:>9}")).collect::<Vec<_>>().join(" ")
    );
    for l in lines {
        println!("{l}");
    }
    let csv_path = args.out.join("drift.csv");
    std::fs::write(&csv_path, csv).map_err(|e| format!("{}: {e}", csv_path.display()))?;
    let png = args.out.join("drift.png");
    match draw(&png, &panels, 3, 1e-17) {
        Ok(()) => println!("wrote {} and {}", csv_path.display(), png.display()),
        Err(e) => println!("wrote {} ({e})", csv_path.display()),
    }
    far_travel(&mut gpu, args.crossings)?;
    degenerate(&mut gpu)
}

/// Far travel along each space's face-axis loop, then the view from there
/// against the closed form's (the start turned by the loop's twist times
/// the steps); in H3, where rounding makes the path wander off its closed
/// form, against the CPU f64 reference's view from the same camera.
fn far_travel(gpu: &mut GpuTracer, crossings: u64) -> Result<(), String> {
    println!("\nfar travel: {crossings} face crossings along the face-axis loop, placements composed in f64");
    println!(
        "{:<22} {:>12} {:>8} {:>12} {:>12} {:>11}",
        "space", "crossings", "s", "isometry err", "from exact", "same view %"
    );
    for name in catalog::NAMES {
        let space = catalog::by_name(name).ok_or("catalog")?;
        let path = stress::face_axis_loop(&space);
        let t = Instant::now();
        let far = stress::far_travel(&space, &path, crossings);
        let secs = t.elapsed().as_secs_f64();
        let [a, b] =
            bevy_manifold_test_support::gpu::far_travel_views(gpu, &space, &path, &far).map_err(|e| e.to_string())?;
        let same = a
            .pixels
            .iter()
            .zip(&b.pixels)
            .filter(|(p, q)| p.object == q.object)
            .count();
        let gap = stress::exact_gap(&space, &path, &far);
        println!(
            "{name:<22} {:>12} {secs:>8.1} {:>12.1e} {gap:>12.1e} {:>11.3}",
            far.crossings,
            far.isometry_error,
            100.0 * same as f64 / a.pixels.len() as f64
        );
    }
    Ok(())
}

/// The degenerate rays walked 1000 transports on the GPU and in f32 and
/// f64 on the CPU: how many went wrong (NaN, outside the domain, stalled).
fn degenerate(gpu: &mut GpuTracer) -> Result<(), String> {
    println!("\ndegenerate rays (vertices, edges, tangent to faces), 1000 transports each");
    println!(
        "{:<22} {:>6} {:>10} {:>12} {:>12}",
        "space", "rays", "side", "worst error", "failures"
    );
    for name in catalog::NAMES {
        let space = catalog::by_name(name).ok_or("catalog")?;
        let rays = stress::degenerate_rays(&space);
        let settings = walk_settings(1000, true, 1);
        let mut results = vec![Vec::new(); 3];
        for ray in &rays {
            let scene = empty_view(stress::camera_along(&space, ray));
            results[0].push(gpu.drift(&space, &scene, &settings).map_err(|e| e.to_string())?[0]);
            results[1].push(cpu_drift::<f32>(&space, &scene, &settings)[0]);
            results[2].push(cpu_drift::<f64>(&space, &scene, &settings)[0]);
        }
        for (k, r) in results.iter().enumerate() {
            let failures = r
                .iter()
                .filter(|d| {
                    !d.worst().is_finite() || d.outside > 1e-4 || d.levels < 1000 || d.distance < 8.0 * space.inradius()
                })
                .count();
            println!(
                "{name:<22} {:>6} {:>10} {:>12.1e} {failures:>12}",
                rays.len(),
                SIDES[k],
                worst(r)
            );
        }
    }
    Ok(())
}
