//! The render scale: a manifold camera may trace fewer pixels than its
//! viewport has ([`ManifoldRenderScale`]), the pass then upscaling the
//! trace into the view target ([`crate::render::upscale`]); and
//! [`AdaptiveRenderScale`] chooses that scale each frame to hold a target
//! frame time. Tracing cost is close to proportional to the pixels traced
//! (the square of the scale), which is what the controller assumes.

use super::ManifoldCamera;
use bevy::prelude::*;

/// The smallest render scale the pass traces at.
pub const MIN_RENDER_SCALE: f32 = 0.1;

/// Traces a [`ManifoldCamera`]'s view at this fraction of its viewport's
/// width and height, then upscales it (bilinear colour, nearest depth) to
/// the whole viewport: `0.5` traces a quarter of the pixels. Values are
/// clamped to `[MIN_RENDER_SCALE, 1]` (NaN is 1); at 1 the trace is drawn
/// straight into the view target as without this component.
///
/// ```
/// use bevy::prelude::*;
/// use bevy_manifold::prelude::*;
///
/// fn spawn(mut commands: Commands, root: Single<Entity, With<ManifoldSpace>>) {
///     commands.spawn((ChildOf(*root), ManifoldCamera::default(), ManifoldRenderScale(0.5)));
/// }
/// # let _ = spawn;
/// ```
#[derive(Component, Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Component, Debug, Default)]
pub struct ManifoldRenderScale(pub f32);

impl Default for ManifoldRenderScale {
    fn default() -> Self {
        ManifoldRenderScale(1.0)
    }
}

impl ManifoldRenderScale {
    /// The scale the pass uses: clamped to `[MIN_RENDER_SCALE, 1]`, NaN
    /// read as 1.
    #[must_use]
    pub fn get(self) -> f32 {
        if self.0.is_nan() {
            1.0
        } else {
            self.0.clamp(MIN_RENDER_SCALE, 1.0)
        }
    }

    /// The pixels traced for a viewport of `size` (each side at least 1).
    #[must_use]
    pub fn traced_size(self, size: UVec2) -> UVec2 {
        let s = self.get();
        UVec2::new(
            ((size.x as f32 * s).round() as u32).clamp(1, size.x.max(1)),
            ((size.y as f32 * s).round() as u32).clamp(1, size.y.max(1)),
        )
    }
}

/// Holds a frame time by choosing the camera's [`ManifoldRenderScale`]
/// each frame (inserting one when missing): the scale falls when frames
/// take longer than `target_frame_ms` and rises, more cautiously, when
/// they take clearly less, within `[min_scale, max_scale]`. Frame times
/// are the app's real frame times (`Time<Real>`), smoothed; after each
/// change the controller waits a few frames for the change to show
/// (Bevy's pipelined renderer draws a frame behind). Where frames are
/// paced (vsync, a headset's runtime) a frame never shows it could be
/// shorter, so a scale held steady in the band is probed one step up
/// every [`Self::PROBE_FRAMES`] frames; a probe that leaves the band goes
/// straight back and the next waits ten times as long.
///
/// ```
/// use bevy::prelude::*;
/// use bevy_manifold::prelude::*;
///
/// fn spawn(mut commands: Commands, root: Single<Entity, With<ManifoldSpace>>) {
///     // Hold 60 fps, never tracing fewer than a quarter of the pixels
///     // along each side.
///     let hold = AdaptiveRenderScale::new(1000.0 / 60.0).with_range(0.25, 1.0);
///     commands.spawn((ChildOf(*root), ManifoldCamera::default(), hold));
/// }
/// # let _ = spawn;
/// ```
#[derive(Component, Clone, Debug, PartialEq, Reflect)]
#[reflect(Component, Debug, Default)]
pub struct AdaptiveRenderScale {
    /// The frame time to hold, in milliseconds.
    pub target_frame_ms: f32,
    /// The least scale chosen.
    pub min_scale: f32,
    /// The greatest scale chosen.
    pub max_scale: f32,
    /// Smoothed frame time since the last change.
    #[reflect(ignore)]
    smoothed_ms: Option<f32>,
    /// Frames still to skip after a change.
    #[reflect(ignore)]
    settle: u32,
    /// Frames in the band still to wait before probing a step up.
    #[reflect(ignore)]
    quiet: u32,
    /// The scale a probe started from, while it is tried.
    #[reflect(ignore)]
    probe_from: Option<f32>,
}

