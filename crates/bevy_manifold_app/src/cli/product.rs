//! `bevy_manifold product`: a view of a space of the product geometries
//! (H2xR, S2xR), traced on the CPU by the math crate's reference tracer
//! (or with `--gpu` by its WGSL twin) and written as a PNG.

use bevy_manifold::space::product::ProductSpace;
use bevy_manifold::trace::product::{ProductScene, render};
use clap::Args;
use std::path::PathBuf;

#[derive(Args)]
pub struct ProductArgs {
    /// The space: `s2xs1`, `twisted-s2xs1` (the sphere turned by 1/k of a
    /// turn round the circle), `genus2xs1` (a closed genus-2 surface x S1),
    /// `twisted-genus2xs1` (turned by k eighths of a turn),
    /// `mirrored-prism` (the right-angled pentagon x interval, all
    /// mirrors), or a product space file (`.json`, as `--export` writes).
    #[arg(long, value_name = "NAME|FILE")]
    space: String,
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
}

/// The space named, or read from its file.
fn space_of(args: &ProductArgs) -> Result<ProductSpace, String> {
    if let Some(space) = ProductSpace::named(&args.space, args.length, args.twist) {
        return Ok(space);
    }
    let path = &args.space;
    let text = std::fs::read_to_string(path).map_err(|e| {
        format!(
            "{path}: {e} (not a product space file, nor one of {})",
            ProductSpace::NAMES.join(", ")
        )
    })?;
    ProductSpace::from_json(&text, path).map_err(|e| e.to_string())
}

fn length(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.01 && v <= 100.0 => Ok(v),
        Ok(v) => Err(format!("must be between 0.01 and 100, got {v}")),
        Err(e) => Err(e.to_string()),
    }
}

/// Renders the view and writes it.
pub fn run(args: &ProductArgs) -> Result<(), String> {
    let space = space_of(args)?;
    space.validate().map_err(|e| e.to_string())?;
    if args.export {
        println!("{}", space.to_json());
        return Ok(());
    }
    let Some(out) = &args.out else {
        return Err("--out FILE.png is needed to draw the space".into());
    };
    let scene = ProductScene::default_for(&space);
    let (w, h) = (args.width, args.height);
    let gpu = if args.gpu {
        match bevy_manifold_gpu::GpuTracer::new() {
            Ok(mut tracer) => Some(
                tracer
                    .render_product(&space, &scene, w, h)
                    .map_err(|e| format!("{}: {e}", space.name))?,
            ),
            Err(e) => {
                eprintln!("warning: {e}; tracing on the CPU instead");
                None
            }
        }
    } else {
        None
    };
    let traced = gpu.is_some();
    let pixels = gpu.unwrap_or_else(|| render(&space, &scene.balls, &scene.view, w, h));
    let bytes: Vec<u8> = pixels
        .iter()
        .flat_map(|p| p.color.map(bevy_manifold::trace::srgb8).into_iter().chain([255]))
        .collect();
    image::save_buffer(out, &bytes, w, h, image::ExtendedColorType::Rgba8)
        .map_err(|e| format!("{}: {e}", out.display()))?;
    let on = if traced { "GPU" } else { "CPU" };
    println!("wrote {} ({w}x{h}, {}, traced on the {on})", out.display(), space.name);
    Ok(())
}
