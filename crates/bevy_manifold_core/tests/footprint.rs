//! Cone tracing (`TraceSettings::footprint`, `trace::footprint`): a ball
//! under a pixel leaves its area in the image wherever it lies, and a
//! cone-traced image is nearer a supersampled one than one ray per pixel
//! is, and flickers less while the camera moves.

use bevy_manifold_core::geometry::Geometry;
use bevy_manifold_core::prelude::*;
use bevy_manifold_test_support::compare::{ConeComparison, compare_cones, psnr_of as psnr};
use glam::{DVec3, DVec4};

/// The point at distance `s` from the origin along the unit `u`.
fn at(g: Geometry, u: DVec3, s: f64) -> DVec4 {
    match g {
        Geometry::Euclidean => (u * s).extend(1.0),
        Geometry::Hyperbolic => (u * s.sinh()).extend(s.cosh()),
        Geometry::Spherical => (u * s.sin()).extend(s.cos()),
    }
}

#[test]
fn a_ball_under_a_pixel_leaves_its_area_in_the_image_wherever_it_lies() {
    // 48x48 at 60 degrees: a pixel spans a slope of 2 tan 30 / 48. A
    // glowing ball (no lights, black background, no transports) straight
    // ahead at distance D, of angular radius theta (sin theta = sinh r /
    // sinh D, r / D, sin r / sin D: the right triangle from the eye),
    // shows on the image plane as a disc of radius tan theta. Its colour
    // summed over the image, over its own colour, is that disc's area in
    // pixels, as the ball moves across a pixel in fifths.
    let size = 48u32;
    let slope = 2.0 * 30f64.to_radians().tan() / f64::from(size);
    for (name, d) in [("torus", 1.5), ("seifert-weber", 0.7), ("poincare", 0.25)] {
        let space = if name == "torus" {
            catalog::torus(4.0)
        } else {
            catalog::by_name(name).expect("catalog")
        };
        let g = space.geometry();
        for px in [0.2, 0.45] {
            let tan = px * slope;
            let sin = tan / tan.hypot(1.0);
            let r = match g {
                Geometry::Euclidean => sin * d,
                Geometry::Hyperbolic => (sin * d.sinh()).asinh(),
                Geometry::Spherical => (sin * d.sin()).asin(),
            };
            let want = core::f64::consts::PI * px * px;
            for fifth in 0..5 {
                // Sideways by fifths of a pixel (and a little down).
                let a = (f64::from(fifth) * 0.2 + 0.1) * slope;
                let dir = DVec3::new(a, -0.37 * slope, -1.0).normalize();
                let mut scene = Scene::empty();
                scene.balls.push(Ball {
                    center: at(g, dir, d),
                    radius: r,
                    color: [1.0; 3],
                    glow: 1.0,
                    pbr: None,
                });
                let settings = TraceSettings {
                    width: size,
                    height: size,
                    levels: 0,
                    footprint: true,
                    ..TraceSettings::default()
                };
                let img = render::<f64>(&space, &scene, &settings);
                let ink: f64 = img.pixels.iter().map(|p| f64::from(p.color[0]) / 1.08).sum();
                assert!(
                    (ink / want - 1.0).abs() < 0.05,
                    "{name}, {px} px, at {fifth}/5: {ink:.4} px against {want:.4}"
                );
                // One ray per pixel: a whole pixel or none.
                let plain = render::<f64>(
                    &space,
                    &scene,
                    &TraceSettings {
                        footprint: false,
                        ..settings
                    },
                );
                let hits = plain.pixels.iter().filter(|p| p.object == 1).count();
                assert!(hits <= 1, "{name}: one ray per pixel hits {hits} pixels");
            }
        }
    }
}

