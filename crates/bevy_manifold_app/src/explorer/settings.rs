//! The explorer's settings, kept between runs as a small JSON file in the
//! platform's config directory. A missing file gives the defaults; a
//! broken one is reported, kept aside as `explorer.json.broken` (nothing
//! the user wrote is lost) and replaced by the defaults; values out of
//! range are clamped, with a warning each. Nothing here panics.
//!
//! ```
//! use bevy_manifold_app::explorer::settings::{ExplorerSettings, load};
//! let dir = std::env::temp_dir().join(format!("bm-settings-doc-{}", std::process::id()));
//! let path = dir.join("explorer.json");
//! let mut s = ExplorerSettings::default();
//! s.levels = 5;
//! s.save(&path).unwrap();
//! let (back, warnings) = load(&path);
//! assert_eq!(back, s);
//! assert!(warnings.is_empty());
//! std::fs::write(&path, "{ not json").unwrap();
//! let (back, warnings) = load(&path);
//! assert_eq!(back, ExplorerSettings::default());
//! assert!(warnings[0].contains("broken"));
//! assert!(dir.join("explorer.json.broken").exists());
//! # std::fs::remove_dir_all(&dir).ok();
//! ```

use bevy::prelude::*;
use bevy_manifold::camera::{
    AdaptiveRenderScale, ManifoldAccumulation, ManifoldCamera, ManifoldFootprint, ManifoldPathTracer,
};
use bevy_manifold::camera::{CellShading, ManifoldFog};
use bevy_manifold::space::rule::{CellRule, OnOff, Walls};
use bevy_manifold::space::{catalog, library};
use bevy_manifold::trace::{MAX_PATH_DEPTH, MAX_REFLECTIONS, PaperOptions, SuzanneMode};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// How per-cell shading is chosen in the panel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum CellMode {
    /// A colour per copy.
    #[default]
    ByCell,
    /// One copy (pinned from the panel) highlighted.
    Highlight,
    /// The paper's on/off pattern by copy.
    Pattern,
}

impl CellMode {
    /// Every mode, in the panel's order.
    pub const ALL: [CellMode; 3] = [CellMode::ByCell, CellMode::Highlight, CellMode::Pattern];

    /// The mode's name in the panel.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            CellMode::ByCell => "colour by cell",
            CellMode::Highlight => "highlight one cell",
            CellMode::Pattern => "on/off pattern",
        }
    }
}

/// Everything the explorer's panel sets, and what is saved between runs.
#[derive(Resource, Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct ExplorerSettings {
    /// A catalog or library name, a product space's name
    /// ([`ProductSpace::NAMES`](bevy_manifold::space::product::ProductSpace::NAMES)),
    /// or the path of a space file (`.json`, `.gen`).
    pub space: String,
    /// Most face transports per ray.
    pub levels: u32,
    /// Rays stop after this distance.
    pub max_distance: f32,
    /// Fog on.
    pub fog: bool,
    /// Fog extinction per unit distance.
    pub fog_density: f64,
    /// Fog colour, sRGB.
    pub fog_color: [f32; 3],
    /// Per-cell shading on.
    pub cells: bool,
    /// Which per-cell shading.
    pub cell_mode: CellMode,
    /// [`CellMode::Pattern`]: fraction of copies on.
    pub pattern_on: f32,
    /// [`CellMode::Highlight`]: the pinned copy's id.
    pub highlight: u64,
    /// The on/off rule: objects in off cells hidden and passed through.
    pub hidden: bool,
    /// Fraction of the cells on under the on/off rule.
    pub hidden_on: f32,
    /// The on/off rule's seed.
    pub hidden_seed: u32,
    /// Walls between cells (the maze).
    pub walls: bool,
    /// Fraction of the faces that are walls.
    pub wall_density: f32,
    /// The walls' seed.
    pub wall_seed: u32,
    /// The domain's edges drawn.
    pub edges: bool,
    /// Suzanne attached to the camera, free, or hidden.
    pub suzanne: SuzanneMode,
    /// The hands shown.
    pub hands: bool,
    /// The camera rides the vehicle (the paper's airplane) instead of
    /// flying freely.
    pub vehicle: bool,
    /// The mirror ball of the paper's Fig. 11 at the domain's centre.
    pub mirror: bool,
    /// Reflections a ray follows off surfaces with a material (0 to
    /// [`bevy_manifold::trace::MAX_REFLECTIONS`]; 0: none, at no cost).
    pub reflections: u32,
    /// Path trace the view ([`ManifoldPathTracer`]): one sample a frame,
    /// averaged over `path_samples` while the view is still.
    pub path_trace: bool,
    /// The most bounces of a path (1 to
    /// [`bevy_manifold::trace::MAX_PATH_DEPTH`]).
    pub path_depth: u32,
    /// Samples per pixel a still path-traced view converges to (2 to
    /// [`ManifoldAccumulation::MAX_SAMPLES`]).
    pub path_samples: u32,
    /// Render resolution as a fraction of the view's pixels.
    pub render_scale: f32,
    /// Hold `target_fps` by tracing fewer pixels than `render_scale` asks
    /// when frames are slow ([`AdaptiveRenderScale`]).
    pub hold_frame_rate: bool,
    /// The frame rate held, in frames per second.
    pub target_fps: f32,
    /// While the view is still, refine it: accumulate `still_samples`
    /// jittered traces per pixel ([`ManifoldAccumulation`]), then stop
    /// tracing.
    pub refine_still: bool,
    /// Samples per pixel a still view is refined to (2 to
    /// [`ManifoldAccumulation::MAX_SAMPLES`]).
    pub still_samples: u32,
    /// Trace each pixel as a cone ([`ManifoldFootprint`]): far copies fade
    /// to their average colour instead of sparkling, moving or still.
    pub smooth_detail: bool,
    /// In a product space (H2xR, S2xR), the balls lit by two point lights
    /// (every image of each, with shadows) instead of from the eye.
    pub lights: bool,
    /// The side panel shown.
    pub panel: bool,
}

