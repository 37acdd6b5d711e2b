//! `explore --xr`: the explorer in a headset through OpenXR
//! (bevy_manifold's `xr` feature). The explorer's camera is the body that
//! carries the room ([`XrBody`]): the keys and the desktop panel fly it,
//! switch spaces, levels, fog and cell shading, and each eye follows with
//! the same settings; the desktop window keeps the camera's own view, a
//! spectator at the room's centre. With a display it opens the usual
//! window as well; without one it runs for the headset alone.
//!
//! In the headset the paper's hands follow the controllers' grips; the
//! left stick flies, the right stick turns (snap) and flies up and down,
//! the primary button (A or X) goes to the next space of the catalog, the
//! secondary (B or Y) back to the start, and both triggers held
//! together for two seconds leave the explorer.
//!
//! Without an OpenXR runtime it says so in one line and runs on the desktop
//! as plain `explore` does. What a run saw goes to stdout, one `xr:` line
//! each: the session states OpenXR reported, and at the end how many
//! frames had both eyes traced.

use super::{ExplorerCamera, ExplorerSettings, ExplorerWorld};
use bevy::prelude::*;
use bevy_manifold::space::catalog;
use bevy_manifold::space::product::ProductSpace;
use bevy_manifold::xr::{
    ManifoldXrPlugin, XrBody, XrControllers, XrEyeCapture, XrFrameStats, XrHand, XrHandSide, XrState,
};
use bevy_mod_openxr::init::OxrInitPlugin;
use bevy_mod_openxr::poll_events::{OxrEventHandlerExt, OxrEventIn};
use bevy_mod_openxr::types::AppInfo;
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::Instant;

/// Metres of the room per unit of the space, for the explorer's body.
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
pub struct ExplorerXr {
    /// [`XrBody::world_scale`].
    pub world_scale: f64,
}

/// When the session first became FOCUSED during this run (the frame rate
/// is measured from there).
static FOCUSED_AT: std::sync::Mutex<Option<Instant>> = std::sync::Mutex::new(None);

/// Frames `--xr-capture` has waited for the eyes' images.
static CAPTURE_WAIT: AtomicU32 = AtomicU32::new(0);

/// `plugins` (Bevy's defaults, with or without a window) with
/// bevy_mod_openxr's session, swapchain and eye cameras.
pub fn plugins(plugins: bevy::app::PluginGroupBuilder) -> bevy::app::PluginGroupBuilder {
    bevy_mod_openxr::add_xr_plugins(plugins).set(OxrInitPlugin {
        app_info: AppInfo {
            name: "bevy_manifold explorer".into(),
            ..default()
        },
        ..default()
    })
}

/// The explorer's XR side: the body on the explorer's camera, the state
/// lines, the fallback note.
#[derive(Debug, Clone, Copy)]
pub struct ExplorerXrPlugin {
    /// [`XrBody::world_scale`].
    pub world_scale: f64,
    /// Whether the explorer's camera is traced for a desktop window (off
    /// for the headset alone: nobody would see it).
    pub spectator: bool,
}

impl Plugin for ExplorerXrPlugin {
    fn build(&self, app: &mut App) {
        app.insert_resource(ExplorerXr {
            world_scale: self.world_scale,
        })
        .add_plugins(ManifoldXrPlugin)
        .add_oxr_event_handler(print_session_state)
        .add_systems(Startup, say_if_unavailable)
        .add_systems(
            Update,
            (put_body_on_camera, hands_on_controllers, buttons).after(super::view::apply_settings),
        );
        if !self.spectator {
            app.add_systems(Update, no_spectator.after(put_body_on_camera));
        }
    }
}

fn say_if_unavailable(state: Option<Res<XrState>>) {
    if state.is_none_or(|s| *s == XrState::Unavailable) {
        println!("xr: no OpenXR runtime answered (see the error above); the explorer runs on the desktop");
    }
}

fn print_session_state(event: OxrEventIn) {
    if let openxr::Event::SessionStateChanged(s) = *event {
        let state = s.state();
        if state == openxr::SessionState::FOCUSED
            && let Ok(mut at) = FOCUSED_AT.lock()
        {
            at.get_or_insert_with(Instant::now);
        }
        println!("xr: session state {state:?}");
    }
}

/// The explorer's camera (re-spawned with each space) is the body.
fn put_body_on_camera(
    mut commands: Commands,
    world: Option<Res<ExplorerWorld>>,
    xr: Res<ExplorerXr>,
    cameras: Query<Option<&XrBody>, With<ExplorerCamera>>,
) {
    let Some(world) = world else { return };
    let wanted = XrBody {
        world_scale: xr.world_scale,
    };
    if let Ok(body) = cameras.get(world.camera)
        && body != Some(&wanted)
    {
        commands.entity(world.camera).insert(wanted);
    }
}

