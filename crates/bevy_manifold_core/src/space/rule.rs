//! Per-cell rules games build on, decided from a cell's path-independent
//! id alone, so the tracer, the gameplay ray casts and the ECS agree on
//! them from every path: the paper's on/off rule by cell
//! (its §7.2: objects in an "off" copy are neither drawn nor hit, rays
//! pass through) and walls between cells (its §6.3: "an opaque cell with
//! a few openings" turns the cover into a maze).
//!
//! A face between cells `a` and `b` is a wall by a hash of the unordered
//! pair `{a, b}`, so it is the same wall seen from either side. With exact
//! ids ([`super::exact`]) the rules hold at any distance.
//!
//! ```
//! use bevy_manifold_core::space::cells::CellId;
//! use bevy_manifold_core::space::rule::{CellRule, OnOff, Walls};
//! let rule = CellRule {
//!     hidden: Some(OnOff { on_fraction: 0.5, seed: 7 }),
//!     walls: Some(Walls { density: 0.3, seed: 1 }),
//! };
//! let (a, b) = (CellId(12345), CellId(678));
//! assert_eq!(rule.wall(a, b), rule.wall(b, a));
//! assert!(rule.visible(CellId(0)), "the origin copy is always on");
//! assert!(!CellRule::default().wall(a, b) && CellRule::default().visible(a));
//! ```

use super::cells::{CellId, hash32};

/// The on/off rule: a cell is on with probability `on_fraction`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OnOff {
    /// Fraction of the cells that are on, in `[0, 1]`.
    pub on_fraction: f32,
    /// Which cells: another seed, another pattern.
    pub seed: u32,
}

/// Walls: each face between two cells is opaque with probability
/// `density`; the others are the openings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Walls {
    /// Fraction of faces that are walls, in `[0, 1]`.
    pub density: f32,
    /// Which faces: another seed, another maze.
    pub seed: u32,
}

/// The rules of a space's cells; the default has none.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct CellRule {
    /// Cells whose objects are hidden and not hit (`None`: all shown).
    pub hidden: Option<OnOff>,
    /// Walls between cells (`None`: no walls).
    pub walls: Option<Walls>,
}

/// The linear colour walls are drawn in (a warm stone grey).
pub const WALL_COLOR: [f32; 3] = [0.62, 0.58, 0.52];

/// The object id the tracer reports for a wall.
pub const WALL_OBJECT: u32 = u32::MAX - 1;

/// A fraction as a 24-bit threshold (NaN as 0, clamped to `[0, 1]`).
fn threshold(f: f32) -> u32 {
    let f = if f.is_nan() { 0.0 } else { f.clamp(0.0, 1.0) };
    (f64::from(f) * f64::from(1u32 << 24)).round() as u32
}

/// 24 bits from an id and a seed, in u32 arithmetic. WGSL twin:
/// `rule_bits` in `bevy_manifold_gpu`'s `shaders/rule.wgsl`.
fn bits(id: CellId, seed: u32) -> u32 {
    hash32(hash32(seed ^ id.0 as u32) ^ (id.0 >> 32) as u32) >> 8
}

impl CellRule {
    /// True when some rule is on.
    #[must_use]
    pub fn is_active(&self) -> bool {
        self.hidden.is_some() || self.walls.is_some()
    }

    /// The four words the shader reads (`Params.rule_hidden`,
    /// `rule_hidden_seed`, `rule_walls`, `rule_walls_seed`): the on
    /// threshold (`1 << 24` when nothing is hidden) and its seed, the wall
    /// threshold (0 without walls) and its seed.
    #[must_use]
    pub fn words(&self) -> [u32; 4] {
        let (on, on_seed) = self.hidden.map_or((1 << 24, 0), |r| (threshold(r.on_fraction), r.seed));
        let (wall, wall_seed) = self.walls.map_or((0, 0), |w| (threshold(w.density), w.seed));
        [on, on_seed, wall, wall_seed]
    }

    /// Whether the objects in cell `id` are drawn and hit. The origin copy
    /// is always on (a game starts there); a cell the GPU could not name
    /// ([`CellId::BEYOND_TABLE`]) is on.
    #[must_use]
    pub fn visible(&self, id: CellId) -> bool {
        match self.hidden {
            None => true,
            Some(r) => id.0 == 0 || id == CellId::BEYOND_TABLE || bits(id, r.seed) < threshold(r.on_fraction),
        }
    }

    /// Whether the face between cells `a` and `b` is a wall (the same from
    /// either side). WGSL twin: `cell_wall` in `shaders/rule.wgsl`. Never between a cell and itself, or next to a cell
    /// the GPU could not name.
    #[must_use]
    pub fn wall(&self, a: CellId, b: CellId) -> bool {
        let Some(w) = self.walls else { return false };
        if a == b || a == CellId::BEYOND_TABLE || b == CellId::BEYOND_TABLE {
            return false;
        }
        let (lo, hi) = if a.0 < b.0 { (a, b) } else { (b, a) };
        let pair = CellId(u64::from(bits(lo, w.seed)) | (hi.0 << 24) ^ (hi.0 >> 40));
        bits(pair, w.seed ^ 0x5bd1_e995) < threshold(w.density)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fractions_come_out_over_many_cells() {
        // Against the binomial: 10^5 ids, 3 standard deviations.
        let rule = CellRule {
            hidden: Some(OnOff {
                on_fraction: 0.3,
                seed: 11,
            }),
            walls: Some(Walls { density: 0.6, seed: 5 }),
        };
        let n = 100_000u64;
        let ids = (1..=n).map(|k| CellId(k.wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 2));
        let on = ids.clone().filter(|&id| rule.visible(id)).count() as f64;
        let walls = ids.clone().zip(ids.skip(1)).filter(|&(a, b)| rule.wall(a, b)).count() as f64;
        let sd = |p: f64| 3.0 * (n as f64 * p * (1.0 - p)).sqrt();
        assert!((on - 0.3 * n as f64).abs() < sd(0.3), "{on}");
        assert!((walls - 0.6 * n as f64).abs() < sd(0.6), "{walls}");
    }
}