impl Default for AdaptiveRenderScale {
    /// 60 frames per second over the whole range.
    fn default() -> Self {
        AdaptiveRenderScale::new(1000.0 / 60.0)
    }
}

impl AdaptiveRenderScale {
    /// Frames skipped after a change before frame times count again.
    pub const SETTLE_FRAMES: u32 = 3;
    /// Above `target * SLOW` the scale falls.
    pub const SLOW: f32 = 1.05;
    /// Below `target * FAST` the scale rises.
    pub const FAST: f32 = 0.85;
    /// A rise aims at this fraction of the target.
    pub const AIM: f32 = 0.95;
    /// The most the scale rises in one change (a factor).
    pub const MAX_RISE: f32 = 1.15;
    /// The most it falls in one change.
    pub const MAX_FALL: f32 = 0.6;
    /// Scales are chosen on this grid, so small changes in frame time
    /// do not remake the traced texture.
    pub const STEP: f32 = 0.02;
    /// Frames held steady in the band before a step up is tried.
    pub const PROBE_FRAMES: u32 = 120;
    /// Weight of a new frame time in the smoothed one.
    const SMOOTHING: f32 = 0.25;

    /// Holds `target_frame_ms` over the whole range of scales.
    #[must_use]
    pub fn new(target_frame_ms: f32) -> Self {
        AdaptiveRenderScale {
            target_frame_ms,
            min_scale: MIN_RENDER_SCALE,
            max_scale: 1.0,
            smoothed_ms: None,
            settle: 0,
            quiet: Self::PROBE_FRAMES,
            probe_from: None,
        }
    }

    /// The same, between `min` and `max`.
    #[must_use]
    pub fn with_range(mut self, min: f32, max: f32) -> Self {
        self.min_scale = min;
        self.max_scale = max;
        self
    }

    /// The smoothed frame time the controller acts on, when it has one.
    #[must_use]
    pub fn smoothed_ms(&self) -> Option<f32> {
        self.smoothed_ms
    }

    /// The range in use: both ends clamped to `[MIN_RENDER_SCALE, 1]`, in
    /// order.
    fn range(&self) -> (f32, f32) {
        let c = |v: f32, or: f32| if v.is_nan() { or } else { v.clamp(MIN_RENDER_SCALE, 1.0) };
        let (a, b) = (c(self.min_scale, MIN_RENDER_SCALE), c(self.max_scale, 1.0));
        (a.min(b), a.max(b))
    }

