//! The shooter's command line, parsed by clap as the CLI's is: an unknown
//! flag or a bad value is named and the game does not start (exit 2),
//! `--help` lists them all.

use clap::Parser;
use std::path::PathBuf;

/// The shooter: a game in a closed universe, where your shots come back
/// around.
#[derive(Parser, Debug)]
#[command(name = "shooter")]
pub struct Args {
    /// The catalog space played in (torus, seifert-weber, poincare,
    /// mirrored-cube, mirrored-dodecahedron).
    #[arg(long, default_value = "torus")]
    pub space: String,
    /// easy, normal or hard.
    #[arg(long)]
    pub difficulty: Option<String>,
    /// The game's seed (where targets and enemies start).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Most face transports per ray (1 to 64).
    #[arg(long, default_value_t = 6, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub levels: u32,
    /// Write the game played as a script (JSON) on exit.
    #[arg(long)]
    pub record: Option<PathBuf>,
    /// Replay a script (JSON): its space, seed and difficulty.
    #[arg(long)]
    pub play: Option<PathBuf>,
    /// No window: play the script (--play) or the bot (--bot) as fast as
    /// it goes, printing the events and the score.
    #[arg(long)]
    pub headless: bool,
    /// The bot plays.
    #[arg(long)]
    pub bot: bool,
    /// With --headless --bot: the ticks played (60 a second).
    #[arg(long)]
    pub ticks: Option<u64>,
    /// Render one frame of a game in progress offscreen to this PNG, and
    /// exit.
    #[arg(long)]
    pub screenshot: Option<PathBuf>,
    /// With --screenshot: WIDTHxHEIGHT (640x360).
    #[arg(long)]
    pub size: Option<String>,
    /// Exit after this many frames.
    #[arg(long)]
    pub frames: Option<u32>,
    /// Play in a headset through OpenXR (the `xr` feature); without a
    /// runtime, on the desktop.
    #[arg(long)]
    pub xr: bool,
    /// With --xr: metres of the room per unit of the space.
    #[arg(long)]
    pub world_scale: Option<f64>,
    /// With --xr --frames N: write both eyes' images to this folder at
    /// frame N - 30.
    #[arg(long)]
    pub xr_capture: Option<PathBuf>,
}
