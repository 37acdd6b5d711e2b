//! How many rays a pixel gets: a view traced at half scale and upscaled, an
//! adaptive scale, samples accumulated while still, and cones.

use super::support::*;
use bevy::prelude::*;
use bevy::render::RenderApp;
use bevy_manifold::prelude::*;
use bevy_manifold_gpu::GpuTracer;
use bevy_manifold_test_support::compare::colors;

pub fn a_view_at_half_scale_is_the_half_size_trace_upscaled_bilinearly() {
    let mut app = headless_app(true);
    let image = target(&mut app, W, H);
    for name in ["seifert-weber", "torus"] {
        let space = catalog::by_name(name).expect("catalog");
        let (root, camera) = spawn_view(&mut app, &space, &image, false, false);
        app.world_mut().entity_mut(camera).insert(ManifoldRenderScale(0.5));
        wait_for_pipelines(&mut app);
        let shown = capture(&mut app, &image);
        let scene = gathered_scene(&app, &space, root, false);
        let at = |width, height| {
            let settings = TraceSettings {
                width,
                height,
                levels: 8,
                ..TraceSettings::default()
            };
            render::<f64>(&space, &scene, &settings)
        };
        let half = at(W / 2, H / 2);
        // Independent expectations: the CPU reference at half size
        // upscaled bilinearly (what a GPU sampler does), the same upscaled
        // by nearest pixel (a wrong filter), and the full-size trace (no
        // scaling at all).
        let bilinear = bevy_manifold::trace::upscale(&colors(&half), (W / 2, H / 2), (W, H));
        let nearest: Vec<[f32; 3]> = (0..W * H)
            .map(|k| colors(&half)[((k / W / 2) * (W / 2) + (k % W) / 2) as usize])
            .collect();
        let full = colors(&at(W, H));
        let (b, n, f) = (
            close_to(&shown, &bilinear, 3),
            close_to(&shown, &nearest, 3),
            close_to(&shown, &full, 3),
        );
        eprintln!(
            "{name}: half scale within 3/255 of: bilinear upscale of the half-size CPU trace {:.2}%, nearest {:.2}%, full-size trace {:.2}%",
            b * 100.0,
            n * 100.0,
            f * 100.0
        );
        assert!(
            b >= 0.97,
            "{name}: the upscaled view is not the half-size trace upscaled ({b})"
        );
        assert!(b > n + 0.03, "{name}: bilinear {b} vs nearest {n}");
        assert!(b > f + 0.03, "{name}: bilinear {b} vs full size {f}");
        // Back to full scale: the view is the full-size trace again.
        app.world_mut().entity_mut(camera).insert(ManifoldRenderScale(1.0));
        app.update();
        let back = capture(&mut app, &image);
        assert!(close_to(&back, &full, 2) >= 0.99, "{name}: full scale again");
        app.world_mut().entity_mut(root).despawn();
        app.update();
    }
}

pub fn an_adaptive_scale_lowers_the_pixels_traced_when_frames_are_slow() {
    let mut app = headless_app(true);
    let image = target(&mut app, W, H);
    let space = catalog::poincare();
    let (root, camera) = spawn_view(&mut app, &space, &image, false, false);
    // No machine draws this in 1 ms: the scale must fall to its least.
    app.world_mut()
        .entity_mut(camera)
        .insert(AdaptiveRenderScale::new(1.0).with_range(0.25, 1.0));
    wait_for_pipelines(&mut app);
    let mut seen = Vec::new();
    for _ in 0..40 {
        app.update();
        let s = app.world().get::<ManifoldRenderScale>(camera).map(|s| s.0);
        seen.push(s);
        if s == Some(0.25) {
            break;
        }
    }
    eprintln!("adaptive scales: {seen:?}");
    assert_eq!(seen.last().copied().flatten(), Some(0.25), "{seen:?}");
    let values: Vec<f32> = seen.iter().flatten().copied().collect();
    assert!(
        values.windows(2).all(|w| w[1] <= w[0]),
        "the scale only falls: {values:?}"
    );
    app.update();
    let shown = capture(&mut app, &image);
    let lit = lit_pixels(&shown);
    assert!(lit > (W * H / 4) as usize, "the view still shows the space ({lit} lit)");
    // A quarter of the pixels along each side: the quarter-size CPU
    // trace, upscaled.
    let scene = gathered_scene(&app, &space, root, false);
    let settings = TraceSettings {
        width: W / 4,
        height: H / 4,
        levels: 8,
        ..TraceSettings::default()
    };
    let quarter = render::<f64>(&space, &scene, &settings);
    let expected = bevy_manifold::trace::upscale(&colors(&quarter), (W / 4, H / 4), (W, H));
    let close = close_to(&shown, &expected, 3);
    eprintln!(
        "at scale 0.25: {:.2}% within 3/255 of the quarter-size trace upscaled",
        close * 100.0
    );
    assert!(close >= 0.97, "{close}");
}

