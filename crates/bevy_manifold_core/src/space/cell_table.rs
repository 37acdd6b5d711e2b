//! The cells around one cell, as a table a walk steps through by index:
//! how the GPU tracer knows the exact id of every copy a ray can reach
//! without exact arithmetic of its own, and how the CPU
//! tracer's rays cross faces near the camera without it
//! ([`CentredTable`]).
//!
//! The table is grown once, breadth first, around the origin copy: cell
//! `k` is an exact element `e_k`, and `neighbours[k * faces + f]` the
//! index of `e_k T_f` (or [`OUTSIDE`]), the convention of the finite
//! groups' Cayley table. Around a camera in cell `c` the same table serves
//! unchanged, since `c e_k T_f = (c e_k) T_f`: only the ids change, to
//! those of `c e_k` ([`CellTable::ids_around`]), one exact product per cell.
//!
//! WGSL twin: the `CELLS_TABLE` walk in `bevy_manifold_gpu`'s
//! `shaders/walk.wgsl` (`walker_step`) and `cell_id` in `shaders/cells.wgsl`.
//!
//! ```
//! use bevy_manifold_core::space::{cell_table::CellTable, catalog, cells::CellScheme};
//! let sw = catalog::seifert_weber();
//! let CellScheme::Exact(exact) = sw.cells() else { unreachable!() };
//! let table = CellTable::grow(&exact.group, 2000);
//! // The origin copy and its 12 neighbours come first.
//! assert!(table.len() >= 13 && table.len() <= 2000);
//! let ids = table.ids_around(&exact.group, &exact.group.identity());
//! assert_eq!(ids[0].0, 0);
//! ```

use super::cell_id::CellId;
use super::exact::{ExactElement, ExactGroup, TooFar};
use std::collections::HashMap;
use std::collections::hash_map::Entry;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

/// A neighbour not in the table.
pub const OUTSIDE: u32 = u32::MAX;

/// Cells of the table by default, at most: about 3.5 MiB of neighbours
/// and ids for a 12-face space. Whole spheres of crossings only, so
/// Seifert-Weber's table holds 16,129 cells (radius 4) and the mirrored
/// dodecahedron's 57,741 (radius 5).
pub const DEFAULT_TABLE_CELLS: usize = 1 << 16;

/// The cells around the origin copy, breadth first.
#[derive(Clone, Debug)]
pub struct CellTable {
    elements: Vec<ExactElement>,
    /// `[k * faces + f]`: the index of `e_k T_f`, or [`OUTSIDE`].
    pub neighbours: Vec<u32>,
    /// Crossings from the origin copy to each cell (its word length).
    pub depth: Vec<u16>,
    faces: usize,
}

impl CellTable {
    /// Grows the table breadth first up to `budget` cells (whole spheres of
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
        CellTable {
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
        self.elements.iter().map(|e| id_around(group, centre, e)).collect()
    }

    /// The index of `e_k T_t`, the cell across face `t`'s partner from
    /// cell `k` (crossing a face multiplies by its partner's pairing), or
    /// [`OUTSIDE`]. WGSL twin: `walker_step`'s `CELLS_TABLE` step in
    /// `shaders/walk.wgsl`.
    ///
    /// # Panics
    /// When `k` is not a cell of the table or `t` not a face.
    #[must_use]
    pub fn neighbour(&self, k: u32, t: usize) -> u32 {
        assert!(t < self.faces, "face {t} of a table of {} faces", self.faces);
        self.neighbours[k as usize * self.faces + t]
    }

    /// Cell `k`'s element `e_k`.
    ///
    /// # Panics
    /// When `k` is not a cell of the table.
    #[must_use]
    pub fn element(&self, k: u32) -> &ExactElement {
        &self.elements[k as usize]
    }
}

/// The id of `centre e`, far-flagged where the arithmetic runs out.
fn id_around(group: &ExactGroup, centre: &ExactElement, e: &ExactElement) -> CellId {
    group
        .compose(centre, e)
        .map_or(CellId(CellId::FAR | 1), |g| g.cell_id())
}

/// A [`CellTable`] centred on one copy `c` (a camera's), as the CPU tracer
/// walks it: cell `k` is `c e_k`, and its id is made on first ask (one
/// exact product) and kept, so a frame pays for the cells its rays reach,
/// not for the whole table ([`CellTable::ids_around`], what the GPU is
/// sent). A ray steps through the table by index ([`CellTable::neighbour`])
/// with no exact arithmetic until it leaves it.
///
/// ```
/// use bevy_manifold_core::space::cell_table::{CellTable, CentredTable};
/// use bevy_manifold_core::space::{catalog, cells::CellScheme};
/// use std::sync::Arc;
/// let sw = catalog::seifert_weber();
/// let CellScheme::Exact(exact) = sw.cells() else { unreachable!() };
/// let g = &exact.group;
/// let table = Arc::new(CellTable::grow(g, 2000));
/// let centre = g.element(&[3, 5]).unwrap();
/// let around = CentredTable::new(table.clone(), centre.clone());
/// // Across face 7 from the centre (by the pairing of 7's partner):
/// let k = table.neighbour(0, g.partner(7));
/// assert_eq!(around.id(g, k), g.cross(&centre, 7).unwrap().cell_id());
/// ```
#[derive(Debug)]
pub struct CentredTable {
    table: Arc<CellTable>,
    centre: ExactElement,
    /// Per cell its id's value, or [`NOT_MADE`].
    ids: Vec<AtomicU64>,
}

/// An id not made yet: no exact id has the lattice bit set.
const NOT_MADE: u64 = u64::MAX;

impl CentredTable {
    /// The table `table` around the copy `centre` names.
    #[must_use]
    pub fn new(table: Arc<CellTable>, centre: ExactElement) -> Self {
        let ids = (0..table.len()).map(|_| AtomicU64::new(NOT_MADE)).collect();
        CentredTable { table, centre, ids }
    }

    /// The table.
    #[must_use]
    pub fn table(&self) -> &CellTable {
        &self.table
    }

    /// The copy at the table's centre.
    #[must_use]
    pub fn centre(&self) -> &ExactElement {
        &self.centre
    }

    /// The id of cell `k`, `centre e_k`: made on the first ask, from any
    /// thread (two threads asking at once both make the same id).
    ///
    /// # Panics
    /// When `k` is not a cell of the table.
    #[must_use]
    pub fn id(&self, group: &ExactGroup, k: u32) -> CellId {
        let slot = &self.ids[k as usize];
        match slot.load(Ordering::Relaxed) {
            NOT_MADE => {
                let id = id_around(group, &self.centre, self.table.element(k));
                slot.store(id.0, Ordering::Relaxed);
                id
            }
            made => CellId(made),
        }
    }

    /// How many cells' ids have been made so far ([`CentredTable::id`]):
    /// the cells the rays traced with this table reached.
    #[must_use]
    pub fn made(&self) -> usize {
        self.ids
            .iter()
            .filter(|id| id.load(Ordering::Relaxed) != NOT_MADE)
            .count()
    }

    /// Cell `k`'s element, `centre e_k`: where a ray leaving the table
    /// goes on by exact products.
    ///
    /// # Errors
    /// [`TooFar`] past the exact arithmetic's reach.
    pub fn element(&self, group: &ExactGroup, k: u32) -> Result<ExactElement, TooFar> {
        group.compose(&self.centre, self.table.element(k))
    }
}
