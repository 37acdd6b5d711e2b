//! Offscreen Bevy apps (feature `offscreen`): the renderer with no window,
//! updated by hand, its manifold cameras drawing into images that can be
//! read back. Used by the tests, `bench pass` and headless screenshots.
//!
//! ```no_run
//! use bevy::prelude::*;
//! use bevy_manifold::prelude::*;
//! use bevy_manifold::render::offscreen;
//!
//! let mut app = offscreen::app(true);
//! let image = offscreen::target(&mut app, 320, 180);
//! let space = catalog::torus(1.0);
//! let root = app.world_mut().spawn(ManifoldSpace::new(space.clone())).id();
//! app.world_mut().spawn((
//!     ChildOf(root),
//!     ManifoldCamera::default(),
//!     bevy::camera::RenderTarget::Image(image.clone().into()),
//! ));
//! app.world_mut().spawn((ChildOf(root), TracedBall::new(0.2, Color::WHITE), Placement::at(&space, glam::DVec3::Z * -0.3)));
//! offscreen::wait_for_pipelines(&mut app).unwrap();
//! let rgba = offscreen::capture(&mut app, &image).unwrap();
//! assert_eq!(rgba.len(), 320 * 180 * 4);
//! ```

use super::pass::ManifoldViewBinding;
use bevy::log::LogPlugin;
use bevy::prelude::*;
use bevy::render::RenderApp;
use bevy::render::gpu_readback::{Readback, ReadbackComplete};
use bevy::render::pipelined_rendering::PipelinedRenderingPlugin;
use bevy::render::render_resource::{PipelineCache, TextureFormat, TextureUsages};
use bevy::window::ExitCondition;
use bevy::winit::WinitPlugin;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// A Bevy app with the renderer and no window (and, when `with_manifold`,
/// [`crate::ManifoldPlugins`]), ready to be updated by hand. The render
/// world runs on the calling thread, so it can be inspected between
/// updates. Bevy's logger is left out, so several such apps can live in
/// one process.
pub fn app(with_manifold: bool) -> App {
    let mut app = App::new();
    app.add_plugins(plugins().disable::<LogPlugin>());
    if with_manifold {
        app.add_plugins(crate::ManifoldPlugins::default());
    }
    app.finish();
    app.cleanup();
    app
}

/// Bevy's default plugins without a window or winit, with the render world
/// on the calling thread: what [`app`] adds (it also leaves the logger
/// out), for apps that want their own logger or plugins.
pub fn plugins() -> bevy::app::PluginGroupBuilder {
    DefaultPlugins
        .build()
        .disable::<WinitPlugin>()
        .disable::<PipelinedRenderingPlugin>()
        .set(WindowPlugin {
            primary_window: None,
            exit_condition: ExitCondition::DontExit,
            ..default()
        })
}

/// Why a window cannot open here, if it cannot: on Linux and the BSDs,
/// neither `DISPLAY` nor `WAYLAND_DISPLAY` is set. The explorer and the
/// shooter then render a picture instead.
#[must_use]
pub fn no_display() -> Option<&'static str> {
    let set = |k: &str| std::env::var_os(k).is_some_and(|v| !v.is_empty());
    (cfg!(all(unix, not(target_os = "macos"))) && !set("DISPLAY") && !set("WAYLAND_DISPLAY"))
        .then_some("no display (neither DISPLAY nor WAYLAND_DISPLAY is set)")
}

/// A `w` x `h` sRGB image a camera can render into and [`capture`] can
/// read back.
pub fn target(app: &mut App, w: u32, h: u32) -> Handle<Image> {
    target_image(&mut app.world_mut().resource_mut::<Assets<Image>>(), w, h)
}

/// [`target`] added to `images` directly (from a system).
pub fn target_image(images: &mut Assets<Image>, w: u32, h: u32) -> Handle<Image> {
    let mut image = Image::new_target_texture(w, h, TextureFormat::Rgba8UnormSrgb, None);
    image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    images.add(image)
}

