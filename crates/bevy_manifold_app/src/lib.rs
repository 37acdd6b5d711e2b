//! The application on top of the `bevy_manifold` plugin: the explorer
//! (what `cargo run --release` opens), the `bevy_manifold` command line
//! (`space`, `render`, `bench`), and the GPU-else-CPU policy they share.
//! Unpublished: a game depends on the plugin and compiles none of this.

pub mod cli;
pub mod explorer;
pub mod policy;
