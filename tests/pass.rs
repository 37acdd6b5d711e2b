//! The ray-traced render pass inside a real (headless) Bevy app on a wgpu
//! device (lavapipe in CI): what a manifold camera shows against the
//! headless tracer and the CPU reference, cameras without the marker
//! untouched, uploads only on change, no buffers left behind.
//!
//! Without any GPU adapter these tests say so and pass; under CI (`CI` set)
//! a missing adapter is a failure.

#![cfg(feature = "app")]

use bevy::camera::{RenderTarget, Viewport};
use bevy::log::LogPlugin;
use bevy::prelude::*;
use bevy::render::RenderApp;
use bevy::render::pipelined_rendering::PipelinedRenderingPlugin;
use bevy::render::render_resource::{PipelineCache, TextureFormat};
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured};
use bevy::window::ExitCondition;
use bevy::winit::WinitPlugin;
use bevy_manifold::drawables::spawn_scene;
use bevy_manifold::prelude::*;
use bevy_manifold::render::GpuTracer;
use bevy_manifold::render::pass::prepare::ManifoldViewBinding;
use bevy_manifold::render::pass::{ManifoldBufferCache, ManifoldUploads};
use bevy_manifold::space::Space;
use std::sync::{Arc, Mutex};

const W: u32 = 160;
const H: u32 = 120;

fn gpu_available() -> bool {
    match GpuTracer::new() {
        Ok(t) => {
            eprintln!("GPU adapter: {}", t.adapter_name());
            true
        }
        Err(e) if std::env::var_os("CI").is_none() => {
            eprintln!("SKIPPED: no GPU to test on: {e}");
            false
        }
        Err(e) => panic!("CI must have a GPU adapter (lavapipe): {e}"),
    }
}

/// A Bevy app with the renderer and no window, updated by hand; the render
/// world runs on this thread so the test can look into it.
fn headless_app(with_manifold: bool) -> App {
    let mut app = App::new();
    app.add_plugins(
        DefaultPlugins
            .build()
            .disable::<WinitPlugin>()
            .disable::<PipelinedRenderingPlugin>()
            .disable::<LogPlugin>()
            .set(WindowPlugin {
                primary_window: None,
                exit_condition: ExitCondition::DontExit,
                ..default()
            }),
    );
    if with_manifold {
        app.add_plugins(ManifoldPlugin::default());
    }
    app.finish();
    app.cleanup();
    app
}

fn target(app: &mut App, w: u32, h: u32) -> Handle<Image> {
    let image = Image::new_target_texture(w, h, TextureFormat::Rgba8UnormSrgb, None);
    app.world_mut().resource_mut::<Assets<Image>>().add(image)
}