pub fn a_still_view_accumulates_jittered_samples_then_stops_tracing() {
    use bevy_manifold::render::pass::ManifoldViewBinding;
    let tracing = |app: &mut App| {
        let world = app.sub_app_mut(RenderApp).world_mut();
        let mut q = world.query::<&ManifoldViewBinding>();
        q.iter(world)
            .map(|b| b.scaled.as_ref().map(|s| s.trace))
            .collect::<Vec<_>>()
    };
    let mut gpu = GpuTracer::new().expect("adapter");
    // In the flat torus a trace hardly depends on the last bit of the
    // frustum; in Seifert-Weber at 8 levels sub-pixel copies do (about 1%
    // of pixels a trace between two f32 tracers, as between f32 and f64),
    // and eight samples spread that over more pixels.
    for (space, bound) in [(catalog::torus(1.0), 0.99), (catalog::seifert_weber(), 0.95)] {
        let name = space.name().to_string();
        let mut app = headless_app(true);
        let image = target(&mut app, W, H);
        let (root, camera) = spawn_view(&mut app, &space, &image, false, false);
        let progress = bevy_manifold::camera::AccumulationProgress::default();
        app.world_mut()
            .entity_mut(camera)
            .insert((ManifoldAccumulation { samples: 8 }, progress.clone()));
        wait_for_pipelines(&mut app);
        for _ in 0..10 {
            app.update();
        }
        let shown = capture(&mut app, &image);
        // All samples in: the pass no longer traces, and says so to the
        // main world.
        assert_eq!(tracing(&mut app), [Some(false)], "{name}");
        assert_eq!(progress.samples(), 8, "{name}");
        let scene = gathered_scene(&app, &space, root, false);
        let settings = TraceSettings {
            width: W,
            height: H,
            levels: 8,
            ..TraceSettings::default()
        };
        // The same 8 jittered traces by the headless GPU tracer (the
        // compute entry, each jitter an off-centre frustum made on the
        // CPU, Frustum::jittered), averaged; and by the CPU f64 reference
        // (its twin, trace::accumulate).
        let base = bevy_manifold::trace::Frustum::symmetric(scene.camera.fov_y_degrees, f64::from(W) / f64::from(H));
        let mut gpu_mean = vec![[0.0f32; 3]; (W * H) as usize];
        for k in 0..8 {
            let mut jittered = scene.clone();
            jittered.camera.frustum = Some(base.jittered(bevy_manifold::trace::sample_offset(k), W, H));
            let img = gpu.render(&space, &jittered, &settings).expect("headless trace");
            for (m, p) in gpu_mean.iter_mut().zip(&img.pixels) {
                for (m, c) in m.iter_mut().zip(p.color) {
                    *m += c / 8.0;
                }
            }
        }
        let cpu_mean = bevy_manifold::trace::accumulate::<f64>(&space, &scene, &settings, 8);
        let plain = colors(&render::<f64>(&space, &scene, &settings));
        let reference = supersampled(&space, &scene, 8);
        let (to_gpu, to_cpu, to_plain) = (
            close_to(&shown, &gpu_mean, 2),
            close_to(&shown, &cpu_mean, 2),
            close_to(&shown, &plain, 2),
        );
        let (p_shown, p_plain) = (psnr(&shown, &reference), psnr(&plain_bytes(&plain), &reference));
        eprintln!(
            "{name}: 8 samples accumulated, within 2/255 of: the headless GPU's mean of the same jittered traces {:.2}%, the CPU f64's {:.2}%, the plain trace {:.2}%; PSNR against 16 spp {p_shown:.2} dB (plain trace {p_plain:.2} dB)",
            to_gpu * 100.0,
            to_cpu * 100.0,
            to_plain * 100.0
        );
        assert!(to_gpu >= bound, "{name}: {to_gpu}");
        assert!(to_cpu >= bound, "{name}: {to_cpu}");
        assert!(to_gpu > to_plain + 0.03, "{name}: {to_gpu} vs {to_plain}");
        assert!(p_shown > p_plain + 2.0, "{name}: {p_shown} vs {p_plain}");
        // The camera moves: the pass traces again from the first sample,
        // and settles on the mean at the new pose.
        let moved = glam::DMat4::from_translation(glam::DVec3::new(0.0, 0.0, -0.02)) * scene.camera.isometry;
        app.world_mut().get_mut::<Placement>(camera).unwrap().isometry = moved;
        app.update();
        assert_eq!(tracing(&mut app), [Some(true)], "{name}");
        assert_eq!(progress.samples(), 1, "{name}: the count starts again");
        for _ in 0..12 {
            app.update();
        }
        let after = capture(&mut app, &image);
        let mut scene_moved = scene.clone();
        scene_moved.camera.isometry = app.world().get::<Placement>(camera).unwrap().isometry;
        let mean_moved = bevy_manifold::trace::accumulate::<f64>(&space, &scene_moved, &settings, 8);
        let agree = close_to(&after, &mean_moved, 2);
        eprintln!(
            "{name}: after a move: {:.2}% within 2/255 of the CPU mean there",
            agree * 100.0
        );
        assert!(agree >= bound, "{name}: {agree}");
    }
}

