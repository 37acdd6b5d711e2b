//! What the examples share (each takes it with `#[path]`, as Bevy's examples take their helpers): a window with the fly camera
//! and a line of help, or, with `--screenshot FILE.png [--size WxH]`, one
//! frame rendered without a window and saved, then exit. The examples'
//! own setup is ordinary Bevy code: spawn a `ManifoldCamera`
//! as always; in screenshot mode it is pointed at an offscreen image.
//!
//! ```ignore
//! use bevy::prelude::*;
//! use bevy_manifold::prelude::*;
//! #[path = "support/showcase.rs"]
//! mod showcase;
//!
//! fn main() -> AppExit {
//!     let mut app = showcase::app("The 3-torus", "a ball in every copy");
//!     app.add_systems(Startup, |mut commands: Commands| {
//!         let space = catalog::torus(1.0);
//!         let root = commands.spawn(ManifoldSpace::new(space.clone())).id();
//!         commands.spawn((ChildOf(root), ManifoldCamera::default(), FlyCamera::default(), Placement::at(&space, glam::DVec3::Z * 0.3)));
//!         commands.spawn((ChildOf(root), TracedBall::new(0.1, Color::WHITE)));
//!     });
//!     showcase::run(app)
//! }
//! ```

use bevy::camera::RenderTarget;
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bevy_manifold::camera::FlyCameraPlugin;
use bevy_manifold::camera::ManifoldCamera;
use bevy_manifold::render::offscreen;
use std::path::PathBuf;
use std::time::Duration;

/// The value after `name` on the command line (`--size 320x180`).
#[must_use]
pub fn arg(name: &str) -> Option<String> {
    std::env::args().skip_while(|a| a != name).nth(1)
}

/// True when `name` is on the command line (`--fog`).
#[must_use]
pub fn flag(name: &str) -> bool {
    std::env::args().any(|a| a == name)
}

/// `WxH`, both at least 1.
///
/// ```
/// assert_eq!(bevy_manifold::showcase::parse_size("320x180"), Some((320, 180)));
/// assert_eq!(bevy_manifold::showcase::parse_size("0x180"), None);
/// ```
#[must_use]
pub fn parse_size(s: &str) -> Option<(u32, u32)> {
    let (w, h) = s.split_once('x')?;
    let (w, h) = (w.parse().ok()?, h.parse().ok()?);
    (w > 0 && h > 0).then_some((w, h))
}

/// Screenshot mode: where to save, and the offscreen image the manifold
/// camera draws into.
#[derive(Resource, Clone)]
pub struct ScreenshotMode {
    /// The PNG to write.
    pub path: PathBuf,
    /// The image every manifold camera renders into.
    pub target: Handle<Image>,
}

/// Screenshot mode for an app built by hand (a game's own plugins on
/// `offscreen::plugins()`, finished and cleaned up): a `w x h` target
/// that every manifold camera (and product camera) draws into, saved to
/// `path` by [`run`].
/// Returns the target.
pub fn screenshot_mode(app: &mut App, path: PathBuf, (w, h): (u32, u32)) -> Handle<Image> {
    let target = offscreen::target(app, w, h);
    app.insert_resource(ScreenshotMode {
        path,
        target: target.clone(),
    });
    app.add_observer(
        |add: On<Add, ManifoldCamera>, mode: Res<ScreenshotMode>, mut commands: Commands| {
            commands
                .entity(add.entity)
                .insert(RenderTarget::Image(mode.target.clone().into()));
        },
    );
    app.add_observer(
        |add: On<Add, bevy_manifold::product::ProductCamera>, mode: Res<ScreenshotMode>, mut commands: Commands| {
            commands
                .entity(add.entity)
                .insert(RenderTarget::Image(mode.target.clone().into()));
        },
    );
    target
}

/// Plays `ticks` ticks of a fixed clock of `hz` in one update, then stops
/// the clock: a game's moment before its screenshot, which stays that
/// moment however long the shaders take to compile.
pub fn play_ticks(app: &mut App, hz: f64, ticks: u32) {
    app.world_mut()
        .resource_mut::<Time<Virtual>>()
        .set_max_delta(Duration::from_secs(60));
    let tick = Duration::from_secs_f64(1.0 / hz);
    app.insert_resource(TimeUpdateStrategy::ManualDuration(tick * ticks));
    app.update();
    app.insert_resource(TimeUpdateStrategy::ManualDuration(Duration::ZERO));
}

/// The repository's `assets` folder (the models the examples load),
/// wherever the example's binary is run from: by `cargo run`, by the
/// examples test or by `docs/images/render.sh`.
fn assets() -> AssetPlugin {
    AssetPlugin {
        file_path: concat!(env!("CARGO_MANIFEST_DIR"), "/assets").into(),
        ..default()
    }
}