    /// One frame of `frame_ms` at scale `scale`: the scale to use from
    /// now on. Frame time is taken as a fixed part plus a part
    /// proportional to the pixels traced; the controller moves the scale
    /// by the square root of target over measured time (what removes the
    /// excess if all the time were tracing), limited per change, and only
    /// outside the band `[FAST, SLOW] * target`.
    pub fn step(&mut self, scale: f32, frame_ms: f32) -> f32 {
        let (lo, hi) = self.range();
        let scale = if scale.is_nan() { hi } else { scale.clamp(lo, hi) };
        let target = self.target_frame_ms;
        if !(frame_ms.is_finite() && frame_ms > 0.0 && target.is_finite() && target > 0.0) {
            return scale;
        }
        if self.settle > 0 {
            self.settle -= 1;
            return scale;
        }
        let smoothed = match self.smoothed_ms {
            Some(s) => s + Self::SMOOTHING * (frame_ms - s),
            None => frame_ms,
        };
        self.smoothed_ms = Some(smoothed);
        let ratio = target / smoothed;
        let factor = if smoothed > target * Self::SLOW {
            if let Some(from) = self.probe_from.take() {
                // The probe cost too much: straight back, and wait longer
                // before the next.
                self.quiet = Self::PROBE_FRAMES * 10;
                return self.changed(from);
            }
            ratio.sqrt().max(Self::MAX_FALL)
        } else if smoothed < target * Self::FAST {
            // Aim inside the band, not at its top edge.
            (ratio * Self::AIM).sqrt().min(Self::MAX_RISE)
        } else {
            if self.probe_from.take().is_some() {
                // The probe held: keep it.
                self.quiet = Self::PROBE_FRAMES;
            }
            if self.quiet > 0 {
                self.quiet -= 1;
                return scale;
            }
            self.quiet = Self::PROBE_FRAMES;
            let up = ((scale / Self::STEP).round() * Self::STEP + Self::STEP).min(hi);
            if up <= scale {
                return scale;
            }
            self.probe_from = Some(scale);
            return self.changed(up);
        };
        self.probe_from = None;
        let next = ((scale * factor / Self::STEP).round() * Self::STEP).clamp(lo, hi);
        if (next - scale).abs() < Self::STEP * 0.5 {
            return scale;
        }
        self.quiet = Self::PROBE_FRAMES;
        self.changed(next)
    }

    /// Starts measuring afresh at `next` after a change.
    fn changed(&mut self, next: f32) -> f32 {
        self.smoothed_ms = None;
        self.settle = Self::SETTLE_FRAMES;
        next
    }
}

