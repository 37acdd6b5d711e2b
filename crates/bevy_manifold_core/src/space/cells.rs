//! Cells of the covering space: which copy `g(D)` of the fundamental domain
//! a point is in, as an id that depends on the group element `g` only,
//! never on the path (the word) that reached it: per-cell shading reads
//! this id, so two paths to the same copy give the same colour.
//!
//! WGSL twin: `shaders/cells.wgsl` in `bevy_manifold_gpu` (`cell_id`,
//! `cell_color`), and its `shaders/cell_tint.wgsl` (`cell_tint`) for
//! [`CellTint::tint`].
//!
//! - **Lattice**: Euclidean box domains (the 3-torus, the mirrored cube),
//!   whose copies sit on a lattice of boxes. The id packs the integer triple
//!   `(i, j, k)` of the copy's centre.
//! - **Finite**: spherical spaces, whose group is finite. The elements are
//!   enumerated once and the id is an index into that list, with a Cayley
//!   table for the step across each face (Poincaré: 120 elements).
//! - **Exact**: hyperbolic spaces whose pairings are golden matrices (the
//!   Seifert-Weber space, the mirrored dodecahedron): the id is a hash of
//!   the exact group element ([`super::exact`]), the same for every path
//!   at any distance. From an `f64` element (this module's
//!   [`CellScheme::id_within`]) the copy is found by walking the element's
//!   centre back into the domain, multiplying the exact crossings on the
//!   way: exact as long as the centre is known to within the inradius.
//!   Game code and the tracers follow the exact element itself
//!   ([`super::element::CellElement`]).
//! - **Hashed**: other infinite groups that are no lattice (hyperbolic spaces
//!   over other fields, such as the Weeks manifold).
//!   The copy's centre `g(origin)` on the hyperboloid is rounded to a grid
//!   finer than half the distance between any two centres and hashed. Two
//!   words for the same element land on the same grid point unless rounding
//!   error reaches a grid boundary, which in f64 needs an error ~1e-10 times
//!   the grid step; the tests measure the margin. An f64 matrix product
//!   loses digits like `e^(2d)` at distance `d` from the origin copy, so
//!   beyond [`HASHED_HORIZON`] (about distance 12) the id carries
//!   [`CellId::FAR`]: a best effort that two paths may not agree on.
//!
//! ```
//! use bevy_manifold_core::space::catalog;
//! use glam::DMat4;
//! let torus = catalog::torus(1.0);
//! let g = torus.crossing(0) * torus.crossing(1); // across +x, then +y
//! assert_eq!(torus.cell_id(&g).lattice(), Some(glam::IVec3::new(1, 1, 0)));
//! assert_eq!(torus.cell_id(&DMat4::IDENTITY).0, 0);
//! ```

use super::cell_id::LATTICE_TAG;
pub use super::cell_id::{CellId, hash32};
use crate::geometry::Geometry;
use crate::space::Space;
use crate::space::exact::ExactGroup;
use glam::{DMat3, DMat4, DVec3, DVec4};

/// `|w|` of a copy's centre on the hyperboloid beyond which hashed ids are
/// flagged [`CellId::FAR`] (distance `acosh(1e5) ~ 12.2`).
pub const HASHED_HORIZON: f64 = <f64 as crate::geometry::Real>::CELL_HORIZON;

/// The same horizon for an element accumulated in f32 (the GPU, and the
/// CPU tracer's f32 mode): a product of a few H3 matrices in f32 is off by
/// about `eps_32 |w|^2` in its centre, a good fraction of a grid step once
/// `|w|` passes a few hundred (distance ~6).
pub const HASHED_HORIZON_F32: f64 = <f32 as crate::geometry::Real>::CELL_HORIZON;

