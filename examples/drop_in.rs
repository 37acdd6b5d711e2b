//! An ordinary Bevy 3D app (its own plugins, meshes, lights, UI text,
//! gizmos, keyboard input) into which a manifold is dropped in a handful of
//! lines marked "manifold": the main camera and a few balls live in the
//! 3-torus; fly with WASD / Space / Shift, turn with the arrows or the
//! mouse, and wrap through the faces. The main view is ray-traced (every
//! copy of the domain); a plain Bevy camera in the corner shows a
//! rasterised map of the one fundamental cube, untouched by the plugin.
//!
//! `cargo run --release --example drop_in`
//! (`-- --frames N` quits after N frames; `-- --screenshot FILE.png` saves
//! a frame and quits)

use bevy::camera::Viewport;
use bevy::camera::visibility::RenderLayers;
use bevy::prelude::*;
use bevy_manifold::prelude::*;
use glam::DVec3;

fn main() {
    let arg = |name: &str| std::env::args().skip_while(|a| a != name).nth(1);
    let frames: Option<u32> = arg("--frames").and_then(|n| n.parse().ok());
    let screenshot = arg("--screenshot");
    App::new()
        .add_plugins(DefaultPlugins)
        // manifold: the plugin and the optional fly camera
        .add_plugins((ManifoldPlugins::default(), FlyCameraPlugin))
        .insert_resource(QuitAfter { frames, screenshot })
        .add_systems(Startup, setup)
        .add_systems(Update, (show_cell, draw_domain, quit_after, toggle_help))
        .run();
}

#[derive(Resource)]
struct QuitAfter {
    frames: Option<u32>,
    screenshot: Option<String>,
}

#[derive(Component)]
struct CellText;

/// The map's render layer: what only the plain corner camera sees.
const MAP: usize = 1;

fn setup(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
    mut gizmos: ResMut<GizmoConfigStore>,
) {
    // manifold: a space at the root, with its edges drawn; its
    // descendants live in it
    let space = catalog::torus(1.0);
    let root = commands
        .spawn((
            ManifoldSpace::new(space.clone()),
            DomainEdges { radius: 0.012 },
            Transform::default(),
            Visibility::default(),
        ))
        .id();
    // manifold: the main camera looks into the torus
    let eye = commands
        .spawn((
            ChildOf(root),
            ManifoldCamera::default(),
            FlyCamera::default(),
            Placement::at(&space, DVec3::new(0.1, 0.05, 0.35)),
        ))
        .id();
    commands.spawn((
        ChildOf(root),
        ManifoldLight {
            intensity: 0.6,
            ..default()
        },
        Placement::at(&space, DVec3::new(0.2, 0.4, 0.3)),
    ));
    let ball = meshes.add(Sphere::new(0.08).mesh().uv(32, 16));
    for (i, p) in [DVec3::ZERO, DVec3::new(0.3, 0.2, -0.25), DVec3::new(-0.3, -0.2, 0.1)]
        .into_iter()
        .enumerate()
    {
        let color = Color::hsl(40.0 + 120.0 * i as f32, 0.8, 0.55);
        commands.spawn((
            ChildOf(root),
            // manifold: traced in the main view, hit by ray casts
            TracedBall::new(0.08, color),
            ManifoldCollider::Ball { radius: 0.08 },
            Placement::at(&space, p),
            // plain Bevy: the same ball as a mesh on the map (Rasterized:
            // a Bevy mesh, not one for the tracer)
            Rasterized,
            Mesh3d(ball.clone()),
            MeshMaterial3d(materials.add(color)),
            RenderLayers::layer(MAP),
        ));
    }

    // The rest is plain Bevy: the map camera in the top-right corner, its
    // light, the gizmos it shows, and UI text over the main view.
    commands.spawn((
        Camera3d::default(),
        Camera {
            order: 1,
            viewport: Some(Viewport {
                physical_position: UVec2::new(16, 16),
                physical_size: UVec2::new(256, 192),
                ..default()
            }),
            clear_color: ClearColorConfig::Custom(Color::srgb(0.08, 0.09, 0.12)),
            ..default()
        },
        Transform::from_xyz(1.3, 1.0, 1.6).looking_at(Vec3::ZERO, Vec3::Y),
        RenderLayers::layer(MAP),
    ));
    commands.spawn((
        PointLight {
            intensity: 40_000.0,
            range: 4.0,
            ..default()
        },
        Transform::from_xyz(0.2, 0.4, 0.3),
        RenderLayers::layer(MAP),
    ));
    gizmos.config_mut::<DefaultGizmoConfigGroup>().0.render_layers = RenderLayers::layer(MAP);
    commands.spawn((
        Text::new(""),
        CellText,
        UiTargetCamera(eye),
        Node {
            position_type: PositionType::Absolute,
            bottom: px(10.0),
            left: px(10.0),
            ..default()
        },
    ));
}

