//! `bench accuracy`: run time against error. For each space, its default
//! scene (clear, and with fog) is rendered from a fixed set of views on the
//! GPU with a matrix of settings; each setting's frame time is set against
//! its error relative to a reference render (the CPU tracer in f64 at 64
//! levels, no early stop). Writes a CSV and a PNG plot with the Pareto
//! front per space, prints a table and the cheapest setting per space
//! whose id mismatch is below 0.1% (and whose PSNR is at least 40 dB).

use crate::plot::{PALETTE, Panel, Series, draw, pareto_front};
use crate::{Progress, fog_for};
use bevy_manifold::prelude::*;
use bevy_manifold_gpu::GpuTracer;
use bevy_manifold_test_support::compare::ImageErrors;
use bevy_manifold_test_support::stress;
use clap::Args;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

/// The levels swept.
pub const LEVELS: [u32; 9] = [1, 2, 3, 4, 6, 8, 12, 16, 32];
/// The reference's levels.
const REFERENCE_LEVELS: u32 = 64;
/// The id-mismatch budget of the summary.
const BUDGET: f64 = 0.001;
/// The colour budget of the summary.
const PSNR_BUDGET: f64 = 40.0;

/// A budget of the summary: its name and whether errors meet it.
type Budget = (&'static str, fn(&ImageErrors) -> bool);

/// Arguments of `bench accuracy`.
#[derive(Args, Clone, Debug)]
pub struct AccuracyArgs {
    /// One space (catalog name) instead of all five.
    #[arg(long)]
    space: Option<String>,
    /// Folder for `accuracy.csv` and `accuracy.png`.
    #[arg(long, default_value = "bench-out")]
    out: PathBuf,
    /// Image width of each view.
    #[arg(long, default_value_t = 256)]
    width: u32,
    /// Image height of each view.
    #[arg(long, default_value_t = 144)]
    height: u32,
    /// Timed runs per setting and view (after one untimed); the best counts.
    #[arg(long, default_value_t = 2)]
    runs: u32,
}

/// One setting of the sweep.
#[derive(Clone, Copy, Debug)]
struct Setting {
    fog: bool,
    levels: u32,
    renormalize: bool,
    early_stop: bool,
}

impl Setting {
    fn label(&self) -> String {
        format!(
            "{} L{} renorm {} early {}",
            if self.fog { "fog" } else { "clear" },
            self.levels,
            on(self.renormalize),
            on(self.early_stop)
        )
    }
}

fn on(b: bool) -> &'static str {
    if b { "on" } else { "off" }
}

/// Every setting: levels x renormalisation, and with fog also the early
/// stop on and off (without fog it changes nothing).
fn settings() -> Vec<Setting> {
    let mut out = Vec::new();
    for fog in [false, true] {
        for levels in LEVELS {
            for renormalize in [true, false] {
                for early_stop in [true, false] {
                    if fog || early_stop {
                        out.push(Setting {
                            fog,
                            levels,
                            renormalize,
                            early_stop,
                        });
                    }
                }
            }
        }
    }
    out
}

/// The fixed views of a space: its default camera; the same turned a
/// quarter turn and tilted (across edges and faces); and from 70% of the
/// way out to a vertex, looking back at the centre.
fn views(space: &Space) -> Vec<glam::DMat4> {
    let g = space.geometry();
    let base = Scene::default_for(space).camera.isometry;
    let turned = base
        * isometry::rotation(glam::DVec3::Y, std::f64::consts::FRAC_PI_2)
        * isometry::rotation(glam::DVec3::X, 0.35);
    let v = space.vertices()[0].point;
    let eye = g.normalize_point::<f64>((v.truncate() / v.w * 0.7).extend(1.0));
    let back = stress::camera_along(
        space,
        &bevy_manifold::trace::step::Ray {
            origin: eye,
            dir: g.normalize_tangent::<f64>(eye, glam::DVec4::W),
        },
    );
    vec![base, turned, back]
}

struct Row {
    space: String,
    setting: Setting,
    ms: f64,
    errors: ImageErrors,
}

