//! The shooter in a headset (`--xr`; the plugin's `xr` feature, which
//! `cargo run --release --features xr --example shooter -- --xr` turns
//! on): the player is the room's body (`XrBody`), each eye is traced from
//! where it is, the paper's hands follow the controllers, and the
//! controllers are the game's input: the left stick flies (along the
//! player's own axes, as W A S D do), the right stick turns (yaw and
//! pitch), either trigger fires (the plugin's trigger action). The
//! controllers feed the same per-tick input as the keyboard, so a game
//! played in the headset records and replays like any other. The room is
//! recentred on the head (`XrRecentre`), so the player entity, its
//! collider and its shots are where the eyes are; each eye draws its own
//! crosshair where it sees the point one inradius ahead on the shots'
//! geodesic, so the two converge there.

use crate::game::{Game, Player};
use crate::input::InputSource;
use bevy::prelude::*;
use bevy::ui::UiTargetCamera;
use bevy_manifold::geometry::{Geometry, isometry};
use bevy_manifold::prelude::*;
use bevy_manifold::xr::{
    ManifoldXrPlugin, TRIGGER_PULLED, XrBody, XrControllers, XrEye, XrHandSide, XrHead, XrLocomotion, XrRecentre,
    XrState, save_eyes_at,
};
use glam::{DMat4, DVec3, DVec4};

/// Adds the headset to the game (after `bevy_mod_openxr::add_xr_plugins`).
pub struct ShooterXrPlugin {
    /// Metres of the room per unit of the space.
    pub world_scale: f64,
    /// `--xr-capture`: at this frame, read both eyes back and save them as
    /// `eye0.png` and `eye1.png` in this folder.
    pub capture: Option<(u32, std::path::PathBuf)>,
}

#[derive(Resource, Clone, Copy)]
struct WorldScale(f64);

impl Plugin for ShooterXrPlugin {
    fn build(&self, app: &mut App) {
        if let Some((at, dir)) = self.capture.clone() {
            app.add_systems(Last, save_eyes_at(at, dir));
        }
        app.insert_resource(WorldScale(self.world_scale))
            .add_plugins(ManifoldXrPlugin)
            .add_systems(Startup, say_if_unavailable)
            .add_systems(Update, (body_on_player, eye_crosshairs))
            // After the keyboard's `read_devices` (in `Update`); the game
            // reads the sum at its next tick.
            .add_systems(PostUpdate, controllers_as_input);
    }
}

fn say_if_unavailable(state: Option<Res<XrState>>) {
    if state.is_some_and(|s| *s == XrState::Unavailable) {
        println!("xr: no OpenXR runtime answered; playing on the desktop");
    }
}

/// The player carries the room; the game moves it, not the sticks.
fn body_on_player(
    mut commands: Commands,
    scale: Res<WorldScale>,
    game: Option<Res<Game>>,
    players: Query<Entity, (With<Player>, Without<XrBody>)>,
) {
    let Some(game) = game else { return };
    if let Ok(player) = players.get(game.player) {
        commands.entity(player).insert((
            XrBody { world_scale: scale.0 },
            XrLocomotion {
                enabled: false,
                ..default()
            },
            XrRecentre::default(),
        ));
    }
}

/// Sticks and triggers, added to the keyboard's input of this frame.
fn controllers_as_input(controllers: Res<XrControllers>, mut source: ResMut<InputSource>) {
    if *controllers == XrControllers::default() {
        return;
    }
    let left = controllers.hand(XrHandSide::Left);
    let right = controllers.hand(XrHandSide::Right);
    let live = &mut source.live;
    live.thrust += DVec3::new(f64::from(left.stick.x), 0.0, -f64::from(left.stick.y));
    live.turn += DVec3::new(f64::from(right.stick.y), -f64::from(right.stick.x), 0.0);
    live.thrust = live.thrust.clamp(DVec3::splat(-1.0), DVec3::splat(1.0));
    live.turn = live.turn.clamp(DVec3::splat(-1.0), DVec3::splat(1.0));
    live.fire |= left.trigger >= TRIGGER_PULLED || right.trigger >= TRIGGER_PULLED;
}

