//! Gameplay ray casts: one ray through the manifold against balls, with
//! every hit on the way (the same ball can be hit again in another copy),
//! using the tracer's own walk and ball test.

use super::flat::{FaceTables, ghost_centres};
use super::step::{Ray, advance, hit_ball, radius_param};
use super::walk::Walker;
use crate::space::Space;
use crate::space::cells::CellId;
use crate::space::element::CellElement;
use crate::space::rule::CellRule;
use glam::{DMat4, DVec4};

/// A ball to cast against, with a key the caller uses to name it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CastBall<K> {
    /// Whatever names the ball (an `Entity` in the ECS).
    pub key: K,
    /// Centre, a normalised point inside the domain.
    pub center: DVec4,
    /// Radius.
    pub radius: f64,
}

/// One hit of a cast.
#[derive(Clone, Debug, PartialEq)]
pub struct CastHit<K> {
    /// The ball's key.
    pub key: K,
    /// Distance from the ray's origin along the geodesic.
    pub distance: f64,
    /// The hit point, in the domain's chart.
    pub point: DVec4,
    /// The faces the ray crossed before the hit, in order.
    pub faces: Vec<usize>,
    /// The group element of the copy of the domain the hit is in, relative
    /// to the ray's starting copy.
    pub element: DMat4,
}

/// Where a cast met a wall ([`crate::space::rule`]) and stopped.
#[derive(Clone, Debug, PartialEq)]
pub struct CastWall {
    /// Distance from the ray's origin.
    pub distance: f64,
    /// The face that is a wall, in the domain the ray was in.
    pub face: usize,
    /// The point on the wall, in the domain's chart.
    pub point: DVec4,
}

/// Casts `ray` (starting inside the domain) through at most `levels`
/// faces and `max_distance`, returning every ball hit, nearest first.
#[must_use]
pub fn cast_balls<K: Copy>(
    space: &Space,
    tables: &FaceTables<f64>,
    ray: Ray<f64>,
    balls: &[CastBall<K>],
    max_distance: f64,
    levels: u32,
) -> Vec<CastHit<K>> {
    cast_with_rule(
        space,
        tables,
        ray,
        balls,
        max_distance,
        levels,
        &space.origin_cell(),
        &CellRule::default(),
    )
    .0
}

/// [`cast_balls`] under per-cell rules, from a ray starting in cell
/// `start`: balls in cells the rule hides are passed through, and the
/// cast stops at the first wall, which it returns. The rule is decided
/// from the same ids as the tracer's.
#[must_use]
#[expect(clippy::too_many_arguments, reason = "the cast's inputs, all needed")]
pub fn cast_with_rule<K: Copy>(
    space: &Space,
    tables: &FaceTables<f64>,
    ray: Ray<f64>,
    balls: &[CastBall<K>],
    max_distance: f64,
    levels: u32,
    start: &CellElement,
    rule: &CellRule,
) -> (Vec<CastHit<K>>, Option<CastWall>) {
    let g = space.geometry();
    let mut cell = start.clone();
    // A ball that reaches across a face is also tested through it.
    let mut copies: Vec<(K, DVec4, f64)> = Vec::new();
    for b in balls {
        let k = radius_param(g, b.radius);
        copies.extend(
            ghost_centres(space, b.center, b.radius)
                .into_iter()
                .map(|c| (b.key, c, k)),
        );
    }
    let mut hits = Vec::new();
    let mut walk = Walker::new(ray, DMat4::IDENTITY);
    let mut faces = Vec::new();
    let mut travelled = 0.0;
    let max_passes = levels as usize + max_distance.min(1e4) as usize + 2;
    let mut wall = None;
    for _ in 0..max_passes {
        let (face, t_end) = walk.segment_end(tables);
        // Ids only when a rule reads them (an exact product per crossing).
        let active = rule.is_active();
        let id = if active { space.cell_id_of(&cell) } else { CellId(0) };
        let shown = rule.visible(id);
        for &(key, c, k) in copies.iter().filter(|_| shown) {
            if let Some(t) = hit_ball(g, &walk.ray, c, k, 0.0)
                && t <= t_end
            {
                let distance = travelled + g.chart_to_distance::<f64>(t);
                if distance <= max_distance {
                    let point = g.normalize_point::<f64>(walk.ray.origin + walk.ray.dir * t);
                    hits.push(CastHit {
                        key,
                        distance,
                        point,
                        faces: faces.clone(),
                        element: walk.cell,
                    });
                }
            }
        }
        travelled += g.chart_to_distance::<f64>(t_end);
        if travelled >= max_distance {
            break;
        }
        let end = advance(g, &walk.ray, t_end);
        if let Some(f) = face
            && active
        {
            let next = space.cross_cell(&cell, f);
            if rule.wall(id, space.cell_id_of(&next)) {
                wall = Some(CastWall {
                    distance: travelled,
                    face: f,
                    point: end.origin,
                });
                break;
            }
            cell = next;
        }
        if face.is_some() && walk.levels >= levels {
            break;
        }
        walk.step(tables, face, end, true);
        faces.extend(face);
    }
    hits.sort_by(|a, b| a.distance.total_cmp(&b.distance));
    (hits, wall)
}
