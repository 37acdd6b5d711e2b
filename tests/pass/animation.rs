//! A glTF character animated by Bevy's `AnimationPlayer`, traced in the
//! manifold in the pose Bevy itself skins it to, at each time, in every
//! copy.

use super::support::*;
use bevy::prelude::*;
use bevy_manifold::prelude::*;
use bevy_manifold_test_support::stalk;

/// The animated stalk (`bevy_manifold_test_support::stalk` writes it).
const STALK: &str = "models/stalk.gltf";

/// The skinned mesh entities below `ancestor`.
fn skinned_below(app: &mut App, ancestor: Entity) -> Vec<Entity> {
    use bevy::mesh::skinning::SkinnedMesh;
    let world = app.world_mut();
    let mut skinned = world.query_filtered::<Entity, With<SkinnedMesh>>();
    let all: Vec<Entity> = skinned.iter(world).collect();
    all.into_iter()
        .filter(|&e| {
            let mut at = e;
            while let Some(parent) = world.get::<ChildOf>(at) {
                at = parent.parent();
                if at == ancestor {
                    return true;
                }
            }
            false
        })
        .collect()
}

/// Where Bevy's own skinning puts each vertex of the stalk: the joint
/// matrices Bevy's render world extracted for `skinned` (the ones its
/// vertex shader blends), read back, blended by the file's weights.
fn bevy_skinned(app: &App, skinned: Entity) -> Vec<Vec3> {
    use bevy::pbr::SkinUniforms;
    use bevy::render::{RenderApp, sync_world::MainEntity};
    let uniforms = app.sub_app(RenderApp).world().resource::<SkinUniforms>();
    let at = uniforms
        .skin_index(MainEntity::from(skinned))
        .expect("Bevy extracted the visible copy's skin") as usize;
    let joints = &uniforms.current_staging_buffer[at..at + 2];
    stalk::rest()
        .iter()
        .map(|(p, _)| {
            let w = stalk::knee_weight(p.y);
            (joints[0] * (1.0 - w) + joints[1] * w).transform_point3(*p)
        })
        .collect()
}

/// The glTF stalk, its sway played by an `AnimationPlayer` in two copies
/// of its scene: one in the torus (traced) and one outside the manifold
/// seen by an ordinary Bevy camera (rasterised and skinned by Bevy). At
/// two times of the clip, every traced vertex is where Bevy's own skinning
/// puts it and where the geometry of the sway says; the pass draws what
/// the CPU tracer computes from that pose, in several copies of the cube.
pub fn an_animated_gltf_character_is_traced_as_bevy_skins_it() {
    use bevy::camera::visibility::RenderLayers;
    use glam::DVec3;
    let mut app = headless_app(true);
    let image = target(&mut app, W, H);
    let space = catalog::torus(1.0);
    let (root, _) = spawn_view(&mut app, &space, &image, false, false);
    let assets = app.world().resource::<AssetServer>().clone();
    let (graph, sway) = AnimationGraph::from_clip(assets.load(GltfAssetLabel::Animation(0).from_asset(STALK)));
    let graph = app.world_mut().resource_mut::<Assets<AnimationGraph>>().add(graph);
    let scene = || WorldAssetRoot(assets.load(GltfAssetLabel::Scene(0).from_asset(STALK)));
    // In the manifold, placed and scaled as a game places a character.
    let traced = app
        .world_mut()
        .spawn((
            ChildOf(root),
            scene(),
            Placement::at(&space, DVec3::new(0.0, -0.15, -0.25)),
            Transform::from_scale(Vec3::splat(0.3)),
        ))
        .id();
    // Outside it, at Bevy's origin, in view of an ordinary camera.
    let plain = app.world_mut().spawn((scene(), Transform::IDENTITY)).id();
    let plain_image = target(&mut app, 64, 64);
    app.world_mut().spawn((
        Camera3d::default(),
        Camera { order: 1, ..default() },
        RenderLayers::layer(1),
        bevy::camera::RenderTarget::Image(plain_image.into()),
        Transform::from_xyz(0.0, 0.5, 3.0).looking_at(Vec3::Y * 0.5, Vec3::Y),
    ));
    let players = |app: &mut App| {
        let world = app.world_mut();
        let mut q = world.query_filtered::<Entity, With<AnimationPlayer>>();
        q.iter(world).collect::<Vec<_>>()
    };
    let meshes_of = |app: &App| app.world().get::<ManifoldMeshes>(root).map_or(0, |m| m.meshes.len());
    for _ in 0..3000 {
        app.update();
        if meshes_of(&app) == 1 && players(&mut app).len() == 2 {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    assert_eq!(meshes_of(&app), 1, "the traced copy's mesh is gathered");
    let players = players(&mut app);
    assert_eq!(players.len(), 2, "each copy of the scene has its animation player");
    let (traced_mesh, plain_mesh) = (skinned_below(&mut app, traced), skinned_below(&mut app, plain));
    assert_eq!((traced_mesh.len(), plain_mesh.len()), (1, 1));
    // The plain copy on a layer of its own, so only its camera draws it.
    app.world_mut().entity_mut(plain_mesh[0]).insert(RenderLayers::layer(1));
    for &player in &players {
        app.world_mut()
            .entity_mut(player)
            .insert(AnimationGraphHandle(graph.clone()))
            .get_mut::<AnimationPlayer>()
            .unwrap()
            .play(sway)
            .pause();
    }
    let rest = stalk::rest();
    let posed = |app: &App| {
        app.world()
            .get::<ManifoldMeshes>(root)
            .and_then(|m| m.meshes.first().map(|m| m.data.clone()))
            .expect("the stalk is gathered")
    };
    for t in [1.5f32, 0.4] {
        for &player in &players {
            let mut player = app.world_mut().get_mut::<AnimationPlayer>(player).unwrap();
            player.animation_mut(sway).unwrap().seek_to(t);
        }
        for _ in 0..4 {
            app.update();
        }
        let bevy = bevy_skinned(&app, plain_mesh[0]);
        let data = posed(&app);
        assert_eq!(data.mesh.positions.len(), rest.len());
        let mut worst = (0.0f32, 0.0f32);
        for (v, (p, _)) in rest.iter().enumerate() {
            let got = Vec3::from(data.mesh.positions[v]);
            let want = stalk::posed(*p, t);
            worst.0 = worst.0.max((got - bevy[v]).length());
            worst.1 = worst.1.max((got - want).length());
            assert!(
                (got - bevy[v]).length() < 1e-5 && (got - want).length() < 1e-5,
                "vertex {v} at t = {t}: traced {got}, Bevy's skinning {}, by geometry {want}",
                bevy[v]
            );
        }
        eprintln!(
            "stalk at t = {t}: largest difference from Bevy's skinning {:.1e}, from geometry {:.1e}",
            worst.0, worst.1
        );
    }
    // The pass draws the posed stalk as the CPU tracer does, in every copy.
    assert_drawn_in_copies(&mut app, &space, root, &image, "an animated stalk in the torus");
}
