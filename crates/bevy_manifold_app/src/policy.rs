//! The app's GPU-else-CPU policy: render on the GPU when an adapter opens,
//! else on the CPU reference, and say which was used.

use bevy_manifold_core::space::Space;
use bevy_manifold_core::trace::{Scene, TraceImage, TraceSettings};
use bevy_manifold_gpu::{GpuError, GpuTracer};

/// Which tracer [`render_any`] used.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum UsedTracer {
    /// The GPU, with this adapter.
    Gpu(String),
    /// The CPU reference, in f64 or f32, and why the GPU was not used
    /// (`None` when the CPU was asked for).
    Cpu {
        /// f32 arithmetic (the GPU's) instead of f64.
        f32: bool,
        /// The GPU error that made it fall back.
        fallback: Option<String>,
    },
}

impl std::fmt::Display for UsedTracer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            UsedTracer::Gpu(a) => write!(f, "GPU: {a}"),
            UsedTracer::Cpu { f32, .. } => write!(f, "CPU {}", if *f32 { "f32" } else { "f64" }),
        }
    }
}

/// Renders on the GPU unless `cpu` (falling back to the CPU reference when
/// no adapter or device opens), or on the CPU reference (f32 arithmetic
/// when `cpu_f32`): what `render` and the explorer's fallback share.
///
/// # Errors
/// A GPU failure after the device opened (shader, validation, readback).
pub fn render_any(
    space: &Space,
    scene: &Scene,
    settings: &TraceSettings,
    cpu: bool,
    cpu_f32: bool,
) -> Result<(TraceImage, UsedTracer), GpuError> {
    let mut fallback = None;
    if !cpu {
        match GpuTracer::new() {
            Ok(mut gpu) => {
                let image = gpu.render(space, scene, settings)?;
                return Ok((image, UsedTracer::Gpu(gpu.adapter_name())));
            }
            Err(e) => fallback = Some(e.to_string()),
        }
    }
    let image = if cpu_f32 {
        bevy_manifold_core::trace::render::<f32>(space, scene, settings)
    } else {
        bevy_manifold_core::trace::render::<f64>(space, scene, settings)
    };
    Ok((image, UsedTracer::Cpu { f32: cpu_f32, fallback }))
}
