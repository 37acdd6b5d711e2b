//! Exact group elements of hyperbolic spaces over the golden field, and
//! path-independent cell ids from them at any distance.
//!
//! The groups of the Seifert-Weber space and of the mirrored right-angled
//! dodecahedron sit inside the symmetries of the `{5,3,5}` and `{5,3,4}`
//! honeycombs, which are arithmetic over `Q(sqrt 5)`. In the hyperboloid
//! chart with the time coordinate rescaled (`w' = s w`, one `s` per
//! space), every pairing is a 4x4 matrix whose entries are
//! `(a + b phi) / 2^k` with integers `a`, `b` (`phi` the golden ratio).
//! Products of such matrices are computed exactly in integers, so the
//! element a sequence of crossings reaches, and the copy of the domain it
//! names, depend on the group element alone: no rounding, at any distance.
//!
//! [`ExactGroup::of`] recognises the golden entries in a space's `f64`
//! pairings (the smallest numerators within 1e-9), then proves the
//! recognised matrices are the group: each pairing times its partner's is
//! the identity and each edge cycle's transformation to its order is the
//! identity, exactly. By Poincare's polyhedron theorem those relations
//! present the group, so the exact matrices generate the same group as the
//! pairings. A space that fails (a library space over another field, or
//! not hyperbolic) keeps the hashed ids of [`super::cells`].
//!
//! A copy `g(D)` is named by `g`'s last column, the exact image of the
//! domain's centre (no element but the identity fixes the centre, where
//! the action is free). The integers grow like `e^d` at distance `d`
//! from the origin copy: `i128` holds them to about distance 80 (about 64
//! random crossings), and integers of any size ([`int::BigInt`]) take over
//! beyond, up to about distance 5,600 ([`int::MAX_BITS`]), where the
//! arithmetic reports [`TooFar`] rather than growing without bound.
//!
//! ```
//! use bevy_manifold_core::space::catalog;
//! use bevy_manifold_core::space::exact::ExactGroup;
//! let sw = catalog::seifert_weber();
//! let group = ExactGroup::of(&sw).expect("Seifert-Weber is golden");
//! // Two crossings through a face and back through its partner: home.
//! let home = group.element(&[3, sw.faces()[3].partner]).unwrap();
//! assert_eq!(home, group.identity());
//! // The same copy by two routes around an edge (an edge cycle is a loop).
//! let cycle = &sw.edge_cycles()[0];
//! assert_eq!(group.element(&group.cycle_word(cycle)).unwrap(), group.identity());
//! ```

use super::{EdgeCycle, FaceKind, Space};
use crate::geometry::Geometry;
use crate::space::cell_id::CellId;
use glam::DMat4;
use int::{BigInt, Int};

pub mod int;

/// `a + b phi` with `phi = (1 + sqrt 5) / 2`: an integer of the golden
/// field, over `i128` or [`BigInt`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
struct Golden<N> {
    a: N,
    b: N,
}

/// The golden ratio.
pub const PHI: f64 = 1.618_033_988_749_895;

/// The element is farther from the origin copy than exact ids reach
/// (about distance 5,600, [`int::MAX_BITS`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("the cell is too far from the origin copy for exact ids")]
pub struct TooFar;

impl<N: Int> Golden<N> {
    fn zero() -> Self {
        Golden {
            a: N::zero(),
            b: N::zero(),
        }
    }

    fn one() -> Self {
        Golden {
            a: N::one(),
            b: N::zero(),
        }
    }

    fn add(&self, o: &Self) -> Option<Self> {
        Some(Golden {
            a: self.a.add(&o.a)?,
            b: self.b.add(&o.b)?,
        })
    }

    /// `(a + b phi)(c + d phi) = (ac + bd) + (ad + bc + bd) phi`, as
    /// `phi^2 = phi + 1`.
    fn mul(&self, o: &Self) -> Option<Self> {
        let bd = self.b.mul(&o.b)?;
        Some(Golden {
            a: self.a.mul(&o.a)?.add(&bd)?,
            b: self.a.mul(&o.b)?.add(&self.b.mul(&o.a)?)?.add(&bd)?,
        })
    }

