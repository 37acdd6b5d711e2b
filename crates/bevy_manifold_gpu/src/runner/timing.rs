//! Timing a trace on the device ([`GpuTracer::time_trace`]), for the
//! benchmarks.

use super::{GpuTracer, scene_defs};
use crate::GpuError;
use bevy_manifold_core::space::Space;
use bevy_manifold_core::trace::{Scene, TraceSettings};

impl GpuTracer {
    /// How long tracing `scene` takes once it is on the device: `repeats`
    /// traces of the same upload, back to back in one submission, with no
    /// read-back, after untimed traces for at least 250 ms (a GPU
    /// idling between calls runs at a fraction of its clock). The device
    /// time is the median pass by the adapter's timestamps at the start and
    /// end of each compute pass (none where the adapter has no timestamp
    /// queries); the wall time is the submission's, from submitting until
    /// the device is idle, over `repeats`. [`GpuTracer::render`] times
    /// more: the packing, the upload and the read-back, which on a discrete
    /// GPU at headset sizes outweigh the trace.
    ///
    /// ```no_run
    /// use bevy_manifold_core::prelude::*;
    /// use bevy_manifold_gpu::GpuTracer;
    ///
    /// let mut gpu = GpuTracer::new()?;
    /// let space = catalog::seifert_weber();
    /// let settings = TraceSettings { width: 1512, height: 1680, levels: 8, ..TraceSettings::default() };
    /// let t = gpu.time_trace(&space, &Scene::default_for(&space), &settings, 10)?;
    /// println!("{:.2} ms", t.device_ms.unwrap_or(t.wall_ms));
    /// # Ok::<(), bevy_manifold_gpu::GpuError>(())
    /// ```
    ///
    /// # Errors
    /// As [`GpuTracer::render`].
    pub fn time_trace(
        &mut self,
        space: &Space,
        scene: &Scene,
        settings: &TraceSettings,
        repeats: u32,
    ) -> Result<TraceTiming, GpuError> {
        let defs = scene_defs(space, scene, settings);
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let bound = self.bind(space, scene, settings, defs, "trace")?;
        self.timed(scope, repeats, |gpu, encoder, timestamps| {
            gpu.encode_trace(encoder, &bound, settings, timestamps);
        })
    }

    /// Times `repeats` passes that `encode` records (each with the
    /// timestamps it is given, where the device has them), after untimed
    /// ones for at least [`WARM_UP`], all under the validation `scope`
    /// opened before the scene was bound: [`GpuTracer::time_trace`] and
    /// [`GpuTracer::time_product`].
    pub(super) fn timed(
        &self,
        scope: wgpu::ErrorScopeGuard,
        repeats: u32,
        encode: impl Fn(&Self, &mut wgpu::CommandEncoder, Option<(&wgpu::QuerySet, u32)>),
    ) -> Result<TraceTiming, GpuError> {
        let repeats = repeats.clamp(1, 1024);
        let queries = self.has_timestamps().then(|| {
            self.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("trace timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: 2 * repeats,
            })
        });
        let wait = || {
            self.device
                .poll(wgpu::PollType::wait_indefinitely())
                .map_err(|e| GpuError::Readback(e.to_string()))
        };
        let warm = std::time::Instant::now();
        for _ in 0..256 {
            let mut encoder = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("warm-up trace"),
            });
            encode(self, &mut encoder, None);
            self.queue.submit([encoder.finish()]);
            wait()?;
            if warm.elapsed() >= WARM_UP {
                break;
            }
        }
        let mut encoder = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("timed traces"),
        });
        for i in 0..repeats {
            encode(self, &mut encoder, queries.as_ref().map(|q| (q, 2 * i)));
        }
        let commands = encoder.finish();
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Validation(e.to_string()));
        }
        let start = std::time::Instant::now();
        self.queue.submit([commands]);
        wait()?;
        let wall_ms = start.elapsed().as_secs_f64() * 1e3 / f64::from(repeats);
        let device_ms = match &queries {
            Some(set) => {
                let bytes = u64::from(2 * repeats) * 8;
                let resolved = self.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("timestamps"),
                    size: bytes,
                    usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                });
                let readback = self.readback_buffer(bytes);
                let mut encoder = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("timestamps"),
                });
                encoder.resolve_query_set(set, 0..2 * repeats, &resolved, 0);
                encoder.copy_buffer_to_buffer(&resolved, 0, &readback, 0, bytes);
                let ticks: Vec<u64> = bytemuck::pod_collect_to_vec(&self.finish(encoder, &readback)?);
                let period = f64::from(self.queue.get_timestamp_period()) * 1e-6;
                let spans: Vec<f64> = ticks
                    .chunks_exact(2)
                    .map(|t| t[1].saturating_sub(t[0]) as f64 * period)
                    .collect();
                Some(median(spans))
            }
            None => None,
        };
        Ok(TraceTiming { device_ms, wall_ms })
    }
}

/// How long [`GpuTracer::time_trace`] keeps the device busy before timing.
const WARM_UP: std::time::Duration = std::time::Duration::from_millis(250);

/// What [`GpuTracer::time_trace`] measured for one trace, in ms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TraceTiming {
    /// The device's own time for the compute pass (its timestamps); `None`
    /// where the adapter has no timestamp queries.
    pub device_ms: Option<f64>,
    /// Wall time from submitting the trace until the device is idle.
    pub wall_ms: f64,
}

/// The median of `values` (the mean of the middle two for an even count).
fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    match n {
        0 => f64::NAN,
        _ if n % 2 == 1 => values[n / 2],
        _ => 0.5 * (values[n / 2 - 1] + values[n / 2]),
    }
}
