//! The CPU reference tracer: transport through the pairings, closed
//! geodesics, invariants over a million random rays, and an image checked
//! against the cover computed independently.

use bevy_manifold_core::geometry::{Geometry, isometry};
use bevy_manifold_core::prelude::*;
use bevy_manifold_core::trace::step::Ray;
use bevy_manifold_core::trace::{FaceTables, FlatScene, Stop, flow, ghost_centres, trace_ray, write_ids_png};
use bevy_manifold_test_support::stress::face_middle;
use glam::{DMat4, DVec3, DVec4, IVec3};
use rayon::prelude::*;
use std::f64::consts::{PI, TAU};

use bevy_manifold_test_support::Rng;

fn empty(space: &Space) -> FlatScene<f64> {
    FlatScene::new(space, &Scene::empty())
}

fn tables(space: &Space) -> FaceTables<f64> {
    FaceTables::new(space)
}

#[test]
fn a_ray_leaving_through_a_face_reenters_through_its_partner() {
    for name in catalog::NAMES {
        let s = catalog::by_name(name).expect("catalog");
        let g = s.geometry();
        let flat = empty(&s);
        let settings = TraceSettings {
            levels: 1,
            max_distance: 50.0,
            ..TraceSettings::default()
        };
        for (i, f) in s.faces().iter().enumerate() {
            // Aim from near the centre at the middle of face i.
            let mid = face_middle(&s, i);
            let o = g.normalize_point::<f64>(DVec4::W * 0.9 + mid * 0.1);
            let ray = Ray {
                origin: o,
                dir: g.normalize_tangent::<f64>(o, mid),
            };
            let mut steps = Vec::new();
            let (_, stop) = trace_ray(&s, &flat, ray, &settings, &mut |st| steps.push(*st));
            assert_eq!(stop, Stop::MaxLevel, "{name}");
            assert_eq!(steps[0].face, Some(i), "{name}: face {i}");
            let end = steps[0].end;
            assert!(
                f.plane.dot(end.origin).abs() < 1e-12,
                "{name}: the exit point is on face {i}"
            );
            let start = steps[1].start;
            let expect = g.normalize_point::<f64>(f.pairing * end.origin);
            assert!(
                (start.origin - expect).length() < 1e-12,
                "{name}: T_{i} applied to the exit point"
            );
            let partner = &s.faces()[f.partner];
            assert!(
                partner.plane.dot(start.origin).abs() < 1e-12,
                "{name}: re-enters on face {}",
                f.partner
            );
            assert!(
                partner.plane.dot(start.dir) < 0.0,
                "{name}: heading inwards from face {}",
                f.partner
            );
        }
    }
}

#[test]
fn torus_ray_along_x_comes_back_after_distance_one() {
    let s = catalog::torus(1.0);
    let flat = tables(&s);
    let o = DVec4::new(0.2, -0.1, 0.3, 1.0);
    let ray = Ray {
        origin: o,
        dir: DVec4::X,
    };
    let before = flow(&flat, ray, 0.99, 10);
    assert_eq!(before.levels, 1);
    assert!((before.ray.origin - o).length() > 1e-3);
    let back = flow(&flat, ray, 1.0, 10);
    assert!(back.complete);
    assert!((back.ray.origin - o).length() < 1e-15, "{:?}", back.ray.origin);
    assert_eq!(
        s.cell_id(&back.cell).lattice(),
        Some(IVec3::X),
        "one copy along +x in the cover"
    );
}