/// Shows the camera's cell and the faces it crossed (from `FaceCrossed`).
fn show_cell(
    mut crossed: MessageReader<FaceCrossed>,
    camera: Query<(&DomainCell, &Placement), With<FlyCamera>>,
    mut text: Query<&mut Text, With<CellText>>,
    mut last: Local<Option<usize>>,
) {
    if let Some(c) = crossed.read().last() {
        *last = Some(c.face);
    }
    let (Ok((cell, placement)), Ok(mut text)) = (camera.single(), text.single_mut()) else {
        return;
    };
    let lattice = cell.id.lattice().unwrap_or_default();
    let p = placement.position();
    text.0 = format!(
        "3-torus, cell ({}, {}, {}), last face crossed: {}\nposition ({:+.2}, {:+.2}, {:+.2})\nWASD/Space/Shift fly, arrows or mouse turn, Q/E roll, H help",
        lattice.x,
        lattice.y,
        lattice.z,
        last.map_or("none".to_string(), |f| f.to_string()),
        p.x,
        p.y,
        p.z
    );
}

/// The map: the fundamental domain's edges in the chart, and where the
/// manifold camera is and looks.
fn draw_domain(spaces: Query<&ManifoldSpace>, eye: Query<&Transform, With<ManifoldCamera>>, mut gizmos: Gizmos) {
    for t in &eye {
        gizmos.sphere(Isometry3d::from_translation(t.translation), 0.03, Color::WHITE);
        gizmos.arrow(t.translation, t.translation + t.forward() * 0.2, Color::WHITE);
    }
    for ms in &spaces {
        let s = ms.space();
        for e in s.edges() {
            let [a, b] = e.vertices.map(|v| {
                let p = s.vertices()[v].point;
                (p.truncate() / p.w).as_vec3()
            });
            gizmos.line(a, b, Color::srgb(0.4, 0.8, 1.0));
        }
    }
}

fn toggle_help(keys: Res<ButtonInput<KeyCode>>, mut text: Query<&mut Visibility, With<CellText>>) {
    if keys.just_pressed(KeyCode::KeyH) {
        for mut v in &mut text {
            v.toggle_visible_hidden();
        }
    }
}

/// Quits after `--frames N`, or takes the `--screenshot` once the scene has
/// settled and quits when it is written.
fn quit_after(mut commands: Commands, quit: Res<QuitAfter>, mut frames: Local<u32>, mut exit: MessageWriter<AppExit>) {
    use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured, save_to_disk};
    *frames += 1;
    if let Some(path) = &quit.screenshot
        && *frames == 30
    {
        commands
            .spawn(Screenshot::primary_window())
            .observe(save_to_disk(path.clone()))
            .observe(|_: On<ScreenshotCaptured>, mut exit: MessageWriter<AppExit>| {
                exit.write(AppExit::Success);
            });
    }
    if quit.frames.is_some_and(|n| *frames >= n) {
        exit.write(AppExit::Success);
    }
}
