//! Materials: the GGX lobe against values worked out by hand from its
//! definition (roughness 1 makes the distribution uniform, a head-on
//! highlight is `F0 / (4 alpha^2)`), energy conservation by numerical
//! integration over the hemisphere, a PBR ball's radiance in E3, H3 and
//! S3 against irradiance times that closed form, and a glTF material
//! written field by field (metallic-roughness, emission with its strength,
//! normal map, alpha mask) read and drawn as the file says.

use bevy_manifold_core::geometry::isometry;
use bevy_manifold_core::material::{Cosines, DIELECTRIC_F0, Pbr, brdf};
use bevy_manifold_core::prelude::*;
use bevy_manifold_core::trace::{SceneMesh, normal_mapped};
use bevy_manifold_test_support::materials::{self, write_material_quad};
use glam::{DMat4, DVec3, DVec4};
use std::f64::consts::PI;

const HEAD_ON: Cosines = Cosines {
    nl: 1.0,
    nv: 1.0,
    nh: 1.0,
    vh: 1.0,
};

#[test]
fn roughness_one_is_uniform_ggx() {
    // alpha = 1: D = 1 / pi everywhere, V = 1 / (2 (nl + nv)) head on = 1/4.
    let gold = [1.0, 0.77, 0.34];
    let r = brdf(
        gold,
        Pbr {
            metallic: 1.0,
            roughness: 1.0,
        },
        HEAD_ON,
    );
    for c in 0..3 {
        assert!((r[c] - gold[c] / 4.0).abs() < 1e-6, "{r:?}");
    }
    // A dielectric: Lambert's albedo plus 0.04 / 4.
    let r = brdf(
        [0.5; 3],
        Pbr {
            metallic: 0.0,
            roughness: 1.0,
        },
        HEAD_ON,
    );
    assert!((r[0] - (0.5 + DIELECTRIC_F0 / 4.0)).abs() < 1e-6, "{r:?}");
}

#[test]
fn head_on_highlight_is_f0_over_four_alpha_squared() {
    // At n = h, D = 1 / (pi alpha^2); V = 1/4; F = F0.
    for roughness in [0.3f32, 0.5, 0.7, 0.9] {
        let alpha = roughness * roughness;
        let r = brdf(
            [1.0; 3],
            Pbr {
                metallic: 1.0,
                roughness,
            },
            HEAD_ON,
        );
        let want = 1.0 / (4.0 * alpha * alpha);
        assert!(
            (r[0] - want).abs() < 1e-4 * want,
            "roughness {roughness}: {} vs {want}",
            r[0]
        );
    }
    // Below the least roughness the peak stays that of MIN_ROUGHNESS.
    let a = brdf(
        [1.0; 3],
        Pbr {
            metallic: 1.0,
            roughness: 0.0,
        },
        HEAD_ON,
    );
    let b = brdf(
        [1.0; 3],
        Pbr {
            metallic: 1.0,
            roughness: 0.089,
        },
        HEAD_ON,
    );
    assert_eq!(a, b);
}

/// The reflected fraction of light arriving from the direction at angle
/// `theta_v` (the directional albedo): the integral over the hemisphere of
/// the BRDF (without the tracer's pi) times cos, by the midpoint rule.
fn directional_albedo(albedo: f32, pbr: Pbr, theta_v: f64) -> f64 {
    let v = DVec3::new(theta_v.sin(), 0.0, theta_v.cos());
    let (n_theta, n_phi) = (400, 400);
    let mut sum = 0.0;
    for i in 0..n_theta {
        let theta = (i as f64 + 0.5) / n_theta as f64 * PI / 2.0;
        for j in 0..n_phi {
            let phi = (j as f64 + 0.5) / n_phi as f64 * 2.0 * PI;
            let l = DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
            let h = (l + v).normalize();
            let c = Cosines {
                nl: l.z as f32,
                nv: v.z as f32,
                nh: h.z as f32,
                vh: v.dot(h) as f32,
            };
            let f = f64::from(brdf([albedo; 3], pbr, c)[0]) / PI;
            sum += f * l.z * theta.sin();
        }
    }
    sum * (PI / 2.0 / n_theta as f64) * (2.0 * PI / n_phi as f64)
}

