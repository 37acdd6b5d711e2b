//! [`ManifoldContacts`]: overlap and contact queries between colliders,
//! through the face pairings (the ECS face of [`crate::contact`]), and
//! [`ContactStarted`] / [`ContactEnded`] messages for colliders that ask
//! for them ([`ContactEvents`]). Shape casts (a ball swept along a
//! geodesic) are [`super::ManifoldRayCast::shape_cast`].
//!
//! ```
//! use bevy::prelude::*;
//! use bevy_manifold::prelude::*;
//! use glam::DVec3;
//!
//! let mut app = App::new();
//! app.add_plugins((MinimalPlugins, PlacementPlugin::default()));
//! let space = catalog::torus(1.0);
//! let root = app.world_mut().spawn(ManifoldSpace::new(space.clone())).id();
//! // Two balls 0.2 apart through the face x = 1/2, 0.8 across the cube.
//! let ball = ManifoldCollider::Ball { radius: 0.15 };
//! let a = app.world_mut().spawn((ChildOf(root), ball, ContactEvents, Placement::at(&space, DVec3::X * -0.4))).id();
//! let b = app.world_mut().spawn((ChildOf(root), ball, Placement::at(&space, DVec3::X * 0.4))).id();
//! app.update();
//! let started: Vec<ContactStarted> = app.world_mut().resource_mut::<Messages<ContactStarted>>().drain().collect();
//! assert_eq!(started, vec![ContactStarted { a, b }]);
//! ```

use super::components::{ManifoldCollider, ManifoldSpace, Placement};
use super::membership::InSpace;
use super::systems::{lives_in, space_of};
use crate::contact::{self, Contact, Image};
use bevy::ecs::system::SystemParam;
use bevy::platform::collections::HashSet;
use bevy::prelude::*;
use glam::DVec4;

/// Opts a collider into [`ContactStarted`] and [`ContactEnded`]: each
/// frame its contacts with every other collider of its space are found
/// (nothing is computed for colliders without it). On an entity without a
/// [`ManifoldCollider`] it does nothing.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Eq, Reflect)]
#[reflect(Component, Debug, Default)]
pub struct ContactEvents;

/// Sent when two colliders (one of them with [`ContactEvents`]) start to
/// touch, through any image. `a` is the one with [`ContactEvents`] (the
/// lower entity when both have it).
#[derive(Message, Clone, Copy, Debug, PartialEq, Eq)]
pub struct ContactStarted {
    /// The collider with [`ContactEvents`].
    pub a: Entity,
    /// The other.
    pub b: Entity,
}

/// Sent when two colliders that touched stop touching, or one of them is
/// despawned, leaves the space or loses its collider.
#[derive(Message, Clone, Copy, Debug, PartialEq, Eq)]
pub struct ContactEnded {
    /// The collider with [`ContactEvents`].
    pub a: Entity,
    /// The other.
    pub b: Entity,
}

/// One collider overlapping a query shape: the entity and its contacts
/// (one per image of it that overlaps, deepest first).
#[derive(Clone, Debug, PartialEq)]
pub struct Overlap {
    /// The collider.
    pub entity: Entity,
    /// Its contacts with the query shape, deepest first.
    pub contacts: Vec<Contact>,
}

/// Overlap and contact queries between colliders ([`ManifoldCollider`])
/// in their manifold, through the face pairings: every image counts, as
/// the tracer draws every image. Each query reads the colliders of one
/// space; its cost is that count times the images within reach
/// ([`crate::contact`]).
///
/// ```
/// use bevy::prelude::*;
/// use bevy_manifold::prelude::*;
/// fn hurt(contacts: ManifoldContacts, players: Query<Entity, With<GeodesicVelocity>>) {
///     for player in &players {
///         for overlap in contacts.touching(player) {
///             info!("{player} touches {} through {} images", overlap.entity, overlap.contacts.len());
///         }
///     }
/// }
/// # bevy::ecs::system::assert_is_system(hurt);
/// ```
#[derive(SystemParam)]
pub struct ManifoldContacts<'w, 's> {
    spaces: Query<'w, 's, &'static ManifoldSpace>,
    members: Query<'w, 's, &'static InSpace>,
    placed: Query<'w, 's, &'static Placement>,
    colliders: Query<'w, 's, (Entity, &'static Placement, &'static ManifoldCollider)>,
}

impl ManifoldContacts<'_, '_> {
    /// The colliders of the space at `root` overlapping `shape` placed at
    /// `at` (in that space's domain), each with its contacts; the nearest
    /// first. Empty when `root` holds no space.
    #[must_use]
    pub fn overlapping(&self, root: Entity, shape: ManifoldCollider, at: &Placement) -> Vec<Overlap> {
        let Ok(ms) = self.spaces.get(root) else {
            return Vec::new();
        };
        self.overlapping_in(ms, None, (at.position(), shape.radius()))
    }

