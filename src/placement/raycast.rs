//! [`ManifoldRayCast`]: geodesic ray casts for gameplay (hits, line of
//! sight), through the face pairings like light.

use super::components::{DomainCell, ManifoldCollider, ManifoldSpace, Placement};
use super::membership::InSpace;
use super::systems::{lives_in, space_of};
use crate::space::cells::CellId;
use crate::trace::step::Ray;
use crate::trace::{CastBall, CastHit, CastWall, cast_with_rule};
use bevy::ecs::system::SystemParam;
use bevy::prelude::*;
use glam::{DMat4, DVec3, DVec4};

/// How far a cast goes and what it ignores.
#[derive(Clone, Debug, PartialEq)]
pub struct RayCastSettings {
    /// Stop after this distance.
    pub max_distance: f64,
    /// Stop after crossing this many faces.
    pub levels: u32,
    /// An entity not to hit (usually the caster).
    pub exclude: Option<Entity>,
}

impl Default for RayCastSettings {
    fn default() -> Self {
        RayCastSettings {
            max_distance: 100.0,
            levels: 32,
            exclude: None,
        }
    }
}

/// One hit, in the order of distance.
#[derive(Clone, Debug, PartialEq)]
pub struct RayHit {
    /// The entity hit.
    pub entity: Entity,
    /// Distance along the ray.
    pub distance: f64,
    /// The hit point, in the domain's chart.
    pub point: DVec4,
    /// The faces the ray crossed before the hit.
    pub faces: Vec<usize>,
    /// The copy of the domain the hit is in (absolute: the caster's cell
    /// times the crossings).
    pub cell: CellId,
    /// The group element of that copy.
    pub element: DMat4,
}

/// Casts geodesic rays through the manifold against entities with a
/// [`ManifoldCollider`].
///
/// ```
/// use bevy::prelude::*;
/// use bevy_manifold::prelude::*;
/// fn shoot(cast: ManifoldRayCast, players: Query<Entity, With<GeodesicVelocity>>) {
///     for player in &players {
///         let settings = RayCastSettings { exclude: Some(player), ..default() };
///         if let Some(hit) = cast.cast(player, glam::DVec3::NEG_Z, &settings).first() {
///             info!("hit {} at {:.2} after {} faces", hit.entity, hit.distance, hit.faces.len());
///         }
///     }
/// }
/// # bevy::ecs::system::assert_is_system(shoot);
/// ```
#[derive(SystemParam)]
pub struct ManifoldRayCast<'w, 's> {
    spaces: Query<'w, 's, &'static ManifoldSpace>,
    members: Query<'w, 's, &'static InSpace>,
    placed: Query<'w, 's, (&'static Placement, Option<&'static DomainCell>)>,
    colliders: Query<'w, 's, (Entity, &'static Placement, &'static ManifoldCollider)>,
}

impl ManifoldRayCast<'_, '_> {
    /// Casts from the entity `from` in the direction `direction` of its own
    /// frame (`DVec3::NEG_Z` is straight ahead), against the colliders in
    /// the same space. Every hit, nearest first; empty when `from` has no
    /// placement or no space.
    #[must_use]
    pub fn cast(&self, from: Entity, direction: DVec3, settings: &RayCastSettings) -> Vec<RayHit> {
        let Ok((placement, cell)) = self.placed.get(from) else {
            return Vec::new();
        };
        let Some(ms) = space_of(from, &self.members, &self.spaces) else {
            return Vec::new();
        };
        let cell = cell.cloned().unwrap_or_default();
        self.cast_in(ms, placement, &cell, direction, 0.0, settings)
    }

