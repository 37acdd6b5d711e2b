//! Tours in the explorer: play one (the camera follows it through the
//! faces, the panel follows its settings, its captions are shown over the
//! view), pause, scrub, change speed; and author one: start a tour where
//! the camera is, add the current view as a keyframe (its pose in the copy
//! the camera's [`bevy_manifold::tour::FaceWord`] names), edit the times and captions, save.
//! [`ExplorerTour`] holds all of it; the panel ([`super::panel`]) and the
//! tests drive the same methods.
//!
//! ```no_run
//! use bevy::prelude::*;
//! use bevy_manifold_app::explorer::tour::ExplorerTour;
//! use bevy_manifold_app::explorer::ExplorerSettings;
//!
//! fn open(mut tour: ResMut<ExplorerTour>, mut settings: ResMut<ExplorerSettings>) {
//!     if let Err(e) = tour.open("assets/tours/seifert-weber.tour.json", &mut settings) {
//!         eprintln!("{e}");
//!     }
//! }
//! ```

use super::settings::{CellMode, ExplorerSettings};
use super::view::{ExplorerCamera, ExplorerWorld, insert_controller};
use bevy::prelude::*;
use bevy_manifold::camera::{FlyCamera, Vehicle};
use bevy_manifold::placement::GeodesicVelocity;
use bevy_manifold::space::Space;
use bevy_manifold::tour::{Tour, TourDesc, TourPlayer};
use glam::DMat4;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The tour the explorer plays or edits, and how it plays.
#[derive(Resource, Debug, Clone)]
pub struct ExplorerTour {
    /// The file it came from or is saved to (typed in the panel).
    pub path: String,
    /// The tour as written (what is edited and saved), if any.
    pub desc: Option<TourDesc>,
    /// The tour built from `desc` (`None` while it has no keyframe or an
    /// edit left it invalid: the error was reported).
    pub tour: Option<Arc<Tour>>,
    /// The explorer's name for the tour's space (a catalog or library
    /// name, or a path): the tour plays while the explorer shows it.
    pub space: String,
    /// The camera follows the tour (otherwise it flies free, as for
    /// recording).
    pub follow: bool,
    /// Tour time, seconds.
    pub time: f64,
    /// Tour seconds per second.
    pub speed: f64,
    /// Time advances.
    pub playing: bool,
    /// Start again at the end.
    pub looping: bool,
    /// The panel follows the tour's settings (levels, fog, Suzanne, cell
    /// colours and rules) while it plays.
    pub apply_settings: bool,
    /// Seconds between the last keyframe and one the recorder adds.
    pub gap: f64,
    /// A jump asked for (the timeline was dragged).
    seek: bool,
}

impl Default for ExplorerTour {
    fn default() -> Self {
        ExplorerTour {
            path: String::new(),
            desc: None,
            tour: None,
            space: String::new(),
            follow: false,
            time: 0.0,
            speed: 1.0,
            playing: false,
            looping: false,
            apply_settings: true,
            gap: 4.0,
            seek: false,
        }
    }
}

/// The shipped tours: `assets/tours/*.tour.json` under the working
/// directory, else in the crate's source tree; sorted by name.
#[must_use]
pub fn shipped_tours() -> Vec<PathBuf> {
    let dirs = [
        PathBuf::from("assets/tours"),
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../bevy_manifold_core/assets/tours"),
    ];
    for dir in dirs {
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        let mut tours: Vec<PathBuf> = entries
            .flatten()
            .map(|e| e.path())
            .filter(|p| p.to_string_lossy().ends_with(".tour.json"))
            .collect();
        if !tours.is_empty() {
            tours.sort();
            return tours;
        }
    }
    Vec::new()
}

impl ExplorerTour {
    /// Opens the tour file at `path` and asks the explorer for its space
    /// (`settings.space`); it starts playing, the camera following, once
    /// the space is shown.
    ///
    /// # Errors
    /// The file's error, naming it and the field.
    pub fn open(&mut self, path: impl AsRef<Path>, settings: &mut ExplorerSettings) -> Result<(), String> {
        let path = path.as_ref();
        let file = path.display().to_string();
        let desc = TourDesc::load(path).map_err(|e| e.to_string())?;
        let space = desc.resolve_space(Some(path)).map_err(|e| e.to_string())?;
        let tour = desc.build(&space, &file).map_err(|e| e.to_string())?;
        // The explorer opens names as they are, files by their path
        // relative to the tour file.
        let key = if bevy_manifold::space::catalog::resolve(&desc.space).is_ok() {
            desc.space.clone()
        } else {
            path.parent()
                .unwrap_or(Path::new(""))
                .join(&desc.space)
                .display()
                .to_string()
        };
        *self = ExplorerTour {
            path: file,
            tour: Some(Arc::new(tour)),
            desc: Some(desc),
            space: key.clone(),
            follow: true,
            playing: true,
            seek: true,
            speed: self.speed,
            looping: self.looping,
            apply_settings: self.apply_settings,
            ..ExplorerTour::default()
        };
        settings.space = key;
        Ok(())
    }

