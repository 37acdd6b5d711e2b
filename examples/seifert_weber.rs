//! The Seifert-Weber dodecahedral space, as in the paper's Fig. 4: a
//! hyperbolic dodecahedron with 72° dihedral angles whose opposite faces
//! are glued with a 3/10 turn (the paper's "3π/10" is a misprint: the
//! geometry needs 3/10 of a full turn, and a test says so). One Suzanne,
//! attached to the camera, and the hands are seen in every copy of the
//! tessellation of hyperbolic space by rotated dodecahedra.
//!
//! `cargo run --release --example seifert_weber [-- --screenshot FILE.png [--size WxH]]`

use bevy::prelude::*;
use bevy_manifold::drawables::paper::{paper_camera, spawn_paper_scene};
use bevy_manifold::prelude::*;
#[path = "support/showcase.rs"]
#[allow(dead_code, reason = "each example uses its own part of it")]
mod showcase;
use bevy_manifold::trace::PaperOptions;

fn main() -> AppExit {
    let mut app = showcase::app(
        "The Seifert-Weber space (paper Fig. 4)",
        "a hyperbolic dodecahedron, opposite faces glued with a 3/10 turn",
    );
    app.add_systems(Startup, setup);
    showcase::run(app)
}

fn setup(mut commands: Commands) {
    let space = catalog::seifert_weber();
    let root = commands.spawn(ManifoldSpace::new(space.clone())).id();
    // Eight levels: beyond four the copies shrink below a pixel. Traced as
    // cones (ManifoldFootprint) they cover the part of each pixel they
    // would, so they fade to their average colour instead of sparkling
    // while the camera moves; once it stops, 16 jittered samples a pixel
    // refine the rest.
    let camera = (
        ManifoldCamera { levels: 8, ..default() },
        ManifoldFootprint,
        ManifoldAccumulation::default(),
    );
    let eye = commands
        .spawn((ChildOf(root), camera, FlyCamera::default(), paper_camera(&space)))
        .id();
    spawn_paper_scene(&mut commands, root, eye, &space, PaperOptions::default());
}
