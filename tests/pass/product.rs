//! A [`ProductCamera`] in a Bevy app: the pass draws what the CPU f64
//! reference traces for the camera's scene, in H2xR and S2xR; a camera
//! that moves draws its new view.

use super::support::*;
use bevy::prelude::*;
use bevy_manifold::product::ProductCamera;
use bevy_manifold::space::product::ProductSpace;
use bevy_manifold::trace::product::{ProductScene, render};

/// What the product pass has uploaded so far.
fn product_uploads(app: &App) -> bevy_manifold::product::render::ProductUploads {
    app.sub_app(bevy::render::RenderApp)
        .world()
        .resource::<bevy_manifold::product::render::ProductBuffers>()
        .uploads
}

/// A `ProductSpaceRoot` of `space` with `scene`'s balls and lights among
/// its children: the root and the lights.
fn spawn_lit_root(app: &mut App, space: &ProductSpace, scene: &ProductScene) -> (Entity, Vec<Entity>) {
    use bevy_manifold::product::{ProductBody, ProductPointLight, ProductSpaceRoot};
    let root = app
        .world_mut()
        .spawn(ProductSpaceRoot(std::sync::Arc::new(space.clone())))
        .id();
    for b in &scene.balls {
        app.world_mut().spawn((ChildOf(root), ProductBody::from(*b)));
    }
    let lights = scene
        .lights
        .iter()
        .map(|l| app.world_mut().spawn((ChildOf(root), ProductPointLight(*l))).id())
        .collect();
    (root, lights)
}

/// A product camera on a `Camera3d` that renders into `image`.
fn spawn_product_camera(app: &mut App, image: &Handle<Image>, camera: ProductCamera) -> Entity {
    app.world_mut()
        .spawn((
            Camera3d::default(),
            bevy::camera::RenderTarget::Image(image.clone().into()),
            camera,
        ))
        .id()
}

/// What the pass draws for a product camera is the CPU reference's view
/// (sRGB bytes within 3 of it in 99% of the pixels: the rest are
/// silhouettes, where f32 and f64 sphere tracing part, and far hits in
/// H2xR); after the camera moves, the new view, as the headless GPU
/// tracer draws it. A still view uploads nothing; a moving one only its
/// params.
pub fn a_product_camera_draws_what_the_cpu_reference_traces() {
    for space in [ProductSpace::genus_two_x_s1(2.0), ProductSpace::s2_x_s1(2.0)] {
        let mut app = headless_app(true);
        let image = target(&mut app, W, H);
        let camera = ProductCamera::default_for(space.clone());
        let entity = spawn_product_camera(&mut app, &image, camera.clone());
        wait_for_pipelines(&mut app);
        let shown = capture(&mut app, &image);
        let cpu: Vec<[f32; 3]> = render(&space, &camera.scene(), W, H).iter().map(|p| p.color).collect();
        let agree = close_to(&shown, &cpu, 3);
        eprintln!(
            "{}: {:.3}% of pixels within 3/255 of the CPU reference",
            space.name,
            100.0 * agree
        );
        assert!(agree >= 0.99, "{}: {agree}", space.name);
        // Balls and fog: the picture is not one colour.
        let mut colours: Vec<&[u8]> = shown.chunks_exact(4).collect();
        colours.sort_unstable();
        colours.dedup();
        assert!(colours.len() > 20, "{}: {} colours", space.name, colours.len());
        // A still view uploads nothing more.
        let still = product_uploads(&app);
        for _ in 0..5 {
            app.update();
        }
        assert_eq!(product_uploads(&app), still, "{}: a still view uploaded", space.name);
        // Moved forward 1.5 and turned: the pass follows the camera, and
        // draws what the headless GPU tracer draws (the same shader and
        // f32 arithmetic: the pass's plumbing, exactly) and, but for the
        // f32 rays that part from the f64 ones (in H2xR far hits), what
        // the CPU traces.
        let moved = camera
            .view
            .moved(&space, [1.0, 0.0, 0.2], 1.5)
            .turned(space.geometry, 0.4, 0.1);
        app.world_mut()
            .get_mut::<ProductCamera>(entity)
            .expect("the camera")
            .view = moved;
        let shown_moved = capture(&mut app, &image);
        let mut moved_scene = camera.scene();
        moved_scene.view = moved;
        let headless: Vec<[f32; 3]> = bevy_manifold_gpu::GpuTracer::new()
            .expect("a GPU")
            .render_product(&space, &moved_scene, W, H)
            .expect("the headless trace")
            .iter()
            .map(|p| p.color)
            .collect();
        let cpu_moved: Vec<[f32; 3]> = render(
            &space,
            &ProductScene {
                view: moved,
                ..camera.scene()
            },
            W,
            H,
        )
        .iter()
        .map(|p| p.color)
        .collect();
        let (same, near) = (
            close_to(&shown_moved, &headless, 1),
            close_to(&shown_moved, &cpu_moved, 3),
        );
        eprintln!(
            "{} moved: {:.3}% within 1/255 of the headless trace, {:.3}% within 3/255 of the CPU reference",
            space.name,
            100.0 * same,
            100.0 * near
        );
        assert!(same >= 0.999, "{} moved: {same}", space.name);
        // Moving wrote the params again, not the faces and balls.
        let moved_uploads = product_uploads(&app);
        assert!(moved_uploads.params > still.params, "{moved_uploads:?}");
        assert_eq!(moved_uploads.scenes, still.scenes, "{moved_uploads:?}");
        assert!(near >= 0.98, "{} moved: {near}", space.name);
        assert!(
            close_to(&shown_moved, &cpu, 3) < 0.9,
            "{}: the view did not change",
            space.name
        );
    }
}

