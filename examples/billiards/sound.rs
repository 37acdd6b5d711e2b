//! The table's sounds (feature `audio`), made in code: two balls that
//! meet click where they touched, heard through the faces from the
//! nearest images of that point ([`bevy_manifold::audio`]) and as loud
//! as they closed in; the cue's stroke and a ball dropping into a pocket
//! are heard from the player.

use crate::table::{Player, Table, TableEvent};
use bevy::prelude::*;
use bevy_manifold::audio::{ManifoldListener, ManifoldSound, wav_source};
use bevy_manifold::geometry::isometry;
use bevy_manifold::prelude::*;

const RATE: u32 = 22_050;

/// The table's sounds.
#[derive(Resource)]
pub struct Sounds {
    click: Handle<AudioSource>,
    stroke: Handle<AudioSource>,
    pocket: Handle<AudioSource>,
}

/// Adds the sounds and the systems that play them.
pub struct SoundPlugin;

impl Plugin for SoundPlugin {
    fn build(&self, app: &mut App) {
        app.add_plugins(bevy_manifold::audio::ManifoldAudioPlugin)
            .add_systems(Startup, make_sounds)
            .add_systems(Update, (hear_with_the_player, events_are_heard));
    }
}

/// A struck ringing body: partials at `freqs`, each dying at its `decay`
/// per second, for `seconds`.
fn knock(seconds: f32, freqs: &[(f32, f32)]) -> Vec<f32> {
    let n = (seconds * RATE as f32) as usize;
    (0..n)
        .map(|i| {
            let t = i as f32 / RATE as f32;
            let ring: f32 = freqs
                .iter()
                .map(|&(f, decay)| (core::f32::consts::TAU * f * t).sin() * (-decay * t).exp())
                .sum();
            ring * 0.5 / freqs.len() as f32
        })
        .collect()
}

fn make_sounds(mut commands: Commands, mut sources: ResMut<Assets<AudioSource>>) {
    commands.insert_resource(Sounds {
        // Phenolic balls: a short, high click.
        click: sources.add(wav_source(
            &knock(0.12, &[(2_900.0, 60.0), (4_700.0, 90.0), (7_300.0, 120.0)]),
            RATE,
        )),
        // The cue's leather tip: lower and duller.
        stroke: sources.add(wav_source(&knock(0.1, &[(900.0, 70.0), (1_500.0, 110.0)]), RATE)),
        // A ball rolling into the pocket: a low thud.
        pocket: sources.add(wav_source(&knock(0.4, &[(110.0, 9.0), (170.0, 14.0)]), RATE)),
    });
}

/// The player hears (its camera is the player).
fn hear_with_the_player(mut commands: Commands, players: Query<Entity, (With<Player>, Without<ManifoldListener>)>) {
    for p in &players {
        commands.entity(p).insert(ManifoldListener);
    }
}

/// Each new event of the table's log, heard.
fn events_are_heard(
    mut commands: Commands,
    sounds: Option<Res<Sounds>>,
    table: Option<Res<Table>>,
    spaces: Query<&ManifoldSpace>,
    players: Query<&Placement, With<Player>>,
    mut seen: Local<usize>,
) {
    let (Some(sounds), Some(table)) = (sounds, table) else {
        return;
    };
    if table.log.len() < *seen {
        // The balls were racked again.
        *seen = 0;
    }
    let (Ok(ms), Ok(player)) = (spaces.get(table.root), players.get(table.player)) else {
        return;
    };
    let g = ms.space().geometry();
    let full = table.rules.max_speed;
    for (_, event) in &table.log[*seen..] {
        let (source, at, volume) = match event {
            TableEvent::Collision { point, speed, .. } => (
                &sounds.click,
                Placement::from_isometry(isometry::translation_to(g, *point)),
                (speed / full) as f32,
            ),
            TableEvent::Struck { speed } => (&sounds.stroke, *player, (speed / full) as f32),
            TableEvent::Sunk(_) | TableEvent::Scratch => (&sounds.pocket, *player, 0.8),
            TableEvent::Cleared { .. } => continue,
        };
        let sound = ManifoldSound::effect(source.clone());
        commands.spawn((ChildOf(table.root), at, ManifoldSound { volume, ..sound }));
    }
    *seen = table.log.len();
}
