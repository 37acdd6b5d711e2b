//! A product space, H2xR or S2xR, in a Bevy app: a `Camera3d` with a
//! `ProductCamera` looks into the space, traced by the product tracer
//! every frame, and a `FlyCamera` flies it along geodesics through the
//! faces. The balls are entities under the space's root, one of them
//! moving through the faces. `--space NAME` picks the space: `genus2xs1`
//! (the default: a closed genus-2 surface times a circle),
//! `twisted-genus2xs1`, `s2xs1`, `twisted-s2xs1` or `mirrored-prism`.
//! `--cells` (or the C key) shades each copy of the prism in its own
//! colour, by its exact cell. `--lights` lights the balls by two point
//! lights (entities with a `ProductPointLight`), every image of each, with
//! shadows; the L key turns them off and on. `--edges` (or the X key)
//! draws the prism's edges as thin tubes. `--tour FILE` plays a product tour
//! (`assets/tours/s2xs1.product-tour.json`, round and round; `--at
//! SECONDS` holds it at that moment) instead of flying.
//!
//! `cargo run --release --example product [-- --space NAME] [-- --cells] [-- --lights] [-- --edges] [-- --tour FILE [--at SECONDS]] [-- --screenshot FILE.png [--size WxH]]`

use bevy::prelude::*;
use bevy_manifold::geometry::product::ProductTangent;
use bevy_manifold::prelude::*;
use bevy_manifold::product::{
    ProductBody, ProductCamera, ProductPointLight, ProductSpaceRoot, ProductTourPlayer, ProductVelocity,
};
use bevy_manifold::space::cells::CellTint;
use bevy_manifold::space::product::ProductSpace;
use bevy_manifold::tour::product::ProductTour;
use bevy_manifold::trace::product::{ProductEdges, ProductLight, ProductScene};
use glam::DVec3;
use std::sync::Arc;
#[path = "support/showcase.rs"]
#[allow(dead_code, reason = "each example uses its own part of it")]
mod showcase;

fn main() -> AppExit {
    let mut app = showcase::app("A product space", "H2xR or S2xR: geodesics bend up and down the circle");
    app.add_systems(Startup, setup)
        .add_systems(Update, (toggle_cells, toggle_lights, toggle_edges));
    showcase::run(app)
}

/// A light of the scene, lit or not (its `ProductPointLight` on or off).
#[derive(Component)]
struct Lamp(ProductLight);

/// L: the lights off or on.
fn toggle_lights(
    keys: Res<ButtonInput<KeyCode>>,
    mut commands: Commands,
    lamps: Query<(Entity, &Lamp, Has<ProductPointLight>)>,
) {
    if keys.just_pressed(KeyCode::KeyL) {
        for (entity, lamp, lit) in &lamps {
            if lit {
                commands.entity(entity).remove::<ProductPointLight>();
            } else {
                commands.entity(entity).insert(ProductPointLight(lamp.0));
            }
        }
    }
}

/// C: per-cell shading on or off.
fn toggle_cells(keys: Res<ButtonInput<KeyCode>>, mut cameras: Query<&mut ProductCamera>) {
    if keys.just_pressed(KeyCode::KeyC) {
        for mut camera in &mut cameras {
            camera.view.tint = match camera.view.tint {
                Some(_) => None,
                None => Some(CellTint::ByCell),
            };
        }
    }
}

/// X: the prism's edges drawn or not.
fn toggle_edges(keys: Res<ButtonInput<KeyCode>>, mut cameras: Query<&mut ProductCamera>) {
    if keys.just_pressed(KeyCode::KeyX) {
        for mut camera in &mut cameras {
            camera.edges = match camera.edges {
                Some(_) => None,
                None => Some(ProductEdges::default()),
            };
        }
    }
}

fn setup(mut commands: Commands) {
    if let Some(path) = showcase::arg("--tour") {
        match ProductTour::load(&path) {
            Ok(tour) => return play(&mut commands, tour),
            Err(e) => eprintln!("error: {e}; flying instead"),
        }
    }
    let name = showcase::arg("--space").unwrap_or_else(|| "genus2xs1".into());
    let space = ProductSpace::named(&name, 2.0, 3).unwrap_or_else(|| {
        eprintln!(
            "--space {name}: not one of {}; using genus2xs1",
            ProductSpace::NAMES.join(", ")
        );
        ProductSpace::genus_two_x_s1(2.0)
    });
    // The default scene's view, and its balls as entities.
    let mut camera = ProductCamera::default_for(space.clone());
    if showcase::flag("--cells") {
        camera.view.tint = Some(CellTint::ByCell);
    }
    if showcase::flag("--edges") {
        camera.edges = Some(ProductEdges::default());
    }
    let root = commands.spawn(ProductSpaceRoot(Arc::new(space.clone()))).id();
    if showcase::flag("--lights") {
        for light in ProductScene::lit_for(&space).lights {
            commands.spawn((ChildOf(root), Lamp(light), ProductPointLight(light)));
        }
    }
    for (k, ball) in camera.balls.iter().enumerate() {
        let body = commands.spawn((ChildOf(root), ProductBody::from(*ball))).id();
        // One ball drifts through the faces (held still for a screenshot).
        if k == 1 && showcase::arg("--screenshot").is_none() {
            let dir = ProductTangent::new(DVec3::Y, 0.5);
            commands
                .entity(body)
                .insert(ProductVelocity::along(space.geometry, ball.center, dir, 0.3));
        }
    }
    commands.spawn((
        ChildOf(root),
        Camera3d::default(),
        camera,
        FlyCamera {
            speed: 1.0,
            ..default()
        },
    ));
}

/// The tour's space, its balls as entities, and a camera that plays it.
fn play(commands: &mut Commands, tour: ProductTour) {
    let mut player = ProductTourPlayer::new(tour);
    player.looping = true;
    if let Some(at) = showcase::arg("--at").and_then(|a| a.parse::<f64>().ok()) {
        player.time = at.clamp(0.0, player.tour.duration());
        player.playing = false;
    }
    let camera = player.camera();
    let root = commands.spawn(ProductSpaceRoot(camera.space.clone())).id();
    // The tour's lights (a tour file's `lights`), as the root's children.
    for light in &camera.lights {
        commands.spawn((ChildOf(root), Lamp(*light), ProductPointLight(*light)));
    }
    for ball in &camera.balls {
        commands.spawn((ChildOf(root), ProductBody::from(*ball)));
    }
    commands.spawn((ChildOf(root), Camera3d::default(), camera, player));
}