    fn is_even(&self) -> bool {
        self.a.is_even() && self.b.is_even()
    }

    fn half(&self) -> Self {
        Golden {
            a: self.a.half(),
            b: self.b.half(),
        }
    }

    fn to_f64(&self) -> f64 {
        self.a.to_f64() + self.b.to_f64() * PHI
    }

    fn to_big(&self) -> Golden<BigInt> {
        Golden {
            a: self.a.to_big(),
            b: self.b.to_big(),
        }
    }
}

impl Golden<i128> {
    /// The smallest `(a + b phi) / 2^k` within `tol` of `x` (relative to
    /// `max(1, |x|)`), `k` up to `MAX_RECOGNISED_SHIFT`, `|b|` up to
    /// `MAX_RECOGNISED_B`: the golden number a rounded entry stands for.
    fn recognise(x: f64, tol: f64) -> Option<(Self, u32)> {
        if !x.is_finite() {
            return None;
        }
        let tol = tol * x.abs().max(1.0);
        for k in 0..=MAX_RECOGNISED_SHIFT {
            let y = x * f64::from(1u32 << k);
            for b in 0..=MAX_RECOGNISED_B {
                for b in [b, -b] {
                    let rest = y - f64::from(b) * PHI;
                    let a = rest.round();
                    if (rest - a).abs() <= tol * f64::from(1u32 << k) {
                        return Some((
                            Golden {
                                a: a as i128,
                                b: i128::from(b),
                            },
                            k,
                        ));
                    }
                }
            }
        }
        None
    }
}

const MAX_RECOGNISED_SHIFT: u32 = 4;
const MAX_RECOGNISED_B: i32 = 256;
/// Most factors of 2 a product may keep in its denominator: the groups
/// recognised keep a bounded denominator (they preserve a lattice), so a
/// growing one means the recognition was wrong.
const MAX_SHIFT: u32 = 16;

/// A 4x4 matrix over the golden field: `m[row][col] / 2^shift`, reduced
/// (no common factor 2 left unless `shift` is 0).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
struct GoldenMatrix<N> {
    m: [[Golden<N>; 4]; 4],
    shift: u32,
}

impl<N: Int> GoldenMatrix<N> {
    fn identity() -> Self {
        let m = core::array::from_fn(|i| core::array::from_fn(|j| if i == j { Golden::one() } else { Golden::zero() }));
        GoldenMatrix { m, shift: 0 }
    }

    /// The product, `None` when `N` overflows.
    fn mul(&self, o: &Self) -> Option<Self> {
        let mut m: [[Golden<N>; 4]; 4] = core::array::from_fn(|_| core::array::from_fn(|_| Golden::zero()));
        for (i, row) in m.iter_mut().enumerate() {
            for (j, out) in row.iter_mut().enumerate() {
                let mut sum = Golden::zero();
                for k in 0..4 {
                    sum = sum.add(&self.m[i][k].mul(&o.m[k][j])?)?;
                }
                *out = sum;
            }
        }
        let mut r = GoldenMatrix {
            m,
            shift: self.shift + o.shift,
        };
        r.reduce();
        Some(r)
    }

    fn reduce(&mut self) {
        while self.shift > 0 && self.m.iter().flatten().all(Golden::is_even) {
            for x in self.m.iter_mut().flatten() {
                *x = x.half();
            }
            self.shift -= 1;
        }
    }

    fn entry_f64(&self, i: usize, j: usize) -> f64 {
        self.m[i][j].to_f64() / 2f64.powi(self.shift as i32)
    }

    fn to_big(&self) -> GoldenMatrix<BigInt> {
        GoldenMatrix {
            m: core::array::from_fn(|i| core::array::from_fn(|j| self.m[i][j].to_big())),
            shift: self.shift,
        }
    }
}

