//! An ordinary Bevy scene put in a manifold as it is: a ground disc, a
//! cube, a point light and a camera, each spawned with a `Transform` only
//! (as Bevy's own `3d_scene` example spawns them), under a root that holds
//! a space. Each lands where its transform says (its translation followed
//! along the geodesic from the origin, its rotation as its frame) and is
//! wrapped into the domain: the camera, nine units out, sees the scene's
//! copies around it. `--space NAME` picks another space (a catalog or
//! library name, or a space file); the default is a 3-torus of edge 12,
//! large enough to hold the scene (in a smaller domain the scene overlaps
//! its own copies).
//!
//! `cargo run --release --example bevy_scene [-- --space NAME] [-- --screenshot FILE.png [--size WxH]]`

use bevy::prelude::*;
use bevy_manifold::prelude::*;
#[path = "support/showcase.rs"]
#[allow(dead_code, reason = "each example uses its own part of it")]
mod showcase;

fn main() -> AppExit {
    let mut app = showcase::app(
        "A Bevy scene in a manifold",
        "a disc, a cube, a light and a camera placed by their Transforms alone",
    );
    app.add_systems(Startup, setup);
    showcase::run(app)
}

fn setup(mut commands: Commands, mut meshes: ResMut<Assets<Mesh>>, mut materials: ResMut<Assets<StandardMaterial>>) {
    let space = match showcase::arg("--space") {
        Some(name) => catalog::resolve(&name).unwrap_or_else(|e| {
            eprintln!("--space {name}: {e}; using the 3-torus of edge 12");
            catalog::torus(12.0)
        }),
        None => catalog::torus(12.0),
    };
    // The only line a manifold needs: the root that holds the space.
    let root = commands.spawn(ManifoldSpace::new(space)).id();
    // From here on, a plain Bevy scene (its entities children of the root).
    commands.spawn((
        ChildOf(root),
        Mesh3d(meshes.add(Circle::new(4.0))),
        MeshMaterial3d(materials.add(Color::srgb(0.9, 0.9, 0.95))),
        Transform::from_rotation(Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2)),
    ));
    commands.spawn((
        ChildOf(root),
        Mesh3d(meshes.add(Cuboid::new(1.0, 1.0, 1.0))),
        MeshMaterial3d(materials.add(Color::srgb(0.49, 0.56, 0.35))),
        Transform::from_xyz(0.0, 0.5, 0.0),
    ));
    commands.spawn((
        ChildOf(root),
        PointLight {
            intensity: 600_000.0,
            ..default()
        },
        Transform::from_xyz(4.0, 8.0, 4.0),
    ));
    commands.spawn((
        ChildOf(root),
        ManifoldCamera::default(),
        FlyCamera::default(),
        Transform::from_xyz(-2.5, 4.5, 9.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
}
