//! The catalog: the paper's five spaces (and the torus with any edge
//! length), each built from first principles: the inradius from the
//! dihedral angle, the pairings as screw motions or reflections.

use super::{Face, FaceKind, Space};
use crate::geometry::{Geometry, isometry, plane};
use glam::{DVec3, DVec4};
use std::f64::consts::{PI, TAU};

/// Names of the catalog spaces, as `space list` prints them.
pub const NAMES: [&str; 5] = [
    "torus",
    "seifert-weber",
    "poincare",
    "mirrored-cube",
    "mirrored-dodecahedron",
];

/// A catalog space by name (`None` for an unknown name).
#[must_use]
pub fn by_name(name: &str) -> Option<Space> {
    Some(match name {
        "torus" => torus(1.0),
        "seifert-weber" => seifert_weber(),
        "poincare" => poincare(),
        "mirrored-cube" => mirrored_cube(1.0),
        "mirrored-dodecahedron" => mirrored_dodecahedron(),
        _ => return None,
    })
}

/// A catalog space by name, else a library space by name (built from its
/// generators, [`super::library`]), else the space file at that path (a
/// space, a `.gen` file or a generator list): what the command line and
/// the explorer accept wherever a space is asked for.
///
/// # Errors
/// An unknown name that is no file either, or the file's error.
///
/// ```
/// use bevy_manifold_core::space::catalog;
/// assert_eq!(catalog::resolve("poincare").unwrap().name(), catalog::poincare().name());
/// assert!(catalog::resolve("no-such-space").unwrap_err().contains("neither a catalog space"));
/// ```
pub fn resolve(name: &str) -> Result<Space, String> {
    if let Some(s) = by_name(name) {
        return Ok(s);
    }
    if let Some(gens) = super::library::by_name(name) {
        return gens
            .dirichlet_domain()
            .map_err(|e| format!("library space '{name}': {e}"));
    }
    let path = std::path::Path::new(name);
    if path.exists() {
        return Space::load(path).map_err(|e| e.to_string());
    }
    Err(format!(
        "'{name}' is neither a catalog space ({}), a library space (see `space list`) nor a space file",
        NAMES.join(", ")
    ))
}

/// The flat 3-torus: the cube of edge `edge` centred at the origin,
/// opposite faces glued by translations (the paper's Example 1, edge 1).
///
/// # Panics
/// If `edge` is not positive and finite.
#[must_use]
pub fn torus(edge: f64) -> Space {
    assert!(
        edge > 0.0 && edge.is_finite(),
        "torus edge must be positive, got {edge}"
    );
    let g = Geometry::Euclidean;
    let normals = cube_normals();
    let faces = normals
        .iter()
        .enumerate()
        .map(|(i, &u)| Face {
            plane: face_plane(g, u, edge / 2.0),
            partner: (i + 3) % 6,
            kind: FaceKind::Glue,
            pairing: isometry::translation(g, -u * edge),
        })
        .collect();
    expect_valid(Space::new("torus", g, faces))
}

/// The mirrored cube: a Euclidean cube of edge `edge` whose six faces are
/// mirrors (the paper's Example 4), an orbifold.
///
/// # Panics
/// If `edge` is not positive and finite.
#[must_use]
pub fn mirrored_cube(edge: f64) -> Space {
    assert!(edge > 0.0 && edge.is_finite(), "cube edge must be positive, got {edge}");
    mirrored("mirrored-cube", Geometry::Euclidean, &cube_normals(), edge / 2.0)
}

/// The Seifert-Weber dodecahedral space: the regular hyperbolic
/// dodecahedron with dihedral angle 72 degrees, opposite faces glued with a
/// twist of 3/10 of a turn (the paper's Example 2; its "3 pi/10" is a
/// misprint for 3/10 of a turn, `3 pi / 5`: only a twist that is an odd
/// multiple of 1/10 turn carries a pentagon onto the opposite one, and
/// 3/10 gives the six edge cycles of five).
#[must_use]
pub fn seifert_weber() -> Space {
    twisted_dodecahedron("seifert-weber", Geometry::Hyperbolic, TAU / 5.0, 3.0 * TAU / 10.0)
}

/// The Poincaré dodecahedral space: the regular spherical dodecahedron with
/// dihedral angle 120 degrees, opposite faces glued with a twist of 1/10 of
/// a turn (the paper's Example 3). Its group has 120 elements.
#[must_use]
pub fn poincare() -> Space {
    twisted_dodecahedron("poincare", Geometry::Spherical, TAU / 3.0, TAU / 10.0)
}

/// The right-angled hyperbolic dodecahedron with mirror faces (the paper's
/// Example 5), an orbifold.
#[must_use]
pub fn mirrored_dodecahedron() -> Space {
    let normals = dodecahedron_normals();
    let r = regular_inradius(Geometry::Hyperbolic, &normals, PI / 2.0);
    mirrored("mirrored-dodecahedron", Geometry::Hyperbolic, &normals, r)
}

