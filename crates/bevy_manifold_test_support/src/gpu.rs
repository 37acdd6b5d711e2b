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

/// What a camera after far travel must see, for the stability test and
/// `bench stability`: the GPU's 64x64 view of the default scene from
/// `far`'s placement, and the view it must match. In E3 and S3 that is the
/// GPU's view from the loop's closed form ([`crate::stress::loop_exact`]);
/// in H3, where rounding makes a long path wander off its closed form, the
/// CPU f64 reference's view from the same camera.
///
/// # Errors
/// As [`GpuTracer::render`].
pub fn far_travel_views(
    gpu: &mut GpuTracer,
    space: &bevy_manifold_core::space::Space,
    path: &crate::stress::Path,
    far: &crate::stress::FarTravel,
) -> Result<[bevy_manifold_core::trace::TraceImage; 2], bevy_manifold_gpu::GpuError> {
    use bevy_manifold_core::geometry::Geometry;
    use bevy_manifold_core::trace::{Scene, TraceSettings, render};
    let settings = TraceSettings {
        width: 64,
        height: 64,
        ..TraceSettings::default()
    };
    let mut scene = Scene::default_for(space);
    scene.camera.isometry = far.placement;
    let seen = gpu.render(space, &scene, &settings)?;
    let reference = if space.geometry() == Geometry::Hyperbolic {
        render::<f64>(space, &scene, &settings)
    } else {
        scene.camera.isometry = crate::stress::loop_exact(space, path, far.steps);
        gpu.render(space, &scene, &settings)?
    };
    Ok([seen, reference])
}
