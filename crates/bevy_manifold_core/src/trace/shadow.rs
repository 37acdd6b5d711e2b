//! Shadows through the faces: a light image lights a hit only if the
//! geodesic between them is free. The shadow ray walks through the faces
//! as a camera ray does ([`Walker`], the same exit and transport), and on
//! each segment meets the same objects ([`each_candidate`]): balls
//! (glowing ones, the lamps, cast no shadow), edge tubes and meshes,
//! ghost copies straddling a face included. It stops at the light.
//!
//! A light with a radius is a ball: each trace aims its shadow rays at
//! one point of the disc the ball shows the hit ([`aim_at_light`]), the
//! trace's `TraceSettings::light_sample`, so that the traces of a still
//! view add up to the penumbra ([`super::accumulate`]).
//!
//! WGSL twin: `shaders/shadow.wgsl` in `bevy_manifold_gpu` (the same
//! names).

use super::cull::{Candidate, each_candidate};
use super::flat::FlatScene;
use super::mesh_hit::hit_instance;
use super::nearest::instance_shown;
use super::step::{ALL_FACES, Ray, advance, hit_ball, hit_tube, may_hit, near_faces};
use super::walk::Walker;
use crate::geometry::{Geometry, Real};

/// How far off the surface a shadow ray starts, along the normal, so
/// that the surface it leaves does not shadow itself.
/// WGSL twin: `SHADOW_OFFSET` in `shaders/shadow.wgsl`.
pub const SHADOW_OFFSET: f64 = 1e-4;

/// Most faces a shadow ray crosses; past them the light is taken as seen.
/// WGSL twin: `SHADOW_LEVELS` in `shaders/shadow.wgsl`.
pub const SHADOW_LEVELS: u32 = 24;

/// The shadow ray's unit tangent and length from the hit `x` towards the
/// point `u` (in the unit square, [`super::light_sample_point`]) of the
/// disc a light of radius `radius` shows it, the light's centre lying
/// at arc length `s` along the unit tangent `dir`: `(dir, s)` itself for
/// a point light, `u = [0, 0]`, or `x` inside the light.
///
/// The disc is the cone of directions meeting the light's ball, of
/// half-angle `a` with `sin a = sin_k(radius) / sin_k(s)` (`sin_k` the
/// geometry's `r`, `sinh r`, `sin r`: the right triangle at the tangent
/// point), and it is sampled evenly in solid angle, where the light's
/// radiance is the same: `cos t = 1 - u0 (1 - cos a)` from `dir`, at the
/// angle `2 pi u1` around it. The length is the arc to the ball's near
/// surface along that direction ([`arc_to_sphere`]).
/// WGSL twin: `aim_at_light` in `shaders/shadow.wgsl`.
#[must_use]
pub fn aim_at_light<R: Real>(g: Geometry, x: R::V4, (dir, s): (R::V4, R), radius: R, u: [R; 2]) -> (R::V4, R) {
    let (zero, one) = (R::of(0.0), R::of(1.0));
    if radius <= zero || u[0] <= zero {
        return (dir, s);
    }
    let sin_a2 = g.sphere_area::<R>(radius) / g.sphere_area::<R>(s);
    if !sin_a2.is_finite() || sin_a2 >= one {
        return (dir, s);
    }
    let cos_a = (one - sin_a2).sqrt();
    let cos_t = one - u[0] * (one - cos_a);
    let sin_t = (one - cos_t * cos_t).max(zero).sqrt();
    let b = longest_perpendicular::<R>(g, x, dir, dir * zero);
    let c = longest_perpendicular::<R>(g, x, dir, b);
    let phi = R::of(std::f64::consts::TAU) * u[1];
    let out = dir * cos_t + (b * phi.cos() + c * phi.sin()) * sin_t;
    (out, arc_to_sphere::<R>(g, s, cos_t, radius))
}

