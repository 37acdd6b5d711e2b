//! The explorer: what `cargo run --release` opens. A window
//! into the manifold with the paper's scene, the fly camera and an egui
//! side panel for the space, the levels, fog, per-cell shading, the scene,
//! the render scale, frame times, the adapter and the camera's cell, and
//! tours: played, scrubbed, recorded and saved ([`tour`]); the camera
//! flies free or rides the vehicle.
//! Settings persist between runs ([`settings`]). Without a display or a GPU
//! adapter it says so in one line, renders the view to `explorer.png`
//! instead ([`fallback`]) and exits 0.
//!
//! The pieces are plugins, so a test or another app can run the explorer's
//! world without its window:
//! - [`ExplorerPlugin`]: the settings, the world they describe (re-spawned
//!   when the space or the scene changes), the keys, the view image, saving;
//! - [`panel::ExplorerPanelPlugin`]: the egui panel and the view in the
//!   window.
//!
//! ```no_run
//! // The explorer as `cargo run --release` starts it:
//! std::process::exit(match bevy_manifold_app::explorer::run() {
//!     bevy::app::AppExit::Success => 0,
//!     _ => 1,
//! });
//! ```

pub mod fallback;
pub mod panel;
pub mod progress;
pub mod settings;
pub mod soak;
pub mod tour;
pub mod tour_panel;
pub mod view;
#[cfg(feature = "xr")]
pub mod xr;

pub use settings::{CellMode, ExplorerSettings};
pub use view::{ExplorerCamera, ExplorerStatus, ExplorerView, ExplorerWorld};

use bevy::prelude::*;
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured, save_to_disk};
use bevy_manifold::camera::FlyCameraPlugin;
use bevy_manifold::placement::DomainCell;
use bevy_manifold::space::catalog;
use bevy_manifold::trace::SuzanneMode;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// The explorer's world, keys and settings (no window needed). Adds
/// [`bevy_manifold::ManifoldPlugins`] and [`FlyCameraPlugin`] when the app has not.
#[derive(Clone, Debug, Default)]
pub struct ExplorerPlugin {
    /// Where the settings are saved when they change and on exit (`None`:
    /// not saved).
    pub settings_path: Option<PathBuf>,
}

/// Where settings are saved, and when they last were.
#[derive(Resource, Debug)]
struct SettingsFile {
    path: Option<PathBuf>,
    saved: ExplorerSettings,
    due: Option<Instant>,
}

impl Plugin for ExplorerPlugin {
    fn build(&self, app: &mut App) {
        if !app.is_plugin_added::<bevy_manifold::placement::PlacementPlugin>() {
            app.add_plugins(bevy_manifold::ManifoldPlugins::default());
        }
        if !app.is_plugin_added::<FlyCameraPlugin>() {
            app.add_plugins(FlyCameraPlugin);
        }
        app.init_resource::<ExplorerSettings>()
            .init_resource::<ExplorerStatus>()
            .init_resource::<tour::ExplorerTour>()
            .insert_resource(SettingsFile {
                path: self.settings_path.clone(),
                saved: ExplorerSettings::default(),
                due: None,
            })
            .add_systems(PreStartup, note_loaded_settings)
            .add_systems(Startup, view::setup)
            .add_systems(
                Update,
                (
                    keys,
                    tour::tour_keys,
                    tour::follow_tour_settings,
                    view::apply_settings,
                    tour::drive_tour,
                    view::resize_view,
                    view::track,
                    save_settings,
                )
                    .chain(),
            )
            .add_systems(
                PostUpdate,
                tour::read_tour_time.after(bevy_manifold::tour::TourSystems::Snap),
            )
            .add_systems(Last, save_on_exit);
    }
}

fn note_loaded_settings(settings: Res<ExplorerSettings>, mut file: ResMut<SettingsFile>) {
    file.saved = settings.clone();
}

/// One line per key, as the panel lists them.
pub const KEYS: &[(&str, &str)] = &[
    ("W A S D, Space, Shift", "fly"),
    ("arrows, right mouse drag", "turn"),
    ("Q / E", "roll"),
    ("1 - 5", "catalog spaces"),
    ("[ / ]", "fewer / more levels"),
    ("F", "fog"),
    ("C", "per-cell shading"),
    ("M", "next cell mode"),
    ("P", "pin the camera's cell (highlight)"),
    ("G", "domain edges"),
    ("B", "Suzanne attached / free / hidden"),
    ("V", "ride the vehicle / fly free"),
    ("T", "play / pause the tour"),
    ("R", "back to the start"),
    ("Tab", "panel"),
    ("F12", "screenshot (PNG)"),
];

