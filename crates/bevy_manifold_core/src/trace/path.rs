//! The path tracer: an unbiased Monte Carlo estimate of the rendering
//! equation in the manifold, one path per pixel and sample
//! ([`TraceSettings::path_depth`]). From the camera, each leg of the path
//! walks through the faces like a camera ray (`next_hit`); at the
//! surface it meets it adds the surface's emission and the light of
//! every light image reaching it through the faces (next-event
//! estimation, [`super::shade`]'s `direct`, shadows included), then goes
//! on in a direction drawn from the surface's lobes (Lambert, and the GGX
//! lobe of a material: [`Lobes::bounce`]), weighted by the BRDF over the
//! mixture's density. Russian roulette ends long paths without bias; fog
//! is a medium that absorbs and glows (the fog colour), so a path
//! converges to what the direct tracer's fog shows.
//!
//! Every random number comes from [`PathRng`], a hash of the seed, the
//! sample index and the pixel: the same path on every run, on the CPU and
//! the GPU alike.
//!
//! In the tracer's units Lambert's BRDF is `albedo` (not `albedo / pi`)
//! and [`crate::material::brdf`] is `pi` times the BRDF; a path's weight
//! after a bounce is `brdf cos / (pi pdf)`. A surface without a material
//! is Lambert for the paths it sends on (its lights keep the classic
//! highlight), and the scene's ambient term is left out: the path's own
//! light replaces it.
//!
//! WGSL twin: `shaders/path.wgsl` in `bevy_manifold_gpu` (the same names).
//!
//! ```
//! use bevy_manifold_core::prelude::*;
//! let space = catalog::torus(1.0);
//! let scene = Scene::default_for(&space);
//! let settings = TraceSettings { width: 8, height: 8, path_depth: 4, ..TraceSettings::default() };
//! let img = render::<f32>(&space, &scene, &settings);
//! assert!(img.pixels.iter().all(|p| p.color.iter().all(|c| c.is_finite() && *c >= 0.0)));
//! ```

use super::cone::SegmentReach;
use super::exact_cell::{ExactCell, TableRef};
use super::flat::{FlatBall, FlatScene};
use super::nearest::Hit;
use super::settings::{MAX_PATH_DEPTH, TraceSettings};
use super::shade::{HitSurface, Lit, MIRROR_OFFSET, cosines, direct, surface};
use super::step::{Ray, advance_or_raw};
use super::trace::{FOG_CUT, MAX_EXACT_LEVELS, TracePixel, nearest_object};
use super::walk::Walker;
use crate::geometry::{Geometry, Real};
use crate::material::{Cosines, MIN_ROUGHNESS, Pbr, brdf};
use crate::space::Space;
use crate::space::cells::CellId;

/// Bounces after which Russian roulette may end a path.
/// WGSL twin: `ROULETTE_AFTER` in `shaders/path.wgsl`.
pub const ROULETTE_AFTER: u32 = 3;

