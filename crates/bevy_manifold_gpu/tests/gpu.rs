//! The WGSL tracer on a real wgpu device (lavapipe in CI) against the CPU
//! reference: same scene, same view, pixel by pixel.
//!
//! Without a GPU adapter these tests are listed as ignored; under CI
//! (`CI` set) a missing adapter is a failure.

use bevy_manifold_core::prelude::*;
use bevy_manifold_core::trace::srgb8;

use bevy_manifold_test_support::{agreement, tracer};

fn gpu_and_cpu_agree_in_every_space() {
    let mut gpu = tracer();
    for name in catalog::NAMES {
        let space = catalog::by_name(name).expect("catalog");
        agree(&mut gpu, name, &space);
    }
}

/// Spaces built from generators by their Dirichlet domains are traced like
/// the catalog's: up to 20 faces (the Weeks manifold), a glide reflection,
/// lens and prism domains, a screw space on a hexagonal lattice, and
/// the domains without vertices: RP3's hemisphere and the lenses of
/// L(3, 1) and L(5, 1), whose rims lie at the chart's infinity.
fn gpu_and_cpu_agree_in_spaces_built_from_generators() {
    let mut gpu = tracer();
    for name in [
        "rp3",
        "lens-3-1",
        "lens-5-1",
        "binary-octahedral",
        "lens-8-3",
        "prism-5",
        "torus-bcc",
        "third-turn",
        "hantzsche-wendt",
        "amphicosm",
        "weeks",
    ] {
        let space = bevy_manifold_core::space::library::by_name(name)
            .expect("library")
            .dirichlet_domain()
            .expect("builds");
        agree(&mut gpu, name, &space);
    }
}

/// A ball near the rim of L(5, 1)'s lens, where the lens is thinnest and
/// the ball straddles both faces, seen from the centre along the rim's
/// direction: the GPU's f32 against the CPU's f64, ids and colours.
fn gpu_and_cpu_agree_near_a_lens_rim() {
    use glam::{DMat4, DVec4};
    let mut gpu = tracer();
    let space = bevy_manifold_core::space::library::by_name("lens-5-1")
        .expect("library")
        .dirichlet_domain()
        .expect("builds");
    let axis = space.faces()[0].plane.truncate().normalize();
    let along = axis.any_orthonormal_vector();
    let mut scene = Scene::default_for(&space);
    scene.balls = vec![Ball {
        center: (along * 1.4f64.sin()).extend(1.4f64.cos()),
        radius: 0.08,
        color: [0.9, 0.3, 0.2],
        glow: 0.0,
        pbr: None,
    }];
    // Look from the centre along the rim's direction.
    let forward = (-along).extend(0.0);
    let up = axis.extend(0.0);
    let right = (along.cross(axis)).extend(0.0);
    scene.camera.isometry = DMat4::from_cols(right, up, forward, DVec4::W);
    let settings = TraceSettings {
        width: 160,
        height: 160,
        levels: 8,
        ..TraceSettings::default()
    };
    let g = gpu.render(&space, &scene, &settings).expect("traced");
    let c = render::<f64>(&space, &scene, &settings);
    let (ids, colors) = agreement(&g, &c);
    let seen = c.pixels.iter().filter(|p| p.object == 1).count();
    eprintln!(
        "lens-5-1 near the rim: ids {:.3}%, colours {:.3}%; the rim ball covers {seen} pixels",
        ids * 100.0,
        colors * 100.0
    );
    assert!(seen > 200, "the rim ball is in view: {seen} pixels");
    assert!(ids >= 0.995 && colors >= 0.99, "ids {ids}, colours {colors}");
}

/// The GPU trace against the CPU f32 and f64 references, plain and with
/// fog, per-cell colour and soft shadows, 256x256 at 8 levels.
fn agree(gpu: &mut bevy_manifold_gpu::GpuTracer, name: &str, space: &Space) {
    {
        let space = space.clone();
        for (fog, cells) in [(false, false), (true, true)] {
            let mut scene = Scene::default_for(&space);
            if fog {
                scene.fog = Some(Fog {
                    density: 0.4 / space.inradius(),
                    color: [0.7, 0.75, 0.8],
                });
                // And shadows through the faces (off by default), soft:
                // a light of finite size, its shadow rays aimed at the
                // fifth point of its disc (SOFT_SHADOWS).
                scene.lighting.shadows = true;
                for l in &mut scene.lights {
                    l.radius = 0.15 * space.inradius();
                }
            }
            let settings = TraceSettings {
                width: 256,
                height: 256,
                levels: 8,
                cell_colors: cells,
                light_sample: if fog { 5 } else { 0 },
                ..TraceSettings::default()
            };
            let g = gpu
                .render(&space, &scene, &settings)
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            let c32 = render::<f32>(&space, &scene, &settings);
            let c64 = render::<f64>(&space, &scene, &settings);
            let (ids32, col32) = agreement(&g, &c32);
            let (ids64, col64) = agreement(&g, &c64);
            let far = g
                .pixels
                .iter()
                .zip(&c64.pixels)
                .filter(|(p, q)| p.cell.is_far() || q.cell.is_far())
                .count();
            eprintln!(
                "{name:<22} fog {fog:<5} cells {cells:<5}: GPU vs CPU f32: ids {:.3}%, colour {:.3}%; vs CPU f64: ids {:.3}%, colour {:.3}% ({far} far-cell pixels)",
                ids32 * 100.0,
                col32 * 100.0,
                ids64 * 100.0,
                col64 * 100.0
            );
            if std::env::var_os("GPU_DIAG").is_some() {
                let mut obj = 0;
                let mut cell_only = 0;
                let mut hist = [0usize; 10];
                for (p, q) in g.pixels.iter().zip(&c64.pixels) {
                    if p.object != q.object {
                        obj += 1;
                        hist[q.levels.min(9) as usize] += 1;
                    } else if p.cell != q.cell && !q.cell.is_far() && !p.cell.is_far() {
                        cell_only += 1;
                        hist[q.levels.min(9) as usize] += 1;
                    }
                }
                eprintln!("  object differs {obj}, cell only {cell_only}, by reference level {hist:?}");
            }
            assert!(
                ids64 >= 0.995,
                "{name}: only {:.3}% of pixels have the f64 reference's object and cell",
                ids64 * 100.0
            );
            assert!(
                col64 >= 0.99,
                "{name}: only {:.3}% of pixels within 2/255 of the f64 reference",
                col64 * 100.0
            );
        }
    }
}