/// The keys for the common toggles (listed in [`KEYS`]).
#[expect(clippy::too_many_arguments, reason = "a system's parameters")]
fn keys(
    mut commands: Commands,
    keys: Option<Res<ButtonInput<KeyCode>>>,
    mut settings: ResMut<ExplorerSettings>,
    world: Option<Res<ExplorerWorld>>,
    view: Option<Res<ExplorerView>>,
    cells: Query<&DomainCell, With<ExplorerCamera>>,
    mut products: Query<&mut bevy_manifold::product::ProductCamera, With<ExplorerCamera>>,
    mut status: ResMut<ExplorerStatus>,
) {
    let (Some(keys), Some(world)) = (keys, world) else {
        return;
    };
    let hit = |k: KeyCode| keys.just_pressed(k);
    let digits = [
        KeyCode::Digit1,
        KeyCode::Digit2,
        KeyCode::Digit3,
        KeyCode::Digit4,
        KeyCode::Digit5,
    ];
    for (k, name) in digits.iter().zip(catalog::NAMES) {
        if hit(*k) && settings.space != *name {
            settings.space = (*name).to_string();
        }
    }
    if hit(KeyCode::BracketLeft) && settings.levels > 1 {
        settings.levels -= 1;
    }
    if hit(KeyCode::BracketRight) && settings.levels < settings::MAX_LEVEL {
        settings.levels += 1;
    }
    if hit(KeyCode::KeyF) {
        settings.fog = !settings.fog;
    }
    if hit(KeyCode::KeyC) {
        settings.cells = !settings.cells;
    }
    if hit(KeyCode::KeyM) {
        let i = CellMode::ALL.iter().position(|m| *m == settings.cell_mode).unwrap_or(0);
        settings.cell_mode = CellMode::ALL[(i + 1) % CellMode::ALL.len()];
        settings.cells = true;
    }
    // The camera's copy: its domain cell's id, or in a product space its
    // exact copy's (the space's exact cells made only when asked).
    let here = || {
        cells.get(world.camera).map(|c| c.id.0).ok().or_else(|| {
            let (space, camera) = (world.product.as_ref()?, products.get(world.camera).ok()?);
            let exact = bevy_manifold::space::product_cells::ProductCells::of(space)?;
            Some(exact.id(&camera.view.cell?).0)
        })
    };
    if hit(KeyCode::KeyP)
        && let Some(id) = here()
    {
        settings.highlight = id;
        settings.cell_mode = CellMode::Highlight;
        settings.cells = true;
    }
    if hit(KeyCode::KeyG) {
        settings.edges = !settings.edges;
    }
    if hit(KeyCode::KeyB) {
        settings.suzanne = match settings.suzanne {
            SuzanneMode::Attached => SuzanneMode::Free,
            SuzanneMode::Free => SuzanneMode::Hidden,
            SuzanneMode::Hidden => SuzanneMode::Attached,
        };
    }
    if hit(KeyCode::KeyV) {
        settings.vehicle = !settings.vehicle;
    }
    if hit(KeyCode::KeyR) {
        match (&world.product, products.get_mut(world.camera)) {
            (Some(space), Ok(mut camera)) => {
                let mut start = bevy_manifold::trace::product::ProductScene::lit_for(space).view;
                view::set_product_view(&mut start, &settings);
                camera.view = start;
            }
            _ => {
                let (placement, _) = bevy_manifold::drawables::paper::paper_camera(&world.space);
                commands.entity(world.camera).insert((
                    placement,
                    DomainCell::default(),
                    bevy_manifold::tour::FaceWord::default(),
                ));
            }
        }
    }
    if hit(KeyCode::Tab) {
        settings.panel = !settings.panel;
    }
    if hit(KeyCode::F12)
        && let Some(view) = view
    {
        let secs = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_secs());
        let path = format!("bevy_manifold-{}-{secs}.png", world.name());
        status.say(format!("screenshot: {path} ({}x{})", view.size.x, view.size.y), false);
        commands
            .spawn(Screenshot::image(view.image.clone()))
            .observe(save_to_disk(path));
    }
}