/// The PCG hash of Jarzynski and Olano ("Hash Functions for GPU
/// Rendering", JCGT 2020): a 32-bit permutation whose output bits all
/// depend on every input bit. WGSL twin: `pcg` in `shaders/path.wgsl`.
#[must_use]
pub fn pcg(v: u32) -> u32 {
    let state = v.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// The random numbers of one path: a state hashed from the seed, the
/// sample index and the pixel, hashed again for each number.
/// WGSL twin: `rng_new` and `rng_uniform` in `shaders/path.wgsl`.
#[derive(Clone, Copy, Debug)]
pub struct PathRng(pub u32);

impl PathRng {
    /// The stream of `pixel` (row-major index) in sample `sample` of the
    /// seed `seed`.
    #[must_use]
    pub fn new(seed: u32, sample: u32, pixel: u32) -> Self {
        PathRng(pcg(pixel ^ pcg(sample ^ pcg(seed))))
    }

    /// The next number, uniform in `[0, 1)` (24 bits).
    pub fn uniform(&mut self) -> f32 {
        self.0 = pcg(self.0);
        (self.0 >> 8) as f32 * (1.0 / 16_777_216.0)
    }
}

/// Where a leg of a path ends: the object and its chart parameter on the
/// walk's ray. WGSL twin: the private `found` in `shaders/path.wgsl`.
pub(super) struct Found<R: Real> {
    t: R,
    hit: Hit<R>,
}

/// Walks `walk` through the faces to the first object it meets
/// (Algorithm 1 without the shading), adding the distance to
/// `travelled` and telling `on_cross` each face it crosses (with the
/// walk's levels after it); `None` when it runs out of levels or
/// distance, or fog has hidden everything further. WGSL twin: `next_hit`
/// in `shaders/path.wgsl` (where the walker's table index follows the
/// crossings itself).
pub(super) fn next_hit<R: Real>(
    flat: &FlatScene<R>,
    walk: &mut Walker<R>,
    travelled: &mut R,
    settings: &TraceSettings,
    on_cross: &mut dyn FnMut(usize, u32),
) -> Option<Found<R>> {
    let g = flat.faces.geometry;
    let max_passes = settings.levels as usize + settings.max_distance.min(1e4) as usize + 2;
    for _ in 0..max_passes {
        if let Some((density, _)) = flat.fog
            && settings.fog_early_stop
            && density * *travelled > R::of(FOG_CUT)
        {
            return None;
        }
        let (face, t_end) = walk.segment_end(&flat.faces);
        let cell_point = walk.cell * R::v4_of(glam::DVec4::W);
        let reach = SegmentReach::new(flat, settings, None, *travelled, (&walk.ray, t_end));
        let met = nearest_object(g, flat, &walk.ray, t_end, cell_point, (reach.near[0], settings.cull));
        if let Some((t, hit, _)) = met.whole {
            return Some(Found { t, hit });
        }
        let end = advance_or_raw(g, &walk.ray, t_end, settings.renormalize);
        *travelled = *travelled + g.chart_to_distance::<R>(t_end);
        if travelled.f64() > settings.max_distance || (face.is_some() && walk.levels >= settings.levels) {
            return None;
        }
        walk.step(&flat.faces, face, end, settings.renormalize);
        if let Some(f) = face {
            on_cross(f, walk.levels);
        }
    }
    None
}

/// Two unit tangents at `x` orthogonal to the unit normal `n` and to
/// each other (in the geometry's form): a frame for sampling directions
/// about `n`. WGSL twin: `tangent_frame` in `shaders/path.wgsl`.
#[must_use]
pub fn tangent_frame<R: Real>(g: Geometry, x: R::V4, n: R::V4) -> (R::V4, R::V4) {
    let axes = [glam::DVec4::X, glam::DVec4::Y, glam::DVec4::Z];
    // The two chart axes least along the normal, as tangents at x.
    let along = |a: &glam::DVec4| R::dot4(R::v4_of(*a), n).f64().abs();
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| along(&axes[a]).total_cmp(&along(&axes[b])));
    let orthogonal = |v: R::V4, against: &[R::V4]| {
        let mut t = g.project_tangent::<R>(x, v);
        for &u in against {
            t = t - u * g.form::<R>(t, u);
        }
        t * (R::of(1.0) / g.form::<R>(t, t).abs().sqrt())
    };
    let t1 = orthogonal(R::v4_of(axes[order[0]]), &[n]);
    let t2 = orthogonal(R::v4_of(axes[order[1]]), &[n, t1]);
    (t1, t2)
}

/// The share of paths a surface sends along its GGX lobe (the rest along
/// Lambert's): none without a material, all of a metal's.
/// WGSL twin: `specular_share` in `shaders/path.wgsl`.
#[must_use]
pub fn specular_share(pbr: Option<Pbr>) -> f32 {
    pbr.map_or(0.0, |p| 0.2 + 0.8 * p.metallic)
}

/// GGX's `alpha^2` for a perceptual roughness (clamped as the BRDF
/// clamps it).
fn alpha2(roughness: f32) -> f32 {
    let r = roughness.max(MIN_ROUGHNESS);
    (r * r) * (r * r)
}

