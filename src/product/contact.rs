//! [`ProductContacts`]: which [`ProductBody`]s of a product space touch,
//! through the faces (the core's `trace::product::contact`).

use super::{ProductBody, ProductSpaceRoot};
use bevy::ecs::system::SystemParam;
use bevy::prelude::*;
use bevy_manifold_core::trace::product::ProductBall;
use bevy_manifold_core::trace::product::contact::{self, ProductContact};

/// Contact queries between the [`ProductBody`]s of a product space,
/// through the faces: every image counts, as the tracer draws every image
/// (the core's [`contact::contacts`]).
///
/// ```
/// use bevy::prelude::*;
/// use bevy_manifold::product::ProductContacts;
/// fn bump(contacts: ProductContacts, bodies: Query<Entity, With<bevy_manifold::product::ProductBody>>) {
///     for body in &bodies {
///         for (other, touch) in contacts.touching(body) {
///             info!("{body} touches {other} {} deep", touch[0].depth);
///         }
///     }
/// }
/// # bevy::ecs::system::assert_is_system(bump);
/// ```
#[derive(SystemParam)]
pub struct ProductContacts<'w, 's> {
    roots: Query<'w, 's, (&'static ProductSpaceRoot, &'static Children)>,
    bodies: Query<'w, 's, (&'static ProductBody, &'static ChildOf)>,
}

impl ProductContacts<'_, '_> {
    /// The contacts between the bodies `a` and `b` (one per image of `b`
    /// that overlaps `a`), deepest first. Empty where they do not touch,
    /// are not bodies or live in different spaces.
    #[must_use]
    pub fn contacts(&self, a: Entity, b: Entity) -> Vec<ProductContact> {
        let (Ok((ba, pa)), Ok((bb, pb))) = (self.bodies.get(a), self.bodies.get(b)) else {
            return Vec::new();
        };
        if pa.parent() != pb.parent() {
            return Vec::new();
        }
        let Ok((space, _)) = self.roots.get(pa.parent()) else {
            return Vec::new();
        };
        contact::contacts(&space.0, &ProductBall::from(*ba), &ProductBall::from(*bb))
    }

    /// The other bodies of its space that `entity` touches, through any
    /// image, deepest first, each with its contacts.
    #[must_use]
    pub fn touching(&self, entity: Entity) -> Vec<(Entity, Vec<ProductContact>)> {
        let Ok((_, parent)) = self.bodies.get(entity) else {
            return Vec::new();
        };
        let Ok((_, children)) = self.roots.get(parent.parent()) else {
            return Vec::new();
        };
        let mut out: Vec<(Entity, Vec<ProductContact>)> = children
            .iter()
            .filter(|c| *c != entity)
            .map(|c| (c, self.contacts(entity, c)))
            .filter(|(_, touch)| !touch.is_empty())
            .collect();
        out.sort_by(|x, y| y.1[0].depth.total_cmp(&x.1[0].depth));
        out
    }
}
