//! The library: spaces beyond the paper's five, each given by generators
//! computed here from the mathematics and turned into a space by its
//! Dirichlet domain ([`Generators::dirichlet_domain`]). The files under
//! `assets/spaces/` are these generators written out
//! (`bevy_manifold space library --out assets/spaces`); a test checks they
//! match.
//!
//! - **Spherical** (quotients of S3 by finite groups of left
//!   multiplications by unit quaternions, or by rotations of the two
//!   planes of C^2): lens spaces `L(p, q)`, the quaternionic space S3/Q8,
//!   the prism manifolds S3/D*_4m, the binary tetrahedral and octahedral
//!   spaces, and the Poincare space from its two generators.
//! - **Flat**: the 3-torus on a hexagonal and a body-centred lattice, the
//!   half-, quarter-, third- and sixth-turn spaces, the Hantzsche-Wendt
//!   space, and the first amphicosm (non-orientable).
//! - **Hyperbolic**: the Weeks manifold, the closed hyperbolic manifold of
//!   least volume, from a presentation of its fundamental group: the
//!   relators are solved for a representation into SL(2, C) by Newton's
//!   method ([`weeks`]).
//!
//! A point `(x, y, z, w)` of S3 is the quaternion `w + x i + y j + z k`.
//!
//! ```
//! use bevy_manifold_core::space::library;
//! let gens = library::by_name("binary-tetrahedral").unwrap();
//! let space = gens.dirichlet_domain().unwrap();
//! assert_eq!(space.group_order(), Some(24));
//! assert_eq!(space.faces().len(), 8); // an octahedron
//! ```

use super::file::from_rows;
use super::generators::Generators;
use crate::geometry::{Geometry, isometry};
use glam::{DMat4, DVec3, DVec4};
use std::f64::consts::{FRAC_1_SQRT_2, PI, TAU};

/// The lens spaces in the library whose domains are polyhedra, as
/// `(p, q)`.
pub const LENS: [(u32, u32); 5] = [(5, 2), (7, 2), (8, 3), (10, 3), (12, 5)];

/// The lens spaces `L(p, 1)` in the library, as `p`: every orbit is a
/// great circle (a Hopf fibre), so about any point the Dirichlet domain
/// is a lens of two faces meeting in a whole great circle
/// ([`super::lens`]). `L(2, 1)` is RP3, elliptic space, named `rp3`: its
/// domain is a hemisphere.
pub const LENS_ROUND: [u32; 3] = [2, 3, 5];

/// The prism manifolds S3/D*_4m in the library, as `m`.
pub const PRISM: [u32; 3] = [3, 4, 5];

/// Every library space's name.
#[must_use]
pub fn names() -> Vec<String> {
    let mut out: Vec<String> = LENS.iter().map(|(p, q)| format!("lens-{p}-{q}")).collect();
    out.extend(LENS_ROUND.iter().map(|&p| round_name(p)));
    out.push("quaternionic".into());
    out.extend(PRISM.iter().map(|m| format!("prism-{m}")));
    out.extend(
        [
            "binary-tetrahedral",
            "binary-octahedral",
            "poincare-generators",
            "torus-hexagonal",
            "torus-bcc",
            "half-turn",
            "quarter-turn",
            "third-turn",
            "sixth-turn",
            "hantzsche-wendt",
            "amphicosm",
            "weeks",
        ]
        .map(String::from),
    );
    out
}

/// The library's name of `L(p, 1)`: `rp3` for `p = 2`.
fn round_name(p: u32) -> String {
    if p == 2 { "rp3".into() } else { format!("lens-{p}-1") }
}

