//! Spherical domains without vertices. The Dirichlet domain of a lens
//! space about a point whose orbit is one great circle (every point of
//! `L(p, +-1)`; the points of the orbit circles of `L(p, q)`) is a
//! **lens**: the points between two faces, half great spheres meeting in
//! the great circle a quarter turn from the basepoint (the rim), at the
//! dihedral angle `2 pi / p`. The domain of RP3 (`L(2, 1)`) is a
//! **hemisphere**: one face, the great sphere a quarter turn from the
//! basepoint, glued to itself by the antipodal map.
//!
//! In the projective chart about the basepoint a lens is the slab between
//! two parallel planes and the hemisphere is the whole chart; the rim and
//! the hemisphere's face lie at infinity. Nothing in the tracer needs the
//! chart to hold them: a ray is a great circle in R4 from its own origin
//! ([`crate::trace`]), and it meets a face where the face's covector
//! vanishes on it, within a quarter turn, as in any domain. What a lens
//! lacks is vertices and edges: its validation (Poincaré's theorem for a
//! lens: the rim's angle times the order of the pairing is a full turn;
//! the hemisphere's self-gluing has no fixed point), its volume (`pi`
//! times the rim's angle: a whole turn is S3's `2 pi^2`) and its surface
//! (`2 pi` a half great sphere) are worked out here instead.
//!
//! ```
//! use bevy_manifold_core::space::library;
//! let l51 = library::by_name("lens-5-1").unwrap().dirichlet_domain().unwrap();
//! assert_eq!(l51.faces().len(), 2);
//! assert!(l51.vertices().is_empty());
//! let pi = std::f64::consts::PI;
//! assert!((l51.volume() - 2.0 * pi * pi / 5.0).abs() < 1e-9);
//! assert!((l51.inradius() - pi / 5.0).abs() < 1e-9);
//! ```

use super::{Face, FaceKind, SpaceError, max_abs_diff};
use crate::geometry::Geometry;
use glam::{DMat4, DVec4};
use std::f64::consts::{PI, TAU};

/// The shape of a spherical domain with no vertices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LensShape {
    /// The interior dihedral angle at the rim (`pi` for the hemisphere,
    /// whose one face is a whole great sphere).
    pub dihedral: f64,
}

impl LensShape {
    /// The domain's volume: `pi` times the rim's angle.
    #[must_use]
    pub fn volume(self) -> f64 {
        PI * self.dihedral
    }

    /// The domain's surface: `4 pi` whatever the angle, two half great
    /// spheres for a lens, the whole great sphere for the hemisphere.
    #[must_use]
    pub fn area(self) -> f64 {
        4.0 * PI
    }
}

/// The component of `v` orthogonal to the unit vectors `basis`.
fn reject(v: DVec4, basis: &[DVec4]) -> DVec4 {
    basis.iter().fold(v, |r, b| r - *b * r.dot(*b))
}

/// `N` orthonormal vectors orthogonal to the orthonormal `given` and to
/// each other, from the axes in turn (`N` at most `4 - given.len()`).
fn complement<const N: usize>(given: &[DVec4]) -> [DVec4; N] {
    let mut basis = given.to_vec();
    for e in [DVec4::X, DVec4::Y, DVec4::Z, DVec4::W] {
        let r = reject(e, &basis);
        if basis.len() < given.len() + N && r.length() > 1e-6 {
            basis.push(r.normalize());
        }
    }
    std::array::from_fn(|k| basis[given.len() + k])
}

/// The lens or hemisphere the normalised face covectors `planes` bound
/// (the inside `n . x <= 0`, the basepoint `(0, 0, 0, 1)` inside), or
/// `None` when they bound something else: S3 only; one face, the great
/// sphere `w = 0`; or two distinct faces whose rim (the great circle
/// where both covectors vanish) lies at `w = 0`, so that the domain lies
/// in the basepoint's hemisphere.
#[must_use]
pub fn shape(g: Geometry, planes: &[DVec4]) -> Option<LensShape> {
    if g != Geometry::Spherical {
        return None;
    }
    match planes {
        [n] => (reject(*n, &[DVec4::W]).length() < 1e-9 && n.w < 0.0).then_some(LensShape { dihedral: PI }),
        [a, b] => {
            let a = a.normalize();
            let e = reject(*b, &[a]);
            if e.length() < 1e-9 {
                return None; // one great sphere twice
            }
            // The rim is orthogonal to a and b: at w = 0 when W is in
            // their span.
            if reject(DVec4::W, &[a, e.normalize()]).length() > 1e-9 {
                return None;
            }
            // The interior angle between the half-spaces a . x <= 0 and
            // b . x <= 0: pi minus the angle between the covectors.
            let b = b.normalize();
            Some(LensShape {
                dihedral: PI - a.dot(b).clamp(-1.0, 1.0).acos(),
            })
        }
        _ => None,
    }
}