/// Updates the app until every pipeline it queued has compiled (Bevy's
/// own, for ordinary meshes, and each manifold view's tracer) and nothing
/// new has been queued for a few frames.
///
/// # Errors
/// When that has not happened within two minutes (a shader error is
/// logged by the pass).
pub fn wait_for_pipelines(app: &mut App) -> Result<(), String> {
    let start = Instant::now();
    let mut quiet = 0;
    while start.elapsed() < Duration::from_secs(120) {
        app.update();
        stopped(app)?;
        let world = app.sub_app_mut(RenderApp).world_mut();
        let ids: Vec<_> = world
            .query::<&ManifoldViewBinding>()
            .iter(world)
            .map(|b| b.pipeline)
            .collect();
        let cache = world.resource::<PipelineCache>();
        let ready =
            cache.waiting_pipelines().next().is_none() && ids.iter().all(|id| cache.get_render_pipeline(*id).is_some());
        quiet = if ready { quiet + 1 } else { 0 };
        if quiet >= 3 {
            return Ok(());
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    Err("the app's pipelines did not all compile within two minutes".into())
}

/// An error when the app asked to exit with an error (Bevy's renderer does
/// so on a wgpu validation or device error, after logging it).
fn stopped(app: &App) -> Result<(), String> {
    match app.should_exit() {
        Some(AppExit::Error(code)) => Err(format!(
            "the app exited with error {code} (a render error is logged above when a logger is on)"
        )),
        _ => Ok(()),
    }
}

/// Renders a frame and reads the image in `target` back; returns its
/// pixels' bytes in its own format, rows top to bottom, unpadded: RGBA
/// sRGB-encoded for a [`target`] image, four `f16` a pixel for an
/// `Rgba16Float` (HDR) one.
///
/// # Errors
/// When the image is unknown or nothing arrives within 200 frames and
/// [`CAPTURE_WAIT`] (frames alone are no bound on a fast GPU, where 200
/// of them can pass while a pipeline still compiles).
pub fn capture(app: &mut App, target: &Handle<Image>) -> Result<Vec<u8>, String> {
    let (w, h, bytes_per_pixel) = {
        let images = app.world().resource::<Assets<Image>>();
        let image = images.get(target).ok_or("capture: unknown image")?;
        let format = image.texture_descriptor.format;
        let bytes = format
            .block_copy_size(None)
            .ok_or_else(|| format!("capture: {format:?} has no single copy size"))?;
        (image.width() as usize, image.height() as usize, bytes as usize)
    };
    let slot: Arc<Mutex<Option<Vec<u8>>>> = Arc::default();
    let out = slot.clone();
    let reader = app
        .world_mut()
        .spawn(Readback::texture(target.clone()))
        .observe(move |done: On<ReadbackComplete>| {
            if let Ok(mut s) = out.lock() {
                s.get_or_insert_with(|| done.data.clone());
            }
        })
        .id();
    let start = Instant::now();
    let mut frames = 0;
    while frames < 200 || start.elapsed() < CAPTURE_WAIT {
        if frames >= 200 {
            std::thread::sleep(Duration::from_millis(2));
        }
        frames += 1;
        app.update();
        stopped(app)?;
        let taken = slot.lock().map_err(|e| e.to_string())?.take();
        if let Some(data) = taken {
            app.world_mut().despawn(reader);
            // Rows come padded to the copy alignment.
            let row = (w * bytes_per_pixel).next_multiple_of(256);
            if data.len() < row * h {
                return Err(format!("capture: {} bytes for a {w}x{h} image", data.len()));
            }
            return Ok(data
                .chunks_exact(row)
                .take(h)
                .flat_map(|r| &r[..w * bytes_per_pixel])
                .copied()
                .collect());
        }
    }
    app.world_mut().despawn(reader);
    Err(format!(
        "no image came back within {frames} frames and {} s",
        CAPTURE_WAIT.as_secs()
    ))
}

/// How long [`capture`] waits for its image, at least.
pub const CAPTURE_WAIT: Duration = Duration::from_secs(30);

/// Spawns `space` with a tracer [`crate::trace::Scene`]'s balls, lights and
/// edges (see [`crate::drawables::spawn_scene`]) and a manifold camera at
/// the scene's camera, with its field of view, drawing into `image`.
/// Returns the space's root and the camera.
pub fn spawn_view(
    app: &mut App,
    space: &crate::space::Space,
    scene: &crate::trace::Scene,
    image: &Handle<Image>,
    camera: impl Bundle,
) -> (Entity, Entity) {
    // One frame is all an offscreen render shows: the table of exact ids
    // is grown now rather than on a task while frames go by.
    if let crate::space::cells::CellScheme::Exact(exact) = space.cells() {
        exact.table();
    }
    let world = app.world_mut();
    let root = world.spawn(crate::placement::ManifoldSpace::new(space.clone())).id();
    let mut commands = world.commands();
    crate::drawables::spawn_scene(&mut commands, root, space, scene);
    let id = commands
        .spawn((
            ChildOf(root),
            camera,
            crate::placement::Placement::from_isometry(scene.camera.isometry),
            bevy::camera::RenderTarget::Image(image.clone().into()),
            Projection::Perspective(PerspectiveProjection {
                fov: (scene.camera.fov_y_degrees as f32).to_radians(),
                ..default()
            }),
        ))
        .id();
    if let Some(fog) = &scene.fog {
        commands.entity(id).insert(crate::camera::ManifoldFog::from_fog(fog));
    }
    world.flush();
    (root, id)
}
