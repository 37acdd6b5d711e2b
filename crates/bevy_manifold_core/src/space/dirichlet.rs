//! The Dirichlet domain of a group given by generators: the points closer
//! to the basepoint than to any of its images,
//! `D = { x : d(x, o) <= d(x, g o) for all g }`.
//!
//! 1. **Enumerate** the group breadth-first, products of generators and
//!    their inverses, keeping every element that moves the basepoint `o`
//!    less than a search radius `R` (told apart by `g o`; a second element
//!    with the same image fixes `o`, and a generic basepoint is taken).
//! 2. **Intersect** the bisector half-spaces of those elements. In the
//!    projective chart every bisector is an affine plane, so the domain is
//!    a convex polytope of R^3 cut from a box, one plane at a time.
//! 3. **Widen**: a bisector of `g` can touch `D` only if `d(o, g o)` is at
//!    most twice the circumradius; while `R` is less, it grows and the
//!    search repeats.
//! 4. **Pair** the face on the bisector of `g` with the face on that of
//!    `g^-1` by `T = g^-1`; a face paired with itself is a mirror when `g`
//!    fixes it, else a half-turn (refused: see
//!    [`GeneratorError::SelfPairedHalfTurn`]).
//! 5. **Prove**: the polyhedron with these pairings is validated as every
//!    space is (faces onto faces, edge cycles closing with angle `2 pi / k`),
//!    which by Poincare's polyhedron theorem makes it a fundamental domain
//!    of the group its pairings generate; and every given generator is
//!    reduced to the identity by those pairings (each step carrying its
//!    image of the basepoint strictly nearer), so that group is the whole
//!    group.
//!
//! The space comes out in coordinates that put the basepoint at the chart
//! origin (the generators conjugated by the translation `F` from the
//! origin to the basepoint), and keeps `F` as its file frame
//! ([`super::frame`]): `F T F^-1` is the file's own element for each
//! pairing `T`, and the file's coordinates are one product away.

use super::generators::{GeneratorError, Generators};
use super::{Face, FaceKind, Space, max_abs_diff};
use crate::geometry::{Geometry, isometry};
use glam::{DMat4, DVec3, DVec4};
use std::collections::HashMap;

/// Most group elements enumerated in one search (a larger count within
/// the radius means the group is not discrete, or the domain is huge).
pub const MAX_ELEMENTS: usize = 60_000;

/// Most faces a Dirichlet domain may have: those of any space.
pub use super::MAX_FACES;

/// Two orbit points closer than this are one point.
const SAME_POINT: f64 = 1e-7;

impl Generators {
    /// The Dirichlet domain of the group, validated as a space.
    ///
    /// # Errors
    /// A group that is not discrete or not cocompact, a domain that breaks
    /// a property of spaces, an orbifold where a manifold was declared,
    /// and the other [`GeneratorError`]s, each saying what it saw.
    pub fn dirichlet_domain(&self) -> Result<Space, GeneratorError> {
        self.dirichlet_domain_and_basepoint().map(|(space, _)| space)
    }

    /// [`Generators::dirichlet_domain`], and the point it was built
    /// about when that is not the one asked for: `Some(p)` when an
    /// element fixes the origin (or the basepoint the file gives is not
    /// given, and the origin would not do) and the domain was built about
    /// the generic point `p` instead. The space then has `p` at its chart
    /// origin (a domain about a fixed point of an element has that point on
    /// its boundary, where no chart origin may lie), and its pairings are
    /// the group's elements conjugated by the move `F` from the origin to
    /// `p`, which the space keeps as its file frame: [`Space::file_pairing`]
    /// gives the group's own elements, [`Space::from_file_frame`] the
    /// file's placements in the chart. `None`: built where asked.
    ///
    /// # Errors
    /// As [`Generators::dirichlet_domain`].
    pub fn dirichlet_domain_and_basepoint(&self) -> Result<(Space, Option<DVec4>), GeneratorError> {
        let basepoints: Vec<Option<DVec4>> = match self.basepoint {
            Some(p) => vec![Some(p)],
            None => std::iter::once(None)
                .chain(generic_points(self).into_iter().map(Some))
                .collect(),
        };
        let mut last = None;
        for point in basepoints {
            match attempt(self, point) {
                Ok(space) => return Ok((space, point.filter(|_| self.basepoint.is_none()))),
                Err(Failure::Retry(e)) if self.basepoint.is_none() => last = Some(e),
                Err(Failure::Retry(e) | Failure::Fatal(e)) => return Err(e),
            }
        }
        Err(last.unwrap_or(GeneratorError::AllFixOrigin))
    }
}