#[test]
fn every_geodesic_of_the_poincare_space_closes_after_two_pi() {
    // The cover is S3, where every geodesic is a great circle of length
    // 2 pi. The group also contains -I, so after pi a ray is back at its
    // start in the quotient too, in the antipodal copy.
    let s = catalog::poincare();
    let flat = tables(&s);
    let mut rng = Rng(1);
    let minus_one = s.cell_id(&(-DMat4::IDENTITY));
    assert_ne!(minus_one.0, 0);
    for _ in 0..2000 {
        let ray = rng.ray_inside(&s);
        let full = flow(&flat, ray, TAU, 100);
        assert!(full.complete);
        assert!(
            (full.ray.origin - ray.origin).length() < 1e-9,
            "not back at the start after 2 pi"
        );
        assert!((full.ray.dir - ray.dir).length() < 1e-9);
        assert_eq!(s.cell_id(&full.cell).0, 0, "back in the original copy");
        let half = flow(&flat, ray, PI, 100);
        assert!(
            (half.ray.origin - ray.origin).length() < 1e-9,
            "the quotient closes it after pi"
        );
        assert_eq!(s.cell_id(&half.cell), minus_one, "in the antipodal copy");
        // Just short of pi it is elsewhere.
        let short = flow(&flat, ray, PI - 0.1, 100);
        assert!((short.ray.origin - ray.origin).length() > 1e-3);
    }
}

#[test]
fn a_million_random_rays_stay_finite_inside_and_normalised() {
    const RAYS: usize = 1_000_000;
    const LEVELS: u32 = 64;
    for name in catalog::NAMES {
        let s = catalog::by_name(name).expect("catalog");
        let g = s.geometry();
        let flat = empty(&s);
        let settings = TraceSettings {
            levels: LEVELS,
            max_distance: 1e6,
            ..TraceSettings::default()
        };
        let worst = (0..RAYS / 1000)
            .into_par_iter()
            .map(|chunk| {
                let mut rng = Rng(chunk as u64 * 7919 + 17);
                let mut worst = [0.0f64; 3];
                for _ in 0..1000 {
                    let ray = rng.ray_inside(&s);
                    let mut check = |r: &Ray<f64>| {
                        assert!(r.origin.is_finite() && r.dir.is_finite(), "{name}: NaN");
                        let outside = s
                            .faces()
                            .iter()
                            .map(|f| f.plane.dot(r.origin / r.origin.w))
                            .fold(f64::MIN, f64::max);
                        worst[0] = worst[0].max(outside);
                        worst[1] = worst[1].max(g.point_error::<f64>(r.origin));
                        worst[2] = worst[2].max(g.tangent_error::<f64>(r.origin, r.dir));
                    };
                    let mut steps = 0;
                    let (_, stop) = trace_ray(&s, &flat, ray, &settings, &mut |st| {
                        check(&st.start);
                        check(&st.end);
                        steps += 1;
                    });
                    assert_eq!(stop, Stop::MaxLevel, "{name}: every ray makes all its transports");
                    assert!(steps as u32 >= LEVELS, "{name}");
                }
                worst
            })
            .reduce(|| [0.0; 3], |a, b| [a[0].max(b[0]), a[1].max(b[1]), a[2].max(b[2])]);
        assert!(
            worst[0] <= 1e-9,
            "{name}: a segment end is {:.3e} outside the domain",
            worst[0]
        );
        assert!(worst[1] <= 1e-9, "{name}: point normalisation error {:.3e}", worst[1]);
        assert!(worst[2] <= 1e-9, "{name}: direction tangency error {:.3e}", worst[2]);
    }
}