/// The density (per unit solid angle) of the lobe mixture at the
/// cosines `c`: `(1 - s) nl / pi + s D(nh) nh / (4 vh)`, `s` the
/// specular share. WGSL twin: `lobe_pdf` in `shaders/path.wgsl`.
#[must_use]
pub fn lobe_pdf(pbr: Option<Pbr>, c: Cosines) -> f32 {
    let s = specular_share(pbr);
    let pi = std::f32::consts::PI;
    let diffuse = (1.0 - s) * c.nl.max(0.0) / pi;
    let Some(p) = pbr else { return diffuse };
    let a2 = alpha2(p.roughness);
    let nh = c.nh.clamp(0.0, 1.0);
    let k = nh * nh * (a2 - 1.0) + 1.0;
    let d = a2 / (pi * k * k);
    diffuse + s * d * nh / (4.0 * c.vh.max(1e-6))
}

/// A surface point as the lobes see it: the point, the unit normal, the
/// unit tangent towards the eye, the albedo and the material (`None`:
/// Lambert).
#[derive(Clone, Copy, Debug)]
pub struct Lobes<R: Real> {
    /// The point.
    pub x: R::V4,
    /// The unit normal (on the eye's side).
    pub normal: R::V4,
    /// The unit tangent towards where the path came from.
    pub view: R::V4,
    /// Linear RGB albedo.
    pub albedo: [f32; 3],
    /// Metallic and roughness; `None`: Lambert alone.
    pub pbr: Option<Pbr>,
}

/// A direction a surface's lobes drew ([`Lobes::bounce`]): the unit
/// tangent, the path's weight along it (`brdf cos / (pi pdf)` per
/// channel) and the mixture's density `pdf` there (per unit solid
/// angle), which multiple importance sampling weighs against the
/// emitters'. WGSL twin: `Bounce` in `shaders/path.wgsl`.
#[derive(Clone, Copy, Debug)]
pub struct Bounce<R: Real> {
    /// The unit tangent the path goes on along.
    pub dir: R::V4,
    /// The path's weight along it, per channel.
    pub weight: [f32; 3],
    /// The lobe mixture's density at `dir` ([`lobe_pdf`]).
    pub pdf: f32,
}

impl<R: Real> Lobes<R> {
    /// A direction drawn from the lobes with the numbers `u`, and the
    /// path's weight along it: with probability [`specular_share`] a GGX
    /// half-vector (density `D(h) cos`, Walter et al. 2007) and the view
    /// mirrored about it, else a cosine-weighted direction about the
    /// normal; the weight `brdf cos / (pi pdf)` per channel, `pdf` the
    /// mixture's ([`lobe_pdf`]; Lambert's `albedo` without a material).
    /// `None` when the direction falls below the surface. WGSL twin:
    /// `bounce` in `shaders/path.wgsl`.
    #[must_use]
    pub fn bounce(&self, g: Geometry, u: [f32; 3]) -> Option<Bounce<R>> {
        let (t1, t2) = tangent_frame::<R>(g, self.x, self.normal);
        let along = |cos: f32, phi: f32| {
            let sin = (1.0 - cos * cos).max(0.0).sqrt();
            t1 * R::of(f64::from(sin * phi.cos()))
                + t2 * R::of(f64::from(sin * phi.sin()))
                + self.normal * R::of(f64::from(cos))
        };
        let phi = std::f32::consts::TAU * u[2];
        let l = if u[0] < specular_share(self.pbr) {
            let a2 = alpha2(self.pbr.map_or(1.0, |p| p.roughness));
            let cos_h = ((1.0 - u[1]) / (1.0 + (a2 - 1.0) * u[1])).max(0.0).sqrt();
            let h = along(cos_h, phi);
            let vh = g.form::<R>(self.view, h);
            h * (vh + vh) - self.view
        } else {
            along(u[1].sqrt(), phi)
        };
        if g.form::<R>(self.normal, l) <= R::of(0.0) {
            return None;
        }
        let c = cosines::<R>(g, self.normal, self.view, l);
        let pdf = lobe_pdf(self.pbr, c);
        if pdf <= 0.0 {
            return None;
        }
        Some(Bounce {
            dir: l,
            weight: self.weight(c, pdf),
            pdf,
        })
    }

