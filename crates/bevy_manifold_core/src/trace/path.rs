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
use super::flat::FlatScene;
use super::nearest::Hit;
use super::settings::{MAX_PATH_DEPTH, TraceSettings};
use super::shade::{Lit, MIRROR_OFFSET, direct, surface};
use super::step::{Ray, advance_or_raw};
use super::trace::{FOG_CUT, TracePixel, nearest_object};
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
/// `travelled`; `None` when it runs out of levels or distance, or fog has
/// hidden everything further. WGSL twin: `next_hit` in
/// `shaders/path.wgsl`.
pub(super) fn next_hit<R: Real>(
    flat: &FlatScene<R>,
    walk: &mut Walker<R>,
    travelled: &mut R,
    settings: &TraceSettings,
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
    pub fn bounce(&self, g: Geometry, u: [f32; 3]) -> Option<(R::V4, [f32; 3])> {
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
        let c = self.cosines(g, l);
        let Some(p) = self.pbr else {
            return Some((l, self.albedo));
        };
        let pdf = lobe_pdf(self.pbr, c);
        if pdf <= 0.0 {
            return None;
        }
        let f = brdf(self.albedo, p, c);
        Some((l, f.map(|f| f * c.nl / (std::f32::consts::PI * pdf))))
    }

    /// The cosines of the direction `l`.
    fn cosines(&self, g: Geometry, l: R::V4) -> Cosines {
        let half = l + self.view;
        let hl = g.form::<R>(half, half).sqrt();
        let (nh, vh) = if hl.f64() > 1e-12 {
            (
                (g.form::<R>(self.normal, half) / hl).f64() as f32,
                (g.form::<R>(self.view, half) / hl).f64() as f32,
            )
        } else {
            (0.0, 0.0)
        };
        Cosines {
            nl: g.form::<R>(self.normal, l).f64() as f32,
            nv: g.form::<R>(self.normal, self.view).f64() as f32,
            nh,
            vh,
        }
    }
}

/// One sample of the rendering equation for the pixel of `ray`
/// (`pixel` its row-major index): the estimate in `color`, the first
/// leg's object, levels, cell and distance in the ids (the cell from the
/// walk's matrix). WGSL twin: `path_sample` in `shaders/path.wgsl`.
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
    let mut travelled = R::of(0.0);
    let (density, fog) = flat.fog.map_or((R::of(0.0), [0.0; 3]), |(d, c)| (d, c));
    let mut throughput = [1.0f32; 3];
    let mut radiance = [0.0f32; 3];
    let mut first: Option<TracePixel> = None;
    let cell_of = |walk: &Walker<R>| space.cell_id(&R::m4_f64(walk.cell));
    for bounce in 0..=settings.path_depth.min(MAX_PATH_DEPTH) {
        let start = travelled;
        let Some(found) = next_hit(flat, &mut walk, &mut travelled, settings) else {
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
                cell: cell_of(&walk),
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
        let lit = Lit {
            normal: s.normal,
            view: s.view,
            albedo: s.albedo,
            pbr: s.pbr,
        };
        let light = direct(g, flat, &lit, s.x, walk.cell, settings);
        for c in 0..3 {
            let emitted = s.emissive[c] + s.albedo[c] * s.glow;
            radiance[c] += throughput[c] * (emitted + light[c]);
        }
        // On along a direction the lobes draw, weighted.
        let lobes = Lobes::<R> {
            x: s.x,
            normal: s.normal,
            view: s.view,
            albedo: s.albedo,
            pbr: s.pbr,
        };
        let u = [rng.uniform(), rng.uniform(), rng.uniform()];
        let Some((l, w)) = lobes.bounce(g, u) else { break };
        for c in 0..3 {
            throughput[c] *= w[c];
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
        let origin = g.normalize_point::<R>(s.x + s.normal * R::of(MIRROR_OFFSET));
        let cell = walk.cell;
        walk = Walker::new(
            Ray {
                origin,
                dir: g.normalize_tangent::<R>(origin, l),
            },
            cell,
        );
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