/// A product camera that shades by cell draws each copy of the prism in
/// its own colour: as the headless GPU tracer does (within 1/255: the
/// pass's table and tint plumbing), and as the CPU reference does with its
/// exact cells (within 3/255 in 98% of the pixels: the GPU's table of
/// cells holds 95% of the hits here, those past it are grey). When the eye
/// flies across a face into another copy, the pass writes the table of
/// cells about it again and the colours follow.
pub fn a_product_camera_shades_each_copy_by_its_cell() {
    use bevy_manifold::space::cells::CellTint;
    let space = ProductSpace::genus_two_x_s1(2.0);
    let mut app = headless_app(true);
    let image = target(&mut app, W, H);
    let mut camera = ProductCamera::default_for(space.clone());
    camera.view.tint = Some(CellTint::ByCell);
    let entity = spawn_product_camera(&mut app, &image, camera.clone());
    wait_for_pipelines(&mut app);
    let mut gpu = bevy_manifold_gpu::GpuTracer::new().expect("a GPU");
    let mut compare = |app: &mut App, view| {
        let shown = capture(app, &image);
        let mut scene = camera.scene();
        scene.view = view;
        let colors = |p: Vec<bevy_manifold::trace::product::ProductPixel>| -> Vec<[f32; 3]> {
            p.iter().map(|p| p.color).collect()
        };
        let headless = colors(gpu.render_product(&space, &scene, W, H).expect("the headless trace"));
        let cpu = colors(render(&space, &ProductScene { view, ..camera.scene() }, W, H));
        let (same, near) = (close_to(&shown, &headless, 1), close_to(&shown, &cpu, 3));
        eprintln!(
            "{} by cell: {:.3}% within 1/255 of the headless trace, {:.3}% within 3/255 of the CPU reference",
            space.name,
            100.0 * same,
            100.0 * near
        );
        assert!(same >= 0.999 && near >= 0.98, "{same} {near}");
        shown
    };
    let shown = compare(&mut app, camera.view);
    let before = product_uploads(&app);
    // Across a side of the octagon: the eye is in another copy.
    let moved = camera.view.moved(&space, [1.0, 0.0, 0.0], 2.5);
    assert_ne!(moved.cell, camera.view.cell, "the move crossed no face");
    app.world_mut()
        .get_mut::<ProductCamera>(entity)
        .expect("the camera")
        .view = moved;
    let shown_moved = compare(&mut app, moved);
    let unchanged = shown
        .chunks_exact(4)
        .zip(shown_moved.chunks_exact(4))
        .filter(|(a, b)| a == b)
        .count();
    assert!(unchanged * 10 < 9 * shown.len() / 4, "the view did not change");
    let after = product_uploads(&app);
    assert_eq!(after.tables, before.tables + 1, "{after:?}");
}