/// How per-cell shading tells the copies of the domain apart: the tint an
/// object's albedo is multiplied by in the copy it is seen in. The copy
/// with id 0 (the camera's, when the camera is in the origin copy) is never
/// darkened.
///
/// ```
/// use bevy_manifold_core::space::cells::{CellId, CellTint};
/// let here = CellId(0);
/// let there = CellId::from_lattice(glam::IVec3::new(1, 0, 0));
/// assert_eq!(CellTint::ByCell.tint(here), [1.0; 3]);
/// assert_eq!(CellTint::Highlight(there).tint(here), [1.0; 3]);
/// assert_eq!(CellTint::Highlight(there).tint(there), CellTint::HIGHLIGHT);
/// // Half the copies on, half dimmed; which ones depends on the id only.
/// let on = CellTint::Pattern { on_fraction: 0.5 }.tint(there);
/// assert!(on == [1.0; 3] || on == [CellTint::OFF; 3]);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum CellTint {
    /// A colour hashed from each copy's id ([`CellId::color`]).
    #[default]
    ByCell,
    /// One copy tinted [`CellTint::HIGHLIGHT`], the others untouched.
    Highlight(CellId),
    /// The paper's on/off rule by cell (§7.2): a copy is on with
    /// probability `on_fraction` (decided by its id's hash, so the same
    /// copies are on from every path and every frame), off copies are
    /// dimmed to [`CellTint::OFF`].
    Pattern {
        /// Fraction of the copies that are on, in `[0, 1]`.
        on_fraction: f32,
    },
}

impl CellTint {
    /// The highlighted copy's tint (orange).
    pub const HIGHLIGHT: [f32; 3] = [1.0, 0.55, 0.15];
    /// The albedo factor of an off copy in [`CellTint::Pattern`].
    pub const OFF: f32 = 0.12;
    /// The neutral grey of a copy whose id the GPU does not know
    /// ([`CellId::BEYOND_TABLE`]), in every mode: neither on nor off in
    /// the pattern, not the highlight, and in by-cell mode the colour of
    /// one hash in 2^24 (whose three bytes are all 85).
    pub const UNKNOWN: f32 = 0.5;

    /// The tint of copy `id`.
    #[must_use]
    pub fn tint(self, id: CellId) -> [f32; 3] {
        if id == CellId::BEYOND_TABLE {
            return [Self::UNKNOWN; 3];
        }
        match self {
            CellTint::ByCell => id.color(),
            CellTint::Highlight(target) => {
                if id == target {
                    Self::HIGHLIGHT
                } else {
                    [1.0; 3]
                }
            }
            CellTint::Pattern { .. } => {
                let [_, threshold, _] = self.words();
                if id.0 == 0 || (id.hash() >> 8) < threshold {
                    [1.0; 3]
                } else {
                    [Self::OFF; 3]
                }
            }
        }
    }

    /// The three words the shader reads (`Params.cell_mode`, `cell_a`,
    /// `cell_b`): the mode (0 by cell, 1 highlight, 2 pattern) and its
    /// argument (the highlighted id's low and high words, or the pattern's
    /// 24-bit threshold).
    #[must_use]
    pub fn words(self) -> [u32; 3] {
        match self {
            CellTint::ByCell => [0, 0, 0],
            CellTint::Highlight(id) => [1, id.0 as u32, (id.0 >> 32) as u32],
            CellTint::Pattern { on_fraction } => {
                let f = if on_fraction.is_nan() {
                    0.0
                } else {
                    on_fraction.clamp(0.0, 1.0)
                };
                [2, (f64::from(f) * f64::from(1u32 << 24)).round() as u32, 0]
            }
        }
    }
}

/// How a space numbers the copies of its domain.
#[derive(Clone, Debug)]
pub enum CellScheme {
    /// Box lattice: the centre of `g(D)` is `B (i, j, k)`.
    Lattice {
        /// Inverse of the lattice basis `B` (the box's edge lengths).
        inverse_basis: DMat3,
    },
    /// A finite group, enumerated.
    Finite {
        /// The elements; index 0 is the identity.
        elements: Vec<DMat4>,
        /// `table[k][f]`: the index of `elements[k] * T_f`.
        table: Vec<Vec<u32>>,
    },
    /// Exact golden arithmetic ([`super::exact`]).
    Exact(Box<ExactCells>),
    /// Rounded hyperboloid (or chart) coordinates of the centre, hashed.
    Hashed {
        /// The grid step.
        quantum: f64,
    },
}