/// The tangent part at `x` of the longest of the axes x, y, z once made
/// perpendicular to the unit tangent `a` and to `other` (zero, or a unit
/// tangent perpendicular to `a`), normalised: twice, a frame about `a`.
/// WGSL twin: `longest_perpendicular` in `shaders/shadow.wgsl`.
fn longest_perpendicular<R: Real>(g: Geometry, x: R::V4, a: R::V4, other: R::V4) -> R::V4 {
    let zero = R::of(0.0);
    let mut longest = (a * zero, zero);
    for e in [glam::DVec4::X, glam::DVec4::Y, glam::DVec4::Z] {
        let mut t = g.project_tangent::<R>(x, R::v4_of(e));
        t = t - a * g.form::<R>(t, a);
        t = t - other * g.form::<R>(t, other);
        let n = g.form::<R>(t, t);
        if n > longest.1 {
            longest = (t, n);
        }
    }
    longest.0 * (R::of(1.0) / longest.1.sqrt())
}

/// The arc length from a point to the near surface of a ball of radius
/// `radius` whose centre lies at arc length `s`, along a geodesic at
/// angle `t` (`cos_t`) from the centre's direction: the law of cosines
/// of the geometry solved for the nearer root. E3: `s cos t -
/// sqrt(r^2 - s^2 sin^2 t)`; S3: `cos r = cos s cos u + sin s sin u cos
/// t`; H3: `cosh r = cosh s cosh u - sinh s sinh u cos t`. For `t` 0 it
/// is `s - r` in all three.
/// WGSL twin: `arc_to_sphere` in `shaders/shadow.wgsl`.
#[must_use]
pub fn arc_to_sphere<R: Real>(g: Geometry, s: R, cos_t: R, radius: R) -> R {
    let (zero, one) = (R::of(0.0), R::of(1.0));
    match g {
        Geometry::Euclidean => {
            let sin2 = (one - cos_t * cos_t).max(zero);
            s * cos_t - (radius * radius - s * s * sin2).max(zero).sqrt()
        }
        Geometry::Spherical => {
            // A cos u + B sin u = cos r, with R cos(u - phi) the left side.
            let (a, b) = (s.cos(), s.sin() * cos_t);
            let len = (a * a + b * b).sqrt();
            let mut phi = b.atan2(a);
            if phi < zero {
                phi = phi + R::of(std::f64::consts::TAU);
            }
            let c = (radius.cos() / len).min(one);
            phi - (one - c * c).max(zero).sqrt().atan2(c)
        }
        Geometry::Hyperbolic => {
            // A cosh u - B sinh u = cosh r, with R cosh(u - phi) the left
            // side.
            let (a, b) = (s.cosh(), s.sinh() * cos_t);
            let len = (a * a - b * b).max(R::of(1e-12)).sqrt();
            let c = (radius.cosh() / len).max(one);
            (b / a).atanh() - (c * c - one).sqrt().asinh()
        }
    }
}

/// A shadow ray on its way: [`light_blocked`]'s walk, taken a segment at
/// a time ([`ShadowWalk::step`]); the GPU walks each lane's own rays
/// side by side this way. WGSL twin: `ShadowWalk` in
/// `shaders/shadow.wgsl`.
pub struct ShadowWalk<R: Real> {
    walk: Walker<R>,
    /// The distance left to the light.
    left: R,
    /// Segments walked.
    level: u32,
}

impl<R: Real> ShadowWalk<R> {
    /// The walk of the geodesic leaving the hit `x` (normal `normal`, in
    /// the cell `cell`) along the unit tangent `dir` for distance
    /// `length`, the arc to a light image. WGSL twin: `shadow_walk_new`.
    pub fn new(flat: &FlatScene<R>, (x, normal): (R::V4, R::V4), dir: R::V4, length: R, cell: R::M4) -> Self {
        let g = flat.faces.geometry;
        let offset = R::of(SHADOW_OFFSET);
        let origin = g.normalize_point::<R>(x + normal * offset);
        let ray = Ray {
            origin,
            dir: g.normalize_tangent::<R>(origin, dir),
        };
        ShadowWalk {
            walk: Walker::new(ray, cell),
            left: length - offset,
            level: 0,
        }
    }

