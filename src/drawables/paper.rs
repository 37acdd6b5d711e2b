//! The paper's scene as Bevy entities (feature `paper_scene`): the same layout as
//! [`Scene::paper`], which the CPU and headless GPU tracers draw, spawned
//! under a space root and its camera. Suzanne and the hands are the crate's
//! built-in models turned into `Mesh3d` assets once per app (no asset folder
//! needed), so respawning the scene (switching spaces) adds no assets.
//!
//! ```no_run
//! use bevy::prelude::*;
//! use bevy_manifold::drawables::paper::{paper_camera, spawn_paper_scene};
//! use bevy_manifold::prelude::*;
//! use bevy_manifold::trace::PaperOptions;
//!
//! fn setup(mut commands: Commands) {
//!     let space = catalog::seifert_weber();
//!     let root = commands.spawn(ManifoldSpace::new(space.clone())).id();
//!     let eye = commands.spawn((ChildOf(root), ManifoldCamera::default(), paper_camera(&space))).id();
//!     spawn_paper_scene(&mut commands, root, eye, &space, PaperOptions::default());
//! }
//!
//! App::new().add_plugins((DefaultPlugins, ManifoldPlugins::default())).add_systems(Startup, setup).run();
//! ```

use super::{CameraBody, DomainEdges, ManifoldLight, TracedBall, bevy_mesh};
use crate::geometry::isometry;
use crate::placement::Placement;
use crate::space::Space;
use crate::trace::{
    HAND_COLOR, PaperOptions, SUZANNE_COLOR, Scene, SuzanneMode, VEHICLE_COLOR, builtin, hand_offset, mirror_ball,
    suzanne_offset, vehicle_offset,
};
use bevy::asset::RenderAssetUsages;
use bevy::prelude::*;
use glam::{DMat3, DMat4, DVec4};

/// The built-in models as assets, made on first use.
#[derive(Resource, Clone)]
pub struct PaperAssets {
    /// Suzanne's mesh.
    pub suzanne: Handle<Mesh>,
    /// The left and right hands' meshes.
    pub hands: [Handle<Mesh>; 2],
    /// Suzanne's material.
    pub suzanne_material: Handle<StandardMaterial>,
    /// The hands' material.
    pub hand_material: Handle<StandardMaterial>,
    /// The vehicle's mesh.
    pub vehicle: Handle<Mesh>,
    /// The vehicle's material.
    pub vehicle_material: Handle<StandardMaterial>,
}

impl PaperAssets {
    /// The app's [`PaperAssets`], added to `world` the first time.
    pub fn get_or_add(world: &mut World) -> PaperAssets {
        if let Some(a) = world.get_resource::<PaperAssets>() {
            return a.clone();
        }
        let mesh = |m: &crate::mesh::MeshData| {
            // The tracer reads the mesh in the main world; nothing
            // rasterises it, so it is not uploaded.
            let mut mesh = bevy_mesh(&m.mesh);
            mesh.asset_usage = RenderAssetUsages::MAIN_WORLD;
            mesh
        };
        let mut meshes = world.resource_mut::<Assets<Mesh>>();
        let suzanne = meshes.add(mesh(&builtin::suzanne()));
        let hands = [true, false].map(|left| meshes.add(mesh(&builtin::hand(left))));
        let vehicle = meshes.add(mesh(&crate::mesh::vehicle::airplane()));
        let mut materials = world.resource_mut::<Assets<StandardMaterial>>();
        let mut color = |c: [f32; 3]| materials.add(StandardMaterial::from_color(Color::linear_rgb(c[0], c[1], c[2])));
        let assets = PaperAssets {
            suzanne_material: color(SUZANNE_COLOR),
            hand_material: color(HAND_COLOR),
            vehicle_material: color(VEHICLE_COLOR),
            suzanne,
            hands,
            vehicle,
        };
        world.insert_resource(assets.clone());
        assets
    }
}

/// What [`spawn_paper_scene`] spawned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PaperEntities {
    /// Suzanne, unless hidden: a child of the camera when attached, of the
    /// root when free.
    pub suzanne: Option<Entity>,
    /// The left and right hands (children of the camera), when shown.
    pub hands: Option<[Entity; 2]>,
    /// The vehicle (a child of the camera: the camera rides it), when
    /// asked for.
    pub vehicle: Option<Entity>,
    /// The mirror ball (a child of the root, at the domain's centre), when
    /// asked for: seen with [`crate::camera::ManifoldCamera::reflections`].
    pub mirror: Option<Entity>,
    /// The light, where the camera starts.
    pub light: Entity,
}

/// Where the paper's camera starts in `space` (the placement
/// [`Scene::default_for`] gives its camera) and its 60° field of view: a
/// bundle for the camera entity.
#[must_use]
pub fn paper_camera(space: &Space) -> (Placement, Projection) {
    let camera = Scene::default_for(space).camera;
    (
        Placement::from_isometry(camera.isometry),
        Projection::Perspective(PerspectiveProjection {
            fov: (camera.fov_y_degrees as f32).to_radians(),
            ..default()
        }),
    )
}