/// The torus image, computed the other way: unfold the torus into its cover
/// (E3 with a ball at every integer point) and intersect each pixel's ray
/// with every copy, plain Euclidean geometry, no faces.
#[test]
fn torus_ball_copies_appear_where_the_lattice_predicts() {
    let s = catalog::torus(1.0);
    let eye = DVec3::new(0.2, 0.1, 0.3);
    let radius = 0.1;
    let scene = Scene {
        camera: bevy_manifold_core::trace::Camera {
            isometry: DMat4::from_translation(eye),
            fov_y_degrees: 90.0,
            frustum: None,
            cell: Vec::new(),
        },
        balls: vec![Ball {
            center: DVec4::W,
            radius,
            color: [1.0, 0.5, 0.2],
            glow: 0.0,
            pbr: None,
        }],
        lights: vec![Light {
            position: eye.extend(1.0),
            intensity: 1.0,
            color: [1.0; 3],
            range: None,
            radius: 0.0,
            spot: None,
        }],
        meshes: Vec::new(),
        lighting: Lighting::default(),
        skipped: Vec::new(),
        edge_radius: None,
        fog: None,
    };
    const L: i32 = 12;
    let settings = TraceSettings {
        width: 64,
        height: 64,
        levels: L as u32,
        max_distance: 1e3,
        ..TraceSettings::default()
    };
    let img = render::<f64>(&s, &scene, &settings);

    // Predicted pixel of copy (i, j, k): project its centre.
    let pixel_of = |c: IVec3| {
        let rel = c.as_dvec3() - eye;
        let x = rel.x / -rel.z; // tan(45 deg) = 1, square image
        let y = rel.y / -rel.z;
        (((x + 1.0) * 32.0) as u32, ((1.0 - y) * 32.0) as u32)
    };
    for c in [
        IVec3::new(0, 0, -1),
        IVec3::new(1, 0, -1),
        IVec3::new(-1, 1, -2),
        IVec3::new(0, -1, -3),
        IVec3::new(2, 1, -4),
    ] {
        let (i, j) = pixel_of(c);
        let p = img.at(i, j);
        assert_eq!(p.object, 1, "copy {c} at pixel ({i}, {j})");
        assert_eq!(p.levels, c.abs().element_sum() as u32, "copy {c}: face crossings");
        assert_eq!(p.cell.lattice(), Some(c), "copy {c}: cell");
    }

    // Every pixel against the unfolded cover.
    let mut mismatches = 0;
    for j in 0..64u32 {
        for i in 0..64u32 {
            let x = 2.0 * (f64::from(i) + 0.5) / 64.0 - 1.0;
            let y = 1.0 - 2.0 * (f64::from(j) + 0.5) / 64.0;
            let d = DVec3::new(x, y, -1.0).normalize();
            let mut best: Option<(f64, IVec3)> = None;
            for a in -L..=L {
                for b in -L..=L {
                    for k in -L..=L {
                        let c = IVec3::new(a, b, k);
                        if c.abs().element_sum() > L {
                            continue;
                        }
                        let q = eye - c.as_dvec3();
                        let (hb, cc) = (q.dot(d), q.length_squared() - radius * radius);
                        let disc = hb * hb - cc;
                        if disc >= 0.0 {
                            let t = -hb - disc.sqrt();
                            if t > 0.0 && best.is_none_or(|(bt, _)| t < bt) {
                                best = Some((t, c));
                            }
                        }
                    }
                }
            }
            let p = img.at(i, j);
            let ok = match best {
                Some((t, c)) => {
                    p.object == 1
                        && p.cell.lattice() == Some(c)
                        && p.levels == c.abs().element_sum() as u32
                        && (f64::from(p.distance) - t).abs() < 1e-5
                }
                None => p.object == 0,
            };
            if !ok {
                mismatches += 1;
            }
        }
    }
    assert_eq!(mismatches, 0, "pixels where the tracer and the unfolded cover disagree");

    // The id buffer file carries the same numbers.
    let path = std::env::temp_dir().join(format!("bevy_manifold_ids_{}.png", std::process::id()));
    write_ids_png(&img, &path).expect("write ids");
    let back = image::open(&path).expect("read ids").to_rgba8();
    let c = IVec3::new(-1, 1, -2);
    let (i, j) = pixel_of(c);
    let px = back.get_pixel(i, j).0;
    assert_eq!(px, [1, 4, (img.at(i, j).cell.0 & 0xff) as u8, 255]);
    let _ = std::fs::remove_file(path);
}

