//! What a trace is asked to do: [`TraceSettings`] (size, levels,
//! distance, per-cell shading and rules, projection, culling, cones) and
//! the limits every tracer keeps to.
//!
//! GPU twin: the `Params` uniform (`GpuParams` in `bevy_manifold_gpu`'s
//! `layout.rs`, `Params` in `shaders/bindings.wgsl`), packed from these
//! settings and the view.

use crate::space::cells::CellTint;
use crate::space::rule::CellRule;

/// How to trace.
#[derive(Clone, Debug, PartialEq)]
pub struct TraceSettings {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Most face crossings (transports) a ray may make: the paper's levels.
    pub levels: u32,
    /// Rays stop after this distance.
    pub max_distance: f64,
    /// Colour objects by the cell they are seen in.
    pub cell_colors: bool,
    /// How, when `cell_colors` is on.
    pub cell_tint: CellTint,
    /// Stop a ray once fog leaves less than 1/255 of its light.
    pub fog_early_stop: bool,
    /// Renormalise the ray after each advance and transport (off only to
    /// measure drift: see [`super::step::advance_raw`]).
    pub renormalize: bool,
    /// Per-cell rules: objects in off cells hidden, walls between cells
    /// ([`crate::space::rule`]); the GPU twin is `CELL_RULES`.
    pub cell_rule: CellRule,
    /// How pixels map to rays: the camera's perspective, or a panorama.
    pub projection: Projection,
    /// Test on each segment only the objects near the faces it comes near
    /// ([`super::step::near_faces`], [`super::cull`]): the same image, fewer tests. Off
    /// only to measure what it saves (the GPU twin is `FLAG_NO_CULL`).
    pub cull: bool,
    /// Trace each pixel as a cone half a pixel wide
    /// ([`super::footprint`]): balls and edge tubes thinner than its
    /// footprint add the part of the pixel they cover and let the rest
    /// through, so far copies fade to their average instead of
    /// flickering, and silhouettes are smooth. Off: one ray per pixel,
    /// hit or miss. The GPU twin is `params.footprint`.
    pub footprint: bool,
    /// Which point of each light's disc shadow rays aim at
    /// ([`super::light_sample_point`]): 0, the centre (hard shadows),
    /// and the `k`-th trace of an accumulating view `k`, so that lights
    /// with a radius cast soft shadows once still frames add up
    /// ([`super::accumulate`]). The GPU twin is `params.light_sample`.
    pub light_sample: u32,
    /// Reflections: how many times a ray may reflect off a surface with a
    /// material ([`crate::material::Pbr`]) and go on along the geodesic
    /// of its mirror direction, through the face pairings like a camera
    /// ray (with a fresh budget of `levels`); its colour is weighted by
    /// [`crate::material::reflectance`]. 0: no reflections (and none of
    /// their code on the GPU, whose twin is the `REFLECTIONS` def and
    /// `params.reflections`). At most [`MAX_REFLECTIONS`].
    pub reflections: u32,
    /// Path tracing ([`super::path`]): above 0, each pixel is one sample
    /// of the rendering equation, a path of up to this many bounces
    /// (diffuse and GGX lobes sampled, the light images sampled at each
    /// bounce), the `light_sample`-th of an accumulating view; 0: the
    /// direct tracer. At most [`MAX_PATH_DEPTH`]. The GPU twin is the
    /// `PATH_TRACE` def and `params.path_depth`.
    pub path_depth: u32,
    /// The path tracer's seed: the same seed, sample and pixel give the
    /// same path on every run, CPU and GPU.
    pub seed: u32,
}

/// How the pixels of an image map to view directions.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Projection {
    /// The camera's field of view, square pixels (the scene camera's
    /// `fov_y_degrees`).
    #[default]
    Perspective,
    /// 360 degrees mono, equirectangular: column `i` is the longitude
    /// (the view direction -z in the middle, +x at three quarters), row
    /// `j` the latitude (+y at the top).
    Equirect,
    /// Omni-directional stereo, top-bottom: the left eye's equirectangular
    /// panorama above the right eye's. For each longitude the eyes sit
    /// `eye_separation` apart (the space's distance) on the line through
    /// the camera perpendicular to that direction, reached along the
    /// geodesic, as VR eyes are; the ray's direction is carried there
    /// unchanged (it is perpendicular to the offset).
    Ods {
        /// Distance between the eyes.
        eye_separation: f64,
    },
}