/// Culling on the GPU changes nothing: the same pixels with it on and off
/// (`FLAG_NO_CULL`), in every catalog space and the 20-face Weeks
/// manifold, with the default scene (edges and joints masked), the
/// paper's (Suzanne on the camera, the hands: masked mesh ghosts) and a
/// swarm of 120 small balls (most in the ball tree).
fn gpu_culling_leaves_the_image_unchanged() {
    let mut gpu = tracer();
    let mut spaces: Vec<(String, Space)> = catalog::NAMES
        .iter()
        .map(|n| (n.to_string(), catalog::by_name(n).expect("catalog")))
        .collect();
    spaces.push(("weeks".into(), catalog::resolve("weeks").expect("library")));
    // 52 faces: faces past the 32nd fold onto the masks' bits.
    let (x, y, z) = bevy_manifold_test_support::stress::FIFTY_TWO_FACES;
    let sw52 = bevy_manifold_test_support::stress::seifert_weber_about(x, y, z).expect("builds");
    spaces.push(("seifert-weber/52".into(), sw52));
    for (name, space) in spaces {
        for (what, scene) in [
            ("default", Scene::default_for(&space)),
            ("paper", Scene::paper_default(&space)),
            ("swarm", bevy_manifold_test_support::stress::swarm(&space, 120, 7)),
        ] {
            let on = TraceSettings {
                width: 128,
                height: 96,
                levels: 8,
                ..TraceSettings::default()
            };
            let off = TraceSettings {
                cull: false,
                ..on.clone()
            };
            let a = gpu
                .render(&space, &scene, &on)
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            let b = gpu
                .render(&space, &scene, &off)
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            let differ = a.pixels.iter().zip(&b.pixels).filter(|(p, q)| p != q).count();
            let hit = a.pixels.iter().filter(|p| p.object != 0).count();
            eprintln!(
                "{name:<22} {what:<8}: {differ} of {} pixels differ, {hit} see objects",
                a.pixels.len()
            );
            assert_eq!(differ, 0, "{name} {what}: culling changed {differ} pixels");
            assert!(hit > 100, "{name} {what}: the view sees objects ({hit})");
        }
    }
}

/// The pixel column that sees horizontal angle `deg` (left negative), in a
/// square image of side `n` with vertical field of view `fov` degrees.
fn column(deg: f64, n: u32, fov: f64) -> u32 {
    let x = deg.to_radians().tan() / (fov / 2.0).to_radians().tan();
    ((x + 1.0) / 2.0 * f64::from(n)).floor() as u32
}

fn a_ball_straddling_a_torus_face_is_seen_whole_from_either_side() {
    use glam::{DMat4, DVec3, DVec4};
    let mut gpu = tracer();
    let space = catalog::torus(1.0);
    let n = 128;
    let fov = 100.0;
    // The ball straddles the face x = 1/2; its ghost sits at x = -0.55.
    let ball = Ball {
        center: DVec4::new(0.45, 0.0, 0.0, 1.0),
        radius: 0.1,
        color: [1.0; 3],
        glow: 0.0,
        pbr: None,
    };
    // Each camera looks along -z from 0.4 in front of the face, 0.05 from
    // it. Probes: horizontal angle, and the levels a ray needs to reach the
    // ball there (0: this side of the face, 1: through the face).
    let views = [
        // +x side: the ball is straight ahead; right of about 8 degrees
        // its surface lies beyond x = 1/2, drawn from its ghost.
        (0.45, [(-10.0, 0), (10.0, 1)]),
        // -x side: the ghost at -0.55 is ahead and left; its sliver
        // x > -1/2 is seen directly, the rest through the face x = -1/2.
        (-0.45, [(-3.0, 0), (-15.0, 1)]),
    ];
    for (x, probes) in views {
        let scene = Scene {
            camera: bevy_manifold_core::trace::Camera {
                isometry: DMat4::from_translation(DVec3::new(x, 0.0, 0.4)),
                fov_y_degrees: fov,
                frustum: None,
                cell: Vec::new(),
            },
            balls: vec![ball.clone()],
            lights: vec![],
            meshes: Vec::new(),
            lighting: Lighting::default(),
            skipped: Vec::new(),
            edge_radius: None,
            fog: None,
        };
        let settings = TraceSettings {
            width: n,
            height: n,
            ..TraceSettings::default()
        };
        let g = gpu.render(&space, &scene, &settings).expect("trace");
        let c = render::<f64>(&space, &scene, &settings);
        for (deg, levels) in probes {
            let (i, j) = (column(deg, n, fov), n / 2);
            let (p, q) = (g.at(i, j), c.at(i, j));
            assert_eq!(
                (p.object, p.levels),
                (1, levels),
                "camera x {x}: at {deg} degrees the GPU sees {p:?}"
            );
            assert_eq!((q.object, q.levels), (1, levels), "camera x {x}: CPU at {deg} degrees");
        }
        // Beyond the disc's edge (14.5 degrees about 0, or 14 about -14)
        // the ray passes this ball and its ghost (it may hit a far copy).
        let outside = if x > 0.0 { 25.0 } else { -35.0 };
        let p = g.at(column(outside, n, fov), n / 2);
        assert!(
            p.object == 0 || p.distance > 1.0,
            "camera x {x}: at {outside} degrees {p:?}"
        );
    }
}

