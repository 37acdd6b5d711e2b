//! The camera path of a tour: a spline on the isometry group through the
//! keyframes, exact in E3, H3 and S3 and across face pairings.
//!
//! Keyframe `i` is a pose in the cover, `K_i = g_i L_i`: the element `g_i`
//! of its copy of the domain (named by a face word from the origin copy)
//! and a local pose `L_i` inside the domain. Keyframes are related by
//! their relative motions `D_i = K_i^-1 K_(i+1) = L_i^-1 (g_i^-1 g_(i+1))
//! L_(i+1)`, computed from the words (never from chart coordinates), so a
//! keyframe three cells away is three cells away.
//!
//! Between keyframes the camera moves on a cubic Bezier curve in the group,
//! evaluated by De Casteljau's construction with geodesic interpolation
//! `lerp(a, b, u) = a exp(u log(a^-1 b))` (Park and Ravani, "Bezier curves
//! on Riemannian manifolds and Lie groups", 1995). Its end velocities are
//! `3 log(b0^-1 b1) / h` and `3 log(b2^-1 b3) / h` in the body frame, so
//! placing the inner control points at `K_i exp(+-xi_i h / 3)` gives every
//! segment meeting at keyframe `i` the body velocity `xi_i` there: the path
//! is C1 (velocity continuous; acceleration is not matched). `xi_i` is the
//! three-point (Catmull-Rom) estimate from the neighbouring relative
//! motions, zero at a keyframe that stops, and a leg's own velocity next to
//! a leg. A leg (fly, turn, loop) is a segment that moves by its screw
//! motion exactly, `K_i exp(u log D_i)`: constant speed, and a loop around
//! a closed geodesic comes back to the same pose in the quotient.
//!
//! ```
//! use bevy_manifold_core::space::catalog;
//! use bevy_manifold_core::tour::{PathKey, Segment, TourPath};
//! use glam::{DMat4, DVec3};
//! let torus = catalog::torus(1.0);
//! let keys = vec![
//!     PathKey { time: 0.0, word: vec![], local: DMat4::IDENTITY, stop: false },
//!     PathKey { time: 2.0, word: vec![0, 0], local: DMat4::IDENTITY, stop: false },
//! ];
//! let path = TourPath::new(&torus, keys, vec![Segment::Smooth]).unwrap();
//! // Two cells along +x in two seconds, through the face +x twice: at
//! // t = 1.25 the camera is a quarter past the centre of the first copy.
//! let at = path.frame(&torus, 1.25);
//! assert_eq!(at.word, vec![0]);
//! assert!((at.placement.w_axis.truncate() - DVec3::X * 0.25).length() < 1e-12);
//! ```

use crate::geometry::{Geometry, isometry};
use crate::space::Space;
use glam::{DMat4, DVec3};

/// A twist: linear and angular velocity in the body frame (see
/// [`isometry::exp_twist`]).
pub type Twist = (DVec3, DVec3);

/// One keyframe of a path.
#[derive(Clone, Debug, PartialEq)]
pub struct PathKey {
    /// When the camera is there, in seconds from the start.
    pub time: f64,
    /// The copy of the domain, as the faces crossed from the origin copy
    /// (crossing face `i` from cell `g` leads to `g T_i^-1`).
    pub word: Vec<usize>,
    /// The pose inside the domain (carries the origin's frame to the
    /// camera's; the camera looks along local -z). In a copy behind an
    /// odd number of mirrors the path mirrors its x axis if it is not
    /// mirrored already, as an entity's frame is after crossing a mirror,
    /// so every pose of the path has the same handedness in the cover.
    pub local: DMat4,
    /// The camera comes to rest here (zero velocity).
    pub stop: bool,
}

/// How the path runs from one keyframe to the next.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Segment {
    /// The smooth spline.
    Smooth,
    /// The screw motion between the two poses, at constant speed (a leg).
    Screw,
}

/// A place on the path: what the camera of a tour is at one time.
#[derive(Clone, Debug, PartialEq)]
pub struct PathFrame {
    /// The copy of the domain the camera is in, as a face word from the
    /// origin copy (the keyframe's word, then the faces the wrap crossed).
    pub word: Vec<usize>,
    /// The camera's pose inside the domain.
    pub placement: DMat4,
}

/// An error in building a path, at a keyframe.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PathError {
    /// The keyframe (its index in the path).
    pub key: usize,
    /// What is wrong.
    pub message: String,
}

#[derive(Clone, Debug)]
struct Piece {
    t0: f64,
    h: f64,
    /// `D = K_i^-1 K_(i+1)`.
    rel: DMat4,
    kind: Segment,
    /// Smooth: the control points `c1, c2` and the twists `X01, X12, X23`
    /// of the first De Casteljau level (`b0 = I, b3 = D`); screw: `X01`
    /// is `log D`.
    c1: DMat4,
    c2: DMat4,
    x: [Twist; 3],
}

