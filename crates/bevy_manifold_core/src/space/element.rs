//! The copy of the domain a walk is in, followed across faces as exactly
//! as the space's cell scheme allows: what `DomainCell`, the gameplay ray
//! casts and the CPU tracer carry, so their ids agree at any distance.
//!
//! - In spaces with exact ids ([`CellScheme::Exact`]), the exact golden
//!   element ([`super::exact`]);
//! - in finite groups, the element's index (its Cayley table gives the
//!   step);
//! - otherwise the `f64` matrix: lattices stay exact to rounding (their
//!   entries are multiples of the box's edges), hashed schemes are the
//!   best effort described in [`super::cells`].
//!
//! ```
//! use bevy_manifold_core::space::catalog;
//! let sw = catalog::seifert_weber();
//! let there = sw.cell_of_word(&[0, 5, 7]);
//! let back = sw.cross_cell(&there, 1);
//! assert_ne!(sw.cell_id_of(&there), sw.cell_id_of(&back));
//! // The same copy from two words: a face, then back through its partner.
//! let p = sw.faces()[2].partner;
//! assert_eq!(sw.cell_id_of(&sw.cell_of_word(&[2, p])), sw.cell_id_of(&sw.origin_cell()));
//! ```

use super::Space;
use super::cells::{CellId, CellScheme, HASHED_HORIZON};
use super::exact::ExactElement;
use crate::geometry::isometry;
use glam::DMat4;

/// The group element of one copy of the domain, as exactly as the space's
/// scheme names it.
#[derive(Clone, Debug, PartialEq)]
pub enum CellElement {
    /// The `f64` matrix (lattices, hashed schemes, and an exact element
    /// that left the reach of exact arithmetic).
    Float(DMat4),
    /// The index of a finite group's element.
    Finite(u32),
    /// The exact element.
    Exact(ExactElement),
}

impl Default for CellElement {
    fn default() -> Self {
        CellElement::Float(DMat4::IDENTITY)
    }
}

impl Space {
    /// The origin copy's element.
    #[must_use]
    pub fn origin_cell(&self) -> CellElement {
        match self.cells() {
            CellScheme::Finite { .. } => CellElement::Finite(0),
            CellScheme::Exact(e) => CellElement::Exact(e.group.identity()),
            _ => CellElement::Float(DMat4::IDENTITY),
        }
    }

    /// The element after crossing face `face` from `cell`: `g T_face^-1`.
    /// An exact element that leaves `i128` becomes a `Float` one.
    ///
    /// # Panics
    /// When `face` is not a face of the space.
    #[must_use]
    pub fn cross_cell(&self, cell: &CellElement, face: usize) -> CellElement {
        // An f64 element where the scheme is exact (a default, or one
        // placed by hand) is located first, while f64 can locate it.
        if let (CellElement::Float(m), CellScheme::Exact(_) | CellScheme::Finite { .. }) = (cell, self.cells())
            && m.is_finite()
            && m.w_axis.w.abs() < HASHED_HORIZON
        {
            let located = self.cell_of_matrix(m);
            if !matches!(located, CellElement::Float(_)) {
                return self.cross_cell(&located, face);
            }
        }
        match (cell, self.cells()) {
            // The table steps by T_f; crossing multiplies by T_partner.
            (CellElement::Finite(k), CellScheme::Finite { table, .. }) => {
                CellElement::Finite(table[*k as usize][self.faces()[face].partner])
            }
            (CellElement::Exact(g), CellScheme::Exact(e)) => match e.group.cross(g, face) {
                Ok(next) => CellElement::Exact(next),
                Err(_) => CellElement::Float(self.cell_matrix(cell) * self.crossing(face)),
            },
            _ => {
                let m = self.cell_matrix(cell) * self.crossing(face);
                // Re-orthonormalising a huge H3 element does more harm
                // than good (its form has cancelled to noise).
                CellElement::Float(if m.is_finite() && m.w_axis.w.abs() < HASHED_HORIZON {
                    isometry::orthonormalize(self.geometry(), m)
                } else {
                    m
                })
            }
        }
    }

    /// The element the crossings `faces` reach from the origin copy.
    ///
    /// # Panics
    /// When a face is not a face of the space.
    #[must_use]
    pub fn cell_of_word(&self, faces: &[usize]) -> CellElement {
        faces.iter().fold(self.origin_cell(), |c, &f| self.cross_cell(&c, f))
    }

    /// The product `a b`: the copy `b` names seen from the copy `a` names
    /// (a camera in cell `a` with a placement that wraps into cell `b`
    /// of its own frame is in cell `a b`).
    #[must_use]
    pub fn compose_cells(&self, a: &CellElement, b: &CellElement) -> CellElement {
        match (a, b, self.cells()) {
            (CellElement::Exact(x), CellElement::Exact(y), CellScheme::Exact(e)) => match e.group.compose(x, y) {
                Ok(g) => CellElement::Exact(g),
                Err(_) => CellElement::Float(self.cell_matrix(a) * self.cell_matrix(b)),
            },
            (a, b, _) => self.cell_of_matrix(&(self.cell_matrix(a) * self.cell_matrix(b))),
        }
    }

    /// The element as an `f64` matrix (rounded for exact elements).
    #[must_use]
    pub fn cell_matrix(&self, cell: &CellElement) -> DMat4 {
        match (cell, self.cells()) {
            (CellElement::Float(m), _) => *m,
            (CellElement::Finite(k), CellScheme::Finite { elements, .. }) => elements[*k as usize],
            (CellElement::Exact(g), CellScheme::Exact(e)) => e.group.to_f64(g),
            // An element of another space: the origin.
            _ => DMat4::IDENTITY,
        }
    }

    /// The element of the copy an `f64` element `g` names: exact when the
    /// scheme is and `g` is known to within the inradius.
    #[must_use]
    pub fn cell_of_matrix(&self, g: &DMat4) -> CellElement {
        match self.cells() {
            CellScheme::Finite { .. } => CellElement::Finite(self.cell_id(g).0 as u32),
            CellScheme::Exact(e) => e.locate(g).map_or(CellElement::Float(*g), CellElement::Exact),
            _ => CellElement::Float(*g),
        }
    }

    /// The path-independent id of the copy.
    #[must_use]
    pub fn cell_id_of(&self, cell: &CellElement) -> CellId {
        match (cell, self.cells()) {
            (CellElement::Finite(k), CellScheme::Finite { .. }) => CellId(u64::from(*k)),
            (CellElement::Exact(g), CellScheme::Exact(_)) => g.cell_id(),
            // Located while f64 can (a default or hand-placed element),
            // flagged far beyond the horizon (and past exact arithmetic).
            (CellElement::Float(m), CellScheme::Exact(_)) => self.cell_id(m),
            (cell, _) => self.cell_id(&self.cell_matrix(cell)),
        }
    }
}
