//! Tours in a Bevy app: [`TourPlayer`] flies an entity (a camera) along a
//! tour's path, through the faces like any entity, and applies the tour's
//! settings and captions. The math and the file format are the core's
//! [`bevy_manifold_core::tour`], re-exported here.
//!
//! ```no_run
//! use bevy::prelude::*;
//! use bevy_manifold::prelude::*;
//! use bevy_manifold::tour::{Tour, TourPlayer};
//!
//! let (space, tour) = Tour::load("assets/tours/seifert-weber.tour.json").unwrap();
//! App::new()
//!     // ManifoldPlugins brings the TourPlugin.
//!     .add_plugins((DefaultPlugins, ManifoldPlugins::default()))
//!     .add_systems(Startup, move |mut commands: Commands| {
//!         let root = commands.spawn(ManifoldSpace::new(space.clone())).id();
//!         commands.spawn((ChildOf(root), ManifoldCamera::default(), TourPlayer::new(tour.clone())));
//!     })
//!     .run();
//! ```
//!
//! The player moves its entity by the path's relative motion each frame
//! and lets the wrap system carry it through the faces, so it sends
//! [`crate::placement::FaceCrossed`] for every face the path crosses; after the wrap it
//! snaps to the path's exact pose (no drift over a long tour). A jump in
//! time ([`TourPlayer::seek`]) places the entity directly, crossing
//! nothing.

pub use bevy_manifold_core::tour::*;

use crate::placement::{DomainCell, FaceCrossed, InSpace, ManifoldSpace, ManifoldSystems, Placement, WrapOrigin};
use crate::space::cells::CellId;
use bevy::prelude::*;
use std::sync::Arc;

/// Plays a tour on its entity (which gets a [`Placement`]): see the module
/// docs.
#[derive(Component, Clone, Debug)]
#[require(Placement)]
pub struct TourPlayer {
    tour: Arc<Tour>,
    /// The tour's time, in seconds.
    pub time: f64,
    /// Tour seconds per real second (negative plays backwards).
    pub speed: f64,
    /// Whether the time advances.
    pub playing: bool,
    /// Start again at the end.
    pub looping: bool,
    /// The time and cell of the pose last placed, when the entity is on
    /// the path.
    on_path: Option<(f64, CellId)>,
}

impl TourPlayer {
    /// A player at the tour's start, playing at normal speed.
    #[must_use]
    pub fn new(tour: Tour) -> Self {
        Self::shared(Arc::new(tour))
    }

    /// A player of a shared tour.
    #[must_use]
    pub fn shared(tour: Arc<Tour>) -> Self {
        TourPlayer {
            time: tour.path.span().0,
            tour,
            speed: 1.0,
            playing: true,
            looping: false,
            on_path: None,
        }
    }

    /// The tour.
    #[must_use]
    pub fn tour(&self) -> &Tour {
        &self.tour
    }

    /// Jumps to `time` (clamped to the tour): the entity is placed there,
    /// without crossing faces on the way.
    pub fn seek(&mut self, time: f64) {
        let (a, b) = self.tour.path.span();
        self.time = if time.is_nan() { a } else { time.clamp(a, b) };
        self.on_path = None;
    }

    /// True at the end of a tour that does not loop.
    #[must_use]
    pub fn finished(&self) -> bool {
        !self.looping && self.time >= self.tour.duration()
    }

    /// The caption at the current time.
    #[must_use]
    pub fn caption(&self) -> Option<&str> {
        self.tour.caption_at(self.time)
    }

    /// The settings in force at the current time.
    #[must_use]
    pub fn settings(&self) -> &TourSettings {
        self.tour.settings_at(self.time)
    }
}

/// Plays [`TourPlayer`]s: advance and place before the placement systems
/// move and wrap, snap to the exact pose after the wrap. Part of
/// [`crate::ManifoldPlugins`], in its schedule.
#[derive(Debug, Clone)]
pub struct TourPlugin {
    schedule: bevy::ecs::schedule::InternedScheduleLabel,
}

impl Default for TourPlugin {
    fn default() -> Self {
        Self::in_schedule(PostUpdate)
    }
}

impl TourPlugin {
    /// The plugin with its systems in `schedule` (the placement systems').
    #[must_use]
    pub fn in_schedule(schedule: impl bevy::ecs::schedule::ScheduleLabel) -> Self {
        TourPlugin {
            schedule: schedule.intern(),
        }
    }
}

/// The tour systems, around [`ManifoldSystems`].
#[derive(SystemSet, Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TourSystems {
    /// Advance the time and move the players' entities along the path.
    Advance,
    /// Put them exactly on the path after the wrap.
    Snap,
}

impl Plugin for TourPlugin {
    fn build(&self, app: &mut App) {
        app.configure_sets(
            self.schedule,
            (
                TourSystems::Advance.before(ManifoldSystems::Integrate),
                TourSystems::Snap
                    .after(ManifoldSystems::Wrap)
                    .before(ManifoldSystems::Sync),
            ),
        )
        .add_systems(
            self.schedule,
            (
                advance_tours.in_set(TourSystems::Advance),
                (track_face_words, snap_to_tours).chain().in_set(TourSystems::Snap),
            ),
        );
        #[cfg(feature = "render")]
        app.add_systems(self.schedule, apply_tour_settings.after(TourSystems::Snap));
    }
}