#[test]
fn a_cone_traced_view_is_nearer_supersampling_and_flickers_less() {
    // Hyperbolic: copies shrink below a pixel within a few levels; the
    // cone gains 5 dB and flickers no more than 16 samples a pixel do. The
    // other geometries: better, and calmer than one ray.
    for (name, gain, hyperbolic) in [
        ("seifert-weber", 5.0, true),
        ("mirrored-dodecahedron", 5.0, true),
        ("torus", 0.0, false),
        ("poincare", 0.0, false),
        ("mirrored-cube", 0.0, false),
    ] {
        let space = catalog::by_name(name).expect("catalog");
        let scene = Scene::default_for(&space);
        let settings = TraceSettings {
            width: 96,
            height: 54,
            levels: 8,
            ..TraceSettings::default()
        };
        // Against 4x4 samples a pixel, and flicker over 4 frames creeping
        // forward.
        let ConeComparison {
            plain,
            cone,
            reference,
            flicker: [f_plain, f_cone, f_ref],
        } = compare_cones(&space, &scene, &settings, 4, (0.002, 4));
        let (p_plain, p_cone) = (psnr(&plain, &reference), psnr(&cone, &reference));
        println!(
            "{name}: PSNR plain {p_plain:.2} cone {p_cone:.2} dB; flicker plain {f_plain:.2} cone {f_cone:.2} reference {f_ref:.2}"
        );
        assert!(p_cone > p_plain + gain, "{name}: {p_cone:.2} dB against {p_plain:.2}");
        let bound = if hyperbolic { f_ref } else { f_plain };
        assert!(f_cone <= bound, "{name}: flicker {f_cone:.2} against {bound:.2}");
    }
}

#[test]
fn cones_along_rays_through_vertices_edges_and_faces_stay_finite() {
    // The rays where layers meet: through vertices (where tubes and the
    // joints meet, their nearest approaches all but level), along edges
    // (a tube's axis: gap 0, and the approach's quadratic degenerate), and
    // sliding along faces. Each view's 5x5 pixels around that ray, traced
    // as cones in f32 and f64 with the paper's scene (fog on in one pass):
    // every colour and distance finite, no colour negative, every level
    // within the limit.
    for name in catalog::NAMES {
        let space = catalog::by_name(name).expect("catalog");
        let rays = bevy_manifold_test_support::stress::degenerate_rays(&space);
        for (k, ray) in rays.iter().enumerate() {
            for fog in [false, true] {
                let mut scene = Scene::default_for(&space);
                scene.camera.isometry = bevy_manifold_test_support::stress::camera_along(&space, ray);
                if fog {
                    scene.fog = Some(Fog {
                        density: 0.5 / space.inradius(),
                        color: [0.7, 0.75, 0.8],
                    });
                }
                let settings = TraceSettings {
                    width: 5,
                    height: 5,
                    levels: 8,
                    footprint: true,
                    ..TraceSettings::default()
                };
                for img in [
                    render::<f32>(&space, &scene, &settings),
                    render::<f64>(&space, &scene, &settings),
                ] {
                    for p in &img.pixels {
                        assert!(
                            p.color.iter().all(|c| c.is_finite() && *c >= 0.0),
                            "{name} ray {k} fog {fog}: {:?}",
                            p.color
                        );
                        assert!(p.levels <= settings.levels, "{name} ray {k}: {} levels", p.levels);
                        assert!(p.distance.is_finite(), "{name} ray {k}: distance {}", p.distance);
                    }
                }
            }
        }
    }
}

/// Where a ray comes nearest a flat only a quarter turn away (S3: the
/// ray runs along the flat's plane, so its nearest point is at the
/// chart's horizon), the approach is the start's own distance, at the
/// start, not the least distance placed at the start: a tube there must
/// not cover the start. The start's distance comes from its coordinates
/// off the flat's plane (the flat is the great circle in the x-w plane).
#[test]
fn an_approach_a_quarter_turn_away_is_the_starts_own() {
    use bevy_manifold_core::trace::footprint::approach;
    use bevy_manifold_core::trace::step::Ray;
    let g = Geometry::Spherical;
    for phi in [0.05f64, 0.25, 0.6, 1.2] {
        for precision in ["f64", "f32"] {
            let o = DVec4::new(0.0, phi.sin(), 0.0, phi.cos());
            let d = DVec4::new(1.0, 0.0, 0.0, 0.0);
            let (a, e) = (DVec4::W, DVec4::X);
            let start = o.y * o.y + o.z * o.z;
            let (lambda, t) = if precision == "f64" {
                let near = approach::<f64>(g, &Ray { origin: o, dir: d }, a, e);
                (near.lambda, near.t)
            } else {
                let f = |v: DVec4| v.as_vec4();
                let near = approach::<f32>(
                    g,
                    &Ray {
                        origin: f(o),
                        dir: f(d),
                    },
                    f(a),
                    f(e),
                );
                (f64::from(near.lambda), f64::from(near.t))
            };
            assert_eq!(t, 0.0, "{precision} phi {phi}");
            assert!(
                (lambda - start).abs() <= 1e-6 * start.max(1e-3),
                "{precision} phi {phi}: lambda {lambda}, the start's sin^2 {start}"
            );
        }
    }
}
