//! The app's GPU-else-CPU policy: render on the GPU when an adapter opens,
//! else on the CPU reference, and say which was used.

use bevy_manifold_core::space::Space;
use bevy_manifold_core::trace::{Scene, TraceImage, TraceSettings, sample_frustum};
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

/// [`render_any`] `samples` times, as a still view accumulates them
/// (`bevy_manifold_core::trace::accumulate`): the `k`-th trace with its
/// pixel grid moved by `sample_offset(k)` and its shadow rays aimed at
/// the `k`-th point of each light's disc (`TraceSettings::light_sample`),
/// the colours averaged (anti-aliased edges, soft shadows of lights with
/// a radius); ids and levels are the first, plain trace's. One tracer for
/// all of them. 0 or 1 sample: [`render_any`].
///
/// # Errors
/// As [`render_any`].
pub fn render_samples(
    space: &Space,
    scene: &Scene,
    settings: &TraceSettings,
    samples: u32,
    (cpu, cpu_f32): (bool, bool),
) -> Result<(TraceImage, UsedTracer), GpuError> {
    let mut gpu = if cpu { None } else { GpuTracer::new().ok() };
    let adapter = gpu.as_ref().map(GpuTracer::adapter_name);
    let mut trace = |scene: &Scene, settings: &TraceSettings| match gpu.as_mut() {
        Some(gpu) => gpu.render(space, scene, settings),
        None => render_any(space, scene, settings, true, cpu_f32).map(|(img, _)| img),
    };
    let (mut image, used) = match adapter {
        Some(name) => (trace(scene, settings)?, UsedTracer::Gpu(name)),
        // No adapter: the CPU, and why.
        None => render_any(space, scene, settings, cpu, cpu_f32)?,
    };
    add_samples(&mut image, scene, settings, samples, &mut trace)?;
    Ok((image, used))
}

/// Adds to `image` (the plain trace, sample 0, of `scene`) samples 1 to
/// `samples - 1` traced by `trace`, the `k`-th with its pixel grid moved
/// by `sample_offset(k)` and `TraceSettings::light_sample` `k` (the
/// point of each light's disc; a path tracer's sample), and leaves the
/// mean colour in it; ids stay the first trace's. With more than 8
/// samples, a progress bar on stderr.
///
/// # Errors
/// The first trace that fails.
pub fn add_samples<E>(
    image: &mut TraceImage,
    scene: &Scene,
    settings: &TraceSettings,
    samples: u32,
    trace: &mut dyn FnMut(&Scene, &TraceSettings) -> Result<TraceImage, E>,
) -> Result<(), E> {
    if samples <= 1 {
        return Ok(());
    }
    let mut sum: Vec<[f64; 3]> = image.pixels.iter().map(|p| p.color.map(f64::from)).collect();
    let mut moved = scene.clone();
    let mut progress = (samples > 8).then(|| bevy_manifold_bench::Progress::new(samples as usize - 1));
    for k in 1..samples {
        moved.camera.frustum = Some(sample_frustum(scene, settings, k));
        let sampled = TraceSettings {
            light_sample: k,
            ..settings.clone()
        };
        for (s, p) in sum.iter_mut().zip(&trace(&moved, &sampled)?.pixels) {
            for (s, c) in s.iter_mut().zip(p.color) {
                *s += f64::from(c);
            }
        }
        if let Some(p) = progress.as_mut() {
            p.step("samples");
        }
    }
    for (p, s) in image.pixels.iter_mut().zip(&sum) {
        p.color = s.map(|v| (v / f64::from(samples)) as f32);
    }
    Ok(())
}
