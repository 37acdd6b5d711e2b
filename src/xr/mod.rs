//! VR through OpenXR (feature `xr`): each eye of the headset is a
//! [`ManifoldCamera`], traced from where the eye is in the manifold.
//!
//! bevy_mod_openxr spawns one `Camera3d` per eye (`XrCamera(i)`) under its
//! tracking root, rendering into a layer of the swapchain, and writes each
//! eye's pose (metres, in the room) into its `Transform` and the eye's
//! off-centre projection into its `Projection`. This plugin:
//!
//! - hangs the tracking root under the entity with an [`XrBody`] (a placed
//!   entity in a [`crate::placement::ManifoldSpace`]): the whole room rides
//!   on the body's placement, so flying, wrapping and holonomy move head
//!   and hands together ([`crate::placement::tracked`] gives the rule);
//! - makes each eye a [`ManifoldCamera`] with the body's levels, fog and cell
//!   shading, `Msaa::Off` and `Tonemapping::None` (set, since `Camera3d`
//!   brought others), and a [`TrackedPose`] so its `Transform` stays the
//!   tracker's;
//! - each frame places the head and the eyes from the body along
//!   geodesics ([`XrHead`] on the body), and again in the render world
//!   from the late-located views, so the traced image and anything
//!   rasterised over it use the same pose;
//! - puts each [`XrHand`] on its controller's grip, measured from the head
//!   like the eyes, so a hand reaching through a face appears where the
//!   eyes expect it; reads the controllers into [`XrControllers`] (grips,
//!   sticks, triggers, two buttons) and sends [`XrTrigger`] when a trigger
//!   is pulled or let go, for games;
//! - flies the room with the sticks ([`XrLocomotion`]: geodesic flight
//!   through the head, snap turns, a reset);
//! - in a product space (H2xR, S2xR), where the body is a
//!   [`crate::product::ProductCamera`], makes each eye a product camera
//!   whose view is the body's moved to the eye (the same rule; see
//!   [`XrProductHead`] and [`product_room_move`]).
//!
//! The tracer reads each eye's full projection (its frustum is off-centre;
//! `Frustum` in the core), and both eyes bind one upload of the scene.
//! Without an OpenXR runtime bevy_mod_openxr renders to the desktop as
//! usual and `XrState` is `Unavailable`.
//!
//! ```no_run
//! use bevy::prelude::*;
//! use bevy_manifold::prelude::*;
//! use bevy_manifold::xr::{ManifoldXrPlugin, XrBody};
//!
//! fn setup(mut commands: Commands) {
//!     let space = catalog::seifert_weber();
//!     let root = commands.spawn((ManifoldSpace::new(space), DomainEdges::default())).id();
//!     // The body: the room's floor centre. Its camera is the desktop's
//!     // spectator view; the eyes copy its levels and fog.
//!     commands.spawn((ChildOf(root), XrBody::default(), ManifoldCamera::default()));
//!     commands.spawn((ChildOf(root), TracedBall::new(0.2, Color::srgb(0.9, 0.4, 0.2))));
//! }
//!
//! App::new()
//!     .add_plugins(bevy_mod_openxr::add_xr_plugins(DefaultPlugins))
//!     .add_plugins((ManifoldPlugins::default(), ManifoldXrPlugin))
//!     .add_systems(Startup, setup)
//!     .run();
//! ```

mod body;
mod capture;
mod controls;
mod late;
mod product;

use crate::camera::{AdaptiveRenderScale, ManifoldCamera, ManifoldFootprint, ManifoldRenderScale};
use crate::camera::{CellShading, ManifoldFog};
use crate::placement::tracked::{self, TrackedPose};
use crate::placement::{DomainCell, InSpace, ManifoldSpace, ManifoldSystems, Placement, WrapOrigin};
use crate::product::ProductCamera;
use bevy::camera::CameraMainTextureUsages;
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::prelude::*;
use bevy::render::render_resource::TextureUsages;
use bevy::render::view::Msaa;
use bevy_mod_xr::camera::XrCamera;
use bevy_mod_xr::session::XrTrackingRoot;

