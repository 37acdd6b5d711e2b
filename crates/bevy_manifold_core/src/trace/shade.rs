//! Shading a hit: Lambert plus a Blinn lobe, or the material's GGX lobe
//! ([`crate::material::brdf`]), under each light image
//! ([`super::light_images()`]), each along its own geodesic (both arcs in
//! S3) with the fall-off of the geometry (1 / area of the geodesic
//! sphere), the light's range and the fog on its way, and only if the way
//! is free ([`super::shadow`]); per-cell colour and fog ([`shade`]); the
//! ray a surface with a material reflects ([`Mirror`]); a wall between
//! cells lit by a lamp at the eye ([`shade_wall`]).
//!
//! WGSL twin: `shaders/shade.wgsl` in `bevy_manifold_gpu` (the same
//! names).

use super::accumulate::light_sample_point;
use super::flat::FlatLight;
use super::flat::FlatScene;
use super::light_images::{image_irradiance, spot_factor};
use super::mesh_hit::{hit_uv, mesh_normal, mesh_surface};
use super::nearest::Hit;
use super::settings::TraceSettings;
use super::shadow::{aim_at_light, light_blocked};
use super::step::{Ray, foot_on_line, normal_from};
use crate::geometry::{Geometry, Real};
use crate::material::{Cosines, Pbr, brdf, reflectance};
use crate::space::cells::CellId;
use crate::space::rule::WALL_COLOR;

/// A light nearer a hit than this (`|tangent towards it|^2`) is on the hit
/// point: `toward_light` lights it along the normal.
/// WGSL twin: `LIGHT_AT_HIT` in `shaders/shade.wgsl`.
pub const LIGHT_AT_HIT: f64 = 1e-10;

/// How far off the surface a reflected ray starts (chart units along
/// the normal), so that it does not meet the surface it leaves in `f32`.
/// WGSL twin: `MIRROR_OFFSET` in `shaders/shade.wgsl`.
pub const MIRROR_OFFSET: f64 = 1e-4;

/// The roughest surface that reflects ([`Mirror`]): its lobe is narrow
/// enough that the mirror direction stands for it (at 0.4 GGX's `alpha`
/// is 0.16). A rougher one, whose reflection would be a wide blur rather
/// than an image, keeps the direct light's highlight only (the path
/// tracer takes every lobe whole). WGSL twin: `MAX_MIRROR_ROUGHNESS` in
/// `shaders/shade.wgsl`.
pub const MAX_MIRROR_ROUGHNESS: f32 = 0.4;

/// The ray a surface reflects ([`super::TraceSettings::reflections`]): from
/// just off the hit (by [`MIRROR_OFFSET`] along the normal) along the
/// mirror image of the way the eye's ray came, `2 (n.v) n - v`; the share
/// of its light that reaches the eye ([`reflectance`]); and the fog's
/// transmittance from the eye to the hit, by which the reflected ray's
/// colour (fogged over the whole way) is put back in front of the fog.
/// WGSL twin: `Mirror` and `mirror_ray` in `shaders/shade.wgsl`.
#[derive(Clone, Copy, Debug)]
pub struct Mirror<R: Real> {
    /// The reflected ray.
    pub ray: Ray<R>,
    /// Linear RGB share of its colour the eye sees.
    pub weight: [f32; 3],
    /// `exp(-density * distance)` to the hit; 1 without fog.
    pub fog_kept: f32,
}

/// The reflected ray of a surface at `x` with unit normal `normal`, seen
/// along the unit tangent `view` (towards the eye): see [`Mirror`].
/// WGSL twin: `mirror_ray` in `shaders/shade.wgsl`.
#[must_use]
pub fn mirror_ray<R: Real>(g: Geometry, x: R::V4, normal: R::V4, view: R::V4) -> Ray<R> {
    let nv = g.form::<R>(normal, view);
    let dir = normal * (nv + nv) - view;
    let origin = g.normalize_point::<R>(x + normal * R::of(MIRROR_OFFSET));
    Ray {
        origin,
        dir: g.normalize_tangent::<R>(origin, dir),
    }
}