/// A library space's generators by name (`None` for an unknown name).
#[must_use]
pub fn by_name(name: &str) -> Option<Generators> {
    if name == "rp3" {
        // L(2, 1): the half-turn in both planes is the antipodal map,
        // written exactly.
        let mut gens = lens(2, 1);
        gens.name = "rp3".into();
        gens.matrices = vec![-DMat4::IDENTITY];
        return Some(gens);
    }
    if let Some(rest) = name.strip_prefix("lens-") {
        let (p, q) = rest.split_once('-')?;
        let (p, q) = (p.parse().ok()?, q.parse().ok()?);
        let round = q == 1 && p != 2 && LENS_ROUND.contains(&p);
        return (LENS.contains(&(p, q)) || round).then(|| lens(p, q));
    }
    if let Some(m) = name.strip_prefix("prism-") {
        let m = m.parse().ok()?;
        return PRISM.contains(&m).then(|| prism(m));
    }
    let h = 0.5;
    let phi = (1.0 + 5f64.sqrt()) / 2.0;
    let (sq3, e) = (3f64.sqrt(), Geometry::Euclidean);
    let hexagonal = [DVec3::X, DVec3::new(0.5, sq3 / 2.0, 0.0)];
    let turn = |name: &str, lattice: [DVec3; 2], k: f64| {
        let screw = isometry::translation(e, DVec3::Z) * isometry::rotation(DVec3::Z, TAU / k);
        flat(name, vec![translate(lattice[0]), translate(lattice[1]), screw])
    };
    Some(match name {
        "quaternionic" => spherical(name, &[[0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]]),
        "binary-tetrahedral" => spherical(name, &[[0.0, 1.0, 0.0, 0.0], [h, h, h, h]]),
        "binary-octahedral" => spherical(name, &[[FRAC_1_SQRT_2, FRAC_1_SQRT_2, 0.0, 0.0], [h, h, h, h]]),
        "poincare-generators" => spherical(name, &[[h, h, h, h], [phi / 2.0, 0.5 / phi, 0.5, 0.0]]),
        "torus-hexagonal" => flat(
            name,
            vec![translate(hexagonal[0]), translate(hexagonal[1]), translate(DVec3::Z)],
        ),
        "torus-bcc" => flat(
            name,
            [
                DVec3::new(1.0, 1.0, -1.0),
                DVec3::new(1.0, -1.0, 1.0),
                DVec3::new(-1.0, 1.0, 1.0),
            ]
            .map(|v| translate(v * 0.5))
            .to_vec(),
        ),
        "half-turn" => turn(name, [DVec3::X, DVec3::Y], 2.0),
        "quarter-turn" => turn(name, [DVec3::X, DVec3::Y], 4.0),
        "third-turn" => turn(name, hexagonal, 3.0),
        "sixth-turn" => turn(name, hexagonal, 6.0),
        // Three screw motions by half-turns about the three axes, the axes
        // pairwise skew: x -> (x + 1/2, 1/2 - y, -z), and cyclically.
        "hantzsche-wendt" => flat(
            name,
            vec![
                affine(DVec3::new(1.0, -1.0, -1.0), DVec3::new(h, h, 0.0)),
                affine(DVec3::new(-1.0, 1.0, -1.0), DVec3::new(0.0, h, h)),
                affine(DVec3::new(-1.0, -1.0, 1.0), DVec3::new(h, 0.0, h)),
            ],
        ),
        // A glide reflection along x in the plane y = 0, and two
        // translations: the first amphicosm, non-orientable.
        "amphicosm" => flat(
            name,
            vec![
                affine(DVec3::new(1.0, -1.0, 1.0), DVec3::X),
                translate(DVec3::Y),
                translate(DVec3::Z),
            ],
        ),
        "weeks" => weeks(),
        _ => return None,
    })
}