/// Why one basepoint failed: worth another basepoint, or not.
enum Failure {
    Retry(GeneratorError),
    Fatal(GeneratorError),
}

impl From<GeneratorError> for Failure {
    fn from(e: GeneratorError) -> Self {
        Failure::Fatal(e)
    }
}

/// Points off every special set of the usual groups, at a few distances
/// scaled to how far the generators move the origin.
fn generic_points(gens: &Generators) -> Vec<DVec4> {
    let g = gens.geometry;
    let scale = gens
        .matrices
        .iter()
        .map(|m| g.distance::<f64>(DVec4::W, m.w_axis))
        .filter(|d| *d > 1e-9)
        .fold(f64::INFINITY, f64::min);
    let scale = if scale.is_finite() { scale } else { 1.0 };
    let dirs = [
        DVec3::new(0.8, 0.5, 0.33),
        DVec3::new(-0.31, 0.72, 0.61),
        DVec3::new(0.57, -0.23, 0.79),
    ];
    let mut out = Vec::new();
    for (k, f) in [0.13, 0.29, 0.41].into_iter().enumerate() {
        let v = dirs[k].normalize() * (f * scale);
        out.push(isometry::translation(g, v).w_axis);
    }
    if g == Geometry::Spherical {
        // Lens spaces want a point off both core circles: the Clifford torus.
        let v = dirs[0].normalize() * core::f64::consts::FRAC_PI_4;
        out.push(isometry::translation(g, v).w_axis);
    }
    out
}

/// One element found by the search.
struct Element {
    m: DMat4,
    displacement: f64,
    /// The element it was reached from and the letter multiplied on the
    /// right (`usize::MAX` for the identity).
    parent: usize,
    letter: usize,
    /// The `expand` of the last [`Search::grow`] that took its products
    /// with every letter: those that move the origin at most that much
    /// are in the list (`-inf`: none taken yet).
    expanded_to: f64,
}

struct Search<'a> {
    g: Geometry,
    letters: &'a [DMat4],
    /// The most any letter moves the origin.
    step: f64,
    elements: Vec<Element>,
    grid: HashMap<[i64; 4], Vec<usize>>,
}

const GRID: f64 = 1e-5;

/// Letter `l` in the user's numbering: `g3` for the fourth generator,
/// `g3^-1` for its inverse (letters past the generators).
fn letter_name(l: usize, generators: usize) -> String {
    if l < generators {
        format!("g{l}")
    } else {
        format!("g{}^-1", l - generators)
    }
}

/// The `letter` of an element pushed as the inverse of its `parent`.
const INVERSE: usize = usize::MAX;

