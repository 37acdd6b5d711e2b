//! `bench compare`: the three ways this project traces a frame, on the
//! same scenes, interleaved in one process so that the machine's drift
//! hits all three alike: the CPU f32 reference (rayon), the GPU tracer
//! headless (`GpuTracer`, compute entry, trace and read-back) and the
//! render pass in a headless Bevy app (fragment entry into a camera's
//! target, one frame and a read-back). Four sweeps, each moving one thing
//! a frame's cost follows: levels (every catalog space), faces (spaces
//! from generators, 6 to 48 faces), balls (a swarm in Seifert-Weber) and
//! triangles (Suzanne subdivided, in Seifert-Weber). It prints ratios
//! (CPU over GPU: above 1 the GPU is faster; the pass over the GPU
//! headless), with the SIMD lane occupancy of each frame's walk
//! ([`lane_occupancy`]: what finished rays waiting on their neighbours
//! cost), and writes `compare.csv` and `compare.png`, frame time against
//! each swept quantity.

use crate::plot::{Panel, Series, draw};
use crate::{Progress, faces, meshes, pass::frame_ms, trace_ms};
use bevy::prelude::*;
use bevy_manifold::drawables::ManifoldMeshes;
use bevy_manifold::mesh::{MeshData, MeshMaterial};
use bevy_manifold::prelude::*;
use bevy_manifold::render::offscreen;
use bevy_manifold::trace::builtin;
use bevy_manifold_gpu::GpuTracer;
use bevy_manifold_test_support::stress::swarm;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

/// `bench compare`'s options.
#[derive(clap::Args, Clone, Debug)]
pub struct CompareArgs {
    /// Image width.
    #[arg(long, default_value_t = 320)]
    pub width: u32,
    /// Image height.
    #[arg(long, default_value_t = 180)]
    pub height: u32,
    /// Interleaved runs per point; the best of each tracer is kept.
    #[arg(long, default_value_t = 3)]
    pub runs: u32,
    /// Only the sweeps whose name holds this (levels, faces, balls,
    /// triangles, scale).
    #[arg(long, default_value = "")]
    pub only: String,
    /// Folder for compare.csv and compare.png.
    #[arg(long, default_value = "bench-out")]
    pub out: PathBuf,
}

/// One point of a sweep: a space, a scene and the levels traced.
struct Case {
    sweep: &'static str,
    label: String,
    x: f64,
    space: Space,
    scene: Scene,
    levels: u32,
    /// The pass's render scale; the CPU and GPU headless trace that
    /// fraction of the size.
    scale: f32,
}

/// Best times of one point, in ms, and how busy SIMD lanes are.
struct Times {
    cpu: f64,
    gpu: f64,
    /// The GPU's trace alone, once uploaded, by the device's clock
    /// ([`GpuTracer::time_trace`]): what `gpu` costs without the packing,
    /// upload and read-back.
    trace: f64,
    pass: f64,
    /// [`lane_occupancy`] of the CPU image.
    lanes: f64,
}

/// Lanes of the SIMD width that lavapipe runs (8 f32 on 256-bit
/// vectors).
const LANES: usize = 8;

/// The fraction of SIMD lane-passes doing work when rays run 8 abreast
/// along a row, as llvmpipe vectorises them: each ray walks its faces
/// crossed plus one segments, and a group of 8 lasts as long as its
/// longest ray, so `sum(passes) / (8 * sum(max passes per group))`. One
/// minus this bounds what compacting finished rays (a wavefront or
/// persistent-thread scheme) could save on the walk.
fn lane_occupancy(img: &TraceImage) -> f64 {
    let width = img.width as usize;
    let (mut work, mut paid) = (0u64, 0u64);
    for row in img.pixels.chunks(width.max(1)) {
        for group in row.chunks(LANES) {
            let passes = group.iter().map(|p| u64::from(p.levels) + 1);
            work += passes.clone().sum::<u64>();
            paid += passes.max().unwrap_or(0) * LANES as u64;
        }
    }
    if paid == 0 { 1.0 } else { work as f64 / paid as f64 }
}

