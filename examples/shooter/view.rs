//! What a person sees and touches: the traced view from the player's
//! eyes (Suzanne's head, as in the paper), the start menu, the HUD with a
//! crosshair, a map of the fundamental domain in the corner (rasterised
//! by a plain Bevy camera, like `drop_in`'s), and the keyboard and mouse.
//!
//! | key | what |
//! |---|---|
//! | W / S, A / D, Space / Shift | fly forward / back, left / right, up / down |
//! | arrows, mouse | turn (yaw and pitch); Q / E roll |
//! | left mouse button, F, Ctrl | fire |
//! | P, Esc | pause |
//! | menu: Left / Right, Up / Down, Enter | space, difficulty, play |
//! | R | restart; M: back to the menu |

use crate::game::{Difficulty, Enemy, Game, GameConfig, Phase, Player, Shot, Target, colors, start_game};
use crate::hud::{CenterText, Crosshair, HudText, spawn_hud};
use crate::input::InputSource;
use bevy::camera::visibility::RenderLayers;
use bevy::camera::{RenderTarget, Viewport};
use bevy::input::mouse::AccumulatedMouseMotion;
use bevy::prelude::*;
use bevy_manifold::drawables::paper::spawn_paper_scene;
use bevy_manifold::motion::chart_position;
use bevy_manifold::prelude::*;
use bevy_manifold::trace::{PaperOptions, SuzanneMode};
use glam::DVec3;

/// The map's render layer: what only the corner camera sees.
const MAP: usize = 1;

/// The view's settings.
#[derive(Resource, Clone, Debug)]
pub struct ViewSettings {
    /// Face transports per ray.
    pub levels: u32,
    /// The offscreen image the cameras draw into (screenshot mode).
    pub target: Option<Handle<Image>>,
    /// Start in the menu (else straight into the game).
    pub menu: bool,
}

/// Adds the view to a game app (one with `DefaultPlugins` or the
/// offscreen plugins).
pub struct ViewPlugin(pub ViewSettings);

impl Plugin for ViewPlugin {
    fn build(&self, app: &mut App) {
        app.insert_resource(self.0.clone())
            .add_systems(Startup, spawn_hud_and_map)
            .add_systems(
                Update,
                (
                    enter_menu,
                    attach_eyes,
                    read_devices,
                    menu_keys,
                    game_keys,
                    show_hud,
                    draw_map,
                ),
            );
    }
}

/// Where the map camera looks from: the domain fits its view.
#[derive(Component)]
struct MapCamera;

/// Puts a freshly started game in the menu when the settings ask for it.
fn enter_menu(settings: Res<ViewSettings>, game: Option<ResMut<Game>>, mut done: Local<bool>) {
    if let Some(mut game) = game
        && !*done
    {
        *done = true;
        if settings.menu {
            game.phase = Phase::Menu;
        }
    }
}