/// Steps every [`AdaptiveRenderScale`] with this frame's real frame time.
pub fn adapt_render_scale(
    time: Res<Time<Real>>,
    mut commands: Commands,
    mut cameras: Query<(Entity, &mut AdaptiveRenderScale, Option<&mut ManifoldRenderScale>), With<ManifoldCamera>>,
) {
    let ms = time.delta_secs() * 1000.0;
    for (entity, mut adaptive, scale) in &mut cameras {
        match scale {
            Some(mut scale) => {
                let next = adaptive.step(scale.0, ms);
                if next != scale.0 {
                    scale.0 = next;
                }
            }
            None => {
                let start = adaptive.range().1;
                let next = adaptive.step(start, ms);
                commands.entity(entity).insert(ManifoldRenderScale(next));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A machine whose frame costs `fixed + per_pixel * scale²` ms, seen
    /// through a pipeline `delay` frames deep, with a ±`noise` wobble.
    fn run(target: f32, fixed: f32, full: f32, delay: usize, noise: f32, frames: usize) -> (f32, Vec<f32>) {
        let mut c = AdaptiveRenderScale::new(target);
        let mut scale = 1.0f32;
        let mut history = vec![scale; delay + 1];
        let mut scales = Vec::new();
        for k in 0..frames {
            let shown = history[history.len() - 1 - delay];
            let wobble = 1.0 + noise * ((k as f32 * 2.399).sin());
            let ms = (fixed + full * shown * shown) * wobble;
            scale = c.step(scale, ms);
            history.push(scale);
            scales.push(scale);
        }
        (scale, scales)
    }

    #[test]
    fn the_scale_settles_where_the_cost_model_meets_the_target_band() {
        // 4 ms fixed, 40 ms at full scale, 60 fps wanted: the scales
        // whose frames fall in [0.85, 1.05] x 16.67 ms are
        // sqrt((0.85*16.67 - 4)/40) = 0.5175 to sqrt((1.05*16.67 - 4)/40) = 0.5906.
        for delay in [0, 1, 2] {
            let (end, scales) = run(1000.0 / 60.0, 4.0, 40.0, delay, 0.03, 1600);
            assert!((0.50..=0.60).contains(&end), "delay {delay}: settled at {end}");
            // Settled: probes up the band, one refused, then quiet.
            let changes = scales[1200..].windows(2).filter(|w| w[0] != w[1]).count();
            assert!(changes <= 2, "delay {delay}: still moving: {:?}", &scales[1200..1240]);
            // And it got there soon: within 60 frames.
            assert!(
                scales[60..].iter().all(|s| (0.48..=0.62).contains(s)),
                "delay {delay}: {:?}",
                &scales[..80]
            );
        }
    }

    #[test]
    fn under_vsync_probes_find_the_most_pixels_that_keep_the_rate() {
        // Frames paced at 60 Hz: a frame takes whole refresh periods. The
        // trace fits one period up to sqrt((16.67 - 4)/40) = 0.5627; a
        // frame at the target never shows room to spare, so only probing
        // climbs back after the first fall overshoots.
        let period = 1000.0 / 60.0;
        let mut c = AdaptiveRenderScale::new(period);
        let mut scale = 1.0f32;
        let mut scales = Vec::new();
        for _ in 0..3000 {
            let t = 4.0 + 40.0 * scale * scale;
            let ms = (t / period).ceil().max(1.0) * period;
            scale = c.step(scale, ms);
            scales.push(scale);
        }
        let low = scales[..100].iter().copied().fold(1.0f32, f32::min);
        assert!(low < 0.5, "the first fall overshoots: {low}");
        assert!((0.54..=0.5627).contains(&scale), "ended at {scale}");
        // The best on the grid (0.56) is held most of the time at the end.
        let at_best = scales[2000..].iter().filter(|s| (**s - 0.56).abs() < 1e-4).count();
        assert!(at_best >= 950, "{at_best} of 1000 frames at 0.56");
    }

    #[test]
    fn an_easy_target_keeps_the_most_and_an_impossible_one_the_least() {
        let (easy, _) = run(20.0, 2.0, 10.0, 1, 0.02, 200);
        assert_eq!(easy, 1.0);
        // 30 ms fixed cost can never make 16.7 ms.
        let (hard, _) = run(1000.0 / 60.0, 30.0, 40.0, 1, 0.02, 200);
        assert!((hard - MIN_RENDER_SCALE).abs() < 1e-6, "{hard}");
    }

    #[test]
    fn a_slow_start_recovers_when_the_load_goes() {
        // Heavy for 150 frames (80 ms at full scale), light afterwards
        // (10 ms): the scale falls, then climbs back to 1.
        let mut c = AdaptiveRenderScale::new(1000.0 / 60.0);
        let mut scale = 1.0f32;
        let mut low = 1.0f32;
        for k in 0..400 {
            let full = if k < 150 { 80.0 } else { 10.0 };
            scale = c.step(scale, 2.0 + full * scale * scale);
            if k == 149 {
                low = scale;
            }
        }
        // 80 ms: sqrt((0.85*16.67-2)/80) = 0.42 to sqrt((1.05*16.67-2)/80) = 0.44.
        assert!((0.38..=0.46).contains(&low), "{low}");
        assert_eq!(scale, 1.0);
    }

    #[test]
    fn bad_input_changes_nothing() {
        let mut c = AdaptiveRenderScale::new(16.0).with_range(f32::NAN, 7.0);
        assert_eq!(c.step(0.5, f32::NAN), 0.5);
        assert_eq!(c.step(0.5, -1.0), 0.5);
        assert_eq!(c.step(f32::NAN, 16.0), 1.0);
        let mut z = AdaptiveRenderScale::new(0.0);
        assert_eq!(z.step(0.7, 100.0), 0.7);
        assert_eq!(ManifoldRenderScale(f32::NAN).get(), 1.0);
        assert_eq!(ManifoldRenderScale(-3.0).get(), MIN_RENDER_SCALE);
        assert_eq!(
            ManifoldRenderScale(0.5).traced_size(UVec2::new(641, 3)),
            UVec2::new(321, 2)
        );
        assert_eq!(ManifoldRenderScale(0.1).traced_size(UVec2::new(4, 1)), UVec2::new(1, 1));
    }
}
