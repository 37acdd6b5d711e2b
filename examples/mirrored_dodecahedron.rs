//! The mirrored right-angled dodecahedron, as in the paper's Fig. 7: every
//! face of a hyperbolic dodecahedron with 90° dihedral angles is a mirror,
//! and the reflections tile hyperbolic space by dodecahedra. Suzanne is
//! attached to the camera. `--no-edges` hides the domain's edges, as in
//! Fig. 10, so the structure is left for the eye to find.
//!
//! `cargo run --release --example mirrored_dodecahedron [-- --no-edges] [-- --screenshot FILE.png [--size WxH]]`

use bevy::prelude::*;
use bevy_manifold::drawables::paper::{paper_camera, spawn_paper_scene};
use bevy_manifold::prelude::*;
#[path = "support/showcase.rs"]
#[allow(dead_code, reason = "each example uses its own part of it")]
mod showcase;
use bevy_manifold::trace::PaperOptions;

fn main() -> AppExit {
    let mut app = showcase::app(
        "The mirrored dodecahedron (paper Fig. 7, Fig. 10 with --no-edges)",
        "every face of a right-angled hyperbolic dodecahedron a mirror",
    );
    app.add_systems(Startup, setup);
    showcase::run(app)
}

fn setup(mut commands: Commands) {
    let space = catalog::mirrored_dodecahedron();
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
    // Turned around, towards the nearer mirrors and their reflections.
    let (mut placement, projection) = paper_camera(&space);
    placement.isometry *= isometry::rotation(glam::DVec3::Y, std::f64::consts::PI);
    let eye = commands
        .spawn((ChildOf(root), camera, FlyCamera::default(), placement, projection))
        .id();
    let scene = PaperOptions {
        edges: !showcase::flag("--no-edges"),
        ..default()
    };
    spawn_paper_scene(&mut commands, root, eye, &space, scene);
}