    /// The path's weight along a direction of cosines `c` drawn with
    /// density `pdf`: `brdf cos / (pi pdf)`, or for Lambert alone drawn
    /// by its own cosine density, `albedo`.
    /// WGSL twin: `lobe_weight` in `shaders/path.wgsl`.
    fn weight(&self, c: Cosines, pdf: f32) -> [f32; 3] {
        let Some(p) = self.pbr else {
            return self.albedo.map(|a| a * c.nl / (std::f32::consts::PI * pdf));
        };
        let f = brdf(self.albedo, p, c);
        f.map(|f| f * c.nl / (std::f32::consts::PI * pdf))
    }
}

/// True for a ball the path tracer aims at as a light (next-event
/// estimation): one that glows.
/// WGSL twin: `is_emitter` in `shaders/path.wgsl`.
fn is_emitter<R: Real>(b: &FlatBall<R>) -> bool {
    b.glow > 0.0 && b.color.iter().any(|&c| c > 0.0)
}

/// The cone of directions at `x` that meet the ball `b`: the unit
/// tangent towards its centre and the cosine of the half-angle `a`,
/// `sin a = sin_k(r) / sin_k(s)` for a centre at arc length `s` (the
/// right triangle at the tangent point, as for a light's disc). `None`
/// when `x` is inside the ball (or, in S3, inside its antipodal image).
/// WGSL twin: `emitter_cone` in `shaders/path.wgsl`.
fn emitter_cone<R: Real>(g: Geometry, b: &FlatBall<R>, x: R::V4) -> Option<(R::V4, f32)> {
    let s = g.distance::<R>(x, b.center);
    // sin_k(r)^2 from the ball's k: r^2, cos r or cosh r.
    let sin_r2 = match g {
        Geometry::Euclidean => b.k,
        Geometry::Spherical => R::of(1.0) - b.k * b.k,
        Geometry::Hyperbolic => b.k * b.k - R::of(1.0),
    };
    let sin_a2 = (sin_r2 * R::of(4.0 * std::f64::consts::PI) / g.sphere_area::<R>(s)).f64();
    if sin_a2.is_nan() || sin_a2 >= 1.0 {
        return None;
    }
    let t = g.project_tangent::<R>(x, b.center);
    let len2 = g.form::<R>(t, t).abs();
    if len2.f64().is_nan() || len2.f64() <= 1e-12 {
        return None;
    }
    Some((t * (R::of(1.0) / len2.sqrt()), (1.0 - sin_a2).sqrt() as f32))
}

/// The density (per unit solid angle) with which [`aim_at_emitter`]
/// draws the unit tangent `l` at `x`: the mean over the `count` emitters
/// of their cones' even densities `1 / (2 pi (1 - cos a))`, the cone of
/// the emitter `drawn` (its index among the balls) counted whatever the
/// rounding says. WGSL twin: `emitter_pdf` in `shaders/path.wgsl`.
fn emitter_pdf<R: Real>(g: Geometry, flat: &FlatScene<R>, x: R::V4, l: R::V4, count: u32, drawn: usize) -> f32 {
    let mut sum = 0.0f32;
    for (i, b) in flat.balls.iter().enumerate() {
        if !is_emitter(b) {
            continue;
        }
        let Some((dir, cos_a)) = emitter_cone::<R>(g, b, x) else {
            continue;
        };
        if i == drawn || g.form::<R>(l, dir).f64() as f32 >= cos_a {
            sum += 1.0 / (std::f32::consts::TAU * (1.0 - cos_a).max(1e-7));
        }
    }
    sum / count.max(1) as f32
}

/// A direction at `x` towards one of the `count` emitters, drawn with the
/// numbers `u`: the emitter `floor(u0 count)`, then a direction of its
/// cone, evenly in solid angle (`cos t = 1 - u1 (1 - cos a)`, at the
/// angle `2 pi u2` about the centre's direction); with the density
/// [`emitter_pdf`] of drawing it. `None` when `x` is inside that
/// emitter. WGSL twin: `aim_at_emitter` in `shaders/path.wgsl`.
fn aim_at_emitter<R: Real>(
    g: Geometry,
    flat: &FlatScene<R>,
    x: R::V4,
    count: u32,
    u: [f32; 3],
) -> Option<(R::V4, f32)> {
    let k = ((u[0] * count as f32) as u32).min(count.saturating_sub(1));
    let (drawn, b) = flat
        .balls
        .iter()
        .enumerate()
        .filter(|(_, b)| is_emitter(b))
        .nth(k as usize)?;
    let (dir, cos_a) = emitter_cone::<R>(g, b, x)?;
    let cos_t = 1.0 - u[1] * (1.0 - cos_a);
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    let phi = std::f32::consts::TAU * u[2];
    let (t1, t2) = tangent_frame::<R>(g, x, dir);
    let l = dir * R::of(f64::from(cos_t))
        + t1 * R::of(f64::from(sin_t * phi.cos()))
        + t2 * R::of(f64::from(sin_t * phi.sin()));
    let l = g.normalize_tangent::<R>(x, l);
    Some((l, emitter_pdf::<R>(g, flat, x, l, count, drawn)))
}

