//! # bevy_manifold_gpu
//!
//! The GPU side of [bevy_manifold](https://crates.io/crates/bevy_manifold)'s
//! ray tracer, as vello keeps its data layout and shaders apart from its
//! renderer:
//!
//! - `shaders/`: the WGSL tracer, the twin of `bevy_manifold_core::trace`
//!   (each step in both languages, each naming its twin);
//! - [`layout`]: the `#[repr(C)]` `Gpu…` twins of the WGSL structs, packed
//!   from the same [`FlatScene`](bevy_manifold_core::trace::FlatScene) the
//!   CPU tracer reads (in f32), so both trace identical inputs;
//! - [`bindings`]: bind group 0, described once for every layout;
//! - [`shader_defs`]: which optional parts of the shader a scene needs;
//! - feature `headless`: [`GpuTracer`], the tracer on a wgpu device outside
//!   Bevy's renderer (headless renders, the GPU/CPU agreement tests), and
//!   [`probe_adapter`].
//!
//! Bevy's render pass (the `bevy_manifold` crate, feature `render`) runs
//! the same shader over the same layout.
//!
//! ```
//! use bevy_manifold_core::prelude::*;
//! use bevy_manifold_gpu::TraceDefs;
//!
//! let space = catalog::seifert_weber();
//! let defs = TraceDefs::for_scene(&space, &Scene::default_for(&space), false);
//! assert!(defs.names().contains(&"GEOMETRY_HYPERBOLIC"));
//! ```

pub mod bindings;
pub mod layout;
pub mod shader_defs;

#[cfg(feature = "headless")]
mod error;
#[cfg(feature = "headless")]
mod probe;
#[cfg(feature = "headless")]
mod runner;

pub use layout::{
    FLAG_NO_EARLY_STOP, FLAG_NO_RENORMALIZE, GpuBall, GpuFace, GpuInstance, GpuLight, GpuObjects, GpuParams, GpuPixel,
    GpuScene, GpuSpace, GpuTube, GpuView, settings_flags,
};
pub use shader_defs::{CellScheme as GpuCellScheme, TraceDefs};

#[cfg(feature = "headless")]
pub use error::GpuError;
#[cfg(feature = "headless")]
pub use probe::{probe_adapter, probe_adapter_info};
#[cfg(feature = "headless")]
pub use runner::GpuTracer;

/// The tracer's WGSL source, carried inside the crate so an app that
/// depends on it from crates.io finds it.
pub const TRACE_WGSL: &str = include_str!("../shaders/trace.wgsl");