impl Search<'_> {
    fn key(p: DVec4) -> [f64; 4] {
        (p / GRID).to_array()
    }

    fn find(&self, p: DVec4) -> Option<usize> {
        let k = Self::key(p);
        let base = k.map(|x| x.floor() as i64);
        for corner in 0..16u32 {
            let mut key = base;
            for (d, item) in key.iter_mut().enumerate() {
                if corner & (1 << d) != 0 {
                    *item += if k[d] - k[d].floor() < 0.5 { -1 } else { 1 };
                }
            }
            let near = self.grid.get(&key).and_then(|list| {
                list.iter()
                    .find(|&&i| self.g.distance::<f64>(self.elements[i].m.w_axis, p) < SAME_POINT)
            });
            if let Some(&i) = near {
                return Some(i);
            }
        }
        None
    }

    fn push(&mut self, e: Element) {
        let key = Self::key(e.m.w_axis).map(|x| x.floor() as i64);
        self.grid.entry(key).or_default().push(self.elements.len());
        self.elements.push(e);
    }

    /// The word of element `i`, in the user's generator numbering.
    fn word(&self, mut i: usize, generators: usize) -> String {
        if self.elements[i].letter == INVERSE {
            return format!("({})^-1", self.word(self.elements[i].parent, generators));
        }
        let mut letters = Vec::new();
        while self.elements[i].parent != usize::MAX {
            letters.push(letter_name(self.elements[i].letter, generators));
            i = self.elements[i].parent;
        }
        letters.reverse();
        if letters.is_empty() {
            "1".into()
        } else {
            letters.join(" ")
        }
    }

    /// Extends the search to every product that moves the origin at most
    /// `expand`, reachable through elements that do too (continuing where
    /// it stopped). Products farther out are not kept: each expanded
    /// element would otherwise add up to one per letter just outside, so
    /// that a long generator list filled the list with them (Seifert-Weber
    /// from 64 generators, its 12 pairings and 52 products of two: over
    /// `MAX_ELEMENTS` within a radius of 4.0 and refused as not discrete;
    /// 465 elements kept now). An element whose products were cut off is
    /// expanded again when `expand` grows.
    fn grow(&mut self, expand: f64, generators: usize, manifold: bool) -> Result<(), Failure> {
        let mut k = 0;
        while k < self.elements.len() {
            let e = &self.elements[k];
            let done = e.expanded_to >= expand || e.displacement + self.step <= e.expanded_to;
            if e.displacement > expand || done {
                k += 1;
                continue;
            }
            self.elements[k].expanded_to = expand;
            for (l, letter) in self.letters.iter().enumerate() {
                // A plain product, not re-orthonormalised: Gram-Schmidt
                // on an element far from the origin (entries of size S)
                // rounds its frame by about eps S^3, far more than the
                // product did (eps S^2), and the next product carries
                // that into its image of the basepoint. The fourth power
                // of a generator of a 5-fold cover of Seifert-Weber
                // (entries near 1500) came out 5e-7 off the plain
                // product; products that were the identity then missed it
                // by 1.2e-7 to 7e-7 and were refused as "an element moves
                // the basepoint by only ..." (the Weeks manifold about
                // far basepoints, in tests/generators.rs).
                let m = self.elements[k].m * *letter;
                let p = m.w_axis;
                if !m.is_finite() {
                    return Err(GeneratorError::NotDiscrete {
                        detail: "a product of the generators overflowed".into(),
                    }
                    .into());
                }
                match self.find(p) {
                    Some(j) => {
                        let size = m.to_cols_array().iter().fold(1.0f64, |a, x| a.max(x.abs()));
                        if max_abs_diff(m, self.elements[j].m) > 1e-6 * size {
                            let word = format!(
                                "({})^-1 {} {}",
                                self.word(j, generators),
                                self.word(k, generators),
                                letter_name(l, generators)
                            );
                            let e = GeneratorError::NotFree {
                                word,
                                what: "the basepoint of the Dirichlet domain".into(),
                            };
                            return Err(if manifold { Failure::Fatal(e) } else { Failure::Retry(e) });
                        }
                    }
                    None => {
                        let displacement = self.g.distance::<f64>(DVec4::W, p);
                        if displacement < 1e-6 {
                            return Err(GeneratorError::NotDiscrete {
                                detail: format!(
                                    "an element moves the basepoint by only {displacement:.3e}: images of it pile up"
                                ),
                            }
                            .into());
                        }
                        if displacement > expand {
                            continue;
                        }
                        self.push(Element {
                            m,
                            displacement,
                            parent: k,
                            letter: l,
                            expanded_to: f64::NEG_INFINITY,
                        });
                        // The elements within a radius are closed under
                        // inversion; the walk might reach g and not g^-1,
                        // whose bisector holds the partner face.
                        // (Exact in H3 and S3, J m^T J: nothing to round.)
                        let inverse = isometry::inverse(self.g, m);
                        if self.find(inverse.w_axis).is_none() {
                            self.push(Element {
                                m: inverse,
                                displacement,
                                parent: self.elements.len() - 1,
                                letter: INVERSE,
                                expanded_to: f64::NEG_INFINITY,
                            });
                        }
                        if self.elements.len() > MAX_ELEMENTS {
                            return Err(GeneratorError::NotDiscrete {
                                detail: format!(
                                    "more than {MAX_ELEMENTS} elements move the basepoint less than {expand:.3}"
                                ),
                            }
                            .into());
                        }
                    }
                }
            }
            k += 1;
        }
        Ok(())
    }
}

