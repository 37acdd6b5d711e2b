//! The ray-traced render pass inside a real (headless) Bevy app on a wgpu
//! device (lavapipe in CI): what a manifold camera shows against the
//! headless tracer and the CPU reference, cameras without the marker
//! untouched, uploads only on change, no buffers left behind.
//!
//! Without a GPU adapter these tests are listed as ignored; under CI
//! (`CI` set) a missing adapter is a failure.

use bevy::camera::{RenderTarget, Viewport};
use bevy::prelude::*;
use bevy::render::RenderApp;
use bevy_manifold::prelude::*;
use bevy_manifold::render::{ManifoldBufferCache, ManifoldUploads, offscreen};
use bevy_manifold::space::Space;
use bevy_manifold::trace::FlatScene;
use bevy_manifold_gpu::{GpuObjects, GpuTracer};
use bevy_manifold_test_support::compare::{colors, rgba8_agreement};

const W: u32 = 160;
const H: u32 = 120;

fn headless_app(with_manifold: bool) -> App {
    offscreen::app(with_manifold)
}

fn target(app: &mut App, w: u32, h: u32) -> Handle<Image> {
    offscreen::target(app, w, h)
}

fn wait_for_pipelines(app: &mut App) {
    offscreen::wait_for_pipelines(app).expect("pipelines");
}

fn capture(app: &mut App, target: &Handle<Image>) -> Vec<u8> {
    offscreen::capture(app, target).expect("capture")
}

fn uploads(app: &App) -> ManifoldUploads {
    *app.sub_app(RenderApp).world().resource::<ManifoldUploads>()
}

/// A space's root with the default scene of that space (with fog when
/// asked) and a manifold camera rendering into `image`; returns the root
/// and the camera.
fn spawn_view(app: &mut App, space: &Space, image: &Handle<Image>, fog: bool, cells: bool) -> (Entity, Entity) {
    let mut scene = Scene::default_for(space);
    if fog {
        scene.fog = Some(fog_of(space));
    }
    let camera = (
        ManifoldCamera { levels: 8, ..default() },
        if cells { CellShading::ByCell } else { CellShading::Off },
    );
    offscreen::spawn_view(app, space, &scene, image, camera)
}

fn fog_of(space: &Space) -> Fog {
    Fog {
        density: 0.4 / space.inradius(),
        color: [0.7, 0.75, 0.8],
    }
}

/// The scene the app gathered for `root`, with the camera and fog the test
/// gave it: what the CPU reference traces.
fn gathered_scene(app: &App, space: &Space, root: Entity, fog: bool) -> Scene {
    let mut scene = app
        .world()
        .get::<ManifoldScene>(root)
        .expect("gathered")
        .scene()
        .clone();
    scene.camera = Scene::default_for(space).camera;
    if fog {
        scene.fog = Some(fog_of(space));
    }
    scene
}

/// A new view of the default scene of `space` into `image` (with fog and
/// per-cell shading as asked): its root, what the pass shows, and the
/// scene the app gathered, which the tracers trace.
fn shown_default_scene(
    app: &mut App,
    space: &Space,
    image: &Handle<Image>,
    (fog, cells): (bool, bool),
) -> (Entity, Vec<u8>, Scene) {
    let (root, _) = spawn_view(app, space, image, fog, cells);
    wait_for_pipelines(app);
    let shown = capture(app, image);
    let scene = gathered_scene(app, space, root, fog);
    (root, shown, scene)
}

/// The pixels of an RGBA8 image brighter than 8 in some channel.
fn lit_pixels(shown: &[u8]) -> usize {
    shown
        .chunks_exact(4)
        .filter(|p| p[0] > 8 || p[1] > 8 || p[2] > 8)
        .count()
}

/// The views' size at 8 levels, as the tracers take it.
fn view_settings() -> TraceSettings {
    TraceSettings {
        width: W,
        height: H,
        levels: 8,
        ..TraceSettings::default()
    }
}

/// The headless compute trace of `scene` at [`view_settings`].
fn headless_trace(space: &Space, scene: &Scene) -> bevy_manifold::trace::TraceImage {
    GpuTracer::new()
        .expect("adapter")
        .render(space, scene, &view_settings())
        .expect("headless trace")
}

/// What the pass showed (`shown`) of a scene with a ball and two meshes
/// (object ids 2 and 3) against the headless compute trace (within 1/255)
/// and the CPU f64 reference (within 2/255), at 8 levels: the meshes'
/// pixel count on the CPU and the two agreements.
fn mesh_agreement(space: &Space, scene: &Scene, shown: &[u8]) -> (usize, f64, f64) {
    let compute = headless_trace(space, scene);
    let cpu = render::<f64>(space, scene, &view_settings());
    let mesh_pixels = cpu.pixels.iter().filter(|p| (2..=3).contains(&p.object)).count();
    (
        mesh_pixels,
        rgba8_agreement(shown, &compute, 1),
        rgba8_agreement(shown, &cpu, 2),
    )
}

