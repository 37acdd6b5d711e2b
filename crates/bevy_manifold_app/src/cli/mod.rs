//! The `bevy_manifold` command line: parsing and dispatch. The command names and flags are a
//! contract other tools rely on; change them only by adding.

use bevy_manifold_bench as bench;
mod cell;
mod library;
pub(crate) mod product;
mod show;
pub mod tour;

use crate::policy::{UsedTracer, render_samples};
use bevy_manifold::prelude::*;
use bevy_manifold::space::rule::{CellRule, OnOff, Walls};
use bevy_manifold::trace::{PaperOptions, write_ids_png, write_png};
use clap::{Args, Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "bevy_manifold",
    version,
    about = "Look inside non-Euclidean 3-manifolds and orbifolds by ray tracing"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// The explorer (what running with no command opens).
    Explore {
        /// The space to open: a catalog or library name (`space list`,
        /// `space library`), or a space file (`.space.json`, `.gen`,
        /// `.gens.json`); also in a headset (`--xr`). Default: the space
        /// the explorer last showed.
        #[arg(long, value_name = "NAME|FILE")]
        space: Option<String>,
        /// Quit after this many frames (for smoke tests).
        #[arg(long)]
        frames: Option<u32>,
        /// With --frames: save the window (panel included) to this PNG at
        /// that frame, then quit.
        #[arg(long, requires = "frames")]
        screenshot: Option<PathBuf>,
        /// Open this tour file and play it (a broken one is reported and
        /// the explorer opens without it).
        #[arg(long)]
        tour: Option<PathBuf>,
        /// In a headset, through OpenXR (SteamVR, Monado, ...): each eye
        /// traced from where it is in the space. Without a runtime it says
        /// so and stays on the desktop; without a display it runs for the
        /// headset alone.
        #[arg(long)]
        xr: bool,
        /// With --xr: metres of the room per unit of the space.
        #[arg(long, default_value_t = 4.0, requires = "xr", value_parser = positive_scale)]
        world_scale: f64,
        /// With --xr and --frames: at the last frame, save each eye's
        /// traced image (read back from its view target) as eye0.png and
        /// eye1.png in this folder.
        #[arg(long, value_name = "DIR", requires_all = ["xr", "frames"])]
        xr_capture: Option<PathBuf>,
        /// Hold this frame rate (5 to 144) by tracing fewer pixels when
        /// frames are slow; the panel shows the scale chosen.
        #[arg(long, value_name = "FPS")]
        hold_fps: Option<f32>,
    },
    /// The explorer left running on a script (every space, every setting,
    /// meshes loaded and dropped), recording memory and GPU objects: a
    /// soak test, not for CI.
    Soak(SoakArgs),
    /// Inspect and export spaces.
    #[command(subcommand)]
    Space(SpaceCommand),
    /// Render a view of a space to PNG.
    Render(RenderArgs),
    /// Render a view of a space of the product geometries (H2xR, S2xR)
    /// to PNG, on the CPU (or the GPU with `--gpu`).
    Product(product::ProductArgs),
    /// Tours: check a tour file, render it to frames and video.
    #[command(subcommand)]
    Tour(tour::TourCommand),
    /// Benchmarks.
    #[command(subcommand)]
    Bench(bench::BenchCommand),
}

#[derive(Args)]
struct SoakArgs {
    /// How long to run, in minutes.
    #[arg(long, default_value_t = 60.0)]
    minutes: f64,
    /// Seconds per script step (one space, one set of settings, one mesh).
    #[arg(long, default_value_t = 15.0)]
    step: f64,
    /// Seconds between samples of memory and GPU objects.
    #[arg(long, default_value_t = 10.0)]
    sample: f64,
    /// The CSV of samples.
    #[arg(long, default_value = "soak.csv")]
    out: PathBuf,
    /// The folder the glTF models are loaded from.
    #[arg(long, default_value = "assets")]
    assets: PathBuf,
}

