//! The mirrored cube, as in the paper's Fig. 6: every face of a cube is a
//! perfect mirror, so rays bounce around the cube and the view is the
//! reflection group's tiling of Euclidean space. Suzanne is attached to the
//! camera; the hands, seen in the mirrors, are mirror images (a left hand
//! appears as a right one after one reflection).
//!
//! `cargo run --release --example mirrored_cube [-- --screenshot FILE.png [--size WxH]]`

use bevy::prelude::*;
use bevy_manifold::drawables::paper::{paper_camera, spawn_paper_scene};
use bevy_manifold::prelude::*;
#[path = "support/showcase.rs"]
#[allow(dead_code, reason = "each example uses its own part of it")]
mod showcase;
use bevy_manifold::trace::PaperOptions;

fn main() -> AppExit {
    let mut app = showcase::app("The mirrored cube (paper Fig. 6)", "every face of a cube a mirror");
    app.add_systems(Startup, setup);
    showcase::run(app)
}

fn setup(mut commands: Commands) {
    let space = catalog::mirrored_cube(1.0);
    let root = commands.spawn(ManifoldSpace::new(space.clone())).id();
    let eye = commands
        .spawn((
            ChildOf(root),
            ManifoldCamera::default(),
            FlyCamera::default(),
            paper_camera(&space),
        ))
        .id();
    spawn_paper_scene(&mut commands, root, eye, &space, PaperOptions::default());
}