#[test]
fn f32_tracing_agrees_with_f64_on_what_each_pixel_sees() {
    for name in catalog::NAMES {
        let s = catalog::by_name(name).expect("catalog");
        let scene = Scene::default_for(&s);
        let settings = TraceSettings {
            width: 96,
            height: 54,
            levels: 6,
            ..TraceSettings::default()
        };
        let a = render::<f64>(&s, &scene, &settings);
        let b = render::<f32>(&s, &scene, &settings);
        // f32 can name a hyperbolic copy only out to its own horizon; past
        // it the id is flagged FAR (best effort) and not compared. The
        // object and the level always are.
        let same_cell = |p: &CellId, q: &CellId| p == q || p.is_far() || q.is_far();
        let same = a
            .pixels
            .iter()
            .zip(&b.pixels)
            .filter(|(p, q)| p.object == q.object && p.levels == q.levels && same_cell(&p.cell, &q.cell))
            .count();
        let frac = same as f64 / a.pixels.len() as f64;
        assert!(frac > 0.99, "{name}: only {:.2}% of pixels agree", frac * 100.0);
        // FAR appears only in hyperbolic spaces, and only in f32 sooner.
        let far64 = a.pixels.iter().filter(|p| p.cell.is_far()).count();
        let far32 = b.pixels.iter().filter(|p| p.cell.is_far()).count();
        assert!(far32 >= far64, "{name}");
        if s.geometry() != Geometry::Hyperbolic {
            assert_eq!(far32, 0, "{name}");
        }
    }
}

#[test]
fn shading_uses_the_geometrys_light_falloff_and_fog() {
    // Camera and light at the same point, a ball straight ahead: at the
    // image centre the normal, the light and the view all line up, so the
    // colour is albedo * (ambient + I / area(d)) + 0.35 I / area(d), with
    // area(d) = 4 pi d^2, 4 pi sinh^2 d or 4 pi sin^2 d.
    for g in [Geometry::Euclidean, Geometry::Hyperbolic, Geometry::Spherical] {
        let s = match g {
            Geometry::Euclidean => catalog::torus(2.0),
            Geometry::Hyperbolic => catalog::seifert_weber(),
            Geometry::Spherical => catalog::poincare(),
        };
        let r = s.inradius();
        let cam = isometry::translation(g, DVec3::Z * 0.6 * r);
        let ball = 0.2 * r;
        let albedo = [0.5f32, 0.25, 1.0];
        let mut scene = Scene {
            camera: bevy_manifold_core::trace::Camera {
                isometry: cam,
                fov_y_degrees: 40.0,
                frustum: None,
                cell: Vec::new(),
            },
            balls: vec![Ball {
                center: DVec4::W,
                radius: ball,
                color: albedo,
                glow: 0.0,
                pbr: None,
            }],
            lights: vec![Light {
                position: cam * DVec4::W,
                intensity: 0.3,
                color: [1.0; 3],
                range: None,
                radius: 0.0,
                spot: None,
            }],
            meshes: Vec::new(),
            // One light, once: the light images' sums are light.rs's.
            lighting: Lighting::DOMAIN_COPY,
            skipped: Vec::new(),
            edge_radius: None,
            fog: None,
        };
        let settings = TraceSettings {
            width: 3,
            height: 3,
            ..TraceSettings::default()
        };
        let d = 0.6 * r - ball;
        let irr = (0.3 / g.sphere_area::<f64>(d)) as f32;
        let p = *render::<f64>(&s, &scene, &settings).at(1, 1);
        assert_eq!(p.object, 1);
        assert!((f64::from(p.distance) - d).abs() < 1e-6, "{g}: distance {}", p.distance);
        for (c, (&got, &a)) in p.color.iter().zip(&albedo).enumerate() {
            let expect = a * (0.08 + irr) + 0.35 * irr;
            assert!((got - expect).abs() < 1e-4, "{g}: channel {c}: {got} vs {expect}");
        }
        // Fog mixes towards its colour by exp(-density * distance).
        scene.fog = Some(Fog {
            density: 2.0,
            color: [0.2, 0.4, 0.6],
        });
        let q = *render::<f64>(&s, &scene, &settings).at(1, 1);
        let tr = (-2.0 * d).exp() as f32;
        for c in 0..3 {
            let expect = p.color[c] * tr + [0.2, 0.4, 0.6][c] * (1.0 - tr);
            assert!((q.color[c] - expect).abs() < 1e-5, "{g}: fog channel {c}");
        }
        // Dense fog and nothing to hit: every ray gives up early, seeing
        // only fog, instead of running through its levels.
        scene.balls.clear();
        scene.fog = Some(Fog {
            density: 500.0,
            color: [0.2, 0.4, 0.6],
        });
        let settings = TraceSettings {
            width: 3,
            height: 3,
            levels: 50,
            ..TraceSettings::default()
        };
        for f in render::<f64>(&s, &scene, &settings).pixels {
            assert_eq!(f.object, 0);
            assert_eq!(f.color, [0.2, 0.4, 0.6]);
            assert!(f.levels <= 2, "{g}: stopped after {} levels", f.levels);
            // It checks the fog between segments, so it finishes the segment
            // it is in (shorter than the domain's diameter).
            let bound = 255f64.ln() / 500.0 + 2.0 * s.circumradius();
            assert!(f64::from(f.distance) < bound, "{g}: travelled {}", f.distance);
        }
    }
}