/// The paper's hands (children of the explorer's camera, the body) move
/// onto two [`XrHand`]s, so they follow the grips; made again with each
/// space.
fn hands_on_controllers(
    mut commands: Commands,
    world: Option<Res<ExplorerWorld>>,
    xr: Res<ExplorerXr>,
    hands: Query<(Entity, &Name, &ChildOf, &Transform), Without<XrHand>>,
) {
    let Some(world) = world else { return };
    for (entity, name, parent, transform) in &hands {
        let side = match name.as_str() {
            "left hand" => XrHandSide::Left,
            "right hand" => XrHandSide::Right,
            _ => continue,
        };
        if parent.parent() != world.camera {
            continue;
        }
        // The model's size in the room: what the desktop shows at 0.3 of
        // the inradius, at arm's length (0.45 m).
        let r = world.space.inradius();
        let scale = transform.scale * (0.45 / xr.world_scale / (0.3 * r)) as f32;
        let hand = commands
            .spawn((Name::new("XR hand"), ChildOf(world.root), XrHand(side)))
            .id();
        commands
            .entity(entity)
            .insert((ChildOf(hand), Transform::from_scale(scale)));
    }
}

/// How long both triggers are held to leave.
const LEAVE_AFTER_SECS: f32 = 2.0;

/// The primary button: the next space (the catalog's, then the product
/// spaces', round again); both triggers held: leave.
fn buttons(
    time: Res<Time>,
    controllers: Res<XrControllers>,
    mut settings: ResMut<ExplorerSettings>,
    mut held: Local<(bool, f32)>,
    mut exit: MessageWriter<AppExit>,
) {
    let [left, right] = controllers.hands;
    let primary = left.primary || right.primary;
    if primary && !held.0 {
        let names: Vec<&str> = catalog::NAMES.iter().chain(&ProductSpace::NAMES).copied().collect();
        let at = names.iter().position(|n| *n == settings.space);
        let next = at.map_or(0, |i| (i + 1) % names.len());
        settings.space = names[next].to_string();
    }
    held.0 = primary;
    if left.trigger > 0.9 && right.trigger > 0.9 {
        held.1 += time.delta_secs();
        if held.1 >= LEAVE_AFTER_SECS {
            println!("xr: both triggers held {LEAVE_AFTER_SECS} s: leaving");
            exit.write(AppExit::Success);
        }
    } else {
        held.1 = 0.0;
    }
}

/// Without a window the explorer's own camera is not traced.
fn no_spectator(mut cameras: Query<&mut Camera, (With<ExplorerCamera>, With<XrBody>)>) {
    for mut camera in &mut cameras {
        if camera.is_active {
            camera.is_active = false;
        }
    }
}

/// Whether OpenXR is there at all (`false`: the desktop fallback).
#[must_use]
pub fn available(world: &World) -> bool {
    world
        .get_resource::<XrState>()
        .is_some_and(|s| *s != XrState::Unavailable)
}

/// Frames with both eyes traced so far.
#[must_use]
pub fn frames_traced(world: &World) -> u64 {
    world
        .get_resource::<XrFrameStats>()
        .map_or(0, XrFrameStats::both_eyes_traced)
}

/// `--xr-capture`: asks for both eyes' images the first time, and saves
/// them as `eye0.png` and `eye1.png` in `dir` once they are back
/// (`Ok(true)`); gives up after 300 frames.
pub fn capture_step(world: &mut World, dir: &std::path::Path) -> Result<bool, String> {
    let capture = world.resource::<XrEyeCapture>().clone();
    let waited = CAPTURE_WAIT.fetch_add(1, Ordering::Relaxed);
    if waited == 0 {
        capture.request();
    }
    if let Some(images) = capture.take() {
        let paths = bevy_manifold::xr::save_eyes(&images, dir)?;
        for (i, (eye, path)) in images.iter().zip(&paths).enumerate() {
            println!("xr: eye {i} ({}x{}) saved to {}", eye.width, eye.height, path.display());
        }
        return Ok(true);
    }
    if waited > 300 {
        return Err("the eyes' images did not come back within 300 frames".into());
    }
    Ok(false)
}

/// The run's last `xr:` line.
pub fn say_summary(world: &World) {
    if available(world) {
        let since = FOCUSED_AT
            .lock()
            .ok()
            .and_then(|a| *a)
            .map(|a| a.elapsed().as_secs_f64());
        let rate = since.map_or(String::new(), |s| {
            format!(
                ", {:.1} frames/s over the {s:.1} s since FOCUSED",
                frames_traced(world) as f64 / s
            )
        });
        println!(
            "xr: focused {}, {} frames with both eyes traced{rate}",
            since.is_some(),
            frames_traced(world)
        );
    }
}
