//! Sound in the manifold (feature `audio`): a [`ManifoldSound`] on a placed
//! entity is heard by the [`ManifoldListener`] from the directions of the
//! nearest images of its source, through the faces, each as loud as the
//! geometry makes it.
//!
//! Sound spreads over the geodesic sphere around its source, whose area is
//! `4 pi d^2` (E3), `4 pi sinh^2 d` (H3) or `4 pi sin^2 d` (S3)
//! ([`Geometry::sphere_area`]): its intensity falls as the inverse, so its
//! amplitude as the inverse square root. A sound is at its
//! [`ManifoldSound::volume`] within its [`ManifoldSound::reference`]
//! distance and falls from there ([`sound_gain`]). In S3 the sphere
//! shrinks again past a quarter turn: a sound grows louder towards its
//! source's antipode, as the geometry focuses it there.
//!
//! Bevy's spatial audio pans each image: the plugin keeps one Bevy
//! emitter per heard image (an `AudioPlayer`, outside every space) at the
//! image's direction in the listener's frame, around one Bevy
//! `SpatialListener` it owns, and sets each emitter's volume to the
//! geometry's gain. An app using this plugin should not spawn a
//! `SpatialListener` of its own.
//!
//! ```no_run
//! use bevy::prelude::*;
//! use bevy_manifold::audio::{ManifoldAudioPlugin, ManifoldListener, ManifoldSound};
//! use bevy_manifold::prelude::*;
//!
//! fn setup(mut commands: Commands, assets: Res<AssetServer>) {
//!     let space = catalog::torus(1.0);
//!     let root = commands.spawn(ManifoldSpace::new(space.clone())).id();
//!     commands.spawn((ChildOf(root), ManifoldCamera::default(), ManifoldListener));
//!     // A humming ball, heard through the faces from its two nearest images.
//!     commands.spawn((
//!         ChildOf(root),
//!         Placement::at(&space, glam::DVec3::X * 0.3),
//!         ManifoldSound { images: 2, ..ManifoldSound::looping(assets.load("hum.wav")) },
//!     ));
//! }
//! App::new()
//!     .add_plugins((DefaultPlugins, ManifoldPlugins::default(), ManifoldAudioPlugin))
//!     .add_systems(Startup, setup)
//!     .run();
//! ```

mod wav;

pub use wav::{wav_bytes, wav_source};

use crate::contact;
use crate::geometry::{Geometry, isometry};
use crate::placement::{InSpace, ManifoldSpace, ManifoldSystems, Placement};
use bevy::audio::{
    AudioPlayer, AudioSinkPlayback, AudioSource, PlaybackMode, PlaybackSettings, SpatialAudioSink, SpatialListener,
    Volume,
};
use bevy::prelude::*;
use bevy::transform::TransformSystems;
use glam::{DVec3, DVec4};

/// Most images of one sound heard at once.
pub const MAX_SOUND_IMAGES: usize = 8;

/// The gap between the listener's ears, in Bevy's audio units; emitters are
/// placed [`EMITTER_DISTANCE`] from the listener, so Bevy's own fall-off
/// (the inverse square of the distance, at most 1) leaves them at full
/// volume and only pans them.
pub const EAR_GAP: f32 = 0.2;

/// How far from the listener each image's Bevy emitter sits.
pub const EMITTER_DISTANCE: f32 = 0.5;

/// Adds the systems that place and weigh each sound's heard images, and
/// the Bevy `SpatialListener` they are heard by. Needs Bevy's
/// `AudioPlugin` (in `DefaultPlugins` with the `audio` feature).
#[derive(Debug, Clone, Copy, Default)]
pub struct ManifoldAudioPlugin;

impl Plugin for ManifoldAudioPlugin {
    fn build(&self, app: &mut App) {
        app.register_type::<ManifoldListener>()
            .add_systems(Startup, spawn_listener)
            .add_systems(
                PostUpdate,
                hear_sounds
                    .after(ManifoldSystems::Sync)
                    .before(TransformSystems::Propagate),
            )
            .add_observer(silence_removed_sound);
    }
}

/// The entity that hears (usually the manifold camera): sounds are heard
/// from its placement, in its frame. One at a time; with none, nothing is
/// heard.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Eq, Reflect)]
#[reflect(Component, Debug, Default)]
#[require(Placement)]
pub struct ManifoldListener;