pub use bevy_mod_xr::session::XrState;
pub use body::{XrHand, XrLocomotion, rest_pose, room_move};
pub use capture::{XrEyeCapture, XrEyeImage, save_eyes, save_eyes_at};
pub use controls::actions::XrGrip;
pub use controls::{TRIGGER_PULLED, TRIGGER_RELEASED, XrController, XrControllers, XrHandSide, XrTrigger};
pub use late::{ExtractedProductXrEye, ExtractedXrEye, XrFrameStats};
pub use product::{XrProductHead, eye_frustum, product_room_move};

/// The body that carries the headset's tracking space (the room) through
/// the manifold: its [`Placement`] is the room's floor centre and facing.
/// One per app (OpenXR has one tracking space); put it on a placed entity
/// under a [`ManifoldSpace`].
///
/// A [`ManifoldCamera`], [`ManifoldFog`] or [`CellShading`] on the same
/// entity is copied to the eyes each frame (the desktop window then shows
/// the body's own view: a spectator camera at the room's centre).
#[derive(Component, Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Component, Debug, Default)]
#[require(Placement, body::XrLocomotion)]
pub struct XrBody {
    /// Metres of tracking space per unit of the space's distance: at 4, a
    /// step of 1 m in the room moves the eyes 0.25 along a geodesic.
    pub world_scale: f64,
}

impl Default for XrBody {
    fn default() -> Self {
        XrBody { world_scale: 4.0 }
    }
}

/// Where the head is this frame (the midpoint of the eyes, facing as the
/// left eye), written on the [`XrBody`]'s entity: where gameplay rays from
/// the head start, and what the hands are measured from.
#[derive(Component, Clone, Debug, PartialEq)]
pub struct XrHead {
    /// The head's placement, inside the domain.
    pub placement: Placement,
    /// The copy of the domain it is in.
    pub cell: DomainCell,
    /// The head's pose in the room (metres), as the tracker measured it
    /// less [`XrHead::recentred`].
    pub room: (glam::DVec3, glam::DQuat),
    /// What was taken off every tracked position ([`XrRecentre`]; zero
    /// without it).
    pub recentred: Vec3,
    /// Each eye's isometry in the body's frame (left, right): what the
    /// eyes see of something placed relative to the body.
    pub eyes: [glam::DMat4; 2],
}

/// On the [`XrBody`]: the room is shifted so that the head, where it was
/// when first tracked (or when `offset` is set to `None` again), is at the
/// body's origin. For seated and flying games whose player entity is the
/// head (its collider, where its shots leave), rather than a room whose
/// floor the player stands on.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Reflect)]
#[reflect(Component, Debug, Default)]
pub struct XrRecentre {
    /// The room position (metres) taken off every tracked position; set
    /// from the head on the first tracked frame when `None`.
    pub offset: Option<Vec3>,
}

/// One eye of the headset, as a manifold camera: `XrCamera`'s view index
/// (0 left, 1 right).
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq)]
pub struct XrEye(pub u32);

/// The plugin: add it after `bevy_mod_openxr::add_xr_plugins(DefaultPlugins)`
/// and [`crate::ManifoldPlugins`]. See the [module](self) for what it does.
#[derive(Debug, Clone, Copy, Default)]
pub struct ManifoldXrPlugin;

impl Plugin for ManifoldXrPlugin {
    fn build(&self, app: &mut App) {
        app.register_type::<XrBody>()
            .register_type::<XrRecentre>()
            .register_type::<XrHand>()
            .register_type::<XrLocomotion>()
            .init_resource::<XrControllers>()
            .add_message::<XrTrigger>()
            .add_systems(
                Update,
                (
                    (adopt_tracking_root, equip_eyes, copy_view_settings).chain(),
                    (controls::trigger_edges, body::locomotion, product::product_locomotion),
                ),
            )
            .add_systems(
                PostUpdate,
                (place_eyes, body::place_hands, product::place_product_eyes)
                    .chain()
                    .after(bevy_mod_openxr::render::update_views)
                    .after(ManifoldSystems::Wrap)
                    .before(ManifoldSystems::Sync),
            );
        late::build(app);
        capture::build(app);
        if app
            .world()
            .contains_resource::<bevy_mod_openxr::resources::OxrInstance>()
            || app.is_plugin_added::<bevy_mod_openxr::init::OxrInitPlugin>()
        {
            controls::actions::build(app);
        }
    }
}

