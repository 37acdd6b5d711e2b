//! `bevy_manifold tour`: check a tour file, and render it offline frame by
//! frame (frame `k` is the camera at `k / fps`), as a PNG sequence, a
//! WebVTT file of its captions and, when `ffmpeg` is on PATH, an MP4.

use bevy_manifold::space::Space;
use bevy_manifold::tour::Tour;
use bevy_manifold::trace::{Projection, Scene, TraceImage, TraceSettings, write_ids_png, write_png};
use bevy_manifold_gpu::GpuTracer;
use clap::{Args, Subcommand, ValueEnum};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The `tour` subcommands.
#[derive(Subcommand)]
pub enum TourCommand {
    /// Validate a tour file and describe it: space, length, keyframes,
    /// captions.
    Check {
        /// The tour file (JSON).
        tour: PathBuf,
    },
    /// Render every frame of a tour to a folder of PNGs (and an MP4 when
    /// ffmpeg is on PATH).
    Render(TourRenderArgs),
}

/// How the frames of `tour render` see.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ProjectionArg {
    /// The tour's camera, its field of view.
    Perspective,
    /// 360 degree mono panorama (equirectangular, 2:1).
    Equirect,
    /// Omni-directional stereo, top-bottom (left eye above), 1:1.
    Ods,
}

/// The flags of `tour render`.
#[derive(Args)]
pub struct TourRenderArgs {
    /// The tour file (JSON).
    tour: PathBuf,
    /// Frames per second.
    #[arg(long, default_value_t = 60.0)]
    fps: f64,
    /// Frame size, WIDTHxHEIGHT.
    #[arg(long, default_value = "1920x1080")]
    size: String,
    /// The folder the frames go to (made if missing).
    #[arg(long)]
    out: PathBuf,
    /// Only frames FIRST..END (END excluded), e.g. `--frames 120..180`.
    #[arg(long)]
    frames: Option<String>,
    /// The projection.
    #[arg(long, value_enum, default_value_t = ProjectionArg::Perspective)]
    projection: ProjectionArg,
    /// With --projection ods: the distance between the eyes, in the
    /// space's units.
    #[arg(long, default_value_t = 0.06)]
    eye_separation: f64,
    /// Also write each frame's id buffer (`ids_NNNNN.png`).
    #[arg(long)]
    ids: bool,
    /// Also write each frame's linear colour, unclamped, as OpenEXR
    /// (`frame_NNNNN.exr`, 32-bit float RGB) for grading elsewhere.
    #[arg(long)]
    exr: bool,
    /// Traces per pixel of each frame, averaged (anti-aliasing, soft
    /// shadows; with --path-trace, path samples). 1 to 256.
    #[arg(long, default_value_t = 1)]
    samples: u32,
    #[command(flatten)]
    path: super::PathArgs,
    /// Use the CPU reference tracer instead of the GPU (f64 unless --f32).
    #[arg(long)]
    cpu: bool,
    /// With --cpu: trace in f32, the GPU's precision.
    #[arg(long)]
    f32: bool,
    /// Do not make an MP4 even when ffmpeg is on PATH.
    #[arg(long)]
    no_video: bool,
}

/// Runs a `tour` subcommand.
///
/// # Errors
/// A broken tour file (named by file, entry and field), bad flags, or a
/// frame that cannot be traced or written.
pub fn run(command: &TourCommand) -> Result<(), String> {
    match command {
        TourCommand::Check { tour } => check(tour),
        TourCommand::Render(args) => render(args),
    }
}

fn load(path: &Path) -> Result<(Space, Tour), String> {
    Tour::load(path).map_err(|e| e.to_string())
}

fn check(path: &Path) -> Result<(), String> {
    let (space, tour) = load(path)?;
    println!("{}: {} space, {:.2} s", path.display(), space.name(), tour.duration());
    println!("keyframes (legs expanded): {}", tour.path.keys().len());
    for (t, caption) in tour.captions() {
        if !caption.is_empty() {
            println!("{t:7.2} s  {caption}");
        }
    }
    Ok(())
}

/// Pixels a CPU tour traces from which it grows the table of exact cells
/// first: two 1920x1080 frames.
const GROW_TABLE_PIXELS: u64 = 2 * 1920 * 1080;

/// `WIDTHxHEIGHT`.
fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("--size {s}: expected WIDTHxHEIGHT, e.g. 1920x1080");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    Ok((
        w.trim().parse().map_err(|_| bad())?,
        h.trim().parse().map_err(|_| bad())?,
    ))
}