fn attempt(gens: &Generators, basepoint: Option<DVec4>) -> Result<Space, Failure> {
    let g = gens.geometry;
    let (shift, back) = match basepoint {
        Some(p) => {
            let t = isometry::translation_to(g, g.normalize_point::<f64>(p));
            (t, isometry::inverse(g, t))
        }
        None => (DMat4::IDENTITY, DMat4::IDENTITY),
    };
    let n = gens.matrices.len();
    let mut letters: Vec<DMat4> = gens
        .matrices
        .iter()
        .map(|m| isometry::orthonormalize(g, back * *m * shift))
        .collect();
    let inverses: Vec<DMat4> = letters.iter().map(|m| isometry::inverse(g, *m)).collect();
    letters.extend(inverses);
    let step = letters
        .iter()
        .map(|m| g.distance::<f64>(DVec4::W, m.w_axis))
        .fold(0.0, f64::max);
    if step < 1e-9 {
        return Err(Failure::Fatal(GeneratorError::AllFixOrigin));
    }
    let mut search = Search {
        g,
        letters: &letters,
        step,
        elements: Vec::new(),
        grid: HashMap::new(),
    };
    search.push(Element {
        m: DMat4::IDENTITY,
        displacement: 0.0,
        parent: usize::MAX,
        letter: 0,
        expanded_to: f64::NEG_INFINITY,
    });
    let mut radius = step * 1.001;
    let whole_sphere = core::f64::consts::PI + 1e-9;
    let mut open = None;
    // How far past the radius the walk expands elements. The words to an
    // element within the radius may pass outside it (a basepoint off the
    // generators' centre: the Weeks manifold about (0.1, 0.05, 0.02)),
    // so a domain whose faces do not pair expands one letter's step
    // further once before it is refused.
    let mut beyond = 0.0;
    for _ in 0..12 {
        search.grow(radius + beyond, n, gens.manifold)?;
        let mut candidates: Vec<usize> = (1..search.elements.len())
            .filter(|&i| search.elements[i].displacement <= radius)
            .collect();
        candidates.sort_by(|&a, &b| {
            search.elements[a]
                .displacement
                .total_cmp(&search.elements[b].displacement)
        });
        let whole = g == Geometry::Spherical && radius >= core::f64::consts::PI;
        match Polytope::cut(g, &search, &candidates) {
            Ok(poly) => {
                let circumradius = poly.circumradius(g);
                if whole || radius >= 2.0 * circumradius + 1e-9 {
                    match pair_faces(gens, &search, &poly) {
                        Ok(space) => {
                            prove(gens, &letters[..n], &space)?;
                            return Ok(space.with_file_frame(shift).map_err(GeneratorError::Domain)?);
                        }
                        Err(_) if beyond == 0.0 => {
                            beyond = step;
                            continue;
                        }
                        Err(e) => return Err(e),
                    }
                }
                // At most 1.5 times a round: a polytope cut by few elements
                // is far larger than the domain (Seifert-Weber about points
                // near its centre: a circumradius of 2.4-3.7 from the 12
                // pairings, 1.85 in the end), and a radius of twice that
                // reached where f64 products lose the identity, so
                // discrete groups were refused as not discrete.
                radius = (2.0 * circumradius * 1.02).clamp(radius * 1.25, radius * 1.5);
            }
            // Not closed yet: more elements may close it.
            Err(e) if !whole => {
                open = Some(e);
                radius *= 1.5;
            }
            Err(e) => return Err(e),
        }
        if g == Geometry::Spherical {
            radius = radius.min(whole_sphere);
        }
    }
    Err(match open {
        Some(e) => e,
        None => Failure::Fatal(GeneratorError::NotDiscrete {
            detail: "the search radius kept growing without closing the domain".into(),
        }),
    })
}

/// A convex polytope of the chart as its faces' polygons, each face the
/// bisector of one element (or one of the six sides of the starting box).
struct Polytope {
    faces: Vec<(usize, DVec4, Vec<DVec3>)>,
    /// A lens or hemisphere of S3 ([`super::lens`]): its faces have no
    /// polygons (they reach the chart's infinity) and its rim lies a
    /// quarter turn away.
    lens: bool,
}

const BOX_FACE: usize = usize::MAX;