pub fn run(args: &AccuracyArgs) -> Result<(), String> {
    let names: Vec<&str> = match &args.space {
        Some(n) => vec![
            catalog::by_name(n)
                .map(|_| n.as_str())
                .ok_or_else(|| format!("no catalog space '{n}' (one of {})", catalog::NAMES.join(", ")))?,
        ],
        None => catalog::NAMES.to_vec(),
    };
    std::fs::create_dir_all(&args.out).map_err(|e| format!("{}: {e}", args.out.display()))?;
    let mut gpu = GpuTracer::new().map_err(|e| e.to_string())?;
    let (w, h, runs) = (args.width.max(1), args.height.max(1), args.runs.max(1));
    let all = settings();
    println!(
        "run time against error: {w}x{h}, 3 views, GPU frame time (trace + readback, best of {runs}) on {}; \
         reference: CPU f64, {REFERENCE_LEVELS} levels, no early stop",
        gpu.adapter_name()
    );
    let mut progress = Progress::new(names.len() * (all.len() + 2));
    let mut rows = Vec::new();
    for name in &names {
        let space = catalog::by_name(name).ok_or("catalog")?;
        let cameras = views(&space);
        let scene_for = |fog: bool, camera: glam::DMat4| {
            let mut scene = Scene::default_for(&space);
            scene.camera.isometry = camera;
            scene.fog = fog.then(|| fog_for(&space));
            scene
        };
        let mut references = Vec::new();
        for fog in [false, true] {
            progress.step(&format!("{name}: reference{}", if fog { " with fog" } else { "" }));
            let settings = TraceSettings {
                width: w,
                height: h,
                levels: REFERENCE_LEVELS,
                fog_early_stop: false,
                ..TraceSettings::default()
            };
            references.push(
                cameras
                    .iter()
                    .map(|&c| render::<f64>(&space, &scene_for(fog, c), &settings))
                    .collect::<Vec<_>>(),
            );
        }
        for setting in &all {
            progress.step(&format!("{name}: {}", setting.label()));
            let settings = TraceSettings {
                width: w,
                height: h,
                levels: setting.levels,
                fog_early_stop: setting.early_stop,
                renormalize: setting.renormalize,
                ..TraceSettings::default()
            };
            let mut errors = ImageErrors::default();
            let mut ms = 0.0;
            for (k, &camera) in cameras.iter().enumerate() {
                let scene = scene_for(setting.fog, camera);
                let img = gpu.render(&space, &scene, &settings).map_err(|e| e.to_string())?;
                errors.add(
                    &img,
                    &references[usize::from(setting.fog)][k],
                    scene.fog.as_ref().map(|f| f.density),
                );
                let mut best = f64::INFINITY;
                for _ in 0..runs {
                    let t = Instant::now();
                    std::hint::black_box(gpu.render(&space, &scene, &settings).map_err(|e| e.to_string())?);
                    best = best.min(t.elapsed().as_secs_f64());
                }
                ms += best * 1e3 / cameras.len() as f64;
            }
            rows.push(Row {
                space: (*name).to_string(),
                setting: *setting,
                ms,
                errors,
            });
        }
    }
    report(&rows, args)
}

