//! The GPU side of the tracer: the WGSL tracer (`shaders/trace.wgsl`, the
//! twin of [`crate::trace`]), the shader defs that specialise it to a
//! scene, its data packed for the GPU, and a headless wgpu runner. The Bevy
//! render pass that runs it in a `Core3d` system comes next.

mod gpu;
mod headless;
mod shader_defs;

pub use gpu::{GpuBall, GpuFace, GpuLight, GpuParams, GpuPixel, GpuScene, GpuTube};
pub use headless::{GpuError, GpuTracer};
pub use shader_defs::{CellScheme as GpuCellScheme, TraceDefs};

/// The tracer's WGSL source, carried inside the crate so an app that
/// depends on it from crates.io finds it.
pub const TRACE_WGSL: &str = include_str!("../../shaders/trace.wgsl");