impl Polytope {
    fn cut(g: Geometry, search: &Search<'_>, candidates: &[usize]) -> Result<Self, Failure> {
        let half = match g {
            Geometry::Hyperbolic => 1.0,
            Geometry::Spherical => 1e4,
            Geometry::Euclidean => {
                1e3 * search
                    .letters
                    .iter()
                    .map(|m| m.w_axis.truncate().length())
                    .fold(1.0, f64::max)
            }
        };
        let mut poly = Polytope::cube(half);
        let mut reach = f64::INFINITY;
        for &i in candidates {
            let e = &search.elements[i];
            if e.displacement / 2.0 > reach + 1e-9 {
                continue; // the bisector lies beyond every vertex
            }
            let n = bisector(g, e.m.w_axis);
            if poly.clip(i, n) {
                reach = poly.circumradius(g);
            }
        }
        let boxed = poly.faces.iter().any(|f| f.0 == BOX_FACE);
        if boxed
            && g == Geometry::Spherical
            && let Some(lens) = Polytope::lens(search, candidates)
        {
            return Ok(lens);
        }
        let outside = g == Geometry::Hyperbolic
            && poly
                .faces
                .iter()
                .flat_map(|f| f.2.iter())
                .any(|c| c.length_squared() >= 1.0 - 1e-12);
        if boxed || outside {
            let detail = match g {
                Geometry::Euclidean => "it is unbounded: the translations do not span three directions",
                Geometry::Hyperbolic => "it reaches the sphere at infinity (a cusp, or too few generators)",
                Geometry::Spherical => {
                    "it reaches the far hemisphere of the basepoint (a lens space L(p, 1) or L(p, -1), whose domains are lenses bounded by two faces, or RP3), which one chart cannot hold"
                }
            };
            let e = GeneratorError::NotCompact { detail: detail.into() };
            return Err(if g == Geometry::Spherical {
                Failure::Retry(e)
            } else {
                Failure::Fatal(e)
            });
        }
        if poly.faces.len() > MAX_FACES {
            return Err(GeneratorError::NotCompact {
                detail: format!("it has {} faces, more than {MAX_FACES}", poly.faces.len()),
            }
            .into());
        }
        Ok(poly)
    }

    fn cube(h: f64) -> Self {
        let mut faces = Vec::new();
        for axis in 0..3 {
            for sign in [-1.0, 1.0] {
                let mut n = DVec3::ZERO;
                n[axis] = sign;
                // Four corners of the square at n * h, counterclockwise.
                let u = DVec3::new(n.y.abs(), n.z.abs(), n.x.abs());
                let v = n.cross(u);
                let corners = [u + v, v - u, -u - v, u - v].map(|c| (n + c) * h);
                faces.push((BOX_FACE, n.extend(-h), corners.to_vec()));
            }
        }
        Polytope { faces, lens: false }
    }

    /// The lens (or hemisphere) the `candidates`' bisectors bound in S3,
    /// if they bound one: every bisector but the antipode's is a plane
    /// of the chart normal to one axis (every image of the origin lies on
    /// one great circle), and the nearest on each side of the origin are
    /// the two faces; with the antipode's alone (RP3) the one face is the
    /// great sphere a quarter turn away, `w = 0`.
    fn lens(search: &Search<'_>, candidates: &[usize]) -> Option<Self> {
        let mut axis: Option<DVec3> = None;
        let mut sides: [Option<(f64, usize, DVec4)>; 2] = [None, None];
        let mut antipode = None;
        for &i in candidates {
            let n = bisector(Geometry::Spherical, search.elements[i].m.w_axis);
            let normal = n.truncate();
            let len = normal.length();
            if len < 1e-9 {
                antipode = Some(i);
                continue;
            }
            let u = *axis.get_or_insert(normal / len);
            if normal.cross(u).length() > 1e-9 * len {
                return None;
            }
            // The plane normal . x = -w, at -w / |normal| along its normal.
            let side = usize::from(normal.dot(u) < 0.0);
            let offset = -n.w / len;
            if sides[side].is_none_or(|(o, _, _)| offset < o) {
                sides[side] = Some((offset, i, n));
            }
        }
        let faces = match (sides, antipode) {
            ([Some((_, a, na)), Some((_, b, nb))], _) => vec![(a, na, Vec::new()), (b, nb, Vec::new())],
            ([None, None], Some(i)) => vec![(i, DVec4::new(0.0, 0.0, 0.0, -1.0), Vec::new())],
            _ => return None,
        };
        Some(Polytope { faces, lens: true })
    }