#[test]
fn no_surface_returns_more_light_than_it_gets() {
    for roughness in [0.2, 0.5, 1.0] {
        for theta_v in [0.0, 0.8, 1.3] {
            let white_metal = directional_albedo(
                1.0,
                Pbr {
                    metallic: 1.0,
                    roughness,
                },
                theta_v,
            );
            assert!(
                white_metal <= 1.0 + 1e-3,
                "roughness {roughness}, angle {theta_v}: {white_metal}"
            );
            assert!(
                white_metal > 0.3,
                "roughness {roughness}, angle {theta_v}: {white_metal}"
            );
        }
    }
    // Roughness 1 head on, by hand: D = 1 / pi, V = 1 / (2 (mu + 1)) for
    // mu = n . l, F = 1, so the albedo is the integral over the hemisphere
    // of mu / (2 pi (mu + 1)), that is int_0^1 mu / (mu + 1) dmu = 1 - ln 2
    // (single-scattering GGX loses the rest, Kulla and Conty's "up to 60%").
    let rough = directional_albedo(
        1.0,
        Pbr {
            metallic: 1.0,
            roughness: 1.0,
        },
        0.0,
    );
    assert!((rough - (1.0 - 2f64.ln())).abs() < 1e-4, "{rough}");
    // Nearly smooth, the lobe keeps nearly everything.
    let smooth = directional_albedo(
        1.0,
        Pbr {
            metallic: 1.0,
            roughness: 0.2,
        },
        0.0,
    );
    assert!(smooth > 0.95, "{smooth}");
    // A black dielectric reflects only Fresnel's few percent head on.
    let black = directional_albedo(
        0.0,
        Pbr {
            metallic: 0.0,
            roughness: 0.5,
        },
        0.0,
    );
    assert!(black > 0.03 && black < 0.06, "{black}");
}

/// A scene with one ball of `pbr` at the domain's centre, the camera on
/// +z at `eye` looking at it, a light at the camera: the centre pixel of
/// an odd-sized image sees the ball head on, lit head on.
fn head_on_scene(space: &Space, pbr: Option<Pbr>) -> (Scene, f64, f64) {
    let g = space.geometry();
    let r = space.inradius();
    let eye = 0.62 * r;
    let radius = 0.22 * r;
    let mut scene = Scene::default_for(space);
    let camera = isometry::translation(g, DVec3::new(0.0, 0.0, eye));
    scene.camera.isometry = camera;
    scene.edge_radius = None;
    scene.meshes.clear();
    scene.fog = None;
    scene.balls = vec![Ball {
        center: DVec4::W,
        radius,
        color: [0.9, 0.6, 0.3],
        glow: 0.0,
        pbr,
    }];
    scene.lights = vec![Light::point(camera * DVec4::W, 1.0, [1.0; 3])];
    scene.lighting = Lighting::DOMAIN_COPY;
    (scene, eye - radius, radius)
}

#[test]
fn pbr_ball_radiance_is_irradiance_times_the_closed_form() {
    let pbr = Pbr {
        metallic: 0.6,
        roughness: 0.7,
    };
    for space in [catalog::torus(2.0), catalog::seifert_weber(), catalog::poincare()] {
        let g = space.geometry();
        let (scene, d, _) = head_on_scene(&space, Some(pbr));
        let settings = TraceSettings {
            width: 9,
            height: 9,
            ..TraceSettings::default()
        };
        let image = render::<f64>(&space, &scene, &settings);
        let p = image.at(4, 4);
        assert_eq!(p.object, 1, "{g}: the centre pixel sees the ball");
        let irradiance = 1.0 / g.sphere_area::<f64>(d);
        let alpha = f64::from(pbr.roughness).powi(2);
        for c in 0..3 {
            let a = f64::from(scene.balls[0].color[c]);
            let m = f64::from(pbr.metallic);
            let f0 = 0.04 * (1.0 - m) + a * m;
            let want = a * 0.08 + (a * (1.0 - m) + f0 / (4.0 * alpha * alpha)) * irradiance;
            let got = f64::from(p.color[c]);
            assert!((got - want).abs() < 1e-4 * want, "{g} channel {c}: {got} vs {want}");
        }
        // The classic look, for contrast: Lambert plus 0.35 head on.
        let (classic, ..) = head_on_scene(&space, None);
        let q = render::<f64>(&space, &classic, &settings);
        let a = f64::from(scene.balls[0].color[0]);
        let want = a * 0.08 + (a + 0.35) * irradiance;
        assert!(
            (f64::from(q.at(4, 4).color[0]) - want).abs() < 1e-4 * want,
            "{g} classic"
        );
    }
}

fn quad_dir(name: &str) -> std::path::PathBuf {
    std::env::temp_dir().join(format!("bevy_manifold_material_{name}_{}", std::process::id()))
}

#[test]
fn gltf_material_fields_are_read_as_written() {
    let path = write_material_quad(&quad_dir("read"));
    let loaded = bevy_manifold_core::mesh::gltf::load(&path).expect("the quad loads");
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let m = &loaded.parts[0].material;
    assert_eq!(
        m.base_color,
        [materials::BASE[0], materials::BASE[1], materials::BASE[2]]
    );
    assert_eq!(m.alpha, materials::BASE[3]);
    assert_eq!(m.alpha_cutoff, Some(materials::CUTOFF));
    assert_eq!(
        m.pbr,
        Some(Pbr {
            metallic: materials::METALLIC,
            roughness: materials::ROUGHNESS
        })
    );
    assert_eq!(m.emissive, materials::EMISSIVE.map(|c| c * materials::STRENGTH));
    for (t, name) in [
        (&m.texture, "base"),
        (&m.metallic_roughness, "mr"),
        (&m.emissive_texture, "emissive"),
        (&m.normal_map, "normal"),
    ] {
        let t = t.as_ref().unwrap_or_else(|| panic!("{name} texture"));
        assert_eq!((t.width, t.height), (2, 2), "{name}");
    }
    // The base texture's right column is transparent.
    let base = m.texture.as_ref().unwrap();
    assert_eq!(base.sample_unorm([0.25, 0.25])[3], 1.0);
    assert_eq!(base.sample_unorm([0.75, 0.25])[3], 0.0);
}

