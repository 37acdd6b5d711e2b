//! The `bevy_manifold` command line: inspect, export and render spaces.
//!
//! Running with no arguments is reserved for the interactive explorer; for
//! now it prints usage.

mod cli;

fn main() -> std::process::ExitCode {
    cli::run()
}