#[derive(Subcommand)]
enum SpaceCommand {
    /// Print the catalog's space names, one per line.
    List,
    /// Describe a space: faces, vertices, edge cycles, radii, volume, group.
    Show {
        /// A catalog name or the path of a space file.
        name: String,
    },
    /// Print a space as JSON (the space-file format).
    Export {
        /// A catalog name or the path of a space file.
        name: String,
    },
    /// Build the Dirichlet domain of a generator file (Curved Spaces
    /// `.gen`, or a JSON generator list) and write it as a space file.
    Import {
        /// The generator file.
        file: PathBuf,
        /// Where to write the space (JSON); stdout without it.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Centre the domain at this point `x,y,z,w` (normalised onto the
        /// geometry) instead of the origin.
        #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
        basepoint: Option<Vec<f64>>,
        /// Refuse a group that does not act freely (an orbifold).
        #[arg(long)]
        manifold: bool,
    },
    /// The cell reached by crossing faces in order from the origin copy
    /// (crossing face i from cell g leads to g T_i^-1, as in the tracer):
    /// its id and group element.
    Cell {
        /// A catalog name, a library name or the path of a space file.
        name: String,
        /// The faces crossed, comma-separated (none: the origin copy).
        #[arg(long)]
        faces: Option<String>,
        /// Print one JSON object (`id`, `id_hex`, `exact`, `element`, ...).
        #[arg(long)]
        json: bool,
        /// Read one comma-separated word a line and print one JSON line per
        /// word.
        #[arg(long, conflicts_with = "faces")]
        words: Option<PathBuf>,
    },
    /// The library of spaces built from generators: one line each (name,
    /// geometry, faces, volume, group order); with --out, write their
    /// generator files there.
    Library {
        /// A folder to write `NAME.gen` files into.
        #[arg(long)]
        out: Option<PathBuf>,
    },
}

#[derive(Args)]
struct RenderArgs {
    /// A catalog name or the path of a space file.
    #[arg(long)]
    space: String,
    /// Image width in pixels.
    #[arg(long, default_value_t = 640)]
    width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 360)]
    height: u32,
    /// Output PNG.
    #[arg(long)]
    out: PathBuf,
    /// Scene file (JSON); without it, the space's default scene.
    #[arg(long)]
    scene: Option<PathBuf>,
    /// Also write the id buffer (R object, G levels, B cell id low byte).
    #[arg(long)]
    ids: Option<PathBuf>,
    /// Also write the linear colour, unclamped, as a Radiance HDR file
    /// (`.hdr`): radiance above 1 kept for tonemapping elsewhere.
    #[arg(long)]
    hdr: Option<PathBuf>,
    /// Also write the linear colour, unclamped, as an OpenEXR file
    /// (`.exr`, 32-bit float RGB).
    #[arg(long)]
    exr: Option<PathBuf>,
    /// Traces per pixel, averaged as a still view accumulates them: each
    /// with the pixel grid moved within the pixel (anti-aliasing) and the
    /// shadow rays aimed at another point of each light (soft shadows of
    /// lights with a radius). 1 to 256.
    #[arg(long, default_value_t = 1)]
    samples: u32,
    /// Most face transports per ray: the paper's levels (`--bounces` is
    /// the same flag under its earlier name).
    #[arg(long, visible_alias = "bounces", default_value_t = 8)]
    levels: u32,
    /// Reflections a ray follows off surfaces with a material (metallic
    /// and roughness), each with the levels of its own; 0 to 8 (default
    /// 0, or 1 with --mirror).
    #[arg(long)]
    reflections: Option<u32>,
    #[command(flatten)]
    path: PathArgs,
    /// Without --scene: add the mirror ball of the paper's Fig. 11 to the
    /// paper's scene (and one reflection unless --reflections says).
    #[arg(long, conflicts_with = "scene")]
    mirror: bool,
    /// Fog density (adds fog, or overrides the scene's).
    #[arg(long)]
    fog: Option<f64>,
    /// Colour objects by the copy of the domain they are seen in.
    #[arg(long)]
    cells: bool,
    /// The on/off rule by cell: objects in off cells hidden; this fraction
    /// of the cells on.
    #[arg(long)]
    hidden: Option<f32>,
    /// Walls between cells: this fraction of the faces walled (a maze).
    #[arg(long)]
    walls: Option<f32>,
    /// The seed of --hidden and --walls.
    #[arg(long, default_value_t = 1)]
    rule_seed: u32,
    /// Use the CPU reference tracer instead of the GPU (f64 unless --f32).
    #[arg(long)]
    cpu: bool,
    /// With --cpu: trace in f32, the GPU's precision, instead of f64.
    #[arg(long)]
    f32: bool,
    /// Trace each pixel as a cone (anti-aliasing: far balls and edges fade
    /// to their average colour instead of sparkling).
    #[arg(long)]
    cones: bool,
    /// The most images of each light in the cover that light a point (0:
    /// each light's copy in the domain only, as before light images);
    /// overrides the scene's.
    #[arg(long)]
    light_images: Option<u32>,
    /// Shadows through the faces: on or off (overrides the scene's).
    #[arg(long)]
    shadows: Option<Switch>,
}