fn the_fragment_entry_draws_what_the_compute_entry_computes() {
    let mut gpu = tracer();
    for name in ["torus", "seifert-weber", "poincare"] {
        let space = catalog::by_name(name).expect("catalog");
        let scene = Scene::default_for(&space);
        let settings = TraceSettings {
            width: 96,
            height: 64,
            ..TraceSettings::default()
        };
        let compute = gpu.render(&space, &scene, &settings).expect("compute");
        let fragment = gpu.render_fragment(&space, &scene, &settings).expect("fragment");
        assert_eq!(fragment.len(), 96 * 64 * 4);
        let close = fragment
            .chunks_exact(4)
            .zip(&compute.pixels)
            .filter(|(f, p)| (0..3).all(|c| f[c].abs_diff(srgb8(p.color[c])) <= 1) && f[3] == 255)
            .count();
        let share = close as f64 / compute.pixels.len() as f64;
        eprintln!("{name}: fragment vs compute within 1/255: {:.3}%", share * 100.0);
        assert!(share >= 0.995, "{name}: {:.3}%", share * 100.0);
    }
}

/// A light exactly on the hit point (the CPU twin's test,
/// `a_light_on_the_hit_point_lights_it_head_on_never_nan`): the GPU
/// lights it head-on too, finite, as the CPU does in f32.
fn a_light_on_the_hit_point_is_lit_head_on_on_the_gpu() {
    let mut gpu = tracer();
    let (s, scene) = bevy_manifold_test_support::stress::light_on_the_hit(0.125);
    let settings = TraceSettings {
        width: 3,
        height: 3,
        ..TraceSettings::default()
    };
    let g = *gpu.render(&s, &scene, &settings).expect("render").at(1, 1);
    let c = *render::<f32>(&s, &scene, &settings).at(1, 1);
    assert_eq!(g.object, 1);
    for k in 0..3 {
        assert!(g.color[k].is_finite(), "{:?}", g.color);
        assert!(
            (g.color[k] - c.color[k]).abs() <= 1e-4 * c.color[k],
            "channel {k}: GPU {} CPU {}",
            g.color[k],
            c.color[k]
        );
    }
}

/// The lights are a uniform array of `MAX_LIGHTS`: a scene with that many,
/// all dark but the last, is lit by the last on the GPU as on the CPU
/// reference (an array that held fewer would leave it at ambient light);
/// past `MAX_LIGHTS` the GPU lights by the first `MAX_LIGHTS`, as the ECS
/// layer does, and renders without a validation error.
fn the_last_of_the_most_lights_lights_the_gpu_scene() {
    use bevy_manifold_core::trace::MAX_LIGHTS;
    let mut gpu = tracer();
    let space = catalog::by_name("seifert-weber").expect("catalog");
    let mut scene = Scene::default_for(&space);
    let bright = scene.lights[0].clone();
    let dark = Light {
        intensity: 0.0,
        ..bright.clone()
    };
    scene.lights = vec![dark.clone(); MAX_LIGHTS - 1];
    scene.lights.push(bright.clone());
    let settings = TraceSettings {
        width: 96,
        height: 54,
        levels: 4,
        ..TraceSettings::default()
    };
    let (g, _) = gpu_against_cpu(&mut gpu, &space, &scene, &settings, "64 lights, the last lit");
    let mut unlit = scene.clone();
    unlit.lights = vec![dark.clone(); MAX_LIGHTS];
    let u = gpu.render(&space, &unlit, &settings).expect("render");
    let brighter = g
        .pixels
        .iter()
        .zip(&u.pixels)
        .filter(|(a, b)| a.color[0] + a.color[1] + a.color[2] > 1.5 * (b.color[0] + b.color[1] + b.color[2]) + 1e-3)
        .count();
    assert!(
        brighter > g.pixels.len() / 10,
        "the last light brightens {brighter} of {} pixels",
        g.pixels.len()
    );
    let mut more = scene.clone();
    more.lights.extend(vec![bright; 6]);
    let m = gpu.render(&space, &more, &settings).expect("render past MAX_LIGHTS");
    assert!(
        m.pixels.iter().zip(&g.pixels).all(|(a, b)| a == b),
        "lights past MAX_LIGHTS change nothing on the GPU"
    );
}

