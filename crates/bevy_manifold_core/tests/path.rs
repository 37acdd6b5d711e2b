//! The path tracer (`TraceSettings::path_depth`) against facts that do
//! not come from it: the white furnace (an enclosure of albedo rho that
//! emits E everywhere has radiance E / (1 - rho) at every point, whatever
//! the geometry), the mean weight of a bounce against the BRDF's
//! directional albedo by quadrature over the hemisphere, the light a
//! glowing ball gives a floor against its solid angle (the cone of
//! half-angle `sin a = sin_k(r) / sin_k(d)`, by closed form for Lambert
//! and by quadrature over the cone for GGX), the 1/N fall of the
//! estimate's variance, and finite, non-negative estimates in hostile
//! scenes.

use bevy_manifold_core::geometry::Geometry;
use bevy_manifold_core::material::{Cosines, MeshMaterial, Pbr, brdf};
use bevy_manifold_core::mesh::{MeshData, TriMesh};
use bevy_manifold_core::prelude::*;
use bevy_manifold_core::trace::step::Ray;
use bevy_manifold_core::trace::{FlatScene, Lobes, PathRng, SceneMesh, path_sample};
use glam::{DMat4, DVec3, DVec4};

/// A closed box of half-size `h` about the domain's centre (outward
/// face normals, 4 vertices a face), as a mesh of `material`.
fn enclosure(h: f32, material: MeshMaterial) -> SceneMesh {
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut triangles = Vec::new();
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
            let base = positions.len() as u32;
            for (u, v) in [(-1.0f32, -1.0f32), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let mut p = [0.0; 3];
                p[axis] = sign * h;
                p[a] = u * h;
                p[b] = v * h;
                positions.push(p);
                let mut n = [0.0; 3];
                n[axis] = sign;
                normals.push(n);
            }
            triangles.push([base, base + 1, base + 2]);
            triangles.push([base, base + 2, base + 3]);
        }
    }
    let mesh = TriMesh::new(positions, Some(normals), None, triangles).expect("a box");
    SceneMesh::new(MeshData::shared(mesh), material, DMat4::IDENTITY, 1.0)
}

