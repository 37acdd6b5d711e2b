//! The GPU side of the tracer. This version holds the WGSL tracer
//! (`shaders/trace.wgsl`, the twin of [`crate::trace`]) and the choice of
//! shader defs that specialises it to a scene; the Bevy render pass that
//! runs it comes next.

mod shader_defs;

pub use shader_defs::{CellScheme as GpuCellScheme, TraceDefs};

/// The tracer's WGSL source, carried inside the crate so an app that
/// depends on it from crates.io finds it.
pub const TRACE_WGSL: &str = include_str!("../../shaders/trace.wgsl");
