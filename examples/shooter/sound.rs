//! The shooter's sounds (feature `audio`), made in code: each shot is
//! heard from where it was fired, through the faces, from the nearest
//! images of that place ([`bevy_manifold::audio`]); hits and rams are
//! heard from the player, as loud as the geometry leaves a sound that
//! travelled the shot's distance.

use crate::game::{Game, GameEvent, Player, Shot};
use bevy::prelude::*;
use bevy_manifold::audio::{ManifoldListener, ManifoldSound, sound_gain, wav_source};
use bevy_manifold::prelude::*;

const RATE: u32 = 22_050;

/// The game's sounds.
#[derive(Resource)]
pub struct Sounds {
    shot: Handle<AudioSource>,
    enemy_shot: Handle<AudioSource>,
    hit: Handle<AudioSource>,
    rammed: Handle<AudioSource>,
}

/// Adds the sounds and the systems that play them.
pub struct SoundPlugin;

impl Plugin for SoundPlugin {
    fn build(&self, app: &mut App) {
        app.add_plugins(bevy_manifold::audio::ManifoldAudioPlugin)
            .add_systems(Startup, make_sounds)
            .add_systems(Update, (hear_with_the_player, shots_are_heard, events_are_heard));
    }
}

/// A falling tone: `seconds` long from `from` to `to` Hz, fading out.
fn chirp(seconds: f32, from: f32, to: f32) -> Vec<f32> {
    let n = (seconds * RATE as f32) as usize;
    let mut phase = 0.0f32;
    (0..n)
        .map(|i| {
            let t = i as f32 / n as f32;
            phase += core::f32::consts::TAU * (from + (to - from) * t) / RATE as f32;
            phase.sin() * (1.0 - t).powi(2) * 0.6
        })
        .collect()
}

/// A burst of noise (a fixed sequence, so every run sounds alike).
fn burst(seconds: f32, tone: f32) -> Vec<f32> {
    let n = (seconds * RATE as f32) as usize;
    let mut state = 0x2545_f491_u32;
    (0..n)
        .map(|i| {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            let noise = state as f32 / u32::MAX as f32 * 2.0 - 1.0;
            let t = i as f32 / n as f32;
            let low = (core::f32::consts::TAU * tone * i as f32 / RATE as f32).sin();
            (0.5 * noise + 0.5 * low) * (1.0 - t).powi(3) * 0.8
        })
        .collect()
}

fn make_sounds(mut commands: Commands, mut sources: ResMut<Assets<AudioSource>>) {
    commands.insert_resource(Sounds {
        shot: sources.add(wav_source(&chirp(0.18, 1400.0, 500.0), RATE)),
        enemy_shot: sources.add(wav_source(&chirp(0.25, 600.0, 200.0), RATE)),
        hit: sources.add(wav_source(&burst(0.35, 180.0), RATE)),
        rammed: sources.add(wav_source(&burst(0.6, 60.0), RATE)),
    });
}

/// The player hears (its camera is the player).
fn hear_with_the_player(mut commands: Commands, players: Query<Entity, (With<Player>, Without<ManifoldListener>)>) {
    for p in &players {
        commands.entity(p).insert(ManifoldListener);
    }
}

/// Each new shot is heard from where it was fired.
fn shots_are_heard(
    mut commands: Commands,
    sounds: Option<Res<Sounds>>,
    game: Option<Res<Game>>,
    shots: Query<(&Shot, &Placement), Added<Shot>>,
) {
    let (Some(sounds), Some(game)) = (sounds, game) else {
        return;
    };
    for (shot, placement) in &shots {
        let source = if shot.by_player {
            &sounds.shot
        } else {
            &sounds.enemy_shot
        };
        commands.spawn((ChildOf(game.root), *placement, ManifoldSound::effect(source.clone())));
    }
}

/// Hits and rams, heard from the player, a hit as faint as its distance.
fn events_are_heard(
    mut commands: Commands,
    sounds: Option<Res<Sounds>>,
    game: Option<Res<Game>>,
    spaces: Query<&ManifoldSpace>,
    players: Query<&Placement, With<Player>>,
    mut seen: Local<usize>,
) {
    let (Some(sounds), Some(game)) = (sounds, game) else {
        return;
    };
    if game.log.len() < *seen {
        // A new game.
        *seen = 0;
    }
    let (Ok(ms), Ok(at)) = (spaces.get(game.root), players.get(game.player)) else {
        return;
    };
    let g = ms.space().geometry();
    for (_, event) in &game.log[*seen..] {
        let (source, distance) = match *event {
            GameEvent::TargetHit { distance, .. } | GameEvent::EnemyHit { distance } => (&sounds.hit, distance),
            GameEvent::PlayerHit { .. } | GameEvent::Rammed => (&sounds.rammed, 0.0),
            _ => continue,
        };
        let sound = ManifoldSound::effect(source.clone());
        let volume = sound_gain(g, distance, sound.reference) as f32;
        commands.spawn((ChildOf(game.root), *at, ManifoldSound { volume, ..sound }));
    }
    *seen = game.log.len();
}
