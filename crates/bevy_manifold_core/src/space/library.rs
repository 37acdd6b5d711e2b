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

/// The lens spaces in the library, as `(p, q)`. `L(p, +-1)` are left out:
/// their Dirichlet domains are lenses with two faces whose edge is a whole
/// great circle, which no single chart holds.
pub const LENS: [(u32, u32); 5] = [(5, 2), (7, 2), (8, 3), (10, 3), (12, 5)];

/// The prism manifolds S3/D*_4m in the library, as `m`.
pub const PRISM: [u32; 3] = [3, 4, 5];

/// Every library space's name.
#[must_use]
pub fn names() -> Vec<String> {
    let mut out: Vec<String> = LENS.iter().map(|(p, q)| format!("lens-{p}-{q}")).collect();
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
        ]
        .map(String::from),
    );
    out
}

/// A library space's generators by name (`None` for an unknown name).
#[must_use]
pub fn by_name(name: &str) -> Option<Generators> {
    if let Some(rest) = name.strip_prefix("lens-") {
        let (p, q) = rest.split_once('-')?;
        let (p, q) = (p.parse().ok()?, q.parse().ok()?);
        return (LENS.contains(&(p, q))).then(|| lens(p, q));
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
        _ => return None,
    })
}

/// The comment a library file starts with: what the space is and how its
/// generators were computed.
#[must_use]
pub fn header(name: &str) -> String {
    let what = if let Some(rest) = name.strip_prefix("lens-") {
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
    Generators {
        name,
        geometry,
        matrices,
        basepoint: None,
        manifold: false,
    }
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
