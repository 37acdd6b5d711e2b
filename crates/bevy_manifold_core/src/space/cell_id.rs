//! The id of a copy of the fundamental domain ([`CellId`]): what every
//! tracer, entity and rule names a cell by, made by the cell schemes of
//! [`super::cells`] and of the exact groups ([`super::exact`]).

use glam::IVec3;

/// The id of one copy of the fundamental domain in the cover. The origin
/// copy is 0 in every scheme.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct CellId(pub u64);

const LATTICE_BITS: u32 = 21;
const LATTICE_MASK: u64 = (1 << LATTICE_BITS) - 1;
/// Marks lattice ids so they can be decoded.
pub(super) const LATTICE_TAG: u64 = 1 << 63;

impl CellId {
    /// Set on hashed ids of copies beyond [`super::cells::HASHED_HORIZON`], where f64 can
    /// no longer tell the copies apart reliably.
    pub const FAR: u64 = 1 << 62;

    /// What the GPU reports for a cell beyond its table of exact ids
    /// (`CELLS_TABLE`, [`super::cell_table`]): the far bit alone, which no id
    /// from a hash carries. Shaded [`super::cells::CellTint::UNKNOWN`] in every mode.
    pub const BEYOND_TABLE: CellId = CellId(Self::FAR);

    /// True for a best-effort id beyond the precision horizon.
    #[must_use]
    pub fn is_far(self) -> bool {
        self.0 & LATTICE_TAG == 0 && self.0 & Self::FAR != 0
    }

    /// The id of lattice cell `(i, j, k)`; each coordinate keeps 21 bits.
    #[must_use]
    pub fn from_lattice(c: IVec3) -> Self {
        if c == IVec3::ZERO {
            return CellId(0);
        }
        let pack = |x: i32| (x as i64 as u64) & LATTICE_MASK;
        CellId(LATTICE_TAG | pack(c.x) | (pack(c.y) << LATTICE_BITS) | (pack(c.z) << (2 * LATTICE_BITS)))
    }

    /// The lattice triple of a lattice id (`Some(ZERO)` for the origin).
    #[must_use]
    pub fn lattice(self) -> Option<IVec3> {
        if self.0 == 0 {
            return Some(IVec3::ZERO);
        }
        if self.0 & LATTICE_TAG == 0 {
            return None;
        }
        let unpack = |s: u32| {
            let v = (self.0 >> s) & LATTICE_MASK;
            // sign-extend 21 bits
            ((v << (64 - LATTICE_BITS)) as i64 >> (64 - LATTICE_BITS)) as i32
        };
        Some(IVec3::new(unpack(0), unpack(LATTICE_BITS), unpack(2 * LATTICE_BITS)))
    }

    /// A colour for per-cell shading, the same for every path to the cell.
    #[must_use]
    pub fn color(self) -> [f32; 3] {
        if self.0 == 0 {
            return [1.0, 1.0, 1.0];
        }
        let h = self.hash();
        let c = |s: u32| 0.25 + 0.75 * ((h >> s) & 0xff) as f32 / 255.0;
        [c(0), c(8), c(16)]
    }

    /// 32 bits hashed from the id, in 32-bit arithmetic only so the GPU
    /// (`cell_hash` in `bevy_manifold_gpu`'s `shaders/cell_tint.wgsl`) gets the same bits.
    #[must_use]
    pub fn hash(self) -> u32 {
        hash32((self.0 as u32) ^ hash32((self.0 >> 32) as u32))
    }
}

/// A 32-bit integer hash (PCG's output permutation), identical in WGSL
/// (`hash32` in `bevy_manifold_gpu`'s `shaders/cell_tint.wgsl`).
#[must_use]
pub fn hash32(x: u32) -> u32 {
    let state = x.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}
