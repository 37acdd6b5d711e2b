//! Billiards in a closed universe: ten numbered balls racked in a
//! pyramid, a cue ball, and a table that is the whole manifold. There are
//! no cushions: a ball that leaves through a face comes back through its
//! partner, and balls strike each other through the faces. The pockets
//! are the corners of the fundamental domain, where the copies of the
//! domain meet: in the 3-torus the cube's eight corners are one pocket,
//! in Seifert-Weber the dodecahedron's twenty are. Clear the table in as
//! few strokes as you can.
//!
//! ```text
//! cargo run --release --example billiards [-- --space seifert-weber]
//!     [--levels N] [--screenshot FILE.png [--size WxH]] [--frames N]
//! cargo run --release --features xr --example billiards -- --xr [--world-scale M]
//!     [--frames N --xr-capture DIR]
//! ```
//!
//! | key | what |
//! |---|---|
//! | W / S, A / D, Space / Shift | fly forward / back, left / right, up / down |
//! | arrows, right mouse button held | turn; Q / E roll |
//! | left mouse button or F, held | the cue: the longer held, the harder the stroke on release |
//! | R | rack again |
//!
//! With `--features gamepad` a gamepad flies as the fly camera's does and
//! its south button is the cue; with `--features audio` the balls click
//! where they meet, heard through the faces (`sound.rs`).
//! The stroke sends the cue ball along your line of sight through its
//! centre, when the first thing on that line is the cue ball (any image
//! of it) within the cue's reach: the crosshair turns green then.
//!
//! In a headset (`--xr`) your hands are the cues, after Weeks' advice on
//! body coherence: the cue ball bounces off a hand that touches it, so
//! what you see your hand touch is what moves. The sticks fly you around
//! the table.
//!
//! The rules are `table.rs` (no rendering: `tests/billiards.rs` plays
//! them headless), the window and controls `view.rs`, the headset
//! `xr.rs`. Without a display it says so and renders the opening break to
//! `billiards.png`.

#[cfg(feature = "audio")]
mod sound;
mod table;
mod view;
#[cfg(feature = "xr")]
mod xr;

#[path = "../support/hud.rs"]
mod hud;
#[path = "../support/showcase.rs"]
#[allow(dead_code, reason = "billiards uses its screenshot part only")]
mod showcase;

use bevy::prelude::*;
use bevy_manifold::camera::FlyCameraPlugin;
use bevy_manifold::prelude::*;
use bevy_manifold::render::offscreen;
use clap::Parser;
use std::path::PathBuf;
use table::{Cue, TableConfig, TablePlugin};
use view::{ViewPlugin, ViewSettings};

/// Billiards in a closed universe.
#[derive(Parser, Debug)]
#[command(name = "billiards")]
struct Args {
    /// The catalog space played in (torus, seifert-weber, poincare,
    /// mirrored-cube, mirrored-dodecahedron).
    #[arg(long, default_value = "torus")]
    space: String,
    /// Most face transports per ray (1 to 64).
    #[arg(long, default_value_t = 6, value_parser = clap::value_parser!(u32).range(1..=64))]
    levels: u32,
    /// Render the opening break offscreen to this PNG, and exit.
    #[arg(long)]
    screenshot: Option<PathBuf>,
    /// With --screenshot: WIDTHxHEIGHT (640x360).
    #[arg(long)]
    size: Option<String>,
    /// Exit after this many frames.
    #[arg(long)]
    frames: Option<u32>,
    /// Play in a headset through OpenXR (the `xr` feature); without a
    /// runtime, on the desktop.
    #[arg(long)]
    xr: bool,
    /// With --xr: metres of the room per unit of the space.
    #[arg(long)]
    world_scale: Option<f64>,
    /// With --xr --frames N: write both eyes' images to this folder at
    /// frame N - 30.
    #[arg(long)]
    xr_capture: Option<PathBuf>,
}

fn main() -> AppExit {
    match run() {
        Ok(exit) => exit,
        Err(e) => {
            eprintln!("error: {e}");
            AppExit::error()
        }
    }
}