    /// A shape cast: `shape` swept from the entity `from` along the
    /// geodesic in the direction `direction` of its frame, against the
    /// colliders of its space, through the faces. A ball of radius `r`
    /// first touches a ball of radius `R` when its centre comes within
    /// `r + R` of the other's, in any geometry, so this is the ray cast
    /// against every collider grown by `r`: each hit's `distance` is how
    /// far the shape travelled before touching and its `point` where the
    /// shape's centre then is. Every hit, nearest first.
    ///
    /// ```
    /// use bevy::prelude::*;
    /// use bevy_manifold::prelude::*;
    /// fn dash(cast: ManifoldRayCast, players: Query<Entity, With<GeodesicVelocity>>) {
    ///     for player in &players {
    ///         let settings = RayCastSettings { max_distance: 2.0, exclude: Some(player), ..default() };
    ///         let shape = ManifoldCollider::Ball { radius: 0.1 };
    ///         if let Some(hit) = cast.shape_cast(player, shape, glam::DVec3::NEG_Z, &settings).first() {
    ///             info!("blocked by {} after {:.2}", hit.entity, hit.distance);
    ///         }
    ///     }
    /// }
    /// # bevy::ecs::system::assert_is_system(dash);
    /// ```
    #[must_use]
    pub fn shape_cast(
        &self,
        from: Entity,
        shape: ManifoldCollider,
        direction: DVec3,
        settings: &RayCastSettings,
    ) -> Vec<RayHit> {
        let Ok((placement, cell)) = self.placed.get(from) else {
            return Vec::new();
        };
        let Some(ms) = space_of(from, &self.members, &self.spaces) else {
            return Vec::new();
        };
        let radius = shape.radius();
        if !(radius.is_finite() && radius >= 0.0) {
            return Vec::new();
        }
        let cell = cell.cloned().unwrap_or_default();
        self.cast_in(ms, placement, &cell, direction, radius, settings)
    }

    /// The wall of the space's rule ([`ManifoldSpace::with_rule`]) that
    /// stops a cast from `from` in `direction`, if one does within the
    /// settings' reach ([`ManifoldRayCast::cast`] returns only the hits
    /// before it).
    #[must_use]
    pub fn wall(&self, from: Entity, direction: DVec3, settings: &RayCastSettings) -> Option<CastWall> {
        let (placement, cell) = self.placed.get(from).ok()?;
        let ms = space_of(from, &self.members, &self.spaces)?;
        let cell = cell.cloned().unwrap_or_default();
        self.cast_raw(ms, placement, &cell, direction, 0.0, settings).1
    }

    fn cast_raw(
        &self,
        ms: &ManifoldSpace,
        placement: &Placement,
        cell: &DomainCell,
        direction: DVec3,
        grow: f64,
        settings: &RayCastSettings,
    ) -> (Vec<CastHit<Entity>>, Option<CastWall>) {
        let space = ms.space();
        let g = space.geometry();
        if direction.length_squared() == 0.0 || !direction.is_finite() {
            return (Vec::new(), None);
        }
        let o = g.normalize_point::<f64>(placement.isometry.w_axis);
        let d = g.normalize_tangent::<f64>(o, placement.isometry * direction.normalize().extend(0.0));
        let balls: Vec<CastBall<Entity>> = self
            .colliders
            .iter()
            .filter(|(e, ..)| Some(*e) != settings.exclude)
            .filter(|(e, ..)| lives_in(*e, &self.members, &self.spaces, space))
            .map(|(e, p, c)| CastBall {
                key: e,
                center: p.isometry.w_axis,
                radius: c.radius() + grow,
            })
            .collect();
        cast_with_rule(
            space,
            ms.tables(),
            Ray { origin: o, dir: d },
            &balls,
            settings.max_distance,
            settings.levels,
            &cell.cell,
            ms.rule(),
        )
    }

    fn cast_in(
        &self,
        ms: &ManifoldSpace,
        placement: &Placement,
        cell: &DomainCell,
        direction: DVec3,
        grow: f64,
        settings: &RayCastSettings,
    ) -> Vec<RayHit> {
        let space = ms.space();
        let (hits, _) = self.cast_raw(ms, placement, cell, direction, grow, settings);
        hits.into_iter()
            .map(|h| {
                // The hit's cell seen from the caster's: exact where the
                // space's ids are (the ray's own element is short).
                let hit_cell = space.compose_cells(&cell.cell, &space.cell_of_matrix(&h.element));
                RayHit {
                    entity: h.key,
                    distance: h.distance,
                    point: h.point,
                    faces: h.faces,
                    cell: space.cell_id_of(&hit_cell),
                    element: cell.element * h.element,
                }
            })
            .collect()
    }
}