/// Most elements a finite group may have before it is treated as infinite.
pub const MAX_FINITE_GROUP: usize = 5_000;

impl CellScheme {
    /// The scheme that fits a space.
    #[must_use]
    pub fn for_space(space: &Space) -> Self {
        match space.geometry() {
            Geometry::Spherical => match enumerate_group(space, MAX_FINITE_GROUP) {
                Some((elements, table)) => CellScheme::Finite { elements, table },
                None => CellScheme::Hashed {
                    quantum: hashed_quantum(space),
                },
            },
            Geometry::Euclidean => match box_lattice(space) {
                Some(inverse_basis) => CellScheme::Lattice { inverse_basis },
                None => CellScheme::Hashed {
                    quantum: hashed_quantum(space),
                },
            },
            Geometry::Hyperbolic => match ExactGroup::of(space) {
                Some(group) => CellScheme::Exact(Box::new(ExactCells {
                    group,
                    planes: space.faces().iter().map(|f| f.plane).collect(),
                    pairings: space.faces().iter().map(|f| f.pairing).collect(),
                    table: std::sync::OnceLock::new(),
                })),
                None => CellScheme::Hashed {
                    quantum: hashed_quantum(space),
                },
            },
        }
    }

    /// The id of the copy `g(D)`.
    #[must_use]
    pub fn id_of(&self, g: &DMat4) -> CellId {
        self.id_within(g, HASHED_HORIZON)
    }

    /// [`CellScheme::id_of`] for an element known only to the precision
    /// whose hashed-id horizon is `horizon` (`|w|` of the copy's centre):
    /// [`HASHED_HORIZON`] in f64, [`HASHED_HORIZON_F32`] for an element
    /// accumulated in f32 as the GPU does.
    #[must_use]
    pub fn id_within(&self, g: &DMat4, horizon: f64) -> CellId {
        let centre = g.w_axis;
        match self {
            CellScheme::Lattice { inverse_basis } => {
                let c = *inverse_basis * (centre.truncate() / centre.w);
                CellId::from_lattice(c.round().as_ivec3())
            }
            CellScheme::Finite { elements, .. } => {
                let best = elements
                    .iter()
                    .enumerate()
                    .map(|(i, e)| (i, (e.w_axis - centre).length_squared()))
                    .fold((0, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
                CellId(best.0 as u64)
            }
            CellScheme::Exact(exact) => {
                let id = exact.locate(g).map_or(CellId(CellId::FAR | 1), |e| e.cell_id());
                if centre.w.abs() >= horizon || !centre.is_finite() {
                    CellId(id.0 | CellId::FAR)
                } else {
                    id
                }
            }
            CellScheme::Hashed { quantum } => hashed_id(centre, *quantum, horizon),
        }
    }

    /// For a finite group, the id after crossing: `id * T_f`.
    #[must_use]
    pub fn step(&self, id: CellId, right_factor_face: usize) -> Option<CellId> {
        match self {
            CellScheme::Finite { table, .. } => Some(CellId(u64::from(table[id.0 as usize][right_factor_face]))),
            _ => None,
        }
    }

    /// A short name: "lattice", "finite", "exact" or "hashed".
    #[must_use]
    pub fn kind(&self) -> &'static str {
        match self {
            CellScheme::Lattice { .. } => "lattice",
            CellScheme::Finite { .. } => "finite",
            CellScheme::Exact(_) => "exact",
            CellScheme::Hashed { .. } => "hashed",
        }
    }

    /// For the hashed scheme, how far (in grid steps, at most 0.5) the
    /// coordinates of `g(origin)` are from a rounding boundary: the margin
    /// that keeps the id path-independent.
    #[must_use]
    pub fn rounding_margin(&self, g: &DMat4) -> f64 {
        match self {
            CellScheme::Hashed { quantum } => (g.w_axis * (1.0 / *quantum))
                .to_array()
                .iter()
                .map(|x| 0.5 - (x - x.round_ties_even()).abs())
                .fold(0.5, f64::min),
            _ => 0.5,
        }
    }
}

/// The exact scheme's data: the group, and the faces to walk an `f64`
/// element's centre home by.
#[derive(Clone, Debug)]
pub struct ExactCells {
    /// The exact group.
    pub group: ExactGroup,
    planes: Vec<DVec4>,
    pairings: Vec<DMat4>,
    table: std::sync::OnceLock<std::sync::Arc<super::cell_table::CellTable>>,
}

/// Most face steps [`ExactCells::locate`] takes walking a centre home.
const MAX_LOCATE_STEPS: usize = 4096;

impl ExactCells {
    /// The table of cells around the origin copy that the GPU walks
    /// ([`super::cell_table`], [`super::cell_table::DEFAULT_TABLE_CELLS`] cells at
    /// most), grown on first use (0.2 s in Seifert-Weber, 0.5 s in the
    /// mirrored dodecahedron, on one core of the development machine,
    /// `bench cells`) and kept with the space.
    pub fn table(&self) -> &std::sync::Arc<super::cell_table::CellTable> {
        self.table.get_or_init(|| {
            std::sync::Arc::new(super::cell_table::CellTable::grow(
                &self.group,
                super::cell_table::DEFAULT_TABLE_CELLS,
            ))
        })
    }

