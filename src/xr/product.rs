//! VR in the product spaces (H2xR, S2xR): an [`XrBody`] on a
//! [`ProductCamera`] carries the room through the space. Each eye is a
//! `ProductCamera` showing what the body's does, from the body's view
//! moved along the geodesic of the eye's tracked offset
//! ([`tracked::product_head_and_eyes`], the rule the eyes of a
//! `ManifoldSpace` follow), through the eye's own off-centre frustum.
//!
//! ```no_run
//! use bevy::prelude::*;
//! use bevy_manifold::prelude::*;
//! use bevy_manifold::product::{ProductBody, ProductCamera, ProductSpaceRoot};
//! use bevy_manifold::space::product::ProductSpace;
//! use bevy_manifold::xr::{ManifoldXrPlugin, XrBody};
//! use std::sync::Arc;
//!
//! fn setup(mut commands: Commands) {
//!     let space = ProductSpace::genus_two_x_s1(2.0);
//!     let root = commands.spawn(ProductSpaceRoot(Arc::new(space.clone()))).id();
//!     // The body: its camera is the desktop's view, and the eyes'.
//!     commands.spawn((ChildOf(root), Camera3d::default(), ProductCamera::default_for(space), XrBody::default()));
//! }
//!
//! App::new()
//!     .add_plugins(bevy_mod_openxr::add_xr_plugins(DefaultPlugins))
//!     .add_plugins((ManifoldPlugins::default(), ManifoldXrPlugin))
//!     .add_systems(Startup, setup)
//!     .run();
//! ```

use super::body::{RoomAsk, read_sticks};
use super::{XrBody, XrControllers, XrEye, XrLocomotion, XrRecentre};
use crate::placement::tracked;
use crate::product::ProductCamera;
use crate::space::product::ProductSpace;
use crate::trace::Frustum;
use crate::trace::product::ProductView;
use bevy::prelude::*;
use glam::{DQuat, DVec3};

/// The off-centre frustum of an eye's projection (OpenXR's): a direction
/// `(x, y, -1)` of the eye lands at NDC `x = p.x_axis.x x - p.z_axis.x`,
/// so the image spans `x` from `(-1 + p.z_axis.x) / p.x_axis.x` to
/// `(1 + p.z_axis.x) / p.x_axis.x` (likewise `y`). `None` for a
/// projection that is not a perspective one.
#[must_use]
pub fn eye_frustum(projection: &Projection) -> Option<Frustum> {
    let p = projection.get_clip_from_view().as_dmat4();
    let (sx, sy) = (p.x_axis.x, p.y_axis.y);
    if sx == 0.0 || sy == 0.0 || p.w_axis.w != 0.0 {
        return None;
    }
    let f = Frustum {
        left: (p.z_axis.x - 1.0) / sx,
        right: (p.z_axis.x + 1.0) / sx,
        down: (p.z_axis.y - 1.0) / sy,
        up: (p.z_axis.y + 1.0) / sy,
    };
    f.is_valid().then_some(f)
}

/// Each eye's [`ProductCamera`]: the body's space, balls, lights and view
/// settings, its view the body's moved to where the eye is tracked, seen
/// through the eye's frustum. Runs where the body has a `ProductCamera`.
pub(super) fn place_product_eyes(
    mut commands: Commands,
    mut bodies: Query<(Entity, &XrBody, &ProductCamera, Option<&mut XrRecentre>), Without<XrEye>>,
    mut eyes: Query<(&XrEye, &Transform, Option<&Projection>, &mut ProductCamera), Without<XrBody>>,
) {
    let Ok((entity, body, camera, recentre)) = bodies.single_mut() else {
        return;
    };
    let Some((poses, _)) = super::room_poses(eyes.iter().map(|(e, t, ..)| (e, t)), recentre) else {
        return;
    };
    let (head, views) = tracked::product_head_and_eyes(&camera.space, &camera.view, poses, body.world_scale);
    commands.entity(entity).insert(XrProductHead {
        view: head,
        room: tracked::head_in_room(poses),
    });
    for (eye, _, projection, mut eye_camera) in &mut eyes {
        let Some(view) = views.get(eye.0 as usize) else {
            continue;
        };
        let finite = [view.eye.surface, view.frame[0].surface, view.frame[2].surface]
            .iter()
            .all(|v| v.is_finite())
            && view.eye.height.is_finite();
        if !finite {
            continue;
        }
        let mut view = *view;
        view.frustum = projection.and_then(eye_frustum);
        let same_scene = std::sync::Arc::ptr_eq(&eye_camera.space, &camera.space)
            && eye_camera.balls == camera.balls
            && eye_camera.lights == camera.lights
            && eye_camera.lighting == camera.lighting
            && eye_camera.edges == camera.edges;
        if !same_scene {
            *eye_camera = ProductCamera { view, ..camera.clone() };
        } else if eye_camera.view != view {
            eye_camera.view = view;
        }
    }
}

