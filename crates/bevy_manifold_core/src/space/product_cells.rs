//! Exact ids of the copies of a product space's prism ([`ProductCells`]),
//! the ids the product tracer's pixels and cell tints read.
//!
//! An element of a product space's group is a pair: an isometry of the
//! surface and a map `t -> flip t + steps L` of the line (`L` the
//! prism's height). A copy of the prism is named by the copy of the
//! polygon its surface part reaches (the image of the polygon's centre)
//! and by `steps`: the group acts freely, so two elements with the same
//! centre image and the same `steps` are one (a twist turns the polygon
//! about its centre, which the name does not see; a mirror end's flip
//! is `steps`' parity).
//!
//! The surface parts are computed exactly. In the basis of three sides'
//! normals (`n_0, n_1, n_2`, as vectors of the model), the gluings of
//! the regular polygons of the catalog are matrices over a quadratic
//! ring: `Z[sqrt 2]` for the octagon of genus 2 (its twists too), and
//! `Z[phi]` for the right-angled pentagon, whose reflections
//! `v -> v - 2 <n, v> n` have Gram entries `0`, `1` and `-phi`.
//! [`ProductCells::of`] recognises those entries in the `f64` gluings
//! (the smallest numerators within 1e-9, over `2^k` for `k <= 3`) and
//! proves them: each gluing times its partner's is the identity,
//! exactly. Products of integers are checked: past `i128` (about 28
//! crossings straight across the octagon, distance 85) an element is
//! [`TooFar`]. The sphere
//! (S2xS1 and its twists) has no sides: its copies are named by `steps`
//! alone.
//!
//! WGSL twin: the table walk in `bevy_manifold_gpu`'s
//! `shaders/product.wgsl` (`cross_cell`, `product_cell_id`), which reads
//! the tiles this module computes for a table of cells around the camera
//! ([`ProductCellTable`]).
//!
//! ```
//! use bevy_manifold_core::space::product::ProductSpace;
//! use bevy_manifold_core::space::product_cells::ProductCells;
//! let space = ProductSpace::genus_two_x_s1(1.0);
//! let cells = ProductCells::of(&space).expect("the octagon is over Z[sqrt 2]");
//! // Round a corner of the octagon: the eight corners meet at one point,
//! // so crossing the sides that meet there in turn comes home.
//! let home = cells.element(&[0, 5, 2, 7, 4, 1, 6, 3]).unwrap();
//! assert_eq!(cells.id(&home), cells.id(&cells.identity()));
//! // Up through the top, then across a side: another copy.
//! let up = cells.element(&[space.top(), 0]).unwrap();
//! assert_ne!(cells.id(&up), cells.id(&cells.identity()));
//! ```

use super::cell_id::{CellId, hash32};
use super::exact::TooFar;
use super::product::{ProductGluing, ProductSpace};
use crate::geometry::product::ProductGeometry;
use glam::{DMat3, DVec3};
use std::collections::HashMap;
use std::collections::hash_map::Entry;

/// A quadratic ring `Z[w]`, `w^2 = p + q w`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Ring {
    p: i128,
    q: i128,
    w: f64,
}

/// The rings [`ProductCells::of`] tries: `Z[sqrt 2]`, `Z[phi]`,
/// `Z[sqrt 3]`.
const RINGS: [Ring; 3] = [
    Ring {
        p: 2,
        q: 0,
        w: std::f64::consts::SQRT_2,
    },
    Ring {
        p: 1,
        q: 1,
        w: 1.618_033_988_749_895,
    },
    Ring {
        p: 3,
        q: 0,
        w: 1.732_050_807_568_877_2,
    },
];

/// `a + b w` in a [`Ring`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
struct Quad {
    a: i128,
    b: i128,
}

impl Quad {
    const ZERO: Quad = Quad { a: 0, b: 0 };
    const ONE: Quad = Quad { a: 1, b: 0 };

    fn add(self, o: Quad) -> Result<Quad, TooFar> {
        Ok(Quad {
            a: self.a.checked_add(o.a).ok_or(TooFar)?,
            b: self.b.checked_add(o.b).ok_or(TooFar)?,
        })
    }

    /// `(a + b w)(c + d w) = ac + bd p + (ad + bc + bd q) w`.
    fn mul(self, o: Quad, r: Ring) -> Result<Quad, TooFar> {
        let m = |x: i128, y: i128| x.checked_mul(y).ok_or(TooFar);
        let bd = m(self.b, o.b)?;
        Ok(Quad {
            a: m(self.a, o.a)?.checked_add(m(bd, r.p)?).ok_or(TooFar)?,
            b: m(self.a, o.b)?
                .checked_add(m(self.b, o.a)?)
                .and_then(|s| s.checked_add(bd.checked_mul(r.q)?))
                .ok_or(TooFar)?,
        })
    }

