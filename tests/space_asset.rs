//! Assets in a manifold: space files loaded by the asset server onto a
//! root, swapped when the asset changes, failures reported as asset events
//! while the root keeps its space; tour files with their space files; and
//! meshes traced once they arrive.

use bevy::asset::AssetLoadFailedEvent;
use bevy::prelude::*;
use bevy_manifold::geometry::{Geometry, isometry};
use bevy_manifold::prelude::*;
use bevy_manifold::space::library;
use glam::{DMat4, DVec3};
use std::path::PathBuf;
use std::sync::Arc;

#[derive(Resource, Default)]
struct Failures(Vec<String>);

fn collect(mut failed: MessageReader<AssetLoadFailedEvent<SpaceAsset>>, mut all: ResMut<Failures>) {
    all.0.extend(failed.read().map(|e| format!("{}: {}", e.path, e.error)));
}

/// A folder of space files for this test run.
fn folder() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("bevy_manifold_space_assets_{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let lens = library::by_name("lens-7-2").expect("library");
    std::fs::write(dir.join("lens-7-2.gen"), lens.to_gen("test")).expect("write");
    std::fs::write(dir.join("broken.gen"), "1 0 0 0\n0 1 0 0\n0 0 1 0\n").expect("write");
    std::fs::write(dir.join("torus.space.json"), catalog::torus(1.0).to_json()).expect("write");
    dir
}

fn app(dir: &std::path::Path) -> App {
    let mut app = App::new();
    app.add_plugins((
        MinimalPlugins,
        AssetPlugin {
            file_path: dir.display().to_string(),
            ..default()
        },
        ManifoldPlugins::default(),
    ))
    .init_resource::<Failures>()
    .add_systems(Last, collect);
    app
}