/// The order of `m` (the least `k` with `m^k = I`), if at most `max`.
fn order(m: DMat4, max: u32) -> Option<u32> {
    let mut power = m;
    for k in 1..=max {
        if max_abs_diff(power, DMat4::IDENTITY) < 1e-8 {
            return Some(k);
        }
        power = m * power;
    }
    None
}

/// Whether the isometry `m` of S3 fixes no point: `m - I` is invertible.
pub(crate) fn is_free(m: DMat4) -> bool {
    (m - DMat4::IDENTITY).determinant().abs() > 1e-9
}

/// Poincaré's condition where a lens has no edges (the faces' own checks,
/// each onto its partner with the inside turned out, are
/// [`super::Space::validate`]'s as for every space): a lens's pairing
/// turns the rim onto itself by the rim's angle, so the angle times the
/// pairing's order must be a whole turn; a hemisphere's face, glued to
/// itself, must be glued by an isometry fixing no point (the antipodal
/// map), or be a mirror.
///
/// # Errors
/// [`SpaceError::Lens`] naming what fails.
pub(crate) fn check(shape: LensShape, faces: &[Face]) -> Result<(), SpaceError> {
    // A mirror fixes its face (a polyhedron's vertices show it; here three
    // points spanning the face's great sphere do).
    for (face, f) in faces.iter().enumerate().filter(|(_, f)| f.kind == FaceKind::Mirror) {
        let moved = face_points(f.plane)
            .iter()
            .map(|p| (f.pairing * *p - *p).length())
            .fold(0.0, f64::max);
        if moved > 1e-8 {
            return Err(SpaceError::NotReflection {
                face,
                detail: format!("it moves its own face by up to {moved:.3e}"),
            });
        }
    }
    match faces {
        [f] => match f.kind {
            FaceKind::Mirror => Ok(()),
            FaceKind::Glue if is_free(f.pairing) => Ok(()),
            FaceKind::Glue => Err(SpaceError::Lens {
                detail: "the hemisphere's face is glued to itself by an isometry with a fixed point".into(),
            }),
        },
        [a, b] => {
            if a.kind == FaceKind::Mirror || b.kind == FaceKind::Mirror {
                // A lens between two mirrors: the rim's angle is pi / k.
                let k = PI / shape.dihedral;
                if a.kind == FaceKind::Mirror && b.kind == FaceKind::Mirror && (k - k.round()).abs() < 1e-8 {
                    return Ok(());
                }
                return Err(SpaceError::Lens {
                    detail: format!(
                        "a lens with a mirror needs mirrors on both faces meeting at pi / k, not {:.9} rad",
                        shape.dihedral
                    ),
                });
            }
            // The pairing carries face a's half great sphere onto face
            // b's, so its rim onto the rim.
            let rim = rim(a.plane, b.plane);
            let moved = rim
                .iter()
                .map(|r| {
                    let t = a.pairing * *r;
                    t.dot(a.plane.normalize()).abs().max(t.dot(b.plane.normalize()).abs())
                })
                .fold(0.0, f64::max);
            if moved > 1e-8 {
                return Err(SpaceError::Lens {
                    detail: format!("the pairing of face 0 moves the rim off itself (by {moved:.3e})"),
                });
            }
            let max = (TAU / shape.dihedral).round().max(1.0) as u32;
            match order(a.pairing, max.min(super::MAX_CYCLE_ORDER)) {
                Some(k) if (f64::from(k) * shape.dihedral - TAU).abs() < 1e-8 => Ok(()),
                Some(k) => Err(SpaceError::Lens {
                    detail: format!(
                        "the rim's angle {:.9} times the pairing's order {k} is {:.9}, not a whole turn",
                        shape.dihedral,
                        f64::from(k) * shape.dihedral
                    ),
                }),
                None => Err(SpaceError::Lens {
                    detail: format!(
                        "the pairing's order is not {max} or less, as the rim's angle {:.9} needs",
                        shape.dihedral
                    ),
                }),
            }
        }
        _ => Err(SpaceError::Lens {
            detail: format!("a lens has one or two faces, not {}", faces.len()),
        }),
    }
}

/// Two orthonormal vectors spanning the rim of the faces `a` and `b`.
fn rim(a: DVec4, b: DVec4) -> [DVec4; 2] {
    let a = a.normalize();
    complement(&[a, reject(b, &[a]).normalize()])
}

/// Three points spanning the face `n`'s great sphere, for tests of what a
/// pairing does to a face that has no vertices.
#[must_use]
pub fn face_points(n: DVec4) -> [DVec4; 3] {
    complement(&[n.normalize()])
}