/// The unit tangent at `x` towards the light at `l`; `normal` when the
/// light is on `x` (or, in S3, at its antipode), where the direction is
/// 0 / 0 and `normalize_tangent` would give NaN.
/// WGSL twin: `toward_light` in `shaders/shade.wgsl`.
fn toward_light<R: Real>(g: Geometry, x: R::V4, l: R::V4, normal: R::V4) -> R::V4 {
    let t = g.project_tangent::<R>(x, l);
    let len2 = g.form::<R>(t, t).abs();
    if len2.f64() > LIGHT_AT_HIT {
        t * (R::of(1.0) / len2.sqrt())
    } else {
        normal
    }
}

/// The unit tangent at the light image `l` towards `x`, for its spot's
/// cone (zero for a light in every direction, which needs none).
/// WGSL twin: `from_light` in `shaders/shade.wgsl`.
fn from_light<R: Real>(g: Geometry, l: &FlatLight<R>, x: R::V4) -> R::V4 {
    if l.spot_scale == R::of(0.0) {
        return l.spot_dir;
    }
    toward_light::<R>(g, l.position, x, l.spot_dir)
}

/// What a hit's light is worked out from.
pub(super) struct Lit<R: Real> {
    pub(super) normal: R::V4,
    pub(super) view: R::V4,
    pub(super) albedo: [f32; 3],
    /// The GGX lobe's metallic and roughness; `None`: the classic look.
    pub(super) pbr: Option<Pbr>,
}

impl<R: Real> Lit<R> {
    /// Adds to `rgb` the light of colour `color` arriving along the unit
    /// tangent `to_light` with irradiance `irradiance`: Lambert plus a
    /// Blinn lobe, or with a material the GGX lobe of [`brdf`]. WGSL twin:
    /// `add_light` in `shaders/shade.wgsl`.
    pub(super) fn add(&self, g: Geometry, rgb: &mut [f32; 3], to_light: R::V4, irradiance: f32, color: [f32; 3]) {
        let c = cosines::<R>(g, self.normal, self.view, to_light);
        let lambert = c.nl.max(0.0);
        let nh = c.nh.max(0.0);
        let Some(pbr) = self.pbr else {
            // nh is 0 where the half-vector vanishes: no highlight.
            let spec = nh.powi(32) * 0.35;
            for c in 0..3 {
                rgb[c] += (self.albedo[c] * lambert + spec) * irradiance * color[c];
            }
            return;
        };
        let f = brdf(self.albedo, pbr, Cosines { nl: lambert, nh, ..c });
        for c in 0..3 {
            rgb[c] += f[c] * lambert * irradiance * color[c];
        }
    }
}

/// The cosines of the unit tangent `l` (towards a light, or a path's next
/// direction) at a surface of unit normal `normal` seen along the unit
/// tangent `view`: `n.l`, `n.v`, and the half-vector's `n.h` and `v.h`
/// (0 where it vanishes, `l` opposite `view`). Unclamped; each user
/// clamps what it needs. WGSL twin: `cosines` in `shaders/shade.wgsl`.
pub(super) fn cosines<R: Real>(g: Geometry, normal: R::V4, view: R::V4, l: R::V4) -> Cosines {
    let half = l + view;
    let hl = g.form::<R>(half, half).sqrt();
    let (nh, vh) = if hl.f64() > 1e-12 {
        (
            (g.form::<R>(normal, half) / hl).f64() as f32,
            (g.form::<R>(view, half) / hl).f64() as f32,
        )
    } else {
        (0.0, 0.0)
    };
    Cosines {
        nl: g.form::<R>(normal, l).f64() as f32,
        nv: g.form::<R>(normal, view).f64() as f32,
        nh,
        vh,
    }
}

/// What a hit's surface is: the point, the unit tangent towards the eye,
/// the unit normal, the albedo, glow, emission and material.
/// WGSL twin: `HitSurface` in `shaders/shade.wgsl`.
pub(super) struct HitSurface<R: Real> {
    pub(super) x: R::V4,
    pub(super) view: R::V4,
    pub(super) normal: R::V4,
    pub(super) albedo: [f32; 3],
    pub(super) glow: f32,
    pub(super) emissive: [f32; 3],
    pub(super) pbr: Option<Pbr>,
}

