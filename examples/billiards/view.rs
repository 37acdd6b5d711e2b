//! What a person sees and touches: the traced view from the player's
//! eyes, a HUD with the strokes, the balls left and the cue's power, a
//! crosshair that turns green when the cue ball is in reach on the line
//! of sight, and the keyboard and mouse (the fly camera's keys, and the
//! cue; see `main.rs` for the table).

use crate::hud::{CenterText, Crosshair, HudText, spawn_hud};
use crate::table::{Cue, Player, Table, TableEvent, set_up_table};
use bevy::camera::RenderTarget;
use bevy::prelude::*;
use bevy_manifold::camera::ManifoldCamera;
use bevy_manifold::prelude::*;
use glam::DVec3;

/// Seconds of holding the cue for a full stroke.
pub const FULL_CHARGE: f64 = 1.2;

/// The view's settings.
#[derive(Resource, Clone, Debug)]
pub struct ViewSettings {
    /// Face transports per ray.
    pub levels: u32,
    /// The offscreen image the camera draws into (screenshot mode).
    pub target: Option<Handle<Image>>,
}

/// Adds the view to a table app (one with `DefaultPlugins` or the
/// offscreen plugins).
pub struct ViewPlugin(pub ViewSettings);

impl Plugin for ViewPlugin {
    fn build(&self, app: &mut App) {
        app.insert_resource(self.0.clone())
            .init_resource::<Charge>()
            .add_systems(Startup, spawn_hud)
            .add_systems(Update, (attach_eyes, cue_input, rack_again, show_hud));
    }
}

/// How long the cue has been held (seconds), while it is.
#[derive(Resource, Default)]
struct Charge(Option<f64>);

/// Gives the player its eyes (the manifold camera) and the fly camera's
/// controls, and points the HUD at it.
#[expect(clippy::type_complexity, reason = "Bevy queries")]
fn attach_eyes(
    mut commands: Commands,
    settings: Res<ViewSettings>,
    table: Option<Res<Table>>,
    spaces: Query<&ManifoldSpace>,
    players: Query<Entity, (With<Player>, Without<ManifoldCamera>)>,
    hud: Query<Entity, Or<(With<HudText>, With<CenterText>, With<Crosshair>)>>,
) {
    let (Some(table), Ok(player)) = (table, players.single()) else {
        return;
    };
    let Ok(ms) = spaces.get(table.root) else { return };
    let r = ms.space().inradius();
    commands.entity(player).insert((
        ManifoldCamera {
            levels: settings.levels,
            max_distance: 40.0,
            ..default()
        },
        FlyCamera {
            speed: 0.5 * r,
            mouse_button: Some(MouseButton::Right),
            ..default()
        },
        Projection::Perspective(PerspectiveProjection {
            fov: 70f32.to_radians(),
            ..default()
        }),
    ));
    if let Some(target) = &settings.target {
        commands
            .entity(player)
            .insert(RenderTarget::Image(target.clone().into()));
    }
    for e in &hud {
        commands.entity(e).insert(UiTargetCamera(player));
    }
}

/// The cue: held (left mouse button, F, or a gamepad's south button with
/// the `gamepad` feature) it charges, released it asks
/// the table for a stroke of the power charged.
fn cue_input(
    keys: Res<ButtonInput<KeyCode>>,
    buttons: Res<ButtonInput<MouseButton>>,
    #[cfg(feature = "gamepad")] gamepads: Query<&Gamepad>,
    time: Res<Time>,
    mut charge: ResMut<Charge>,
    mut cue: ResMut<Cue>,
) {
    #[cfg(feature = "gamepad")]
    let pad = gamepads.iter().any(|p| p.pressed(GamepadButton::South));
    #[cfg(not(feature = "gamepad"))]
    let pad = false;
    let held = pad || buttons.pressed(MouseButton::Left) || keys.pressed(KeyCode::KeyF);
    match (held, charge.0) {
        (true, c) => charge.0 = Some(c.unwrap_or(0.0) + time.delta_secs_f64()),
        (false, Some(held_for)) => {
            cue.strike = Some((held_for / FULL_CHARGE).min(1.0));
            charge.0 = None;
        }
        (false, None) => {}
    }
}

/// R racks the balls again, in the same space.
fn rack_again(mut commands: Commands, keys: Res<ButtonInput<KeyCode>>) {
    if keys.just_pressed(KeyCode::KeyR) {
        commands.run_system_cached(set_up_table);
    }
}

/// Strokes, balls left, the cue's power, the last event; the crosshair
/// green when a stroke would strike the cue ball.
fn show_hud(
    table: Option<Res<Table>>,
    charge: Res<Charge>,
    cast: ManifoldRayCast,
    mut hud: Query<&mut Text, (With<HudText>, Without<CenterText>)>,
    mut center: Query<&mut Text, (With<CenterText>, Without<HudText>)>,
    mut crosshair: Query<&mut TextColor, With<Crosshair>>,
) {
    let Some(table) = table else { return };
    let (Ok(mut hud), Ok(mut center)) = (hud.single_mut(), center.single_mut()) else {
        return;
    };
    let power = charge.0.map_or(0.0, |c| (c / FULL_CHARGE).min(1.0));
    let bar: String = (0..20)
        .map(|i| if f64::from(i) < power * 20.0 { '|' } else { '.' })
        .collect();
    let last = table.log.last().map_or(String::new(), |(_, e)| match e {
        TableEvent::Sunk(n) => format!("ball {n} down"),
        TableEvent::Scratch => "scratch: the cue ball is back on its spot, one stroke more".into(),
        TableEvent::Collision {
            through_faces: true, ..
        } => "a hit through the faces".into(),
        _ => String::new(),
    });
    hud.0 = format!(
        "strokes {}   balls left {}   cue [{bar}]   {last}\n\
         WASD Space Shift fly | arrows or right button turn | hold click or F, release to strike | R rack again",
        table.strokes, table.left
    );
    center.0 = if table.left == 0 {
        format!("TABLE CLEARED in {} strokes\n\nR: rack again", table.strokes)
    } else {
        String::new()
    };
    let settings = RayCastSettings {
        max_distance: table.rules.reach,
        exclude: Some(table.player),
        ..default()
    };
    let aimed = cast
        .cast(table.player, DVec3::NEG_Z, &settings)
        .first()
        .is_some_and(|hit| hit.entity == table.cue_ball);
    for mut c in &mut crosshair {
        c.0 = if aimed {
            Color::srgb(0.3, 1.0, 0.4)
        } else {
            Color::srgba(1.0, 1.0, 1.0, 0.8)
        };
    }
}
