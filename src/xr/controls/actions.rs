//! The controllers through OpenXR actions: one action set (grip pose,
//! thumbstick, trigger, two buttons, for each hand), bound to the common
//! controllers (Oculus Touch, Valve Index, HTC Vive, and the Khronos
//! simple controller every runtime has), read once a frame into
//! [`XrControllers`]. The grips are OpenXR action spaces on two entities
//! ([`XrGrip`]) whose `Transform` bevy_mod_openxr writes.

use super::{XrControllers, XrHandSide};
use bevy::prelude::*;
use bevy_mod_openxr::action_binding::{OxrSendActionBindings, OxrSuggestActionBinding};
use bevy_mod_openxr::action_set_attaching::OxrAttachActionSet;
use bevy_mod_openxr::action_set_syncing::{OxrActionSetSyncSet, OxrSyncActionSet};
use bevy_mod_openxr::openxr_session_running;
use bevy_mod_openxr::resources::OxrInstance;
use bevy_mod_openxr::session::OxrSession;
use bevy_mod_openxr::spaces::OxrSpaceLocationFlags;
use bevy_mod_xr::session::{XrSessionCreated, session_available};
use bevy_mod_xr::spaces::XrSpaceSyncSet;
use openxr::{Posef, Vector2f};

/// The action set and its actions (with the two hands' subaction paths).
#[derive(Resource)]
struct Actions {
    set: openxr::ActionSet,
    grip: openxr::Action<Posef>,
    stick: openxr::Action<Vector2f>,
    trigger: openxr::Action<f32>,
    primary: openxr::Action<bool>,
    secondary: openxr::Action<bool>,
    hands: [openxr::Path; 2],
}

/// An entity whose `Transform` is a grip's pose in the room (written by
/// bevy_mod_openxr from the grip's action space).
#[derive(Component, Clone, Copy, Debug)]
pub struct XrGrip(pub XrHandSide);

/// Adds the action set and reads it each frame (into `XrControllers`).
pub(crate) fn build(app: &mut App) {
    app.add_systems(Startup, create_actions.run_if(session_available))
        .add_systems(OxrSendActionBindings, suggest_bindings)
        .add_systems(XrSessionCreated, (attach_actions, spawn_grips))
        .add_systems(
            PreUpdate,
            (
                sync_actions.before(OxrActionSetSyncSet),
                read_actions.after(OxrActionSetSyncSet).after(XrSpaceSyncSet),
            )
                .run_if(openxr_session_running),
        );
}

fn create_actions(mut commands: Commands, instance: Res<OxrInstance>) {
    let made = (|| -> openxr::Result<Actions> {
        let hands = [
            instance.string_to_path("/user/hand/left")?,
            instance.string_to_path("/user/hand/right")?,
        ];
        let set = instance.create_action_set("bevy_manifold", "bevy_manifold", 0)?;
        Ok(Actions {
            grip: set.create_action("grip", "Hand pose", &hands)?,
            stick: set.create_action("stick", "Fly and turn", &hands)?,
            trigger: set.create_action("trigger", "Trigger", &hands)?,
            primary: set.create_action("primary", "Next space", &hands)?,
            secondary: set.create_action("secondary", "Reset", &hands)?,
            set,
            hands,
        })
    })();
    match made {
        Ok(actions) => commands.insert_resource(actions),
        Err(e) => warn!("xr: the controllers' actions could not be made ({e}); no controller input"),
    }
}