/// Saves the settings a second after they last changed.
fn save_settings(settings: Res<ExplorerSettings>, mut file: ResMut<SettingsFile>, mut status: ResMut<ExplorerStatus>) {
    if file.path.is_none() {
        return;
    }
    if settings.is_changed() && *settings != file.saved {
        file.due = Some(Instant::now() + Duration::from_secs(1));
    }
    if file.due.is_some_and(|d| Instant::now() >= d) {
        write_settings(&settings, &mut file, &mut status);
    }
}

fn write_settings(settings: &ExplorerSettings, file: &mut SettingsFile, status: &mut ExplorerStatus) {
    file.due = None;
    let Some(path) = &file.path else { return };
    match settings.save(path) {
        Ok(()) => file.saved = settings.clone(),
        Err(e) => status.say(format!("settings not saved to {}: {e}", path.display()), true),
    }
}

fn save_on_exit(
    exits: MessageReader<AppExit>,
    settings: Res<ExplorerSettings>,
    mut file: ResMut<SettingsFile>,
    mut status: ResMut<ExplorerStatus>,
) {
    if !exits.is_empty() && *settings != file.saved {
        write_settings(&settings, &mut file, &mut status);
    }
}

/// The explorer's app with its window, starting from `settings`, saving
/// them to `settings_path` (`None`: not saved), loading assets from
/// `asset_root` (`None`: Bevy's default).
pub(crate) fn window_app(
    settings: ExplorerSettings,
    settings_path: Option<PathBuf>,
    asset_root: Option<String>,
) -> App {
    explorer_app(settings, settings_path, asset_root, None, true)
}

/// The explorer's app: with its window and panel (`window`), or for the
/// headset alone; with OpenXR when `xr` gives the world scale.
fn explorer_app(
    settings: ExplorerSettings,
    settings_path: Option<PathBuf>,
    asset_root: Option<String>,
    xr: Option<f64>,
    window: bool,
) -> App {
    let mut assets = AssetPlugin::default();
    if let Some(root) = asset_root {
        assets.file_path = root;
    }
    let plugins = if window {
        DefaultPlugins
            .set(WindowPlugin {
                primary_window: Some(Window {
                    title: "bevy_manifold explorer".into(),
                    resolution: (1280, 720).into(),
                    ..default()
                }),
                ..default()
            })
            .set(assets)
    } else {
        // No winit: the schedule runner loops the app instead.
        bevy_manifold::render::offscreen::plugins()
            .set(assets)
            .add(bevy::app::ScheduleRunnerPlugin::run_loop(Duration::ZERO))
    };
    let mut app = App::new();
    match xr {
        #[cfg(feature = "xr")]
        Some(_) => app.add_plugins(xr::plugins(plugins)),
        _ => app.add_plugins(plugins),
    };
    app.insert_resource(settings)
        .add_plugins(ExplorerPlugin { settings_path });
    if window {
        app.add_plugins(panel::ExplorerPanelPlugin);
    }
    #[cfg(feature = "xr")]
    if let Some(world_scale) = xr {
        app.add_plugins(xr::ExplorerXrPlugin {
            world_scale,
            spectator: window,
        });
    }
    app
}

/// Loads the settings from [`settings::settings_path`] (printing what was
/// wrong with them), then opens the explorer window; or, without a display
/// or a GPU adapter, says so and renders `explorer.png` instead.
pub fn run() -> AppExit {
    run_with(ExploreOptions::default())
}

/// How `explore` runs: see [`run_with`].
#[derive(Clone, Debug, Default)]
pub struct ExploreOptions {
    /// Open this space (a catalog or library name, or a space file)
    /// instead of the one last shown; one that does not resolve is an
    /// error naming it, and the explorer does not open.
    pub space: Option<String>,
    /// Quit after this many frames (smoke tests); in a headset, after
    /// this many frames with both eyes traced.
    pub frames: Option<u32>,
    /// With `frames`: save the whole window, panel included, to this PNG
    /// at that frame.
    pub screenshot: Option<PathBuf>,
    /// Play this tour file (a broken one is reported and the explorer
    /// opens without it).
    pub tour: Option<PathBuf>,
    /// In a headset through OpenXR (feature `xr`), at this many metres of
    /// the room per unit of the space.
    pub xr: Option<f64>,
    /// With `xr` and `frames`: save each eye's traced image, read back from
    /// its view target, as `eye0.png` and `eye1.png` in this folder at that
    /// frame.
    pub xr_capture: Option<PathBuf>,
    /// Hold this frame rate by tracing fewer pixels when frames are slow
    /// (the panel's "hold a frame rate"; in a headset both eyes follow).
    pub hold_fps: Option<f32>,
}

