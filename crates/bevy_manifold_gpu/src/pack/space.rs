//! The space's part of the GPU data ([`GpuSpace`]: the faces and the cell
//! table), and the one cache of it ([`PackedSpace`]) that the render pass
//! and the headless runner keep.

use super::{m, non_empty, v};
use crate::layout::GpuFace;
use bevy_manifold_core::space::cell_table::{CellTable, OUTSIDE};
use bevy_manifold_core::space::cells::{CellId, CellScheme};
use bevy_manifold_core::space::element::CellElement;
use bevy_manifold_core::space::{Face, Space};
use std::sync::Arc;

/// The space's part of the GPU data: faces and the cell table. Uploaded
/// when the space changes.
#[derive(Clone, Debug, PartialEq)]
pub struct GpuSpace {
    /// Faces.
    pub faces: Vec<GpuFace>,
    /// The cell table: for a finite group its Cayley table, `[k * faces +
    /// f]`; for exact ids (`CELLS_TABLE`) the neighbours of the cells
    /// around the camera, the same way, then each cell's id as two words
    /// (at least one element: empty storage buffers are not allowed).
    pub cell_table: Vec<u32>,
    /// [`GpuParams::cell_scale`].
    pub cell_scale: [f32; 4],
    /// `FaceTables::near_scale`.
    pub near_scale: f32,
}

impl GpuSpace {
    /// Packs a space's faces (in f32) and its cell scheme.
    #[must_use]
    pub fn pack(space: &Space) -> Self {
        let t = bevy_manifold_core::trace::FaceTables::<f32>::new(space);
        let faces = (0..t.planes.len())
            .map(|i| GpuFace {
                plane: v(t.planes[i]),
                pairing: m(t.pairings[i]),
                crossing: m(t.crossings[i]),
                partner: t.partners[i] as u32,
                pad_a: 0,
                pad_b: 0,
                pad_c: 0,
            })
            .collect();
        let (cell_scale, cell_table) = match space.cells() {
            CellScheme::Lattice { inverse_basis } => (
                [
                    inverse_basis.x_axis.x as f32,
                    inverse_basis.y_axis.y as f32,
                    inverse_basis.z_axis.z as f32,
                    0.0,
                ],
                Vec::new(),
            ),
            CellScheme::Finite { table, .. } => ([0.0; 4], table.iter().flatten().copied().collect()),
            // The neighbours, then each cell's id as (lo, hi) from
            // cell_scale.x's bits on; centred on the origin copy until
            // GpuSpace::centre_on moves it. Before the table is grown
            // (the render pass grows it on a task), one cell: the camera's.
            CellScheme::Exact(exact) => match exact.grown_table() {
                Some(grown) => {
                    let offset = grown.neighbours.len() as u32;
                    let mut table = grown.neighbours.clone();
                    table.extend(
                        grown
                            .ids_around(&exact.group, &exact.group.identity())
                            .iter()
                            .flat_map(|id| id_words(*id)),
                    );
                    ([f32::from_bits(offset), 0.0, 0.0, 0.0], table)
                }
                None => {
                    let faces = space.faces().len();
                    let mut table = vec![OUTSIDE; faces];
                    table.extend([0, 0]);
                    ([f32::from_bits(faces as u32), 0.0, 0.0, 0.0], table)
                }
            },
            CellScheme::Hashed { quantum } => (
                [
                    (1.0 / quantum) as f32,
                    bevy_manifold_core::space::cells::HASHED_HORIZON_F32 as f32,
                    0.0,
                    0.0,
                ],
                Vec::new(),
            ),
        };
        GpuSpace {
            faces,
            cell_table: non_empty(cell_table),
            cell_scale,
            near_scale: t.near_scale,
        }
    }
}

impl GpuSpace {
    /// For `CELLS_TABLE`: true while the table is the one cell of a space
    /// whose table of cells is still being grown.
    #[must_use]
    pub fn table_pending(&self, space: &Space) -> bool {
        matches!(space.cells(), CellScheme::Exact(_))
            && self.cell_table.len() == space.faces().len() + 2
            && self.cell_scale[0].to_bits() as usize == space.faces().len()
    }

    /// For `CELLS_TABLE`: the table's ids for a camera in `camera` (cell
    /// `k` becomes `camera e_k`); nothing for other schemes. One exact
    /// product per cell (10 ms for Seifert-Weber's 16,129 cells).
    pub fn centre_on(&mut self, space: &Space, camera: &CellElement) {
        let (CellScheme::Exact(exact), CellElement::Exact(centre)) = (space.cells(), camera) else {
            return;
        };
        let offset = self.cell_scale[0].to_bits() as usize;
        let ids = match exact.grown_table() {
            // The table grown when packed.
            Some(table) if self.cell_table.len() == offset + 2 * table.len() => table.ids_around(&exact.group, centre),
            // The one-cell table of a space whose table is still growing.
            _ => vec![centre.cell_id()],
        };
        for (k, id) in ids.iter().enumerate() {
            let [lo, hi] = id_words(*id);
            self.cell_table[offset + 2 * k] = lo;
            self.cell_table[offset + 2 * k + 1] = hi;
        }
    }
}