    fn is_even(self) -> bool {
        self.a & 1 == 0 && self.b & 1 == 0
    }

    fn half(self) -> Quad {
        Quad {
            a: self.a >> 1,
            b: self.b >> 1,
        }
    }

    /// The `a + b w` over `2^shift` nearest `x`, with `|b| <= 64`, if
    /// one is within 1e-9 (relative to `x`'s size).
    fn recognise(x: f64, shift: u32, r: Ring) -> Option<Quad> {
        let scaled = x * f64::from(1u32 << shift);
        let tolerance = 1e-9 * scaled.abs().max(1.0);
        (0..=128i128)
            .map(|k| if k % 2 == 0 { k / 2 } else { -(k + 1) / 2 })
            .find_map(|b| {
                let a = (scaled - b as f64 * r.w).round();
                (a.abs() < 1e15 && (scaled - a - b as f64 * r.w).abs() < tolerance).then_some(Quad { a: a as i128, b })
            })
    }
}

/// A 3x3 matrix over a [`Ring`] divided by `2^shift`, kept with the
/// least shift (so equal matrices are equal values).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct Dyadic<const N: usize> {
    m: [[Quad; 3]; N],
    shift: u32,
}

type Matrix = Dyadic<3>;
/// A column vector over the ring, as a 1x3 (transposed) array.
type Vector = Dyadic<1>;

impl<const N: usize> Dyadic<N> {
    /// Halves while every entry is even.
    fn reduced(mut self) -> Self {
        while self.shift > 0 && self.m.iter().flatten().all(|q| q.is_even()) {
            for q in self.m.iter_mut().flatten() {
                *q = q.half();
            }
            self.shift -= 1;
        }
        self
    }
}

impl Matrix {
    fn identity() -> Self {
        let mut m = [[Quad::ZERO; 3]; 3];
        for (i, row) in m.iter_mut().enumerate() {
            row[i] = Quad::ONE;
        }
        Dyadic { m, shift: 0 }
    }

    fn mul(&self, o: &Matrix, r: Ring) -> Result<Matrix, TooFar> {
        let mut m = [[Quad::ZERO; 3]; 3];
        for (i, row) in m.iter_mut().enumerate() {
            for (j, out) in row.iter_mut().enumerate() {
                for k in 0..3 {
                    *out = out.add(self.m[i][k].mul(o.m[k][j], r)?)?;
                }
            }
        }
        let shift = self.shift.checked_add(o.shift).filter(|s| *s < 120).ok_or(TooFar)?;
        Ok(Dyadic { m, shift }.reduced())
    }

    fn apply(&self, v: &Vector, r: Ring) -> Result<Vector, TooFar> {
        let mut m = [[Quad::ZERO; 3]; 1];
        for (i, out) in m[0].iter_mut().enumerate() {
            for k in 0..3 {
                *out = out.add(self.m[i][k].mul(v.m[0][k], r)?)?;
            }
        }
        let shift = self.shift.checked_add(v.shift).filter(|s| *s < 120).ok_or(TooFar)?;
        Ok(Dyadic { m: [m[0]], shift }.reduced())
    }

    /// The `f64` matrix `a` recognised over the ring, with the least shift
    /// up to 3 that recognises every entry.
    fn recognise(a: DMat3, r: Ring) -> Option<Matrix> {
        (0..=3).find_map(|shift| {
            let mut m = [[Quad::ZERO; 3]; 3];
            for (i, row) in m.iter_mut().enumerate() {
                for (j, out) in row.iter_mut().enumerate() {
                    *out = Quad::recognise(a.col(j)[i], shift, r)?;
                }
            }
            Some(Dyadic { m, shift }.reduced())
        })
    }
}

/// An element of a product space's group, exactly: the surface part over
/// the space's ring (in its basis; the identity for the sphere) and
/// `t -> flip t + steps L` on the line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ProductElement {
    surface: Matrix,
    /// 1 or -1.
    flip: i8,
    /// The line's translation, in heights of the prism.
    steps: i64,
}

impl ProductElement {
    /// The identity, the origin copy, in every space.
    pub const IDENTITY: ProductElement = ProductElement {
        surface: Dyadic {
            m: [
                [Quad::ONE, Quad::ZERO, Quad::ZERO],
                [Quad::ZERO, Quad::ONE, Quad::ZERO],
                [Quad::ZERO, Quad::ZERO, Quad::ONE],
            ],
            shift: 0,
        },
        flip: 1,
        steps: 0,
    };