/// A camera with `ManifoldFootprint` traces cones (the `FOOTPRINT`
/// pipeline): what it shows is the CPU f64 cone trace, and it is nearer
/// the 16-spp reference than the plain pass in a hyperbolic space, moving
/// or not (one frame, no accumulation).
pub fn a_cone_traced_view_is_the_cpu_cone_trace_and_nearer_supersampling() {
    for (space, bound, gain) in [(catalog::torus(1.0), 0.98, 2.0), (catalog::seifert_weber(), 0.97, 5.0)] {
        let name = space.name().to_string();
        let mut app = headless_app(true);
        let image = target(&mut app, W, H);
        let (root, camera) = spawn_view(&mut app, &space, &image, false, false);
        wait_for_pipelines(&mut app);
        let plain_shown = capture(&mut app, &image);
        app.world_mut().entity_mut(camera).insert(ManifoldFootprint);
        wait_for_pipelines(&mut app);
        let shown = capture(&mut app, &image);
        let scene = gathered_scene(&app, &space, root, false);
        let settings = TraceSettings {
            width: W,
            height: H,
            levels: 8,
            footprint: true,
            ..TraceSettings::default()
        };
        let cone = colors(&render::<f64>(&space, &scene, &settings));
        let close = close_to(&shown, &cone, 2);
        let reference = supersampled(&space, &scene, 8);
        let (p_cone, p_plain) = (psnr(&shown, &reference), psnr(&plain_shown, &reference));
        eprintln!(
            "{name}: pass vs CPU cone trace within 2/255: {:.2}%; PSNR against 16 spp: plain {p_plain:.2} dB, cone {p_cone:.2} dB",
            close * 100.0
        );
        assert!(close >= bound, "{name}: {close}");
        assert!(
            p_cone > p_plain + gain,
            "{name}: cone {p_cone:.2} dB, plain {p_plain:.2} dB"
        );
    }
}

