//! `bench pass`: the render pass's fragment path against the compute path,
//! the pass inside a headless Bevy app, and Bevy's own rasteriser as a
//! reference point.

use crate::best_ms;
use bevy_manifold::prelude::*;
use bevy_manifold_gpu::GpuTracer;

/// Compute entry (storage buffer of pixels with ids, read back) against
/// the fragment entry (sRGB target and depth, read back) on one device,
/// then the pass inside Bevy.
pub fn pass(runs: u32) -> Result<(), String> {
    let mut tracer = GpuTracer::new().map_err(|e| e.to_string())?;
    println!(
        "compute vs fragment entry, default scene, 8 levels, trace + readback, best of {runs}, on {}",
        tracer.adapter_name()
    );
    println!(
        "{:<22} {:>10} {:>11} {:>12}",
        "space", "size", "compute ms", "fragment ms"
    );
    for name in catalog::NAMES {
        let space = catalog::by_name(name).ok_or_else(|| format!("no space {name}"))?;
        let scene = Scene::default_for(&space);
        for (width, height) in [(640, 360), (1280, 720)] {
            let settings = TraceSettings {
                width,
                height,
                levels: 8,
                ..TraceSettings::default()
            };
            let compute = best_ms(runs, || {
                tracer.render(&space, &scene, &settings).map_err(|e| e.to_string())
            })?;
            let fragment = best_ms(runs, || {
                tracer
                    .render_fragment(&space, &scene, &settings)
                    .map_err(|e| e.to_string())
            })?;
            println!(
                "{name:<22} {:>10} {compute:>11.1} {fragment:>12.1}",
                format!("{width}x{height}")
            );
        }
    }
    bevy_pass(runs)
}

/// Frame time of the pass in a headless Bevy app, and of the same scene
/// (one copy of it) drawn by Bevy's own rasteriser through an ordinary
/// camera.
fn bevy_pass(runs: u32) -> Result<(), String> {
    use bevy_manifold::render::offscreen;
    println!(
        "\nin a headless Bevy app, default scene, ms per frame (best of {runs}): the pass at 8 levels, and Bevy's rasteriser drawing one copy"
    );
    println!("{:<22} {:>10} {:>9} {:>10}", "space", "size", "trace ms", "raster ms");
    for name in catalog::NAMES {
        let space = catalog::by_name(name).ok_or_else(|| format!("no space {name}"))?;
        let scene = Scene::default_for(&space);
        for (width, height) in [(640, 360), (1280, 720)] {
            let mut app = offscreen::app(true);
            let image = offscreen::target(&mut app, width, height);
            offscreen::spawn_view(&mut app, &space, &scene, &image, ManifoldCamera::default());
            let trace = frame_ms(&mut app, &image, runs)?;
            let mut app = offscreen::app(false);
            let image = offscreen::target(&mut app, width, height);
            raster::spawn(&mut app, &space, &scene, &image);
            let raster = frame_ms(&mut app, &image, runs)?;
            println!(
                "{name:<22} {:>10} {trace:>9.1} {raster:>10.1}",
                format!("{width}x{height}")
            );
        }
    }
    Ok(())
}

/// Milliseconds per frame of an offscreen app once its pipelines are
/// ready: the difference between `1 + 5` and `1` frames each ending in a
/// read-back of `image` (which waits for the GPU), over 5; best of `runs`.
pub fn frame_ms(
    app: &mut bevy::app::App,
    image: &bevy::asset::Handle<bevy::image::Image>,
    runs: u32,
) -> Result<f64, String> {
    use bevy_manifold::render::offscreen;
    use std::time::Instant;
    offscreen::wait_for_pipelines(app)?;
    let mut frames = |n: u32| -> Result<f64, String> {
        let t = Instant::now();
        for _ in 0..n {
            app.update();
        }
        offscreen::capture(app, image)?;
        Ok(t.elapsed().as_secs_f64())
    };
    let mut best = f64::INFINITY;
    for _ in 0..runs {
        let short = frames(1)?;
        let long = frames(6)?;
        best = best.min((long - short) / 5.0);
    }
    Ok(best.max(0.0) * 1e3)
}

/// The default scene as ordinary Bevy meshes: the ball a UV sphere, the
/// domain's edges thin cylinders between their chart end points, the light
/// a point light, seen by a plain `Camera3d` at the scene's camera.
mod raster {
    use bevy::camera::RenderTarget;
    use bevy::prelude::*;
    use bevy_manifold::prelude::*;

    fn chart(p: glam::DVec4) -> Vec3 {
        (p.truncate() / p.w).as_vec3()
    }

    pub fn spawn(app: &mut App, space: &Space, scene: &Scene, image: &Handle<Image>) {
        let world = app.world_mut();
        let mut meshes = Vec::new();
        for b in &scene.balls {
            let c = chart(b.center);
            meshes.push((
                Sphere::new(b.radius as f32).mesh().uv(32, 16),
                Transform::from_translation(c),
                b.color,
            ));
        }
        if let Some(r) = scene.edge_radius {
            for e in space.edges() {
                let [a, b] = e.vertices.map(|i| chart(space.vertices()[i].point));
                let mid = (a + b) / 2.0;
                let along = b - a;
                let t =
                    Transform::from_translation(mid).with_rotation(Quat::from_rotation_arc(Vec3::Y, along.normalize()));
                meshes.push((
                    Cylinder::new(r as f32, along.length()).mesh().build(),
                    t,
                    [0.8, 0.8, 0.85],
                ));
            }
        }
        for (mesh, transform, [r, g, b]) in meshes {
            let mesh = world.resource_mut::<Assets<Mesh>>().add(mesh);
            let material = world
                .resource_mut::<Assets<StandardMaterial>>()
                .add(StandardMaterial::from_color(Color::linear_rgb(r, g, b)));
            world.spawn((Mesh3d(mesh), MeshMaterial3d(material), transform));
        }
        for l in &scene.lights {
            world.spawn((
                PointLight {
                    intensity: 20_000.0,
                    ..default()
                },
                Transform::from_translation(chart(l.position)),
            ));
        }
        let eye = chart(scene.camera.isometry * glam::DVec4::W);
        let forward = (scene.camera.isometry * glam::DVec4::NEG_Z).truncate().as_vec3();
        world.spawn((
            Camera3d::default(),
            RenderTarget::Image(image.clone().into()),
            Projection::Perspective(PerspectiveProjection {
                fov: (scene.camera.fov_y_degrees as f32).to_radians(),
                ..default()
            }),
            Transform::from_translation(eye).looking_to(forward, Vec3::Y),
        ));
        world.flush();
    }
}
