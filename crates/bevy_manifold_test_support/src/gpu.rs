//! The GPU to test on. GPU tests run under [`crate::harness`], which lists
//! them as ignored when there is no adapter (and runs them under CI,
//! where a missing adapter is a failure), so here one is expected.

use bevy_manifold_gpu::GpuTracer;

/// The GPU tracer on the default adapter.
///
/// # Panics
/// When no adapter or device opens: the harness only runs GPU tests with
/// an adapter, or under CI (`CI` set), where its absence is a failure.
#[must_use]
pub fn tracer() -> GpuTracer {
    match GpuTracer::new() {
        Ok(t) => {
            eprintln!("GPU adapter: {}", t.adapter_name());
            t
        }
        Err(e) => panic!("no GPU to test on (CI must have one: lavapipe): {e}"),
    }
}
