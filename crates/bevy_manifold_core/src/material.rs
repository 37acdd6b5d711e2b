//! What a surface is made of: base colour and its texture, metallic and
//! perceptual roughness (the GGX microfacet lobe of Bevy's PBR), emission,
//! a normal map and an alpha mask, as glTF and Bevy's `StandardMaterial`
//! describe them; and the BRDF both tracers shade with ([`brdf`], WGSL
//! twin `brdf` in `bevy_manifold_gpu`'s `shaders/shade.wgsl`).
//!
//! A surface without [`Pbr`] keeps the tracer's classic look (Lambert plus
//! a fixed Blinn lobe), so scenes made before materials look as they did.
//!
//! ```
//! use bevy_manifold_core::material::{MeshMaterial, Pbr};
//! // A brushed gold: metallic, fairly smooth, glowing a little.
//! let gold = MeshMaterial {
//!     base_color: [1.0, 0.77, 0.34],
//!     pbr: Some(Pbr { metallic: 1.0, roughness: 0.3 }),
//!     emissive: [0.1, 0.05, 0.0],
//!     ..MeshMaterial::default()
//! };
//! assert!(gold.check().is_ok());
//! ```

use crate::mesh::Texture;
use std::sync::Arc;

/// The least perceptual roughness shaded (Bevy clamps to the same): a
/// smaller one makes the GGX peak a spike no pixel samples.
pub const MIN_ROUGHNESS: f32 = 0.089;

/// Reflectance at normal incidence of a dielectric: 0.04, Bevy's
/// `StandardMaterial::reflectance` 0.5 (`0.16 r^2`).
pub const DIELECTRIC_F0: f32 = 0.04;

/// Metallic and perceptual roughness: a surface shaded by the GGX lobe
/// (as Bevy's `StandardMaterial`, glTF's metallic-roughness model).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pbr {
    /// 0 for a dielectric (plastic, stone), 1 for a metal; in between
    /// blends them.
    pub metallic: f32,
    /// Perceptual roughness, 0 (mirror-like) to 1 (chalk); squared, it is
    /// GGX's `alpha`. Shaded no smoother than [`MIN_ROUGHNESS`].
    pub roughness: f32,
}

impl Default for Pbr {
    /// Bevy's `StandardMaterial` defaults: a dielectric of roughness 0.5.
    fn default() -> Self {
        Pbr {
            metallic: 0.0,
            roughness: 0.5,
        }
    }
}

impl Pbr {
    /// Both in `[0, 1]` (and not NaN).
    #[must_use]
    pub fn is_valid(&self) -> bool {
        (0.0..=1.0).contains(&self.metallic) && (0.0..=1.0).contains(&self.roughness)
    }
}

/// A mesh's surface: base colour (linear RGB) and texture, the GGX lobe's
/// metallic and roughness (and their texture), emission (and its
/// texture), a normal map and an alpha mask.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshMaterial {
    /// Base colour factor, linear RGB.
    pub base_color: [f32; 3],
    /// Base colour texture (sRGB, alpha in `a`), multiplied in.
    pub texture: Option<Arc<Texture>>,
    /// Base alpha factor: multiplies the texture's alpha for the mask.
    pub alpha: f32,
    /// Alpha mask: where alpha is below this the surface is not there
    /// (rays and shadows go through); `None`: opaque.
    pub alpha_cutoff: Option<f32>,
    /// Metallic and roughness; `None`: the classic Lambert + Blinn look.
    pub pbr: Option<Pbr>,
    /// glTF's metallic-roughness texture (linear; blue is metallic, green
    /// roughness), multiplying [`MeshMaterial::pbr`]'s factors.
    pub metallic_roughness: Option<Arc<Texture>>,
    /// Light given off, linear RGB radiance (glTF's emissive factor times
    /// `KHR_materials_emissive_strength`; Bevy's `emissive`). It lights
    /// nothing else in the direct lighting.
    pub emissive: [f32; 3],
    /// Emissive texture (sRGB), multiplying [`MeshMaterial::emissive`].
    pub emissive_texture: Option<Arc<Texture>>,
    /// Tangent-space normal map (linear, `xyz = 2 rgb - 1`), the tangent
    /// frame from the triangle's texture coordinates.
    pub normal_map: Option<Arc<Texture>>,
}