impl GoldenMatrix<BigInt> {
    /// The `i128` form, when every entry fits: elements keep one form per
    /// value, so `==` and `Hash` are on the value.
    fn to_small(&self) -> Option<GoldenMatrix<i128>> {
        let mut m = [[Golden::<i128>::default(); 4]; 4];
        for (i, row) in m.iter_mut().enumerate() {
            for (j, out) in row.iter_mut().enumerate() {
                let g = &self.m[i][j];
                *out = Golden {
                    a: g.a.to_i128()?,
                    b: g.b.to_i128()?,
                };
            }
        }
        Some(GoldenMatrix { m, shift: self.shift })
    }
}

/// An element of a golden group, exactly: equal elements are equal
/// values (`==`, `Hash`), whatever words reached them.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ExactElement(Repr);

/// `i128` while every entry fits, else integers of any size.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum Repr {
    Small(Box<GoldenMatrix<i128>>),
    Big(Box<GoldenMatrix<BigInt>>),
}

impl ExactElement {
    /// The id of the copy this element carries the domain to: a 62-bit
    /// hash of its exact image of the centre, 0 for the origin copy. The
    /// lattice and far bits of [`CellId`] stay clear.
    #[must_use]
    pub fn cell_id(&self) -> CellId {
        if self.is_identity() {
            return CellId(0);
        }
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        let mut eat = |x: u64| {
            h = (h ^ x).wrapping_mul(0x0000_0100_0000_01b3);
            h ^= h >> 29;
        };
        // Each value has one form (Small whenever it fits), so hashing the
        // forms differently keeps equal values on equal ids.
        let shift = match &self.0 {
            Repr::Small(m) => {
                for row in &m.m {
                    for v in [row[3].a, row[3].b] {
                        eat(v as u64);
                        eat((v >> 64) as u64);
                    }
                }
                m.shift
            }
            Repr::Big(m) => {
                for row in &m.m {
                    for v in [&row[3].a, &row[3].b] {
                        let (negative, limbs) = v.parts();
                        eat(u64::from(negative) | 2);
                        eat(limbs.len() as u64);
                        limbs.iter().for_each(|&l| eat(u64::from(l)));
                    }
                }
                m.shift
            }
        };
        eat(u64::from(shift));
        CellId((h & !((1 << 63) | CellId::FAR)).max(1))
    }

    fn is_identity(&self) -> bool {
        matches!(&self.0, Repr::Small(m) if **m == GoldenMatrix::identity())
    }

    /// The exact image of the domain's centre in the rescaled chart
    /// (`x, y, z, s w`): `(a, b)` of `a + b phi` per coordinate, over
    /// `2^shift`. What names the copy.
    #[must_use]
    pub fn centre(&self) -> ([(BigInt, BigInt); 4], u32) {
        match &self.0 {
            Repr::Small(m) => (
                core::array::from_fn(|i| (m.m[i][3].a.to_big(), m.m[i][3].b.to_big())),
                m.shift,
            ),
            Repr::Big(m) => (
                core::array::from_fn(|i| (m.m[i][3].a.clone(), m.m[i][3].b.clone())),
                m.shift,
            ),
        }
    }

    /// True while the integers fit in `i128` (about distance 80).
    #[must_use]
    pub fn is_small(&self) -> bool {
        matches!(self.0, Repr::Small(_))
    }

    fn entry_f64(&self, i: usize, j: usize) -> f64 {
        match &self.0 {
            Repr::Small(m) => m.entry_f64(i, j),
            Repr::Big(m) => m.entry_f64(i, j),
        }
    }
}

/// The exact group of a hyperbolic space whose pairings are golden.
#[derive(Clone, Debug)]
pub struct ExactGroup {
    /// `s` of the rescaled chart `w' = s w`.
    scale: f64,
    /// The exact `crossing(f)` (`T_f^-1`) per face, rescaled.
    crossings: Vec<GoldenMatrix<i128>>,
    /// The same over integers of any size.
    big_crossings: Vec<GoldenMatrix<BigInt>>,
    /// The partner of each face.
    partners: Vec<usize>,
}

