//! The `bevy_manifold` command line: with no arguments the explorer (a
//! window into the manifold, or without a display `explorer.png`); with a
//! command, inspect, export, render and benchmark spaces.

fn main() -> std::process::ExitCode {
    bevy_manifold_app::cli::run()
}