    /// The table, if it has been grown (never blocks).
    #[must_use]
    pub fn grown_table(&self) -> Option<&std::sync::Arc<super::cell_table::CellTable>> {
        self.table.get()
    }

    /// The exact element of the copy whose centre `g` (an `f64` element)
    /// carries the domain's centre to: the centre is walked back into the
    /// domain through the face it lies most outside of, the exact
    /// crossings multiplied on the way (as [`Space::wrap`] does in `f64`,
    /// by the same face rule, [`Space::outside_face`]).
    /// `None` when the walk does not end within 4096 steps or the
    /// arithmetic overflows.
    #[must_use]
    pub fn locate(&self, g: &DMat4) -> Option<super::exact::ExactElement> {
        let mut p = g.w_axis;
        let mut e = self.group.identity();
        for _ in 0..MAX_LOCATE_STEPS {
            if !(p.w > 0.0 && p.is_finite()) {
                return None;
            }
            let Some(f) = super::most_outside(self.planes.iter().copied(), p, 1e-9) else {
                return Some(e);
            };
            p = self.pairings[f] * p;
            p /= p.w;
            e = self.group.cross(&e, f).ok()?;
        }
        None
    }
}

/// Half the smallest possible distance between two copies' centres,
/// shrunk so that a grid cube (diagonal 2 steps in 4D) fits between them.
/// Centres are at least `2 r` apart (`r` the inradius), and in H3 the
/// Euclidean norm of a difference of hyperboloid points is at least its
/// Minkowski norm `2 sinh(d/2) >= 2 sinh r`.
fn hashed_quantum(space: &Space) -> f64 {
    let r = space.inradius();
    match space.geometry() {
        Geometry::Hyperbolic => r.sinh() / 2.0,
        Geometry::Spherical => r.sin() / 2.0,
        Geometry::Euclidean => r / 2.0,
    }
}

/// Largest magnitude of a rounded hashed-id key coordinate: exact in f32,
/// well inside i32, so the conversion never saturates differently on the
/// GPU. Keys this large are FAR anyway.
pub const HASH_KEY_LIMIT: f64 = (1u32 << 30) as f64;

/// The integer grid key of a centre: each coordinate times the scale
/// (`1 / quantum`), rounded half to even (WGSL's `round`), clamped to
/// [`HASH_KEY_LIMIT`]. WGSL twin: the key in `cell_id`, `shaders/cells.wgsl`.
#[must_use]
pub fn hash_key_of(centre: DVec4, scale: f64) -> [i32; 4] {
    (centre * scale)
        .to_array()
        .map(|x| x.round_ties_even().clamp(-HASH_KEY_LIMIT, HASH_KEY_LIMIT) as i32)
}

fn hashed_id(centre: DVec4, quantum: f64, horizon: f64) -> CellId {
    // Not finite: flagged far (the GPU tests the bits the same way).
    if !centre.is_finite() {
        return CellId(CellId::FAR | 1);
    }
    let far = centre.w.abs() >= horizon;
    let scale = 1.0 / quantum;
    let key = hash_key_of(centre, scale);
    if key == hash_key_of(DVec4::W, scale) {
        return CellId(0);
    }
    // Two independent 32-bit hashes of the integer key make the 64-bit id:
    // u32 arithmetic only, so the WGSL tracer computes the same id.
    let h = (u64::from(hash_key(key, HASH_SEED_HI)) << 32) | u64::from(hash_key(key, HASH_SEED_LO));
    // Keep the lattice tag and far bits clear, and never produce the
    // origin's 0; then mark far ids.
    let id = (h & !(LATTICE_TAG | CellId::FAR)).max(1);
    CellId(if far { id | CellId::FAR } else { id })
}

const HASH_SEED_LO: u32 = 0x9e37_79b9;
const HASH_SEED_HI: u32 = 0x85eb_ca6b;

/// Hash of a rounded cell centre, seeded; identical in WGSL (`hash_key`).
#[must_use]
pub fn hash_key(key: [i32; 4], seed: u32) -> u32 {
    key.iter().fold(seed, |h, &k| hash32(h ^ k as u32))
}

/// A Euclidean domain that is an axis-aligned box centred at the origin:
/// the inverse of `diag(edge lengths)`.
fn box_lattice(space: &Space) -> Option<DMat3> {
    let mut half = [0.0f64; 3];
    if space.faces().len() != 6 {
        return None;
    }
    for f in space.faces() {
        let n = f.plane.truncate();
        let axis = (0..3).find(|&a| (n[a].abs() - n.length()).abs() < 1e-12)?;
        let h = -f.plane.w / n.length();
        if half[axis] != 0.0 && (half[axis] - h).abs() > 1e-12 {
            return None;
        }
        half[axis] = h;
    }
    if half.contains(&0.0) {
        return None;
    }
    Some(DMat3::from_diagonal(DVec3::from_array(half).recip() * 0.5))
}

/// Breadth-first enumeration of the group generated by the pairings, up to
/// `limit` elements, with its right Cayley table. Elements are told apart by
/// where they send the origin, which no non-identity element fixes (the
/// origin is interior, where the action is free).
fn enumerate_group(space: &Space, limit: usize) -> Option<(Vec<DMat4>, Vec<Vec<u32>>)> {
    let g = space.geometry();
    let gens: Vec<DMat4> = space.faces().iter().map(|f| f.pairing).collect();
    let mut elements = vec![DMat4::IDENTITY];
    let mut table: Vec<Vec<u32>> = Vec::new();
    let find = |els: &[DMat4], m: &DMat4| els.iter().position(|e| (e.w_axis - m.w_axis).length() < 1e-6);
    let mut k = 0;
    while k < elements.len() {
        let mut row = Vec::with_capacity(gens.len());
        for t in &gens {
            let m = crate::geometry::isometry::orthonormalize(g, elements[k] * *t);
            let idx = match find(&elements, &m) {
                Some(i) => i,
                None => {
                    if elements.len() >= limit {
                        return None;
                    }
                    elements.push(m);
                    elements.len() - 1
                }
            };
            row.push(idx as u32);
        }
        table.push(row);
        k += 1;
    }
    Some((elements, table))
}
