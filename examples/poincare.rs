//! The Poincaré dodecahedral space, as in the paper's Fig. 5: a spherical
//! dodecahedron whose opposite faces are glued with a 1/10 turn (π/5); its
//! 120 copies tile the 3-sphere as the 120-cell. Suzanne is not attached to
//! the camera: she stands in front of it, her images first shrink with
//! distance and then grow again, and the large upside-down Suzanne in the
//! background is her image from the far side of the sphere.
//!
//! `cargo run --release --example poincare [-- --screenshot FILE.png [--size WxH]]`

use bevy::prelude::*;
use bevy_manifold::drawables::paper::{paper_camera, spawn_paper_scene};
use bevy_manifold::prelude::*;
#[path = "support/showcase.rs"]
#[allow(dead_code, reason = "each example uses its own part of it")]
mod showcase;
use bevy_manifold::trace::{PaperOptions, SuzanneMode};

fn main() -> AppExit {
    let mut app = showcase::app(
        "The Poincaré dodecahedral space (paper Fig. 5)",
        "a spherical dodecahedron, opposite faces glued with a 1/10 turn",
    );
    app.add_systems(Startup, setup);
    showcase::run(app)
}

fn setup(mut commands: Commands) {
    let space = catalog::poincare();
    let root = commands.spawn(ManifoldSpace::new(space.clone())).id();
    let eye = commands
        .spawn((
            ChildOf(root),
            ManifoldCamera::default(),
            FlyCamera::default(),
            paper_camera(&space),
        ))
        .id();
    let scene = PaperOptions {
        suzanne: SuzanneMode::Free,
        ..default()
    };
    spawn_paper_scene(&mut commands, root, eye, &space, scene);
}