impl Default for ExplorerSettings {
    fn default() -> Self {
        let camera = ManifoldCamera::default();
        let fog = ManifoldFog::default();
        ExplorerSettings {
            space: "torus".into(),
            levels: camera.levels,
            max_distance: camera.max_distance,
            fog: false,
            fog_density: fog.density,
            fog_color: fog.color.to_srgba().to_f32_array_no_alpha(),
            cells: false,
            cell_mode: CellMode::ByCell,
            pattern_on: 0.5,
            highlight: 0,
            hidden: false,
            hidden_on: 0.7,
            hidden_seed: 1,
            walls: false,
            wall_density: 0.4,
            wall_seed: 1,
            edges: true,
            suzanne: SuzanneMode::Attached,
            hands: true,
            vehicle: false,
            mirror: false,
            reflections: 0,
            path_trace: false,
            path_depth: 8,
            path_samples: ManifoldAccumulation::MAX_SAMPLES,
            render_scale: 1.0,
            hold_frame_rate: false,
            target_fps: 30.0,
            refine_still: true,
            still_samples: 16,
            smooth_detail: true,
            lights: true,
            panel: true,
        }
    }
}

/// The most levels the panel offers.
pub const MAX_LEVEL: u32 = 32;
/// The smallest render scale.
pub const MIN_SCALE: f32 = 0.1;
/// The frame rates the panel offers to hold.
pub const TARGET_FPS: std::ops::RangeInclusive<f32> = 5.0..=144.0;

impl ExplorerSettings {
    /// The camera these settings ask for, with its cell shading.
    #[must_use]
    pub fn camera(&self) -> (ManifoldCamera, CellShading) {
        (
            ManifoldCamera {
                levels: self.levels,
                max_distance: self.max_distance,
                reflections: self.reflections,
            },
            self.cell_shading(),
        )
    }

    /// The controller that holds the frame rate, when asked for.
    #[must_use]
    pub fn adaptive_scale(&self) -> Option<AdaptiveRenderScale> {
        self.hold_frame_rate
            .then(|| AdaptiveRenderScale::new(1000.0 / self.target_fps).with_range(MIN_SCALE, 1.0))
    }

    /// The refinement of a still view, when asked for.
    #[must_use]
    pub fn accumulation(&self) -> Option<ManifoldAccumulation> {
        if self.path_trace {
            return Some(ManifoldAccumulation {
                samples: self.path_samples,
            });
        }
        self.refine_still.then_some(ManifoldAccumulation {
            samples: self.still_samples,
        })
    }

    /// The path tracer these settings ask for, if any.
    #[must_use]
    pub fn path_tracer(&self) -> Option<ManifoldPathTracer> {
        self.path_trace.then_some(ManifoldPathTracer {
            depth: self.path_depth,
            seed: 0,
        })
    }