    /// Starts an empty tour in the space shown (`settings.space`); add
    /// keyframes with [`ExplorerTour::record`].
    pub fn start_new(&mut self, settings: &ExplorerSettings, fov_y_degrees: f64) {
        *self = ExplorerTour {
            path: self.path.clone(),
            desc: Some(TourDesc {
                space: settings.space.clone(),
                fov_y_degrees,
                scene: bevy_manifold::tour::SceneDesc {
                    edges: settings.edges,
                    hands: settings.hands,
                    suzanne: settings.suzanne,
                    vehicle: settings.vehicle,
                    mirror: settings.mirror,
                    reflections: settings.reflections,
                },
                keyframes: Vec::new(),
            }),
            space: settings.space.clone(),
            ..ExplorerTour::default()
        };
    }

    /// The tour's length in seconds (0 without one).
    #[must_use]
    pub fn duration(&self) -> f64 {
        self.tour.as_ref().map_or(0.0, |t| t.duration())
    }

    /// Jumps to `time` (the camera is placed there, crossing nothing).
    pub fn seek(&mut self, time: f64) {
        self.time = if time.is_finite() {
            time.clamp(0.0, self.duration())
        } else {
            0.0
        };
        self.seek = true;
    }

    /// Play or pause, the camera following; played from the start when
    /// paused at the end.
    pub fn toggle_play(&mut self) {
        if !self.playing && self.time >= self.duration() {
            self.seek(0.0);
        }
        self.playing = !self.playing;
        self.follow = true;
    }

    /// The caption at the current time, while following.
    #[must_use]
    pub fn caption(&self) -> Option<&str> {
        self.tour.as_ref().filter(|_| self.follow)?.caption_at(self.time)
    }

    /// Adds the camera's pose `placement` in the copy `word` names as a
    /// keyframe at `time` (entries stay in time order), in `space` (the
    /// tour's, shown); returns its index.
    ///
    /// # Errors
    /// No tour started, or the keyframe makes the tour invalid (a time
    /// already taken, a half turn from the keyframe before): the keyframe
    /// is not added.
    pub fn record(&mut self, space: &Space, time: f64, word: &[usize], placement: DMat4) -> Result<usize, String> {
        let desc = self.desc.as_mut().ok_or("no tour: start one or open one first")?;
        let entry = TourDesc::keyframe(time, word.to_vec(), placement);
        // After every entry that starts no later (a leg starts where the
        // entry before it ends: it stays after its keyframe).
        let at = desc
            .keyframes
            .iter()
            .rposition(|e| e.time.is_some_and(|t| t <= time))
            .map_or(0, |i| {
                let mut j = i + 1;
                while desc.keyframes.get(j).is_some_and(|e| e.time.is_none()) {
                    j += 1;
                }
                j
            });
        desc.keyframes.insert(at, entry);
        if let Err(e) = self.rebuild(space) {
            if let Some(d) = self.desc.as_mut() {
                d.keyframes.remove(at);
            }
            self.rebuild(space).ok();
            return Err(e);
        }
        Ok(at)
    }

    /// Builds the tour again after `desc` was edited.
    ///
    /// # Errors
    /// What is wrong with the edited tour, naming the entry and field; the
    /// tour is then `None` until fixed.
    pub fn rebuild(&mut self, space: &Space) -> Result<(), String> {
        self.tour = None;
        let Some(desc) = &self.desc else { return Ok(()) };
        if desc.keyframes.is_empty() {
            return Ok(());
        }
        let name = if self.path.is_empty() { "new tour" } else { &self.path };
        let tour = desc.build(space, name).map_err(|e| e.to_string())?;
        self.tour = Some(Arc::new(tour));
        self.time = self.time.clamp(0.0, self.duration());
        self.seek = true;
        Ok(())
    }

    /// Saves the tour to `self.path`.
    ///
    /// # Errors
    /// No tour, no path, or the file cannot be written (named).
    pub fn save(&mut self) -> Result<(), String> {
        let desc = self.desc.as_ref().ok_or("no tour to save")?;
        if self.path.trim().is_empty() {
            return Err("give the file to save the tour to".into());
        }
        desc.save(self.path.trim()).map_err(|e| e.to_string())
    }
}

/// What [`drive_tour`] reads on the camera: its player, its velocity,
/// and whether a controller is on it.
type OnTour = (
    &'static mut TourPlayer,
    &'static mut GeodesicVelocity,
    Has<FlyCamera>,
    Has<Vehicle>,
);