    /// Heights of the prism the element moves the line by: the copy's
    /// place up the line.
    #[must_use]
    pub fn steps(&self) -> i64 {
        self.steps
    }

    /// True where the element turns the line upside down.
    #[must_use]
    pub fn flips(&self) -> bool {
        self.flip < 0
    }
}

/// The exact group of a product space, for the ids of its cells: the
/// gluings over a quadratic ring, proven to pair up.
///
/// ```
/// use bevy_manifold_core::space::product::ProductSpace;
/// use bevy_manifold_core::space::product_cells::ProductCells;
/// let space = ProductSpace::mirrored_prism(5, 1.0);
/// let cells = ProductCells::of(&space).expect("the right-angled pentagon is over Z[phi]");
/// // Adjacent sides meet at right angles: their mirrors commute.
/// let a = cells.element(&[0, 1]).unwrap();
/// let b = cells.element(&[1, 0]).unwrap();
/// assert_eq!(cells.id(&a), cells.id(&b));
/// ```
#[derive(Clone, Debug)]
pub struct ProductCells {
    /// The ring, for a space with sides.
    ring: Option<Ring>,
    /// Per face `f`, the element a crossing of `f` multiplies by (on the
    /// right): its gluing's inverse, the partner's gluing.
    crossings: Vec<ProductElement>,
    /// The polygon's centre in the basis, exactly: names a copy of the
    /// polygon by its image.
    centre: Vector,
    partners: Vec<usize>,
    /// The polygon's sides: the faces before the bottom and the top.
    sides: usize,
}

impl ProductCells {
    /// The space's exact group, or `None` where its gluings are not over
    /// `Z[sqrt 2]`, `Z[phi]` or `Z[sqrt 3]` in the basis of its sides'
    /// normals (such a space has no cell ids), or do not pair up exactly.
    #[must_use]
    pub fn of(space: &ProductSpace) -> Option<Self> {
        let l = space.height;
        let vertical = |gluing: &ProductGluing| {
            let iso = gluing.isometry();
            let steps = (iso.shift / l).round();
            ((iso.shift - steps * l).abs() < 1e-9 * l.max(1.0) && steps.abs() < 1e6 && iso.flip.abs() == 1.0)
                .then_some((if iso.flip > 0.0 { 1i8 } else { -1 }, steps as i64))
        };
        let partners: Vec<usize> = (0..space.face_count()).map(|f| space.partner(f)).collect();
        if space.sides.len() < 3 {
            // The sphere: the surface part does not name the copy.
            let crossings = partners
                .iter()
                .map(|&p| {
                    let (flip, steps) = vertical(&space.gluings[p])?;
                    Some(ProductElement {
                        surface: Matrix::identity(),
                        flip,
                        steps,
                    })
                })
                .collect::<Option<Vec<_>>>()?;
            return Self::proven(
                0,
                None,
                crossings,
                Dyadic {
                    m: [[Quad::ZERO; 3]],
                    shift: 0,
                },
                partners,
            );
        }
        let n = &space.sides;
        let basis = DMat3::from_cols(n[0], n[1], n[2]);
        if basis.determinant().abs() < 1e-9 {
            return None;
        }
        let inverse = basis.inverse();
        let centre: DVec3 = inverse * n.iter().sum::<DVec3>();
        // The centre must be inside the polygon, where no element but the
        // identity fixes it.
        let inside = basis * centre;
        let inside = if inside.z < 0.0 && matches!(space.geometry, ProductGeometry::H2xR) {
            -inside
        } else {
            inside
        };
        if !space.sides.iter().all(|n| space.geometry.form(*n, inside) < -1e-9) {
            return None;
        }
        RINGS.iter().find_map(|&ring| {
            let vector = (0..=3).find_map(|shift| {
                let mut m = [[Quad::ZERO; 3]; 1];
                for (i, out) in m[0].iter_mut().enumerate() {
                    *out = Quad::recognise(centre[i], shift, ring)?;
                }
                Some(Dyadic { m, shift }.reduced())
            })?;
            let crossings = partners
                .iter()
                .map(|&p| {
                    let (flip, steps) = vertical(&space.gluings[p])?;
                    let surface = Matrix::recognise(inverse * space.gluings[p].isometry().surface * basis, ring)?;
                    Some(ProductElement { surface, flip, steps })
                })
                .collect::<Option<Vec<_>>>()?;
            Self::proven(n.len(), Some(ring), crossings, vector, partners.clone())
        })
    }

