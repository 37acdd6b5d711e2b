//! The explorer without a window: when there is no display to open one on,
//! or no GPU adapter for Bevy's renderer, it says so in one line, renders
//! the view it would have opened (the settings' space and scene, from the
//! paper's camera) to a PNG with the headless GPU tracer, or the CPU
//! reference when there is no adapter, and exits 0.

use super::settings::ExplorerSettings;
use crate::policy::{UsedTracer, render_any};
use bevy::app::AppExit;
use bevy_manifold::space::catalog;
use bevy_manifold::trace::{Scene, TraceSettings, write_png};
use bevy_manifold_gpu::probe_adapter_info;
use std::path::Path;

/// The GPU adapter a window would render with, or why no window can be
/// opened here: no display server (Linux and the BSDs: neither `DISPLAY`
/// nor `WAYLAND_DISPLAY` is set), or no GPU adapter.
///
/// # Errors
/// The reason, in one line.
pub fn window_adapter() -> Result<wgpu::AdapterInfo, String> {
    if let Some(why) = bevy_manifold::render::offscreen::no_display() {
        return Err(why.into());
    }
    probe_adapter_info().map_err(|e| format!("no window: {e}"))
}

/// The explorer's first view as a CPU/GPU tracer scene: the settings'
/// space (the 3-torus, with a warning, when it cannot be loaded), the
/// paper's scene with the settings' options, fog and cell shading.
#[must_use]
pub fn view_scene(
    settings: &ExplorerSettings,
    width: u32,
    height: u32,
) -> (bevy_manifold::space::Space, Scene, TraceSettings) {
    let space = catalog::resolve(&settings.space).unwrap_or_else(|e| {
        eprintln!("warning: {e}; showing the 3-torus");
        catalog::torus(1.0)
    });
    let mut scene = Scene::paper(&space, &settings.paper());
    // As the pass reads the camera's fog (no fog at density 0).
    scene.fog = settings.fog().and_then(|fog| fog.to_fog());
    let tint = settings.cell_shading().tint();
    let trace = TraceSettings {
        width,
        height,
        levels: settings.levels,
        max_distance: f64::from(settings.max_distance),
        cell_colors: tint.is_some(),
        cell_tint: tint.unwrap_or_default(),
        cell_rule: settings.rule(),
        ..TraceSettings::default()
    };
    (space, scene, trace)
}

/// The explorer's view of a product space drawn to `out`: its lit scene
/// (or lit from the eye, as the settings say) from its start, traced by
/// the product tracer (its WGSL twin where there is a GPU tracer).
/// Returns the space's name and what traced it.
fn draw_product(
    settings: &ExplorerSettings,
    space: &bevy_manifold::space::product::ProductSpace,
    out: &Path,
    (w, h): (u32, u32),
    gpu: bool,
) -> Result<(String, String), String> {
    use bevy_manifold::trace::product::ProductScene;
    let mut scene = if settings.lights {
        ProductScene::lit_for(space)
    } else {
        ProductScene::default_for(space)
    };
    super::view::set_product_view(&mut scene.view, settings);
    scene.edges = super::view::product_edges(settings);
    let mut tracer = gpu.then(bevy_manifold_gpu::GpuTracer::new).and_then(Result::ok);
    let on = match &tracer {
        Some(t) => format!("on the GPU ({})", t.adapter_name()),
        None => "with the CPU reference tracer".into(),
    };
    let pixels = crate::cli::product::trace(space, &scene, tracer.as_mut(), (w, h))?;
    crate::cli::product::write_png(&pixels, out, (w, h))?;
    Ok((space.name.clone(), on))
}

/// The explorer's view of a space of E3, H3 or S3 drawn to `out`, on the
/// GPU where there is one. Returns the space's name and what traced it.
fn draw_manifold(
    settings: &ExplorerSettings,
    out: &Path,
    (w, h): (u32, u32),
    gpu: bool,
) -> Result<(String, String), String> {
    let (space, scene, trace) = view_scene(settings, w, h);
    let (img, used) = render_any(&space, &scene, &trace, !gpu, false).map_err(|e| e.to_string())?;
    write_png(&img, out).map_err(|e| e.to_string())?;
    let on = match used {
        UsedTracer::Gpu(a) => format!("on the GPU ({a})"),
        UsedTracer::Cpu { .. } => "with the CPU reference tracer".into(),
    };
    Ok((space.name().to_owned(), on))
}

/// Prints why there is no window, renders the view to `out` (1280x720 on
/// the GPU, 640x360 on the CPU reference) and returns success; an error
/// exit only when the image cannot be made or written.
pub fn render_instead(why: &str, settings: &ExplorerSettings, out: &Path) -> AppExit {
    let gpu = probe_adapter_info().is_ok();
    let size = if gpu { (1280, 720) } else { (640, 360) };
    let drawn = match super::view::product_space(&settings.space) {
        Some(space) => draw_product(settings, &space, out, size, gpu),
        None => draw_manifold(settings, out, size, gpu),
    };
    match drawn {
        Ok((name, on)) => {
            println!(
                "{why}: rendered the explorer's view of {name} to {} ({}x{}, {on}) instead of opening a window",
                out.display(),
                size.0,
                size.1
            );
            AppExit::Success
        }
        Err(e) => {
            eprintln!("{why}, and rendering {} failed: {e}", out.display());
            AppExit::error()
        }
    }
}