/// Updates until `done` holds (the loader runs on the task pool).
fn update_until(app: &mut App, what: &str, done: impl Fn(&mut App) -> bool) {
    for _ in 0..2_000 {
        app.update();
        if done(app) {
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    panic!("timed out waiting for {what}");
}

#[test]
fn a_gen_file_loads_onto_its_root_and_a_swap_rewraps_the_members() {
    let dir = folder();
    let mut app = app(&dir);
    let handle: Handle<SpaceAsset> = app.world().resource::<AssetServer>().load("lens-7-2.gen");
    let root = app.world_mut().spawn(ManifoldSpaceSource(handle.clone())).id();
    // A member placed before the space is there.
    let s = Geometry::Spherical;
    let member = app
        .world_mut()
        .spawn((
            ChildOf(root),
            Placement::from_isometry(isometry::translation(s, DVec3::new(0.05, 0.0, 0.0))),
        ))
        .id();
    update_until(&mut app, "the lens space", |app| {
        app.world().get::<ManifoldSpace>(root).is_some()
    });
    let space = app.world().get::<ManifoldSpace>(root).expect("loaded").space().clone();
    assert_eq!(space.name(), "lens-7-2");
    assert_eq!(space.geometry(), Geometry::Spherical);
    assert_eq!(space.group_order(), Some(7));
    assert!((space.volume() - 2.0 * std::f64::consts::PI.powi(2) / 7.0).abs() < 1e-9);

    // The asset changes (what hot reload does): the root takes the new
    // space, and the member is wrapped into the new domain from its origin
    // cell. A point far outside the Poincare dodecahedron ends inside it.
    app.world_mut().get_mut::<Placement>(member).expect("member").isometry =
        isometry::translation(s, DVec3::new(1.2, 0.3, 0.0));
    app.update();
    // Where the lens space's wrap left it: the chart point the swap keeps.
    let before = app.world().get::<Placement>(member).expect("member").isometry;
    let poincare = catalog::poincare();
    assert!(
        poincare.outside_face(before.w_axis, 1e-6).is_some(),
        "the test wants a point outside the Poincare dodecahedron"
    );
    app.world_mut()
        .resource_mut::<Assets<SpaceAsset>>()
        .insert(handle.id(), SpaceAsset(Arc::new(poincare.clone())))
        .expect("insert");
    update_until(&mut app, "the swap", |app| {
        app.world()
            .get::<ManifoldSpace>(root)
            .is_some_and(|m| m.space().name() == "poincare")
    });
    app.update();
    let placed = app.world().get::<Placement>(member).expect("member").isometry;
    assert!(
        poincare.outside_face(placed.w_axis, 1e-9).is_none(),
        "the member was wrapped into the new domain"
    );
    let cell = app.world().get::<DomainCell>(member).expect("cell");
    // Its point in the cover is unchanged by the wrap: element * placement.
    let back = cell.element * placed;
    assert!(
        (back - before).to_cols_array().iter().all(|x| x.abs() < 1e-9),
        "the cover point moved: {:?} vs {:?}",
        back.w_axis,
        before.w_axis
    );
    assert_ne!(cell.element, DMat4::IDENTITY);
}

#[test]
fn a_broken_file_is_reported_and_the_root_keeps_its_space() {
    let dir = folder();
    let mut app = app(&dir);
    let server = app.world().resource::<AssetServer>().clone();
    let root = app
        .world_mut()
        .spawn(ManifoldSpaceSource(server.load("torus.space.json")))
        .id();
    update_until(&mut app, "the torus", |app| {
        app.world().get::<ManifoldSpace>(root).is_some()
    });
    app.world_mut()
        .entity_mut(root)
        .insert(ManifoldSpaceSource(server.load("broken.gen")));
    update_until(&mut app, "the failure", |app| {
        !app.world().resource::<Failures>().0.is_empty()
    });
    let failures = &app.world().resource::<Failures>().0;
    assert!(
        failures[0].contains("broken.gen") && failures[0].contains("matrix 0 is incomplete"),
        "{failures:?}"
    );
    for _ in 0..5 {
        app.update();
    }
    let kept = app.world().get::<ManifoldSpace>(root).expect("still there");
    assert_eq!(kept.space().name(), "torus");
}

/// The test app with Bevy's meshes, its plugins finished (the mesh
/// gathering is registered where meshes exist).
fn mesh_app() -> App {
    let mut app = app(&folder());
    app.init_asset::<Mesh>();
    app.finish();
    app.cleanup();
    app
}

/// A `Mesh3d` whose asset is not there yet (still loading) is traced once it
/// arrives, while the entity keeps moving; before, the missing asset was
/// cached as untraceable for good.
#[test]
fn a_mesh_that_arrives_after_its_entity_is_traced_from_then_on() {
    use bevy::asset::RenderAssetUsages;
    use bevy::mesh::{Indices, PrimitiveTopology};
    let mut app = mesh_app();
    let space = catalog::torus(1.0);
    let root = app.world_mut().spawn(ManifoldSpace::new(space.clone())).id();
    let handle = app.world().resource::<Assets<Mesh>>().reserve_handle();
    let mover = app
        .world_mut()
        .spawn((
            ChildOf(root),
            Mesh3d(handle.clone()),
            Placement::default(),
            Transform::default(),
        ))
        .id();
    // Frames go by with the entity moving and the mesh still "loading".
    let e = Geometry::Euclidean;
    for k in 0..5 {
        app.world_mut().get_mut::<Placement>(mover).expect("placed").isometry =
            isometry::translation(e, DVec3::X * (0.01 * f64::from(k)));
        app.update();
        let traced = app
            .world()
            .get::<bevy_manifold::drawables::ManifoldMeshes>(root)
            .map_or(0, |m| m.meshes.len());
        assert_eq!(traced, 0, "nothing to trace before the mesh is there");
    }
    // It arrives.
    let mut mesh = Mesh::new(PrimitiveTopology::TriangleList, RenderAssetUsages::default());
    mesh.insert_attribute(
        Mesh::ATTRIBUTE_POSITION,
        vec![[0.0f32, 0.0, 0.0], [0.1, 0.0, 0.0], [0.0, 0.1, 0.0]],
    );
    mesh.insert_indices(Indices::U32(vec![0, 1, 2]));
    app.world_mut()
        .resource_mut::<Assets<Mesh>>()
        .insert(handle.id(), mesh)
        .expect("insert");
    for _ in 0..3 {
        app.update();
    }
    let meshes = app
        .world()
        .get::<bevy_manifold::drawables::ManifoldMeshes>(root)
        .expect("gathered");
    assert_eq!(meshes.meshes.len(), 1, "the mesh is traced once it is there");
    assert_eq!(meshes.meshes[0].data.mesh.triangles.len(), 1);
}

/// A mesh past `ASYNC_BVH_TRIANGLES` has its BVH built off the frame: the
/// frame that meets it does not wait, and the mesh appears once built.
#[test]
fn a_large_mesh_is_built_off_the_frame_and_appears_when_ready() {
    use bevy::asset::RenderAssetUsages;
    use bevy::mesh::{Indices, PrimitiveTopology};
    use bevy_manifold::drawables::{ASYNC_BVH_TRIANGLES, MeshBvhCache};
    let mut app = mesh_app();
    // A 200 x 200 grid: 80,000 triangles.
    let n = 200u32;
    let positions: Vec<[f32; 3]> = (0..=n)
        .flat_map(|i| (0..=n).map(move |j| [i as f32 * 0.001, j as f32 * 0.001, 0.0]))
        .collect();
    let mut indices = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let a = i * (n + 1) + j;
            indices.extend([a, a + 1, a + n + 1, a + 1, a + n + 2, a + n + 1]);
        }
    }
    assert!(indices.len() / 3 > ASYNC_BVH_TRIANGLES);
    let mut mesh = Mesh::new(PrimitiveTopology::TriangleList, RenderAssetUsages::default());
    mesh.insert_attribute(Mesh::ATTRIBUTE_POSITION, positions);
    mesh.insert_indices(Indices::U32(indices));
    let handle = app.world_mut().resource_mut::<Assets<Mesh>>().add(mesh);
    let root = app.world_mut().spawn(ManifoldSpace::new(catalog::torus(1.0))).id();
    app.world_mut().spawn((
        ChildOf(root),
        Mesh3d(handle),
        Placement::default(),
        Transform::default(),
    ));
    app.update();
    assert_eq!(
        app.world().resource::<MeshBvhCache>().building(),
        1,
        "built off the frame"
    );
    update_until(&mut app, "the large mesh", |app| {
        app.world()
            .get::<bevy_manifold::drawables::ManifoldMeshes>(root)
            .is_some_and(|m| m.meshes.len() == 1)
    });
    assert_eq!(app.world().resource::<MeshBvhCache>().building(), 0);
}