    /// Cone tracing, when asked for.
    #[must_use]
    pub fn footprint(&self) -> Option<ManifoldFootprint> {
        self.smooth_detail.then_some(ManifoldFootprint)
    }

    /// The per-cell shading these settings ask for.
    #[must_use]
    pub fn cell_shading(&self) -> CellShading {
        if !self.cells {
            return CellShading::Off;
        }
        match self.cell_mode {
            CellMode::ByCell => CellShading::ByCell,
            CellMode::Highlight => CellShading::Highlight { cell: self.highlight },
            CellMode::Pattern => CellShading::Pattern {
                on_fraction: self.pattern_on,
            },
        }
    }

    /// The per-cell rules these settings ask for.
    #[must_use]
    pub fn rule(&self) -> CellRule {
        CellRule {
            hidden: self.hidden.then_some(OnOff {
                on_fraction: self.hidden_on,
                seed: self.hidden_seed,
            }),
            walls: self.walls.then_some(Walls {
                density: self.wall_density,
                seed: self.wall_seed,
            }),
        }
    }

    /// The fog these settings ask for, when on.
    #[must_use]
    pub fn fog(&self) -> Option<ManifoldFog> {
        let [r, g, b] = self.fog_color;
        self.fog.then(|| ManifoldFog {
            density: self.fog_density,
            color: Color::srgb(r, g, b),
        })
    }

    /// What of the paper's scene is shown.
    #[must_use]
    pub fn paper(&self) -> PaperOptions {
        PaperOptions {
            edges: self.edges,
            suzanne: self.suzanne,
            hands: self.hands,
            vehicle: self.vehicle,
            mirror: self.mirror,
        }
    }

    /// Brings every value into range (levels 1 to [`MAX_LEVEL`], positive
    /// finite distances and densities, colours and fractions in `[0, 1]`,
    /// a render scale in `[MIN_SCALE, 1]`, a known space), returning a
    /// warning for each value changed.
    pub fn sanitize(&mut self) -> Vec<String> {
        let mut warnings = Vec::new();
        let d = ExplorerSettings::default();
        let mut fix = |what: &str, bad: String, good: String| {
            warnings.push(format!("settings: {what} {bad} is out of range; using {good}"));
        };
        if !(1..=MAX_LEVEL).contains(&self.levels) {
            let v = self.levels.clamp(1, MAX_LEVEL);
            fix("levels", self.levels.to_string(), v.to_string());
            self.levels = v;
        }
        if !(self.max_distance.is_finite() && self.max_distance > 0.0) {
            fix(
                "max_distance",
                self.max_distance.to_string(),
                d.max_distance.to_string(),
            );
            self.max_distance = d.max_distance;
        }
        if !(self.fog_density.is_finite() && self.fog_density >= 0.0) {
            fix("fog_density", self.fog_density.to_string(), d.fog_density.to_string());
            self.fog_density = d.fog_density;
        }
        if !self.fog_color.iter().all(|c| (0.0..=1.0).contains(c)) {
            fix(
                "fog_color",
                format!("{:?}", self.fog_color),
                format!("{:?}", d.fog_color),
            );
            self.fog_color = d.fog_color;
        }
        if !(0.0..=1.0).contains(&self.pattern_on) {
            fix("pattern_on", self.pattern_on.to_string(), d.pattern_on.to_string());
            self.pattern_on = d.pattern_on;
        }
        if !(0.0..=1.0).contains(&self.hidden_on) {
            fix("hidden_on", self.hidden_on.to_string(), d.hidden_on.to_string());
            self.hidden_on = d.hidden_on;
        }
        if !(0.0..=1.0).contains(&self.wall_density) {
            fix(
                "wall_density",
                self.wall_density.to_string(),
                d.wall_density.to_string(),
            );
            self.wall_density = d.wall_density;
        }
        if !(MIN_SCALE..=1.0).contains(&self.render_scale) {
            let v = if self.render_scale.is_nan() {
                1.0
            } else {
                self.render_scale.clamp(MIN_SCALE, 1.0)
            };
            fix("render_scale", self.render_scale.to_string(), v.to_string());
            self.render_scale = v;
        }
        if !(1..=MAX_PATH_DEPTH).contains(&self.path_depth) {
            let v = self.path_depth.clamp(1, MAX_PATH_DEPTH);
            fix("path_depth", self.path_depth.to_string(), v.to_string());
            self.path_depth = v;
        }
        if !(2..=ManifoldAccumulation::MAX_SAMPLES).contains(&self.path_samples) {
            let v = self.path_samples.clamp(2, ManifoldAccumulation::MAX_SAMPLES);
            fix("path_samples", self.path_samples.to_string(), v.to_string());
            self.path_samples = v;
        }
        if self.reflections > MAX_REFLECTIONS {
            fix("reflections", self.reflections.to_string(), MAX_REFLECTIONS.to_string());
            self.reflections = MAX_REFLECTIONS;
        }
        if !(2..=ManifoldAccumulation::MAX_SAMPLES).contains(&self.still_samples) {
            let v = self.still_samples.clamp(2, ManifoldAccumulation::MAX_SAMPLES);
            fix("still_samples", self.still_samples.to_string(), v.to_string());
            self.still_samples = v;
        }
        if !TARGET_FPS.contains(&self.target_fps) {
            let v = if self.target_fps.is_nan() {
                d.target_fps
            } else {
                self.target_fps.clamp(*TARGET_FPS.start(), *TARGET_FPS.end())
            };
            fix("target_fps", self.target_fps.to_string(), v.to_string());
            self.target_fps = v;
        }
        let known = catalog::by_name(&self.space).is_some()
            || library::by_name(&self.space).is_some()
            || super::view::product_space(&self.space).is_some();
        if !known && !Path::new(&self.space).exists() {
            warnings.push(format!(
                "settings: space '{}' is neither a catalog or library space nor an existing file; using {}",
                self.space, d.space
            ));
            self.space = d.space;
        }
        warnings
    }