fn the_pass_draws_what_the_tracer_computes_in_every_space() {
    let mut app = headless_app(true);
    let image = target(&mut app, W, H);
    let mut gpu = GpuTracer::new().expect("adapter");
    for (i, name) in catalog::NAMES.iter().enumerate() {
        let space = catalog::by_name(name).expect("catalog");
        // Fog and per-cell shading on every other space.
        let (fog, cells) = (i % 2 == 1, i % 2 == 1);
        let (root, shown, scene) = shown_default_scene(&mut app, &space, &image, (fog, cells));
        let reference = Scene::default_for(&space);
        assert_eq!(
            scene.balls, reference.balls,
            "{name}: the ECS scene is the default scene"
        );
        assert_eq!(scene.edge_radius, reference.edge_radius);
        assert_eq!(scene.lights.len(), 1);
        let settings = TraceSettings {
            width: W,
            height: H,
            levels: 8,
            cell_colors: cells,
            ..TraceSettings::default()
        };
        let compute = gpu.render(&space, &scene, &settings).expect("headless trace");
        let cpu = render::<f64>(&space, &scene, &settings);
        let vs_compute = rgba8_agreement(&shown, &compute, 1);
        let vs_cpu = rgba8_agreement(&shown, &cpu, 2);
        let lit = lit_pixels(&shown);
        eprintln!(
            "{name:<22} fog {fog:<5} cells {cells:<5}: pass vs headless compute (±1/255): {:.3}%, vs CPU f64 (±2/255): {:.3}%, {lit} lit pixels",
            vs_compute * 100.0,
            vs_cpu * 100.0
        );
        assert!(lit > (W * H / 4) as usize, "{name}: the view is mostly black");
        assert!(vs_compute >= 0.995, "{name}: the pass differs from the headless trace");
        assert!(vs_cpu >= 0.99, "{name}: the pass differs from the CPU reference");
        // Switching spaces: the old hierarchy goes, its buffers with it.
        app.world_mut().entity_mut(root).despawn();
        app.update();
        app.update();
        assert_eq!(
            app.sub_app(RenderApp).world().resource::<ManifoldBufferCache>().len(),
            0
        );
    }
}

fn uploads_happen_only_when_something_changed() {
    let mut app = headless_app(true);
    let image = target(&mut app, 64, 48);
    let space = catalog::seifert_weber();
    let (root, camera) = spawn_view(&mut app, &space, &image, false, false);
    wait_for_pipelines(&mut app);
    let settled = uploads(&app);
    assert_eq!(
        (settled.space, settled.objects),
        (1, 1),
        "one upload of each to start with"
    );
    for _ in 0..5 {
        app.update();
    }
    assert_eq!(uploads(&app), settled, "a still view uploads nothing");

    // The camera turns: only the params buffer is written.
    app.world_mut().get_mut::<Placement>(camera).unwrap().isometry *=
        bevy_manifold::geometry::isometry::rotation(glam::DVec3::Y, 0.1);
    app.update();
    let turned = uploads(&app);
    assert_eq!((turned.space, turned.objects), (1, 1));
    assert_eq!(turned.params, settled.params + 1);

    // A ball moves: the objects are uploaded again, the space is not.
    let ball = app.world().get::<ManifoldScene>(root).unwrap().entities()[0];
    app.world_mut().get_mut::<Placement>(ball).unwrap().isometry =
        bevy_manifold::geometry::isometry::translation(space.geometry(), glam::DVec3::X * 0.1);
    app.update();
    let moved = uploads(&app);
    assert_eq!((moved.space, moved.objects), (1, 2));

    // The space is replaced on the same root: faces go up again.
    app.world_mut()
        .entity_mut(root)
        .insert(ManifoldSpace::new(catalog::seifert_weber()));
    app.update();
    assert_eq!(uploads(&app).space, 2);

    // The camera stops being a manifold camera: its buffers are dropped.
    app.world_mut().entity_mut(camera).remove::<ManifoldCamera>();
    app.update();
    app.update();
    assert_eq!(
        app.sub_app(RenderApp).world().resource::<ManifoldBufferCache>().len(),
        0
    );
}