/// Takes the tracking root off its body, so that despawning the body (or
/// its space's root, as switching spaces does) leaves bevy_mod_openxr's
/// root and eyes alive; the plugin hangs it under the next [`XrBody`].
/// Queue it before the despawn.
pub fn keep_tracking_root(commands: &mut Commands) {
    commands.queue(|world: &mut World| {
        let mut roots = world.query_filtered::<Entity, (With<XrTrackingRoot>, With<ChildOf>)>();
        let roots: Vec<Entity> = roots.iter(world).collect();
        for root in roots {
            world.entity_mut(root).remove::<ChildOf>();
        }
    });
}

/// Hangs the tracking root under the body, scaled to the space's units
/// (so rasterised overlays on the eyes land near the chart positions).
fn adopt_tracking_root(
    mut commands: Commands,
    bodies: Query<(Entity, &XrBody)>,
    mut roots: Query<(Entity, Option<&ChildOf>, &mut Transform), With<XrTrackingRoot>>,
) {
    let Ok((body, xb)) = bodies.single() else { return };
    for (root, parent, mut transform) in &mut roots {
        if parent.map(ChildOf::parent) != Some(body) {
            commands.entity(root).insert(ChildOf(body));
        }
        let s = Vec3::splat((1.0 / xb.world_scale) as f32);
        if transform.scale != s && s.is_finite() {
            transform.scale = s;
        }
    }
}

/// Makes each new eye a camera whose `Transform` is the tracker's: a
/// manifold camera, or where the body is in a product space a product
/// camera; an eye whose body changes kind (the explorer switching
/// spaces) changes with it.
#[expect(clippy::type_complexity, reason = "a system's queries")]
fn equip_eyes(
    mut commands: Commands,
    eyes: Query<(Entity, &XrCamera, Has<XrEye>, Has<ManifoldCamera>, Has<ProductCamera>)>,
    bodies: Query<(Option<&ManifoldCamera>, Option<&ProductCamera>), With<XrBody>>,
) {
    let body = bodies.single().ok();
    for (entity, camera, equipped, manifold_eye, product_eye) in &eyes {
        let mut eye = commands.entity(entity);
        if !equipped {
            eye.insert((
                XrEye(camera.0),
                TrackedPose,
                Msaa::Off,
                Tonemapping::None,
                // The eye's view target can be read back (XrEyeCapture).
                CameraMainTextureUsages::default().with(TextureUsages::COPY_SRC),
            ));
        }
        // An eye of a product space's body sees it as the body does;
        // any other is a manifold camera (with none yet, a new one).
        match body {
            Some((_, Some(p))) if !product_eye => {
                eye.remove::<ManifoldCamera>().insert(p.clone());
            }
            Some((m, None)) if product_eye || !manifold_eye => {
                eye.remove::<ProductCamera>().insert(m.copied().unwrap_or_default());
            }
            None if !equipped => {
                eye.insert(ManifoldCamera::default());
            }
            _ => {}
        }
    }
}

/// The body's levels, distance, fog, cell shading, render scale and cone
/// tracing ([`ManifoldFootprint`]) on every eye. A body holding a frame rate ([`crate::camera::AdaptiveRenderScale`])
/// chooses one scale from the whole frame's time, both eyes included,
/// and both eyes trace at it; an eye with a controller of its own keeps
/// its own.
#[expect(clippy::type_complexity, reason = "a system's queries")]
fn copy_view_settings(
    mut commands: Commands,
    bodies: Query<
        (
            Option<&ManifoldCamera>,
            Option<&ManifoldFog>,
            Option<&CellShading>,
            Option<&ManifoldRenderScale>,
            Has<ManifoldFootprint>,
        ),
        With<XrBody>,
    >,
    mut eyes: Query<
        (
            Entity,
            &mut ManifoldCamera,
            Option<&ManifoldFog>,
            Option<&CellShading>,
            Option<&ManifoldRenderScale>,
            Has<AdaptiveRenderScale>,
            Has<ManifoldFootprint>,
        ),
        (With<XrEye>, Without<XrBody>),
    >,
) {
    let Ok((camera, fog, shading, scale, cones)) = bodies.single() else {
        return;
    };
    for (entity, mut eye, eye_fog, eye_shading, eye_scale, own_controller, eye_cones) in &mut eyes {
        match (cones, eye_cones) {
            (true, false) => {
                commands.entity(entity).insert(ManifoldFootprint);
            }
            (false, true) => {
                commands.entity(entity).remove::<ManifoldFootprint>();
            }
            _ => {}
        }
        match (scale, eye_scale) {
            _ if own_controller => {}
            (Some(s), e) if e != Some(s) => {
                commands.entity(entity).insert(*s);
            }
            (None, Some(_)) => {
                commands.entity(entity).remove::<ManifoldRenderScale>();
            }
            _ => {}
        }
        if let Some(c) = camera {
            eye.set_if_neq(*c);
        }
        match (fog, eye_fog) {
            (Some(f), e) if e != Some(f) => {
                commands.entity(entity).insert(*f);
            }
            (None, Some(_)) => {
                commands.entity(entity).remove::<ManifoldFog>();
            }
            _ => {}
        }
        if let Some(s) = shading
            && eye_shading != Some(s)
        {
            commands.entity(entity).insert(*s);
        }
    }
}