/// The comment a library file starts with: what the space is and how its
/// generators were computed.
#[must_use]
pub fn header(name: &str) -> String {
    let what = if name == "rp3" {
        "Elliptic space RP3 = L(2,1): the antipodal map of S3, domain the hemisphere about a point of the Clifford torus".into()
    } else if let Some(rest) = name.strip_prefix("lens-") {
        let (p, q) = rest.split_once('-').unwrap_or((rest, "?"));
        format!(
            "Lens space L({p},{q}): the rotation by 2 pi/{p} in the xy-plane and 2 pi {q}/{p} in the zw-plane of R^4, domain centred on the Clifford torus"
        )
    } else if let Some(m) = name.strip_prefix("prism-") {
        format!("Prism manifold S3/D*: left multiplication by e^(i pi/{m}) and by j (binary dihedral group)")
    } else {
        match name {
            "quaternionic" => "Quaternionic space S3/Q8: left multiplication by i and j".into(),
            "binary-tetrahedral" => "Binary tetrahedral space: left multiplication by i and (1+i+j+k)/2".into(),
            "binary-octahedral" => {
                "Binary octahedral space: left multiplication by (1+i)/sqrt 2 and (1+i+j+k)/2".into()
            }
            "poincare-generators" => {
                "Poincare dodecahedral space: left multiplication by (1+i+j+k)/2 and (phi + i/phi + j)/2".into()
            }
            "torus-hexagonal" => "3-torus on the hexagonal lattice".into(),
            "torus-bcc" => "3-torus on the body-centred cubic lattice (truncated-octahedron domain)".into(),
            "half-turn" | "quarter-turn" | "third-turn" | "sixth-turn" => {
                format!("Flat {name} space: two lattice translations and a screw motion along z")
            }
            "hantzsche-wendt" => "Hantzsche-Wendt space: three half-turn screw motions about pairwise skew axes".into(),
            "amphicosm" => "First amphicosm (non-orientable): a glide reflection and two translations".into(),
            _ => name.into(),
        }
    };
    format!(
        "{what}\nComputed by bevy_manifold (space::library); written by `bevy_manifold space library --out assets/spaces`.\nRow-vector convention (v * M), as Curved Spaces reads it."
    )
}

/// The isometry `p -> q p` of S3 for the unit quaternion
/// `q = [re, i, j, k]`, on points `(x, y, z, w) = w + x i + y j + z k`.
#[must_use]
pub fn left_multiplication(q: [f64; 4]) -> DMat4 {
    let [a, b, c, d] = q;
    from_rows([[a, -d, c, b], [d, a, -b, c], [-c, b, a, d], [-b, -c, -d, a]])
}

/// The lens space `L(p, q)`: the rotation by `2 pi / p` in the `xy`-plane
/// and by `2 pi q / p` in the `zw`-plane, its domain centred at a point of
/// the Clifford torus (where every point is alike).
#[must_use]
pub fn lens(p: u32, q: u32) -> Generators {
    let (a, b) = (TAU / f64::from(p), TAU * f64::from(q) / f64::from(p));
    let m = from_rows([
        [a.cos(), -a.sin(), 0.0, 0.0],
        [a.sin(), a.cos(), 0.0, 0.0],
        [0.0, 0.0, b.cos(), -b.sin()],
        [0.0, 0.0, b.sin(), b.cos()],
    ]);
    let mut gens = of(format!("lens-{p}-{q}"), Geometry::Spherical, vec![m]);
    gens.basepoint = Some(DVec4::new(FRAC_1_SQRT_2, 0.0, 0.0, FRAC_1_SQRT_2));
    gens.manifold = true;
    gens
}

/// The prism manifold S3/D*_4m: left multiplication by `e^(i pi / m)` and
/// by `j` (the binary dihedral group of order `4 m`).
#[must_use]
pub fn prism(m: u32) -> Generators {
    let a = PI / f64::from(m);
    spherical(
        &format!("prism-{m}"),
        &[[a.cos(), a.sin(), 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]],
    )
}

fn spherical(name: &str, quaternions: &[[f64; 4]]) -> Generators {
    let mut gens = of(
        name.into(),
        Geometry::Spherical,
        quaternions.iter().map(|q| left_multiplication(*q)).collect(),
    );
    gens.manifold = true;
    gens
}

fn flat(name: &str, matrices: Vec<DMat4>) -> Generators {
    let mut gens = of(name.into(), Geometry::Euclidean, matrices);
    gens.manifold = true;
    gens
}

fn of(name: String, geometry: Geometry, matrices: Vec<DMat4>) -> Generators {
    Generators::unchecked(name, geometry, matrices)
}