impl ExactGroup {
    /// The exact group of `space`, when it is hyperbolic and its pairings
    /// are golden matrices in a rescaled chart whose relations hold
    /// exactly; `None` otherwise.
    #[must_use]
    pub fn of(space: &Space) -> Option<Self> {
        if space.geometry() != Geometry::Hyperbolic {
            return None;
        }
        let faces = space.faces();
        // s: the largest time-row entry becomes 1.
        let m = faces
            .iter()
            .flat_map(|f| (0..3).map(move |i| f.pairing.col(i).w.abs()))
            .fold(0.0, f64::max);
        if !(m > 1e-6 && m.is_finite()) {
            return None;
        }
        let scale = 1.0 / m;
        let pairings = faces
            .iter()
            .map(|f| recognise_matrix(f.pairing, scale))
            .collect::<Option<Vec<_>>>()?;
        let crossings: Vec<GoldenMatrix<i128>> = faces.iter().map(|f| pairings[f.partner].clone()).collect();
        let group = ExactGroup {
            scale,
            big_crossings: crossings.iter().map(GoldenMatrix::to_big).collect(),
            crossings,
            partners: faces.iter().map(|f| f.partner).collect(),
        };
        group.relations_hold(space).then_some(group)
    }

    /// The identity: the origin copy.
    #[must_use]
    pub fn identity(&self) -> ExactElement {
        ExactElement(Repr::Small(Box::new(GoldenMatrix::identity())))
    }

    /// How many faces (generators).
    #[must_use]
    pub fn faces(&self) -> usize {
        self.crossings.len()
    }

    /// The element after crossing `face` from `g`: `g T_face^-1`, as the
    /// tracer composes it.
    ///
    /// # Errors
    /// [`TooFar`] past [`int::MAX_BITS`].
    ///
    /// # Panics
    /// When `face` is not a face of the space.
    pub fn cross(&self, g: &ExactElement, face: usize) -> Result<ExactElement, TooFar> {
        let big = match &g.0 {
            Repr::Small(m) => match m.mul_small(&self.crossings[face]) {
                Some(r) => return checked_shift(Repr::Small(Box::new(r))),
                None => m.to_big().mul(&self.big_crossings[face]),
            },
            Repr::Big(m) => m.mul(&self.big_crossings[face]),
        }
        .ok_or(TooFar)?;
        from_big(big)
    }

    /// The product `a b`: the copy `b` names, seen from the copy `a`
    /// names (a walk from `a` that reaches `b` from the origin copy).
    ///
    /// # Errors
    /// [`TooFar`] past [`int::MAX_BITS`].
    pub fn compose(&self, a: &ExactElement, b: &ExactElement) -> Result<ExactElement, TooFar> {
        if let (Repr::Small(x), Repr::Small(y)) = (&a.0, &b.0)
            && let Some(r) = x.mul_small(y)
        {
            return checked_shift(Repr::Small(Box::new(r)));
        }
        let big = |r: &Repr| match r {
            Repr::Small(m) => m.to_big(),
            Repr::Big(m) => (**m).clone(),
        };
        from_big(big(&a.0).mul(&big(&b.0)).ok_or(TooFar)?)
    }

    /// The element the crossings `faces` reach from the origin copy.
    ///
    /// # Errors
    /// [`TooFar`] past [`int::MAX_BITS`].
    ///
    /// # Panics
    /// When a face is not a face of the space.
    pub fn element(&self, faces: &[usize]) -> Result<ExactElement, TooFar> {
        faces.iter().try_fold(self.identity(), |g, &f| self.cross(&g, f))
    }

    /// The crossings that walk around `cycle`'s edge `cycle.order` times:
    /// its transformation `T_{a_m} ... T_{a_1}` (`T_a` is the crossing of
    /// `a`'s partner) to its order, a relation of the group.
    #[must_use]
    pub fn cycle_word(&self, cycle: &EdgeCycle) -> Vec<usize> {
        let once: Vec<usize> = cycle.faces.iter().rev().map(|&a| self.partners[a]).collect();
        once.repeat(cycle.order as usize)
    }

    /// The partner of `face`: crossing `face` multiplies by the pairing of
    /// its partner.
    #[must_use]
    pub fn partner(&self, face: usize) -> usize {
        self.partners[face]
    }