fn cases(only: &str) -> Result<Vec<Case>, String> {
    let mut out = Vec::new();
    let wanted = |s: &str| s.contains(only);
    if wanted("levels") {
        for name in catalog::NAMES {
            let space = catalog::resolve(name)?;
            for levels in [1, 2, 4, 8, 16] {
                out.push(Case {
                    sweep: "levels",
                    label: (*name).to_string(),
                    x: f64::from(levels),
                    scene: Scene::default_for(&space),
                    space: space.clone(),
                    levels,
                    scale: 1.0,
                });
            }
        }
    }
    if wanted("faces") {
        for (name, space) in faces::spaces()? {
            out.push(Case {
                sweep: "faces",
                label: name,
                x: space.faces().len() as f64,
                scene: Scene::default_for(&space),
                space,
                levels: 8,
                scale: 1.0,
            });
        }
    }
    let sw = catalog::seifert_weber();
    if wanted("balls") {
        for n in [1usize, 4, 16, 64, 128] {
            let mut scene = swarm(&sw, n - 1, 11);
            scene.edge_radius = None;
            out.push(Case {
                sweep: "balls",
                label: "seifert-weber".into(),
                x: n as f64,
                scene,
                space: sw.clone(),
                levels: 8,
                scale: 1.0,
            });
        }
    }
    if wanted("triangles") {
        let suzanne = builtin::suzanne();
        for k in [1, 3, 10] {
            let mesh = if k == 1 {
                suzanne.mesh.clone()
            } else {
                meshes::subdivide(&suzanne.mesh, k)
            };
            let triangles = mesh.triangles.len();
            let data = Arc::new(MeshData::build(mesh));
            let mut scene = Scene::default_for(&sw);
            scene.balls.clear();
            let facing = isometry::rotation(glam::DVec3::Y, 0.4);
            scene.meshes.push(SceneMesh::new(
                data,
                MeshMaterial::default(),
                facing,
                0.12 * sw.inradius(),
            ));
            out.push(Case {
                sweep: "triangles",
                label: "seifert-weber".into(),
                x: triangles as f64,
                scene,
                space: sw.clone(),
                levels: 8,
                scale: 1.0,
            });
        }
    }
    if wanted("scale") {
        for scale in [1.0, 0.75, 0.5, 0.35, 0.25] {
            out.push(Case {
                sweep: "scale",
                label: "seifert-weber".into(),
                x: scale,
                scene: Scene::default_for(&sw),
                space: sw.clone(),
                levels: 8,
                scale: scale as f32,
            });
        }
    }
    Ok(out)
}

/// A headless Bevy app drawing `case` with the pass into a target of the
/// benchmark's size; meshes go on the root as [`ManifoldMeshes`].
fn pass_app(case: &Case, settings: &TraceSettings) -> Result<(App, Handle<Image>), String> {
    let mut app = offscreen::app(true);
    let image = offscreen::target(&mut app, settings.width, settings.height);
    let camera = ManifoldCamera {
        levels: case.levels,
        max_distance: settings.max_distance as f32,
        reflections: settings.reflections,
    };
    let (root, _) = offscreen::spawn_view(
        &mut app,
        &case.space,
        &case.scene,
        &image,
        (camera, ManifoldRenderScale(case.scale)),
    );
    if !case.scene.meshes.is_empty() {
        // After the first gathering, which would replace them (nothing
        // moves afterwards, so they stay).
        app.update();
        app.update();
        app.world_mut().entity_mut(root).insert(ManifoldMeshes {
            entities: vec![root; case.scene.meshes.len()],
            meshes: case.scene.meshes.clone(),
        });
        app.update();
        let drawn = app
            .world()
            .get::<bevy_manifold::drawables::ManifoldScene>(root)
            .map_or(0, |s| s.scene().meshes.len());
        if drawn != case.scene.meshes.len() {
            return Err(format!(
                "the pass's scene holds {drawn} meshes, not {}",
                case.scene.meshes.len()
            ));
        }
    }
    Ok((app, image))
}

/// Times one point, the three tracers in turn `runs` times over.
fn time(case: &Case, tracer: &mut GpuTracer, width: u32, height: u32, runs: u32) -> Result<Times, String> {
    let full = TraceSettings {
        width,
        height,
        levels: case.levels,
        ..TraceSettings::default()
    };
    let (mut app, image) = pass_app(case, &full)?;
    let traced = ManifoldRenderScale(case.scale).traced_size(UVec2::new(width, height));
    let settings = TraceSettings {
        width: traced.x,
        height: traced.y,
        ..full
    };
    // Untimed first calls: pipelines compiled, tables grown.
    tracer
        .render(&case.space, &case.scene, &settings)
        .map_err(|e| e.to_string())?;
    offscreen::wait_for_pipelines(&mut app)?;
    let mut best = Times {
        cpu: f64::INFINITY,
        gpu: f64::INFINITY,
        trace: trace_ms(tracer, &case.space, &case.scene, &settings, runs.max(3))?,
        pass: f64::INFINITY,
        lanes: lane_occupancy(&render::<f32>(&case.space, &case.scene, &settings)),
    };
    for _ in 0..runs {
        let t = Instant::now();
        std::hint::black_box(render::<f32>(&case.space, &case.scene, &settings));
        best.cpu = best.cpu.min(t.elapsed().as_secs_f64() * 1e3);
        let t = Instant::now();
        std::hint::black_box(
            tracer
                .render(&case.space, &case.scene, &settings)
                .map_err(|e| e.to_string())?,
        );
        best.gpu = best.gpu.min(t.elapsed().as_secs_f64() * 1e3);
        best.pass = best.pass.min(frame_ms(&mut app, &image, 1)?);
    }
    Ok(best)
}