fn run() -> Result<AppExit, String> {
    let args = Args::parse();
    if catalog::by_name(&args.space).is_none() {
        return Err(format!(
            "--space: no catalog space {:?} (one of {})",
            args.space,
            catalog::NAMES.join(", ")
        ));
    }
    let config = TableConfig {
        space: args.space.clone(),
        rack: true,
    };
    let size = match &args.size {
        Some(s) => showcase::parse_size(s).ok_or(format!("--size: WIDTHxHEIGHT, both at least 1, not {s:?}"))?,
        None => (640, 360),
    };
    let world_scale = match args.world_scale {
        Some(v) if v.is_finite() && v > 0.0 && v <= 1e6 => v,
        Some(v) => return Err(format!("--world-scale: a positive number of metres per unit, not {v}")),
        None => 2.0,
    };
    if let Some(path) = args.screenshot {
        return Ok(screenshot(config, args.levels, path, size));
    }
    if !args.xr
        && let Some(why) = offscreen::no_display()
    {
        eprintln!("{why}: rendering the opening break to billiards.png instead of opening a window");
        return Ok(screenshot(config, args.levels, PathBuf::from("billiards.png"), size));
    }
    let mut app = App::new();
    let plugins = DefaultPlugins.set(WindowPlugin {
        primary_window: Some(Window {
            title: "bevy_manifold billiards: the table is the universe".into(),
            resolution: (960, 540).into(),
            ..default()
        }),
        ..default()
    });
    #[cfg(feature = "xr")]
    if args.xr {
        // With --frames N: both eyes read back at frame N - 30.
        let capture = args
            .xr_capture
            .clone()
            .map(|d| (args.frames.unwrap_or(0).saturating_sub(30).max(1), d));
        app.add_plugins(bevy_mod_openxr::add_xr_plugins(plugins))
            .add_plugins(xr::BilliardsXrPlugin { world_scale, capture });
    } else {
        app.add_plugins(plugins);
    }
    #[cfg(not(feature = "xr"))]
    {
        if args.xr {
            eprintln!("warning: --xr: built without the `xr` feature (add --features xr); playing on the desktop");
        }
        let _ = world_scale;
        app.add_plugins(plugins);
    }
    app.add_plugins((
        ManifoldPlugins::in_schedule(FixedPostUpdate),
        FlyCameraPlugin,
        TablePlugin { config },
        ViewPlugin(ViewSettings {
            levels: args.levels,
            target: None,
        }),
    ));
    // Clicks heard through the faces (Bevy's audio is in the window's
    // DefaultPlugins).
    #[cfg(feature = "audio")]
    app.add_plugins(sound::SoundPlugin);
    if let Some(n) = args.frames {
        app.add_systems(
            Update,
            move |mut frames: Local<u32>, mut exit: MessageWriter<AppExit>| {
                *frames += 1;
                if *frames >= n {
                    exit.write(AppExit::Success);
                }
            },
        );
    }
    Ok(app.run())
}

/// Renders the break offscreen and writes it: a full stroke at the first
/// tick, 0.7 s of play, then the clock stops while the shaders compile,
/// so the picture is always the same moment.
fn screenshot(config: TableConfig, levels: u32, path: PathBuf, (w, h): (u32, u32)) -> AppExit {
    let mut app = App::new();
    app.add_plugins(offscreen::plugins());
    let mut settings = ViewSettings { levels, target: None };
    app.add_plugins((
        ManifoldPlugins::in_schedule(FixedPostUpdate),
        TablePlugin { config },
        ViewPlugin(settings.clone()),
    ));
    app.finish();
    app.cleanup();
    settings.target = Some(showcase::screenshot_mode(&mut app, path, (w, h)));
    app.insert_resource(settings);
    // The first update sets the table up; the stroke is taken at the
    // first tick of the next, and 0.7 s are played.
    showcase::play_ticks(&mut app, table::TICK_HZ, 1);
    app.world_mut().resource_mut::<Cue>().strike = Some(1.0);
    showcase::play_ticks(&mut app, table::TICK_HZ, 42);
    showcase::run(app)
}