    fn vertices(&self) -> impl Iterator<Item = &DVec3> {
        self.faces.iter().flat_map(|f| f.2.iter())
    }

    fn circumradius(&self, g: Geometry) -> f64 {
        if self.lens {
            return core::f64::consts::FRAC_PI_2;
        }
        self.vertices()
            .map(|c| g.distance::<f64>(DVec4::W, g.normalize_point::<f64>(c.extend(1.0))))
            .fold(0.0, f64::max)
    }

    /// Cuts by the half-space `n . (c, 1) <= 0`; true when anything was cut.
    fn clip(&mut self, id: usize, n: DVec4) -> bool {
        let normal = n.truncate();
        let len = normal.length();
        let side = |c: &DVec3| (normal.dot(*c) + n.w) / len;
        let eps = 1e-10;
        if self.vertices().all(|c| side(c) <= eps) {
            return false;
        }
        let mut on: Vec<DVec3> = Vec::new();
        let mut kept = Vec::new();
        for (fid, plane, verts) in self.faces.drain(..) {
            let d: Vec<f64> = verts.iter().map(side).collect();
            let mut out = Vec::new();
            for k in 0..verts.len() {
                let (a, b) = (verts[k], verts[(k + 1) % verts.len()]);
                let (da, db) = (d[k], d[(k + 1) % verts.len()]);
                if da <= eps {
                    out.push(a);
                    if da >= -eps {
                        on.push(a);
                    }
                }
                if (da < -eps && db > eps) || (da > eps && db < -eps) {
                    let x = a + (b - a) * (da / (da - db));
                    out.push(x);
                    on.push(x);
                }
            }
            if out.len() >= 3 && polygon_area(&out) > 1e-14 {
                kept.push((fid, plane, out));
            }
        }
        if let Some(polygon) = convex_polygon(&on, normal / len) {
            kept.push((id, n, polygon));
        }
        self.faces = kept;
        true
    }
}

/// The bisector covector of the origin and `q = g o`: `n . p <= 0` on the
/// origin's side.
fn bisector(g: Geometry, q: DVec4) -> DVec4 {
    match g {
        // <q - o, p> <= 0 with the Lorentz form.
        Geometry::Hyperbolic => DVec4::new(q.x, q.y, q.z, -(q.w - 1.0)),
        // (q - o) . p <= 0.
        Geometry::Spherical => DVec4::new(q.x, q.y, q.z, q.w - 1.0),
        // 2 q . x <= |q|^2.
        Geometry::Euclidean => {
            let v = q.truncate() / q.w;
            v.extend(-v.length_squared() / 2.0)
        }
    }
}

fn polygon_area(pts: &[DVec3]) -> f64 {
    let mut s = DVec3::ZERO;
    for k in 0..pts.len() {
        s += pts[k].cross(pts[(k + 1) % pts.len()]);
    }
    s.length() / 2.0
}

/// The points (on one plane with unit normal `normal`) in counterclockwise
/// order around it, duplicates dropped; `None` when they span no area.
fn convex_polygon(points: &[DVec3], normal: DVec3) -> Option<Vec<DVec3>> {
    let mut pts: Vec<DVec3> = Vec::new();
    for p in points {
        if !pts.iter().any(|q| (*q - *p).length() < 1e-9) {
            pts.push(*p);
        }
    }
    if pts.len() < 3 {
        return None;
    }
    let centre = pts.iter().copied().sum::<DVec3>() / pts.len() as f64;
    let u = normal.any_orthonormal_vector();
    let v = normal.cross(u);
    pts.sort_by(|a, b| {
        let (da, db) = (*a - centre, *b - centre);
        da.dot(v).atan2(da.dot(u)).total_cmp(&db.dot(v).atan2(db.dot(u)))
    });
    (polygon_area(&pts) > 1e-14).then_some(pts)
}