/// Glowing balls with no light in the scene, in a flat, a hyperbolic and
/// a spherical space: what the shading rule predicts (unlit, a ball shows
/// its albedo times ambient plus glow, at every distance), on the GPU as
/// on the CPU, and the edges (no glow) stay dark.
fn glowing_balls_show_their_glow_in_the_dark_on_the_gpu() {
    let mut gpu = tracer();
    for name in ["torus", "seifert-weber", "poincare"] {
        let space = catalog::by_name(name).expect("catalog");
        let mut scene = Scene::default_for(&space);
        scene.lights.clear();
        let albedo = [0.9f32, 0.6, 0.2];
        let glow = 2.0f32;
        for b in &mut scene.balls {
            b.color = albedo;
            b.glow = glow;
        }
        let settings = TraceSettings {
            width: 96,
            height: 96,
            levels: 6,
            ..TraceSettings::default()
        };
        let g = gpu
            .render(&space, &scene, &settings)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let c = render::<f32>(&space, &scene, &settings);
        let (ids, colour) = agreement(&g, &c);
        assert!(ids >= 0.995 && colour >= 0.99, "{name}: ids {ids}, colour {colour}");
        let mut balls = 0;
        for p in g.pixels.iter().filter(|p| p.object == 1) {
            balls += 1;
            for (k, (&got, &a)) in p.color.iter().zip(&albedo).enumerate() {
                let want = a * (0.08 + glow);
                assert!(
                    (got - want).abs() <= 1e-5 * want,
                    "{name}: channel {k} of a glowing ball is {got}, not {want}"
                );
            }
        }
        assert!(balls > 50, "{name}: the ball is seen ({balls} pixels)");
        let edge = g.pixels.iter().find(|p| p.object == bevy_manifold_core::trace::EDGE_ID);
        if let Some(e) = edge {
            assert!(
                e.color.iter().all(|&x| x < 0.1),
                "{name}: an unlit edge glows {:?}",
                e.color
            );
        }
    }
}

/// The WGSL panoramas (`view_ray`) against the CPU f64 reference's, in a
/// flat, a hyperbolic and a spherical space, mono and stereo.
fn gpu_panoramas_agree_with_the_cpu_reference() {
    use bevy_manifold_core::trace::Projection;
    let mut gpu = tracer();
    for name in ["torus", "seifert-weber", "poincare"] {
        let space = catalog::by_name(name).expect("catalog");
        let scene = Scene::default_for(&space);
        for projection in [
            Projection::Equirect,
            Projection::Ods {
                eye_separation: 0.3 * space.inradius(),
            },
        ] {
            let settings = TraceSettings {
                width: 256,
                height: 128,
                levels: 6,
                projection,
                ..TraceSettings::default()
            };
            let (_, c64) = gpu_against_cpu(
                &mut gpu,
                &space,
                &scene,
                &settings,
                &format!("{name:<14} {projection:?}"),
            );
            let hit = c64.pixels.iter().filter(|p| p.object != 0).count();
            assert!(
                hit > c64.pixels.len() / 10,
                "{name}: the panorama sees something ({hit})"
            );
        }
    }
}

/// Reflections (`REFLECTIONS`) on the GPU against the CPU f64 reference:
/// the paper's Fig. 11 scene (the mirror ball, Suzanne on the camera, the
/// hands, the edges) in the torus, Seifert-Weber and the Poincare sphere,
/// at five levels, with one reflection, then two with fog, with and
/// without cones (those
/// against the CPU's f32 twin); and the mirror shows
/// something other than its own shading once reflections are on (where
/// its reflection meets an object within the levels, a fifth of it or
/// more: the rest sees the black beyond them), so that the agreement is
/// that of reflections.
fn gpu_reflections_agree_with_the_cpu_reference() {
    use bevy_manifold_core::trace::PaperOptions;
    let mut gpu = tracer();
    for space in [catalog::torus(1.0), catalog::seifert_weber(), catalog::poincare()] {
        let options = PaperOptions {
            mirror: true,
            ..PaperOptions::default()
        };
        let mut scene = Scene::paper(&space, &options);
        // Five levels: past them a reflected ray's f32 walk in H3 drifts
        // from the f64 reference's on 2% of Seifert-Weber's pixels (the
        // CPU's f32 twin as much as the GPU), as a camera ray does further
        // out.
        let plain = TraceSettings {
            width: 160,
            height: 120,
            levels: 5,
            ..TraceSettings::default()
        };
        let one = TraceSettings {
            reflections: 1,
            ..plain.clone()
        };
        let name = space.name().to_string();
        let (with, _) = gpu_against_cpu(&mut gpu, &space, &scene, &one, &format!("{name}, one reflection"));
        let without = gpu.render(&space, &scene, &plain).expect("traced");
        // The mirror ball is the last ball of the scene.
        let mirror_id = scene.balls.len() as u32;
        let on_mirror: Vec<usize> = (0..with.pixels.len())
            .filter(|&i| without.pixels[i].object == mirror_id)
            .collect();
        let changed = on_mirror
            .iter()
            .filter(|&&i| {
                let (a, b) = (with.pixels[i].color, without.pixels[i].color);
                (0..3).any(|c| (a[c] - b[c]).abs() > 0.05)
            })
            .count();
        assert!(
            on_mirror.len() > 500 && changed * 5 > on_mirror.len(),
            "{name}: {changed} of the mirror's {} pixels show a reflection",
            on_mirror.len()
        );
        scene.fog = Some(Fog {
            density: 0.3 / space.inradius(),
            color: [0.7, 0.75, 0.8],
        });
        let two = TraceSettings {
            reflections: 2,
            footprint: true,
            ..plain.clone()
        };
        gpu_against_cpu(
            &mut gpu,
            &space,
            &scene,
            &TraceSettings {
                footprint: false,
                ..two.clone()
            },
            &format!("{name}, two reflections, fog"),
        );
        // Cones against the CPU's f32 twin, to the bounds of the cone
        // test (gpu_cone_tracing_agrees_with_the_cpu_reference): layers of
        // nearly equal approaches stack in another order under another
        // f32 sin or atan2 on 1-3% of pixels.
        let g = gpu.render(&space, &scene, &two).expect("traced");
        let (ids, colour) = agreement(&g, &render::<f32>(&space, &scene, &two));
        eprintln!("{name}, two reflections, fog, cones: GPU vs CPU f32: ids {ids:.5}, colour {colour:.5}");
        assert!(
            ids >= 0.999 && colour >= 0.97,
            "{name}, two reflections, fog, cones: ids {ids}, colours {colour} against the CPU f32"
        );
    }
}