    /// The element as an `f64` matrix in the usual chart (rounded).
    #[must_use]
    pub fn to_f64(&self, g: &ExactElement) -> DMat4 {
        let e = |i: usize, j: usize| {
            let x = g.entry_f64(i, j);
            match (i == 3, j == 3) {
                (true, false) => x / self.scale,
                (false, true) => x * self.scale,
                _ => x,
            }
        };
        DMat4::from_cols_array_2d(&[0, 1, 2, 3].map(|j| [e(0, j), e(1, j), e(2, j), e(3, j)]))
    }

    /// The rescaling `s` of the chart (`w' = s w`).
    #[must_use]
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// The pairings' exact relations: `T_f T_partner = 1` for every face
    /// and every edge cycle's transformation to its order is 1.
    fn relations_hold(&self, space: &Space) -> bool {
        let faces_ok = space.faces().iter().enumerate().all(|(f, face)| {
            let p = if face.kind == FaceKind::Mirror { f } else { face.partner };
            self.cross(&self.identity(), f)
                .and_then(|g| self.cross(&g, p))
                .is_ok_and(|g| g.is_identity())
        });
        faces_ok
            && space
                .edge_cycles()
                .iter()
                .all(|c| self.element(&self.cycle_word(c)).is_ok_and(|g| g.is_identity()))
    }
}

/// A product in big integers, in its one form: `i128` when it fits.
fn from_big(m: GoldenMatrix<BigInt>) -> Result<ExactElement, TooFar> {
    checked_shift(match m.to_small() {
        Some(small) => Repr::Small(Box::new(small)),
        None => Repr::Big(Box::new(m)),
    })
}

fn checked_shift(r: Repr) -> Result<ExactElement, TooFar> {
    let shift = match &r {
        Repr::Small(m) => m.shift,
        Repr::Big(m) => m.shift,
    };
    if shift > MAX_SHIFT {
        Err(TooFar)
    } else {
        Ok(ExactElement(r))
    }
}

impl GoldenMatrix<i128> {
    /// The product, as [`GoldenMatrix::mul`] gives it, without checking
    /// each operation where the operands' sizes rule overflow out: an
    /// entry of the product is four golden products, each at most three
    /// integer products (the `phi` part: `ad + bc + bd`), so it is under
    /// `12 * 2^(bits(self) + bits(o)) < 2^(bits(self) + bits(o) + 4)`, and
    /// so is every partial sum. Below `2^127` nothing wraps. Checked
    /// `i128` products cost a library call each; near the origin copy, where
    /// the walk's elements are, the plain ones are about ten times cheaper.
    /// Past the bound it is [`GoldenMatrix::mul`], checked.
    fn mul_small(&self, o: &Self) -> Option<Self> {
        let bits = self.bits() + o.bits() + 4;
        if bits > 127 {
            return self.mul(o);
        }
        let m = if bits <= 63 {
            // Within i64 the same sums again, a machine product each.
            let narrow = |x: i128| x as i64;
            product(self, o, |x, y| narrow(x).wrapping_mul(narrow(y)), i128::from)
        } else {
            product(self, o, i128::wrapping_mul, |x| x)
        };
        let mut r = GoldenMatrix {
            m,
            shift: self.shift + o.shift,
        };
        r.reduce();
        Some(r)
    }

    /// The most bits of any integer's magnitude in the matrix.
    fn bits(&self) -> u32 {
        let all = self
            .m
            .iter()
            .flatten()
            .fold(0u128, |acc, g| acc | g.a.unsigned_abs() | g.b.unsigned_abs());
        128 - all.leading_zeros()
    }
}