/// [`run`], playing the tour file `tour` when given (a broken one is
/// reported and the explorer opens without it), quitting after `frames`
/// frames when given (smoke tests), and then saving the whole window,
/// panel included, to `screenshot`.
pub fn run_for(frames: Option<u32>, screenshot: Option<PathBuf>, tour: Option<PathBuf>) -> AppExit {
    run_with(ExploreOptions {
        frames,
        screenshot,
        tour,
        ..ExploreOptions::default()
    })
}

/// What `--space` names, as the settings keep it: a catalog, library or
/// product space's name as it is, a file by its absolute path (so the
/// saved settings find it from any directory); or why it is none of
/// these, naming it.
fn explored_space(space: &str) -> Result<String, String> {
    if view::product_space(space).is_some() {
        return Ok(space.to_owned());
    }
    bevy_manifold::space::catalog::resolve(space).map_err(|e| format!("{space}: {e}"))?;
    let path = std::path::Path::new(space);
    let known = bevy_manifold::space::catalog::by_name(space).is_some()
        || bevy_manifold::space::library::by_name(space).is_some();
    Ok(match path.canonicalize() {
        Ok(absolute) if !known => absolute.display().to_string(),
        _ => space.to_owned(),
    })
}

/// [`run_for`] with every option: in a headset too (`xr`), with the
/// window when there is a display, for the headset alone when not.
pub fn run_with(options: ExploreOptions) -> AppExit {
    let ExploreOptions {
        space,
        frames,
        screenshot,
        tour,
        xr,
        xr_capture,
        hold_fps,
    } = options;
    if xr.is_some() && !cfg!(feature = "xr") {
        eprintln!("warning: --xr: this build has no OpenXR support (feature `xr`); the explorer runs on the desktop");
    }
    let xr = xr.filter(|_| cfg!(feature = "xr"));
    let path = settings::settings_path();
    let first_run = path.as_ref().is_some_and(|p| !p.exists());
    let (mut settings, mut warnings) = match &path {
        Some(p) => settings::load(p),
        None => (
            ExplorerSettings::default(),
            vec!["no config directory is known: settings are not saved".into()],
        ),
    };
    if let Some(space) = space {
        match explored_space(&space) {
            Ok(name) => settings.space = name,
            Err(e) => {
                eprintln!("error: --space {e}");
                return AppExit::error();
            }
        }
    }
    if let Some(fps) = hold_fps {
        settings.hold_frame_rate = true;
        settings.target_fps = fps;
        warnings.extend(settings.sanitize());
    }
    let mut tour_state = tour::ExplorerTour::default();
    if let Some(path) = &tour
        && let Err(e) = tour_state.open(path, &mut settings)
    {
        warnings.push(format!("tour not opened: {e}"));
    }
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    // A headset needs no display: without one the XR explorer runs for
    // the headset alone (the runtime finds its own GPU adapter).
    let window = match fallback::window_adapter() {
        Ok(a) => {
            // A first run on a software rasteriser (lavapipe, WARP,
            // SwiftShader) starts at half resolution and four levels, or
            // a frame takes seconds.
            if first_run && a.device_type == wgpu::DeviceType::Cpu {
                settings.render_scale = 0.5;
                settings.levels = 4;
                let note = "a software GPU adapter: starting at render scale 0.5 and 4 levels (the panel sets both)";
                eprintln!("note: {note}");
                warnings.push(note.into());
            }
            true
        }
        Err(why) if xr.is_some() => {
            println!("xr: {why}; running for the headset alone");
            false
        }
        Err(why) => return fallback::render_instead(&why, &settings, std::path::Path::new("explorer.png")),
    };
    let fallback_settings = settings.clone();
    let mut app = explorer_app(settings, path, None, xr, window);
    if !window && !xr_frames_counted(app.world()) {
        // No window and no headset after all: as plain `explore` does.
        drop(app);
        let why = "no display and no OpenXR runtime";
        return fallback::render_instead(why, &fallback_settings, std::path::Path::new("explorer.png"));
    }
    app.insert_resource(tour_state);
    if !warnings.is_empty() {
        app.world_mut().resource_mut::<ExplorerStatus>().message = Some((warnings.join("\n"), true));
    }
    if let Some(n) = frames {
        let started = Instant::now();
        app.add_systems(
            Last,
            move |world: &mut World, mut count: Local<u32>, mut done: Local<bool>| {
                if *done {
                    return;
                }
                *count += 1;
                // In a headset: frames with both eyes traced; on the
                // desktop (or without a runtime): updates.
                let (reached, waited) = if xr_frames_counted(world) {
                    (xr_traced(world) >= u64::from(n), started.elapsed() > XR_FRAMES_TIMEOUT)
                } else {
                    (*count >= n, false)
                };
                if !(reached || waited) {
                    return;
                }
                if reached
                    && let Some(dir) = &xr_capture
                    && xr_frames_counted(world)
                {
                    // The eyes' images first: asked for once, saved when
                    // they come back.
                    match xr_capture_step(world, dir) {
                        Ok(false) => return,
                        Ok(true) => {}
                        Err(e) => {
                            eprintln!("error: xr: {e}");
                            *done = true;
                            world.write_message(AppExit::error());
                            return;
                        }
                    }
                }
                *done = true;
                smoke_summary(world, n);
                if waited && !reached {
                    eprintln!(
                        "error: xr: {} of {n} frames traced in {} s",
                        xr_traced(world),
                        XR_FRAMES_TIMEOUT.as_secs()
                    );
                    world.write_message(AppExit::error());
                    return;
                }
                match &screenshot {
                    Some(path) if window => {
                        world
                            .spawn(Screenshot::primary_window())
                            .observe(save_to_disk(path.clone()))
                            .observe(|_: On<ScreenshotCaptured>, mut exit: MessageWriter<AppExit>| {
                                exit.write(AppExit::Success);
                            });
                    }
                    _ => {
                        world.write_message(AppExit::Success);
                    }
                }
            },
        );
    }
    app.run()
}