/// A view whose space is replaced on its root keeps its buffers, written
/// in place where the new space fits and grown where it does not (the
/// Poincare space's Cayley table does not fit the first buffer). Each
/// space is drawn as the headless trace draws it, and coming back to the
/// first space gives exactly the first picture: nothing of the spaces in
/// between is left in the buffers.
fn a_view_whose_space_changes_draws_each_space_from_its_reused_buffers() {
    let mut app = headless_app(true);
    let image = target(&mut app, W, H);
    let mut gpu = GpuTracer::new().expect("adapter");
    let first = catalog::seifert_weber();
    let (root, camera) = spawn_view(&mut app, &first, &image, false, false);
    wait_for_pipelines(&mut app);
    let at_first = capture(&mut app, &image);
    for name in ["poincare", "torus", "seifert-weber"] {
        let space = catalog::by_name(name).expect("catalog");
        app.world_mut()
            .entity_mut(root)
            .insert(ManifoldSpace::new(space.clone()));
        // The camera where the new space's default scene puts it, wrapped
        // from the origin of the new space.
        app.world_mut()
            .entity_mut(camera)
            .insert((DomainCell::default(), bevy_manifold::placement::WrapOrigin::default()));
        app.world_mut().get_mut::<Placement>(camera).unwrap().isometry = Scene::default_for(&space).camera.isometry;
        app.update();
        wait_for_pipelines(&mut app);
        let shown = capture(&mut app, &image);
        assert_eq!(
            app.sub_app(RenderApp).world().resource::<ManifoldBufferCache>().len(),
            1,
            "one view, its buffers kept"
        );
        if name == first.name() {
            assert!(shown == at_first, "back in {name}: not the first picture");
            continue;
        }
        let scene = gathered_scene(&app, &space, root, false);
        let settings = TraceSettings {
            width: W,
            height: H,
            levels: 8,
            ..TraceSettings::default()
        };
        let compute = gpu.render(&space, &scene, &settings).expect("headless trace");
        let agree = rgba8_agreement(&shown, &compute, 1);
        eprintln!(
            "{name}: the reused view vs the headless trace (±1/255): {:.3}%",
            agree * 100.0
        );
        assert!(agree >= 0.995, "{name}: the reused view draws another space");
    }
}

fn a_viewport_shows_the_same_trace_as_a_whole_target() {
    let mut app = headless_app(true);
    let space = catalog::torus(1.0);
    let whole = target(&mut app, 64, 48);
    let big = target(&mut app, 100, 80);
    let (_, _) = spawn_view(&mut app, &space, &whole, false, false);
    let (_, inset) = spawn_view(&mut app, &space, &big, false, false);
    app.world_mut().get_mut::<Camera>(inset).unwrap().viewport = Some(Viewport {
        physical_position: UVec2::new(30, 20),
        physical_size: UVec2::new(64, 48),
        ..default()
    });
    wait_for_pipelines(&mut app);
    let a = capture(&mut app, &whole);
    let b = capture(&mut app, &big);
    let mut same = 0;
    for y in 0..48 {
        for x in 0..64 {
            let pa = &a[(y * 64 + x) * 4..][..4];
            let pb = &b[((y + 20) * 100 + x + 30) * 4..][..4];
            same += usize::from(pa == pb);
        }
    }
    assert_eq!(
        same,
        64 * 48,
        "the inset viewport differs from the whole-target trace (lit pixels: whole {}, inset target {})",
        lit_pixels(&a),
        lit_pixels(&b)
    );
}

/// The fraction of `shown` (RGBA8, sRGB) within `tol` of linear `colors`.
fn close_to(shown: &[u8], colors: &[[f32; 3]], tol: u8) -> f64 {
    let close = shown
        .chunks_exact(4)
        .zip(colors)
        .filter(|(px, c)| (0..3).all(|k| px[k].abs_diff(bevy_manifold::trace::srgb8(c[k])) <= tol))
        .count();
    close as f64 / colors.len() as f64
}