#[derive(Resource, Default)]
struct TourFailures(Vec<String>);

fn collect_tours(mut failed: MessageReader<AssetLoadFailedEvent<TourAsset>>, mut all: ResMut<TourFailures>) {
    all.0.extend(failed.read().map(|e| format!("{}: {}", e.path, e.error)));
}

#[test]
fn a_tour_file_loads_as_an_asset_with_its_space_file_and_a_broken_one_is_named() {
    let dir = folder();
    // A tour in a space file next to it (read through the asset server),
    // and one whose times go backwards.
    std::fs::write(
        dir.join("short.tour.json"),
        r#"{"space": "torus.space.json", "keyframes": [
            {"time": 0, "position": [0, 0, 0, 1]},
            {"fly": {"seconds": 3, "speed": 0.5}, "caption": "ahead"}]}"#,
    )
    .expect("write");
    std::fs::write(
        dir.join("backwards.tour.json"),
        r#"{"space": "torus", "keyframes": [
            {"time": 2, "position": [0, 0, 0, 1]}, {"time": 1, "position": [0.1, 0, 0, 1]}]}"#,
    )
    .expect("write");
    let mut app = app(&dir);
    app.init_resource::<TourFailures>().add_systems(Last, collect_tours);
    let assets = app.world().resource::<AssetServer>().clone();
    let source = TourSource(assets.load("short.tour.json"));
    let root = app.world_mut().spawn(source.clone()).id();
    let camera = app.world_mut().spawn((ChildOf(root), source)).id();
    let broken_root = app.world_mut().spawn(ManifoldSpace::new(catalog::torus(1.0))).id();
    let broken = app
        .world_mut()
        .spawn((ChildOf(broken_root), TourSource(assets.load("backwards.tour.json"))))
        .id();
    update_until(&mut app, "the tour and the broken one", |app| {
        app.world().get::<TourPlayer>(camera).is_some() && !app.world().resource::<TourFailures>().0.is_empty()
    });
    // The root took the tour's space; the camera plays the tour: 3 s
    // flying ahead at 0.5, so at 2 s it is 1.0 along -z, wrapped once
    // through the unit torus's face back to the start point.
    let space = app
        .world()
        .get::<ManifoldSpace>(root)
        .expect("the tour's space")
        .space()
        .clone();
    assert_eq!(space.name(), catalog::torus(1.0).name());
    let player = app.world().get::<TourPlayer>(camera).unwrap();
    assert!((player.tour().duration() - 3.0).abs() < 1e-12);
    assert_eq!(player.tour().caption_at(1.0), Some("ahead"));
    let at = player.tour().frame(&space, 2.0).placement;
    let want = isometry::translation(Geometry::Euclidean, DVec3::ZERO);
    assert!(
        (at - want).to_cols_array().iter().all(|x| x.abs() < 1e-9),
        "one period ahead is the start: {at:?}"
    );
    let failures = &app.world().resource::<TourFailures>().0;
    assert!(
        failures[0].contains("backwards.tour.json") && failures[0].contains("keyframes[1].time"),
        "{failures:?}"
    );
    assert!(app.world().get::<TourPlayer>(broken).is_none());
}

