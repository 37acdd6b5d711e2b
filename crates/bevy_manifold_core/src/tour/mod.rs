//! Tours: scripted flights through the manifold.
//!
//! A tour is a space, a camera path through keyframes and legs
//! ([`path`]: a spline on the isometry group, exact in every geometry and
//! across face pairings), settings that change along the way (levels, fog,
//! Suzanne, the cell rules) and captions. [`file`](mod@file) reads and writes the
//! JSON format (`assets/tours/*.tour.json`); [`Tour::frame`] is the camera,
//! settings and caption at any time, what the explorer plays, the
//! `tour render` command traces frame by frame, and the plugin's
//! `TourPlayer` follows.
//!
//! ```
//! use bevy_manifold_core::prelude::*;
//! use bevy_manifold_core::tour::TourDesc;
//! let text = r#"{"space": "torus", "keyframes": [
//!     {"time": 0, "position": [0, 0, 0, 1], "look": [1, 0, 0], "caption": "off along +x"},
//!     {"fly": {"seconds": 3, "speed": 1}}
//! ]}"#;
//! let space = catalog::torus(1.0);
//! let tour = TourDesc::parse(text, "inline").unwrap().build(&space, "inline").unwrap();
//! assert_eq!(tour.duration(), 3.0);
//! let end = tour.frame(&space, 3.0);
//! // Three periods along +x: three faces crossed, back at the centre.
//! assert_eq!(end.word, vec![0, 0, 0]);
//! assert!(end.placement.w_axis.truncate().length() < 1e-9);
//! assert_eq!(end.caption.as_deref(), Some("off along +x"));
//! ```

mod build;
pub mod file;
pub mod path;
pub mod product;

pub use file::{EntryDesc, MAX_TOTAL_WORDS, MAX_TOUR_BYTES, SceneDesc, TourDesc, TourError};
pub use path::{PathFrame, PathKey, Segment, TourPath};

use crate::space::Space;
use crate::space::rule::CellRule;
use crate::trace::{Camera, Fog, PaperOptions, Scene, SuzanneMode, TraceSettings};
use glam::DMat4;
use std::path::Path;

/// The settings a tour changes along the way.
#[derive(Clone, Debug, PartialEq)]
pub struct TourSettings {
    /// Face transports per ray.
    pub levels: u32,
    /// Fog, if any.
    pub fog: Option<Fog>,
    /// Suzanne.
    pub suzanne: SuzanneMode,
    /// Objects coloured by their cell.
    pub cell_colors: bool,
    /// The per-cell rules.
    pub rule: CellRule,
}

impl Default for TourSettings {
    fn default() -> Self {
        TourSettings {
            levels: 8,
            fog: None,
            suzanne: SuzanneMode::Attached,
            cell_colors: false,
            rule: CellRule::default(),
        }
    }
}

/// A tour, built and validated against its space ([`TourDesc::build`]).
#[derive(Clone, Debug)]
pub struct Tour {
    /// Vertical field of view in degrees.
    pub fov_y_degrees: f64,
    /// The scene's parts.
    pub scene: file::SceneDesc,
    /// The camera path.
    pub path: TourPath,
    /// The settings, each from its time on, in time order.
    settings: Vec<(f64, TourSettings)>,
    /// The captions, each from its time on (an empty one ends the last).
    captions: Vec<(f64, String)>,
}

/// What a tour shows at one time.
#[derive(Clone, Debug, PartialEq)]
pub struct TourFrame {
    /// The camera's copy of the domain, as a face word from the origin copy.
    pub word: Vec<usize>,
    /// The camera's pose inside the domain.
    pub placement: DMat4,
    /// The settings in force.
    pub settings: TourSettings,
    /// The caption shown, if any.
    pub caption: Option<String>,
}

impl Tour {
    /// Reads a tour file and builds it in the space it names (a catalog or
    /// library name, or a space file relative to the tour file).
    ///
    /// # Errors
    /// An unreadable or broken file, or a space that does not load, named
    /// by the file and the field.
    pub fn load(path: impl AsRef<Path>) -> Result<(Space, Tour), TourError> {
        let path = path.as_ref();
        let name = path.display().to_string();
        let desc = TourDesc::load(path)?;
        let space = desc.resolve_space(Some(path))?;
        let tour = desc.build(&space, &name)?;
        Ok((space, tour))
    }