/// A product camera lit by `ProductPointLight`s among its root's children
/// (every image of each, with shadows) draws what the headless GPU tracer
/// draws for the lit scene (within 1/255: the pass's light images, gathered
/// and packed once, and its specialised shader) and what the CPU reference
/// traces (within 3/255 in 98% of the pixels); with the lights taken away
/// it draws the scene lit from the eye again.
pub fn a_product_camera_is_lit_by_its_roots_lights() {
    for space in [ProductSpace::s2_x_s1(2.0), ProductSpace::genus_two_x_s1(2.0)] {
        let mut app = headless_app(true);
        let image = target(&mut app, W, H);
        let scene = ProductScene::lit_for(&space);
        let (root, lights) = spawn_lit_root(&mut app, &space, &scene);
        let camera = spawn_product_camera(&mut app, &image, ProductCamera::default_for(space.clone()));
        app.world_mut().entity_mut(camera).insert(ChildOf(root));
        wait_for_pipelines(&mut app);
        let shown = capture(&mut app, &image);
        let colors = |p: Vec<bevy_manifold::trace::product::ProductPixel>| -> Vec<[f32; 3]> {
            p.iter().map(|p| p.color).collect()
        };
        let headless = colors(
            bevy_manifold_gpu::GpuTracer::new()
                .expect("a GPU")
                .render_product(&space, &scene, W, H)
                .expect("the headless trace"),
        );
        let cpu = colors(render(&space, &scene, W, H));
        let (same, near) = (close_to(&shown, &headless, 1), close_to(&shown, &cpu, 3));
        eprintln!(
            "{} lit: {:.3}% within 1/255 of the headless trace, {:.3}% within 3/255 of the CPU reference",
            space.name,
            100.0 * same,
            100.0 * near
        );
        assert!(same >= 0.999, "{} lit: {same}", space.name);
        assert!(near >= 0.98, "{} lit: {near}", space.name);
        // The lights taken away: lit from the eye, as the default scene.
        for l in lights {
            app.world_mut().entity_mut(l).despawn();
        }
        // (The shader without the lights' code is another specialisation.)
        app.update();
        wait_for_pipelines(&mut app);
        let unlit = capture(&mut app, &image);
        let from_eye = colors(render(&space, &ProductScene::default_for(&space), W, H));
        let back = close_to(&unlit, &from_eye, 3);
        assert!(back >= 0.98, "{} without its lights: {back}", space.name);
        assert!(
            close_to(&unlit, &cpu, 3) < 0.9,
            "{}: the lights changed nothing",
            space.name
        );
    }
}

/// Meshes in a product space: a Bevy `Cuboid` asset on a `Mesh3d` with a
/// `ProductMeshPlacement` (y up, turned into the chart's z up) and the
/// airplane as a `ProductMeshBody`, among the root's children, draw what
/// the CPU reference traces for `ProductScene::furnished_for` (whose box
/// is the core's own `cuboid`, made apart from Bevy's) and what the
/// headless GPU tracer draws. Moving the box's placement writes the mesh
/// images again, not the meshes' triangles.
pub fn meshes_in_a_product_space_are_traced() {
    use bevy_manifold::product::{ProductMeshBody, ProductMeshPlacement, ProductSpaceRoot};
    use std::sync::Arc;
    for space in [ProductSpace::genus_two_x_s1(2.0), ProductSpace::s2_x_s1(2.0)] {
        let mut app = headless_app(true);
        let image = target(&mut app, W, H);
        let mut scene = ProductScene::furnished_for(&space);
        let root = app.world_mut().spawn(ProductSpaceRoot(Arc::new(space.clone()))).id();
        for b in &scene.balls {
            app.world_mut()
                .spawn((ChildOf(root), bevy_manifold::product::ProductBody::from(*b)));
        }
        app.world_mut()
            .spawn((ChildOf(root), ProductMeshBody(scene.meshes[0].clone())));
        let cuboid = app
            .world_mut()
            .resource_mut::<Assets<Mesh>>()
            .add(Cuboid::new(0.24, 0.36, 0.24));
        let block = scene.meshes[1].clone();
        let placed = app
            .world_mut()
            .spawn((
                ChildOf(root),
                Mesh3d(cuboid),
                ProductMeshPlacement {
                    placement: block.placement,
                    id: block.id,
                },
            ))
            .id();
        let camera = spawn_product_camera(&mut app, &image, ProductCamera::default_for(space.clone()));
        app.world_mut().entity_mut(camera).insert(ChildOf(root));
        wait_for_pipelines(&mut app);
        let mut gpu = bevy_manifold_gpu::GpuTracer::new().expect("a GPU");
        let mut compare = |app: &mut App, scene: &ProductScene| {
            let shown = capture(app, &image);
            let colors = |p: Vec<bevy_manifold::trace::product::ProductPixel>| -> Vec<[f32; 3]> {
                p.iter().map(|p| p.color).collect()
            };
            let headless = colors(gpu.render_product(&space, scene, W, H).expect("the headless trace"));
            let cpu = render(&space, scene, W, H);
            let seen = cpu.iter().filter(|p| p.object == 4 || p.object == 5).count();
            let cpu = colors(cpu);
            let (same, near) = (close_to(&shown, &headless, 1), close_to(&shown, &cpu, 3));
            eprintln!(
                "{} with meshes: {seen} pixels of meshes, {:.3}% within 1/255 of the headless trace, {:.3}% within 3/255 of the CPU reference",
                space.name,
                100.0 * same,
                100.0 * near
            );
            assert!(seen > 100, "{}: {seen} pixels of meshes", space.name);
            assert!(same >= 0.999 && near >= 0.98, "{}: {same} {near}", space.name);
        };
        compare(&mut app, &scene);
        let before = product_uploads(&app);
        // The box lifted 0.2 and turned.
        let g = space.geometry;
        let lifted =
            bevy_manifold::geometry::product::ProductIsometry::new(g.rotation(0.5), 1.0, 0.2).compose(&block.placement);
        app.world_mut()
            .get_mut::<ProductMeshPlacement>(placed)
            .expect("the box")
            .placement = lifted;
        scene.meshes[1].placement = lifted;
        compare(&mut app, &scene);
        let after = product_uploads(&app);
        // The mesh images written again (and nothing as large as the
        // triangles: the airplane's alone are 200 of 96 bytes).
        assert_eq!(after.scenes, before.scenes + 1, "{after:?}");
        assert!(after.bytes - before.bytes < 4096, "{before:?} {after:?}");
    }
}

