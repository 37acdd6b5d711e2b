//! `bevy_manifold product`: a view of a space of the product geometries
//! (H2xR, S2xR), traced on the CPU by the math crate's reference tracer
//! (or with `--gpu` by its WGSL twin) and written as a PNG; or a product
//! tour's frames (`--tour`).

use bevy_manifold::space::product::ProductSpace;
use bevy_manifold::tour::product::ProductTour;
use bevy_manifold::trace::product::{ProductEdges, ProductPixel, ProductScene, render};
use bevy_manifold_gpu::GpuTracer;
use clap::Args;
use std::path::PathBuf;

#[derive(Args)]
pub struct ProductArgs {
    /// The space: `s2xs1`, `twisted-s2xs1` (the sphere turned by 1/k of a
    /// turn round the circle), `genus2xs1` (a closed genus-2 surface x S1),
    /// `twisted-genus2xs1` (turned by k eighths of a turn),
    /// `mirrored-prism` (the right-angled pentagon x interval, all
    /// mirrors), or a product space file (`.json`, as `--export` writes).
    #[arg(long, value_name = "NAME|FILE", required_unless_present = "tour")]
    space: Option<String>,
    /// A product tour file (`*.product-tour.json`): its frames, into the
    /// directory `--out` (or with `--time`, the one frame, into the PNG
    /// `--out`).
    #[arg(long, value_name = "FILE", conflicts_with_all = ["space", "export"])]
    tour: Option<PathBuf>,
    /// Frames per second of the tour.
    #[arg(long, default_value_t = 24, value_parser = clap::value_parser!(u32).range(1..=240), requires = "tour")]
    fps: u32,
    /// The one moment of the tour to draw, in seconds.
    #[arg(long, requires = "tour", value_parser = seconds)]
    time: Option<f64>,
    /// The length of the circle (or interval) of a named space.
    #[arg(long, default_value_t = 2.0, value_parser = length, allow_negative_numbers = true)]
    length: f64,
    /// The twist of the twisted spaces: 1/k of a turn of the sphere, k
    /// eighths of a turn of the genus-2 surface.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=64))]
    twist: u32,
    /// Width in pixels.
    #[arg(long, default_value_t = 480, value_parser = clap::value_parser!(u32).range(1..=4096))]
    width: u32,
    /// Height in pixels.
    #[arg(long, default_value_t = 270, value_parser = clap::value_parser!(u32).range(1..=4096))]
    height: u32,
    /// The PNG to write.
    #[arg(long, required_unless_present = "export")]
    out: Option<PathBuf>,
    /// Print the space's file (JSON) instead of drawing it.
    #[arg(long)]
    export: bool,
    /// Trace on the GPU (the WGSL twin of the CPU reference, f32) instead
    /// of the CPU; without a GPU adapter, a warning and the CPU.
    #[arg(long)]
    gpu: bool,
    /// Shade each copy of the prism in its own colour, by its exact cell
    /// (the paper's per-cell shading).
    #[arg(long)]
    cells: bool,
    /// Light the balls by two point lights, every image of each, with
    /// shadows (`ProductScene::lit_for`), instead of from the eye.
    #[arg(long)]
    lights: bool,
    /// Draw the prism's edges as tubes of the product metric of this
    /// radius (`ProductScene::edges`).
    #[arg(long, value_name = "RADIUS", value_parser = radius)]
    edges: Option<f64>,
    /// Add two meshes, traced in the product metric: the airplane and a
    /// box (`ProductScene::furnished_for`).
    #[arg(long)]
    meshes: bool,
}

/// The space named, or read from its file.
fn space_of(args: &ProductArgs) -> Result<ProductSpace, String> {
    let path = args.space.as_deref().unwrap_or_default();
    if let Some(space) = ProductSpace::named(path, args.length, args.twist) {
        return Ok(space);
    }
    let text = std::fs::read_to_string(path).map_err(|e| {
        format!(
            "{path}: {e} (not a product space file, nor one of {})",
            ProductSpace::NAMES.join(", ")
        )
    })?;
    ProductSpace::from_json(&text, path).map_err(|e| e.to_string())
}

fn seconds(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v >= 0.0 => Ok(v),
        Ok(v) => Err(format!("must be 0 or more, got {v}")),
        Err(e) => Err(e.to_string()),
    }
}

