//! Which space an entity lives in, as a Bevy relationship (in the manner
//! of avian's `ColliderOf`): every entity below a [`ManifoldSpace`] root
//! carries [`InSpace`] naming the root, and the root's [`SpaceMembers`]
//! lists them. Observers keep it current when the hierarchy changes (an
//! entity spawned or re-parented, a root made or unmade), so the systems,
//! the scene gathering and the render extraction read one component
//! instead of walking ancestors, and gathering a space is O(members).
//!
//! ```
//! use bevy::prelude::*;
//! use bevy_manifold::prelude::*;
//!
//! let mut app = App::new();
//! app.add_plugins((MinimalPlugins, PlacementPlugin::default()));
//! let root = app.world_mut().spawn(ManifoldSpace::new(catalog::torus(1.0))).id();
//! let ship = app.world_mut().spawn((ChildOf(root), Placement::default())).id();
//! let gun = app.world_mut().spawn(ChildOf(ship)).id();
//! assert_eq!(app.world().get::<InSpace>(gun).map(InSpace::space), Some(root));
//! app.world_mut().entity_mut(ship).remove::<ChildOf>();
//! assert!(app.world().get::<InSpace>(gun).is_none());
//! assert!(app.world().get::<SpaceMembers>(root).is_none_or(|m| m.is_empty()));
//! ```

use super::components::ManifoldSpace;
use bevy::prelude::*;

/// The [`ManifoldSpace`] root an entity lives in: its nearest ancestor
/// with one. Kept by the placement plugin's observers; not meant to be
/// inserted by hand (re-parent the entity instead).
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq)]
#[relationship(relationship_target = SpaceMembers)]
pub struct InSpace(Entity);

impl InSpace {
    /// The root entity holding the [`ManifoldSpace`].
    #[must_use]
    pub fn space(&self) -> Entity {
        self.0
    }
}

/// On a [`ManifoldSpace`] root: every entity that lives in it (each with
/// [`InSpace`] naming this root), in the order they joined.
#[derive(Component, Debug, Default)]
#[relationship_target(relationship = InSpace)]
pub struct SpaceMembers(Vec<Entity>);

impl SpaceMembers {
    /// The members.
    pub fn iter(&self) -> impl Iterator<Item = Entity> + '_ {
        self.0.iter().copied()
    }

    /// How many entities live in the space.
    #[must_use]
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// True when no entity lives in the space.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

/// The observers that keep [`InSpace`] current. Each queues [`refresh`]
/// of the subtree whose membership may have changed; it runs once the
/// hierarchy change is complete.
pub(super) fn observe(app: &mut App) {
    app.add_observer(refresh_later::<Insert, ChildOf>)
        .add_observer(refresh_later::<Remove, ChildOf>)
        .add_observer(refresh_later::<Add, ManifoldSpace>)
        .add_observer(refresh_later::<Remove, ManifoldSpace>);
}

/// The observer: queues [`refresh`] of the entity the event is about.
fn refresh_later<E: EntityEvent, B: Bundle>(event: On<E, B>, mut commands: Commands) {
    let entity = event.event_target();
    commands.queue(move |world: &mut World| refresh(world, entity));
}

/// The root an entity below `entity`'s parent chain belongs to: the
/// nearest strict ancestor with a [`ManifoldSpace`] (the one walk up the
/// hierarchy, run only when the hierarchy changed).
fn root_above(world: &World, entity: Entity) -> Option<Entity> {
    let mut at = world.get::<ChildOf>(entity)?.parent();
    loop {
        if world.get::<ManifoldSpace>(at).is_some() {
            return Some(at);
        }
        at = world.get::<ChildOf>(at)?.parent();
    }
}

/// Sets [`InSpace`] on `top` and every entity below it. A root is a
/// member of no space; its descendants are members of it.
fn refresh(world: &mut World, top: Entity) {
    if world.get_entity(top).is_err() {
        return;
    }
    let mut stack = vec![(top, root_above(world, top))];
    while let Some((entity, root)) = stack.pop() {
        let Ok(mut e) = world.get_entity_mut(entity) else {
            continue;
        };
        let is_root = e.contains::<ManifoldSpace>();
        let wanted = if is_root { None } else { root };
        let current = e.get::<InSpace>().map(InSpace::space);
        if current != wanted {
            match wanted {
                Some(r) => {
                    e.insert(InSpace(r));
                }
                None => {
                    e.remove::<InSpace>();
                }
            }
        }
        let below = if is_root { Some(entity) } else { root };
        if let Some(children) = e.get::<Children>() {
            stack.extend(children.iter().map(|c| (c, below)));
        }
    }
}