/// The surface of `hit` at chart parameter `t` of `ray`, with the
/// object's normal there unless `normal_at` gives another (a cone's
/// layer, see [`super::cone::cone_layer`]). WGSL twin: `surface` in
/// `shaders/shade.wgsl`.
pub(super) fn surface<R: Real>(
    g: Geometry,
    flat: &FlatScene<R>,
    ray: &Ray<R>,
    (t, normal_at): (R, Option<R::V4>),
    hit: Hit<R>,
) -> HitSurface<R> {
    let x = g.normalize_point::<R>(ray.origin + ray.dir * t);
    let view = -g.normalize_tangent::<R>(x, ray.dir);
    let (normal, albedo, glow, emissive, pbr) = match hit {
        Hit::Ball(i) => {
            let b = &flat.balls[i];
            (normal_from::<R>(g, x, b.center), b.color, b.glow, [0.0; 3], b.pbr)
        }
        Hit::Tube(i) => {
            let seg = &flat.tubes[i].segment;
            (
                normal_from::<R>(g, x, foot_on_line::<R>(g, x, seg)),
                flat.tubes[i].color,
                0.0,
                [0.0; 3],
                None,
            )
        }
        Hit::Mesh(i, h) => {
            let inst = &flat.instances[i];
            let uv = hit_uv(&flat.meshes[inst.mesh], &h);
            let (albedo, emissive, pbr) = mesh_surface(flat, inst, uv);
            (
                mesh_normal(g, flat, inst, (&h, uv), x, view),
                albedo,
                0.0,
                emissive,
                pbr,
            )
        }
    };
    HitSurface {
        x,
        view,
        normal: normal_at.unwrap_or(normal),
        albedo,
        glow,
        emissive,
        pbr,
    }
}

/// The light of every light image a surface point `x` receives, each
/// along its own geodesic (both arcs in S3), with the fall-off of the
/// geometry, the light's range and the fog on its way, and only if the
/// way is free ([`super::shadow`]): the sum of [`Lit::add`] over them.
/// WGSL twin: `direct` in `shaders/shade.wgsl`.
pub(super) fn direct<R: Real>(
    g: Geometry,
    flat: &FlatScene<R>,
    lit: &Lit<R>,
    x: R::V4,
    cell_matrix: R::M4,
    settings: &TraceSettings,
) -> [f32; 3] {
    let normal = lit.normal;
    let mut rgb = [0.0f32; 3];
    if flat.lighting.images == 0 {
        for l in &flat.lights {
            let d = g.distance::<R>(x, l.position);
            let to_light = toward_light::<R>(g, x, l.position, normal);
            let area = g.sphere_area::<R>(d).max(l.min_area);
            let spot = spot_factor::<R>(g, l, from_light::<R>(g, l, x));
            lit.add(g, &mut rgb, to_light, (l.intensity * spot / area).f64() as f32, l.color);
        }
    } else {
        let density = flat.fog.map_or(R::of(0.0), |(d, _)| d);
        let tau = R::of(std::f64::consts::TAU);
        let sample = light_sample_point(settings.light_sample).map(R::of);
        for l in &flat.lights {
            let d = g.distance::<R>(x, l.position);
            let to_light = toward_light::<R>(g, x, l.position, normal);
            // The short arc, and in S3 the long way round, arriving from
            // the other side.
            let from = from_light::<R>(g, l, x);
            let arcs = [(d, to_light, from), (tau - d, -to_light, -from)];
            let count = if g == Geometry::Spherical { 2 } else { 1 };
            for &(s, dir, from) in &arcs[..count] {
                let e = image_irradiance::<R>(g, l, s, density) * spot_factor::<R>(g, l, from);
                if e <= R::of(0.0) || g.form::<R>(normal, dir) <= R::of(0.0) {
                    continue;
                }
                if flat.lighting.shadows {
                    let (aim, length) = aim_at_light::<R>(g, x, (dir, s), l.radius, sample);
                    if light_blocked(flat, (x, normal), aim, length, (cell_matrix, settings.cull)) {
                        continue;
                    }
                }
                lit.add(g, &mut rgb, dir, e.f64() as f32, l.color);
            }
        }
    }
    rgb
}