/// How long `--frames` waits for a headset's frames before giving up.
const XR_FRAMES_TIMEOUT: Duration = Duration::from_secs(300);

/// Whether `--frames` counts the headset's frames: an OpenXR runtime is
/// there.
fn xr_frames_counted(world: &World) -> bool {
    #[cfg(feature = "xr")]
    {
        xr::available(world)
    }
    #[cfg(not(feature = "xr"))]
    {
        let _ = world;
        false
    }
}

/// One step of `--xr-capture`: asks for the eyes' images, then saves them
/// when they are back (`Ok(true)`).
fn xr_capture_step(world: &mut World, dir: &std::path::Path) -> Result<bool, String> {
    #[cfg(feature = "xr")]
    {
        xr::capture_step(world, dir)
    }
    #[cfg(not(feature = "xr"))]
    {
        let _ = (world, dir);
        Ok(true)
    }
}

/// Frames with both eyes traced (0 without `xr`).
fn xr_traced(world: &World) -> u64 {
    #[cfg(feature = "xr")]
    {
        xr::frames_traced(world)
    }
    #[cfg(not(feature = "xr"))]
    {
        let _ = world;
        0
    }
}

/// What a smoke run measured, for its log.
fn smoke_summary(world: &World, n: u32) {
    let status = world.resource::<ExplorerStatus>();
    let view = world.resource::<ExplorerView>();
    let tour = world.resource::<tour::ExplorerTour>();
    let played = match &tour.tour {
        Some(t) => format!("; tour {} at {:.2} s of {:.0}", tour.path, tour.time, t.duration()),
        None => String::new(),
    };
    println!(
        "explorer: {n} frames, mean frame time over the last {:.0} s {:.1} ms, view {}x{} traced{played}",
        ExplorerStatus::HISTORY_SECS,
        status.mean_frame_ms().unwrap_or(f32::NAN),
        view.size.x,
        view.size.y
    );
    #[cfg(feature = "xr")]
    xr::say_summary(world);
}