/// The mean and the standard error of the mean of `xs`.
fn mean_and_error(xs: &[f64]) -> (f64, f64) {
    let n = xs.len() as f64;
    let mean = xs.iter().sum::<f64>() / n;
    let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// Every pixel's estimate (red channel) of `samples` samples.
fn estimates(space: &Space, scene: &Scene, settings: &TraceSettings, samples: u32) -> Vec<Vec<f64>> {
    let n = (settings.width * settings.height) as usize;
    let mut out = vec![Vec::new(); n];
    for k in 0..samples {
        let s = TraceSettings {
            light_sample: k,
            ..settings.clone()
        };
        let img = render::<f64>(space, scene, &s);
        for (o, p) in out.iter_mut().zip(&img.pixels) {
            o.push(f64::from(p.color[0]));
        }
    }
    out
}

#[test]
fn the_white_furnace_glows_at_e_over_one_minus_rho_in_every_geometry() {
    // A box inside the domain about the camera: every path stays in it,
    // so every pixel converges to E / (1 - rho) (depth 40 leaves rho^41
    // of it out: 1e-12 for rho 0.5, 5e-7 for 0.7).
    let cases = [
        (catalog::torus(1.0), 0.3f32),
        (catalog::seifert_weber(), 0.3),
        (catalog::poincare(), 0.15),
    ];
    for (space, h) in cases {
        for (rho, e) in [(0.5f32, 0.25f32), (0.7, 0.1)] {
            let mut scene = Scene::empty();
            scene.camera.isometry = DMat4::IDENTITY;
            scene.meshes.push(enclosure(
                h,
                MeshMaterial {
                    base_color: [rho; 3],
                    emissive: [e; 3],
                    ..MeshMaterial::default()
                },
            ));
            let settings = TraceSettings {
                width: 16,
                height: 12,
                path_depth: 40,
                seed: 7,
                ..TraceSettings::default()
            };
            let all: Vec<f64> = estimates(&space, &scene, &settings, 24).concat();
            let want = f64::from(e) / (1.0 - f64::from(rho));
            let (mean, error) = mean_and_error(&all);
            eprintln!(
                "{} rho {rho} E {e}: {mean:.4} +- {error:.4}, want {want:.4}",
                space.name()
            );
            assert!(
                (mean - want).abs() < 4.0 * error && error < 0.02 * want,
                "{} rho {rho}: {mean} +- {error}, want {want}",
                space.name()
            );
        }
    }
}

/// `sin_k(x)`: `x`, `sinh x` or `sin x`.
fn sin_k(g: Geometry, x: f64) -> f64 {
    match g {
        Geometry::Euclidean => x,
        Geometry::Hyperbolic => x.sinh(),
        Geometry::Spherical => x.sin(),
    }
}

#[test]
fn a_glowing_ball_lights_a_floor_by_its_solid_angle() {
    // A floor ball of albedo rho at the domain's centre and, a height h
    // above its top point x, a ball of radius r glowing with radiance L.
    // Seen straight down, x reflects what the cone of directions meeting
    // the lamp brings, its half-angle `a` from `sin a = sin_k(r) /
    // sin_k(h)` (radiance keeps along geodesics): a Lambert floor
    // `rho L sin^2 a`; a GGX floor `2 L int_0^a brdf cos t sin t dt`
    // (tracer units, `brdf` pi times the BRDF) by quadrature. One bounce
    // and no levels: only this copy's lamp is seen. Next-event
    // estimation keeps the spread small where the lobes alone would hit
    // the lamp a few times in a hundred (relative spread sqrt((1-p)/p),
    // 2 to 3 here).
    let cases = [
        (catalog::torus(4.0), 0.5, 0.8, 0.3),
        (catalog::seifert_weber(), 0.2, 0.45, 0.15),
        (catalog::poincare(), 0.08, 0.14, 0.06),
    ];
    let (rho, glow) = (0.6f32, 2.0f32);
    for (space, floor, h, r) in cases {
        let g = space.geometry();
        let o = g.origin::<f64>();
        let up = DVec4::new(0.0, 0.0, 1.0, 0.0);
        let at = |s: f64| g.exp::<f64>(o, up, s);
        for pbr in [
            None,
            Some(Pbr {
                metallic: 0.0,
                roughness: 0.3,
            }),
            Some(Pbr {
                metallic: 1.0,
                roughness: 0.3,
            }),
        ] {
            let mut scene = Scene::empty();
            scene.camera.isometry = DMat4::IDENTITY;
            scene.balls.push(Ball {
                center: o,
                radius: floor,
                color: [rho; 3],
                glow: 0.0,
                pbr,
            });
            scene.balls.push(Ball {
                center: at(floor + h).0,
                radius: r,
                color: [1.0; 3],
                glow,
                pbr: None,
            });
            let flat = FlatScene::<f64>::new(&space, &scene);
            // From halfway up, straight down at x.
            let (eye, down) = at(floor + 0.5 * h);
            let ray = Ray {
                origin: eye,
                dir: -down,
            };
            let sin_a = sin_k(g, r) / sin_k(g, h);
            let a = sin_a.asin();
            let want = match pbr {
                None => f64::from(rho * glow) * sin_a * sin_a,
                Some(p) => {
                    let n = 20_000;
                    let mut sum = 0.0;
                    for i in 0..n {
                        let t = a * (f64::from(i) + 0.5) / f64::from(n);
                        let c = Cosines {
                            nl: t.cos() as f32,
                            nv: 1.0,
                            nh: (t / 2.0).cos() as f32,
                            vh: (t / 2.0).cos() as f32,
                        };
                        sum += f64::from(brdf([rho; 3], p, c)[0]) * t.cos() * t.sin() * (a / f64::from(n));
                    }
                    2.0 * f64::from(glow) * sum
                }
            };
            let samples: Vec<f64> = (0..3000)
                .map(|k| {
                    let settings = TraceSettings {
                        levels: 0,
                        path_depth: 1,
                        seed: 5,
                        light_sample: k,
                        ..TraceSettings::default()
                    };
                    f64::from(path_sample(&space, &flat, ray, &settings, 0).color[0])
                })
                .collect();
            let (mean, error) = mean_and_error(&samples);
            let spread = error * (samples.len() as f64).sqrt() / mean;
            eprintln!(
                "{} {pbr:?}: {mean:.5} +- {error:.5} (spread {spread:.3}), want {want:.5}",
                space.name()
            );
            assert!(
                (mean - want).abs() < (4.0 * error).max(1e-3 * want) && (mean - want).abs() < 0.01 * want,
                "{} {pbr:?}: {mean} +- {error}, want {want}",
                space.name()
            );
            // Lambert's lobe alone would spread by 2 to 3.
            let bound = if pbr.is_none() { 0.25 } else { 0.6 };
            assert!(spread < bound, "{} {pbr:?}: relative spread {spread}", space.name());
        }
    }
}

#[test]
fn the_estimates_variance_falls_as_one_over_the_samples() {
    // The spread of per-pixel means over N samples shrinks as 1/N: 16
    // times the samples, a sixteenth of the variance (within the scatter
    // of a variance estimated from 192 pixels: a factor of 1.6).
    let space = catalog::seifert_weber();
    let mut scene = Scene::empty();
    scene.camera.isometry = DMat4::IDENTITY;
    scene.meshes.push(enclosure(
        0.3,
        MeshMaterial {
            base_color: [0.6; 3],
            emissive: [0.2; 3],
            ..MeshMaterial::default()
        },
    ));
    let settings = TraceSettings {
        width: 16,
        height: 12,
        path_depth: 40,
        ..TraceSettings::default()
    };
    let per_pixel = estimates(&space, &scene, &settings, 64);
    let spread = |n: usize| {
        let means: Vec<f64> = per_pixel
            .iter()
            .map(|xs| xs[..n].iter().sum::<f64>() / n as f64)
            .collect();
        let (_, error) = mean_and_error(&means);
        error * error * means.len() as f64
    };
    let ratio = spread(4) / spread(64);
    assert!(
        (10.0..25.0).contains(&ratio),
        "variance ratio {ratio} for 16x the samples"
    );
}

/// The directional albedo of `pbr` (white) seen at the cosine `nv`:
/// `integral of brdf / pi cos` over the hemisphere, by the midpoint rule
/// on a 600 x 1200 grid of polar angles and azimuths.
fn directional_albedo(pbr: Pbr, nv: f64) -> f64 {
    let n = DVec3::Z;
    let v = DVec3::new((1.0 - nv * nv).sqrt(), 0.0, nv);
    let (rows, cols) = (600, 1200);
    let (dt, dp) = (
        std::f64::consts::FRAC_PI_2 / f64::from(rows),
        std::f64::consts::TAU / f64::from(cols),
    );
    let mut sum = 0.0;
    for i in 0..rows {
        let theta = (f64::from(i) + 0.5) * dt;
        for j in 0..cols {
            let phi = (f64::from(j) + 0.5) * dp;
            let l = DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
            let h = (l + v).normalize();
            let c = Cosines {
                nl: n.dot(l) as f32,
                nv: nv as f32,
                nh: n.dot(h) as f32,
                vh: v.dot(h) as f32,
            };
            let f = f64::from(brdf([1.0; 3], pbr, c)[0]) / std::f64::consts::PI;
            sum += f * theta.cos() * theta.sin() * dt * dp;
        }
    }
    sum
}

#[test]
fn a_bounce_returns_the_lobes_directional_albedo() {
    // The mean weight of a bounce is the BRDF's directional albedo, here
    // by quadrature (another algorithm than the sampler's), for a white
    // metal, a dielectric and Lambert, in each geometry's tangent space.
    for g in [Geometry::Euclidean, Geometry::Hyperbolic, Geometry::Spherical] {
        let x = match g {
            Geometry::Euclidean => DVec4::new(0.1, 0.2, -0.1, 1.0),
            Geometry::Hyperbolic => DVec4::new(0.3, 0.0, 0.2, (1.0f64 + 0.13).sqrt()),
            Geometry::Spherical => DVec4::new(0.3, 0.0, 0.2, (1.0f64 - 0.13).sqrt()),
        };
        let normal = g.normalize_tangent::<f64>(x, DVec4::new(0.0, 1.0, 0.0, 0.0));
        let side = g.project_tangent::<f64>(x, DVec4::new(1.0, 0.0, 0.0, 0.0));
        let side = side - normal * g.form::<f64>(side, normal);
        let side = side * (1.0 / g.form::<f64>(side, side).sqrt());
        for pbr in [
            Some(Pbr {
                metallic: 1.0,
                roughness: 0.2,
            }),
            Some(Pbr {
                metallic: 1.0,
                roughness: 0.6,
            }),
            Some(Pbr {
                metallic: 0.0,
                roughness: 0.4,
            }),
            None,
        ] {
            for nv in [0.9f64, 0.5, 0.2] {
                let lobes = Lobes::<f64> {
                    x,
                    normal,
                    view: normal * nv + side * (1.0 - nv * nv).sqrt(),
                    albedo: [1.0; 3],
                    pbr,
                };
                let mut rng = PathRng::new(3, 0, 0);
                let n = 200_000;
                let mut sum = 0.0f64;
                for _ in 0..n {
                    let u = [rng.uniform(), rng.uniform(), rng.uniform()];
                    if let Some(b) = lobes.bounce(g, u) {
                        assert!(g.form::<f64>(b.dir, normal) > 0.0);
                        sum += f64::from(b.weight[0]);
                    }
                }
                let got = sum / f64::from(n);
                let want = pbr.map_or(1.0, |p| directional_albedo(p, nv));
                assert!(
                    (got - want).abs() < 0.01,
                    "{g:?} {pbr:?} nv {nv}: {got} against the quadrature's {want}"
                );
            }
        }
    }
}

#[test]
fn hostile_scenes_give_finite_non_negative_estimates() {
    // A zero-roughness metal, a light on a surface, grazing views, fog,
    // deep paths: no NaN, no infinity, nothing negative.
    for space in [catalog::torus(1.0), catalog::seifert_weber(), catalog::poincare()] {
        let mut scene = Scene::default_for(&space);
        scene.balls[0].pbr = Some(Pbr {
            metallic: 1.0,
            roughness: 0.0,
        });
        let on_ball = scene.balls[0].center;
        let mut light = scene.lights[0].clone();
        light.position = space
            .geometry()
            .normalize_point::<f64>(on_ball + DVec4::new(scene.balls[0].radius.sin(), 0.0, 0.0, 0.0));
        let lamp = light.position;
        scene.lights.push(light);
        // A lamp ball straddling the mirror's surface, and one about the
        // camera.
        scene.balls.push(Ball {
            center: lamp,
            radius: 0.05,
            color: [1.0, 0.5, 0.0],
            glow: 50.0,
            pbr: None,
        });
        scene.balls.push(Ball {
            center: scene.camera.isometry.w_axis,
            radius: 0.02,
            color: [0.3; 3],
            glow: 1.0,
            pbr: None,
        });
        scene.lighting.shadows = true;
        scene.fog = Some(Fog {
            density: 0.5,
            color: [0.5, 0.6, 0.7],
        });
        let settings = TraceSettings {
            width: 24,
            height: 16,
            path_depth: 64,
            ..TraceSettings::default()
        };
        for k in 0..3 {
            let img = render::<f32>(
                &space,
                &scene,
                &TraceSettings {
                    light_sample: k,
                    ..settings.clone()
                },
            );
            for p in &img.pixels {
                assert!(
                    p.color.iter().all(|c| c.is_finite() && *c >= 0.0),
                    "{}: {:?}",
                    space.name(),
                    p.color
                );
            }
        }
    }
}

#[test]
fn a_path_is_the_same_for_the_same_seed_and_sample() {
    let space = catalog::poincare();
    let scene = Scene::default_for(&space);
    let settings = TraceSettings {
        width: 16,
        height: 12,
        path_depth: 8,
        seed: 11,
        light_sample: 5,
        ..TraceSettings::default()
    };
    let a = render::<f32>(&space, &scene, &settings);
    let b = render::<f32>(&space, &scene, &settings);
    assert!(a.pixels.iter().zip(&b.pixels).all(|(p, q)| p.color == q.color));
    let c = render::<f32>(
        &space,
        &scene,
        &TraceSettings {
            light_sample: 6,
            ..settings.clone()
        },
    );
    let d = render::<f32>(&space, &scene, &TraceSettings { seed: 12, ..settings });
    for other in [c, d] {
        let differ = a
            .pixels
            .iter()
            .zip(&other.pixels)
            .filter(|(p, q)| p.color != q.color)
            .count();
        assert!(differ > a.pixels.len() / 4, "{differ} pixels differ");
    }
}