impl Default for MeshMaterial {
    fn default() -> Self {
        MeshMaterial {
            base_color: [0.8; 3],
            texture: None,
            alpha: 1.0,
            alpha_cutoff: None,
            pbr: None,
            metallic_roughness: None,
            emissive: [0.0; 3],
            emissive_texture: None,
            normal_map: None,
        }
    }
}

/// The most emitted radiance a material or ball may give, per channel
/// (bright enough for bloom, not so bright that f32 sums overflow).
pub const MAX_EMISSIVE: f32 = 1.0e4;

impl MeshMaterial {
    /// The material with only a base colour (classic look).
    #[must_use]
    pub fn colored(base_color: [f32; 3]) -> Self {
        MeshMaterial {
            base_color,
            ..MeshMaterial::default()
        }
    }

    /// The material of Bevy's `StandardMaterial::from_color`: the base
    /// colour with Bevy's default surface (a dielectric of roughness 0.5,
    /// [`Pbr::default`]). The paper's models wear it, as their entities
    /// do in a Bevy app.
    #[must_use]
    pub fn standard(base_color: [f32; 3]) -> Self {
        MeshMaterial {
            base_color,
            pbr: Some(Pbr::default()),
            ..MeshMaterial::default()
        }
    }

    /// Checks every factor: colours finite and non-negative, alpha and
    /// the cutoff in `[0, 1]`, metallic and roughness in `[0, 1]`,
    /// emission at most [`MAX_EMISSIVE`].
    ///
    /// # Errors
    /// The first field out of range, named as a file would name it.
    pub fn check(&self) -> Result<(), String> {
        if !self.base_color.iter().all(|c| c.is_finite() && *c >= 0.0) {
            return Err(format!(
                "color {:?} is not a finite non-negative colour",
                self.base_color
            ));
        }
        if !(0.0..=1.0).contains(&self.alpha) {
            return Err(format!("alpha {} is not in [0, 1]", self.alpha));
        }
        if let Some(c) = self.alpha_cutoff
            && !(0.0..=1.0).contains(&c)
        {
            return Err(format!("alpha_cutoff {c} is not in [0, 1]"));
        }
        if let Some(p) = self.pbr
            && !p.is_valid()
        {
            return Err(format!(
                "metallic {} / roughness {} are not in [0, 1]",
                p.metallic, p.roughness
            ));
        }
        if !self.emissive.iter().all(|c| (0.0..=MAX_EMISSIVE).contains(c)) {
            return Err(format!(
                "emission {:?} is not in [0, {MAX_EMISSIVE}] per channel",
                self.emissive
            ));
        }
        Ok(())
    }
}

/// What one light does at a surface point: the unit-free cosines of the
/// normal `n`, the way to the light `l`, the way to the eye `v` and their
/// half-vector `h`, all measured by the geometry's form in the tangent
/// space at the hit (so the same formula serves E3, H3 and S3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cosines {
    /// `n . l`, positive (the light is in front).
    pub nl: f32,
    /// `n . v`.
    pub nv: f32,
    /// `n . h`.
    pub nh: f32,
    /// `v . h` (= `l . h`).
    pub vh: f32,
}