    /// When the tour ends, in seconds (it starts at its first keyframe's
    /// time).
    #[must_use]
    pub fn duration(&self) -> f64 {
        self.path.span().1
    }

    /// The settings in force at `t`.
    #[must_use]
    pub fn settings_at(&self, t: f64) -> &TourSettings {
        let i = self.settings.partition_point(|(s, _)| *s <= t);
        &self.settings[i.saturating_sub(1)].1
    }

    /// The caption shown at `t`.
    #[must_use]
    pub fn caption_at(&self, t: f64) -> Option<&str> {
        let i = self.captions.partition_point(|(s, _)| *s <= t);
        let c = self.captions.get(i.checked_sub(1)?)?;
        (!c.1.is_empty()).then_some(c.1.as_str())
    }

    /// The captions and their start times.
    #[must_use]
    pub fn captions(&self) -> &[(f64, String)] {
        &self.captions
    }

    /// The camera, settings and caption at time `t` (clamped to the tour).
    #[must_use]
    pub fn frame(&self, space: &Space, t: f64) -> TourFrame {
        let PathFrame { word, placement } = self.path.frame(space, t);
        TourFrame {
            word,
            placement,
            settings: self.settings_at(t).clone(),
            caption: self.caption_at(t).map(str::to_owned),
        }
    }

    /// The scene and trace settings of the frame at `t`, `width` x
    /// `height` pixels: the paper's scene with the tour's parts, seen from
    /// the tour's camera (what `tour render` traces).
    #[must_use]
    pub fn scene_at(&self, space: &Space, t: f64, width: u32, height: u32) -> (Scene, TraceSettings) {
        let frame = self.frame(space, t);
        let s = &frame.settings;
        let mut scene = Scene::paper(
            space,
            &PaperOptions {
                edges: self.scene.edges,
                suzanne: s.suzanne,
                hands: self.scene.hands,
                vehicle: self.scene.vehicle,
                mirror: self.scene.mirror,
            },
        );
        // The paper's meshes sit relative to its start camera: the body
        // (attached Suzanne, the hands) goes with the tour's camera; a free
        // Suzanne stays where she stands.
        let carry = frame.placement * crate::geometry::isometry::inverse(space.geometry(), scene.camera.isometry);
        let free = usize::from(s.suzanne == SuzanneMode::Free);
        for mesh in scene.meshes.iter_mut().skip(free) {
            mesh.placement = carry * mesh.placement;
        }
        scene.camera = Camera {
            isometry: frame.placement,
            fov_y_degrees: self.fov_y_degrees,
            frustum: None,
            cell: frame.word,
        };
        scene.fog.clone_from(&s.fog);
        let settings = TraceSettings {
            width,
            height,
            levels: s.levels,
            cell_colors: s.cell_colors,
            cell_rule: s.rule,
            reflections: self.scene.reflections,
            ..TraceSettings::default()
        };
        (scene, settings)
    }
}

impl TourDesc {
    /// The space the file names: a catalog or library name, else a space
    /// file found relative to the tour file `tour_file`.
    ///
    /// # Errors
    /// A name that is none of these, or a space file that does not load,
    /// named as the tour file's `space` field.
    pub fn resolve_space(&self, tour_file: Option<&Path>) -> Result<Space, TourError> {
        let relative = tour_file.and_then(Path::parent).map(|d| d.join(&self.space));
        let name = match &relative {
            Some(p) if p.exists() && crate::space::catalog::by_name(&self.space).is_none() => p.display().to_string(),
            _ => self.space.clone(),
        };
        crate::space::catalog::resolve(&name).map_err(|message| TourError::Field {
            path: tour_file.map_or_else(|| "tour".into(), |p| p.display().to_string()),
            field: "space".into(),
            message,
        })
    }
}