/// The path tracer's flags, of `render` and `tour render`.
#[derive(Args)]
pub(crate) struct PathArgs {
    /// Path trace: each of the --samples is one sample of the rendering
    /// equation (diffuse and GGX lobes, every light image at each bounce,
    /// Russian roulette), their mean the image.
    #[arg(long)]
    path_trace: bool,
    /// With --path-trace: the most bounces of a path (1 to 64).
    #[arg(long, default_value_t = 8)]
    depth: u32,
    /// With --path-trace: the seed of the paths' random numbers.
    #[arg(long, default_value_t = 0)]
    seed: u32,
}

impl PathArgs {
    /// `TraceSettings::path_depth` (0 without --path-trace) and `seed`.
    ///
    /// # Errors
    /// --path-trace with --depth 0.
    pub(crate) fn depth_and_seed(&self) -> Result<(u32, u32), String> {
        if self.path_trace && self.depth == 0 {
            return Err("--depth must be at least 1".into());
        }
        Ok((if self.path_trace { self.depth } else { 0 }, self.seed))
    }
}

/// `on` or `off`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum Switch {
    /// On.
    On,
    /// Off.
    Off,
}

/// Parses the arguments and runs the command.
pub fn run() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        // The explorer: a window, or its headless fallback.
        None => return explore(crate::explorer::ExploreOptions::default()),
        Some(Command::Explore {
            space,
            frames,
            screenshot,
            tour,
            xr,
            world_scale,
            xr_capture,
            hold_fps,
        }) => {
            return explore(crate::explorer::ExploreOptions {
                space,
                frames,
                screenshot,
                tour,
                xr: xr.then_some(world_scale),
                xr_capture,
                hold_fps,
            });
        }
        Some(Command::Soak(args)) => return soak(&args),
        Some(Command::Space(SpaceCommand::List)) => {
            for name in catalog::NAMES {
                println!("{name}");
            }
            Ok(())
        }
        Some(Command::Space(SpaceCommand::Show { name })) => {
            resolve_space(&name).map(|s| print!("{}", show::describe(&s)))
        }
        Some(Command::Space(SpaceCommand::Export { name })) => {
            resolve_space(&name).map(|s| println!("{}", s.to_json()))
        }
        Some(Command::Space(SpaceCommand::Import {
            file,
            out,
            basepoint,
            manifold,
        })) => library::import(&file, out.as_deref(), basepoint.as_deref(), manifold),
        Some(Command::Space(SpaceCommand::Library { out })) => library::library(out.as_deref()),
        Some(Command::Space(SpaceCommand::Cell {
            name,
            faces,
            json,
            words,
        })) => resolve_space(&name).and_then(|s| cell::cell(&s, faces.as_deref(), json, words.as_deref())),
        Some(Command::Render(args)) => render_command(&args),
        Some(Command::Product(args)) => product::run(&args),
        Some(Command::Tour(t)) => tour::run(&t),
        Some(Command::Bench(b)) => bench::run(&b),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

/// `--world-scale`: a positive, finite number of metres per unit.
fn positive_scale(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 && v <= 1e6 => Ok(v),
        Ok(v) => Err(format!("must be positive and at most 1e6 metres per unit, got {v}")),
        Err(e) => Err(e.to_string()),
    }
}

fn explore(options: crate::explorer::ExploreOptions) -> ExitCode {
    match crate::explorer::run_with(options) {
        bevy::app::AppExit::Success => ExitCode::SUCCESS,
        bevy::app::AppExit::Error(_) => ExitCode::FAILURE,
    }
}

fn soak(args: &SoakArgs) -> ExitCode {
    use crate::explorer::soak::{SoakOptions, run_soak};
    let secs = |what: &str, v: f64| {
        if v.is_finite() && v > 0.0 && v < 1e7 {
            Ok(std::time::Duration::from_secs_f64(v))
        } else {
            Err(format!("--{what} {v}: it must be a positive number"))
        }
    };
    let options = (|| {
        Ok::<_, String>(SoakOptions {
            duration: secs("minutes", args.minutes * 60.0)?,
            phase: secs("step", args.step)?,
            sample: secs("sample", args.sample)?,
            out: args.out.clone(),
            assets: args.assets.clone(),
            ..SoakOptions::default()
        })
    })();
    match options {
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
        Ok(options) => match run_soak(&options) {
            bevy::app::AppExit::Success => ExitCode::SUCCESS,
            bevy::app::AppExit::Error(_) => ExitCode::FAILURE,
        },
    }
}