fn report(rows: &[Row], args: &AccuracyArgs) -> Result<(), String> {
    let mut csv = String::from(
        "space,fog,levels,renormalize,early_stop,frame_ms,object_mismatch,cell_mismatch,id_mismatch,visible_id_mismatch,far_cells,rmse,psnr_db\n",
    );
    println!(
        "{:<22} {:>5} {:>6} {:>6} {:>6} {:>9} {:>9} {:>9} {:>8} {:>8}",
        "space", "fog", "levels", "renorm", "early", "frame ms", "object %", "cell %", "far %", "PSNR dB"
    );
    for r in rows {
        let (s, e) = (&r.setting, &r.errors);
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{:.3},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.2}",
            r.space,
            on(s.fog),
            s.levels,
            on(s.renormalize),
            on(s.early_stop),
            r.ms,
            e.share(e.object),
            e.share(e.cell),
            e.id_mismatch(),
            e.visible_mismatch(),
            e.share(e.far),
            e.rmse(),
            e.psnr()
        );
        println!(
            "{:<22} {:>5} {:>6} {:>6} {:>6} {:>9.1} {:>9.3} {:>9.3} {:>8.2} {:>8.1}",
            r.space,
            on(s.fog),
            s.levels,
            on(s.renormalize),
            on(s.early_stop),
            r.ms,
            100.0 * e.share(e.object),
            100.0 * e.share(e.cell),
            100.0 * e.share(e.far),
            e.psnr()
        );
    }
    let csv_path = args.out.join("accuracy.csv");
    std::fs::write(&csv_path, csv).map_err(|e| format!("{}: {e}", csv_path.display()))?;
    println!(
        "\ncheapest setting with id mismatch below {:.1}% (ids: all objects; seen: objects fog leaves visible), and with PSNR of at least {PSNR_BUDGET} dB:",
        BUDGET * 100.0
    );
    let mut spaces: Vec<&str> = rows.iter().map(|r| r.space.as_str()).collect();
    spaces.dedup();
    let mut panels = Vec::new();
    for space in &spaces {
        for fog in [false, true] {
            let mine: Vec<&Row> = rows
                .iter()
                .filter(|r| r.space == *space && r.setting.fog == fog)
                .collect();
            let tests: [Budget; 3] = [
                ("ids", |e| e.id_mismatch() < BUDGET),
                ("seen", |e| e.visible_mismatch() < BUDGET),
                ("PSNR", |e| e.psnr() >= PSNR_BUDGET),
            ];
            for (what, ok) in tests {
                match mine
                    .iter()
                    .filter(|r| ok(&r.errors))
                    .min_by(|a, b| a.ms.total_cmp(&b.ms))
                {
                    Some(r) => println!(
                        "  {space:<22} {:<5} by {what:<4} {:<34} {:>8.1} ms  id mismatch {:.3}% (seen {:.3}%)  PSNR {:.1} dB",
                        if fog { "fog" } else { "clear" },
                        r.setting.label(),
                        r.ms,
                        100.0 * r.errors.id_mismatch(),
                        100.0 * r.errors.visible_mismatch(),
                        r.errors.psnr()
                    ),
                    None => println!(
                        "  {space:<22} {:<5} by {what:<4} none up to {} levels",
                        if fog { "fog" } else { "clear" },
                        LEVELS[LEVELS.len() - 1]
                    ),
                }
            }
        }
        // The plot: id mismatch against frame time, one series per
        // (fog, renormalisation) pair, early stop as separate points.
        let mine: Vec<&Row> = rows.iter().filter(|r| r.space == *space).collect();
        let mut series = Vec::new();
        for (k, (fog, renorm, early)) in [
            (false, true, true),
            (false, false, true),
            (true, true, true),
            (true, true, false),
            (true, false, true),
        ]
        .into_iter()
        .enumerate()
        {
            let points: Vec<(f64, f64)> = mine
                .iter()
                .filter(|r| r.setting.fog == fog && r.setting.renormalize == renorm && r.setting.early_stop == early)
                .map(|r| (r.ms, r.errors.id_mismatch()))
                .collect();
            series.push(Series {
                label: format!(
                    "{}{}{}",
                    if fog { "fog" } else { "clear" },
                    if renorm { "" } else { ", no renorm" },
                    if fog && !early { ", no early stop" } else { "" }
                ),
                color: PALETTE[k],
                points,
                line: true,
            });
        }
        let all: Vec<(f64, f64)> = mine.iter().map(|r| (r.ms, r.errors.id_mismatch())).collect();
        panels.push(Panel {
            title: (*space).to_string(),
            x: "GPU frame ms".into(),
            y: "id mismatch (fraction of pixels)".into(),
            series,
            front: pareto_front(&all),
        });
    }
    let png = args.out.join("accuracy.png");
    match draw(&png, &panels, 3, 1e-5) {
        Ok(()) => println!("\nwrote {} and {}", csv_path.display(), png.display()),
        Err(e) => println!("\nwrote {} ({e})", csv_path.display()),
    }
    Ok(())
}