    /// The cells if every crossing undoes its partner's, exactly.
    fn proven(
        sides: usize,
        ring: Option<Ring>,
        crossings: Vec<ProductElement>,
        centre: Vector,
        partners: Vec<usize>,
    ) -> Option<Self> {
        let cells = ProductCells {
            ring,
            crossings,
            centre,
            partners,
            sides,
        };
        let identity = cells.identity();
        (0..cells.crossings.len())
            .all(|f| {
                let there = cells.cross(&identity, f);
                there.and_then(|e| cells.cross(&e, cells.partners[f])) == Ok(identity)
            })
            .then_some(cells)
    }

    /// The identity: the origin copy.
    #[must_use]
    pub fn identity(&self) -> ProductElement {
        ProductElement::IDENTITY
    }

    /// The faces of the space.
    #[must_use]
    pub fn faces(&self) -> usize {
        self.crossings.len()
    }

    /// The copy across `face` of copy `e`: `e` times the face's crossing.
    ///
    /// # Errors
    /// [`TooFar`] as [`ProductCells::compose`].
    pub fn cross(&self, e: &ProductElement, face: usize) -> Result<ProductElement, TooFar> {
        self.compose(e, &self.crossings[face])
    }

    /// The copy the faces crossed in turn reach from the origin copy.
    ///
    /// # Errors
    /// [`TooFar`] as [`ProductCells::cross`].
    pub fn element(&self, faces: &[usize]) -> Result<ProductElement, TooFar> {
        faces.iter().try_fold(self.identity(), |e, &f| self.cross(&e, f))
    }

    /// `a` after `b`: the copy `b` names, seen from copy `a`.
    ///
    /// # Errors
    /// [`TooFar`] where the surface part's integers pass `i128`, or the
    /// steps `2^30`.
    pub fn compose(&self, a: &ProductElement, b: &ProductElement) -> Result<ProductElement, TooFar> {
        Ok(ProductElement {
            surface: match self.ring {
                Some(ring) => a.surface.mul(&b.surface, ring)?,
                None => a.surface,
            },
            flip: a.flip * b.flip,
            steps: a
                .steps
                .checked_add(i64::from(a.flip) * b.steps)
                .filter(|s| s.abs() < 1 << 30)
                .ok_or(TooFar)?,
        })
    }

    /// The id of the copy of the polygon `e`'s surface part reaches: 62
    /// bits hashed from its centre's exact image, `[0, 0]` for the
    /// origin's, `[u32::MAX; 2]` where it is too far to name.
    #[must_use]
    pub fn tile(&self, e: &ProductElement) -> [u32; 2] {
        let Some(ring) = self.ring else { return [0, 0] };
        let Ok(image) = e.surface.apply(&self.centre, ring) else {
            return [u32::MAX, u32::MAX];
        };
        if image == self.centre {
            return [0, 0];
        }
        let mut lo = hash32(image.shift);
        let mut hi = hash32(!image.shift);
        for q in image.m[0] {
            for x in [q.a, q.b] {
                for word in 0..4 {
                    let w = (x >> (32 * word)) as u32;
                    lo = hash32(lo ^ w);
                    hi = hash32(hi.rotate_left(5) ^ w);
                }
            }
        }
        // Never the origin's, never the table's "beyond".
        [lo | 1, hi & 0x3fff_ffff]
    }

    /// The copy's [`CellId`]: its [`ProductCells::tile`] and its steps,
    /// combined by [`product_cell_id`].
    #[must_use]
    pub fn id(&self, e: &ProductElement) -> CellId {
        product_cell_id(self.tile(e), e.steps)
    }
}

/// The [`CellId`] of the copy at `steps` up the line over the copy of the
/// polygon `tile` ([`ProductCells::tile`]): 0 for the origin copy, else
/// the tile's bits crossed with the steps' hash, in 32-bit arithmetic so
/// the GPU (`product_cell_id` in `bevy_manifold_gpu`'s `shaders/product.wgsl`)
/// gets the same; [`CellId::BEYOND_TABLE`] for the unknown tile
/// (`[u32::MAX; 2]`, too far to name).
/// Steps are within `2^30` ([`ProductCells::cross`] refuses more).
#[must_use]
pub fn product_cell_id(tile: [u32; 2], steps: i64) -> CellId {
    if tile == [u32::MAX; 2] {
        return CellId::BEYOND_TABLE;
    }
    if tile == [0, 0] && steps == 0 {
        return CellId(0);
    }
    let s = steps as i32 as u32;
    let lo = tile[0] ^ hash32(s);
    let hi = (tile[1] ^ hash32(s ^ 0x9e37_79b9)) & 0x3fff_ffff;
    CellId(u64::from(lo) | (u64::from(hi) << 32))
}