/// Two product cameras showing the same lit scene (as a headset's two
/// eyes do) share one working-out of the light images, off the main
/// thread; when a light moves, the images are worked out once more and
/// both cameras come to draw the new lighting (what the CPU reference
/// traces, within 3/255 in 98% of the pixels).
pub fn light_images_are_worked_out_once_for_every_camera_that_shows_them() {
    use bevy_manifold::product::ProductPointLight;
    use bevy_manifold::product::render::ProductLightJobs;
    let space = ProductSpace::genus_two_x_s1(2.0);
    let mut app = headless_app(true);
    let images = [target(&mut app, W, H), target(&mut app, W, H)];
    let mut scene = ProductScene::lit_for(&space);
    let (root, lights) = spawn_lit_root(&mut app, &space, &scene);
    for image in &images {
        let camera = spawn_product_camera(&mut app, image, ProductCamera::default_for(space.clone()));
        app.world_mut().entity_mut(camera).insert(ChildOf(root));
    }
    wait_for_pipelines(&mut app);
    let started = |app: &App| {
        app.sub_app(bevy::render::RenderApp)
            .world()
            .resource::<ProductLightJobs>()
            .started
    };
    let agree = |app: &mut App, scene: &ProductScene| -> [f64; 2] {
        let cpu: Vec<[f32; 3]> = render(&space, scene, W, H).iter().map(|p| p.color).collect();
        images.clone().map(|image| close_to(&capture(app, &image), &cpu, 3))
    };
    let first = agree(&mut app, &scene);
    eprintln!("two cameras, lit: {first:?} of pixels within 3/255 of the CPU reference");
    assert!(first.iter().all(|&a| a >= 0.98), "{first:?}");
    assert_eq!(started(&app), 1, "one working-out for both cameras");
    // The warm light moved down the circle.
    scene.lights[0].position.height -= 0.5;
    app.world_mut()
        .get_mut::<ProductPointLight>(lights[0])
        .expect("the light")
        .0 = scene.lights[0];
    let mut now = [0.0; 2];
    for _ in 0..60 {
        app.update();
        now = agree(&mut app, &scene);
        if now.iter().all(|&a| a >= 0.98) {
            break;
        }
    }
    eprintln!("the light moved: {now:?} within 3/255 of the new CPU reference");
    assert!(now.iter().all(|&a| a >= 0.98), "{now:?}");
    assert_eq!(started(&app), 2, "one more working-out, for both cameras");
    assert!(
        agree(&mut app, &ProductScene::lit_for(&space))
            .iter()
            .all(|&a| a < 0.95),
        "the light's move changed nothing"
    );
}