fn pair_faces(gens: &Generators, search: &Search<'_>, poly: &Polytope) -> Result<Space, Failure> {
    let g = gens.geometry;
    let n = gens.matrices.len();
    let ids: Vec<usize> = poly.faces.iter().map(|f| f.0).collect();
    let mut faces = Vec::with_capacity(ids.len());
    for (i, &id) in ids.iter().enumerate() {
        let m = search.elements[id].m;
        let inverse = isometry::inverse(g, m);
        let target = inverse.w_axis;
        let partner = ids
            .iter()
            .position(|&j| g.distance::<f64>(search.elements[j].m.w_axis, target) < SAME_POINT)
            .ok_or_else(|| GeneratorError::NotDiscrete {
                detail: format!(
                    "face {i} (element {}) has no partner face for the inverse element",
                    search.word(id, n)
                ),
            })?;
        let kind = if partner == i {
            // The face's corners, or for a face without any (a lens's,
            // a hemisphere's) three points spanning its great sphere.
            let points: Vec<DVec4> = if poly.faces[i].2.is_empty() {
                super::lens::face_points(poly.faces[i].1).to_vec()
            } else {
                poly.faces[i]
                    .2
                    .iter()
                    .map(|c| g.normalize_point::<f64>(c.extend(1.0)))
                    .collect()
            };
            let fixes = points.iter().all(|p| g.distance::<f64>(m * *p, *p) < 1e-7);
            if fixes {
                FaceKind::Mirror
            } else if poly.lens && super::lens::is_free(m) {
                // RP3's hemisphere, glued to itself by the antipodal map.
                FaceKind::Glue
            } else {
                return Err(GeneratorError::SelfPairedHalfTurn { face: i }.into());
            }
        } else {
            FaceKind::Glue
        };
        faces.push(Face {
            plane: poly.faces[i].1,
            partner,
            kind,
            pairing: inverse,
        });
    }
    Ok(Space::new(gens.name.clone(), g, faces).map_err(GeneratorError::Domain)?)
}

/// Carries `h` back by face pairings while its image of the origin lies
/// beyond a face: each step brings that point strictly nearer the origin
/// (a Dirichlet domain's pairing `g^-1` maps the points nearer `g o` than
/// `o` nearer `o`). Tested on the normalised point itself, not its chart
/// image, so S3 points in the far hemisphere are seen too.
fn reduce(space: &Space, h: DMat4) -> DMat4 {
    let g = space.geometry();
    let mut m = h;
    for _ in 0..100_000 {
        let p = g.normalize_point::<f64>(m.w_axis);
        let beyond = space
            .faces()
            .iter()
            .enumerate()
            .map(|(i, f)| (i, f.plane.dot(p)))
            .filter(|(_, s)| *s > 1e-9)
            .max_by(|a, b| a.1.total_cmp(&b.1));
        let Some((i, _)) = beyond else { break };
        m = isometry::orthonormalize(g, space.faces()[i].pairing * m);
    }
    m
}

/// Every generator is a product of the face pairings, and the quotient is
/// a manifold when the list says so.
fn prove(gens: &Generators, generators: &[DMat4], space: &Space) -> Result<(), Failure> {
    let g = gens.geometry;
    for (i, h) in generators.iter().enumerate() {
        let rest = reduce(space, *h);
        let size = rest.to_cols_array().iter().fold(1.0f64, |a, x| a.max(x.abs()));
        if max_abs_diff(rest, DMat4::IDENTITY) > 1e-6 * size {
            let moved = g.distance::<f64>(DVec4::W, rest.w_axis);
            return Err(GeneratorError::NotGenerated {
                matrix: i,
                detail: format!(
                    "it reduces to an element moving the basepoint by {moved:.6}: the group is larger than the domain's pairings generate, so it is not discrete"
                ),
            }
            .into());
        }
    }
    if gens.manifold && !space.is_manifold() {
        let what = if let Some(f) = space.faces().iter().position(|f| f.kind == FaceKind::Mirror) {
            format!("face {f} is a mirror")
        } else {
            let (c, cycle) = space
                .edge_cycles()
                .iter()
                .enumerate()
                .find(|(_, c)| c.order > 1)
                .map_or((0, 1), |(c, cy)| (c, cy.order));
            format!("the edges of edge cycle {c} are the axis of a rotation of order {cycle}")
        };
        return Err(GeneratorError::NotFree {
            word: "of the domain's pairings".into(),
            what,
        }
        .into());
    }
    Ok(())
}