/// The faces an entity crossed since it was in the origin copy, freely
/// reduced (crossing a face and straight back through its partner cancels):
/// the copy it is in as a tour names it (a keyframe's `cell`), so a
/// recorder can write the entity's pose as a keyframe. Kept up to date
/// from [`FaceCrossed`] and set by a [`TourPlayer`] when it places its
/// entity; reset it with the entity's [`DomainCell`].
///
/// ```
/// use bevy::prelude::*;
/// use bevy_manifold::prelude::*;
/// use bevy_manifold::tour::FaceWord;
/// let mut world = World::new();
/// world.spawn((Placement::default(), FaceWord::default()));
/// ```
#[derive(Component, Clone, Debug, Default, PartialEq, Eq)]
pub struct FaceWord(pub Vec<usize>);

impl FaceWord {
    /// The word after crossing `face` (whose partner is `partner`).
    pub fn cross(&mut self, face: usize, partner: usize) {
        if self.0.last() == Some(&partner) {
            self.0.pop();
        } else {
            self.0.push(face);
        }
    }
}

/// Appends each face crossed to the entity's [`FaceWord`].
pub fn track_face_words(
    mut crossed: MessageReader<FaceCrossed>,
    spaces: Query<&ManifoldSpace>,
    mut words: Query<(&mut FaceWord, &InSpace)>,
) {
    for c in crossed.read() {
        let Ok((mut word, in_space)) = words.get_mut(c.entity) else {
            continue;
        };
        let Some(face) = spaces
            .get(in_space.space())
            .ok()
            .and_then(|ms| ms.space().faces().get(c.face))
        else {
            continue;
        };
        word.cross(c.face, face.partner);
    }
}

/// What [`advance_tours`] reads and moves on a player's entity.
type PlayerParts = (
    &'static mut TourPlayer,
    &'static InSpace,
    &'static mut Placement,
    &'static mut DomainCell,
    &'static mut WrapOrigin,
    Option<&'static mut FaceWord>,
);

/// Advances each player's time and moves its entity by the path's motion
/// since the last frame (the wrap system then crosses the faces), or
/// places it on the path when it is not on it (a new player, a seek).
pub fn advance_tours(time: Res<Time>, spaces: Query<&ManifoldSpace>, mut players: Query<PlayerParts>) {
    let dt = time.delta_secs_f64();
    for (mut player, in_space, mut placement, mut cell, mut origin, word) in &mut players {
        let Ok(ms) = spaces.get(in_space.space()) else {
            continue;
        };
        let space = ms.space();
        let (start, end) = player.tour.path.span();
        if player.playing && dt > 0.0 {
            let mut t = player.time + dt * player.speed;
            if player.looping && (t > end || t < start) && end > start {
                t = start + (t - start).rem_euclid(end - start);
                player.on_path = None;
            }
            player.time = t.clamp(start, end);
        }
        let t = player.time;
        match player.on_path {
            Some((last, id)) if id == cell.id => {
                if last != t {
                    placement.isometry *= player.tour.path.relative(last, t);
                }
            }
            _ => {
                let frame = player.tour.path.frame(space, t);
                *cell = DomainCell::new(space, space.cell_of_word(&frame.word));
                *placement = Placement::from_isometry(frame.placement);
                origin.0 = Some(frame.placement);
                if let Some(mut word) = word {
                    word.0 = frame.word;
                }
            }
        }
        player.on_path = Some((t, cell.id));
    }
}

/// After the wrap: an entity in the copy the path is in at this time is
/// set exactly to the path's pose there.
pub fn snap_to_tours(
    spaces: Query<&ManifoldSpace>,
    mut players: Query<(&mut TourPlayer, &InSpace, &mut Placement, &DomainCell, &mut WrapOrigin)>,
) {
    for (mut player, in_space, mut placement, cell, mut origin) in &mut players {
        let Ok(ms) = spaces.get(in_space.space()) else {
            continue;
        };
        let space = ms.space();
        let frame = player.tour.path.frame(space, player.time);
        if space.cell_id_of(&space.cell_of_word(&frame.word)) == cell.id {
            placement.isometry = frame.placement;
            origin.0 = Some(frame.placement);
            player.on_path = Some((player.time, cell.id));
        } else {
            // Off the path (a wall stopped it, or the space changed):
            // placed again next frame.
            player.on_path = None;
        }
    }
}

/// The tour's levels and fog on a player that is a manifold camera.
#[cfg(feature = "render")]
pub fn apply_tour_settings(
    mut players: Query<(
        &TourPlayer,
        &mut crate::camera::ManifoldCamera,
        Option<&mut crate::camera::ManifoldFog>,
    )>,
) {
    for (player, mut camera, fog) in &mut players {
        let s = player.settings();
        if camera.levels != s.levels {
            camera.levels = s.levels;
        }
        if let Some(mut fog) = fog {
            let (density, color) = s.fog.as_ref().map_or((0.0, fog.color), |f| {
                (f.density, Color::linear_rgb(f.color[0], f.color[1], f.color[2]))
            });
            if fog.density != density || fog.color != color {
                fog.density = density;
                fog.color = color;
            }
        }
    }
}
