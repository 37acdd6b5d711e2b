//! The copy of the domain a ray is in, as exactly as the space names it,
//! for the ids the CPU tracer gives its pixels and its cell rules read:
//! by index in the table of cells around the camera while the ray is in
//! it ([`FlatScene::cells_around`]: no arithmetic at a crossing), then by
//! exact products ([`Space::cross_cell`]), one per crossing.
//!
//! WGSL twin: the `CELLS_TABLE` index of `Walker` in `bevy_manifold_gpu`'s
//! `shaders/walk.wgsl` (`walker_step`). The GPU stops at the table's edge
//! and shades what lies beyond it neutral grey; the CPU goes on exactly.

use super::flat::FlatScene;
use super::walk::Walker;
use crate::geometry::Real;
use crate::space::Space;
use crate::space::ball::OUTSIDE;
use crate::space::cells::{CellId, CellScheme};
use crate::space::element::CellElement;

/// Where a ray is, for its cell id.
#[derive(Clone, Debug)]
pub(crate) enum ExactCell {
    /// No exact cell: the id comes from the walk's matrix (a space whose
    /// ids are not exact, or a camera whose copy is not known exactly,
    /// with no cell rule; or past [`super::render::MAX_EXACT_LEVELS`]
    /// crossings).
    Off,
    /// Cell `k` of the table around the camera ([`FlatScene::cells_around`]).
    Table(u32),
    /// The element itself: past the table, or where there is none.
    Element(CellElement),
}

impl ExactCell {
    /// Where a ray from the camera starts: the table's centre where there
    /// is a table, else the camera's element where the space's ids are
    /// exact or `rules` read ids, else [`ExactCell::Off`].
    pub(crate) fn start<R: Real>(space: &Space, prep: &FlatScene<R>, rules: bool) -> Self {
        match &prep.camera_element {
            CellElement::Exact(_) if prep.cells_around(space).is_some() => ExactCell::Table(0),
            CellElement::Exact(_) => ExactCell::Element(prep.camera_element.clone()),
            _ if rules => ExactCell::Element(prep.camera_element.clone()),
            _ => ExactCell::Off,
        }
    }

    /// The id of the cell, or of the walk's cell for [`ExactCell::Off`].
    pub(crate) fn id<R: Real>(&self, space: &Space, prep: &FlatScene<R>, walk: &Walker<R>) -> CellId {
        match self {
            ExactCell::Table(k) => {
                if let (CellScheme::Exact(exact), Some(around)) = (space.cells(), prep.cells_around(space)) {
                    return around.id(&exact.group, *k);
                }
            }
            ExactCell::Element(e) => return space.cell_id_of(e),
            ExactCell::Off => {}
        }
        // Off, or a table cell traced with another space than the scene's
        // (no table there).
        space.cells().id_within(&R::m4_f64(walk.cell), R::CELL_HORIZON)
    }

    /// The cell across `face`: the table's neighbour while there is one,
    /// else the element times the crossing. [`ExactCell::Off`] stays off.
    pub(crate) fn crossed<R: Real>(&self, space: &Space, prep: &FlatScene<R>, face: usize) -> Self {
        match self {
            ExactCell::Table(k) => {
                let (CellScheme::Exact(exact), Some(around)) = (space.cells(), prep.cells_around(space)) else {
                    // Traced with another space than the scene's.
                    return ExactCell::Off;
                };
                match around.ball().neighbour(*k, space.faces()[face].partner) {
                    OUTSIDE => {
                        // Exact within reach (the centre is within `i128`,
                        // the cell a few crossings from it), else rounded.
                        let here = around.element(&exact.group, *k).map_or_else(
                            |_| CellElement::Float(prep.camera_cell * exact.group.to_f64(around.ball().element(*k))),
                            CellElement::Exact,
                        );
                        ExactCell::Element(space.cross_cell(&here, face))
                    }
                    next => ExactCell::Table(next),
                }
            }
            ExactCell::Element(e) => ExactCell::Element(space.cross_cell(e, face)),
            ExactCell::Off => ExactCell::Off,
        }
    }

    /// True for [`ExactCell::Off`].
    pub(crate) fn is_off(&self) -> bool {
        matches!(self, ExactCell::Off)
    }
}
