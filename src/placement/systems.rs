//! The systems of [`super::PlacementPlugin`], in the order they run.

use super::components::{DomainCell, FaceCrossed, GeodesicVelocity, ManifoldSpace, Placement, WallHit, WrapOrigin};
use super::membership::InSpace;
use crate::geometry::isometry;
use crate::motion::{Moved, advance_placement, chart_position, move_placement};
use crate::space::{FaceKind, Space};
use bevy::prelude::*;

/// Most faces one entity may cross in one step before the nearest-face rule
/// finishes the wrap (a bound, so no motion can stall a frame).
pub const MAX_CROSSINGS_PER_STEP: usize = 4096;

/// The space an entity lives in (its [`InSpace`] root's).
pub(crate) fn space_of<'a>(
    entity: Entity,
    members: &Query<&InSpace>,
    spaces: &'a Query<&ManifoldSpace>,
) -> Option<&'a ManifoldSpace> {
    spaces.get(members.get(entity).ok()?.space()).ok()
}

/// Whether `entity` lives in `space` (the ray casts' and contact queries'
/// filter over every collider).
pub(crate) fn lives_in(
    entity: Entity,
    members: &Query<&InSpace>,
    spaces: &Query<&ManifoldSpace>,
    space: &Space,
) -> bool {
    space_of(entity, members, spaces).is_some_and(|s| core::ptr::eq(s.space(), space))
}

/// Moves entities along geodesics, `M <- M exp(v dt, w dt)`, in
/// sub-steps with a wrap after each (see [`crate::motion::advance_placement`]),
/// so a fast mover crosses faces exactly as a slow one does.
pub fn integrate_velocities(
    time: Res<Time>,
    spaces: Query<&ManifoldSpace>,
    members: Query<&InSpace>,
    mut movers: Query<(
        Entity,
        &mut Placement,
        &GeodesicVelocity,
        &mut DomainCell,
        &mut WrapOrigin,
    )>,
    mut crossed: MessageWriter<FaceCrossed>,
    mut walls: MessageWriter<WallHit>,
) {
    let dt = time.delta_secs_f64();
    if dt <= 0.0 {
        return;
    }
    for (entity, mut placement, velocity, mut cell, mut origin) in &mut movers {
        if velocity.linear == glam::DVec3::ZERO && velocity.angular == glam::DVec3::ZERO {
            continue;
        }
        if !velocity.linear.is_finite() || !velocity.angular.is_finite() {
            warn!("entity {entity}: velocity has NaN or infinite entries; not moved");
            continue;
        }
        let Some(ms) = space_of(entity, &members, &spaces) else {
            continue;
        };
        let (moved, complete) = advance_placement(
            ms.space(),
            ms.tables(),
            placement.isometry,
            velocity.linear,
            velocity.angular,
            dt,
        );
        if !complete {
            warn!(
                "entity {entity}: moving {:.3e} in one step; cut short",
                velocity.linear.length() * dt
            );
        }
        if let Some(hit) = wall_on_the_way(ms, entity, &moved, &cell) {
            walls.write(hit);
            continue;
        }
        apply_crossings(ms, entity, &moved, &mut placement, &mut cell, &mut crossed);
        origin.0 = Some(placement.isometry);
    }
}

/// The first wall of the space's rule on a motion's faces, if any.
fn wall_on_the_way(ms: &ManifoldSpace, entity: Entity, moved: &Moved, cell: &DomainCell) -> Option<WallHit> {
    let rule = ms.rule();
    rule.walls?;
    let space = ms.space();
    let mut c = cell.cell.clone();
    for &face in &moved.faces {
        let next = space.cross_cell(&c, face);
        let id = space.cell_id_of(&c);
        if rule.wall(id, space.cell_id_of(&next)) {
            return Some(WallHit { entity, face, cell: id });
        }
        c = next;
    }
    None
}

