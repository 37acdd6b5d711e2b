//! The flat 3-torus, as in the paper's Fig. 3: the cube's opposite faces
//! are glued by translations, so the one Suzanne (attached to the camera),
//! the hands and the cube's edges are seen in every copy of the cube,
//! tiling Euclidean space. `--fog` adds fog, as in Fig. 1 (right);
//! `--mirror` a mirror ball in the middle of the cube, reflecting the
//! space with one reflection a ray, as in Fig. 11.
//!
//! `cargo run --release --example torus [-- --fog] [-- --mirror] [-- --screenshot FILE.png [--size WxH]]`

use bevy::prelude::*;
use bevy_manifold::drawables::paper::{paper_camera, spawn_paper_scene};
use bevy_manifold::prelude::*;
#[path = "support/showcase.rs"]
#[allow(dead_code, reason = "each example uses its own part of it")]
mod showcase;
use bevy_manifold::trace::PaperOptions;

fn main() -> AppExit {
    let mut app = showcase::app(
        "The 3-torus (paper Fig. 3, Fig. 1 with --fog)",
        "opposite faces of a cube glued by translations",
    );
    app.add_systems(Startup, setup);
    showcase::run(app)
}

fn setup(mut commands: Commands) {
    let space = catalog::torus(1.0);
    let root = commands.spawn(ManifoldSpace::new(space.clone())).id();
    let mut camera = commands.spawn((
        ChildOf(root),
        ManifoldCamera {
            // One reflection a ray: the mirror shows the space (Suzanne
            // and the hands are too rough to mirror anything).
            reflections: u32::from(showcase::flag("--mirror")),
            ..default()
        },
        FlyCamera::default(),
        paper_camera(&space),
    ));
    if showcase::flag("--fog") {
        camera.insert(ManifoldFog {
            density: 0.35,
            ..default()
        });
    }
    let eye = camera.id();
    let options = PaperOptions {
        mirror: showcase::flag("--mirror"),
        ..default()
    };
    spawn_paper_scene(&mut commands, root, eye, &space, options);
}