/// `FIRST..END`.
fn parse_frames(s: &str, total: u64) -> Result<(u64, u64), String> {
    let bad = || format!("--frames {s}: expected FIRST..END with FIRST < END <= {total}");
    let (a, b) = s.split_once("..").ok_or_else(bad)?;
    let (a, b): (u64, u64) = (
        a.trim().parse().map_err(|_| bad())?,
        b.trim().parse().map_err(|_| bad())?,
    );
    if a < b && b <= total { Ok((a, b)) } else { Err(bad()) }
}

/// The number of frames of a tour of `duration` seconds at `fps`: every
/// `k / fps` from 0 to the end, the end included.
#[must_use]
pub fn frame_count(duration: f64, fps: f64) -> u64 {
    (duration * fps + 1e-9).floor() as u64 + 1
}

/// The scene and settings of frame `k`: what `tour render` traces.
#[must_use]
pub fn frame_scene(
    space: &Space,
    tour: &Tour,
    k: u64,
    fps: f64,
    size: (u32, u32),
    projection: Projection,
) -> (bevy_manifold::trace::Scene, TraceSettings) {
    let (scene, mut settings) = tour.scene_at(space, k as f64 / fps, size.0, size.1);
    settings.projection = projection;
    (scene, settings)
}

fn render(args: &TourRenderArgs) -> Result<(), String> {
    let (space, tour) = load(&args.tour)?;
    if !(args.fps.is_finite() && args.fps > 0.0 && args.fps <= 1000.0) {
        return Err(format!("--fps {}: must be in (0, 1000]", args.fps));
    }
    let size = parse_size(&args.size)?;
    let (path_depth, seed) = args.path.depth_and_seed()?;
    let check = TraceSettings {
        width: size.0,
        height: size.1,
        path_depth,
        ..TraceSettings::default()
    };
    check.check().map_err(|e| format!("tour render: {e}"))?;
    if !(1..=256).contains(&args.samples) {
        return Err(format!("--samples must be between 1 and 256, got {}", args.samples));
    }
    if !(args.eye_separation.is_finite() && args.eye_separation >= 0.0 && args.eye_separation < 1.0) {
        return Err(format!("--eye-separation {}: must be in [0, 1)", args.eye_separation));
    }
    let projection = match args.projection {
        ProjectionArg::Perspective => Projection::Perspective,
        ProjectionArg::Equirect => Projection::Equirect,
        ProjectionArg::Ods => Projection::Ods {
            eye_separation: args.eye_separation,
        },
    };
    let total = frame_count(tour.duration(), args.fps);
    let (first, end) = match &args.frames {
        Some(s) => parse_frames(s, total)?,
        None => (0, total),
    };
    std::fs::create_dir_all(&args.out).map_err(|e| format!("{}: {e}", args.out.display()))?;
    let mut gpu = None;
    if !args.cpu {
        match GpuTracer::new() {
            Ok(g) => gpu = Some(g),
            Err(e) => eprintln!("warning: {e}; rendering with the CPU reference tracer instead"),
        }
    }
    // On the CPU, where the space's ids are exact, its table of cells is
    // grown first (0.2 s in Seifert-Weber, 0.5 s in the mirrored
    // dodecahedron, `bench cells`) so that rays cross faces near the
    // camera by index rather than by exact products, when there are
    // enough pixels to repay it: three 1920x1080 frames took 4.6-5.0 s
    // with it against 6.5, one 640x360 frame 0.4 s against 0.3
    // (docs/benchmarks/history.md, "The table of cells around the camera, on the CPU
    // too"). The GPU grows it when it packs the space.
    let pixels = u64::from(size.0) * u64::from(size.1) * (end - first);
    if gpu.is_none()
        && pixels >= GROW_TABLE_PIXELS
        && let bevy_manifold::space::cells::CellScheme::Exact(exact) = space.cells()
    {
        exact.table();
    }
    let tracer = gpu.as_ref().map_or_else(
        || format!("CPU {}", if args.f32 { "f32" } else { "f64" }),
        |g| format!("GPU: {}", g.adapter_name()),
    );
    eprintln!(
        "{}: {} frames of {}x{} at {} fps ({:.2} s of {} space), {tracer}",
        args.tour.display(),
        end - first,
        size.0,
        size.1,
        args.fps,
        tour.duration(),
        space.name()
    );
    let started = Instant::now();
    for k in first..end {
        let (scene, mut settings) = frame_scene(&space, &tour, k, args.fps, size, projection);
        settings.path_depth = path_depth;
        settings.seed = seed;
        let mut trace = |scene: &Scene, settings: &TraceSettings| -> Result<TraceImage, String> {
            Ok(match gpu.as_mut() {
                Some(g) => g
                    .render(&space, scene, settings)
                    .map_err(|e| format!("frame {k}: {e}"))?,
                None if args.f32 => bevy_manifold::trace::render::<f32>(&space, scene, settings),
                None => bevy_manifold::trace::render::<f64>(&space, scene, settings),
            })
        };
        let mut image = trace(&scene, &settings)?;
        crate::policy::add_samples(&mut image, &scene, &settings, args.samples, &mut trace)?;
        let file = args.out.join(format!("frame_{k:05}.png"));
        write_png(&image, &file).map_err(|e| format!("{}: {e}", file.display()))?;
        if args.exr {
            let file = args.out.join(format!("frame_{k:05}.exr"));
            bevy_manifold::trace::write_exr(&image, &file).map_err(|e| format!("{}: {e}", file.display()))?;
        }
        if args.ids {
            let file = args.out.join(format!("ids_{k:05}.png"));
            write_ids_png(&image, &file).map_err(|e| format!("{}: {e}", file.display()))?;
        }
        let done = k + 1 - first;
        let per = started.elapsed().as_secs_f64() / done as f64;
        let left = per * (end - k - 1) as f64;
        eprint!(
            "\r[{:<30}] {done}/{} frames, {per:.2} s/frame, {} left   ",
            "#".repeat((30 * done / (end - first)) as usize),
            end - first,
            clock(left)
        );
    }
    eprintln!();
    let secs = started.elapsed().as_secs_f64();
    eprintln!(
        "rendered {} frames in {:.1} s ({:.3} s/frame) -> {}",
        end - first,
        secs,
        secs / (end - first) as f64,
        args.out.display()
    );
    let vtt = args.out.join("captions.vtt");
    std::fs::write(&vtt, captions_vtt(&tour)).map_err(|e| format!("{}: {e}", vtt.display()))?;
    if !args.no_video {
        video(args, first)?;
    }
    Ok(())
}