/// Updates until every manifold view's pipeline has compiled.
fn wait_for_pipelines(app: &mut App) {
    for _ in 0..3000 {
        app.update();
        let world = app.sub_app_mut(RenderApp).world_mut();
        let ids: Vec<_> = world
            .query::<&ManifoldViewBinding>()
            .iter(world)
            .map(|b| b.pipeline)
            .collect();
        let cache = world.resource::<PipelineCache>();
        if !ids.is_empty() && ids.iter().all(|id| cache.get_render_pipeline(*id).is_some()) {
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    panic!("the tracer pipeline did not compile");
}

/// The next frame's image in `target`, as sRGB bytes.
fn capture(app: &mut App, target: &Handle<Image>) -> Vec<u8> {
    let slot: Arc<Mutex<Option<Image>>> = Arc::default();
    let out = slot.clone();
    app.world_mut()
        .spawn(Screenshot::image(target.clone()))
        .observe(move |shot: On<ScreenshotCaptured>| {
            *out.lock().unwrap() = Some(shot.image.clone());
        });
    for _ in 0..200 {
        app.update();
        if let Some(image) = slot.lock().unwrap().take() {
            return image.data.expect("screenshot data");
        }
    }
    panic!("no screenshot arrived");
}

fn uploads(app: &App) -> ManifoldUploads {
    *app.sub_app(RenderApp).world().resource::<ManifoldUploads>()
}

fn to_srgb8(c: f32) -> u8 {
    let c = c.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

/// The fraction of pixels whose three channels are within `tol` of the
/// reference image's (linear colours, sRGB-encoded as the target does).
fn agreement(bytes: &[u8], reference: &TraceImage, tol: u8) -> f64 {
    let close = bytes
        .chunks_exact(4)
        .zip(&reference.pixels)
        .filter(|(px, q)| (0..3).all(|c| px[c].abs_diff(to_srgb8(q.color[c])) <= tol))
        .count();
    close as f64 / reference.pixels.len() as f64
}

/// A space's root with the default scene of that space and a manifold
/// camera rendering into `image`; returns the root and the camera.
fn spawn_view(app: &mut App, space: &Space, image: &Handle<Image>, fog: bool, cells: bool) -> (Entity, Entity) {
    let scene = Scene::default_for(space);
    let world = app.world_mut();
    let root = world.spawn(ManifoldSpace::new(space.clone())).id();
    let mut commands = world.commands();
    spawn_scene(&mut commands, root, space, &scene);
    let camera = commands
        .spawn((
            ChildOf(root),
            ManifoldCamera {
                max_level: 8,
                cell_shading: if cells { CellShading::ByCell } else { CellShading::Off },
                ..default()
            },
            Placement::from_isometry(scene.camera.isometry),
            RenderTarget::Image(image.clone().into()),
            Projection::Perspective(PerspectiveProjection {
                fov: (scene.camera.fov_y_degrees as f32).to_radians(),
                ..default()
            }),
        ))
        .id();
    if fog {
        commands.entity(camera).insert(ManifoldFog {
            density: 0.4 / space.inradius(),
            color: Color::linear_rgb(0.7, 0.75, 0.8),
        });
    }
    world.flush();
    (root, camera)
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
        scene.fog = Some(Fog {
            density: 0.4 / space.inradius(),
            color: [0.7, 0.75, 0.8],
        });
    }
    scene
}

#[test]
fn the_pass_draws_what_the_tracer_computes_in_every_space() {
    if !gpu_available() {
        return;
    }
    let mut app = headless_app(true);
    let image = target(&mut app, W, H);
    let mut gpu = GpuTracer::new().expect("adapter");
    for (i, name) in catalog::NAMES.iter().enumerate() {
        let space = catalog::by_name(name).expect("catalog");
        // Fog and per-cell shading on every other space.
        let (fog, cells) = (i % 2 == 1, i % 2 == 1);
        let (root, _) = spawn_view(&mut app, &space, &image, fog, cells);
        wait_for_pipelines(&mut app);
        let shown = capture(&mut app, &image);
        let scene = gathered_scene(&app, &space, root, fog);
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
            max_level: 8,
            cell_colors: cells,
            ..TraceSettings::default()
        };
        let compute = gpu.render(&space, &scene, &settings).expect("headless trace");
        let cpu = render::<f64>(&space, &scene, &settings);
        let vs_compute = agreement(&shown, &compute, 1);
        let vs_cpu = agreement(&shown, &cpu, 2);
        let lit = shown
            .chunks_exact(4)
            .filter(|p| p[0] > 8 || p[1] > 8 || p[2] > 8)
            .count();
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

#[test]
fn uploads_happen_only_when_something_changed() {
    if !gpu_available() {
        return;
    }
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

    // The camera turns: only the params uniform is written.
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

#[test]
fn a_viewport_shows_the_same_trace_as_a_whole_target() {
    if !gpu_available() {
        return;
    }
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
    assert_eq!(same, 64 * 48, "the inset viewport differs from the whole-target trace");
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

#[test]
fn cameras_without_the_marker_render_exactly_as_before() {
    if !gpu_available() {
        return;
    }
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
                wait_for_pipelines(&mut app);
            } else {
                for _ in 0..20 {
                    app.update();
                }
            }
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