/// The help line shown over the view.
#[derive(Component)]
struct HelpText;

/// The app an example builds on: in a window titled `title` with `help`
/// and the controls shown, or (with `--screenshot`) offscreen. Either way
/// it has [`crate::ManifoldPlugins`] and [`FlyCameraPlugin`]; add the
/// example's systems and pass it to [`run`].
pub fn app(title: &str, help: &str) -> App {
    if let Some(path) = arg("--screenshot") {
        let (w, h) = arg("--size").as_deref().and_then(parse_size).unwrap_or((640, 360));
        let mut app = App::new();
        app.add_plugins(offscreen::plugins().set(assets()));
        app.add_plugins((crate::ManifoldPlugins::default(), FlyCameraPlugin));
        app.finish();
        app.cleanup();
        screenshot_mode(&mut app, path.into(), (w, h));
        return app;
    }
    let mut app = App::new();
    app.add_plugins(
        DefaultPlugins
            .set(WindowPlugin {
                primary_window: Some(Window {
                    title: title.into(),
                    resolution: (1280, 720).into(),
                    ..default()
                }),
                ..default()
            })
            .set(assets()),
    )
    .add_plugins((crate::ManifoldPlugins::default(), FlyCameraPlugin));
    let text = format!("{title}: {help}\nWASD / Space / Shift fly, arrows or mouse turn, Q / E roll, H hides this");
    app.add_systems(Startup, move |mut commands: Commands| {
        commands.spawn((
            Text::new(text.clone()),
            HelpText,
            Node {
                position_type: PositionType::Absolute,
                bottom: px(10.0),
                left: px(10.0),
                ..default()
            },
        ));
    })
    .add_systems(Update, toggle_help);
    app
}

fn toggle_help(keys: Res<ButtonInput<KeyCode>>, mut text: Query<&mut Visibility, With<HelpText>>) {
    if keys.just_pressed(KeyCode::KeyH) {
        for mut v in &mut text {
            v.toggle_visible_hidden();
        }
    }
}

/// Runs an example's app: the window until it is closed, or in screenshot
/// mode renders once everything has compiled, writes the PNG and returns.
pub fn run(mut app: App) -> AppExit {
    let Some(mode) = app.world().get_resource::<ScreenshotMode>().cloned() else {
        return app.run();
    };
    match screenshot(&mut app, &mode) {
        Ok((w, h)) => {
            println!("wrote {} ({w}x{h})", mode.path.display());
            AppExit::Success
        }
        Err(e) => {
            eprintln!("error: screenshot {}: {e}", mode.path.display());
            AppExit::error()
        }
    }
}

fn screenshot(app: &mut App, mode: &ScreenshotMode) -> Result<(u32, u32), String> {
    wait_for_scenes(app)?;
    offscreen::wait_for_pipelines(app)?;
    // A camera refining its still view: let its samples in first.
    let world = app.world_mut();
    let samples = world
        .query::<&bevy_manifold::camera::ManifoldAccumulation>()
        .iter(world)
        .map(|a| a.samples)
        .max()
        .unwrap_or(0);
    for _ in 0..samples + 2 {
        app.update();
    }
    let rgba = offscreen::capture(app, &mode.target)?;
    let size = app
        .world()
        .resource::<Assets<Image>>()
        .get(&mode.target)
        .map(|i| (i.width(), i.height()))
        .ok_or("the target image is gone")?;
    let image = image::RgbaImage::from_raw(size.0, size.1, rgba).ok_or("the capture has the wrong size")?;
    image.save(&mode.path).map_err(|e| e.to_string())?;
    Ok(size)
}

/// Updates the app until every glTF scene it spawns (each
/// `WorldAssetRoot`) has loaded with its dependencies, or failed to; a
/// minute at most. The meshes a scene brings are what the pipelines then
/// compile for, so a screenshot waits for the scenes first.
fn wait_for_scenes(app: &mut App) -> Result<(), String> {
    use bevy::asset::RecursiveDependencyLoadState as State;
    use bevy::world_serialization::WorldAssetRoot;
    let start = std::time::Instant::now();
    while start.elapsed() < Duration::from_secs(60) {
        app.update();
        let world = app.world_mut();
        let server = world.resource::<AssetServer>().clone();
        let mut roots = world.query::<&WorldAssetRoot>();
        let loading = roots.iter(world).any(|root| {
            matches!(
                server.recursive_dependency_load_state(root.0.id()),
                State::NotLoaded | State::Loading
            )
        });
        if !loading {
            return Ok(());
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    Err("the glTF scenes did not load within a minute".into())
}