/// A sound a placed entity makes.
#[derive(Component, Clone, Debug)]
#[require(Placement)]
pub struct ManifoldSound {
    /// What it plays.
    pub source: Handle<AudioSource>,
    /// Linear volume within [`ManifoldSound::reference`] of the source.
    pub volume: f32,
    /// The distance within which the sound is at its full volume; beyond,
    /// it falls with the area of the geodesic sphere.
    pub reference: f64,
    /// How many of its nearest images are heard (1 to
    /// [`MAX_SOUND_IMAGES`]): 1 is the shortest route only; more let a
    /// sound in a small space come from several sides at once.
    pub images: usize,
    /// Loop, or play once; [`PlaybackMode::Despawn`] despawns the sound's
    /// entity when it has played.
    pub mode: PlaybackMode,
}

impl ManifoldSound {
    /// A sound that plays once and then despawns its entity (an effect).
    #[must_use]
    pub fn effect(source: Handle<AudioSource>) -> Self {
        ManifoldSound {
            source,
            volume: 1.0,
            reference: 0.1,
            images: 1,
            mode: PlaybackMode::Despawn,
        }
    }

    /// A sound that plays over and over (a hum, an engine).
    #[must_use]
    pub fn looping(source: Handle<AudioSource>) -> Self {
        ManifoldSound {
            mode: PlaybackMode::Loop,
            ..Self::effect(source)
        }
    }
}

/// One image of a sound as the listener hears it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Heard {
    /// Unit direction towards the image in the listener's frame (x right,
    /// y up, -z ahead); straight ahead for a source where the listener is.
    pub direction: DVec3,
    /// Geodesic distance to the image.
    pub distance: f64,
    /// The amplitude gain, [`sound_gain`].
    pub gain: f64,
}

/// The amplitude a sound keeps at `distance`, heard at full volume within
/// `reference`: `sqrt(A(reference) / A(distance))` at most 1, where `A` is
/// the area of the geodesic sphere ([`Geometry::sphere_area`]); `r / d` in
/// E3, `sinh r / sinh d` in H3, `sin r / |sin d|` in S3.
///
/// ```
/// use bevy_manifold::audio::sound_gain;
/// use bevy_manifold::prelude::*;
/// assert!((sound_gain(Geometry::Euclidean, 2.0, 0.5) - 0.25).abs() < 1e-12);
/// assert!((sound_gain(Geometry::Hyperbolic, 2.0, 0.5) - 0.5f64.sinh() / 2.0f64.sinh()).abs() < 1e-12);
/// ```
#[must_use]
pub fn sound_gain(g: Geometry, distance: f64, reference: f64) -> f64 {
    if !(distance.is_finite() && reference.is_finite()) || reference <= 0.0 {
        return 0.0;
    }
    let near = g.sphere_area::<f64>(reference);
    let here = g.sphere_area::<f64>(distance);
    if here <= near { 1.0 } else { (near / here).sqrt() }
}

/// The `count` nearest images of a source at `source` (a point of the
/// domain) as heard from `listener`, nearest first.
#[must_use]
pub fn heard_images(
    space: &crate::space::Space,
    listener: &Placement,
    source: DVec4,
    count: usize,
    reference: f64,
) -> Vec<Heard> {
    let g = space.geometry();
    let count = count.clamp(1, MAX_SOUND_IMAGES);
    let back = isometry::inverse(g, listener.isometry);
    contact::nearest_images(space, listener.position(), source, count)
        .into_iter()
        .map(|image| {
            let local = (back * image.direction).truncate();
            Heard {
                direction: if local.length_squared() > 0.0 {
                    local.normalize()
                } else {
                    DVec3::NEG_Z
                },
                distance: image.distance,
                gain: sound_gain(g, image.distance, reference),
            }
        })
        .collect()
}

/// How long an effect ([`PlaybackMode::Despawn`]) may wait for Bevy to
/// start playing it (no audio device, a source that never loads) before
/// its entity is despawned unplayed, so effects never pile up.
pub const EFFECT_START_TIMEOUT: f64 = 5.0;

/// The Bevy emitters of one sound, one per heard image, nearest first.
#[derive(Component, Clone, Debug, Default)]
pub struct SoundEmitters {
    emitters: Vec<Entity>,
    /// Seconds since they were spawned.
    age: f64,
    /// Whether Bevy started playing any of them.
    playing: bool,
}

impl SoundEmitters {
    /// The emitter entities (Bevy `AudioPlayer`s outside every space).
    #[must_use]
    pub fn entities(&self) -> &[Entity] {
        &self.emitters
    }
}