    /// One segment of the walk: `Some(true)` when it meets an object that
    /// casts shadows, `Some(false)` when it reaches the light (or has
    /// crossed [`SHADOW_LEVELS`] faces), `None` when it goes on across
    /// the face. WGSL twin: `shadow_step`.
    pub fn step(&mut self, flat: &FlatScene<R>, cull: bool) -> Option<bool> {
        let g = flat.faces.geometry;
        if self.left <= R::of(0.0) || self.level > SHADOW_LEVELS {
            return Some(false);
        }
        let walk = &mut self.walk;
        let (face, t_end) = walk.segment_end(&flat.faces);
        let seg = g.chart_to_distance::<R>(t_end);
        let last = self.left <= seg;
        let t_stop = if last {
            g.distance_to_chart::<R>(self.left)
        } else {
            t_end
        };
        let near = if cull {
            near_faces(
                &flat.faces.planes,
                flat.faces.near_scale,
                flat.near_reach,
                &walk.ray,
                t_stop,
            )
        } else {
            ALL_FACES
        };
        let cell_point = walk.cell * R::v4_of(glam::DVec4::W);
        if segment_blocked(flat, &walk.ray, t_stop, cell_point, (near, cull)) {
            return Some(true);
        }
        if last {
            return Some(false);
        }
        let end = advance(g, &walk.ray, t_end);
        walk.step(&flat.faces, face, end, true);
        self.left = self.left - seg;
        self.level += 1;
        None
    }
}

/// True when something lies on the geodesic leaving the hit `x` (normal
/// `normal`, in the cell `cell`) along the unit tangent `dir` within
/// distance `length`, the arc to a light image: the [`ShadowWalk`] to
/// its end. The GPU takes these walks a segment at a time, each lane its
/// own (`shade` in `shaders/shade.wgsl`).
pub fn light_blocked<R: Real>(
    flat: &FlatScene<R>,
    (x, normal): (R::V4, R::V4),
    dir: R::V4,
    length: R,
    (cell, cull): (R::M4, bool),
) -> bool {
    let mut walk = ShadowWalk::new(flat, (x, normal), dir, length, cell);
    loop {
        if let Some(blocked) = walk.step(flat, cull) {
            return blocked;
        }
    }
}

/// True when the segment of `ray` up to `t_end` meets an object that
/// casts shadows. WGSL twin: `segment_blocked` in `shaders/shadow.wgsl`.
fn segment_blocked<R: Real>(
    flat: &FlatScene<R>,
    ray: &Ray<R>,
    t_end: R,
    cell_point: R::V4,
    (near, cull): (u32, bool),
) -> bool {
    let g = flat.faces.geometry;
    let zero = R::of(0.0);
    let mut blocked = false;
    each_candidate(flat, ray, t_end, ([near; 2], cull), 0.0, |c| {
        if blocked {
            return zero;
        }
        blocked = match c {
            Candidate::Ball(i) => {
                let b = &flat.balls[i];
                b.glow <= 0.0
                    && may_hit(b.face_mask, near)
                    && hit_ball(g, ray, b.center, b.k, zero).is_some_and(|t| t <= t_end)
            }
            Candidate::Tube(i) => {
                let tube = &flat.tubes[i];
                may_hit(tube.face_mask, near)
                    && hit_tube(g, ray, &tube.segment, flat.tube_k, zero).is_some_and(|t| t <= t_end)
            }
            Candidate::Instance(i) => {
                let inst = &flat.instances[i];
                instance_shown(inst, near, cell_point)
                    && hit_instance(g, flat, ray, inst, t_end).is_some_and(|h| h.t <= t_end)
            }
        };
        // Any hit blocks: once blocked, nothing further matters.
        if blocked { zero } else { t_end }
    });
    blocked
}