/// A tour's camera path: see the module docs.
#[derive(Clone, Debug)]
pub struct TourPath {
    keys: Vec<PathKey>,
    pieces: Vec<Piece>,
    geometry: Geometry,
}

fn scale((v, w): Twist, s: f64) -> Twist {
    (v * s, w * s)
}

fn add(a: Twist, b: Twist) -> Twist {
    (a.0 + b.0, a.1 + b.1)
}

/// The word of `g^-1` for the word of `g`: reversed, each face by its
/// partner.
#[must_use]
pub fn inverse_word(space: &Space, word: &[usize]) -> Vec<usize> {
    word.iter().rev().map(|&f| space.faces()[f].partner).collect()
}

impl TourPath {
    /// The path through `keys` (times strictly increasing, at least one),
    /// with `segments[i]` the kind of the segment from key `i` to `i + 1`.
    ///
    /// # Errors
    /// A keyframe whose motion from the previous one has no unique screw
    /// (a half turn: split it with a keyframe between), a face out of
    /// range, times not increasing, or a count mismatch.
    pub fn new(space: &Space, mut keys: Vec<PathKey>, segments: Vec<Segment>) -> Result<Self, PathError> {
        let g = space.geometry();
        let err = |key: usize, message: String| PathError { key, message };
        if keys.is_empty() {
            return Err(err(0, "a tour needs at least one keyframe".into()));
        }
        if segments.len() + 1 != keys.len() {
            return Err(err(
                0,
                format!("{} segments for {} keyframes", segments.len(), keys.len()),
            ));
        }
        let faces = space.faces().len();
        for (i, k) in keys.iter().enumerate() {
            if let Some(f) = k.word.iter().find(|&&f| f >= faces) {
                return Err(err(
                    i,
                    format!("face {f} in the cell's word, but the space has {faces} faces"),
                ));
            }
            if !k.time.is_finite() || (i > 0 && k.time <= keys[i - 1].time) {
                return Err(err(
                    i,
                    format!("time {} does not come after the previous keyframe's", k.time),
                ));
            }
        }
        for k in &mut keys {
            let cell = space.cell_matrix(&space.cell_of_word(&k.word));
            if isometry::is_orientation_reversing(cell) != isometry::is_orientation_reversing(k.local) {
                k.local.x_axis = -k.local.x_axis;
            }
        }
        // Relative motions and their screws, from the words.
        let mut rel = Vec::new();
        let mut screws = Vec::new();
        for (i, pair) in keys.windows(2).enumerate() {
            let mut word = inverse_word(space, &pair[0].word);
            word.extend_from_slice(&pair[1].word);
            let between = space.cell_matrix(&space.cell_of_word(&word));
            let d = isometry::inverse(g, pair[0].local) * between * pair[1].local;
            let x = isometry::log_twist(g, d).ok_or_else(|| {
                err(
                    i + 1,
                    "the motion from the previous keyframe has no single shortest screw (a half turn?): put a keyframe between"
                        .into(),
                )
            })?;
            rel.push(d);
            screws.push(x);
        }
        let h = |i: usize| keys[i + 1].time - keys[i].time;
        let velocity = |i: usize| scale(screws[i], 1.0 / h(i));
        let zero = (DVec3::ZERO, DVec3::ZERO);
        let n = keys.len();
        let tangent = |i: usize| -> Twist {
            if keys[i].stop {
                return zero;
            }
            let before = (i > 0).then(|| i - 1);
            let after = (i + 1 < n).then_some(i);
            match (before, after) {
                (Some(b), _) if segments[b] == Segment::Screw => velocity(b),
                (_, Some(a)) if segments[a] == Segment::Screw => velocity(a),
                (Some(b), Some(a)) => {
                    let (hb, ha) = (h(b), h(a));
                    add(scale(velocity(b), ha / (ha + hb)), scale(velocity(a), hb / (ha + hb)))
                }
                (Some(b), None) => velocity(b),
                (None, Some(a)) => velocity(a),
                (None, None) => zero,
            }
        };
        let mut pieces = Vec::new();
        for i in 0..n - 1 {
            let hi = h(i);
            let piece = match segments[i] {
                Segment::Screw => Piece {
                    t0: keys[i].time,
                    h: hi,
                    rel: rel[i],
                    kind: Segment::Screw,
                    c1: DMat4::IDENTITY,
                    c2: DMat4::IDENTITY,
                    x: [screws[i], zero, zero],
                },
                Segment::Smooth => {
                    let x01 = scale(tangent(i), hi / 3.0);
                    let x23 = scale(tangent(i + 1), hi / 3.0);
                    let c1 = exp(g, x01, 1.0);
                    let c2 = rel[i] * exp(g, x23, -1.0);
                    let x12 = isometry::log_twist(g, isometry::inverse(g, c1) * c2).ok_or_else(|| {
                        err(
                            i + 1,
                            "the path bends by a half turn on the way here: put a keyframe between".into(),
                        )
                    })?;
                    Piece {
                        t0: keys[i].time,
                        h: hi,
                        rel: rel[i],
                        kind: Segment::Smooth,
                        c1,
                        c2,
                        x: [x01, x12, x23],
                    }
                }
            };
            pieces.push(piece);
        }
        Ok(TourPath {
            keys,
            pieces,
            geometry: g,
        })
    }

