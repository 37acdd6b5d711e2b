//! The GPU side of the tracer: the WGSL tracer (`shaders/trace.wgsl`, the
//! twin of [`crate::trace`]), the shader defs that specialise it to a
//! scene, its data packed for the GPU, a headless wgpu runner, and (feature
//! `render`) the Bevy render pass that runs it for manifold cameras.

mod gpu;
mod headless;
mod shader_defs;

#[cfg(feature = "render")]
pub mod pass;

pub use gpu::{
    FLAG_NO_EARLY_STOP, FLAG_NO_RENORMALIZE, GpuBall, GpuFace, GpuInstance, GpuLight, GpuObjects, GpuParams, GpuPixel,
    GpuScene, GpuSpace, GpuTube, GpuView, settings_flags,
};
pub use headless::{GpuError, GpuTracer, UsedTracer, probe_adapter, probe_adapter_info, render_any};
pub use shader_defs::{CellScheme as GpuCellScheme, TraceDefs};

/// The tracer's WGSL source, carried inside the crate so an app that
/// depends on it from crates.io finds it.
pub const TRACE_WGSL: &str = include_str!("../../shaders/trace.wgsl");