/// A light with a radius under `ManifoldAccumulation`: each still frame
/// aims the shadow rays at the next point of the light's disc
/// (`GpuParams::sample`), so the pass settles on the CPU's accumulated
/// soft shadows (`trace::accumulate`, its twin), and not on the hard
/// shadows of the light's centre that a moving view shows.
pub fn a_still_view_softens_the_shadows_of_a_light_with_a_radius() {
    let space = catalog::poincare();
    let mut scene = Scene::default_for(&space);
    scene.lighting.shadows = true;
    for l in &mut scene.lights {
        l.radius = 0.15 * space.inradius();
    }
    let camera = (
        ManifoldCamera { levels: 8, ..default() },
        ManifoldAccumulation { samples: 8 },
    );
    let (shown, scene) = settled_view(&space, &scene, camera);
    assert!(
        scene.lighting.shadows && scene.lights.iter().all(|l| l.radius > 0.0),
        "{:?}",
        scene.lights
    );
    let settings = view_settings();
    let soft = bevy_manifold::trace::accumulate::<f64>(&space, &scene, &settings, 8);
    let hard_settings = TraceSettings {
        light_sample: 0,
        ..settings.clone()
    };
    let hard = bevy_manifold::trace::accumulate::<f64>(
        &space,
        &Scene {
            lights: scene
                .lights
                .iter()
                .map(|l| bevy_manifold::trace::Light {
                    radius: 0.0,
                    ..l.clone()
                })
                .collect(),
            ..scene.clone()
        },
        &hard_settings,
        8,
    );
    let (to_soft, to_hard) = (close_to(&shown, &soft, 2), close_to(&shown, &hard, 2));
    eprintln!(
        "8 samples with a light of radius {:.3}: within 2/255 of the CPU's soft shadows {:.2}%, of the hard ones {:.2}%",
        scene.lights[0].radius,
        to_soft * 100.0,
        to_hard * 100.0
    );
    assert!(to_soft >= 0.97, "{to_soft}");
    assert!(to_soft > to_hard + 0.02, "{to_soft} vs {to_hard}");
}

/// A path-traced camera (`ManifoldPathTracer`) accumulates path samples
/// while still: the pass settles on the CPU's mean of the same samples
/// (`trace::accumulate` with `path_depth`, the same seed: the same paths
/// up to f32), not on the direct trace. A path whose bounce an f32
/// rounding turns elsewhere moves its pixel's mean of 8 samples by more
/// than 3/255: about 6% of pixels here (the GPU test compares the two in
/// distribution).
pub fn a_still_path_traced_view_is_the_cpus_mean_of_the_same_paths() {
    let space = catalog::torus(1.0);
    let scene = Scene::default_for(&space);
    let camera = (
        ManifoldCamera { levels: 8, ..default() },
        ManifoldPathTracer { depth: 4, seed: 3 },
        ManifoldAccumulation { samples: 8 },
    );
    let (shown, scene) = settled_view(&space, &scene, camera);
    let settings = TraceSettings {
        path_depth: 4,
        seed: 3,
        ..view_settings()
    };
    let paths = bevy_manifold::trace::accumulate::<f32>(&space, &scene, &settings, 8);
    let direct = bevy_manifold::trace::accumulate::<f32>(&space, &scene, &view_settings(), 8);
    let (to_paths, to_direct) = (close_to(&shown, &paths, 3), close_to(&shown, &direct, 3));
    eprintln!(
        "8 path samples: within 3/255 of the CPU's paths {:.2}%, of the direct trace {:.2}%",
        to_paths * 100.0,
        to_direct * 100.0
    );
    assert!(to_paths >= 0.9, "{to_paths}");
    assert!(to_paths > to_direct + 0.5, "{to_paths} vs {to_direct}");
}