/// Per-pixel means and squared standard errors (red, green, blue summed)
/// of `samples` path samples.
fn path_means(samples: &[TraceImage]) -> Vec<(f64, f64)> {
    let n = samples.len() as f64;
    (0..samples[0].pixels.len())
        .map(|i| {
            let xs: Vec<f64> = samples
                .iter()
                .map(|img| img.pixels[i].color.iter().map(|&c| f64::from(c)).sum())
                .collect();
            let mean = xs.iter().sum::<f64>() / n;
            let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
            (mean, var / n)
        })
        .collect()
}

/// The GPU path tracer (`PATH_TRACE`) against the CPU's f32 twin in
/// distribution: per-pixel means of 16 samples within 4 standard errors
/// (or 2/255) of each other on 99% of pixels, in the torus,
/// Seifert-Weber and the Poincare sphere (the default scene with a
/// glossy metal ball, shadows and fog); and the white furnace on the
/// GPU: a box of albedo 0.5 emitting 0.25 about the camera glows at 0.5.
fn gpu_path_tracer_agrees_in_distribution_with_the_cpu() {
    use bevy_manifold_core::material::{MeshMaterial, Pbr};
    use bevy_manifold_core::mesh::{MeshData, TriMesh};
    use bevy_manifold_core::trace::SceneMesh;
    let mut gpu = tracer();
    for space in [catalog::torus(1.0), catalog::seifert_weber(), catalog::poincare()] {
        let mut scene = Scene::default_for(&space);
        scene.balls[0].pbr = Some(Pbr {
            metallic: 1.0,
            roughness: 0.3,
        });
        // A glowing ball beside it: the paths aim at it and weigh both
        // ways of meeting it (multiple importance sampling).
        let mut lamp = scene.balls[0].clone();
        lamp.center = scene.lights[0].position;
        lamp.radius = 0.15 * space.inradius();
        lamp.color = [1.0, 0.8, 0.5];
        lamp.glow = 4.0;
        lamp.pbr = None;
        scene.balls.push(lamp);
        scene.lighting.shadows = true;
        scene.fog = Some(Fog {
            density: 0.2 / space.inradius(),
            color: [0.6, 0.65, 0.7],
        });
        let settings = TraceSettings {
            width: 48,
            height: 32,
            path_depth: 6,
            seed: 9,
            ..TraceSettings::default()
        };
        let (mut g, mut c) = (Vec::new(), Vec::new());
        for k in 0..16 {
            let s = TraceSettings {
                light_sample: k,
                ..settings.clone()
            };
            g.push(gpu.render(&space, &scene, &s).expect("traced"));
            c.push(render::<f32>(&space, &scene, &s));
        }
        let (mg, mc) = (path_means(&g), path_means(&c));
        let agree = mg
            .iter()
            .zip(&mc)
            .filter(|((a, va), (b, vb))| (a - b).abs() <= 4.0 * (va + vb).sqrt() || (a - b).abs() <= 2.0 / 255.0)
            .count();
        let ids = g[0]
            .pixels
            .iter()
            .zip(&c[0].pixels)
            .filter(|(p, q)| p.object == q.object && (p.cell == q.cell || p.cell.is_far() || q.cell.is_far()))
            .count();
        eprintln!(
            "{}: path means agree on {agree} of {} pixels, first-hit objects and cells on {ids}",
            space.name(),
            mg.len()
        );
        assert!(
            agree * 100 >= mg.len() * 99,
            "{}: {agree} of {}",
            space.name(),
            mg.len()
        );
        assert!(
            ids * 1000 >= mg.len() * 995,
            "{}: ids {ids} of {}",
            space.name(),
            mg.len()
        );
    }
    // The white furnace on the GPU.
    let space = catalog::torus(1.0);
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for axis in 0..3 {
        for sign in [-0.3f32, 0.3] {
            let base = positions.len() as u32;
            for (u, v) in [(-0.3f32, -0.3f32), (0.3, -0.3), (0.3, 0.3), (-0.3, 0.3)] {
                let mut p = [0.0; 3];
                p[axis] = sign;
                p[(axis + 1) % 3] = u;
                p[(axis + 2) % 3] = v;
                positions.push(p);
            }
            triangles.push([base, base + 1, base + 2]);
            triangles.push([base, base + 2, base + 3]);
        }
    }
    let mesh = TriMesh::new(positions, None, None, triangles).expect("a box");
    let mut scene = Scene::empty();
    scene.camera.isometry = glam::DMat4::IDENTITY;
    scene.meshes.push(SceneMesh::new(
        MeshData::shared(mesh),
        MeshMaterial {
            base_color: [0.5; 3],
            emissive: [0.25; 3],
            ..MeshMaterial::default()
        },
        glam::DMat4::IDENTITY,
        1.0,
    ));
    let mut all = Vec::new();
    for k in 0..16 {
        let s = TraceSettings {
            width: 32,
            height: 24,
            path_depth: 40,
            light_sample: k,
            ..TraceSettings::default()
        };
        all.extend(
            gpu.render(&space, &scene, &s)
                .expect("traced")
                .pixels
                .iter()
                .map(|p| f64::from(p.color[0])),
        );
    }
    let n = all.len() as f64;
    let mean = all.iter().sum::<f64>() / n;
    let error = (all.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0) / n).sqrt();
    eprintln!("GPU white furnace: {mean} +- {error}, want 0.5");
    assert!((mean - 0.5).abs() < 4.0 * error && error < 0.01, "{mean} +- {error}");
}

