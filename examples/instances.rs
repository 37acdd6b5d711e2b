//! A level of thousands of props: `--count N` of them (4,000 by default)
//! made of three Bevy meshes (a cube, an icosphere, a torus), spawned as a
//! Bevy game spawns props under the root that holds the space: a
//! `Transform` each (a place, a turn, a scale of its own on each axis)
//! and a `StandardMaterial` of its own colour. The instances share their
//! mesh's BVH, and the tracer walks them by instance trees, so the frame
//! at 10,000 costs about what the frame at 100 does (`bench instances`).
//! `--space NAME` picks another space (the default is the 3-torus).
//!
//! `cargo run --release --example instances [-- --count N] [-- --space NAME] [-- --screenshot FILE.png [--size WxH]]`

use bevy::prelude::*;
use bevy_manifold::prelude::*;
#[path = "support/showcase.rs"]
#[allow(dead_code, reason = "each example uses its own part of it")]
mod showcase;

fn main() -> AppExit {
    let mut app = showcase::app(
        "A level of thousands of props",
        "instances of three meshes, each with its own transform and material",
    );
    app.add_systems(Startup, setup);
    showcase::run(app)
}

/// A small generator of numbers in `[0, 1)` (xorshift), so the level is
/// the same on every run.
struct Dice(u64);

impl Dice {
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
}

fn setup(mut commands: Commands, mut meshes: ResMut<Assets<Mesh>>, mut materials: ResMut<Assets<StandardMaterial>>) {
    let space = match showcase::arg("--space") {
        Some(name) => catalog::resolve(&name).unwrap_or_else(|e| {
            eprintln!("--space {name}: {e}; using the 3-torus");
            catalog::torus(1.0)
        }),
        None => catalog::torus(1.0),
    };
    let count: usize = match showcase::arg("--count").map(|c| c.parse::<usize>()) {
        Some(Ok(n)) if (1..=100_000).contains(&n) => n,
        Some(_) => {
            eprintln!("--count: a number from 1 to 100000; using 4000");
            4000
        }
        None => 4000,
    };
    let r = space.inradius() as f32;
    let root = commands.spawn(ManifoldSpace::new(space.clone())).id();
    commands.spawn((
        ChildOf(root),
        ManifoldCamera::default(),
        // Fog by distance, so the copies of the level read near to far.
        ManifoldFog {
            density: f64::from(0.25 / r),
            color: Color::srgb(0.55, 0.6, 0.7),
        },
        FlyCamera::default(),
        Transform::from_xyz(0.0, 0.0, 0.6 * r).looking_at(Vec3::new(0.3 * r, 0.1 * r, 0.0), Vec3::Y),
    ));
    commands.spawn((
        ChildOf(root),
        ManifoldLight {
            intensity: 2.0,
            ..default()
        },
        Transform::from_xyz(0.0, 0.5 * r, 0.0),
    ));
    let shapes = [
        meshes.add(Cuboid::new(1.0, 1.0, 1.0)),
        meshes.add(Sphere::new(0.6).mesh().ico(2).expect("a small icosphere")),
        meshes.add(Torus::new(0.3, 0.6)),
    ];
    let mut dice = Dice(0x9e37_79b9_7f4a_7c15);
    for k in 0..count {
        // A point of the ball of 0.95 of the inradius, away from the eye.
        let at = loop {
            let p = Vec3::new(dice.next(), dice.next(), dice.next()) * 2.0 - 1.0;
            if p.length() < 1.0 && p.distance(Vec3::new(0.0, 0.0, 0.6)) > 0.15 {
                break p * 0.95 * r;
            }
        };
        let turn = Quat::from_euler(
            EulerRot::YXZ,
            dice.next() * std::f32::consts::TAU,
            dice.next() * std::f32::consts::TAU,
            dice.next() * std::f32::consts::TAU,
        );
        let size = 0.018 * r * (0.6 + 0.8 * dice.next());
        let stretch = Vec3::new(1.0, 0.5 + dice.next(), 0.5 + dice.next());
        let color = Color::hsl(360.0 * dice.next(), 0.7, 0.55);
        commands.spawn((
            ChildOf(root),
            Mesh3d(shapes[k % 3].clone()),
            MeshMaterial3d(materials.add(StandardMaterial {
                base_color: color,
                perceptual_roughness: 0.6,
                ..default()
            })),
            Transform::from_translation(at)
                .with_rotation(turn)
                .with_scale(stretch * size),
        ));
    }
}