    /// The keyframes.
    #[must_use]
    pub fn keys(&self) -> &[PathKey] {
        &self.keys
    }

    /// The time of the first keyframe and of the last.
    #[must_use]
    pub fn span(&self) -> (f64, f64) {
        (self.keys[0].time, self.keys[self.keys.len() - 1].time)
    }

    /// The segment `t` falls in and its parameter in `[0, 1]` (`t` clamped
    /// to the span); `None` for a path of one keyframe.
    fn locate(&self, t: f64) -> Option<(usize, f64)> {
        if self.pieces.is_empty() {
            return None;
        }
        let (start, end) = self.span();
        let t = if t.is_nan() { start } else { t.clamp(start, end) };
        let i = self
            .pieces
            .partition_point(|p| p.t0 + p.h <= t)
            .min(self.pieces.len() - 1);
        let p = &self.pieces[i];
        Some((i, ((t - p.t0) / p.h).clamp(0.0, 1.0)))
    }

    /// The motion from keyframe `i` at parameter `u` of segment `i`: `K_i^-1 P`.
    fn bezier(&self, i: usize, u: f64) -> DMat4 {
        let g = self.geometry;
        let p = &self.pieces[i];
        if p.kind == Segment::Screw {
            return exp(g, p.x[0], u);
        }
        let a01 = exp(g, p.x[0], u);
        let a12 = p.c1 * exp(g, p.x[1], u);
        let a23 = p.c2 * exp(g, p.x[2], u);
        let a012 = lerp(g, a01, a12, u);
        let a123 = lerp(g, a12, a23, u);
        lerp(g, a012, a123, u)
    }

    /// The cover pose at time `t` relative to the copy of keyframe `i`, the
    /// keyframe `t` falls after: `(i, g_i^-1 P(t))`.
    #[must_use]
    pub fn local_pose(&self, t: f64) -> (usize, DMat4) {
        match self.locate(t) {
            None => (0, self.keys[0].local),
            Some((i, u)) => (i, self.keys[i].local * self.bezier(i, u)),
        }
    }

    /// The camera at time `t` (clamped to the span): its copy of the domain
    /// and its pose there.
    #[must_use]
    pub fn frame(&self, space: &Space, t: f64) -> PathFrame {
        let (i, pose) = self.local_pose(t);
        let mut word = self.keys[i].word.clone();
        let (placement, _) = space.wrap_with(pose, 100_000, &mut |f| word.push(f));
        PathFrame { word, placement }
    }

    /// The motion from the pose at `t0` to the pose at `t1`, in the frame
    /// at `t0`: `P(t0)^-1 P(t1)`, from the keyframes' relative motions
    /// (well conditioned however far the path has gone).
    #[must_use]
    pub fn relative(&self, t0: f64, t1: f64) -> DMat4 {
        let g = self.geometry;
        let (Some((i, u0)), Some((j, u1))) = (self.locate(t0), self.locate(t1)) else {
            return DMat4::IDENTITY;
        };
        let (lo, hi, forward) = if i <= j { (i, j, true) } else { (j, i, false) };
        let (ulo, uhi) = if forward { (u0, u1) } else { (u1, u0) };
        let mut m = isometry::inverse(g, self.bezier(lo, ulo));
        for piece in &self.pieces[lo..hi] {
            m *= piece.rel;
        }
        m *= self.bezier(hi, uhi);
        if forward { m } else { isometry::inverse(g, m) }
    }

    /// The body velocity (linear, angular) at time `t`, by a central
    /// difference of the path's relative motion over `dt`.
    #[must_use]
    pub fn velocity(&self, t: f64, dt: f64) -> Twist {
        let m = self.relative(t - dt, t + dt);
        isometry::log_twist(self.geometry, m).map_or((DVec3::ZERO, DVec3::ZERO), |x| scale(x, 0.5 / dt))
    }
}

/// `exp(s X)`.
fn exp(g: Geometry, (v, w): Twist, s: f64) -> DMat4 {
    isometry::exp_twist(g, v * s, w * s)
}

/// Geodesic interpolation in the group: `a exp(u log(a^-1 b))`; the nearer
/// end when the screw from `a` to `b` is not unique (never for the
/// control points of a built path, whose screws were checked).
fn lerp(g: Geometry, a: DMat4, b: DMat4, u: f64) -> DMat4 {
    let d = isometry::inverse(g, a) * b;
    match isometry::log_twist(g, d) {
        Some(x) => a * exp(g, x, u),
        None if u < 0.5 => a,
        None => b,
    }
}