    /// Writes the settings as JSON to `path` (through a temporary file, so
    /// a crash mid-write leaves the old file), creating its directory.
    ///
    /// # Errors
    /// The directory or file cannot be written.
    pub fn save(&self, path: &Path) -> std::io::Result<()> {
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir)?;
        }
        let text = serde_json::to_string_pretty(self).map_err(std::io::Error::other)?;
        let tmp = path.with_extension("json.tmp");
        std::fs::write(&tmp, text + "\n")?;
        std::fs::rename(&tmp, path)
    }
}

/// Reads the settings at `path`: the defaults when there is no file, or
/// when it is broken (then it is renamed to `<path>.broken` and a warning
/// says so); values out of range are clamped. Returns the settings and the
/// warnings to show.
#[must_use]
pub fn load(path: &Path) -> (ExplorerSettings, Vec<String>) {
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return (ExplorerSettings::default(), Vec::new()),
        Err(e) => {
            return (
                ExplorerSettings::default(),
                vec![format!(
                    "settings file {} cannot be read ({e}); using defaults",
                    path.display()
                )],
            );
        }
    };
    match serde_json::from_str::<ExplorerSettings>(bevy_manifold_core::text::without_bom(&text)) {
        Ok(mut s) => {
            let warnings = s.sanitize();
            (s, warnings)
        }
        Err(e) => {
            let mut kept = path.as_os_str().to_owned();
            kept.push(".broken");
            let kept = PathBuf::from(kept);
            let aside = match std::fs::rename(path, &kept) {
                Ok(()) => format!("kept as {}", kept.display()),
                Err(re) => format!("could not be kept aside: {re}"),
            };
            (
                ExplorerSettings::default(),
                vec![format!(
                    "settings file {} is broken ({e}); using defaults (the file was {aside})",
                    path.display()
                )],
            )
        }
    }
}

/// Where the explorer keeps its settings: `$BEVY_MANIFOLD_CONFIG_DIR` if
/// set, else the platform's config directory (`$XDG_CONFIG_HOME` or
/// `~/.config` on Linux and the BSDs, `~/Library/Application Support` on
/// macOS, `%APPDATA%` on Windows), then `bevy_manifold/explorer.json`.
/// `None` when none of those is known.
#[must_use]
pub fn settings_path() -> Option<PathBuf> {
    let var = |k: &str| std::env::var_os(k).filter(|v| !v.is_empty()).map(PathBuf::from);
    if let Some(dir) = var("BEVY_MANIFOLD_CONFIG_DIR") {
        return Some(dir.join("explorer.json"));
    }
    let base = if cfg!(windows) {
        var("APPDATA")
    } else if cfg!(target_os = "macos") {
        var("HOME").map(|h| h.join("Library/Application Support"))
    } else {
        var("XDG_CONFIG_HOME").or_else(|| var("HOME").map(|h| h.join(".config")))
    }?;
    Some(base.join("bevy_manifold").join("explorer.json"))
}
