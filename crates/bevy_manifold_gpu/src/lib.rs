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
//! - feature `headless`: `GpuTracer`, the tracer on a wgpu device outside
//!   Bevy's renderer (headless renders, the GPU/CPU agreement tests), and
//!   `probe_adapter`.
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
pub mod pack;
pub mod product;
pub mod shader_defs;

#[cfg(feature = "headless")]
mod error;
#[cfg(feature = "headless")]
mod probe;
#[cfg(feature = "headless")]
mod runner;

pub use layout::{
    FLAG_NO_CULL, FLAG_NO_EARLY_STOP, FLAG_NO_RENORMALIZE, GpuBall, GpuFace, GpuInstance, GpuLight, GpuParams,
    GpuPixel, GpuTube, settings_flags,
};
pub use pack::{GpuObjects, GpuScene, GpuSpace, GpuView, PackedSpace, binding_bytes};
pub use shader_defs::{CellScheme as GpuCellScheme, TraceDefs};

#[cfg(feature = "headless")]
pub use error::GpuError;
#[cfg(feature = "headless")]
pub use probe::{probe_adapter, probe_adapter_info};
#[cfg(feature = "headless")]
pub use runner::{GpuTracer, MAX_PRODUCT_BALLS, TraceTiming};

/// One WGSL file of the tracer, carried inside the crate so an app that
/// depends on it from crates.io finds it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WgslModule {
    /// Its path, as Bevy's asset and naga_oil's composer name it.
    pub path: &'static str,
    /// Its source.
    pub source: &'static str,
}

macro_rules! wgsl {
    ($name:literal) => {
        WgslModule {
            path: concat!("bevy_manifold/shaders/", $name, ".wgsl"),
            source: include_str!(concat!("../shaders/", $name, ".wgsl")),
        }
    };
}

/// The per-cell tint of a cell id, `shaders/cell_tint.wgsl`, imported by
/// `cells` (in [`SHADER_IMPORTS`]) and by [`PRODUCT_WGSL`].
pub const CELL_TINT_WGSL: WgslModule = wgsl!("cell_tint");

/// The tracer's import modules, each after the modules it imports (the
/// order naga_oil's composer needs; Bevy resolves them by their
/// `#define_import_path`, `bevy_manifold::<name>`). Each is the WGSL twin
/// of a Rust file of the same name: `bindings` of [`layout`], `geometry`
/// of the core's `geometry/mod.rs`, `cells` and `rule` of its `space/`
/// (and [`CELL_TINT_WGSL`] of its `space/cell_id.rs` with the tint of
/// `space/cells.rs`),
/// `bvh` of its `mesh/`, and the others of its `trace/` (the tracer's
/// stages: see `bevy_manifold_core::trace`).
pub const SHADER_IMPORTS: [WgslModule; 23] = [
    wgsl!("output"),
    CELL_TINT_WGSL,
    wgsl!("bindings"),
    wgsl!("geometry"),
    wgsl!("step"),
    wgsl!("footprint"),
    wgsl!("cells"),
    wgsl!("rule"),
    wgsl!("texture"),
    wgsl!("bvh"),
    wgsl!("mesh_hit"),
    wgsl!("ball_tree"),
    wgsl!("walk"),
    wgsl!("camera"),
    wgsl!("cone"),
    wgsl!("nearest"),
    wgsl!("instance_tree"),
    wgsl!("cull"),
    wgsl!("shadow"),
    wgsl!("shade"),
    wgsl!("trace"),
    wgsl!("path"),
    wgsl!("drift"),
];

/// An item's name as the WGSL wrote it: naga_oil suffixes each item of an
/// imported module with `X_naga_oil_mod_X<the module path>X` in the
/// composed module.
///
/// ```
/// assert_eq!(bevy_manifold_gpu::undecorated("hit_meshX_naga_oil_mod_XMJSXEX"), "hit_mesh");
/// assert_eq!(bevy_manifold_gpu::undecorated("trace"), "trace");
/// ```
#[must_use]
pub fn undecorated(name: &str) -> &str {
    name.split("X_naga_oil_mod_X").next().unwrap_or(name)
}

/// The tracer's entry module, `shaders/render.wgsl` (twin of the core's
/// `trace::render`): `trace` and `drift` (compute, the headless runner)
/// and `fragment` (the render pass).
pub const RENDER_WGSL: WgslModule = wgsl!("render");

/// The tracer of the product spaces (H2xR, S2xR), `shaders/product.wgsl`:
/// one module of its own, importing [`CELL_TINT_WGSL`] only (twin of the core's
/// `trace::product`), entry `product_trace` (compute, the headless
/// runner's [`GpuTracer::render_product`]). Its inputs are
/// [`product::GpuProductScene`]'s.
pub const PRODUCT_WGSL: WgslModule = wgsl!("product");

/// The render pass's drawing of a view traced into textures of its own:
/// `upscale` (fragment; bilinear colour, nearest depth; Rust twin
/// `bevy_manifold_core::trace::upscale`) and `blend_in` (a trace into an
/// accumulation history; Rust twin `bevy_manifold_core::trace::accumulate`).
/// It imports `output` under `ENCODE_SRGB`.
pub const UPSCALE_WGSL: WgslModule = wgsl!("upscale");
