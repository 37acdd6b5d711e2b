//! A product space, H2xR or S2xR, in a Bevy app: a `Camera3d` with a
//! `ProductCamera` looks into the space (three balls and fog, traced by the
//! product tracer every frame) and a `FlyCamera` flies it along geodesics
//! through the faces. `--space NAME` picks the space: `genus2xs1` (the
//! default: a closed genus-2 surface times a circle), `twisted-genus2xs1`,
//! `s2xs1`, `twisted-s2xs1` or `mirrored-prism`.
//!
//! `cargo run --release --example product [-- --space NAME] [-- --screenshot FILE.png [--size WxH]]`

use bevy::prelude::*;
use bevy_manifold::prelude::*;
use bevy_manifold::product::ProductCamera;
use bevy_manifold::space::product::ProductSpace;
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
    commands.spawn((
        Camera3d::default(),
        ProductCamera::default_for(space),
        FlyCamera {
            speed: 1.0,
            ..default()
        },
    ));
}