/// The GPU's image and the CPU f64 reference's of one scene, which must
/// agree on 99.5% of ids and 99% of colours; `what` names the case.
fn gpu_against_cpu(
    gpu: &mut bevy_manifold_gpu::GpuTracer,
    space: &Space,
    scene: &Scene,
    settings: &TraceSettings,
    what: &str,
) -> (TraceImage, TraceImage) {
    let g = gpu
        .render(space, scene, settings)
        .unwrap_or_else(|e| panic!("{what}: {e}"));
    let c64 = render::<f64>(space, scene, settings);
    let (ids, colour) = agreement(&g, &c64);
    eprintln!(
        "{what}: GPU vs CPU f64: ids {:.3}%, colour {:.3}%",
        ids * 100.0,
        colour * 100.0
    );
    assert!(ids >= 0.995, "{what}: ids agree on {:.3}%", ids * 100.0);
    assert!(colour >= 0.99, "{what}: colours agree on {:.3}%", colour * 100.0);
    (g, c64)
}

/// An off-centre frustum (a headset's left eye: wider to the left and
/// below) traced by the WGSL `view_slopes` against the CPU f64 reference;
/// and it moves the picture against the symmetric frustum (the desktop's,
/// which both tracers still compute by the old expression).
fn gpu_off_centre_frustums_agree_with_the_cpu_reference() {
    use bevy_manifold_core::trace::Frustum;
    let mut gpu = tracer();
    for name in ["torus", "seifert-weber", "poincare"] {
        let space = catalog::by_name(name).expect("catalog");
        let mut scene = Scene::default_for(&space);
        scene.camera.frustum = Some(Frustum::from_angles(-0.87, 0.70, -0.84, 0.77));
        let settings = TraceSettings {
            width: 200,
            height: 180,
            levels: 6,
            ..TraceSettings::default()
        };
        let (g, _) = gpu_against_cpu(
            &mut gpu,
            &space,
            &scene,
            &settings,
            &format!("{name:<14} off-centre frustum"),
        );
        // The frustum moved the image: the symmetric view differs.
        scene.camera.frustum = None;
        let sym = gpu.render(&space, &scene, &settings).expect("trace");
        let moved = sym
            .pixels
            .iter()
            .zip(&g.pixels)
            .filter(|(a, b)| a.object != b.object)
            .count();
        assert!(moved > sym.pixels.len() / 50, "{name}: only {moved} pixels moved");
    }
}

/// Cone tracing (`TraceSettings::footprint`, `footprint.wgsl`) on the GPU
/// against the CPU's: the f32 mirror runs the same arithmetic, the f64
/// reference the same algorithm; fog and cell colours on in one pass.
fn gpu_cone_tracing_agrees_with_the_cpu_reference() {
    let mut gpu = tracer();
    for name in ["torus", "seifert-weber", "poincare", "mirrored-dodecahedron"] {
        let space = catalog::by_name(name).expect("catalog");
        for fog in [false, true] {
            let mut scene = Scene::default_for(&space);
            if fog {
                scene.fog = Some(Fog {
                    density: 0.3 / space.inradius(),
                    color: [0.7, 0.75, 0.8],
                });
                // Shadow rays under cones too.
                scene.lighting.shadows = true;
            }
            let settings = TraceSettings {
                width: 192,
                height: 108,
                levels: 8,
                cell_colors: fog,
                footprint: true,
                ..TraceSettings::default()
            };
            let g = gpu.render(&space, &scene, &settings).expect("trace");
            let c32 = render::<f32>(&space, &scene, &settings);
            let c64 = render::<f64>(&space, &scene, &settings);
            let (ids32, col32) = agreement(&g, &c32);
            let (ids64, col64) = agreement(&g, &c64);
            eprintln!(
                "{name:<22} fog {fog:<5}: cone GPU vs CPU f32 ids {:.2}% colour {:.2}%, vs f64 ids {:.2}% colour {:.2}%",
                ids32 * 100.0,
                col32 * 100.0,
                ids64 * 100.0,
                col64 * 100.0
            );
            // A plain trace differs: the cone's layers change pixels.
            let plain = gpu
                .render(
                    &space,
                    &scene,
                    &TraceSettings {
                        footprint: false,
                        ..settings.clone()
                    },
                )
                .expect("trace");
            let (_, col_plain) = agreement(&plain, &c64);
            eprintln!(
                "{name:<22} fog {fog:<5}: plain GPU vs cone CPU f64 colour {:.2}%",
                col_plain * 100.0
            );
            // Layers sorted by nearly equal approaches (the tubes and the
            // joint meeting at a vertex) may stack in another order under
            // another f32 sin or atan2: 1-3% of pixels, in S3 most.
            for (what, ids, col) in [("f32", ids32, col32), ("f64", ids64, col64)] {
                assert!(
                    ids >= 0.999,
                    "{name} fog {fog}: ids agree with the CPU {what} on {:.2}%",
                    ids * 100.0
                );
                assert!(
                    col >= 0.97,
                    "{name} fog {fog}: colours agree with the CPU {what} on {:.2}%",
                    col * 100.0
                );
            }
            assert!(
                col_plain < 0.7,
                "{name}: the cone's image is not the plain one ({:.2}%)",
                col_plain * 100.0
            );
        }
    }
}

