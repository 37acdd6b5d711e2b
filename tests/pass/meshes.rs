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

/// A bar of three rings of four vertices (y = 0, 0.5, 1; x and z =
/// +-0.05), skinned to two joints: the bottom ring to the root joint, the
/// top ring to the second joint (at y = 0.5), the middle ring half to
/// each. Its side faces, as triangles.
fn skinned_bar() -> Mesh {
    use bevy::asset::RenderAssetUsages;
    use bevy::mesh::{Indices, PrimitiveTopology, VertexAttributeValues};
    let corners = [[-0.05, -0.05], [0.05, -0.05], [0.05, 0.05], [-0.05, 0.05]];
    let mut positions = Vec::new();
    let mut joints = Vec::new();
    let mut weights = Vec::new();
    for (ring, w) in [(0.0, [1.0, 0.0]), (0.5, [0.5, 0.5]), (1.0, [0.0, 1.0])] {
        for [x, z] in corners {
            positions.push([x, ring, z]);
            joints.push([0u16, 1, 0, 0]);
            weights.push([w[0], w[1], 0.0f32, 0.0]);
        }
    }
    let mut indices = Vec::new();
    for ring in 0..2u32 {
        for side in 0..4u32 {
            let (a, b) = (ring * 4 + side, ring * 4 + (side + 1) % 4);
            indices.extend([a, b, b + 4, a, b + 4, a + 4]);
        }
    }
    let mut mesh = Mesh::new(PrimitiveTopology::TriangleList, RenderAssetUsages::all());
    mesh.insert_attribute(Mesh::ATTRIBUTE_POSITION, positions);
    mesh.insert_attribute(Mesh::ATTRIBUTE_JOINT_INDEX, VertexAttributeValues::Uint16x4(joints));
    mesh.insert_attribute(Mesh::ATTRIBUTE_JOINT_WEIGHT, weights);
    mesh.insert_indices(Indices::U32(indices));
    mesh
}

/// Where the skinned bar's vertex `(x, y, z)` goes when the second joint
/// (at y = 0.5) is turned by `angle` about z, by the geometry of the bend
/// rather than by matrices: the top ring turns about the point (0, 0.5),
/// the middle ring is the mean of staying and turning, the bottom stays.
fn bent(p: [f32; 3], angle: f32) -> Vec3 {
    let (s, c) = angle.sin_cos();
    let [x, y, z] = p;
    let turned = Vec3::new(x * c - (y - 0.5) * s, 0.5 + x * s + (y - 0.5) * c, z);
    match y {
        y if y < 0.25 => Vec3::new(x, y, z),
        y if y < 0.75 => (Vec3::new(x, y, z) + turned) / 2.0,
        _ => turned,
    }
}

/// A skinned mesh whose joint is turned, as an `AnimationPlayer` turns
/// it, is traced in its pose: every vertex where the bend puts it, the
/// pose rebuilt when the joint turns again and kept (no new BVH, no new
/// upload) while it does not, and the pass draws what the CPU tracer
/// computes from it, in every copy of the torus.
pub fn a_skinned_mesh_is_traced_as_its_joints_pose_it() {
    use bevy::mesh::skinning::{SkinnedMesh, SkinnedMeshInverseBindposes};
    use glam::DVec3;
    let mut app = headless_app(true);
    let image = target(&mut app, W, H);
    let space = catalog::torus(1.0);
    let (root, _) = spawn_view(&mut app, &space, &image, false, false);
    let bar = skinned_bar();
    let rest: Vec<[f32; 3]> = match bar.attribute(Mesh::ATTRIBUTE_POSITION) {
        Some(bevy::mesh::VertexAttributeValues::Float32x3(p)) => p.clone(),
        _ => unreachable!(),
    };
    let mesh = app.world_mut().resource_mut::<Assets<Mesh>>().add(bar);
    // The joints' inverse bind poses: the root at the origin, the second
    // at y = 0.5.
    let bindposes = app
        .world_mut()
        .resource_mut::<Assets<SkinnedMeshInverseBindposes>>()
        .add(SkinnedMeshInverseBindposes::from(vec![
            Mat4::IDENTITY,
            Mat4::from_translation(Vec3::new(0.0, -0.5, 0.0)),
        ]));
    // A placed entity with the joints and the mesh below it, as a glTF
    // scene spawns a character; scaled to 0.3.
    let parent = app
        .world_mut()
        .spawn((
            ChildOf(root),
            Placement::at(&space, DVec3::new(0.0, -0.12, -0.25)),
            Transform::from_scale(Vec3::splat(0.3)),
            Visibility::default(),
        ))
        .id();
    let joint0 = app.world_mut().spawn((ChildOf(parent), Transform::IDENTITY)).id();
    let angle = 0.9f32;
    let joint1 = app
        .world_mut()
        .spawn((
            ChildOf(joint0),
            Transform::from_xyz(0.0, 0.5, 0.0).with_rotation(Quat::from_rotation_z(angle)),
        ))
        .id();
    app.world_mut().spawn((
        ChildOf(parent),
        Mesh3d(mesh),
        SkinnedMesh {
            inverse_bindposes: bindposes,
            joints: vec![joint0, joint1],
        },
        Transform::IDENTITY,
    ));
    let posed = |app: &App| {
        app.world()
            .get::<ManifoldMeshes>(root)
            .and_then(|m| m.meshes.first().map(|m| m.data.clone()))
    };
    for _ in 0..20 {
        app.update();
    }
    let data = posed(&app).expect("the skinned bar is gathered");
    let check = |data: &bevy_manifold::mesh::MeshData, angle: f32| {
        for (v, p) in rest.iter().enumerate() {
            let got = Vec3::from(data.mesh.positions[v]);
            let want = bent(*p, angle);
            assert!(
                (got - want).length() < 1e-5,
                "vertex {v} at {angle}: {got} against {want}"
            );
        }
    };
    check(&data, angle);
    // Nothing moved: the same pose, the same BVH.
    app.update();
    assert!(std::sync::Arc::ptr_eq(&data, &posed(&app).unwrap()));
    // The joint turns further: a new pose.
    let angle = 1.4f32;
    app.world_mut().get_mut::<Transform>(joint1).unwrap().rotation = Quat::from_rotation_z(angle);
    app.update();
    let data = posed(&app).unwrap();
    check(&data, angle);
    // The pass draws it as the CPU tracer does, in every copy.
    assert_drawn_in_copies(&mut app, &space, root, &image, "a skinned bar in the torus");
}