fn translate(v: DVec3) -> DMat4 {
    isometry::translation(Geometry::Euclidean, v)
}

/// `x -> diag(s) x + t`.
fn affine(s: DVec3, t: DVec3) -> DMat4 {
    DMat4::from_cols(
        DVec4::new(s.x, 0.0, 0.0, 0.0),
        DVec4::new(0.0, s.y, 0.0, 0.0),
        DVec4::new(0.0, 0.0, s.z, 0.0),
        t.extend(1.0),
    )
}

/// A presentation of the Weeks manifold's fundamental group, two
/// generators `a`, `b` (capitals are inverses): `a^2 b^2 a^2 b^-1 a b^-1`
/// and `a^2 b^2 a^-1 b a^-1 b^2`, as given by Chinburg, Friedman, Jones and
/// Reid, "The arithmetic hyperbolic 3-manifold of smallest volume" (2001).
/// Abelianised they say `5a = 5b = 0`: H1 = Z/5 + Z/5.
pub const WEEKS_RELATORS: [&str; 2] = ["aabbaaBaB", "aabbAbAbb"];

/// The Weeks manifold: its group's representation into SL(2, C) with
/// `a = [[x, 1], [0, 1/x]]`, `b = [[y, 0], [z, 1/y]]`, the relators solved
/// for `(x, y, z)` by Gauss-Newton from a start near the discrete faithful
/// solution (the one where `tr a` is the complex root of `t^3 - t + 1`, the
/// generator of the manifold's trace field), then carried to SO(3,1).
/// Other starts reach the Galois conjugates (real traces), which are no
/// discrete group; the Dirichlet domain's volume tells them apart.
#[must_use]
pub fn weeks() -> Generators {
    let start = [C(0.237, -0.708), C(0.425, 1.270), C(-1.215, 1.307)];
    let v = solve_relators(&WEEKS_RELATORS, start);
    let (a, b) = sl2_pair(v);
    let mut gens = of("weeks".into(), Geometry::Hyperbolic, vec![lorentz(a), lorentz(b)]);
    gens.manifold = true;
    gens
}

/// A complex number, for the SL(2, C) side of the Weeks manifold.
#[derive(Clone, Copy, Debug, PartialEq)]
struct C(f64, f64);

impl core::ops::Add for C {
    type Output = C;
    fn add(self, o: C) -> C {
        C(self.0 + o.0, self.1 + o.1)
    }
}

impl core::ops::Sub for C {
    type Output = C;
    fn sub(self, o: C) -> C {
        C(self.0 - o.0, self.1 - o.1)
    }
}

impl core::ops::Mul for C {
    type Output = C;
    fn mul(self, o: C) -> C {
        C(self.0 * o.0 - self.1 * o.1, self.0 * o.1 + self.1 * o.0)
    }
}

impl C {
    fn conj(self) -> C {
        C(self.0, -self.1)
    }
    fn norm2(self) -> f64 {
        self.0 * self.0 + self.1 * self.1
    }
    fn recip(self) -> C {
        let n = self.norm2();
        C(self.0 / n, -self.1 / n)
    }
}

type M2 = [[C; 2]; 2];

fn mul2(a: &M2, b: &M2) -> M2 {
    let e = |i: usize, j: usize| a[i][0] * b[0][j] + a[i][1] * b[1][j];
    [[e(0, 0), e(0, 1)], [e(1, 0), e(1, 1)]]
}

/// The inverse of a matrix of determinant 1.
fn inv2(a: &M2) -> M2 {
    let z = C(0.0, 0.0);
    [[a[1][1], z - a[0][1]], [z - a[1][0], a[0][0]]]
}

fn sl2_pair(v: [C; 3]) -> (M2, M2) {
    let (one, zero) = (C(1.0, 0.0), C(0.0, 0.0));
    (
        [[v[0], one], [zero, v[0].recip()]],
        [[v[1], zero], [v[2], v[1].recip()]],
    )
}