/// Lambert + Blinn (or the material's GGX) shading at the hit (chart parameter `t`, with the
/// object's normal there unless `normal_at` gives another: a cone's
/// layer, see [`super::cone::cone_layer`]), lights with geometry-correct
/// fall-off (1 / area of the sphere of radius d), per-cell colour, fog;
/// with `settings.reflections` above 0 and a material, the ray the surface
/// reflects ([`Mirror`]). WGSL twin: `shade` in `shaders/shade.wgsl`
/// (which leaves the mirror in its private `last_mirror`).
#[expect(clippy::too_many_arguments, reason = "the shading inputs are all distinct")]
pub(super) fn shade<R: Real>(
    g: Geometry,
    flat: &FlatScene<R>,
    ray: &Ray<R>,
    (t, normal_at): (R, Option<R::V4>),
    hit: Hit<R>,
    dist: R,
    (cell, cell_matrix): (CellId, R::M4),
    settings: &TraceSettings,
) -> ([f32; 3], Option<Mirror<R>>) {
    let HitSurface {
        x,
        view,
        normal,
        albedo,
        glow,
        emissive,
        pbr,
    } = surface(g, flat, ray, (t, normal_at), hit);
    let mut albedo = albedo;
    if settings.cell_colors {
        let c = settings.cell_tint.tint(cell);
        albedo = [albedo[0] * c[0], albedo[1] * c[1], albedo[2] * c[2]];
    }
    // Ambient light, the object's own glow and its emission.
    let ambient = 0.08f32 + glow;
    let mut rgb = [0, 1, 2].map(|c| albedo[c] * ambient + emissive[c]);
    let lit = Lit::<R> {
        normal,
        view,
        albedo,
        pbr,
    };
    let direct = direct(g, flat, &lit, x, cell_matrix, settings);
    for c in 0..3 {
        rgb[c] += direct[c];
    }
    let mut fog_kept = 1.0;
    if let Some((density, fog_color)) = flat.fog {
        let tr = (-(density * dist)).exp().f64() as f32;
        for c in 0..3 {
            rgb[c] = rgb[c] * tr + fog_color[c] * (1.0 - tr);
        }
        fog_kept = tr;
    }
    let mirror = match pbr {
        Some(p) if settings.reflections > 0 && p.roughness <= MAX_MIRROR_ROUGHNESS => Some(Mirror {
            ray: mirror_ray::<R>(g, x, normal, view),
            weight: reflectance(albedo, p, g.form::<R>(normal, view).f64() as f32),
            fog_kept,
        }),
        _ => None,
    };
    (rgb, mirror)
}

/// A wall on face `plane`, met at distance `dist`: [`WALL_COLOR`] lit by
/// the angle the ray meets it at (a lamp at the eye), then fog.
/// WGSL twin: `shade_wall` in `shaders/shade.wgsl`.
pub(super) fn shade_wall<R: Real>(flat: &FlatScene<R>, plane: &R::V4, ray: &Ray<R>, dist: R) -> [f32; 3] {
    let n = R::dot4(*plane, *plane).sqrt();
    let facing = (R::dot4(*plane, ray.dir) / (n * R::dot4(ray.dir, ray.dir).sqrt()))
        .f64()
        .abs()
        .min(1.0) as f32;
    let lit = 0.3 + 0.7 * facing;
    let rgb = WALL_COLOR.map(|c| c * lit);
    match flat.fog {
        Some((density, fog)) => {
            let keep = (-(density * dist).f64()).exp() as f32;
            [0, 1, 2].map(|i| rgb[i] * keep + fog[i] * (1.0 - keep))
        }
        None => rgb,
    }
}