/// Places the head and the eyes from the body along geodesics, each
/// wrapped into the domain, from the eyes' tracked `Transform`s.
#[expect(clippy::type_complexity, reason = "a system's queries")]
fn place_eyes(
    mut commands: Commands,
    mut bodies: Query<
        (
            Entity,
            &XrBody,
            &Placement,
            &DomainCell,
            &InSpace,
            Option<&mut XrRecentre>,
        ),
        Without<XrEye>,
    >,
    spaces: Query<&ManifoldSpace>,
    mut eyes: Query<(&XrEye, &Transform, &mut Placement, &mut DomainCell, &mut WrapOrigin), Without<XrBody>>,
) {
    let Ok((entity, body, placement, cell, in_space, recentre)) = bodies.single_mut() else {
        return;
    };
    let Ok(ms) = spaces.get(in_space.space()) else { return };
    let Some((poses, recentred)) = room_poses(eyes.iter().map(|(e, t, ..)| (e, t)), recentre) else {
        return;
    };
    let g = ms.space().geometry();
    // In the body's frame, then carried by the body's placement.
    let (head_from_body, from_body) = tracked::head_and_eyes(g, glam::DMat4::IDENTITY, poses, body.world_scale);
    let head = placement.isometry * head_from_body;
    let placed = from_body.map(|e| placement.isometry * e);
    let room = tracked::head_in_room(poses);
    if !head.is_finite() {
        return;
    }
    let (head_placement, head_cell) = tracked::tracked_placement(ms, placement, cell, head);
    for (eye, _, mut p, mut c, mut origin) in &mut eyes {
        let Some(to) = placed.get(eye.0 as usize) else { continue };
        let (np, nc) = tracked::tracked_placement(ms, placement, cell, *to);
        origin.0 = Some(np.isometry);
        p.set_if_neq(np);
        c.set_if_neq(nc);
    }
    commands.entity(entity).insert(XrHead {
        placement: head_placement,
        cell: head_cell,
        room,
        recentred,
        eyes: from_body,
    });
}

/// The two eyes' tracked poses in the room (left, right), less what
/// [`XrRecentre`] takes off (set from these poses on the first tracked
/// frame), and what it takes off; `None` until both eyes are there.
fn room_poses<'a>(
    eyes: impl Iterator<Item = (&'a XrEye, &'a Transform)>,
    recentre: Option<Mut<XrRecentre>>,
) -> Option<([(Vec3, Quat); 2], Vec3)> {
    let mut poses = [(Vec3::ZERO, Quat::IDENTITY); 2];
    let mut seen = 0;
    for (eye, transform) in eyes {
        if let Some(p) = poses.get_mut(eye.0 as usize) {
            *p = (transform.translation, transform.rotation);
            seen += 1;
        }
    }
    if seen < 2 {
        return None;
    }
    let recentred = match recentre {
        Some(mut r) => *r.offset.get_or_insert((poses[0].0 + poses[1].0) / 2.0),
        None => Vec3::ZERO,
    };
    for p in &mut poses {
        p.0 -= recentred;
    }
    Some((poses, recentred))
}