/// Where the head is this frame in a product space, written on the
/// [`XrBody`]'s entity when it carries a [`ProductCamera`]: the view from
/// the midpoint of the eyes, facing as the left eye (where gameplay rays
/// from the head start).
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct XrProductHead {
    /// The head's view.
    pub view: ProductView,
    /// The head's pose in the room (metres), less [`XrRecentre`]'s offset.
    pub room: (DVec3, DQuat),
}

/// [`super::room_move`] in a product space: the body's view after the
/// room flies `distance` (at full stick) along the geodesic through the
/// head of the stick's direction (turned to the head's yaw, level with
/// the floor), then snap-turns by `turn` (radians, to the left) about the
/// head's vertical. The head's point does not move in a turn.
///
/// ```
/// use bevy_manifold::space::product::ProductSpace;
/// use bevy_manifold::trace::product::ProductScene;
/// use bevy_manifold::xr::product_room_move;
/// use glam::{DQuat, DVec3};
///
/// let space = ProductSpace::s2_x_s1(3.0);
/// let body = ProductScene::default_for(&space).view;
/// let head = (DVec3::new(0.3, 1.6, -0.2), DQuat::IDENTITY);
/// let turned = product_room_move(&space, &body, head, DVec3::ZERO, 0.0, 0.5, 4.0);
/// let at = |v: &bevy_manifold::trace::product::ProductView| v.posed(&space, head.0, DQuat::IDENTITY, 4.0).eye;
/// assert!(space.geometry.distance(at(&body), at(&turned)) < 1e-9);
/// ```
#[must_use]
pub fn product_room_move(
    space: &ProductSpace,
    body: &ProductView,
    head_room: (DVec3, DQuat),
    stick: DVec3,
    distance: f64,
    turn: f64,
    scale: f64,
) -> ProductView {
    let at = body.posed(space, head_room.0, DQuat::IDENTITY, scale);
    let forward = head_room.1 * DVec3::NEG_Z;
    let yaw = f64::atan2(-forward.x, -forward.z);
    let d = DQuat::from_rotation_y(yaw) * stick.clamp_length_max(1.0);
    let stepped = at.moved(space, [-d.z, d.x, d.y], d.length() * distance);
    let spun = stepped.posed(space, DVec3::ZERO, DQuat::from_rotation_y(turn), scale);
    spun.posed(space, -head_room.0, DQuat::IDENTITY, scale)
}

/// Reads the sticks and flies the body's [`ProductCamera`] ([`product_room_move`]);
/// the reset puts it back where it was first seen.
pub(super) fn product_locomotion(
    time: Res<Time>,
    controllers: Res<XrControllers>,
    mut bodies: Query<(Entity, &XrBody, &XrLocomotion, &XrProductHead, &mut ProductCamera)>,
    mut armed: Local<Option<(bool, bool)>>,
    mut start: Local<Option<(Entity, ProductView)>>,
) {
    let Ok((entity, body, motion, head, mut camera)) = bodies.single_mut() else {
        return;
    };
    if start.is_none_or(|(e, _)| e != entity) {
        *start = Some((entity, camera.view));
    }
    let armed = armed.get_or_insert((true, true));
    match read_sticks(&controllers, motion, armed) {
        RoomAsk::Stay => {}
        RoomAsk::Reset => {
            if let Some((_, view)) = *start {
                camera.view = view;
            }
        }
        RoomAsk::Move { stick, turn } => {
            let distance = motion.speed * time.delta_secs_f64();
            let view = product_room_move(
                &camera.space,
                &camera.view,
                head.room,
                stick,
                distance,
                turn,
                body.world_scale,
            );
            camera.view = view;
        }
    }
}