#[test]
fn a_normal_map_tilts_along_the_texture_axes() {
    // The quad's first triangle: u runs along +x, v down the image (-y).
    let p = [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0]];
    let uv = [[0.0, 1.0], [1.0, 1.0], [1.0, 0.0]];
    let n = [0.0, 0.0, 1.0];
    let close = |a: [f64; 3], b: [f64; 3]| (0..3).all(|i| (a[i] - b[i]).abs() < 1e-9);
    // Flat texel (0.5, 0.5, 1): the normal itself.
    assert!(close(normal_mapped(p, uv, n, [0.5, 0.5, 1.0, 1.0]), n));
    // Red full: along the tangent, +x; green full: up the image, +y.
    assert!(close(normal_mapped(p, uv, n, [1.0, 0.5, 0.5, 1.0]), [1.0, 0.0, 0.0]));
    assert!(close(normal_mapped(p, uv, n, [0.5, 1.0, 0.5, 1.0]), [0.0, 1.0, 0.0]));
    // 45 degrees towards -x.
    let s = 0.5f64.sqrt();
    let t = (1.0 - s) / 2.0;
    let got = normal_mapped(p, uv, n, [t as f32, 0.5, ((1.0 + s) / 2.0) as f32, 1.0]);
    // (The texel holds f32s: within their rounding.)
    assert!((0..3).all(|i| (got[i] - [-s, 0.0, s][i]).abs() < 1e-6), "{got:?}");
    // Texture coordinates that span no plane: the normal is kept.
    assert!(close(normal_mapped(p, [[0.0, 0.0]; 3], n, [1.0, 0.5, 0.5, 1.0]), n));
}

/// The material quad at the origin of a 3-torus, facing the camera on
/// +z, a ball behind it; no light, so what shows is ambient and emission.
fn quad_scene(space: &Space) -> Scene {
    let g = space.geometry();
    let loaded = bevy_manifold_core::mesh::gltf::load(write_material_quad(&quad_dir("scene"))).unwrap();
    let part = loaded.parts.into_iter().next().unwrap();
    let mut scene = Scene::default_for(space);
    scene.camera.isometry = isometry::translation(g, DVec3::new(0.0, 0.0, 0.9));
    scene.camera.fov_y_degrees = 60.0;
    scene.edge_radius = None;
    scene.fog = None;
    scene.lights.clear();
    scene.balls = vec![Ball {
        center: isometry::translation(g, DVec3::new(0.0, 0.0, -0.3)) * DVec4::W,
        radius: 0.25,
        color: [0.2, 0.9, 0.2],
        glow: 0.0,
        pbr: None,
    }];
    let data = bevy_manifold_core::mesh::MeshData::shared(part.mesh);
    scene.meshes = vec![SceneMesh::new(data, part.material, DMat4::IDENTITY, 0.25)];
    scene
}

#[test]
fn alpha_mask_and_emission_show_as_the_file_says() {
    let space = catalog::torus(2.0);
    let scene = quad_scene(&space);
    let settings = TraceSettings {
        width: 41,
        height: 41,
        ..TraceSettings::default()
    };
    let image = render::<f64>(&space, &scene, &settings);
    // The quad spans +-0.25 at distance 0.9: tan = 0.278, about 9.6
    // pixels of the 41 (tan 30 = 0.577 over 20.5 pixels) each side. Its
    // left half (x < 0) is opaque, its right half cut away: through it
    // the ball behind shows.
    let mesh_id = 2;
    let left = image.at(20 - 5, 20);
    let right = image.at(20 + 5, 20);
    assert_eq!(left.object, mesh_id, "the opaque half");
    assert_eq!(right.object, 1, "through the transparent half, the ball");
    // No light: ambient 0.08 times the base colour (white texture times
    // the factor) plus the emission (white texture times factor times
    // strength).
    for c in 0..3 {
        let want = 0.08 * materials::BASE[c] + materials::EMISSIVE[c] * materials::STRENGTH;
        assert!(
            (left.color[c] - want).abs() < 1e-5 * want,
            "channel {c}: {} vs {want}",
            left.color[c]
        );
    }
    // Without the mask the whole quad is there.
    let mut opaque = scene.clone();
    opaque.meshes[0].material.alpha_cutoff = None;
    assert_eq!(render::<f64>(&space, &opaque, &settings).at(20 + 5, 20).object, mesh_id);
}