fn a_view_at_half_scale_is_the_half_size_trace_upscaled_bilinearly() {
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

fn an_adaptive_scale_lowers_the_pixels_traced_when_frames_are_slow() {
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

/// PSNR (dB) of an RGBA8 sRGB image against linear reference colours,
/// both compared as sRGB bytes.
fn psnr(shown: &[u8], reference: &[[f32; 3]]) -> f64 {
    let mut sq = 0.0;
    for (px, c) in shown.chunks_exact(4).zip(reference) {
        for k in 0..3 {
            let d = f64::from(px[k]) - f64::from(bevy_manifold::trace::srgb8(c[k]));
            sq += d * d;
        }
    }
    let rmse = (sq / (3 * reference.len()) as f64).sqrt() / 255.0;
    -20.0 * rmse.log10()
}

/// A 16-samples-per-pixel reference: the CPU f64 trace at 4x the size,
/// each pixel the mean of its 4x4 block (a box filter over the pixel).
fn supersampled(space: &Space, scene: &Scene, levels: u32) -> Vec<[f32; 3]> {
    let settings = TraceSettings {
        width: W,
        height: H,
        levels,
        ..TraceSettings::default()
    };
    bevy_manifold_test_support::compare::supersampled(space, scene, &settings, 4)
}

fn a_still_view_accumulates_jittered_samples_then_stops_tracing() {
    use bevy_manifold::render::prepare::ManifoldViewBinding;
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
        app.world_mut()
            .entity_mut(camera)
            .insert(ManifoldAccumulation { samples: 8 });
        wait_for_pipelines(&mut app);
        for _ in 0..10 {
            app.update();
        }
        let shown = capture(&mut app, &image);
        // All samples in: the pass no longer traces.
        assert_eq!(tracing(&mut app), [Some(false)], "{name}");
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

/// Linear colours as the RGBA8 sRGB bytes a target stores.
fn plain_bytes(colors: &[[f32; 3]]) -> Vec<u8> {
    colors
        .iter()
        .flat_map(|c| {
            let [r, g, b] = c.map(bevy_manifold::trace::srgb8);
            [r, g, b, 255]
        })
        .collect()
}

/// A plain Bevy scene: a lit cube seen by an ordinary `Camera3d`.
fn plain_scene(app: &mut App, image: &Handle<Image>) {
    let world = app.world_mut();
    let mesh = world.resource_mut::<Assets<Mesh>>().add(Cuboid::new(1.0, 1.0, 1.0));
    let material = world
        .resource_mut::<Assets<StandardMaterial>>()
        .add(Color::srgb(0.8, 0.5, 0.3));
    world.spawn((Mesh3d(mesh), MeshMaterial3d(material)));
    world.spawn((
        DirectionalLight::default(),
        Transform::from_xyz(1.0, 2.0, 3.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    world.spawn((
        Camera3d::default(),
        RenderTarget::Image(image.clone().into()),
        Transform::from_xyz(2.0, 1.5, 3.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
}

fn cameras_without_the_marker_render_exactly_as_before() {
    let shots: Vec<Vec<u8>> = [false, true]
        .into_iter()
        .map(|with_manifold| {
            let mut app = headless_app(with_manifold);
            let image = target(&mut app, 96, 64);
            plain_scene(&mut app, &image);
            if with_manifold {
                // A manifold camera in the same app, drawing elsewhere.
                let other = target(&mut app, 32, 32);
                spawn_view(&mut app, &catalog::poincare(), &other, true, true);
            }
            wait_for_pipelines(&mut app);
            capture(&mut app, &image)
        })
        .collect();
    let lit = shots[0].chunks_exact(4).filter(|p| p[0] > 20).count();
    assert!(lit > 500, "the plain scene shows its cube ({lit} lit pixels)");
    assert!(
        shots[0] == shots[1],
        "the plain camera's image changed when the plugin was added"
    );
}

fn gltf_meshes_in_a_manifold_are_traced_and_not_rasterised() {
    use bevy::camera::visibility::RenderLayers;
    use bevy_manifold::traced_meshes::MeshBvhCache;
    use glam::DVec3;
    let mut app = headless_app(true);
    let image = target(&mut app, W, H);
    let space = catalog::poincare();
    let r = space.inradius();
    let (root, _) = spawn_view(&mut app, &space, &image, false, false);
    let assets = app.world().resource::<AssetServer>().clone();
    let mesh: Handle<Mesh> = assets.load("models/suzanne.glb#Mesh0/Primitive0");
    let scale = Transform::from_scale(Vec3::splat((0.1 * r) as f32));
    // One Suzanne on the placed entity itself; one below a placed parent,
    // offset and turned by the child's transform, as a glTF scene root
    // spawns its meshes.
    let suzanne = app
        .world_mut()
        .spawn((
            ChildOf(root),
            Mesh3d(mesh.clone()),
            Placement::at(&space, DVec3::new(-0.3, 0.12, 0.15) * r),
            scale,
        ))
        .id();
    let parent = app
        .world_mut()
        .spawn((
            ChildOf(root),
            Placement::at(&space, DVec3::new(0.3, -0.12, 0.15) * r),
            scale,
            Visibility::default(),
        ))
        .id();
    app.world_mut().spawn((
        ChildOf(parent),
        Mesh3d(mesh.clone()),
        Transform::from_xyz(0.2, 0.1, 0.0).with_rotation(Quat::from_rotation_y(0.6)),
    ));
    // A file that is not there: reported by Bevy's asset server, and the
    // rest of the scene still renders.
    app.world_mut().spawn((
        ChildOf(root),
        Mesh3d(assets.load("models/missing.glb#Mesh0/Primitive0")),
        Placement::default(),
    ));
    let meshes_of = |app: &App| app.world().get::<ManifoldMeshes>(root).map_or(0, |m| m.meshes.len());
    for _ in 0..2000 {
        app.update();
        if meshes_of(&app) == 2 {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    assert_eq!(meshes_of(&app), 2, "both Suzannes are gathered");
    let m = &app.world().get::<ManifoldMeshes>(root).unwrap().meshes;
    assert!(
        m.iter().any(|m| m.local != glam::DMat4::IDENTITY),
        "the child's transform is kept"
    );
    assert_eq!(
        app.world().resource::<MeshBvhCache>().built(),
        1,
        "two instances, one BVH"
    );
    wait_for_pipelines(&mut app);
    let shown = capture(&mut app, &image);
    let scene = gathered_scene(&app, &space, root, false);
    assert_eq!((scene.balls.len(), scene.meshes.len()), (1, 2));
    // The glTF's meshes are off the rasteriser.
    let world = app.world_mut();
    let mut layers = world.query_filtered::<&RenderLayers, With<Mesh3d>>();
    let hidden = layers.iter(world).filter(|l| **l == RenderLayers::none()).count();
    assert_eq!(
        hidden, 3,
        "each traced mesh entity is hidden from Bevy's cameras (the missing one too)"
    );
    let (mesh_pixels, vs_compute, vs_cpu) = mesh_agreement(&space, &scene, &shown);
    eprintln!(
        "two traced Suzannes in poincare: {mesh_pixels} mesh pixels; pass vs compute {:.3}%, vs CPU f64 {:.3}%",
        vs_compute * 100.0,
        vs_cpu * 100.0
    );
    assert!(mesh_pixels > 200, "Suzanne is in view");
    assert!(vs_compute >= 0.995 && vs_cpu >= 0.99);
    // Moving an instance moves its matrix; the BVH stays.
    let before = scene.meshes[0].data.clone();
    app.world_mut().get_mut::<Placement>(suzanne).unwrap().isometry =
        isometry::translation(space.geometry(), DVec3::Y * 0.2 * r);
    app.update();
    app.update();
    let moved = gathered_scene(&app, &space, root, false);
    assert!(moved.meshes.iter().all(|m| std::sync::Arc::ptr_eq(&m.data, &before)));
    assert_ne!(moved.meshes, scene.meshes, "the placement changed");
    assert_eq!(app.world().resource::<MeshBvhCache>().built(), 1);
}

fn gltf_scene_roots_in_a_manifold_are_traced() {
    use bevy::camera::visibility::RenderLayers;
    use glam::DVec3;
    let mut app = headless_app(true);
    let image = target(&mut app, W, H);
    let space = catalog::torus(1.0);
    let (root, _) = spawn_view(&mut app, &space, &image, false, false);
    let assets = app.world().resource::<AssetServer>().clone();
    // Whole glTF scenes, as a Bevy user spawns them: Suzanne's and the left
    // hand's (a skinned mesh under its joints), each under a placed entity
    // that scales it; and a scene file that is not there.
    let scene_of = |path: &str| WorldAssetRoot(assets.load(GltfAssetLabel::Scene(0).from_asset(path.to_string())));
    app.world_mut().spawn((
        ChildOf(root),
        scene_of("models/suzanne.glb"),
        Placement::at(&space, DVec3::new(-0.12, 0.0, -0.1)),
        Transform::from_scale(Vec3::splat(0.06)),
    ));
    app.world_mut().spawn((
        ChildOf(root),
        scene_of("models/left.glb"),
        Placement::at(&space, DVec3::new(0.15, -0.05, 0.1)),
        Transform::from_scale(Vec3::splat(0.8)),
    ));
    app.world_mut()
        .spawn((ChildOf(root), scene_of("models/missing.glb"), Placement::default()));
    let meshes_of = |app: &App| app.world().get::<ManifoldMeshes>(root).map_or(0, |m| m.meshes.len());
    for _ in 0..3000 {
        app.update();
        if meshes_of(&app) == 2 {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    assert_eq!(
        meshes_of(&app),
        2,
        "each scene's mesh is gathered (the missing file adds none)"
    );
    let world = app.world_mut();
    let mut layers = world.query_filtered::<Option<&RenderLayers>, With<Mesh3d>>();
    let all: Vec<_> = layers.iter(world).collect();
    assert_eq!(all.len(), 2);
    assert!(
        all.iter().all(|l| *l == Some(&RenderLayers::none())),
        "the scenes' meshes are off the rasteriser"
    );
    wait_for_pipelines(&mut app);
    let shown = capture(&mut app, &image);
    let scene = gathered_scene(&app, &space, root, false);
    let (mesh_pixels, vs_compute, vs_cpu) = mesh_agreement(&space, &scene, &shown);
    eprintln!(
        "glTF scenes in the torus: {mesh_pixels} mesh pixels; pass vs compute {:.3}%, vs CPU f64 {:.3}%",
        vs_compute * 100.0,
        vs_cpu * 100.0
    );
    assert!(mesh_pixels > 200, "the scenes' meshes are in view");
    assert!(vs_compute >= 0.995 && vs_cpu >= 0.99);
}

fn the_papers_scene_as_entities_matches_the_tracers() {
    use bevy_manifold::paper_scene::{paper_camera, spawn_paper_scene};
    use bevy_manifold::trace::PaperOptions;
    let mut app = headless_app(true);
    let image = target(&mut app, W, H);
    let space = catalog::mirrored_cube(1.0);
    let root = app.world_mut().spawn(ManifoldSpace::new(space.clone())).id();
    let (placement, projection) = paper_camera(&space);
    let camera = app
        .world_mut()
        .spawn((
            ChildOf(root),
            ManifoldCamera::default(),
            placement,
            projection,
            RenderTarget::Image(image.clone().into()),
        ))
        .id();
    let mut commands = app.world_mut().commands();
    let spawned = spawn_paper_scene(&mut commands, root, camera, &space, PaperOptions::default());
    app.world_mut().flush();
    let meshes_of = |app: &App| app.world().get::<ManifoldMeshes>(root).map_or(0, |m| m.meshes.len());
    for _ in 0..200 {
        app.update();
        if meshes_of(&app) == 3 {
            break;
        }
    }
    assert_eq!(meshes_of(&app), 3, "Suzanne and the two hands");
    let gathered = &app.world().get::<ManifoldMeshes>(root).unwrap();
    let body = gathered
        .entities
        .iter()
        .position(|e| Some(*e) == spawned.suzanne)
        .expect("Suzanne is gathered");
    assert!(gathered.meshes[body].attached, "Suzanne is the camera's body");
    assert_eq!(
        gathered.meshes.iter().filter(|m| m.attached).count(),
        1,
        "the hands are drawn in the home copy too"
    );
    wait_for_pipelines(&mut app);
    let shown = capture(&mut app, &image);
    // Against the tracer's own version of the paper's scene: the same
    // layout, the hands placed through the camera's chart instead of by an
    // isometry (exact in the flat cube).
    let reference = Scene::paper_default(&space);
    let settings = TraceSettings {
        width: W,
        height: H,
        levels: 8,
        ..TraceSettings::default()
    };
    let cpu = render::<f64>(&space, &reference, &settings);
    let mesh_pixels = cpu.pixels.iter().filter(|p| p.object >= 1 && p.object < 100).count();
    let close = rgba8_agreement(&shown, &cpu, 2);
    eprintln!(
        "paper's scene as entities in the mirrored cube: {mesh_pixels} mesh pixels, {:.3}% within 2/255 of Scene::paper_default on the CPU",
        close * 100.0
    );
    assert!(mesh_pixels > 500, "the hands and Suzanne's images are in view");
    assert!(close >= 0.99);
    // The camera moves, and the body and hands with it: their instances
    // are uploaded again, their BVHs are not.
    let scene = app.world().get::<ManifoldScene>(root).unwrap().scene();
    let packed = GpuObjects::pack(&FlatScene::<f32>::new(&space, scene));
    let mesh_bytes = (packed.mesh_data.len() * 16) as u64;
    let before = uploads(&app);
    app.world_mut().get_mut::<Placement>(camera).unwrap().isometry *=
        isometry::translation(space.geometry(), glam::DVec3::X * 0.05);
    app.update();
    app.update();
    let after = uploads(&app);
    eprintln!(
        "moving the camera: {} object uploads, {} bytes (the meshes' data is {mesh_bytes} bytes)",
        after.objects - before.objects,
        after.bytes - before.bytes
    );
    assert!(after.objects > before.objects, "the attached meshes moved");
    assert!(
        after.bytes - before.bytes < mesh_bytes / 4,
        "the BVHs were not uploaded again"
    );
    // In another copy, two mirrors away: the body's home (the copy not
    // drawn) is the camera's copy there, so the picture is the CPU's from
    // that copy, not one from inside Suzanne.
    let word = vec![0, 2];
    app.world_mut()
        .entity_mut(camera)
        .insert(bevy_manifold::placement::DomainCell::new(
            &space,
            space.cell_of_word(&word),
        ));
    for _ in 0..3 {
        app.update();
    }
    let shown = capture(&mut app, &image);
    let mut scene = gathered_scene(&app, &space, root, false);
    scene.camera.isometry = app.world().get::<Placement>(camera).unwrap().isometry;
    scene.camera.cell = word;
    let cpu = render::<f64>(&space, &scene, &settings);
    let close = rgba8_agreement(&shown, &cpu, 2);
    eprintln!("the same two mirrors away: {:.3}% within 2/255", close * 100.0);
    assert!(close >= 0.99, "{close}");
}

fn cell_tints_agree_between_the_pass_and_the_cpu() {
    use bevy_manifold::space::cells::CellTint;
    let space = catalog::torus(1.0);
    let lattice = |x, y, z| CellId::from_lattice(glam::IVec3::new(x, y, z));
    for (shading, tint) in [
        (
            CellShading::Highlight {
                cell: lattice(0, 0, -1).0,
            },
            CellTint::Highlight(lattice(0, 0, -1)),
        ),
        (
            CellShading::Pattern { on_fraction: 0.4 },
            CellTint::Pattern { on_fraction: 0.4 },
        ),
    ] {
        let mut app = headless_app(true);
        let image = target(&mut app, W, H);
        let camera = (ManifoldCamera { levels: 6, ..default() }, shading);
        let (root, _) = offscreen::spawn_view(&mut app, &space, &Scene::default_for(&space), &image, camera);
        wait_for_pipelines(&mut app);
        let shown = capture(&mut app, &image);
        let scene = gathered_scene(&app, &space, root, false);
        let settings = TraceSettings {
            width: W,
            height: H,
            levels: 6,
            cell_colors: true,
            cell_tint: tint,
            ..TraceSettings::default()
        };
        let cpu = render::<f64>(&space, &scene, &settings);
        let plain = render::<f64>(
            &space,
            &scene,
            &TraceSettings {
                cell_colors: false,
                ..settings.clone()
            },
        );
        let tinted = cpu
            .pixels
            .iter()
            .zip(&plain.pixels)
            .filter(|(a, b)| a.color != b.color)
            .count();
        let close = rgba8_agreement(&shown, &cpu, 2);
        eprintln!(
            "{tint:?}: {tinted} of {} pixels tinted on the CPU; the pass within 2/255 of it: {:.3}%",
            cpu.pixels.len(),
            close * 100.0
        );
        assert!(tinted > 100, "{tint:?} changes some copies");
        assert!(tinted < cpu.pixels.len(), "{tint:?} leaves some pixels alone");
        assert!(close >= 0.995, "{tint:?}");
    }
}

/// A camera 20 crossings from the origin copy of Seifert-Weber, under
/// walls and per-cell colour: the pass centres its table of exact ids on
/// the camera's exact cell (recentred off the frame) and draws what the
/// CPU f64 reference draws from that cell. Three levels keep every ray in
/// the table (radius 4).
fn the_pass_draws_exact_cells_and_walls_far_from_the_origin_copy() {
    use bevy_manifold::placement::DomainCell;
    use bevy_manifold::space::rule::{CellRule, Walls};
    let space = catalog::seifert_weber();
    let word: Vec<usize> = (0..20).map(|k| (k * 5 + k / 3) % 12).collect();
    let rule = CellRule {
        hidden: None,
        walls: Some(Walls { density: 0.3, seed: 5 }),
    };
    let mut app = headless_app(true);
    let image = target(&mut app, W, H);
    let camera = (ManifoldCamera { levels: 3, ..default() }, CellShading::ByCell);
    let (root, cam) = offscreen::spawn_view(&mut app, &space, &Scene::default_for(&space), &image, camera);
    app.world_mut().get_mut::<ManifoldSpace>(root).unwrap().set_rule(rule);
    let far = DomainCell::new(&space, space.cell_of_word(&word));
    assert!(!far.id.is_far());
    app.world_mut().entity_mut(cam).insert(far);
    wait_for_pipelines(&mut app);
    // The recentred table arrives from the async pool within a few frames.
    for _ in 0..20 {
        app.update();
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let shown = capture(&mut app, &image);
    let mut scene = gathered_scene(&app, &space, root, false);
    scene.camera.cell = word;
    let settings = TraceSettings {
        width: W,
        height: H,
        levels: 3,
        cell_colors: true,
        cell_rule: rule,
        ..TraceSettings::default()
    };
    let cpu = render::<f64>(&space, &scene, &settings);
    let walls = cpu
        .pixels
        .iter()
        .filter(|p| p.object == bevy_manifold::space::rule::WALL_OBJECT)
        .count();
    let close = rgba8_agreement(&shown, &cpu, 2);
    eprintln!(
        "far camera, walls: {walls} wall pixels on the CPU; the pass within 2/255: {:.3}%",
        close * 100.0
    );
    assert!(walls > 100);
    assert!(close >= 0.99, "{close}");
}

/// A camera with `ManifoldFootprint` traces cones (the `FOOTPRINT`
/// pipeline): what it shows is the CPU f64 cone trace, and it is nearer
/// the 16-spp reference than the plain pass in a hyperbolic space, moving
/// or not (one frame, no accumulation).
fn a_cone_traced_view_is_the_cpu_cone_trace_and_nearer_supersampling() {
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

/// A scene whose balls make more copies than the GPU holds (254 large
/// balls in the torus: past `bevy_manifold_gpu::bindings::MAX_BALLS` with
/// their ghosts) is drawn, its first `MAX_BALLS` copies, with no
/// validation error; the same app then draws the default scene as the
/// headless tracer does.
fn a_scene_past_the_gpus_ball_copies_is_drawn_and_the_next_scene_is_right() {
    let mut app = headless_app(true);
    let image = target(&mut app, W, H);
    let space = catalog::by_name("torus").expect("catalog");
    let mut crowd = Scene::default_for(&space);
    let mut rng = bevy_manifold_test_support::Rng(5);
    while crowd.balls.len() < 254 {
        crowd.balls.push(bevy_manifold::trace::Ball {
            center: rng.ray_inside(&space).origin,
            radius: 1.2 * space.inradius(),
            color: [0.5, 0.5, 0.5],
            glow: 0.5,
        });
    }
    let copies = FlatScene::<f32>::new(&space, &crowd).balls.len();
    // Past what even a 64 KiB uniform binding would hold (1365 balls), so
    // that uploading them all could not bind.
    assert!(copies > 65_536 / 48, "the scene makes only {copies} balls");
    let camera = (ManifoldCamera { levels: 4, ..default() }, CellShading::Off);
    let (root, _) = offscreen::spawn_view(&mut app, &space, &crowd, &image, camera);
    wait_for_pipelines(&mut app);
    let lit = lit_pixels(&capture(&mut app, &image));
    assert!(lit > (W * H / 4) as usize, "the crowd is drawn ({lit} lit pixels)");
    app.world_mut().entity_mut(root).despawn();
    app.update();
    let (_, shown, scene) = shown_default_scene(&mut app, &space, &image, (false, false));
    let settings = TraceSettings {
        width: W,
        height: H,
        levels: 8,
        ..TraceSettings::default()
    };
    let compute = GpuTracer::new()
        .expect("adapter")
        .render(&space, &scene, &settings)
        .expect("headless trace");
    let agreement = rgba8_agreement(&shown, &compute, 1);
    assert!(agreement >= 0.995, "after the crowd the pass agrees on {agreement}");
}

/// Balls in `space` at `n` points inside its domain (seeded), each a
/// tenth of the inradius, as entities under `root`; the scene's balls.
fn spawn_balls(app: &mut App, space: &Space, root: Entity, n: usize, seed: u64) -> Vec<Entity> {
    let mut rng = bevy_manifold_test_support::Rng(seed);
    let g = space.geometry();
    (0..n)
        .map(|k| {
            let centre = rng.ray_inside(space).origin;
            let hue = k as f32 / n as f32;
            app.world_mut()
                .spawn((
                    ChildOf(root),
                    Placement::from_isometry(bevy_manifold::geometry::isometry::translation_to(g, centre)),
                    TracedBall::new(
                        0.1 * space.inradius(),
                        Color::linear_rgb(1.0 - hue, 0.3 + 0.6 * hue, 0.4),
                    ),
                ))
                .id()
        })
        .collect()
}

/// A view whose balls cross a doubling of the ball tree's leaves (as the
/// shooter's shots do) keeps drawing them: the frames before the pipeline
/// for the new leaf count is compiled are drawn by the last one, and show
/// what the headless tracer shows of the new scene. Both ways: 8 leaves
/// to 16 (the last pipeline, compiled for 8, tests every ball) and then
/// 16 to 4 (the last, compiled for 16, tests the 4 there are, not the 12
/// left in its uniform from before, whose balls are gone). Not drawn, the frames would show the scene
/// before.
fn a_view_keeps_drawing_its_balls_while_a_new_leaf_count_compiles() {
    let mut app = headless_app(true);
    let image = target(&mut app, W, H);
    let space = catalog::by_name("torus").expect("catalog");
    let mut scene = Scene::default_for(&space);
    scene.edge_radius = None;
    let camera = (ManifoldCamera { levels: 8, ..default() }, CellShading::Off);
    let (root, _) = offscreen::spawn_view(&mut app, &space, &scene, &image, camera);
    // 20 balls and the scene's own, 17 to 32 of them away from the faces:
    // 8 leaves (leaf_count).
    let first = spawn_balls(&mut app, &space, root, 20, 11);
    wait_for_pipelines(&mut app);
    let before = capture(&mut app, &image);
    let leaves = |app: &App| {
        let prep = FlatScene::<f32>::new(
            &space,
            app.world().get::<ManifoldScene>(root).expect("gathered").scene(),
        );
        prep.ball_tree.words.len()
    };
    assert_eq!(leaves(&app), 8, "the first scene's tree");
    let check = |app: &mut App, before: &[u8], want: usize, what: &str| {
        let shown = capture(app, &image);
        assert_eq!(leaves(app), want, "{what}: the tree");
        let compute = headless_trace(&space, &gathered_scene(app, &space, root, false));
        let changed = before
            .chunks_exact(4)
            .zip(shown.chunks_exact(4))
            .filter(|(a, b)| a != b)
            .count();
        let agreement = rgba8_agreement(&shown, &compute, 1);
        eprintln!(
            "{what}: {changed} pixels changed, agreement {agreement}, lit {}",
            lit_pixels(&shown)
        );
        assert!(changed > (W * H / 20) as usize, "{what}: only {changed} pixels changed");
        assert!(agreement >= 0.995, "{what}: the pass agrees on {agreement}");
        shown
    };
    // 20 more: 16 leaves.
    let second = spawn_balls(&mut app, &space, root, 20, 12);
    let after = check(&mut app, &before, 16, "20 balls more");
    // The 16-leaf pipeline compiled, 27 balls fewer: 14, and 9 to 16 of
    // them away from the faces, 4 leaves.
    wait_for_pipelines(&mut app);
    for e in first.into_iter().chain(second.into_iter().take(7)) {
        app.world_mut().despawn(e);
    }
    check(&mut app, &after, 4, "27 balls fewer");
}

bevy_manifold_test_support::test_main! {
    cpu: [],
    gpu: [
        a_cone_traced_view_is_the_cpu_cone_trace_and_nearer_supersampling,
        the_pass_draws_exact_cells_and_walls_far_from_the_origin_copy,
        the_pass_draws_what_the_tracer_computes_in_every_space,
        uploads_happen_only_when_something_changed,
        a_view_whose_space_changes_draws_each_space_from_its_reused_buffers,
        a_viewport_shows_the_same_trace_as_a_whole_target,
        cameras_without_the_marker_render_exactly_as_before,
        gltf_meshes_in_a_manifold_are_traced_and_not_rasterised,
        gltf_scene_roots_in_a_manifold_are_traced,
        the_papers_scene_as_entities_matches_the_tracers,
        cell_tints_agree_between_the_pass_and_the_cpu,
        a_view_at_half_scale_is_the_half_size_trace_upscaled_bilinearly,
        an_adaptive_scale_lowers_the_pixels_traced_when_frames_are_slow,
        a_still_view_accumulates_jittered_samples_then_stops_tracing,
        a_scene_past_the_gpus_ball_copies_is_drawn_and_the_next_scene_is_right,
        a_view_keeps_drawing_its_balls_while_a_new_leaf_count_compiles,
    ],
}
