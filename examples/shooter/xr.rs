//! The shooter in a headset (`--xr`; the plugin's `xr` feature, which
//! `cargo run --release --features xr --example shooter -- --xr` turns
//! on): the player is the room's body (`XrBody`), each eye is traced from
//! where it is, the paper's hands follow the controllers, and the
//! controllers are the game's input: the left stick flies (along the
//! player's own axes, as W A S D do), the right stick turns (yaw and
//! pitch), either trigger fires (the plugin's trigger action). The
//! controllers feed the same per-tick input as the keyboard, so a game
//! played in the headset records and replays like any other.

use crate::game::{Game, Player};
use crate::input::InputSource;
use bevy::prelude::*;
use bevy_manifold::xr::{ManifoldXrPlugin, TRIGGER_PULLED, XrBody, XrControllers, XrHandSide, XrLocomotion, XrState};
use glam::DVec3;

/// Adds the headset to the game (after `bevy_mod_openxr::add_xr_plugins`).
pub struct ShooterXrPlugin {
    /// Metres of the room per unit of the space.
    pub world_scale: f64,
}

#[derive(Resource, Clone, Copy)]
struct WorldScale(f64);

impl Plugin for ShooterXrPlugin {
    fn build(&self, app: &mut App) {
        app.insert_resource(WorldScale(self.world_scale))
            .add_plugins(ManifoldXrPlugin)
            .add_systems(Startup, say_if_unavailable)
            .add_systems(Update, body_on_player)
            // After the keyboard's `read_devices` (in `Update`); the game
            // reads the sum at its next tick.
            .add_systems(PostUpdate, controllers_as_input);
    }
}

fn say_if_unavailable(state: Option<Res<XrState>>) {
    if state.is_some_and(|s| *s == XrState::Unavailable) {
        println!("xr: no OpenXR runtime answered; playing on the desktop");
    }
}

/// The player carries the room; the game moves it, not the sticks.
fn body_on_player(
    mut commands: Commands,
    scale: Res<WorldScale>,
    game: Option<Res<Game>>,
    players: Query<Entity, (With<Player>, Without<XrBody>)>,
) {
    let Some(game) = game else { return };
    if let Ok(player) = players.get(game.player) {
        commands.entity(player).insert((
            XrBody { world_scale: scale.0 },
            XrLocomotion {
                enabled: false,
                ..default()
            },
        ));
    }
}

/// Sticks and triggers, added to the keyboard's input of this frame.
fn controllers_as_input(controllers: Res<XrControllers>, mut source: ResMut<InputSource>) {
    if *controllers == XrControllers::default() {
        return;
    }
    let left = controllers.hand(XrHandSide::Left);
    let right = controllers.hand(XrHandSide::Right);
    let live = &mut source.live;
    live.thrust += DVec3::new(f64::from(left.stick.x), 0.0, -f64::from(left.stick.y));
    live.turn += DVec3::new(f64::from(right.stick.y), -f64::from(right.stick.x), 0.0);
    live.thrust = live.thrust.clamp(DVec3::splat(-1.0), DVec3::splat(1.0));
    live.turn = live.turn.clamp(DVec3::splat(-1.0), DVec3::splat(1.0));
    live.fire |= left.trigger >= TRIGGER_PULLED || right.trigger >= TRIGGER_PULLED;
}