/// A child transform in the parent's chart that carries the parent's
/// origin frame as the isometry `offset` does (exact for the position and
/// the frame at it), scaled by `scale`.
#[must_use]
pub fn chart_transform(space: &Space, offset: DMat4, scale: f64) -> Transform {
    let g = space.geometry();
    let p = offset * DVec4::W;
    let turn = isometry::inverse(g, isometry::translation_to(g, p)) * offset;
    let rotation = glam::DQuat::from_mat3(&DMat3::from_mat4(turn)).normalize();
    Transform {
        translation: (p.truncate() / p.w).as_vec3(),
        rotation: rotation.as_quat(),
        scale: Vec3::splat(scale as f32),
    }
}

/// Spawns the paper's scene (see [`crate::trace::PaperOptions`]) in the
/// space under `root`, around `camera` (a placed entity under `root`,
/// usually the [`crate::camera::ManifoldCamera`]), which starts at
/// `camera_at` (for the free Suzanne and the light): edges on the root,
/// Suzanne (attached: a [`CameraBody`] child of the camera), the hands and
/// the vehicle as children of the camera (they move with it), a light at
/// the eye.
pub fn spawn_paper_scene(
    commands: &mut Commands,
    root: Entity,
    camera: Entity,
    space: &Space,
    options: PaperOptions,
) -> PaperEntities {
    let scene = Scene::paper(space, &options);
    let camera_at = scene.camera.isometry;
    let light = &scene.lights[0];
    let light_entity = commands
        .spawn((
            ChildOf(root),
            ManifoldLight {
                intensity: light.intensity,
                ..default()
            },
            Placement::from_isometry(isometry::translation_to(space.geometry(), light.position)),
        ))
        .id();
    if let Some(radius) = scene.edge_radius {
        commands.entity(root).insert(DomainEdges { radius });
    } else {
        commands.entity(root).remove::<DomainEdges>();
    }
    let suzanne = suzanne_offset(space, options.suzanne).map(|(offset, scale)| {
        let e = commands.spawn(Name::new("Suzanne")).id();
        if options.suzanne == SuzanneMode::Attached {
            commands
                .entity(e)
                .insert((ChildOf(camera), CameraBody, chart_transform(space, offset, scale)));
        } else {
            commands.entity(e).insert((
                ChildOf(root),
                Placement::from_isometry(camera_at * offset),
                Transform::from_scale(Vec3::splat(scale as f32)),
            ));
        }
        e
    });
    let hands = options.hands.then(|| {
        [true, false].map(|left| {
            let (offset, scale) = hand_offset(space, left);
            commands
                .spawn((
                    Name::new(if left { "left hand" } else { "right hand" }),
                    ChildOf(camera),
                    chart_transform(space, offset, scale),
                ))
                .id()
        })
    });
    let vehicle = options.vehicle.then(|| {
        let (offset, scale) = vehicle_offset(space);
        commands
            .spawn((
                Name::new("vehicle"),
                ChildOf(camera),
                chart_transform(space, offset, scale),
            ))
            .id()
    });
    let mirror = options.mirror.then(|| {
        let ball = mirror_ball(space);
        let [r, g, b] = ball.color;
        let pbr = ball.pbr.unwrap_or_default();
        commands
            .spawn((
                Name::new("mirror ball"),
                ChildOf(root),
                TracedBall::new(ball.radius, Color::linear_rgb(r, g, b)).with_pbr(pbr.metallic, pbr.roughness),
                Placement::from_isometry(isometry::translation_to(space.geometry(), ball.center)),
            ))
            .id()
    });
    let (s, h, v) = (suzanne, hands, vehicle);
    commands.queue(move |world: &mut World| {
        let assets = PaperAssets::get_or_add(world);
        if let Some(e) = s
            && let Ok(mut e) = world.get_entity_mut(e)
        {
            e.insert((
                Mesh3d(assets.suzanne.clone()),
                MeshMaterial3d(assets.suzanne_material.clone()),
            ));
        }
        for (e, mesh) in h.into_iter().flatten().zip(assets.hands.iter()) {
            if let Ok(mut e) = world.get_entity_mut(e) {
                e.insert((Mesh3d(mesh.clone()), MeshMaterial3d(assets.hand_material.clone())));
            }
        }
        if let Some(e) = v
            && let Ok(mut e) = world.get_entity_mut(e)
        {
            e.insert((
                Mesh3d(assets.vehicle.clone()),
                MeshMaterial3d(assets.vehicle_material.clone()),
            ));
        }
    });
    PaperEntities {
        suzanne,
        hands,
        vehicle,
        mirror,
        light: light_entity,
    }
}