/// Runs the sweeps, printing each point as it is measured, then the CSV
/// and the plot.
///
/// # Errors
/// No GPU adapter, a space that does not build, or a file not written.
pub fn run(args: &CompareArgs) -> Result<(), String> {
    let (width, height, runs) = (args.width.max(1), args.height.max(1), args.runs.max(1));
    let mut tracer = GpuTracer::new().map_err(|e| e.to_string())?;
    let cases = cases(&args.only)?;
    println!(
        "CPU f32 reference ({} threads), GPU headless and the pass in Bevy on {}, {width}x{height}, best of {runs} interleaved; ms",
        rayon::current_num_threads(),
        tracer.adapter_name()
    );
    println!(
        "(trace: the GPU's compute pass alone by the device's clock, median of {})",
        runs.max(3)
    );
    println!(
        "{:<10} {:<22} {:>8} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>7}",
        "sweep", "space", "x", "CPU", "GPU", "trace", "pass", "CPU/GPU", "pass/GPU", "lanes"
    );
    let mut csv = String::from("sweep,space,x,levels,cpu_ms,gpu_ms,trace_ms,pass_ms,lane_occupancy\n");
    let mut results = Vec::new();
    let mut progress = Progress::new(cases.len());
    for case in &cases {
        let t = time(case, &mut tracer, width, height, runs)?;
        progress.step(&case.label);
        println!(
            "{:<10} {:<22} {:>8} {:>9.1} {:>9.1} {:>9.2} {:>9.1} {:>9.2} {:>9.2} {:>6.1}%",
            case.sweep,
            case.label,
            case.x,
            t.cpu,
            t.gpu,
            t.trace,
            t.pass,
            t.cpu / t.gpu,
            t.pass / t.gpu,
            t.lanes * 100.0
        );
        let _ = writeln!(
            csv,
            "{},{},{},{},{:.3},{:.3},{:.3},{:.3},{:.4}",
            case.sweep, case.label, case.x, case.levels, t.cpu, t.gpu, t.trace, t.pass, t.lanes
        );
        results.push((case, t));
    }
    std::fs::create_dir_all(&args.out).map_err(|e| format!("{}: {e}", args.out.display()))?;
    let csv_path = args.out.join("compare.csv");
    std::fs::write(&csv_path, csv).map_err(|e| format!("{}: {e}", csv_path.display()))?;
    let panels = panels(&results);
    let png = args.out.join("compare.png");
    match draw(&png, &panels, 2, 0.1) {
        Ok(()) => println!("\nwrote {} and {}", csv_path.display(), png.display()),
        Err(e) => println!("\nwrote {} ({e})", csv_path.display()),
    }
    Ok(())
}

/// One panel per sweep: each tracer's frame time against the swept
/// quantity (the levels sweep in Seifert-Weber and the torus).
fn panels(results: &[(&Case, Times)]) -> Vec<Panel> {
    const TRACERS: [(&str, (u8, u8, u8)); 3] =
        [("CPU", (200, 60, 40)), ("GPU", (40, 90, 200)), ("pass", (40, 160, 70))];
    let mut out = Vec::new();
    for (sweep, x_label, spaces) in [
        ("levels", "levels", &["seifert-weber", "torus"][..]),
        ("faces", "faces of the domain", &[][..]),
        ("balls", "balls", &[][..]),
        ("triangles", "triangles", &[][..]),
        ("scale", "render scale", &[][..]),
    ] {
        let points: Vec<&(&Case, Times)> = results.iter().filter(|(c, _)| c.sweep == sweep).collect();
        if points.is_empty() {
            continue;
        }
        let mut series = Vec::new();
        let groups: Vec<Option<&str>> = if spaces.is_empty() {
            vec![None]
        } else {
            spaces.iter().map(|s| Some(*s)).collect()
        };
        for (g, group) in groups.iter().enumerate() {
            for (k, (name, (r, gr, b))) in TRACERS.iter().enumerate() {
                let mut pts: Vec<(f64, f64)> = points
                    .iter()
                    .filter(|(c, _)| group.is_none_or(|s| c.label == s))
                    .map(|(c, t)| (c.x, [t.cpu, t.gpu, t.pass][k]))
                    .collect();
                pts.sort_by(|a, b| a.0.total_cmp(&b.0));
                // A second group in lighter shades.
                let fade = |v: u8| if g == 0 { v } else { v / 2 + 120 };
                series.push(Series {
                    label: group.map_or_else(|| (*name).to_string(), |s| format!("{name} {s}")),
                    color: (fade(*r), fade(*gr), fade(*b)),
                    points: pts,
                    // Faces come from different spaces: points, not a curve.
                    line: sweep != "faces",
                });
            }
        }
        out.push(Panel {
            title: format!("frame time against {x_label}"),
            x: x_label.into(),
            y: "ms".into(),
            series,
            front: Vec::new(),
        });
    }
    out
}