/// The entries that vanish when every relator is `+-I`: the off-diagonal
/// entries and the difference of the diagonal ones.
fn relator_residual(relators: &[&str], v: [C; 3]) -> Vec<C> {
    let (a, b) = sl2_pair(v);
    let (ai, bi) = (inv2(&a), inv2(&b));
    let mut out = Vec::new();
    for r in relators {
        let mut m: M2 = [[C(1.0, 0.0), C(0.0, 0.0)], [C(0.0, 0.0), C(1.0, 0.0)]];
        for ch in r.chars() {
            let g = match ch {
                'a' => &a,
                'b' => &b,
                'A' => &ai,
                _ => &bi,
            };
            m = mul2(&m, g);
        }
        out.extend([m[0][1], m[1][0], m[0][0] - m[1][1]]);
    }
    out
}

/// Gauss-Newton on the relators (holomorphic in `x, y, z`, so the complex
/// Jacobian is taken by a forward difference), to machine precision.
fn solve_relators(relators: &[&str], mut v: [C; 3]) -> [C; 3] {
    for _ in 0..60 {
        let r = relator_residual(relators, v);
        if r.iter().map(|c| c.norm2()).sum::<f64>() < 1e-30 {
            break;
        }
        let h = 1e-7;
        let cols: Vec<Vec<C>> = (0..3)
            .map(|k| {
                let mut w = v;
                w[k] = w[k] + C(h, 0.0);
                let rk = relator_residual(relators, w);
                rk.iter()
                    .zip(&r)
                    .map(|(p, q)| C((p.0 - q.0) / h, (p.1 - q.1) / h))
                    .collect()
            })
            .collect();
        // Normal equations J^H J d = -J^H r, a complex 3x3 system.
        let mut m = [[C(0.0, 0.0); 4]; 3];
        for k in 0..3 {
            for l in 0..3 {
                m[k][l] = cols[k]
                    .iter()
                    .zip(&cols[l])
                    .fold(C(0.0, 0.0), |s, (p, q)| s + p.conj() * *q);
            }
            m[k][3] = cols[k].iter().zip(&r).fold(C(0.0, 0.0), |s, (p, q)| s - p.conj() * *q);
        }
        for c in 0..3 {
            let p = (c..3)
                .max_by(|&i, &j| m[i][c].norm2().total_cmp(&m[j][c].norm2()))
                .unwrap_or(c);
            m.swap(c, p);
            let pivot = m[c][c].recip();
            let row = m[c];
            for (i, other) in m.iter_mut().enumerate() {
                if i != c {
                    let f = other[c] * pivot;
                    for (x, y) in other.iter_mut().zip(row).skip(c) {
                        *x = *x - f * y;
                    }
                }
            }
        }
        for k in 0..3 {
            v[k] = v[k] + m[k][3] * m[k][k].recip();
        }
    }
    v
}

/// The Lorentz transformation of `A` in SL(2, C): its action `X -> A X A^H`
/// on the Hermitian matrices `X = [[w + z, x + i y], [x - i y, w - z]]`,
/// whose determinant is `w^2 - x^2 - y^2 - z^2`.
fn lorentz(a: M2) -> DMat4 {
    let (o, z, i) = (C(1.0, 0.0), C(0.0, 0.0), C(0.0, 1.0));
    let basis: [M2; 4] = [
        [[z, o], [o, z]],
        [[z, i], [z - i, z]],
        [[o, z], [z, z - o]],
        [[o, z], [z, o]],
    ];
    let ah = [[a[0][0].conj(), a[1][0].conj()], [a[0][1].conj(), a[1][1].conj()]];
    let cols = basis.map(|x| {
        let y = mul2(&mul2(&a, &x), &ah);
        DVec4::new(
            y[0][1].0,
            y[0][1].1,
            (y[0][0].0 - y[1][1].0) / 2.0,
            (y[0][0].0 + y[1][1].0) / 2.0,
        )
    });
    DMat4::from_cols(cols[0], cols[1], cols[2], cols[3])
}