/// Where emitter `k` sits and its gain: image `k`'s, or silence ahead
/// when fewer images are heard.
fn image(heard: &[Heard], k: usize) -> (Vec3, f64) {
    heard
        .get(k)
        .map_or((Vec3::NEG_Z, 0.0), |h| (h.direction.as_vec3(), h.gain))
}

/// A sound's volume times an image's gain, as Bevy takes it: a volume
/// that is negative or not finite is silence.
fn level(volume: f32, gain: f64) -> f32 {
    let v = volume * gain as f32;
    if v.is_finite() && v > 0.0 { v } else { 0.0 }
}

/// Marks the Bevy `SpatialListener` this plugin owns.
#[derive(Component, Clone, Copy, Debug)]
pub struct ManifoldEars;

fn spawn_listener(mut commands: Commands) {
    commands.spawn((
        ManifoldEars,
        SpatialListener::new(EAR_GAP),
        Transform::IDENTITY,
        Name::new("manifold ears"),
    ));
}

/// A sound removed (or its entity despawned): its emitters go with it.
fn silence_removed_sound(event: On<Remove, ManifoldSound>, emitters: Query<&SoundEmitters>, mut commands: Commands) {
    if let Ok(e) = emitters.get(event.event_target()) {
        for &emitter in &e.emitters {
            if let Ok(mut c) = commands.get_entity(emitter) {
                c.despawn();
            }
        }
    }
}

/// Each frame: every sound's heard images from the listener, each placed
/// around Bevy's listener in the listener's frame and weighed by the
/// geometry ([`heard_images`]). A sound in another space than the
/// listener's, or with no listener, is silent.
#[expect(clippy::type_complexity, reason = "a system's queries")]
pub fn hear_sounds(
    mut commands: Commands,
    time: Res<Time>,
    spaces: Query<&ManifoldSpace>,
    listener: Query<(&Placement, &InSpace), With<ManifoldListener>>,
    mut sounds: Query<(
        Entity,
        &ManifoldSound,
        &Placement,
        Option<&InSpace>,
        Option<&mut SoundEmitters>,
    )>,
    mut emitters: Query<(&mut Transform, Option<&mut SpatialAudioSink>), Without<Placement>>,
) {
    let hearer = listener.iter().next();
    for (entity, sound, placement, in_space, mut state) in &mut sounds {
        let heard: Vec<Heard> = match (hearer, in_space) {
            (Some((lp, ls)), Some(ss)) if ls.space() == ss.space() => spaces
                .get(ss.space())
                .map(|ms| heard_images(ms.space(), lp, placement.position(), sound.images, sound.reference))
                .unwrap_or_default(),
            _ => Vec::new(),
        };
        let Some(state) = state.as_deref_mut() else {
            // First frame: one emitter per image, starting at its volume.
            let count = sound.images.clamp(1, MAX_SOUND_IMAGES);
            let emitters: Vec<Entity> = (0..count)
                .map(|k| {
                    let (at, gain) = image(&heard, k);
                    commands
                        .spawn((
                            AudioPlayer::new(sound.source.clone()),
                            PlaybackSettings {
                                mode: sound.mode,
                                volume: Volume::Linear(level(sound.volume, gain)),
                                spatial: true,
                                ..PlaybackSettings::ONCE
                            },
                            Transform::from_translation(at * EMITTER_DISTANCE),
                            Name::new("manifold sound image"),
                        ))
                        .id()
                })
                .collect();
            commands.entity(entity).insert(SoundEmitters {
                emitters,
                age: 0.0,
                playing: false,
            });
            continue;
        };
        state.age += time.delta_secs_f64();
        // Emitters that finished (despawned by their playback mode) are
        // dropped; an effect whose emitters all finished is done, and one
        // that never started in time is dropped unplayed.
        state.emitters.retain(|&e| emitters.contains(e));
        state.playing |= state
            .emitters
            .iter()
            .any(|&e| emitters.get(e).is_ok_and(|(_, sink)| sink.is_some()));
        let unplayed = !state.playing && state.age > EFFECT_START_TIMEOUT;
        if matches!(sound.mode, PlaybackMode::Despawn) && (state.emitters.is_empty() || unplayed) {
            commands.entity(entity).despawn();
            continue;
        }
        for (k, &e) in state.emitters.iter().enumerate() {
            let Ok((mut transform, sink)) = emitters.get_mut(e) else {
                continue;
            };
            let (at, gain) = image(&heard, k);
            let translation = at * EMITTER_DISTANCE;
            if transform.translation != translation {
                transform.translation = translation;
            }
            if let Some(mut sink) = sink {
                sink.set_volume(Volume::Linear(level(sound.volume, gain)));
            }
        }
    }
}