/// A mesh entity spawned as a Bevy scene spawns it (a `Transform` with a
/// turn and a scale of its own on each axis, mirrored or not, and no
/// placement) is traced where Bevy would draw it: in the torus, whose
/// chart is Euclidean space, each vertex lands at Bevy's own
/// `Transform::transform_point` of it.
#[test]
fn a_scale_of_its_own_on_each_axis_is_traced_as_bevy_draws_it() {
    use bevy::asset::RenderAssetUsages;
    use bevy::mesh::{Indices, PrimitiveTopology};
    let mut app = mesh_app();
    let root = app.world_mut().spawn(ManifoldSpace::new(catalog::torus(1.0))).id();
    let corners = vec![[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.3, 0.2, 1.0]];
    let mut mesh = Mesh::new(PrimitiveTopology::TriangleList, RenderAssetUsages::default());
    mesh.insert_attribute(Mesh::ATTRIBUTE_POSITION, corners.clone());
    mesh.insert_indices(Indices::U32(vec![0, 1, 2, 0, 1, 3]));
    let handle = app.world_mut().resource_mut::<Assets<Mesh>>().add(mesh);
    let transforms = [
        Transform::from_xyz(0.1, -0.2, 0.05)
            .with_rotation(Quat::from_euler(EulerRot::YXZ, 0.4, -0.3, 0.2))
            .with_scale(Vec3::new(0.1, 0.3, 0.05)),
        Transform::from_xyz(-0.2, 0.1, 0.15)
            .with_rotation(Quat::from_rotation_z(1.1))
            .with_scale(Vec3::new(-0.2, 0.05, 0.1)),
    ];
    let entities: Vec<Entity> = transforms
        .iter()
        .map(|t| app.world_mut().spawn((ChildOf(root), Mesh3d(handle.clone()), *t)).id())
        .collect();
    for _ in 0..3 {
        app.update();
    }
    let meshes = app
        .world()
        .get::<bevy_manifold::drawables::ManifoldMeshes>(root)
        .expect("gathered");
    assert_eq!(meshes.meshes.len(), 2);
    for (t, e) in transforms.iter().zip(&entities) {
        let k = meshes.entities.iter().position(|x| x == e).expect("traced");
        let m = &meshes.meshes[k];
        let to_chart = m.placement * DMat4::from_scale(DVec3::splat(m.scale)) * m.local;
        // The mesh's own triangles keep their vertices in order.
        for p in &corners {
            let got = to_chart.transform_point3(Vec3::from(*p).as_dvec3());
            let want = t.transform_point(Vec3::from(*p)).as_dvec3();
            assert!(
                (got - want).abs().max_element() < 1e-5,
                "{t:?}: vertex {p:?} traced at {got}, Bevy draws it at {want}"
            );
        }
    }
}