/// A light exactly on the point a ray hits: the direction to it is 0 / 0.
/// It lights the point head-on (along the normal), as a light a hair
/// above the surface does, never NaN. In the torus the numbers are exact
/// in binary (camera 3/8 from a ball of radius 1/8: the centre ray hits at
/// z = 1/8 exactly, where the light is); then the light is moved 1e-9
/// along the normal and the colour must not change, in f64 and f32.
#[test]
fn a_light_on_the_hit_point_lights_it_head_on_never_nan() {
    use bevy_manifold_test_support::stress::light_on_the_hit;
    let albedo = [0.5f32, 0.25, 1.0];
    let (s, _) = light_on_the_hit(0.125);
    let at = |z: f64| light_on_the_hit(z).1;
    let settings = TraceSettings {
        width: 3,
        height: 3,
        ..TraceSettings::default()
    };
    for (on, above) in [
        (
            *render::<f64>(&s, &at(0.125), &settings).at(1, 1),
            *render::<f64>(&s, &at(0.125 + 1e-9), &settings).at(1, 1),
        ),
        (
            *render::<f32>(&s, &at(0.125), &settings).at(1, 1),
            *render::<f32>(&s, &at(0.125 + 1e-9), &settings).at(1, 1),
        ),
    ] {
        assert_eq!(on.object, 1);
        assert!((f64::from(on.distance) - 0.25).abs() < 1e-6);
        assert!(on.color.iter().all(|c| c.is_finite()), "{:?}", on.color);
        // Head-on, area clamped at 1e-4: albedo * (ambient + I / 1e-4)
        // + 0.35 I / 1e-4 (the view is along the normal too).
        for (c, a) in albedo.iter().enumerate() {
            let irr = 0.3f32 / 1e-4;
            let expect = a * (0.08 + irr) + 0.35 * irr;
            assert!(
                (on.color[c] - expect).abs() <= 1e-4 * expect,
                "channel {c}: {} vs {expect}",
                on.color[c]
            );
            assert!((on.color[c] - above.color[c]).abs() <= 1e-4 * expect, "channel {c}");
        }
    }
}

#[test]
fn a_ball_straddling_a_face_is_drawn_through_it() {
    let s = catalog::torus(1.0);
    let c = DVec4::new(0.45, 0.0, 0.0, 1.0);
    let ghosts = ghost_centres(&s, c, 0.1);
    assert_eq!(ghosts.len(), 2, "{ghosts:?}");
    assert!((ghosts[1] - DVec4::new(-0.55, 0.0, 0.0, 1.0)).length() < 1e-15);
    // A ball in a corner reaches into three faces: 8 copies.
    assert_eq!(ghost_centres(&s, DVec4::new(0.45, 0.45, -0.45, 1.0), 0.1).len(), 8);
    // Seen from the -x side, the ghost is what the ray hits first.
    let scene = Scene {
        camera: bevy_manifold_core::trace::Camera {
            isometry: DMat4::from_translation(DVec3::new(-0.1, 0.0, 0.0))
                * DMat4::from_rotation_y(std::f64::consts::FRAC_PI_2),
            fov_y_degrees: 30.0,
            frustum: None,
            cell: Vec::new(),
        },
        balls: vec![Ball {
            center: c,
            radius: 0.1,
            color: [1.0; 3],
            glow: 0.0,
            pbr: None,
        }],
        lights: vec![],
        meshes: Vec::new(),
        lighting: Lighting::default(),
        skipped: Vec::new(),
        edge_radius: None,
        fog: None,
    };
    // The camera looks along -x; the ghost at -0.55 is 0.45 - 0.1 away,
    // without crossing a face.
    let img = render::<f64>(
        &s,
        &scene,
        &TraceSettings {
            width: 5,
            height: 5,
            ..TraceSettings::default()
        },
    );
    let p = img.at(2, 2);
    assert_eq!((p.object, p.levels), (1, 0));
    assert!((f64::from(p.distance) - 0.35).abs() < 1e-6);
}