    /// The other colliders that `entity`'s collider touches, through any
    /// image, nearest first (and its own images, when it is wider than the
    /// space is small). Empty when it has no collider or no space.
    #[must_use]
    pub fn touching(&self, entity: Entity) -> Vec<Overlap> {
        let Ok((_, placement, collider)) = self.colliders.get(entity) else {
            return Vec::new();
        };
        let Some(ms) = space_of(entity, &self.members, &self.spaces) else {
            return Vec::new();
        };
        self.overlapping_in(ms, Some(entity), (placement.position(), collider.radius()))
    }

    /// The contacts between the colliders of `a` and `b` (one per image of
    /// `b` that overlaps `a`), deepest first. Empty when they do not
    /// touch, lack colliders or live in different spaces.
    #[must_use]
    pub fn contacts(&self, a: Entity, b: Entity) -> Vec<Contact> {
        let (Ok((_, pa, ca)), Ok((_, pb, cb))) = (self.colliders.get(a), self.colliders.get(b)) else {
            return Vec::new();
        };
        let Some(ms) = self.shared_space(a, b) else {
            return Vec::new();
        };
        contact::ball_contacts(ms.space(), (pa.position(), ca.radius()), (pb.position(), cb.radius()))
    }

    /// The image of `b` nearest to `a` (any placed entities of one space):
    /// the shortest route from `a` to `b` through the faces, with the
    /// direction to fly and the distance. `None` when they live in
    /// different spaces.
    #[must_use]
    pub fn nearest_image(&self, a: Entity, b: Entity) -> Option<Image> {
        let (pa, pb) = (self.placed.get(a).ok()?, self.placed.get(b).ok()?);
        let ms = self.shared_space(a, b)?;
        contact::nearest_image(ms.space(), pa.position(), pb.position())
    }

    fn shared_space(&self, a: Entity, b: Entity) -> Option<&ManifoldSpace> {
        let (ra, rb) = (self.members.get(a).ok()?, self.members.get(b).ok()?);
        (ra.space() == rb.space()).then(|| self.spaces.get(ra.space()).ok())?
    }

    fn overlapping_in(&self, ms: &ManifoldSpace, me: Option<Entity>, shape: (DVec4, f64)) -> Vec<Overlap> {
        let space = ms.space();
        let mut out: Vec<Overlap> = self
            .colliders
            .iter()
            .filter(|(e, ..)| lives_in(*e, &self.members, &self.spaces, space))
            .filter_map(|(e, p, c)| {
                let mut contacts = contact::ball_contacts(space, shape, (p.position(), c.radius()));
                if Some(e) == me {
                    // Itself, where it is: not a contact.
                    contacts.retain(|c| c.image.distance > 0.0);
                }
                (!contacts.is_empty()).then_some(Overlap { entity: e, contacts })
            })
            .collect();
        out.sort_by(|a, b| a.contacts[0].image.distance.total_cmp(&b.contacts[0].image.distance));
        out
    }
}

/// The pairs touching at the last run of [`detect_contacts`].
#[derive(Resource, Default, Debug)]
pub struct Touching(HashSet<(Entity, Entity)>);

/// Finds the contacts of each collider with [`ContactEvents`] and sends
/// [`ContactStarted`] and [`ContactEnded`] as pairs begin and stop
/// touching. Runs after the wrap ([`super::ManifoldSystems::Contacts`]).
pub fn detect_contacts(
    contacts: ManifoldContacts,
    watched: Query<Entity, With<ContactEvents>>,
    mut touching: ResMut<Touching>,
    mut started: MessageWriter<ContactStarted>,
    mut ended: MessageWriter<ContactEnded>,
) {
    let mut now: HashSet<(Entity, Entity)> = HashSet::new();
    for a in &watched {
        for overlap in contacts.touching(a) {
            let b = overlap.entity;
            if b == a {
                continue;
            }
            // Once per pair: the lower entity first when both watch.
            let pair = if watched.contains(b) && b < a { (b, a) } else { (a, b) };
            now.insert(pair);
        }
    }
    let mut begun: Vec<_> = now.difference(&touching.0).copied().collect();
    let mut gone: Vec<_> = touching.0.difference(&now).copied().collect();
    // A stable order, whatever the hash set's.
    begun.sort();
    gone.sort();
    for (a, b) in begun {
        started.write(ContactStarted { a, b });
    }
    for (a, b) in gone {
        ended.write(ContactEnded { a, b });
    }
    touching.0 = now;
}