/// A mesh with morph targets is traced in the shape its weights blend,
/// `p + sum_i w_i d_i` for each vertex (Bevy's morph targets), whether
/// the weights are the entity's own or those of the `MorphWeights` it
/// refers to (as a glTF scene spawns them), and again when they change.
#[test]
fn a_morphing_mesh_is_traced_in_the_shape_its_weights_blend() {
    use bevy::asset::RenderAssetUsages;
    use bevy::mesh::morph::{MeshMorphWeights, MorphAttributes, MorphWeights};
    use bevy::mesh::{Indices, PrimitiveTopology};
    let mut app = mesh_app();
    let root = app.world_mut().spawn(ManifoldSpace::new(catalog::torus(1.0))).id();
    let base = [[0.0f32, 0.0, 0.0], [0.1, 0.0, 0.0], [0.0, 0.1, 0.0], [0.1, 0.1, 0.0]];
    // Two targets: the first lifts the far corner, the second pushes the
    // first two corners along x.
    let d = [
        [[0.0f32, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.08]],
        [[0.02f32, 0.0, 0.0], [0.04, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]],
    ];
    let mut mesh = Mesh::new(PrimitiveTopology::TriangleList, RenderAssetUsages::default());
    mesh.insert_attribute(Mesh::ATTRIBUTE_POSITION, base.to_vec());
    mesh.insert_indices(Indices::U32(vec![0, 1, 2, 1, 3, 2]));
    mesh.set_morph_targets(
        d.iter()
            .flat_map(|t| {
                t.iter()
                    .map(|&p| MorphAttributes::new(Vec3::from(p), Vec3::ZERO, Vec3::ZERO))
            })
            .collect(),
    );
    let handle = app.world_mut().resource_mut::<Assets<Mesh>>().add(mesh);
    let own = app
        .world_mut()
        .spawn((
            ChildOf(root),
            Mesh3d(handle.clone()),
            Placement::default(),
            Transform::default(),
            MeshMorphWeights::Value {
                weights: vec![0.5, 0.25],
            },
        ))
        .id();
    let holder = app
        .world_mut()
        .spawn(MorphWeights::new(vec![1.0, 0.0], None).expect("weights"))
        .id();
    let shared = app
        .world_mut()
        .spawn((
            ChildOf(root),
            Mesh3d(handle),
            Placement::default(),
            Transform::default(),
            MeshMorphWeights::Reference(holder),
        ))
        .id();
    let shape = |app: &App, e: Entity| -> Vec<[f32; 3]> {
        let meshes = app
            .world()
            .get::<bevy_manifold::drawables::ManifoldMeshes>(root)
            .expect("gathered");
        let k = meshes.entities.iter().position(|x| *x == e).expect("traced");
        meshes.meshes[k].data.mesh.positions.clone()
    };
    let blend = |w: [f32; 2]| -> Vec<[f32; 3]> {
        (0..4)
            .map(|v| [0, 1, 2].map(|c| base[v][c] + w[0] * d[0][v][c] + w[1] * d[1][v][c]))
            .collect()
    };
    let same = |a: &[[f32; 3]], b: &[[f32; 3]]| {
        a.iter()
            .flatten()
            .zip(b.iter().flatten())
            .all(|(x, y)| (x - y).abs() < 1e-6)
    };
    for _ in 0..3 {
        app.update();
    }
    assert!(same(&shape(&app, own), &blend([0.5, 0.25])), "{:?}", shape(&app, own));
    assert!(
        same(&shape(&app, shared), &blend([1.0, 0.0])),
        "{:?}",
        shape(&app, shared)
    );
    // New weights, as an animation writes them: the new shape is traced.
    *app.world_mut().get_mut::<MeshMorphWeights>(own).expect("weights") = MeshMorphWeights::Value {
        weights: vec![0.0, 1.0],
    };
    app.world_mut()
        .get_mut::<MorphWeights>(holder)
        .expect("weights")
        .weights_mut()
        .copy_from_slice(&[0.25, 0.5]);
    app.update();
    assert!(same(&shape(&app, own), &blend([0.0, 1.0])), "{:?}", shape(&app, own));
    assert!(
        same(&shape(&app, shared), &blend([0.25, 0.5])),
        "{:?}",
        shape(&app, shared)
    );
}