#[test]
fn scene_files_report_the_bad_field() {
    let s = catalog::poincare();
    let good = Scene::default_for(&s).to_json();
    let parse = |t: &str| Scene::parse(t, "scene.json", &s);
    assert!(parse(&good).is_ok());
    let v: serde_json::Value = serde_json::from_str(&good).expect("json");
    let with = |path: &[&str], value: serde_json::Value| {
        let mut v = v.clone();
        let mut cur = &mut v;
        for p in path {
            cur = match p.parse::<usize>() {
                Ok(i) => &mut cur[i],
                Err(_) => &mut cur[*p],
            };
        }
        *cur = value;
        parse(&v.to_string()).unwrap_err().to_string()
    };
    let e = with(&["balls", "0", "radius"], serde_json::json!(-1.0));
    assert_eq!(e, "scene.json: balls[0].radius: must be positive and finite, got -1");
    let e = with(&["balls", "0", "center"], serde_json::json!([0.0, 0.0, 0.0, 2.0]));
    assert!(
        e.starts_with("scene.json: balls[0].center: ") && e.contains("not normalised"),
        "{e}"
    );
    let e = with(&["balls", "0", "center"], serde_json::json!([0.6, 0.0, 0.0, 0.8]));
    assert!(
        e.contains("balls[0].center") && e.contains("outside the fundamental domain"),
        "{e}"
    );
    let e = with(&["balls", "0", "glow"], serde_json::json!(-0.5));
    assert_eq!(
        e,
        "scene.json: balls[0].glow: glow must be finite, in [0, 1000], got -0.5"
    );
    // A glow is kept through the file.
    let mut glowing = Scene::default_for(&s);
    glowing.balls[0].glow = 1.5;
    assert_eq!(parse(&glowing.to_json()).expect("parses").balls[0].glow, 1.5);
    let e = with(&["lights", "0", "intensity"], serde_json::json!(-2.0));
    assert!(e.contains("lights[0].intensity"), "{e}");
    let e = with(&["camera", "fov_y_degrees"], serde_json::json!(180.0));
    assert!(e.contains("camera.fov_y_degrees"), "{e}");
    let e = with(&["camera", "isometry", "0", "0"], serde_json::json!(3.0));
    assert!(e.contains("camera.isometry") && e.contains("not an isometry"), "{e}");
    let e = parse(r#"{"balls": []}"#).unwrap_err().to_string();
    assert!(e.contains("missing field `camera`"), "{e}");
    let e = parse(
        r#"{"camera": {"isometry": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]], "fov_y_degrees": 60}, "bals": []}"#,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("unknown field `bals`"), "{e}");
}

#[test]
fn a_camera_placed_in_another_copy_sees_the_same_view() {
    // The camera isometry may point anywhere in the cover: it is wrapped into
    // the domain first, and the cells it reports are offset by its own.
    for (s, shift) in [
        (catalog::torus(1.0), DMat4::from_translation(DVec3::new(1.0, -2.0, 0.0))),
        (
            catalog::seifert_weber(),
            catalog::seifert_weber().crossing(3) * catalog::seifert_weber().crossing(7),
        ),
    ] {
        let scene = Scene::default_for(&s);
        let mut moved = scene.clone();
        moved.camera.isometry = shift * scene.camera.isometry;
        let settings = TraceSettings {
            width: 40,
            height: 24,
            levels: 4,
            ..TraceSettings::default()
        };
        let (a, b) = (
            render::<f64>(&s, &scene, &settings),
            render::<f64>(&s, &moved, &settings),
        );
        for (p, q) in a.pixels.iter().zip(&b.pixels) {
            assert_eq!((p.object, p.levels), (q.object, q.levels), "{}", s.name());
            assert!((p.distance - q.distance).abs() < 1e-5, "{}", s.name());
        }
        let centre = (a.at(20, 12), b.at(20, 12));
        assert_eq!(centre.0.cell.0, 0);
        assert_eq!(
            centre.1.cell,
            s.cell_id(&shift),
            "{}: the view starts in the camera's copy",
            s.name()
        );
    }
}

#[test]
fn rays_through_vertices_along_edges_and_tangent_to_faces_stay_sane() {
    // The degenerate cases of the face test: a ray that meets several faces
    // at once (a vertex, an edge) or slides along one. None may produce NaN,
    // leave the domain, or burn its levels without moving on.
    for name in catalog::NAMES {
        let s = catalog::by_name(name).expect("catalog");
        let g = s.geometry();
        let flat = empty(&s);
        let settings = TraceSettings {
            levels: 64,
            max_distance: 1e6,
            ..TraceSettings::default()
        };
        for (i, ring) in s.polyhedron().face_vertices.iter().enumerate() {
            // The sliding rays really are tangent to their face.
            let dir = g.normalize_tangent::<f64>(face_middle(&s, i), s.vertices()[ring[0]].point);
            assert!(s.faces()[i].plane.dot(dir).abs() < 1e-12, "{name}: tangent to face {i}");
        }
        let rays = bevy_manifold_test_support::stress::degenerate_rays(&s);
        assert_eq!(rays.len(), s.vertices().len() + 2 * s.edges().len() + s.faces().len());
        for ray in rays {
            let mut steps = 0usize;
            let mut length = 0.0;
            let (_, stop) = trace_ray(&s, &flat, ray, &settings, &mut |st| {
                for r in [st.start, st.end] {
                    assert!(r.origin.is_finite() && r.dir.is_finite(), "{name}: NaN");
                    let out = s
                        .faces()
                        .iter()
                        .map(|f| f.plane.dot(r.origin / r.origin.w))
                        .fold(f64::MIN, f64::max);
                    assert!(out <= 1e-9, "{name}: {out:e} outside");
                    assert!(g.tangent_error::<f64>(r.origin, r.dir) < 1e-9, "{name}");
                }
                steps += 1;
                length += st.length;
            });
            assert_eq!(stop, Stop::MaxLevel, "{name}");
            // Zero-length hops at a vertex are allowed, a stall is not: the
            // 64 crossings must cover real distance.
            assert!(
                length > 8.0 * s.inradius(),
                "{name}: only {length} after {steps} segments"
            );
        }
    }
}

#[test]
fn scene_files_refuse_radii_lights_and_meshes_no_tracer_can_draw() {
    // H3: cosh r overflows f32 past r = 89, where the GPU would draw
    // nothing and the CPU a ball: radii are capped by geometry.
    let s = catalog::seifert_weber();
    let mut v: serde_json::Value = serde_json::from_str(&Scene::default_for(&s).to_json()).expect("json");
    v["balls"][0]["radius"] = serde_json::json!(95.0);
    let e = Scene::parse(&v.to_string(), "scene.json", &s).unwrap_err().to_string();
    assert_eq!(
        e,
        "scene.json: balls[0].radius: must be at most 40 in hyperbolic space, got 95"
    );
    v["balls"][0]["radius"] = serde_json::json!(0.1);
    v["edges"] = serde_json::json!({"radius": 1e9});
    let e = Scene::parse(&v.to_string(), "scene.json", &s).unwrap_err().to_string();
    assert!(e.contains("edges.radius") && e.contains("at most 40"), "{e}");
    // 65 lights: every hit would loop over each.
    v["edges"] = serde_json::json!({"radius": 0.02});
    let light = v["lights"][0].clone();
    v["lights"] = serde_json::Value::Array(vec![light; 65]);
    let e = Scene::parse(&v.to_string(), "scene.json", &s).unwrap_err().to_string();
    assert!(e.contains("lights: at most 64 lights"), "{e}");
    // A mesh with a NaN colour, or placed outside the domain, is named
    // before its file is read.
    let rows = |x: f64| {
        let m = bevy_manifold_core::geometry::isometry::translation(Geometry::Hyperbolic, DVec3::X * x);
        bevy_manifold_core::space::file::to_rows(m)
    };
    let t = catalog::seifert_weber();
    let mut v: serde_json::Value = serde_json::from_str(&Scene::default_for(&t).to_json()).expect("json");
    v["lights"] = serde_json::json!([]);
    v["meshes"] =
        serde_json::json!([{"file": "nowhere.glb", "placement": rows(0.1), "scale": 0.1, "color": [0.5, -1.0, 0.5]}]);
    let e = Scene::parse(&v.to_string(), "scene.json", &t).unwrap_err().to_string();
    assert!(e.contains("meshes[0].color"), "{e}");
    v["meshes"] = serde_json::json!([{"file": "nowhere.glb", "placement": rows(3.0), "scale": 0.1}]);
    let e = Scene::parse(&v.to_string(), "scene.json", &t).unwrap_err().to_string();
    assert!(
        e.contains("meshes[0].placement") && e.contains("outside the fundamental domain"),
        "{e}"
    );
}

#[test]
fn the_camera_never_sees_its_own_body_from_inside_even_beside_a_face() {
    // The camera 0.05 inradius from face 0, looking at it, wearing a body
    // (Suzanne around the eye) that reaches across the face. Every copy of
    // the body other than its own lies a whole translation away (1 in the
    // torus, 2r = 1.99 in Seifert-Weber), so a hit nearer than the body's
    // radius can only be the home body met from inside: through the face,
    // a ghost copy of it is that body, and must be skipped at every level.
    for s in [catalog::torus(1.0), catalog::seifert_weber()] {
        let (scene, radius) = bevy_manifold_test_support::stress::body_beside_a_face(&s);
        let settings = TraceSettings {
            width: 96,
            height: 96,
            levels: 6,
            ..TraceSettings::default()
        };
        let img = render::<f64>(&s, &scene, &settings);
        let id = 1; // no balls: the mesh is object 1
        let seen: Vec<f32> = img
            .pixels
            .iter()
            .filter(|p| p.object == id)
            .map(|p| p.distance)
            .collect();
        let nearest = seen.iter().copied().fold(f32::INFINITY, f32::min);
        assert!(!seen.is_empty(), "{}: the body's images are seen", s.name());
        assert!(
            f64::from(nearest) > radius,
            "{}: a hit on the body at {nearest}, inside its own radius {radius}: the home body seen from inside",
            s.name()
        );
    }
}

#[test]
fn a_ball_on_a_seifert_weber_vertex_has_a_copy_in_each_of_its_20_cells() {
    // In the tiling {5,3,5} twenty dodecahedra meet at each vertex (the
    // vertex figure is an icosahedron, 20 faces); four of them are four or
    // five crossings from the home cell. A small ball on a vertex of the
    // domain reaches into it from each: 20 copies, all distinct.
    let s = catalog::seifert_weber();
    for v in s.vertices().iter().take(4) {
        let ghosts = bevy_manifold_core::trace::ghost_elements(&s, v.point, 0.05);
        assert_eq!(ghosts.len(), 20, "vertex on faces {:?}", v.faces);
        let mut ids: Vec<_> = ghosts.iter().map(|h| s.cell_id(h)).collect();
        ids.sort();
        ids.dedup();
        assert_eq!(ids.len(), 20);
        // Each copy's centre is the vertex of D it sits on: at the
        // circumradius from the origin, within rounding.
        for h in &ghosts {
            let c = Geometry::Hyperbolic.normalize_point::<f64>(*h * v.point);
            let d = Geometry::Hyperbolic.distance::<f64>(DVec4::W, c);
            assert!((d - s.circumradius()).abs() < 1e-9, "a copy's centre at {d}");
        }
    }
    // In the torus, a ball on a corner of the cube: 8 cubes meet there.
    let t = catalog::torus(1.0);
    let corner = t.vertices()[0].point;
    assert_eq!(bevy_manifold_core::trace::ghost_elements(&t, corner, 0.05).len(), 8);
}
