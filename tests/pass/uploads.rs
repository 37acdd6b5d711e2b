//! What the pass uploads and keeps: only what changed, buffers reused
//! across spaces, more ball copies than the GPU holds, and the last
//! pipeline drawing while a new one compiles.

use super::support::*;
use bevy::prelude::*;
use bevy::render::RenderApp;
use bevy_manifold::prelude::*;
use bevy_manifold::render::{ManifoldBufferCache, offscreen};
use bevy_manifold::trace::FlatScene;
use bevy_manifold_gpu::GpuTracer;
use bevy_manifold_test_support::compare::rgba8_agreement;

pub fn uploads_happen_only_when_something_changed() {
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
pub fn a_view_whose_space_changes_draws_each_space_from_its_reused_buffers() {
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

/// A scene whose balls make more copies than the GPU holds (254 large
/// balls in the torus: past `bevy_manifold_gpu::bindings::MAX_BALLS` with
/// their ghosts) is drawn, its first `MAX_BALLS` copies, with no
/// validation error; the same app then draws the default scene as the
/// headless tracer does.
pub fn a_scene_past_the_gpus_ball_copies_is_drawn_and_the_next_scene_is_right() {
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
            pbr: None,
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

/// A view whose balls cross a doubling of the ball tree's leaves (as the
/// shooter's shots do) keeps drawing them: the frames before the pipeline
/// for the new leaf count is compiled are drawn by the last one, and show
/// what the headless tracer shows of the new scene. Both ways: 8 leaves
/// to 16 (the last pipeline, compiled for 8, tests every ball) and then
/// 16 to 4 (the last, compiled for 16, tests the 4 there are, not the 12
/// left in its uniform from before, whose balls are gone). Not drawn, the frames would show the scene
/// before.
pub fn a_view_keeps_drawing_its_balls_while_a_new_leaf_count_compiles() {
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
        let flat = FlatScene::<f32>::new(
            &space,
            app.world().get::<ManifoldScene>(root).expect("gathered").scene(),
        );
        flat.ball_tree.words.len()
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
