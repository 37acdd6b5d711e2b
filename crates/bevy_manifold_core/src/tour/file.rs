//! Tour files: JSON, validated entry by entry, each error named by the
//! file, the entry and the field (`tours/sw.tour.json: keyframes[3].position:
//! outside the domain, past face 7`).
//!
//! ```text
//! {"space": "seifert-weber",            catalog or library name, or a space
//!                                       file relative to the tour file
//!  "fov_y_degrees": 60,                 optional (60)
//!  "scene": {"edges": true, "hands": true, "suzanne": "Attached", "vehicle": false,
//!            "mirror": false, "reflections": 0},  optional
//!  "keyframes": [
//!    {"time": 0, "position": [0,0,0,1], "look": [0,0,-1], "up": [0,1,0],
//!     "cell": [3, 7], "stop": true, "caption": "...", "levels": 8},
//!    {"time": 4, "isometry": [[..4..] x4], "cell": [3]},
//!    {"fly": {"seconds": 4, "speed": 0.5}},
//!    {"turn": {"seconds": 2, "yaw_degrees": 90, "pitch_degrees": 0, "roll_degrees": 0}},
//!    {"loop": {"faces": [0], "laps": 1, "seconds": 6}, "caption": "..."}
//!  ]}
//! ```
//!
//! An entry is a keyframe (a `time` and a pose: `position` with an
//! optional `look` and `up`, or a whole `isometry`, in the copy of the
//! domain its `cell` word names) or a leg that starts where the previous
//! entry ends and lasts `seconds`: `fly` straight ahead (local -z) at
//! `speed`, `turn` in place (yaw about local y, then pitch about x, then
//! roll about z), or `loop` once or more around the closed path that
//! carries the camera to the same pose in the copy a face word names (a
//! closed geodesic when the camera sits on the element's axis, as at the
//! centre of the dodecahedral spaces looking at a face). `look` and `up`
//! are directions in the frame parallel to the origin's, carried to the
//! position along the geodesic. Settings on an entry (`levels`, `fog`,
//! `suzanne`, `cell_colors`, `hidden`, `walls`) hold from its start until
//! an entry changes them; a `caption` shows until the next one (`""` ends it).

use crate::space::file::to_rows;
use crate::trace::{PaperOptions, SuzanneMode};
use glam::DMat4;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// A tour file that is wrong, named by the file and the field.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TourError {
    /// Malformed JSON or a missing field.
    #[error("{path}: not a tour file: {message}")]
    Json {
        /// The file.
        path: String,
        /// serde's message, with line and column.
        message: String,
    },
    /// A field with a bad value.
    #[error("{path}: {field}: {message}")]
    Field {
        /// The file.
        path: String,
        /// The field, e.g. `keyframes[2].time`.
        field: String,
        /// What is wrong with it.
        message: String,
    },
    /// The file could not be read or written.
    #[error("{path}: cannot read or write: {message}")]
    Io {
        /// The file.
        path: String,
        /// The OS error.
        message: String,
    },
}

/// Most entries in one tour file, and most keyframes its legs may expand
/// into (memory stays bounded whatever a file says).
pub const MAX_KEYFRAMES: usize = 4096;
/// Longest face word of a keyframe's `cell` (and of a loop).
pub const MAX_WORD: usize = 4096;
/// Most faces the keyframes' cells may name in all (the sum of their
/// words' lengths, legs included): each is a product of exact elements,
/// so this bounds the work of checking any tour file: four keyframes of
/// 4,096 random faces each take 3 s in Seifert-Weber (exact integers
/// grow along a word), where 4,096 such keyframes would take about 40
/// minutes.
pub const MAX_TOTAL_WORDS: usize = 16_384;
/// Largest tour file read (32 MiB: 4,096 entries with the longest
/// captions and every face the words may name take under 20 MiB).
pub const MAX_TOUR_BYTES: u64 = 32 << 20;
/// Longest tour, in seconds (a day).
pub const MAX_SECONDS: f64 = 86_400.0;

/// A tour file's JSON read into `T` (at most [`MAX_TOUR_BYTES`]), named
/// by the file in errors: the tour files' and the product tour files'.
pub(crate) fn read_json<T: serde::de::DeserializeOwned>(path: &Path) -> Result<T, TourError> {
    let p = path.display().to_string();
    let text = crate::text::read_capped(path, MAX_TOUR_BYTES).map_err(|message| TourError::Io {
        path: p.clone(),
        message,
    })?;
    parse_json(&text, &p)
}

/// Tour JSON parsed into `T`; `path` names it in errors.
pub(crate) fn parse_json<T: serde::de::DeserializeOwned>(text: &str, path: &str) -> Result<T, TourError> {
    serde_json::from_str(crate::text::without_bom(text)).map_err(|e| TourError::Json {
        path: path.into(),
        message: e.to_string(),
    })
}

/// The scene a tour is seen in: the paper's, with these parts.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SceneDesc {
    /// The domain's edges as tubes.
    pub edges: bool,
    /// The two hands.
    pub hands: bool,
    /// Suzanne at the start (an entry's `suzanne` changes it).
    pub suzanne: SuzanneMode,
    /// The camera rides the vehicle (the paper's airplane).
    pub vehicle: bool,
    /// The mirror ball of the paper's Fig. 11 at the domain's centre.
    pub mirror: bool,
    /// Reflections a ray follows (`TraceSettings::reflections`, at most
    /// [`crate::trace::MAX_REFLECTIONS`]).
    pub reflections: u32,
}