/// Keeps the camera on the tour while following (a [`TourPlayer`] on it,
/// its controller taken off), gives it back its controller when not, and
/// carries the panel's seeks, speed and play state to the player
/// ([`read_tour_time`] brings its time back).
pub fn drive_tour(
    mut commands: Commands,
    mut tour: ResMut<ExplorerTour>,
    settings: Res<ExplorerSettings>,
    world: Res<ExplorerWorld>,
    mut players: Query<OnTour, With<ExplorerCamera>>,
) {
    let shown = world.applied.space == tour.space && settings.space == tour.space;
    let wanted = tour.follow && shown && tour.tour.is_some();
    let t = tour.tour.clone().filter(|_| wanted);
    match (players.get_mut(world.camera), t) {
        (Ok((mut player, mut velocity, fly, ride)), Some(t)) => {
            // A controller put back by a respawn (the tour's scene
            // changed) would steer against the tour.
            if fly || ride {
                commands.entity(world.camera).remove::<(FlyCamera, Vehicle)>();
            }
            if !std::ptr::eq(player.tour(), t.as_ref()) {
                *player = TourPlayer::shared(t);
                tour.seek = true;
            }
            if std::mem::take(&mut tour.seek) {
                player.seek(tour.time);
            }
            player.speed = tour.speed;
            player.playing = tour.playing;
            player.looping = tour.looping;
            if player.finished() {
                tour.playing = false;
            }
            *velocity = GeodesicVelocity::default();
        }
        (Ok(_), None) => {
            let mut camera = commands.entity(world.camera);
            camera.remove::<TourPlayer>();
            insert_controller(&mut camera, &world.space, settings.vehicle);
        }
        (Err(_), Some(t)) => {
            let mut player = TourPlayer::shared(t);
            player.seek(tour.time);
            player.playing = tour.playing;
            player.speed = tour.speed;
            player.looping = tour.looping;
            tour.seek = false;
            let mut camera = commands.entity(world.camera);
            camera.remove::<(FlyCamera, Vehicle)>();
            camera.insert(player);
        }
        (Err(_), None) => {}
    }
}

/// The player's time, once it moved the camera this frame, for the panel.
pub fn read_tour_time(
    mut tour: ResMut<ExplorerTour>,
    world: Res<ExplorerWorld>,
    players: Query<&TourPlayer, With<ExplorerCamera>>,
) {
    if let Ok(player) = players.get(world.camera)
        && !tour.seek
        && tour.follow
    {
        tour.time = player.time;
    }
}

/// While a tour plays and [`ExplorerTour::apply_settings`] is on, the
/// settings take the tour's: its scene (edges, hands, the vehicle), levels,
/// fog, Suzanne, cell colours, the on/off rule and walls (what the panel
/// then shows).
pub fn follow_tour_settings(tour: Res<ExplorerTour>, mut settings: ResMut<ExplorerSettings>) {
    let Some(t) = tour.tour.as_ref().filter(|_| tour.follow && tour.apply_settings) else {
        return;
    };
    if settings.space != tour.space {
        return;
    }
    let ts = t.settings_at(tour.time);
    let mut s = settings.clone();
    s.edges = t.scene.edges;
    s.hands = t.scene.hands;
    s.vehicle = t.scene.vehicle;
    s.levels = ts.levels;
    s.fog = ts.fog.is_some();
    if let Some(f) = &ts.fog {
        s.fog_density = f.density;
        s.fog_color = Color::linear_rgb(f.color[0], f.color[1], f.color[2])
            .to_srgba()
            .to_f32_array_no_alpha();
    }
    s.suzanne = ts.suzanne;
    if ts.cell_colors != (s.cells && s.cell_mode == CellMode::ByCell) {
        s.cells = ts.cell_colors;
        s.cell_mode = CellMode::ByCell;
    }
    s.hidden = ts.rule.hidden.is_some();
    if let Some(h) = ts.rule.hidden {
        s.hidden_on = h.on_fraction;
        s.hidden_seed = h.seed;
    }
    s.walls = ts.rule.walls.is_some();
    if let Some(w) = ts.rule.walls {
        s.wall_density = w.density;
        s.wall_seed = w.seed;
    }
    if s != *settings {
        *settings = s;
    }
}

/// `T` plays or pauses the tour.
pub fn tour_keys(keys: Option<Res<ButtonInput<KeyCode>>>, mut tour: ResMut<ExplorerTour>) {
    if keys.is_some_and(|k| k.just_pressed(KeyCode::KeyT)) && tour.tour.is_some() {
        tour.toggle_play();
    }
}