impl GpuSpace {
    /// For `CELLS_TABLE`: the index of the cell with id `id` in the table,
    /// if it is there (a scan of the ids, 20-60 us).
    #[must_use]
    pub fn index_of(&self, id: CellId) -> Option<u32> {
        let offset = self.cell_scale[0].to_bits() as usize;
        let [lo, hi] = id_words(id);
        self.cell_table
            .get(offset..)?
            .chunks_exact(2)
            .position(|w| w[0] == lo && w[1] == hi)
            .map(|k| k as u32)
    }
}

/// A cell id as the two words the shader reads.
fn id_words(id: CellId) -> [u32; 2] {
    [id.0 as u32, (id.0 >> 32) as u32]
}

/// A space packed for the GPU and what it was packed for: its faces, the
/// cell table it was packed from (none while the table is still growing),
/// and the cell the table's ids are centred on. The render pass keeps one
/// per space it draws, the headless runner the last one it packed (the
/// frames of a tour); both pack, recentre and repack through it. Packing
/// is cheap but for the cell table of a space with exact ids, whose ids
/// move with the camera: one exact product per cell (16,129 cells in
/// Seifert-Weber, about 10 ms), so a still camera's table is kept, and a
/// moving one's recentred, off the frame where the caller can
/// ([`PackedSpace::recentred`]).
///
/// ```
/// use bevy_manifold_core::space::catalog;
/// use bevy_manifold_gpu::PackedSpace;
///
/// let space = catalog::seifert_weber();
/// let packed = PackedSpace::pack(&space, space.origin_cell());
/// assert!(packed.is_for(&space));
/// assert!(!packed.is_for(&catalog::poincare()));
/// assert_eq!(packed.gpu().faces.len(), space.faces().len());
/// ```
#[derive(Clone, Debug)]
pub struct PackedSpace {
    faces: Vec<Face>,
    table: Option<Arc<CellTable>>,
    centre: CellElement,
    gpu: Arc<GpuSpace>,
}

impl PackedSpace {
    /// `space` packed, its cell table (as far as it has grown: see
    /// [`GpuSpace::pack`]) centred on `centre`.
    #[must_use]
    pub fn pack(space: &Space, centre: CellElement) -> Self {
        let mut gpu = GpuSpace::pack(space);
        gpu.centre_on(space, &centre);
        PackedSpace {
            faces: space.faces().to_vec(),
            table: grown_table(space).cloned(),
            centre,
            gpu: Arc::new(gpu),
        }
    }

    /// True while this is `space` packed as it stands: the same faces and
    /// the same cell table (a table that has grown since calls for
    /// [`PackedSpace::outgrown`]'s repacking).
    #[must_use]
    pub fn is_for(&self, space: &Space) -> bool {
        self.faces == space.faces()
            && match (grown_table(space), &self.table) {
                (Some(now), Some(then)) => Arc::ptr_eq(now, then),
                (None, None) => true,
                _ => false,
            }
    }

    /// True while `space`'s ids are exact and its cell table was still
    /// growing when this was packed (the camera's own cell alone).
    #[must_use]
    pub fn table_pending(&self, space: &Space) -> bool {
        self.table.is_none() && matches!(space.cells(), CellScheme::Exact(_))
    }

    /// True when this was packed while `space`'s cell table was still
    /// growing (the camera's own cell alone) and the table has grown
    /// since: pack it again, on the same centre.
    #[must_use]
    pub fn outgrown(&self, space: &Space) -> bool {
        self.table.is_none() && grown_table(space).is_some()
    }

    /// The same space with its cell table's ids centred on `centre`
    /// instead (one exact product per cell of the table: the render pass
    /// runs it on a task, off the frame).
    #[must_use]
    pub fn recentred(&self, space: &Space, centre: CellElement) -> Self {
        // Only exact ids move with the camera: elsewhere the same `Arc`,
        // so nothing is uploaded again.
        let gpu = match (space.cells(), &centre) {
            (CellScheme::Exact(_), CellElement::Exact(_)) => {
                let mut gpu = (*self.gpu).clone();
                gpu.centre_on(space, &centre);
                Arc::new(gpu)
            }
            _ => self.gpu.clone(),
        };
        PackedSpace {
            gpu,
            centre,
            ..self.clone()
        }
    }

    /// The cell the table's ids are centred on.
    #[must_use]
    pub fn centre(&self) -> &CellElement {
        &self.centre
    }

    /// Where a walk from the camera in `camera` starts in the cell table
    /// (`GpuParams::camera_cell_index` of a space with exact ids): its
    /// centre, 0, when the table is centred on that cell; else the cell
    /// found by its id (another camera's, or this one's before a crossing
    /// while the table is recentred), or [`OUTSIDE`] when it is not in
    /// the table.
    #[must_use]
    pub fn index_of(&self, space: &Space, camera: &CellElement) -> u32 {
        if !matches!(camera, CellElement::Exact(_)) || *camera == self.centre {
            return 0;
        }
        self.gpu.index_of(space.cell_id_of(camera)).unwrap_or(OUTSIDE)
    }

    /// The packed faces and cell table, shared (an unchanged `Arc` uploads
    /// nothing).
    #[must_use]
    pub fn gpu(&self) -> &Arc<GpuSpace> {
        &self.gpu
    }
}

/// The cell table of `space`, if its ids are exact and the table has grown.
fn grown_table(space: &Space) -> Option<&Arc<CellTable>> {
    match space.cells() {
        CellScheme::Exact(exact) => exact.grown_table(),
        _ => None,
    }
}