/// The pixel (from the image's top left) where an eye, whose isometry in
/// the body's frame is `eye`, sees the point `distance` ahead of the body
/// on its forward geodesic, in an image of `size` pixels drawn with
/// `clip_from_view`; `None` when the point is not in front of the eye.
/// In the eye's frame, after carrying the point there, the projective
/// chart shows true directions, so the point's chart coordinates are its
/// direction.
#[must_use]
pub fn crosshair_pixel(g: Geometry, eye: DMat4, clip_from_view: Mat4, size: Vec2, distance: f64) -> Option<Vec2> {
    let p = isometry::inverse(g, eye) * isometry::translation(g, DVec3::NEG_Z * distance) * DVec4::W;
    let d = p.truncate();
    if d.z.is_nan() || d.z >= 0.0 {
        return None;
    }
    let slope = (d / -d.z).as_vec3();
    let clip = clip_from_view * Vec4::new(slope.x, slope.y, -1.0, 1.0);
    let ndc = Vec2::new(clip.x, clip.y) / clip.w;
    ndc.is_finite()
        .then(|| Vec2::new((ndc.x + 1.0) / 2.0 * size.x, (1.0 - ndc.y) / 2.0 * size.y))
}

/// An eye's crosshair: a UI node drawn on that eye's camera only.
#[derive(Component)]
struct EyeCrosshair(Entity);

/// Half the crosshair's box, in pixels.
const HALF_CROSSHAIR: f32 = 14.0;

/// One crosshair per eye, moved each frame to where that eye sees the
/// point one inradius ahead on the shots' geodesic.
fn eye_crosshairs(
    mut commands: Commands,
    game: Option<Res<Game>>,
    spaces: Query<&ManifoldSpace>,
    heads: Query<&XrHead, With<Player>>,
    eyes: Query<(Entity, &XrEye, &Projection, &Camera)>,
    mut crosshairs: Query<(Entity, &EyeCrosshair, &mut Node, &mut Visibility)>,
) {
    let Some(game) = game else { return };
    let (Ok(head), Ok(ms)) = (heads.get(game.player), spaces.get(game.root)) else {
        return;
    };
    let space = ms.space();
    let mut drawn = Vec::new();
    for (entity, owner, mut node, mut visibility) in &mut crosshairs {
        let Ok((_, eye, projection, camera)) = eyes.get(owner.0) else {
            commands.entity(entity).despawn();
            continue;
        };
        drawn.push(owner.0);
        let at = camera.logical_viewport_size().and_then(|size| {
            let from_body = *head.eyes.get(eye.0 as usize)?;
            crosshair_pixel(
                space.geometry(),
                from_body,
                projection.get_clip_from_view(),
                size,
                space.inradius(),
            )
        });
        match at {
            Some(p) => {
                node.left = px(p.x - HALF_CROSSHAIR);
                node.top = px(p.y - HALF_CROSSHAIR);
                visibility.set_if_neq(Visibility::Inherited);
            }
            None => {
                visibility.set_if_neq(Visibility::Hidden);
            }
        }
    }
    for (entity, ..) in &eyes {
        if !drawn.contains(&entity) {
            commands.spawn((
                EyeCrosshair(entity),
                UiTargetCamera(entity),
                Text::new("+"),
                TextFont::from_font_size(2.0 * HALF_CROSSHAIR),
                TextColor(Color::srgba(1.0, 1.0, 1.0, 0.8)),
                TextLayout::justify(Justify::Center),
                Node {
                    position_type: PositionType::Absolute,
                    width: px(2.0 * HALF_CROSSHAIR),
                    height: px(2.0 * HALF_CROSSHAIR),
                    ..default()
                },
                Visibility::Hidden,
            ));
        }
    }
}