/// The entries of `x y` over the golden field, each integer product made
/// by `mul` in an integer type `T` that the caller knows holds every sum,
/// then widened back by `wide`. `(a + b phi)(c + d phi) = (ac + bd) +
/// (ad + bc + bd) phi` ([`Golden::mul`], unchecked).
fn product<T: Copy + core::ops::Add<Output = T> + Default>(
    x: &GoldenMatrix<i128>,
    y: &GoldenMatrix<i128>,
    mul: impl Fn(i128, i128) -> T,
    wide: impl Fn(T) -> i128,
) -> [[Golden<i128>; 4]; 4] {
    core::array::from_fn(|i| {
        core::array::from_fn(|j| {
            let (mut a, mut b) = (T::default(), T::default());
            for k in 0..4 {
                let (p, q) = (&x.m[i][k], &y.m[k][j]);
                let bd = mul(p.b, q.b);
                a = a + mul(p.a, q.a) + bd;
                b = b + mul(p.a, q.b) + mul(p.b, q.a) + bd;
            }
            Golden { a: wide(a), b: wide(b) }
        })
    })
}

/// Recognises `pairing`, rescaled by `s`, as a golden matrix within 1e-9.
fn recognise_matrix(pairing: DMat4, s: f64) -> Option<GoldenMatrix<i128>> {
    let mut entries = [[(Golden::<i128>::default(), 0u32); 4]; 4];
    for (i, row) in entries.iter_mut().enumerate() {
        for (j, out) in row.iter_mut().enumerate() {
            let x = pairing.col(j)[i];
            let x = match (i == 3, j == 3) {
                (true, false) => x * s,
                (false, true) => x / s,
                _ => x,
            };
            *out = Golden::recognise(x, 1e-9)?;
        }
    }
    let shift = entries.iter().flatten().map(|e| e.1).max().unwrap_or(0);
    let m = entries.map(|row| {
        row.map(|(g, k)| {
            let f = 1i128 << (shift - k);
            Golden { a: g.a * f, b: g.b * f }
        })
    });
    let mut r = GoldenMatrix { m, shift };
    r.reduce();
    Some(r)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A matrix whose integers are drawn from `(-2^bits, 2^bits)` by a
    /// xorshift stream, or all `2^bits - 1` (the worst case for the bound:
    /// every term of every sum the largest it can be, and of one sign).
    fn matrix(state: &mut u64, bits: u32, extreme: bool) -> GoldenMatrix<i128> {
        let mut next = || {
            *state ^= *state << 13;
            *state ^= *state >> 7;
            *state ^= *state << 17;
            *state
        };
        let top = (1i128 << bits) - 1;
        let mut draw = || {
            if extreme {
                return top;
            }
            let wide = (i128::from(next()) << 64) | i128::from(next());
            let x = wide.rem_euclid(top + 1);
            if next() & 1 == 0 { x } else { -x }
        };
        GoldenMatrix {
            m: core::array::from_fn(|_| core::array::from_fn(|_| Golden { a: draw(), b: draw() })),
            shift: 0,
        }
    }

    /// The unchecked product against the product in big integers (limbs,
    /// another arithmetic): equal wherever it is given, and always given
    /// where the sizes allow it, up to the bound `bits + bits + 4 = 127`.
    #[test]
    fn unchecked_products_are_the_big_integer_products() {
        let mut state = 0x9e37_79b9_7f4a_7c15;
        // The i64 path up to 29 + 30 + 4 = 63 bits, the i128 one from 64.
        for (b1, b2) in [
            (1, 1),
            (3, 40),
            (20, 30),
            (29, 30),
            (30, 30),
            (61, 62),
            (62, 61),
            (100, 23),
            (62, 62),
            (63, 63),
            (70, 70),
        ] {
            for trial in 0..40 {
                let extreme = trial == 0;
                let x = matrix(&mut state, b1, extreme);
                let y = matrix(&mut state, b2, extreme);
                let big = x.to_big().mul(&y.to_big()).expect("far below the big limit");
                let eligible = b1 + b2 + 4 <= 127;
                match x.mul_small(&y) {
                    Some(fast) => assert_eq!(fast.to_big(), big, "{b1}+{b2} bits, trial {trial}"),
                    None => assert!(!eligible, "{b1}+{b2} bits, trial {trial}: refused within the bound"),
                }
                if eligible {
                    assert_eq!(
                        x.mul(&y),
                        x.mul_small(&y),
                        "{b1}+{b2} bits: checked and unchecked differ"
                    );
                }
            }
        }
    }
}