/// The reflected radiance per unit irradiance (from a light straight
/// above) of a PBR surface of base colour `albedo`: a Lambert diffuse of
/// `albedo (1 - metallic)` plus the GGX specular lobe `pi D V F`, with D
/// the Trowbridge-Reitz distribution of `alpha = roughness^2`, V the
/// height-correlated Smith visibility and F Schlick's Fresnel from
/// `F0 = mix(0.04, albedo, metallic)` (the terms of Bevy's `pbr_lighting`,
/// with its Burley diffuse taken as Lambert). Multiply by `n . l` and the
/// irradiance. The `pi` keeps the tracer's scale, where Lambert is
/// `albedo` rather than `albedo / pi`. WGSL twin: `brdf` in
/// `shaders/shade.wgsl`.
///
/// ```
/// use bevy_manifold_core::material::{Cosines, Pbr, brdf};
/// // Roughness 1 makes GGX uniform (D = 1 / pi); lit and seen head on,
/// // V = 1/4 and F = F0: a white metal returns 1/4 of the light.
/// let head_on = Cosines { nl: 1.0, nv: 1.0, nh: 1.0, vh: 1.0 };
/// let r = brdf([1.0; 3], Pbr { metallic: 1.0, roughness: 1.0 }, head_on);
/// assert!((r[0] - 0.25).abs() < 1e-6);
/// ```
#[must_use]
pub fn brdf(albedo: [f32; 3], pbr: Pbr, c: Cosines) -> [f32; 3] {
    let r = pbr.roughness.max(MIN_ROUGHNESS);
    let a2 = (r * r) * (r * r);
    let nl = c.nl.max(0.0);
    let nv = c.nv.max(1e-4);
    let nh = c.nh.clamp(0.0, 1.0);
    let k = nh * nh * (a2 - 1.0) + 1.0;
    let d = a2 / (std::f32::consts::PI * k * k);
    let vis = 0.5 / (nl * (nv * nv * (1.0 - a2) + a2).sqrt() + nv * (nl * nl * (1.0 - a2) + a2).sqrt());
    let fresnel = (1.0 - c.vh.clamp(0.0, 1.0)).powi(5);
    let m = pbr.metallic;
    let mut out = [0.0; 3];
    for i in 0..3 {
        let f0 = DIELECTRIC_F0 * (1.0 - m) + albedo[i] * m;
        let f = f0 + (1.0 - f0) * fresnel;
        out[i] = albedo[i] * (1.0 - m) + std::f32::consts::PI * d * vis * f;
    }
    out
}

/// The share of the light arriving along the mirror direction that a PBR
/// surface sends to the eye, per channel: the GGX lobe integrated over the
/// hemisphere for the view's cosine `nv` (the "split sum" environment
/// term), in the analytic fit of Karis ("Physically Based Shading on
/// Mobile", 2014, after Lazarov): `F0 A + B` with `F0 = mix(0.04,
/// albedo, metallic)`. What a reflected ray's colour is weighted by
/// ([`crate::trace::TraceSettings::reflections`]). WGSL twin: `reflectance`
/// in `shaders/shade.wgsl`.
///
/// ```
/// use bevy_manifold_core::material::{Pbr, reflectance};
/// // A smooth metal seen head on reflects its own colour (F = F0)...
/// let silver = reflectance([0.95; 3], Pbr { metallic: 1.0, roughness: 0.0 }, 1.0);
/// assert!((silver[0] - 0.95).abs() < 0.02);
/// // ... a smooth dielectric about 4%, and at grazing angles nearly all.
/// let glass = Pbr { metallic: 0.0, roughness: 0.0 };
/// assert!((reflectance([0.5; 3], glass, 1.0)[0] - 0.04).abs() < 0.01);
/// assert!(reflectance([0.5; 3], glass, 0.01)[0] > 0.7);
/// ```
#[must_use]
pub fn reflectance(albedo: [f32; 3], pbr: Pbr, nv: f32) -> [f32; 3] {
    let r = pbr.roughness.clamp(0.0, 1.0);
    let nv = nv.clamp(0.0, 1.0);
    let (r0, r1, r2, r3) = (1.0 - r, 0.0425 - 0.0275 * r, 1.04 - 0.572 * r, 0.022 * r - 0.04);
    let a004 = (r0 * r0).min((-9.28 * nv).exp2()) * r0 + r1;
    let (a, b) = (-1.04 * a004 + r2, 1.04 * a004 + r3);
    let m = pbr.metallic;
    [0, 1, 2].map(|i| ((DIELECTRIC_F0 * (1.0 - m) + albedo[i] * m) * a + b).clamp(0.0, 1.0))
}