/// Carries entities whose placement game code set outside the domain back
/// through the faces on the way there (the chord from where the wrap last
/// left them), updating their cell and parity, re-orthonormalising, and
/// sending [`FaceCrossed`] for each face. Movers were wrapped already.
pub fn wrap_placements(
    spaces: Query<&ManifoldSpace>,
    members: Query<&InSpace>,
    mut entities: Query<(Entity, &mut Placement, &mut DomainCell, &mut WrapOrigin)>,
    mut crossed: MessageWriter<FaceCrossed>,
    mut walls: MessageWriter<WallHit>,
) {
    for (entity, mut placement, mut cell, mut origin) in &mut entities {
        if origin.0 == Some(placement.isometry) {
            continue;
        }
        let Some(ms) = space_of(entity, &members, &spaces) else {
            continue;
        };
        if !placement.isometry.is_finite() {
            // Keep what the user had; refuse to spread NaN into the cell.
            warn!("entity {entity}: placement has NaN or infinite entries; left where it was");
            if let Some(prev) = origin.0 {
                placement.isometry = prev;
            }
            continue;
        }
        // A new entity starts its chord at the domain's origin.
        let from = origin.0.unwrap_or(glam::DMat4::IDENTITY);
        let moved = move_placement(
            ms.space(),
            ms.tables(),
            from,
            placement.isometry,
            MAX_CROSSINGS_PER_STEP,
        );
        if let Some(hit) = wall_on_the_way(ms, entity, &moved, &cell) {
            // Back to where the wrap last left it.
            walls.write(hit);
            placement.isometry = from;
            origin.0 = Some(from);
            continue;
        }
        apply_crossings(ms, entity, &moved, &mut placement, &mut cell, &mut crossed);
        origin.0 = Some(placement.isometry);
    }
}

/// Writes a motion's result into the entity: placement, parity, cell, and
/// one [`FaceCrossed`] per face.
fn apply_crossings(
    ms: &ManifoldSpace,
    entity: Entity,
    moved: &Moved,
    placement: &mut Placement,
    cell: &mut DomainCell,
    crossed: &mut MessageWriter<FaceCrossed>,
) {
    let space = ms.space();
    for &face in &moved.faces {
        let old_cell = cell.id;
        *cell = DomainCell::new(space, space.cross_cell(&cell.cell, face));
        if space.faces()[face].kind == FaceKind::Mirror {
            placement.mirrored = !placement.mirrored;
        }
        crossed.write(FaceCrossed {
            entity,
            face,
            old_cell,
            new_cell: cell.id,
        });
    }
    placement.isometry = moved.placement;
}

/// Writes each moved entity's chart position and orientation into its
/// `Transform`, so Bevy code that reads `Transform` sees a sensible place.
/// A mirrored entity gets a negative x scale (its size is kept). Entities
/// whose `Transform` a tracker writes ([`super::TrackedPose`]) are left alone.
#[expect(clippy::type_complexity, reason = "a system's query")]
pub fn sync_transforms(
    spaces: Query<&ManifoldSpace>,
    members: Query<&InSpace>,
    mut entities: Query<(Entity, &Placement, &mut Transform), (Changed<Placement>, Without<super::TrackedPose>)>,
) {
    for (entity, placement, mut transform) in &mut entities {
        let Some(ms) = space_of(entity, &members, &spaces) else {
            continue;
        };
        let g = ms.space().geometry();
        let m = placement.isometry;
        // The frame, carried back to the origin along the geodesic: a
        // rotation (or a reflection for a mirrored entity).
        let back = isometry::inverse(g, isometry::translation_to(g, m.w_axis)) * m;
        let mut r = glam::DMat3::from_mat4(back);
        let reflected = r.determinant() < 0.0;
        if reflected {
            r.x_axis = -r.x_axis;
        }
        transform.translation = chart_position(&m).as_vec3();
        transform.rotation = Quat::from_mat3(&r.as_mat3()).normalize();
        let sx = transform.scale.x.abs();
        transform.scale.x = if reflected { -sx } else { sx };
    }
}