/// Cells by default in a [`ProductCellTable`]: 8 bytes of id and 4 per
/// face each, 1 MiB or so for ten faces.
pub const DEFAULT_PRODUCT_TABLE_CELLS: usize = 1 << 15;

/// The surface parts of the cells around the origin copy, breadth first,
/// for the GPU's walk: cell `k` is an element `e_k` of the surface group
/// with its twists, and `neighbours[k * faces + f]` the index of the
/// surface part of `e_k` times face `f`'s crossing ([`OUTSIDE`] where it
/// is not in the table). The GPU counts `steps` and `flip` itself, exactly,
/// and combines them with the tile ids of [`ProductCellTable::tiles_around`]
/// ([`product_cell_id`]).
///
/// [`OUTSIDE`]: super::cell_table::OUTSIDE
#[derive(Clone, Debug)]
pub struct ProductCellTable {
    elements: Vec<ProductElement>,
    /// `[k * faces + f]`: the index of `e_k` crossed by `f`.
    pub neighbours: Vec<u32>,
    faces: usize,
}

impl ProductCellTable {
    /// Grows the table breadth first up to `budget` cells (whole spheres
    /// of crossings only). The elements' line parts are dropped: only the
    /// surface parts are kept (one cell for the sphere).
    #[must_use]
    pub fn grow(cells: &ProductCells, budget: usize) -> Self {
        let n = cells.faces();
        let flat = |e: ProductElement| ProductElement { flip: 1, steps: 0, ..e };
        let mut elements = vec![cells.identity()];
        let mut index: HashMap<ProductElement, u32> = HashMap::from([(cells.identity(), 0)]);
        // Crosses from the cells `from..` by `faces`, adding the new ones;
        // with `close`, from the new ones too, until none is new.
        let mut reach =
            |elements: &mut Vec<ProductElement>, from: usize, faces: std::ops::Range<usize>, close: bool| {
                let end = elements.len();
                let mut k = from;
                while k < if close { elements.len() } else { end } && elements.len() <= budget {
                    for f in faces.clone() {
                        if let Ok(e) = cells.cross(&elements[k], f).map(flat)
                            && let Entry::Vacant(slot) = index.entry(e)
                        {
                            slot.insert(elements.len() as u32);
                            elements.push(e);
                        }
                    }
                    k += 1;
                }
            };
        // A sphere is closed under the bottom and top's crossings, whose
        // surface parts (a twist, of finite order) do not move the
        // polygon: a ray going up and down stays in the table.
        let (sides, vertical) = (0..cells.sides, cells.sides..n);
        reach(&mut elements, 0, vertical.clone(), true);
        let mut sphere = 0..elements.len();
        loop {
            let start = elements.len();
            reach(&mut elements, sphere.start, sides.clone(), false);
            reach(&mut elements, start, vertical.clone(), true);
            if elements.len() == start {
                break;
            }
            if elements.len() > budget {
                // Whole spheres only: drop the one that did not fit.
                for e in &elements[start..] {
                    index.remove(e);
                }
                elements.truncate(start);
                break;
            }
            sphere = start..elements.len();
        }
        let neighbours = elements
            .iter()
            .flat_map(|e| {
                (0..n).map(|f| {
                    cells
                        .cross(e, f)
                        .ok()
                        .and_then(|next| index.get(&flat(next)).copied())
                        .unwrap_or(super::cell_table::OUTSIDE)
                })
            })
            .collect();
        ProductCellTable {
            elements,
            neighbours,
            faces: n,
        }
    }

    /// Cells in the table.
    #[must_use]
    pub fn len(&self) -> usize {
        self.elements.len()
    }

    /// Never: the origin is always in.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.elements.is_empty()
    }

    /// Faces per cell.
    #[must_use]
    pub fn faces(&self) -> usize {
        self.faces
    }

    /// The tile of each cell seen from a camera in copy `camera`: the
    /// [`ProductCells::tile`] of `camera` times `e_k` (`u32::MAX` pairs
    /// where that is [`TooFar`]).
    #[must_use]
    pub fn tiles_around(&self, cells: &ProductCells, camera: &ProductElement) -> Vec<[u32; 2]> {
        self.elements
            .iter()
            .map(|e| {
                cells
                    .compose(camera, e)
                    .map_or([u32::MAX, u32::MAX], |c| cells.tile(&c))
            })
            .collect()
    }
}