/// Gives the player its eyes (the manifold camera) and its head (Suzanne,
/// seen in the other copies), and the map its camera.
#[expect(clippy::type_complexity, reason = "Bevy queries")]
fn attach_eyes(
    mut commands: Commands,
    settings: Res<ViewSettings>,
    game: Option<Res<Game>>,
    spaces: Query<&ManifoldSpace>,
    players: Query<Entity, (With<Player>, Without<ManifoldCamera>)>,
    hud: Query<Entity, Or<(With<HudText>, With<CenterText>, With<Crosshair>)>>,
    maps: Query<Entity, With<MapCamera>>,
) {
    let (Some(game), Ok(player)) = (game, players.single()) else {
        return;
    };
    let Ok(ms) = spaces.get(game.root) else {
        return;
    };
    let space = ms.space().clone();
    commands.entity(player).insert((
        ManifoldCamera {
            levels: settings.levels,
            max_distance: 40.0,
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
    spawn_paper_scene(
        &mut commands,
        game.root,
        player,
        &space,
        PaperOptions {
            edges: true,
            suzanne: SuzanneMode::Attached,
            hands: false,
            vehicle: false,
            mirror: false,
        },
    );
    for e in &hud {
        commands.entity(e).insert(UiTargetCamera(player));
    }
    for e in &maps {
        commands.entity(e).despawn();
    }
    // The map: a plain camera in the top-right corner looking at the
    // domain drawn by gizmos.
    let mut map = commands.spawn((
        MapCamera,
        Camera3d::default(),
        Camera {
            order: 1,
            viewport: Some(Viewport {
                physical_position: UVec2::new(8, 8),
                physical_size: UVec2::new(200, 150),
                ..default()
            }),
            clear_color: ClearColorConfig::Custom(Color::srgb(0.06, 0.07, 0.1)),
            ..default()
        },
        Transform::from_xyz(1.6, 1.2, 2.0).looking_at(Vec3::ZERO, Vec3::Y),
        RenderLayers::layer(MAP),
    ));
    if let Some(target) = &settings.target {
        map.insert(RenderTarget::Image(target.clone().into()));
    }
}

/// The HUD, and the gizmos (the map's lines) on the map's layer only.
fn spawn_hud_and_map(commands: Commands, mut gizmos: ResMut<GizmoConfigStore>) {
    gizmos.config_mut::<DefaultGizmoConfigGroup>().0.render_layers = RenderLayers::layer(MAP);
    spawn_hud(commands);
}

/// The keyboard and mouse (and with the `gamepad` feature every gamepad:
/// sticks, triggers and bumpers fly and turn as the fly camera's, the
/// south or west button fires), as the game's live input.
pub(crate) fn read_devices(
    keys: Res<ButtonInput<KeyCode>>,
    buttons: Res<ButtonInput<MouseButton>>,
    mouse: Res<AccumulatedMouseMotion>,
    time: Res<Time>,
    game: Option<Res<Game>>,
    #[cfg(feature = "gamepad")] gamepads: Query<&Gamepad>,
    mut source: ResMut<InputSource>,
) {
    let axis = |pos: KeyCode, neg: KeyCode| f64::from(i8::from(keys.pressed(pos)) - i8::from(keys.pressed(neg)));
    let thrust = DVec3::new(
        axis(KeyCode::KeyD, KeyCode::KeyA),
        axis(KeyCode::Space, KeyCode::ShiftLeft),
        axis(KeyCode::KeyS, KeyCode::KeyW),
    );
    let mut turn = DVec3::new(
        axis(KeyCode::ArrowUp, KeyCode::ArrowDown),
        axis(KeyCode::ArrowLeft, KeyCode::ArrowRight),
        axis(KeyCode::KeyQ, KeyCode::KeyE),
    );
    let dt = time.delta_secs_f64();
    if let Some(game) = &game
        && dt > 0.0
    {
        // The mouse's motion this frame as a turn rate, in units of the
        // full stick.
        let per = 0.003 / (dt * game.rules.turn_rate);
        turn += DVec3::new(-f64::from(mouse.delta.y), -f64::from(mouse.delta.x), 0.0) * per;
    }
    #[cfg(feature = "gamepad")]
    let (pad_thrust, pad_turn, pad_fire) = gamepads
        .iter()
        .fold((DVec3::ZERO, DVec3::ZERO, false), |(l, a, f), pad| {
            let (linear, angular) = bevy_manifold::camera::gamepad_motion(pad);
            let fire = pad.pressed(GamepadButton::South) || pad.pressed(GamepadButton::West);
            (l + linear, a + angular, f || fire)
        });
    #[cfg(not(feature = "gamepad"))]
    let (pad_thrust, pad_turn, pad_fire) = (DVec3::ZERO, DVec3::ZERO, false);
    source.live.thrust = (thrust + pad_thrust).clamp(DVec3::splat(-1.0), DVec3::splat(1.0));
    source.live.turn = (turn + pad_turn).clamp(DVec3::splat(-1.0), DVec3::splat(1.0));
    source.live.fire = pad_fire
        || buttons.pressed(MouseButton::Left)
        || keys.pressed(KeyCode::KeyF)
        || keys.pressed(KeyCode::ControlLeft);
}

/// The menu: choose the space and the difficulty, then play.
fn menu_keys(
    mut commands: Commands,
    keys: Res<ButtonInput<KeyCode>>,
    mut config: ResMut<GameConfig>,
    game: Option<ResMut<Game>>,
) {
    let Some(mut game) = game else { return };
    if game.phase != Phase::Menu {
        return;
    }
    let names = catalog::NAMES;
    let at = names.iter().position(|n| *n == config.space).unwrap_or(0);
    let d = Difficulty::ALL
        .iter()
        .position(|d| *d == config.difficulty)
        .unwrap_or(1);
    let step = |k: usize, n: usize, fwd: bool| if fwd { (k + 1) % n } else { (k + n - 1) % n };
    if keys.just_pressed(KeyCode::ArrowRight) || keys.just_pressed(KeyCode::ArrowLeft) {
        config.space = names[step(at, names.len(), keys.just_pressed(KeyCode::ArrowRight))].into();
        commands.run_system_cached(start_game);
        commands.queue(|w: &mut World| w.resource_mut::<Game>().phase = Phase::Menu);
    }
    if keys.just_pressed(KeyCode::ArrowUp) || keys.just_pressed(KeyCode::ArrowDown) {
        config.difficulty = Difficulty::ALL[step(d, 3, keys.just_pressed(KeyCode::ArrowUp))];
        commands.run_system_cached(start_game);
        commands.queue(|w: &mut World| w.resource_mut::<Game>().phase = Phase::Menu);
    }
    if keys.just_pressed(KeyCode::Enter) {
        game.phase = Phase::Playing;
    }
}

/// Pause, restart (another game: the next seed), back to the menu.
fn game_keys(
    mut commands: Commands,
    keys: Res<ButtonInput<KeyCode>>,
    mut config: ResMut<GameConfig>,
    game: Option<ResMut<Game>>,
) {
    let Some(mut game) = game else { return };
    let again = matches!(game.phase, Phase::Paused | Phase::Over)
        && (keys.just_pressed(KeyCode::KeyR) || keys.just_pressed(KeyCode::KeyM));
    if again {
        config.seed = config.seed.wrapping_add(1);
    }
    match game.phase {
        Phase::Playing if keys.just_pressed(KeyCode::KeyP) || keys.just_pressed(KeyCode::Escape) => {
            game.phase = Phase::Paused;
        }
        Phase::Paused if keys.just_pressed(KeyCode::KeyP) || keys.just_pressed(KeyCode::Escape) => {
            game.phase = Phase::Playing;
        }
        Phase::Paused | Phase::Over if keys.just_pressed(KeyCode::KeyR) => {
            commands.run_system_cached(start_game);
        }
        Phase::Paused | Phase::Over if keys.just_pressed(KeyCode::KeyM) => {
            commands.run_system_cached(start_game);
            commands.queue(|w: &mut World| w.resource_mut::<Game>().phase = Phase::Menu);
        }
        _ => {}
    }
}

/// Score, level, health; the menu, pause and game-over screens.
fn show_hud(
    game: Option<Res<Game>>,
    config: Res<GameConfig>,
    mut hud: Query<&mut Text, (With<HudText>, Without<CenterText>)>,
    mut center: Query<&mut Text, (With<CenterText>, Without<HudText>)>,
    mut crosshair: Query<&mut Visibility, With<Crosshair>>,
) {
    let Some(game) = game else { return };
    let (Ok(mut hud), Ok(mut center)) = (hud.single_mut(), center.single_mut()) else {
        return;
    };
    hud.0 = format!(
        "{}   score {}   level {}   targets {}/{}   health {:.0}   {:.0}% of cells on",
        config.space,
        game.score,
        game.level,
        game.hits,
        Game::targets_for(game.level),
        game.health,
        Game::on_fraction(game.level) * 100.0
    );
    center.0 = match game.phase {
        Phase::Menu => format!(
            "SHOTS COME BACK AROUND\n\nspace  < {} >   (Left / Right)\ndifficulty  {}   (Up / Down)\n\nEnter: play\n\n\
             WASD Space Shift fly | mouse or arrows turn | Q E roll | click, F or Ctrl fire | P pause\n\
             hit the green targets in any copy where they are shown; mind your own shots",
            config.space,
            config.difficulty.name()
        ),
        Phase::Paused => "PAUSED\n\nP: play | R: restart | M: menu".into(),
        Phase::Over => format!(
            "GAME OVER\n\nscore {} at level {}\n\nR: again | M: menu",
            game.score, game.level
        ),
        Phase::Playing => String::new(),
    };
    for mut v in &mut crosshair {
        *v = if game.phase == Phase::Playing {
            Visibility::Inherited
        } else {
            Visibility::Hidden
        };
    }
}

/// The map: the fundamental domain's edges and, inside it, the player
/// (with its heading), the shots, the targets and the enemies.
#[expect(clippy::type_complexity, reason = "Bevy queries")]
fn draw_map(
    game: Option<Res<Game>>,
    spaces: Query<&ManifoldSpace>,
    things: Query<(
        &Placement,
        Has<Player>,
        Has<Shot>,
        Has<Target>,
        Has<Enemy>,
        Option<&Shot>,
    )>,
    mut gizmos: Gizmos,
) {
    let Some(game) = game else { return };
    let Ok(ms) = spaces.get(game.root) else { return };
    let s = ms.space();
    let chart = |p: glam::DVec4| (p.truncate() / p.w).as_vec3();
    let size = s
        .vertices()
        .iter()
        .map(|v| chart(v.point).length())
        .fold(0.0f32, f32::max)
        .max(1e-3);
    let k = 1.0 / size;
    for e in s.edges() {
        let [a, b] = e.vertices.map(|v| chart(s.vertices()[v].point) * k);
        gizmos.line(a, b, Color::srgb(0.4, 0.7, 1.0));
    }
    for (placement, player, shot, target, enemy, shot_info) in &things {
        let p = chart_position(&placement.isometry).as_vec3() * k;
        if player {
            let ahead = chart_position(
                &(placement.isometry
                    * bevy_manifold::geometry::isometry::translation(s.geometry(), DVec3::NEG_Z * 0.3 * s.inradius())),
            )
            .as_vec3()
                * k;
            gizmos.sphere(Isometry3d::from_translation(p), 0.06, Color::WHITE);
            gizmos.arrow(p, ahead, Color::WHITE);
        } else if shot {
            let c = if shot_info.is_some_and(|s| s.by_player) {
                colors::SHOT
            } else {
                colors::ENEMY_SHOT
            };
            gizmos.sphere(Isometry3d::from_translation(p), 0.025, c);
        } else if target {
            gizmos.sphere(Isometry3d::from_translation(p), 0.08, colors::TARGET);
        } else if enemy {
            gizmos.sphere(Isometry3d::from_translation(p), 0.07, colors::ENEMY);
        }
    }
}
