//! The copy of the domain a ray is in, as exactly as the space names it,
//! for the ids the CPU tracer gives its pixels and its cell rules read:
//! by index in the table of cells around the camera while the ray is in
//! it ([`FlatScene::centred_table`]: no arithmetic at a crossing), then by
//! exact products ([`Space::cross_cell`]), one per crossing.
//!
//! WGSL twin: the `CELLS_TABLE` index of `Walker` in `bevy_manifold_gpu`'s
//! `shaders/walk.wgsl` (`walker_step`). The GPU stops at the table's edge
//! and shades what lies beyond it neutral grey; the CPU goes on exactly.

use super::flat::FlatScene;
use super::walk::Walker;
use crate::geometry::Real;
use crate::space::Space;
use crate::space::cell_table::{CentredTable, OUTSIDE};
use crate::space::cells::{CellId, CellScheme};
use crate::space::element::CellElement;
use crate::space::exact::ExactGroup;

/// The table of cells around the camera a ray steps through, checked
/// once per ray ([`FlatScene::centred_table`]), with the group its ids
/// are made in.
#[derive(Clone, Copy)]
pub(crate) struct TableRef<'a> {
    around: &'a CentredTable,
    group: &'a ExactGroup,
}

impl<'a> TableRef<'a> {
    /// The scene's table for `space`, if it has one.
    pub(crate) fn of<R: Real>(space: &'a Space, flat: &'a FlatScene<R>) -> Option<Self> {
        match (space.cells(), flat.centred_table(space)) {
            (CellScheme::Exact(exact), Some(around)) => Some(TableRef {
                around,
                group: &exact.group,
            }),
            _ => None,
        }
    }
}

/// Where a ray is, for its cell id.
#[derive(Clone, Debug)]
pub(crate) enum ExactCell {
    /// No exact cell: the id comes from the walk's matrix (a space whose
    /// ids are not exact, or a camera whose copy is not known exactly,
    /// with no cell rule; or past [`super::trace::MAX_EXACT_LEVELS`]
    /// crossings).
    Off,
    /// Cell `k` of the ray's [`TableRef`], the one around the camera.
    Table(u32),
    /// The element itself: past the table, or where there is none.
    Element(CellElement),
}

impl ExactCell {
    /// Where a ray from the camera starts: the table's centre where there
    /// is a `table`, else the camera's element where the space's ids are
    /// exact or `rules` read ids, else [`ExactCell::Off`].
    pub(crate) fn start<R: Real>(table: Option<TableRef>, flat: &FlatScene<R>, rules: bool) -> Self {
        match &flat.camera_element {
            CellElement::Exact(_) if table.is_some() => ExactCell::Table(0),
            CellElement::Exact(_) => ExactCell::Element(flat.camera_element.clone()),
            _ if rules => ExactCell::Element(flat.camera_element.clone()),
            _ => ExactCell::Off,
        }
    }

    /// The id of the cell, or of the walk's cell for [`ExactCell::Off`]
    /// (and for a table cell with no `table`, which [`ExactCell::start`]
    /// never makes).
    pub(crate) fn id<R: Real>(&self, table: Option<TableRef>, space: &Space, walk: &Walker<R>) -> CellId {
        match (self, table) {
            (ExactCell::Table(k), Some(t)) => t.around.id(t.group, *k),
            (ExactCell::Element(e), _) => space.cell_id_of(e),
            _ => space.cells().id_within(&R::m4_f64(walk.cell), R::CELL_HORIZON),
        }
    }

    /// The cell across `face`: the table's neighbour while there is one,
    /// else the element times the crossing. [`ExactCell::Off`] (and a
    /// table cell with no `table`) stays off.
    pub(crate) fn crossed<R: Real>(
        &self,
        table: Option<TableRef>,
        space: &Space,
        flat: &FlatScene<R>,
        face: usize,
    ) -> Self {
        match (self, table) {
            (ExactCell::Table(k), Some(t)) => match t.around.table().neighbour(*k, space.faces()[face].partner) {
                OUTSIDE => {
                    // Exact within reach (the centre is within `i128`, the
                    // cell a few crossings from it), else rounded.
                    let here = t.around.element(t.group, *k).map_or_else(
                        |_| CellElement::Float(flat.camera_cell * t.group.to_f64(t.around.table().element(*k))),
                        CellElement::Exact,
                    );
                    ExactCell::Element(space.cross_cell(&here, face))
                }
                next => ExactCell::Table(next),
            },
            (ExactCell::Element(e), _) => ExactCell::Element(space.cross_cell(e, face)),
            _ => ExactCell::Off,
        }
    }

    /// True for [`ExactCell::Off`].
    pub(crate) fn is_off(&self) -> bool {
        matches!(self, ExactCell::Off)
    }
}
