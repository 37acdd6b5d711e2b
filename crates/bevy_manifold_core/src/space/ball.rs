//! The cells around one cell, as a table a walk steps through by index:
//! how the GPU tracer knows the exact id of every copy a ray can reach
//! without exact arithmetic of its own (issue #14).
//!
//! The ball is grown once, breadth first, around the origin copy: cell
//! `k` is an exact element `e_k`, and `neighbours[k * faces + f]` the
//! index of `e_k T_f` (or [`OUTSIDE`]), the convention of the finite
//! groups' Cayley table. Around a camera in cell `c` the same table serves
//! unchanged, since `c e_k T_f = (c e_k) T_f`: only the ids change, to
//! those of `c e_k` ([`CellBall::ids_around`]), one exact product per cell.
//!
//! WGSL twin: the `CELLS_TABLE` walk in `bevy_manifold_gpu`'s
//! `shaders/walk.wgsl` (`walker_step`) and `cell_id` in `shaders/cells.wgsl`.
//!
//! ```
//! use bevy_manifold_core::space::{ball::CellBall, catalog, cells::CellScheme};
//! let sw = catalog::seifert_weber();
//! let CellScheme::Exact(exact) = sw.cells() else { unreachable!() };
//! let ball = CellBall::grow(&exact.group, 2000);
//! // The origin copy and its 12 neighbours come first.
//! assert!(ball.len() >= 13 && ball.len() <= 2000);
//! let ids = ball.ids_around(&exact.group, &exact.group.identity());
//! assert_eq!(ids[0].0, 0);
//! ```

use super::cells::CellId;
use super::exact::{ExactElement, ExactGroup};
use std::collections::HashMap;
use std::collections::hash_map::Entry;

/// A neighbour not in the table.
pub const OUTSIDE: u32 = u32::MAX;

/// Cells of the GPU's table by default: about 2.5 MiB of neighbours and ids
/// for a 12-face space (the ball of radius 5 in Seifert-Weber, most of
/// radius 6 in the mirrored dodecahedron).
pub const DEFAULT_BALL_CELLS: usize = 1 << 16;

/// The cells around the origin copy, breadth first.
#[derive(Clone, Debug)]
pub struct CellBall {
    elements: Vec<ExactElement>,
    /// `[k * faces + f]`: the index of `e_k T_f`, or [`OUTSIDE`].
    pub neighbours: Vec<u32>,
    /// Crossings from the origin copy to each cell (its word length).
    pub depth: Vec<u16>,
    faces: usize,
}

impl CellBall {
    /// Grows the ball breadth first up to `budget` cells (whole spheres of
    /// crossings only, so the table holds every cell within its radius).
    #[must_use]
    pub fn grow(group: &ExactGroup, budget: usize) -> Self {
        let n = group.faces();
        let mut elements = vec![group.identity()];
        let mut depth = vec![0u16];
        // Keyed by the 62-bit id and checked against the element, so a
        // lookup hashes one column, not the matrix. Two cells with one id
        // (never seen; odds about n^2 / 2^63) keep the first, the second
        // stays outside the table.
        let mut index: HashMap<CellId, u32> = HashMap::from([(CellId(0), 0)]);
        // By T_f: the crossing of f's partner.
        let pairing_face: Vec<usize> = (0..n).map(|f| group.partner(f)).collect();
        let mut sphere = 0..1usize;
        loop {
            let start = elements.len();
            let d = depth[sphere.start] + 1;
            for k in sphere.clone() {
                for &f in &pairing_face {
                    let Ok(e) = group.cross(&elements[k], f) else { continue };
                    if let Entry::Vacant(slot) = index.entry(e.cell_id()) {
                        slot.insert(elements.len() as u32);
                        elements.push(e);
                        depth.push(d);
                    }
                }
            }
            if elements.len() == start {
                break;
            }
            if elements.len() > budget {
                // Whole spheres only: drop the one that did not fit.
                for e in &elements[start..] {
                    index.remove(&e.cell_id());
                }
                elements.truncate(start);
                depth.truncate(start);
                break;
            }
            sphere = start..elements.len();
        }
        let mut neighbours = vec![OUTSIDE; elements.len() * n];
        for (k, e) in elements.iter().enumerate() {
            for (t, &f) in pairing_face.iter().enumerate() {
                if let Ok(next) = group.cross(e, f)
                    && let Some(&i) = index.get(&next.cell_id())
                    && elements[i as usize] == next
                {
                    neighbours[k * n + t] = i;
                }
            }
        }
        CellBall {
            elements,
            neighbours,
            depth,
            faces: n,
        }
    }

    /// Cells in the table.
    #[must_use]
    pub fn len(&self) -> usize {
        self.elements.len()
    }

    /// Never empty (the origin copy is cell 0).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.elements.is_empty()
    }

    /// Faces per cell.
    #[must_use]
    pub fn faces(&self) -> usize {
        self.faces
    }

    /// The largest number of crossings from the centre to a cell in it.
    #[must_use]
    pub fn radius(&self) -> u16 {
        self.depth.last().copied().unwrap_or(0)
    }

    /// The ids of the cells around `centre`: `ids[k]` is the id of
    /// `centre e_k` (far-flagged where the arithmetic ran out).
    #[must_use]
    pub fn ids_around(&self, group: &ExactGroup, centre: &ExactElement) -> Vec<CellId> {
        self.elements
            .iter()
            .map(|e| {
                group
                    .compose(centre, e)
                    .map_or(CellId(CellId::FAR | 1), |g| g.cell_id())
            })
            .collect()
    }
}
