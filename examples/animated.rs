//! Animated characters: `--count N` (12 by default) copies of a glTF
//! stalk skinned to two bones (`assets/models/stalk.gltf`), each swaying
//! by its own Bevy `AnimationPlayer` at its own phase. They are spawned
//! as a Bevy game spawns a character: the glTF's scene under a
//! `WorldAssetRoot` with a `Transform`, a child of the root that holds the
//! space, and its animation played once the scene is in. The plugin
//! poses each skinned mesh from its joints every frame, so every copy of
//! every stalk around the space moves. `--space NAME` picks another space
//! (the default is Seifert-Weber's).
//!
//! `cargo run --release --example animated [-- --count N] [-- --space NAME] [-- --screenshot FILE.png [--size WxH]]`

use bevy::prelude::*;
use bevy::world_serialization::WorldInstanceReady;
use bevy_manifold::prelude::*;
#[path = "support/showcase.rs"]
#[allow(dead_code, reason = "each example uses its own part of it")]
mod showcase;

/// The animated glTF character.
const STALK: &str = "models/stalk.gltf";

fn main() -> AppExit {
    let mut app = showcase::app(
        "Animated characters",
        "glTF stalks skinned to two bones, each swaying by its AnimationPlayer",
    );
    app.add_systems(Startup, setup);
    showcase::run(app)
}

/// The clip to play and where in it a stalk starts.
#[derive(Component)]
struct Sway {
    graph: Handle<AnimationGraph>,
    clip: AnimationNodeIndex,
    phase: f32,
}

fn setup(mut commands: Commands, assets: Res<AssetServer>, mut graphs: ResMut<Assets<AnimationGraph>>) {
    let space = match showcase::arg("--space") {
        Some(name) => catalog::resolve(&name).unwrap_or_else(|e| {
            eprintln!("--space {name}: {e}; using Seifert-Weber's");
            catalog::seifert_weber()
        }),
        None => catalog::seifert_weber(),
    };
    let count: usize = match showcase::arg("--count").map(|c| c.parse::<usize>()) {
        Some(Ok(n)) if (1..=1000).contains(&n) => n,
        Some(_) => {
            eprintln!("--count: a number from 1 to 1000; using 12");
            12
        }
        None => 12,
    };
    let r = space.inradius() as f32;
    let root = commands.spawn(ManifoldSpace::new(space)).id();
    commands.spawn((
        ChildOf(root),
        ManifoldCamera::default(),
        ManifoldFog {
            density: f64::from(0.1 / r),
            color: Color::srgb(0.6, 0.65, 0.75),
        },
        FlyCamera::default(),
        Transform::from_xyz(0.0, 0.05 * r, 0.3 * r).looking_at(Vec3::new(0.0, -0.25 * r, -0.4 * r), Vec3::Y),
    ));
    commands.spawn((
        ChildOf(root),
        ManifoldLight {
            intensity: 2.0,
            ..default()
        },
        Transform::from_xyz(0.0, 0.5 * r, 0.3 * r),
    ));
    let (graph, clip) = AnimationGraph::from_clip(assets.load(GltfAssetLabel::Animation(0).from_asset(STALK)));
    let graph = graphs.add(graph);
    // A ring of stalks on the floor of the domain, each turned to face
    // the ring's centre and started at its own point of the sway.
    for k in 0..count {
        let a = std::f32::consts::TAU * k as f32 / count as f32;
        commands
            .spawn((
                ChildOf(root),
                WorldAssetRoot(assets.load(GltfAssetLabel::Scene(0).from_asset(STALK))),
                Transform::from_xyz(0.45 * r * a.cos(), -0.4 * r, 0.45 * r * a.sin())
                    .with_rotation(Quat::from_rotation_y(-a))
                    .with_scale(Vec3::splat(0.3 * r)),
                Sway {
                    graph: graph.clone(),
                    clip,
                    phase: 2.0 * k as f32 / count as f32,
                },
            ))
            .observe(play_when_ready);
    }
}

/// Once a stalk's scene is in: its animation player plays the sway from
/// the stalk's phase, round and round (held at that phase for a
/// screenshot, so the picture is the same on every run).
fn play_when_ready(
    ready: On<WorldInstanceReady>,
    mut commands: Commands,
    children: Query<&Children>,
    sways: Query<&Sway>,
    mut players: Query<&mut AnimationPlayer>,
    screenshot: Option<Res<showcase::ScreenshotMode>>,
) {
    let Ok(sway) = sways.get(ready.entity) else {
        return;
    };
    for child in children.iter_descendants(ready.entity) {
        if let Ok(mut player) = players.get_mut(child) {
            let playing = player.play(sway.clip).repeat().seek_to(sway.phase);
            if screenshot.is_some() {
                playing.pause();
            }
            commands.entity(child).insert(AnimationGraphHandle(sway.graph.clone()));
        }
    }
}