/// Timing a trace on the device (what `bench stereo` and `bench compare`
/// report) gives finite positive times, by the adapter's own clock where it
/// has timestamps (lavapipe has), refuses bad settings by name, and leaves
/// the tracer drawing exactly what it drew before.
fn timing_a_trace_reports_device_time_and_changes_nothing() {
    let mut gpu = tracer();
    let space = catalog::by_name("seifert-weber").expect("catalog");
    let scene = Scene::default_for(&space);
    let settings = TraceSettings {
        width: 64,
        height: 36,
        levels: 4,
        ..TraceSettings::default()
    };
    let before = gpu.render(&space, &scene, &settings).expect("render");
    let t = gpu.time_trace(&space, &scene, &settings, 4).expect("timed");
    eprintln!("64x36 Seifert-Weber, 4 levels: {t:?}");
    assert!(t.wall_ms.is_finite() && t.wall_ms > 0.0, "{t:?}");
    let device = t.device_ms.expect("lavapipe and desktop GPUs have timestamp queries");
    assert!(device.is_finite() && device > 0.0, "{t:?}");
    let after = gpu.render(&space, &scene, &settings).expect("render");
    assert_eq!(before.pixels, after.pixels, "timing changed what the tracer draws");
    let bad = TraceSettings { width: 0, ..settings };
    let err = gpu
        .time_trace(&space, &scene, &bad, 4)
        .expect_err("zero width")
        .to_string();
    assert!(err.contains("0x36 pixels"), "{err}");
}

/// A tour's frames through one tracer, which keeps the packed table of
/// exact ids between calls: the camera in the origin copy, in another copy
/// (the table centred anew), back, then another space with as many faces,
/// then the first again. Each frame is what a fresh tracer, which keeps
/// nothing, draws: ids, levels, cells and colours.
fn kept_tables_draw_what_fresh_ones_do() {
    let mut kept = tracer();
    let settings = TraceSettings {
        width: 48,
        height: 27,
        levels: 6,
        ..TraceSettings::default()
    };
    let sw = catalog::by_name("seifert-weber").expect("catalog");
    let md = catalog::by_name("mirrored-dodecahedron").expect("catalog");
    let g = Geometry::Hyperbolic;
    let at = |space: &Space, x: f64| {
        let mut scene = Scene::default_for(space);
        scene.camera.isometry = bevy_manifold_core::geometry::isometry::translation(g, glam::DVec3::new(x, 0.1, 0.0))
            * scene.camera.isometry;
        scene
    };
    let mut cells = Vec::new();
    for (space, x) in [
        (&sw, 0.0),
        (&sw, 0.3),
        (&sw, 2.5),
        (&sw, 0.3),
        (&md, 0.3),
        (&md, 2.5),
        (&sw, 2.5),
    ] {
        let scene = at(space, x);
        let a = kept.render(space, &scene, &settings).expect("kept");
        let b = tracer().render(space, &scene, &settings).expect("fresh");
        assert_eq!(a.pixels, b.pixels, "{} at x = {x}", space.name());
        cells.push(bevy_manifold_core::trace::FlatScene::<f32>::new(space, &scene).camera_element);
    }
    // The camera did change copies, so the table was centred anew.
    assert_ne!(cells[1], cells[2], "x = 2.5 is in another copy");
    assert_ne!(cells[4], cells[5], "x = 2.5 is in another copy");
}

/// Every face of a domain of more than 16 faces, which the shader's face
/// loops take in chunks of 16 (`FACE_CHUNK` in `step.wgsl`), is crossed
/// on the GPU where the CPU f64 reference crosses it: the ray from the
/// centre through each face's middle (away from every edge), one level,
/// ends in the same cell, the one across that face, a different cell for
/// each face. In the Weeks manifold and Seifert-Weber's 52-face domain.
fn every_face_of_large_domains_is_crossed_on_the_gpu() {
    use glam::{DMat3, DMat4, DQuat, DVec3};
    let mut gpu = tracer();
    let (x, y, z) = bevy_manifold_test_support::stress::FIFTY_TWO_FACES;
    let weeks = bevy_manifold_core::space::library::by_name("weeks")
        .expect("library")
        .dirichlet_domain()
        .expect("builds");
    let sw52 = bevy_manifold_test_support::stress::seifert_weber_about(x, y, z).expect("builds");
    for (name, space) in [("weeks", weeks), ("seifert-weber/52", sw52)] {
        assert!(space.faces().len() > 16, "{name}: {} faces", space.faces().len());
        let settings = TraceSettings {
            width: 1,
            height: 1,
            levels: 1,
            ..TraceSettings::default()
        };
        let mut cells = std::collections::HashSet::new();
        for f in 0..space.faces().len() {
            let towards = bevy_manifold_test_support::stress::face_middle(&space, f)
                .truncate()
                .normalize();
            let mut scene = Scene::empty();
            scene.camera.isometry = DMat4::from_mat3(DMat3::from_quat(DQuat::from_rotation_arc(DVec3::NEG_Z, towards)));
            let g = gpu
                .render(&space, &scene, &settings)
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            let c = render::<f64>(&space, &scene, &settings);
            assert_eq!(
                c.pixels[0].levels, 1,
                "{name}, face {f}: the reference crosses one face"
            );
            assert_eq!(g.pixels[0].levels, 1, "{name}, face {f}: the GPU crosses one face");
            assert_eq!(
                g.pixels[0].cell, c.pixels[0].cell,
                "{name}, face {f}: another cell than the reference's"
            );
            cells.insert(c.pixels[0].cell);
        }
        assert_eq!(
            cells.len(),
            space.faces().len(),
            "{name}: each face leads to its own neighbour"
        );
    }
}