fn clock(secs: f64) -> String {
    let s = secs.max(0.0).round() as u64;
    format!("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
}

/// The tour's captions as WebVTT (players and ffmpeg read it).
#[must_use]
pub fn captions_vtt(tour: &Tour) -> String {
    let stamp = |t: f64| {
        let ms = (t.max(0.0) * 1000.0).round() as u64;
        format!(
            "{:02}:{:02}:{:02}.{:03}",
            ms / 3_600_000,
            ms / 60_000 % 60,
            ms / 1000 % 60,
            ms % 1000
        )
    };
    let mut out = String::from("WEBVTT\n");
    let caps = tour.captions();
    for (i, (t, text)) in caps.iter().enumerate() {
        if text.is_empty() {
            continue;
        }
        let end = caps.get(i + 1).map_or(tour.duration(), |c| c.0).max(*t);
        out.push_str(&format!("\n{} --> {}\n{text}\n", stamp(*t), stamp(end)));
    }
    out
}

/// An MP4 of the frames by ffmpeg, or a clear word that it is not there.
fn video(args: &TourRenderArgs, first: u64) -> Result<(), String> {
    let have = std::process::Command::new("ffmpeg")
        .arg("-version")
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    let pattern = args.out.join("frame_%05d.png");
    let mp4 = args.out.join("tour.mp4");
    let command = format!(
        "ffmpeg -y -framerate {} -start_number {first} -i {} -c:v libx264 -pix_fmt yuv420p {}",
        args.fps,
        pattern.display(),
        mp4.display()
    );
    if !have {
        eprintln!("ffmpeg is not on PATH: no MP4 made, the PNG frames are all there. To make one: {command}");
        return Ok(());
    }
    let status = std::process::Command::new("ffmpeg")
        .args(["-y", "-loglevel", "error", "-framerate", &args.fps.to_string()])
        .args(["-start_number", &first.to_string(), "-i"])
        .arg(&pattern)
        .args(["-c:v", "libx264", "-pix_fmt", "yuv420p"])
        .arg(&mp4)
        .status()
        .map_err(|e| format!("ffmpeg: {e}"))?;
    if status.success() {
        eprintln!("video -> {}", mp4.display());
        Ok(())
    } else {
        Err(format!(
            "ffmpeg failed ({status}); the PNG frames are in {}",
            args.out.display()
        ))
    }
}