impl Projection {
    /// The projection's number on the GPU (`params.projection`) and the
    /// half eye separation.
    #[must_use]
    pub fn words(self) -> (u32, f32) {
        match self {
            Projection::Perspective => (0, 0.0),
            Projection::Equirect => (1, 0.0),
            Projection::Ods { eye_separation } => (2, (eye_separation * 0.5) as f32),
        }
    }
}

/// Most levels (face transports per ray) any tracer takes; more are
/// clamped or refused. Enough for the drift probe's 10^4-transport walks;
/// the GPU walk's loop bound (levels plus at most 10^4 distance steps)
/// stays far from `u32` overflow.
pub const MAX_LEVELS: u32 = 16_384;

/// Most pixels in one traced image (8192 x 8192).
pub const MAX_PIXELS: u64 = 1 << 26;

/// Most bounces of a traced path ([`TraceSettings::path_depth`]).
/// WGSL twin: `MAX_PATH_DEPTH` in `shaders/path.wgsl`.
pub const MAX_PATH_DEPTH: u32 = 64;

/// Most reflections a ray follows ([`TraceSettings::reflections`]): each
/// reflection is a walk of up to `levels` crossings of its own. WGSL twin:
/// `MAX_REFLECTIONS` in `shaders/trace.wgsl`.
pub const MAX_REFLECTIONS: u32 = 8;

impl TraceSettings {
    /// Checks the settings a tracer can honour: a size of at least one
    /// pixel and at most [`MAX_PIXELS`] (multiplied in 64 bits), levels at
    /// most [`MAX_LEVELS`], a positive `max_distance` (not NaN; the GPU
    /// walk bounds its loop by at most 10^4 steps of it whatever it is).
    ///
    /// # Errors
    /// The first setting out of range, named with its value.
    ///
    /// ```
    /// use bevy_manifold_core::trace::TraceSettings;
    /// let huge = TraceSettings { width: 70_000, height: 70_000, ..TraceSettings::default() };
    /// assert!(huge.check().unwrap_err().contains("70000x70000"));
    /// assert!(TraceSettings::default().check().is_ok());
    /// ```
    pub fn check(&self) -> Result<(), String> {
        let pixels = u64::from(self.width) * u64::from(self.height);
        if pixels == 0 || pixels > MAX_PIXELS {
            return Err(format!(
                "an image of {}x{} pixels: it must have between 1 and {MAX_PIXELS} pixels",
                self.width, self.height
            ));
        }
        if self.levels > MAX_LEVELS {
            return Err(format!("{} levels: at most {MAX_LEVELS}", self.levels));
        }
        if self.path_depth > MAX_PATH_DEPTH {
            return Err(format!("a path depth of {}: at most {MAX_PATH_DEPTH}", self.path_depth));
        }
        if self.reflections > MAX_REFLECTIONS {
            return Err(format!("{} reflections: at most {MAX_REFLECTIONS}", self.reflections));
        }
        if self.max_distance.is_nan() || self.max_distance <= 0.0 {
            return Err(format!("max distance {}: it must be positive", self.max_distance));
        }
        Ok(())
    }
}

impl Default for TraceSettings {
    fn default() -> Self {
        TraceSettings {
            width: 640,
            height: 360,
            levels: 8,
            max_distance: 100.0,
            cell_colors: false,
            cell_tint: CellTint::ByCell,
            fog_early_stop: true,
            renormalize: true,
            cell_rule: CellRule::default(),
            projection: Projection::Perspective,
            cull: true,
            footprint: false,
            light_sample: 0,
            reflections: 0,
            path_depth: 0,
            seed: 0,
        }
    }
}