fn radius(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 && v <= 1.0 => Ok(v),
        Ok(v) => Err(format!("must be more than 0 and at most 1, got {v}")),
        Err(e) => Err(e.to_string()),
    }
}

fn length(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.01 && v <= 100.0 => Ok(v),
        Ok(v) => Err(format!("must be between 0.01 and 100, got {v}")),
        Err(e) => Err(e.to_string()),
    }
}

/// Renders the view (or the tour) and writes it.
pub fn run(args: &ProductArgs) -> Result<(), String> {
    if let Some(tour) = &args.tour {
        return run_tour(args, tour);
    }
    let space = space_of(args)?;
    space.validate().map_err(|e| e.to_string())?;
    if args.export {
        println!("{}", space.to_json());
        return Ok(());
    }
    let Some(out) = &args.out else {
        return Err("--out FILE.png is needed to draw the space".into());
    };
    let mut scene = if args.lights {
        ProductScene::lit_for(&space)
    } else {
        ProductScene::default_for(&space)
    };
    if args.meshes {
        scene.meshes = ProductScene::furnished_for(&space).meshes;
    }
    if args.cells {
        scene.view.tint = Some(bevy_manifold::space::cells::CellTint::ByCell);
    }
    scene.edges = args.edges.map(|radius| ProductEdges {
        radius,
        ..ProductEdges::default()
    });
    let mut gpu = args.gpu.then(gpu_tracer).flatten();
    let on = if gpu.is_some() { "GPU" } else { "CPU" };
    write_png(
        &trace(&space, &scene, gpu.as_mut(), (args.width, args.height))?,
        out,
        (args.width, args.height),
    )?;
    println!(
        "wrote {} ({}x{}, {}, traced on the {on})",
        out.display(),
        args.width,
        args.height,
        space.name
    );
    Ok(())
}

/// The tour's frames, or its one frame at `--time`.
fn run_tour(args: &ProductArgs, path: &std::path::Path) -> Result<(), String> {
    let tour = ProductTour::load(path).map_err(|e| e.to_string())?;
    let Some(out) = &args.out else {
        return Err("--out is needed: a directory for the frames (a PNG with --time)".into());
    };
    let size = (args.width, args.height);
    let mut gpu = args.gpu.then(gpu_tracer).flatten();
    if let Some(t) = args.time {
        write_png(&trace(&tour.space, &tour.scene_at(t), gpu.as_mut(), size)?, out, size)?;
        println!(
            "wrote {} ({}, {t} s of {} s)",
            out.display(),
            tour.space.name,
            tour.duration()
        );
        return Ok(());
    }
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let frames = (tour.duration() * f64::from(args.fps)).ceil() as u64 + 1;
    for k in 0..frames {
        let t = k as f64 / f64::from(args.fps);
        let file = out.join(format!("frame_{k:05}.png"));
        write_png(&trace(&tour.space, &tour.scene_at(t), gpu.as_mut(), size)?, &file, size)?;
    }
    println!(
        "wrote {frames} frames of {} ({} s at {} fps) into {}",
        tour.space.name,
        tour.duration(),
        args.fps,
        out.display()
    );
    Ok(())
}

/// The GPU tracer, or a warning and none.
fn gpu_tracer() -> Option<GpuTracer> {
    GpuTracer::new()
        .map_err(|e| eprintln!("warning: {e}; tracing on the CPU instead"))
        .ok()
}

/// The scene's pixels, on the GPU where there is one.
pub(crate) fn trace(
    space: &ProductSpace,
    scene: &ProductScene,
    gpu: Option<&mut GpuTracer>,
    (w, h): (u32, u32),
) -> Result<Vec<ProductPixel>, String> {
    match gpu {
        Some(gpu) => gpu
            .render_product(space, scene, w, h)
            .map_err(|e| format!("{}: {e}", space.name)),
        None => Ok(render(space, scene, w, h)),
    }
}

/// The pixels' colours written as an sRGB PNG.
pub(crate) fn write_png(pixels: &[ProductPixel], out: &std::path::Path, (w, h): (u32, u32)) -> Result<(), String> {
    let bytes: Vec<u8> = pixels
        .iter()
        .flat_map(|p| p.color.map(bevy_manifold::trace::srgb8).into_iter().chain([255]))
        .collect();
    image::save_buffer(out, &bytes, w, h, image::ExtendedColorType::Rgba8)
        .map_err(|e| format!("{}: {e}", out.display()))
}
