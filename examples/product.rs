//! A product space, H2xR or S2xR, in a Bevy app: a `Camera3d` with a
//! `ProductCamera` looks into the space, traced by the product tracer
//! every frame, and a `FlyCamera` flies it along geodesics through the
//! faces. The balls are entities under the space's root, one of them
//! moving through the faces. `--space NAME` picks the space: `genus2xs1`
//! (the default: a closed genus-2 surface times a circle),
//! `twisted-genus2xs1`, `s2xs1`, `twisted-s2xs1` or `mirrored-prism`.
//!
//! `cargo run --release --example product [-- --space NAME] [-- --screenshot FILE.png [--size WxH]]`

use bevy::prelude::*;
use bevy_manifold::geometry::product::ProductTangent;
use bevy_manifold::prelude::*;
use bevy_manifold::product::{ProductBody, ProductCamera, ProductSpaceRoot, ProductVelocity};
use bevy_manifold::space::product::ProductSpace;
use glam::DVec3;
use std::sync::Arc;
#[path = "support/showcase.rs"]
#[allow(dead_code, reason = "each example uses its own part of it")]
mod showcase;

fn main() -> AppExit {
    let mut app = showcase::app("A product space", "H2xR or S2xR: geodesics bend up and down the circle");
    app.add_systems(Startup, setup);
    showcase::run(app)
}

fn setup(mut commands: Commands) {
    let name = showcase::arg("--space").unwrap_or_else(|| "genus2xs1".into());
    let space = ProductSpace::named(&name, 2.0, 3).unwrap_or_else(|| {
        eprintln!(
            "--space {name}: not one of {}; using genus2xs1",
            ProductSpace::NAMES.join(", ")
        );
        ProductSpace::genus_two_x_s1(2.0)
    });
    // The default scene's view, and its balls as entities.
    let camera = ProductCamera::default_for(space.clone());
    let root = commands.spawn(ProductSpaceRoot(Arc::new(space.clone()))).id();
    for (k, ball) in camera.balls.iter().enumerate() {
        let body = commands
            .spawn((
                ChildOf(root),
                ProductBody {
                    center: ball.center,
                    radius: ball.radius,
                    id: ball.id,
                },
            ))
            .id();
        // One ball drifts through the faces (held still for a screenshot).
        if k == 1 && showcase::arg("--screenshot").is_none() {
            let g = space.geometry;
            let along = g.normalize_tangent(ball.center, ProductTangent::new(DVec3::Y, 0.5));
            commands.entity(body).insert(ProductVelocity(ProductTangent::new(
                along.surface * 0.3,
                along.height * 0.3,
            )));
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