/// Every edge tube of Seifert-Weber's 52-face domain, keyed by its two
/// faces' bits, by one of them, or (5 of its 150 tubes, where two edges
/// fold onto the same bits) by none, is drawn on the GPU where the CPU
/// f64 reference draws it: the ray from the centre through the middle of
/// each edge (no central ball) meets the edges' object in the first cell,
/// at the reference's distance. A walk that drops a tube shows here,
/// where a whole image hides it (a dropped unkeyed tube changed 1 pixel
/// of 65,536).
fn every_tube_of_a_large_domain_is_hit_on_the_gpu() {
    use bevy_manifold_core::trace::{EDGE_ID, FlatScene};
    use glam::{DMat3, DMat4, DQuat, DVec3};
    let mut gpu = tracer();
    let (x, y, z) = bevy_manifold_test_support::stress::FIFTY_TWO_FACES;
    let space = bevy_manifold_test_support::stress::seifert_weber_about(x, y, z).expect("builds");
    let mut scene = Scene::default_for(&space);
    scene.balls.clear();
    let flat = FlatScene::<f64>::new(&space, &scene);
    assert!(
        flat.tubes.iter().any(|t| t.edge == 0),
        "the domain has tubes with no edge bits"
    );
    let settings = TraceSettings {
        width: 1,
        height: 1,
        levels: 2,
        ..TraceSettings::default()
    };
    for (i, edge) in space.edges().iter().enumerate() {
        let [a, b] = edge.vertices.map(|v| space.vertices()[v].point);
        let middle = space.geometry().normalize_point::<f64>(a + b);
        let towards = middle.truncate().normalize();
        scene.camera.isometry = DMat4::from_mat3(DMat3::from_quat(DQuat::from_rotation_arc(DVec3::NEG_Z, towards)));
        let g = gpu.render(&space, &scene, &settings).expect("render").pixels[0];
        let c = render::<f64>(&space, &scene, &settings).pixels[0];
        assert!(
            c.object == EDGE_ID && c.levels == 0,
            "edge {i}: the reference sees {} at level {}",
            c.object,
            c.levels
        );
        assert!(
            g.object == EDGE_ID && g.levels == 0 && (g.distance - c.distance).abs() <= 1e-4 * c.distance.max(1.0),
            "edge {i}: the GPU sees {} at level {}, distance {} (the reference {})",
            g.object,
            g.levels,
            g.distance,
            c.distance
        );
    }
}

/// A scene whose balls make more copies than the balls' uniform array
/// holds (254 large balls in the torus, each with a ghost across every
/// face it reaches) is refused by name, not drawn wrong or panicking; the
/// same tracer then draws the default scene exactly as a fresh one does.
fn too_many_ball_copies_are_refused_by_name() {
    use bevy_manifold_core::trace::{Ball, FlatScene};
    use bevy_manifold_gpu::bindings::MAX_BALLS;
    let space = catalog::by_name("torus").expect("catalog");
    let mut scene = Scene::default_for(&space);
    let mut rng = bevy_manifold_test_support::Rng(5);
    while scene.balls.len() < 254 {
        scene.balls.push(Ball {
            center: rng.ray_inside(&space).origin,
            radius: 0.9 * space.inradius(),
            color: [0.5, 0.5, 0.5],
            glow: 0.0,
            pbr: None,
        });
    }
    let flat = FlatScene::<f32>::new(&space, &scene);
    let copies = flat.balls.len();
    assert!(copies > MAX_BALLS, "the scene makes only {copies} balls");
    // What the render pass uploads (it draws the first MAX_BALLS, with a
    // warning): no group reaches past them.
    let packed = bevy_manifold_gpu::GpuObjects::pack(&flat);
    assert_eq!(packed.balls.len(), MAX_BALLS);
    assert!(
        packed.groups.iter().all(|g| g[0] as usize <= MAX_BALLS),
        "{:?}",
        packed.groups
    );
    let settings = TraceSettings {
        width: 32,
        height: 18,
        levels: 2,
        ..TraceSettings::default()
    };
    let mut gpu = tracer();
    let err = gpu
        .render(&space, &scene, &settings)
        .expect_err("too many balls")
        .to_string();
    assert!(
        err.contains(&format!("{copies} balls")) && err.contains(&MAX_BALLS.to_string()),
        "{err}"
    );
    let plain = Scene::default_for(&space);
    let after = gpu.render(&space, &plain, &settings).expect("render");
    let fresh = tracer().render(&space, &plain, &settings).expect("render");
    assert_eq!(
        after.pixels, fresh.pixels,
        "the refused scene changed what the tracer draws"
    );
}

bevy_manifold_test_support::test_main! {
    cpu: [],
    gpu: [
        kept_tables_draw_what_fresh_ones_do,
        timing_a_trace_reports_device_time_and_changes_nothing,
        gpu_cone_tracing_agrees_with_the_cpu_reference,
        glowing_balls_show_their_glow_in_the_dark_on_the_gpu,
        gpu_reflections_agree_with_the_cpu_reference,
        gpu_path_tracer_agrees_in_distribution_with_the_cpu,
        gpu_panoramas_agree_with_the_cpu_reference,
        gpu_off_centre_frustums_agree_with_the_cpu_reference,
        gpu_and_cpu_agree_in_every_space,
        gpu_culling_leaves_the_image_unchanged,
        gpu_and_cpu_agree_in_spaces_built_from_generators,
        gpu_and_cpu_agree_near_a_lens_rim,
        a_ball_straddling_a_torus_face_is_seen_whole_from_either_side,
        the_fragment_entry_draws_what_the_compute_entry_computes,
        a_light_on_the_hit_point_is_lit_head_on_on_the_gpu,
        the_last_of_the_most_lights_lights_the_gpu_scene,
        every_face_of_large_domains_is_crossed_on_the_gpu,
        every_tube_of_a_large_domain_is_hit_on_the_gpu,
        too_many_ball_copies_are_refused_by_name,
    ],
}