/// Where each action is bound on each controller the plugin knows.
fn suggest_bindings(actions: Option<Res<Actions>>, mut bindings: MessageWriter<OxrSuggestActionBinding>) {
    let Some(a) = actions else { return };
    // (profile, stick, primary, secondary): per hand, left then right.
    let profiles: [(&str, &str, [&str; 2], [&str; 2]); 4] = [
        (
            "/interaction_profiles/oculus/touch_controller",
            "thumbstick",
            ["x/click", "a/click"],
            ["y/click", "b/click"],
        ),
        (
            "/interaction_profiles/valve/index_controller",
            "thumbstick",
            ["a/click", "a/click"],
            ["b/click", "b/click"],
        ),
        (
            "/interaction_profiles/htc/vive_controller",
            "trackpad",
            ["trackpad/click", "trackpad/click"],
            ["menu/click", "menu/click"],
        ),
        (
            "/interaction_profiles/khr/simple_controller",
            "",
            ["", ""],
            ["menu/click", "menu/click"],
        ),
    ];
    for (profile, stick, primary, secondary) in profiles {
        let mut bind = |action: openxr::sys::Action, paths: [String; 2]| {
            let paths: Vec<_> = paths
                .into_iter()
                .filter(|p| !p.ends_with("input/"))
                .map(Into::into)
                .collect();
            if !paths.is_empty() {
                bindings.write(OxrSuggestActionBinding {
                    action,
                    interaction_profile: profile.into(),
                    bindings: paths,
                });
            }
        };
        let per_hand =
            |input: [&str; 2]| [0, 1].map(|i| format!("/user/hand/{}/input/{}", ["left", "right"][i], input[i]));
        let trigger = if profile.contains("simple") {
            "select/click"
        } else {
            "trigger/value"
        };
        bind(a.grip.as_raw(), per_hand(["grip/pose"; 2]));
        bind(a.trigger.as_raw(), per_hand([trigger; 2]));
        bind(a.stick.as_raw(), per_hand([stick; 2]));
        bind(a.primary.as_raw(), per_hand(primary));
        bind(a.secondary.as_raw(), per_hand(secondary));
    }
}

fn attach_actions(actions: Option<Res<Actions>>, mut attach: MessageWriter<OxrAttachActionSet>) {
    if let Some(a) = actions {
        attach.write(OxrAttachActionSet(a.set.clone()));
    }
}

fn spawn_grips(mut commands: Commands, actions: Option<Res<Actions>>, session: Res<OxrSession>) {
    let Some(a) = actions else { return };
    for side in XrHandSide::BOTH {
        match session.create_action_space(&a.grip, a.hands[side.index()], Isometry3d::IDENTITY) {
            Ok(space) => {
                commands.spawn((Name::new("XR grip"), XrGrip(side), space, Transform::default()));
            }
            Err(e) => warn!("xr: no grip space for the {side:?} hand ({e})"),
        }
    }
}

fn sync_actions(actions: Option<Res<Actions>>, mut sync: MessageWriter<OxrSyncActionSet>) {
    if let Some(a) = actions {
        sync.write(OxrSyncActionSet(a.set.clone()));
    }
}

/// An action's state, when it is bound and active.
fn active<T: openxr::ActionInput>(state: openxr::Result<openxr::ActionState<T>>) -> Option<T> {
    state.ok().filter(|s| s.is_active).map(|s| s.current_state)
}

/// The actions' states and the grips' poses into [`XrControllers`].
fn read_actions(
    actions: Option<Res<Actions>>,
    session: Res<OxrSession>,
    grips: Query<(&XrGrip, &Transform, &OxrSpaceLocationFlags)>,
    mut controllers: ResMut<XrControllers>,
) {
    let Some(a) = actions else { return };
    let mut next = XrControllers::default();
    for side in XrHandSide::BOTH {
        let path = a.hands[side.index()];
        let c = &mut next.hands[side.index()];
        c.stick = active(a.stick.state(&session, path)).map_or(Vec2::ZERO, |v: Vector2f| Vec2::new(v.x, v.y));
        c.trigger = active(a.trigger.state(&session, path)).unwrap_or(0.0);
        c.primary = active(a.primary.state(&session, path)).unwrap_or(false);
        c.secondary = active(a.secondary.state(&session, path)).unwrap_or(false);
    }
    for (grip, transform, flags) in &grips {
        if flags.pos_valid() && flags.rot_valid() {
            next.hands[grip.0.index()].grip = Some((transform.translation, transform.rotation));
        }
    }
    controllers.set_if_neq(next);
}