/// A catalog space by name, or a space file by path.
pub fn resolve_space(name: &str) -> Result<Space, String> {
    catalog::resolve(name)
}

/// The most traces per pixel `render --samples` takes (as
/// `ManifoldAccumulation::MAX_SAMPLES`).
const MAX_SAMPLES: u32 = 256;

fn render_command(args: &RenderArgs) -> Result<(), String> {
    let space = resolve_space(&args.space)?;
    let (path_depth, path_seed) = args.path.depth_and_seed()?;
    let size_check = TraceSettings {
        width: args.width,
        height: args.height,
        levels: args.levels,
        reflections: args.reflections.unwrap_or(u32::from(args.mirror)),
        path_depth,
        seed: path_seed,
        ..TraceSettings::default()
    };
    size_check.check().map_err(|e| format!("render: {e}"))?;
    if !(1..=MAX_SAMPLES).contains(&args.samples) {
        return Err(format!(
            "--samples must be between 1 and {MAX_SAMPLES}, got {}",
            args.samples
        ));
    }
    let mut scene = match &args.scene {
        Some(p) => Scene::load(p, &space).map_err(|e| e.to_string())?,
        None => Scene::paper(
            &space,
            &PaperOptions {
                mirror: args.mirror,
                ..PaperOptions::default()
            },
        ),
    };
    for why in &scene.skipped {
        eprintln!("warning: {why}");
    }
    if let Some(density) = args.fog {
        if !(density >= 0.0 && density.is_finite()) {
            return Err(format!("--fog must be a density >= 0, got {density}"));
        }
        let color = scene.fog.as_ref().map_or([0.75, 0.78, 0.82], |f| f.color);
        scene.fog = Some(Fog { density, color });
    }
    if let Some(n) = args.light_images {
        if n as usize > bevy_manifold_core::trace::MAX_LIGHT_IMAGES {
            return Err(format!(
                "--light-images must be at most {}, got {n}",
                bevy_manifold_core::trace::MAX_LIGHT_IMAGES
            ));
        }
        scene.lighting.images = n;
    }
    if let Some(s) = args.shadows {
        scene.lighting.shadows = s == Switch::On;
    }
    for (flag, v) in [("--hidden", args.hidden), ("--walls", args.walls)] {
        if let Some(f) = v
            && !(0.0..=1.0).contains(&f)
        {
            return Err(format!("{flag} must be a fraction in [0, 1], got {f}"));
        }
    }
    let seed = args.rule_seed;
    let settings = TraceSettings {
        width: args.width,
        height: args.height,
        levels: args.levels,
        cell_colors: args.cells,
        cell_rule: CellRule {
            hidden: args.hidden.map(|on_fraction| OnOff { on_fraction, seed }),
            walls: args.walls.map(|density| Walls { density, seed }),
        },
        footprint: args.cones,
        reflections: size_check.reflections,
        path_depth,
        seed: path_seed,
        ..TraceSettings::default()
    };
    let start = std::time::Instant::now();
    let (img, tracer) =
        render_samples(&space, &scene, &settings, args.samples, (args.cpu, args.f32)).map_err(|e| e.to_string())?;
    if let UsedTracer::Cpu {
        fallback: Some(why), ..
    } = &tracer
    {
        eprintln!("warning: {why}; rendered with the CPU reference tracer instead");
    }
    let secs = start.elapsed().as_secs_f64();
    write_png(&img, &args.out).map_err(|e| format!("{}: {e}", args.out.display()))?;
    if let Some(ids) = &args.ids {
        write_ids_png(&img, ids).map_err(|e| format!("{}: {e}", ids.display()))?;
    }
    if let Some(hdr) = &args.hdr {
        bevy_manifold::trace::write_hdr(&img, hdr).map_err(|e| format!("{}: {e}", hdr.display()))?;
    }
    if let Some(exr) = &args.exr {
        bevy_manifold::trace::write_exr(&img, exr).map_err(|e| format!("{}: {e}", exr.display()))?;
    }
    eprintln!(
        "rendered {} ({}x{}, {} levels{}{}, {tracer}) in {:.2} s -> {}",
        space.name(),
        args.width,
        args.height,
        args.levels,
        if args.cones { ", cones" } else { "" },
        if args.samples > 1 {
            format!(", {} samples", args.samples)
        } else {
            String::new()
        },
        secs,
        args.out.display()
    );
    Ok(())
}