/// A regular dodecahedron with the given dihedral angle in `g`, opposite
/// faces glued by the screw motion along their common axis: translation by
/// twice the inradius and a turn by `twist` about the face's outward normal.
#[must_use]
pub fn twisted_dodecahedron(name: &str, g: Geometry, dihedral: f64, twist: f64) -> Space {
    let normals = dodecahedron_normals();
    let r = regular_inradius(g, &normals, dihedral);
    let faces = normals
        .iter()
        .enumerate()
        .map(|(i, &u)| Face {
            plane: face_plane(g, u, r),
            partner: (i + 6) % 12,
            kind: FaceKind::Glue,
            pairing: isometry::screw(g, u, -2.0 * r, twist),
        })
        .collect();
    expect_valid(Space::new(name, g, faces))
}

/// The inradius of the regular polyhedron with face directions `normals`
/// (unit vectors from the centre) and dihedral angle `dihedral` in `g`.
///
/// In the right triangle formed by the centre, a face centre and the
/// midpoint of one of its edges, the angle at the centre `A` is fixed by
/// the symmetry (half the angle between adjacent face normals), the angle at
/// the edge midpoint is half the dihedral angle and the leg at the centre is
/// the inradius `r`. Right-triangle trigonometry gives
/// `cosh r = cos(dihedral/2) / sin A` in H3 and `cos r = ...` in S3.
///
/// # Panics
/// In E3 (where the dihedral angle does not fix the size) and when the
/// angle is impossible in `g`.
#[must_use]
pub fn regular_inradius(g: Geometry, normals: &[DVec3], dihedral: f64) -> f64 {
    let nearest = normals[1..]
        .iter()
        .map(|u| normals[0].dot(*u))
        .fold(f64::NEG_INFINITY, f64::max);
    let a = nearest.acos() / 2.0;
    let c = (dihedral / 2.0).cos() / a.sin();
    match g {
        Geometry::Hyperbolic => {
            assert!(c > 1.0, "dihedral angle too large for a hyperbolic polyhedron");
            c.acosh()
        }
        Geometry::Spherical => {
            assert!(c < 1.0, "dihedral angle too small for a spherical polyhedron");
            c.acos()
        }
        Geometry::Euclidean => panic!("in E3 the dihedral angle does not fix the size"),
    }
}

/// The plane at distance `r` from the origin with outward unit normal `u`.
#[must_use]
pub fn face_plane(g: Geometry, u: DVec3, r: f64) -> DVec4 {
    let (c, s) = match g {
        Geometry::Euclidean => (1.0, r),
        Geometry::Hyperbolic => (r.cosh(), r.sinh()),
        Geometry::Spherical => (r.cos(), r.sin()),
    };
    (u * c).extend(-s)
}

/// The 12 face directions of the regular dodecahedron (the vertices of the
/// icosahedron), ordered so that face `i + 6` is opposite face `i`.
#[must_use]
pub fn dodecahedron_normals() -> [DVec3; 12] {
    let phi = (1.0 + 5f64.sqrt()) / 2.0;
    let half = [
        DVec3::new(0.0, 1.0, phi),
        DVec3::new(0.0, -1.0, phi),
        DVec3::new(1.0, phi, 0.0),
        DVec3::new(-1.0, phi, 0.0),
        DVec3::new(phi, 0.0, 1.0),
        DVec3::new(phi, 0.0, -1.0),
    ];
    core::array::from_fn(|i| {
        if i < 6 {
            half[i].normalize()
        } else {
            -half[i - 6].normalize()
        }
    })
}

/// The 6 face directions of the cube, face `i + 3` opposite face `i`.
#[must_use]
pub fn cube_normals() -> [DVec3; 6] {
    [DVec3::X, DVec3::Y, DVec3::Z, -DVec3::X, -DVec3::Y, -DVec3::Z]
}

fn mirrored(name: &str, g: Geometry, normals: &[DVec3], r: f64) -> Space {
    let faces = normals
        .iter()
        .enumerate()
        .map(|(i, &u)| {
            let n = face_plane(g, u, r);
            Face {
                plane: n,
                partner: i,
                kind: FaceKind::Mirror,
                pairing: isometry::reflection(g, plane::normalize(g, n).unwrap_or(n)),
            }
        })
        .collect();
    expect_valid(Space::new(name, g, faces))
}

/// Catalog spaces are built from exact constructions; failing validation is
/// a bug in this file, caught by the tests.
fn expect_valid(s: Result<Space, super::SpaceError>) -> Space {
    match s {
        Ok(s) => s,
        Err(e) => panic!("catalog space failed validation: {e}"),
    }
}