impl Default for SceneDesc {
    fn default() -> Self {
        let p = PaperOptions::default();
        SceneDesc {
            edges: p.edges,
            hands: p.hands,
            suzanne: p.suzanne,
            vehicle: p.vehicle,
            mirror: p.mirror,
            reflections: 0,
        }
    }
}

/// Fly straight ahead (local -z).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FlyDesc {
    /// How long.
    pub seconds: f64,
    /// Distance per second.
    pub speed: f64,
}

/// Turn in place.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TurnDesc {
    /// How long.
    pub seconds: f64,
    /// About the local y axis (left is positive).
    #[serde(default)]
    pub yaw_degrees: f64,
    /// About the local x axis (up is positive).
    #[serde(default)]
    pub pitch_degrees: f64,
    /// About the local z axis.
    #[serde(default)]
    pub roll_degrees: f64,
}

/// Around the loop that ends at the same pose in the copy `faces` names.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoopDesc {
    /// The face word of the copy the loop leads to.
    pub faces: Vec<usize>,
    /// How many times.
    #[serde(default = "one")]
    pub laps: u32,
    /// How long, all laps together.
    pub seconds: f64,
}

fn one() -> u32 {
    1
}

/// Fog from an entry on (`density` 0: off).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FogDesc {
    /// Extinction per unit distance (0: no fog).
    pub density: f64,
    /// Colour (linear RGB).
    #[serde(default = "fog_color")]
    pub color: [f32; 3],
}

fn fog_color() -> [f32; 3] {
    [0.75, 0.78, 0.82]
}

/// The on/off rule from an entry on (`on_fraction` 1: every cell on).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HiddenDesc {
    /// Fraction of cells on.
    pub on_fraction: f32,
    /// Which cells.
    #[serde(default = "seed")]
    pub seed: u32,
}

/// Walls from an entry on (`density` 0: none).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WallsDesc {
    /// Fraction of faces walled.
    pub density: f32,
    /// Which faces.
    #[serde(default = "seed")]
    pub seed: u32,
}

fn seed() -> u32 {
    1
}

/// One entry of a tour file: a keyframe or a leg, with the settings and
/// caption that start with it (see the module docs).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EntryDesc {
    /// A keyframe's time, in seconds.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<f64>,
    /// The keyframe's copy of the domain: the faces crossed from the
    /// origin copy.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub cell: Vec<usize>,
    /// The keyframe's position: a normalised point inside the domain.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub position: Option<[f64; 4]>,
    /// Where the camera looks, in the frame parallel to the origin's
    /// (default -z).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub look: Option<[f64; 3]>,
    /// The camera's up, likewise (default +y).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub up: Option<[f64; 3]>,
    /// The whole pose instead of `position`/`look`/`up` (row-major).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub isometry: Option<[[f64; 4]; 4]>,
    /// A leg: fly straight.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fly: Option<FlyDesc>,
    /// A leg: turn in place.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub turn: Option<TurnDesc>,
    /// A leg: around a loop.
    #[serde(default, rename = "loop", skip_serializing_if = "Option::is_none")]
    pub loop_: Option<LoopDesc>,
    /// The camera comes to rest at this keyframe.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub stop: bool,
    /// Levels (face transports per ray) from here on.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub levels: Option<u32>,
    /// Fog from here on.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fog: Option<FogDesc>,
    /// Suzanne from here on.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub suzanne: Option<SuzanneMode>,
    /// Per-cell colours from here on.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cell_colors: Option<bool>,
    /// The on/off rule from here on.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hidden: Option<HiddenDesc>,
    /// Walls from here on.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub walls: Option<WallsDesc>,
    /// A caption shown from here until the next (`""` ends it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub caption: Option<String>,
}

/// A tour file as written: edit it (the explorer's recorder does), save
/// it, and [`TourDesc::build`] it into a [`Tour`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TourDesc {
    /// The space: a catalog or library name, or a space file (relative to
    /// the tour file).
    pub space: String,
    /// Vertical field of view in degrees.
    #[serde(default = "fov")]
    pub fov_y_degrees: f64,
    /// The scene.
    #[serde(default)]
    pub scene: SceneDesc,
    /// Keyframes and legs, in order.
    pub keyframes: Vec<EntryDesc>,
}

fn fov() -> f64 {
    60.0
}

impl TourDesc {
    /// Reads a tour file.
    ///
    /// # Errors
    /// Unreadable file or malformed JSON, named by the file.
    pub fn load(path: impl AsRef<Path>) -> Result<TourDesc, TourError> {
        read_json(path.as_ref())
    }

    /// Parses tour JSON; `path` names it in errors.
    ///
    /// # Errors
    /// Malformed JSON, a missing or unknown field.
    pub fn parse(text: &str, path: &str) -> Result<TourDesc, TourError> {
        parse_json(text, path)
    }

    /// The file's JSON, pretty-printed.
    #[must_use]
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }

    /// Writes the file.
    ///
    /// # Errors
    /// The file cannot be written.
    pub fn save(&self, path: impl AsRef<Path>) -> Result<(), TourError> {
        std::fs::write(path.as_ref(), self.to_json() + "\n").map_err(|e| TourError::Io {
            path: path.as_ref().display().to_string(),
            message: e.to_string(),
        })
    }

    /// A keyframe entry for the pose `placement` in the copy `cell` (a
    /// face word), at `time`: what the recorder adds.
    #[must_use]
    pub fn keyframe(time: f64, cell: Vec<usize>, placement: DMat4) -> EntryDesc {
        EntryDesc {
            time: Some(time),
            cell,
            isometry: Some(to_rows(placement)),
            ..EntryDesc::default()
        }
    }
}
