//! The copies of the domain near it in the cover: the group elements `g`
//! whose cell `g(D)` has its centre `g o` within a distance of the
//! domain's centre `o`, nearest first ([`Space::cover_within`]). The
//! images of a light are made from them ([`crate::trace::light_images`]).
//!
//! Found by a walk over the cells across their faces, nearest first:
//! every cell whose centre lies within `r` of `o` is reached through
//! cells that come within `r` of `o` (the geodesic from `o` to its
//! centre passes through them), so the walk goes on from a cell only
//! when it may come that near (by [`Space::distance_outside`], a lower
//! bound), and keeps the cells whose centres lie within `r`. Two paths
//! to the same cell are told apart by its centre: distinct cells'
//! centres lie at least twice the inradius apart.

use super::Space;
use crate::geometry::{isometry, plane};
use glam::{DMat4, DVec4};
use std::cmp::Ordering;
use std::collections::{BinaryHeap, HashMap};
use std::sync::{Arc, Mutex};

/// Most elements a cover walk keeps: in H3 their number grows like
/// `e^{2r}`, and past this the walk stops and says how far it is complete
/// ([`Cover::complete_to`]).
pub const MAX_COVER_ELEMENTS: usize = 40_000;

/// The group elements whose cells lie near the domain.
#[derive(Clone, Debug, Default)]
pub struct Cover {
    /// `(g, d(o, g o))`, nearest first; the identity first.
    pub elements: Vec<(DMat4, f64)>,
    /// Every element with `d(o, g o) <= complete_to` is in `elements`.
    pub complete_to: f64,
}

/// What a [`Space`] keeps of its last cover walk, shared by its clones.
#[derive(Clone, Debug, Default)]
pub struct CoverCache(Arc<Mutex<Option<Arc<Cover>>>>);

/// A cell on the walk's frontier, nearest first in the heap.
struct Frontier(f64, DMat4);

impl PartialEq for Frontier {
    fn eq(&self, other: &Self) -> bool {
        self.0 == other.0
    }
}
impl Eq for Frontier {}
impl PartialOrd for Frontier {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Frontier {
    fn cmp(&self, other: &Self) -> Ordering {
        other.0.total_cmp(&self.0)
    }
}

impl Space {
    /// The group elements `g` with `d(o, g o) <= radius` (`o` the chart
    /// origin, the domain's centre), nearest first, or as many as
    /// [`MAX_COVER_ELEMENTS`] allows ([`Cover::complete_to`] says how far
    /// the list is whole). Kept between calls: a smaller radius reuses
    /// the last walk.
    ///
    /// ```
    /// use bevy_manifold_core::space::catalog;
    /// // The cube of edge 1: its 6 face neighbours at distance 1, then
    /// // 12 edge neighbours at sqrt 2.
    /// let cover = catalog::torus(1.0).cover_within(1.2);
    /// assert_eq!(cover.elements.len(), 7);
    /// // The Poincare sphere: its group has 120 elements.
    /// let all = catalog::poincare().cover_within(4.0);
    /// assert_eq!(all.elements.len(), 120);
    /// ```
    #[must_use]
    pub fn cover_within(&self, radius: f64) -> Arc<Cover> {
        let radius = radius.max(0.0);
        let mut kept = self.cover.0.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some(c) = kept.as_ref()
            && (c.complete_to >= radius || c.elements.len() >= MAX_COVER_ELEMENTS)
        {
            let n = c.elements.partition_point(|e| e.1 <= radius);
            return Arc::new(Cover {
                elements: c.elements[..n].to_vec(),
                complete_to: c.complete_to.min(radius),
            });
        }
        let cover = Arc::new(self.walk_cover(radius));
        *kept = Some(cover.clone());
        cover
    }

    /// The walk behind [`Space::cover_within`].
    fn walk_cover(&self, radius: f64) -> Cover {
        let g = self.geometry;
        let o = DVec4::W;
        let reach = radius + 1e-9;
        // Centres closer than this are the same cell reached twice.
        let same = (self.inradius * 0.5).max(1e-9);
        let quantum = self.inradius.max(1e-6);
        let mut seen: HashMap<[i64; 4], Vec<DVec4>> = HashMap::new();
        let key = |c: DVec4| (c / quantum).to_array().map(|x| x.floor() as i64);
        // Every key a centre within `same` of `c` may have been filed under.
        let keys_near = |c: DVec4| {
            let lo = key(c - DVec4::splat(same));
            let hi = key(c + DVec4::splat(same));
            let mut out = Vec::with_capacity(16);
            for a in lo[0]..=hi[0] {
                for b in lo[1]..=hi[1] {
                    for cc in lo[2]..=hi[2] {
                        for d in lo[3]..=hi[3] {
                            out.push([a, b, cc, d]);
                        }
                    }
                }
            }
            out
        };
        let mut heap = BinaryHeap::new();
        heap.push(Frontier(0.0, DMat4::IDENTITY));
        seen.entry(key(o)).or_default().push(o);
        let mut elements = Vec::new();
        let mut popped_to = 0.0f64;
        let crossings: Vec<DMat4> = (0..self.faces.len()).map(|f| self.crossing(f)).collect();
        while let Some(Frontier(near, m)) = heap.pop() {
            popped_to = near;
            if elements.len() >= MAX_COVER_ELEMENTS {
                break;
            }
            let d = g.distance::<f64>(o, g.normalize_point::<f64>(m * o));
            if d <= radius {
                elements.push((m, d));
            }
            for t in &crossings {
                let n = m * *t;
                let c = g.normalize_point::<f64>(n * o);
                // How near the cell n(D) may come to o: how far o lies
                // outside D seen from n.
                let near = self.distance_outside(g.normalize_point::<f64>(isometry::inverse(g, n) * o));
                if near.is_nan() || near > reach || !c.is_finite() {
                    continue;
                }
                let known = keys_near(c)
                    .iter()
                    .filter_map(|k| seen.get(k))
                    .flatten()
                    .any(|p| (*p - c).length() < same);
                if known {
                    continue;
                }
                seen.entry(key(c)).or_default().push(c);
                heap.push(Frontier(near, n));
            }
        }
        let complete_to = if heap.is_empty() && elements.len() < MAX_COVER_ELEMENTS {
            radius
        } else {
            popped_to.clamp(0.0, radius)
        };
        elements.sort_by(|a, b| a.1.total_cmp(&b.1));
        Cover { elements, complete_to }
    }

    /// A lower bound on the distance from the domain to the point `p`:
    /// how far it lies beyond the farthest face plane it is outside of (0
    /// inside). Exact where the nearest point of the domain is inside a
    /// face.
    #[must_use]
    pub fn distance_outside(&self, p: DVec4) -> f64 {
        self.faces
            .iter()
            .map(|f| plane::signed_distance(self.geometry, f.plane, p))
            .fold(0.0, f64::max)
    }
}