/// The power heuristic (Veach 1997, beta 2): the weight of a strategy of
/// density `a` against one of density `b` for the same direction.
/// WGSL twin: `power_heuristic` in `shaders/path.wgsl`.
#[must_use]
pub fn power_heuristic(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 > 0.0 { a2 / (a2 + b2) } else { 0.0 }
}

/// What a surface gives off: its emission and its glow.
fn emitted<R: Real>(s: &HitSurface<R>) -> [f32; 3] {
    [0, 1, 2].map(|c| s.emissive[c] + s.albedo[c] * s.glow)
}

/// Where a path left a surface, for multiple importance sampling of the
/// emitter its next leg may meet: the point, the unit tangent it left
/// along and the lobes' density there.
struct Left<R: Real> {
    x: R::V4,
    dir: R::V4,
    pdf: f32,
}

/// The walk of a leg leaving `x` (normal `normal`) along the unit tangent
/// `dir`, in the copy `cell` (table index kept by the GPU twin, whose
/// walker also carries the distance travelled).
fn leave<R: Real>(g: Geometry, (x, normal): (R::V4, R::V4), dir: R::V4, cell: R::M4) -> Walker<R> {
    let origin = g.normalize_point::<R>(x + normal * R::of(MIRROR_OFFSET));
    Walker::new(
        Ray {
            origin,
            dir: g.normalize_tangent::<R>(origin, dir),
        },
        cell,
    )
}

