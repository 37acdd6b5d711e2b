//! Bevy meshes in a manifold: glTF meshes and whole glTF scenes traced, not
//! rasterised.

use super::support::*;
use bevy::prelude::*;
use bevy_manifold::prelude::*;

pub fn gltf_meshes_in_a_manifold_are_traced_and_not_rasterised() {
    use bevy::camera::visibility::RenderLayers;
    use bevy_manifold::drawables::MeshBvhCache;
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

pub fn gltf_scene_roots_in_a_manifold_are_traced() {
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