/// One sample of the rendering equation for the pixel of `ray`
/// (`pixel` its row-major index): the estimate in `color`, the first
/// leg's object, levels, cell and distance in the ids (the cell as the
/// direct tracer names it: by the table around the camera, then by exact
/// elements, where the space has them).
///
/// At each surface the light of the glowing balls is taken twice and
/// weighed by the power heuristic (multiple importance sampling): a
/// direction towards one of them ([`aim_at_emitter`]) walked through
/// the faces to what it meets, and the lobes' own next direction when it
/// meets something that glows. Emission a path meets right after the
/// camera, and what meshes give off, count in full.
/// WGSL twin: `path_sample` in `shaders/path.wgsl`.
#[must_use]
pub fn path_sample<R: Real>(
    space: &Space,
    flat: &FlatScene<R>,
    ray: Ray<R>,
    settings: &TraceSettings,
    pixel: u32,
) -> TracePixel {
    let g = flat.faces.geometry;
    let mut rng = PathRng::new(settings.seed, settings.light_sample, pixel);
    let mut walk = Walker::new(ray, R::m4_of(flat.camera_cell));
    let table = TableRef::of(space, flat);
    let mut exact = ExactCell::start(table, flat, false);
    let mut travelled = R::of(0.0);
    let (density, fog) = flat.fog.map_or((R::of(0.0), [0.0; 3]), |(d, c)| (d, c));
    let emitters = flat.balls.iter().filter(|b| is_emitter(b)).count() as u32;
    let mut throughput = [1.0f32; 3];
    let mut radiance = [0.0f32; 3];
    let mut first: Option<TracePixel> = None;
    let mut left: Option<Left<R>> = None;
    for bounce in 0..=settings.path_depth.min(MAX_PATH_DEPTH) {
        let start = travelled;
        let found = if bounce == 0 {
            next_hit(flat, &mut walk, &mut travelled, settings, &mut |f, levels| {
                if levels > MAX_EXACT_LEVELS {
                    exact = ExactCell::Off;
                } else if !exact.is_off() {
                    exact = exact.crossed(table, space, flat, f);
                }
            })
        } else {
            next_hit(flat, &mut walk, &mut travelled, settings, &mut |_, _| {})
        };
        let Some(found) = found else {
            // Nothing met: the fog's colour (black without fog), as the
            // direct tracer's background.
            for c in 0..3 {
                radiance[c] += throughput[c] * fog[c];
            }
            break;
        };
        let dist = travelled + g.chart_to_distance::<R>(found.t);
        if first.is_none() {
            first = Some(TracePixel {
                color: [0.0; 3],
                object: found.hit.id(flat),
                levels: walk.levels,
                cell: exact.id(table, space, &walk),
                distance: dist.f64() as f32,
            });
        }
        // The fog on the leg: it glows by what it takes.
        let kept = (-(density * (dist - start))).exp().f64() as f32;
        for c in 0..3 {
            radiance[c] += throughput[c] * fog[c] * (1.0 - kept);
            throughput[c] *= kept;
        }
        let s = surface(g, flat, &walk.ray, (found.t, None), found.hit);
        // What it gives off, weighed against the emitters' aim when the
        // lobes of the last surface drew this way.
        let mis = match &left {
            Some(l) if emitters > 0 => {
                power_heuristic(l.pdf, emitter_pdf::<R>(g, flat, l.x, l.dir, emitters, usize::MAX))
            }
            _ => 1.0,
        };
        let lit = Lit {
            normal: s.normal,
            view: s.view,
            albedo: s.albedo,
            pbr: s.pbr,
        };
        let light = direct(g, flat, &lit, s.x, walk.cell, settings);
        let glow = emitted(&s);
        for c in 0..3 {
            radiance[c] += throughput[c] * (glow[c] * mis + light[c]);
        }
        let lobes = Lobes::<R> {
            x: s.x,
            normal: s.normal,
            view: s.view,
            albedo: s.albedo,
            pbr: s.pbr,
        };
        // Next-event estimation towards the glowing balls.
        let u = [rng.uniform(), rng.uniform(), rng.uniform()];
        if emitters > 0
            && let Some((l, p_light)) = aim_at_emitter::<R>(g, flat, s.x, emitters, u)
        {
            let c = cosines::<R>(g, s.normal, s.view, l);
            if c.nl > 0.0 {
                let w = lobes.weight(c, p_light);
                let mis = power_heuristic(p_light, lobe_pdf(s.pbr, c));
                let mut aim = leave(g, (s.x, s.normal), l, walk.cell);
                let mut to = dist;
                if let Some(hit) = next_hit(flat, &mut aim, &mut to, settings, &mut |_, _| {}) {
                    let there = surface(g, flat, &aim.ray, (hit.t, None), hit.hit);
                    let far = to + g.chart_to_distance::<R>(hit.t);
                    let through = (-(density * (far - dist))).exp().f64() as f32;
                    let e = emitted(&there);
                    for c in 0..3 {
                        radiance[c] += throughput[c] * w[c] * mis * through * e[c];
                    }
                }
            }
        }
        // On along a direction the lobes draw, weighted.
        let u = [rng.uniform(), rng.uniform(), rng.uniform()];
        let Some(next) = lobes.bounce(g, u) else { break };
        for (t, w) in throughput.iter_mut().zip(next.weight) {
            *t *= w;
        }
        if bounce >= ROULETTE_AFTER {
            let keep = throughput.iter().fold(0.0f32, |m, &t| m.max(t)).min(0.95);
            if rng.uniform() >= keep {
                break;
            }
            for t in &mut throughput {
                *t /= keep;
            }
        }
        if throughput.iter().all(|&t| t <= 0.0) {
            break;
        }
        left = Some(Left {
            x: s.x,
            dir: next.dir,
            pdf: next.pdf,
        });
        walk = leave(g, (s.x, s.normal), next.dir, walk.cell);
        travelled = dist;
    }
    let mut pixel = first.unwrap_or(TracePixel {
        color: [0.0; 3],
        object: 0,
        levels: walk.levels,
        cell: CellId::BEYOND_TABLE,
        distance: travelled.f64() as f32,
    });
    pixel.color = radiance;
    pixel
}
