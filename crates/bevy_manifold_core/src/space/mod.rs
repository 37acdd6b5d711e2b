//! Spaces: a geometry, a fundamental polyhedron, and for each face its
//! partner, its kind (glued or mirror) and its pairing isometry `T_i`.
//!
//! `T_i` maps face `i` onto its partner face so that a ray leaving the
//! domain through face `i` continues inside it from the partner
//! (the transport of Algorithm 1, [`crate::trace`]): it carries the copy of the domain beyond face `i` back
//! onto the domain. Glued faces come in pairs with `T_j = T_i^-1`; a mirror
//! is its own partner and `T_i` is the reflection in it.
//!
//! ```
//! use bevy_manifold_core::space::catalog;
//! let poincare = catalog::poincare();
//! assert_eq!(poincare.faces().len(), 12);
//! assert_eq!(poincare.group_order(), Some(120));
//! assert!(poincare.validate().is_ok());
//! ```

pub mod catalog;
pub mod cell_id;
pub mod cell_table;
pub mod cells;
pub mod cover;
mod cycles;
pub mod dirichlet;
pub mod element;
mod error;
pub mod exact;
pub mod file;
pub mod frame;
pub mod generators;
pub mod lens;
pub mod library;
mod polyhedron;
pub mod product;
pub mod product_cells;
pub mod product_file;
pub mod rule;
mod volume;

pub use cycles::{AbelianRelations, EdgeCycle, Homology};
pub use error::{DisplayPath, SpaceError, SpaceFileError, SpaceFileErrorKind};
pub use file::{FaceDesc, SpaceDesc};
pub use generators::{GeneratorError, Generators, GeneratorsDesc};
pub use polyhedron::{Edge, Polyhedron, Vertex, dihedral_angle};
pub use volume::{gauss_legendre, polyhedron_area};

use crate::geometry::{Geometry, isometry, plane};
use cells::{CellId, CellScheme};
use glam::{DMat4, DVec4};
use serde::{Deserialize, Serialize};

/// Most faces a space may have: building the polyhedron is quartic in the
/// face count (128 faces take about a tenth of a second).
pub const MAX_FACES: usize = 128;

/// Largest order of an edge cycle's rotation (angle sum `2 pi / k`).
pub const MAX_CYCLE_ORDER: u32 = 1000;

/// How a face is identified with its partner.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FaceKind {
    /// Glued to another face by an isometry: a manifold-like gluing.
    Glue,
    /// A mirror: its own partner, the pairing is the reflection in it.
    Mirror,
}

impl FaceKind {
    /// "glue" or "mirror".
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            FaceKind::Glue => "glue",
            FaceKind::Mirror => "mirror",
        }
    }
}

/// One face of the fundamental polyhedron.
#[derive(Clone, Debug, PartialEq)]
pub struct Face {
    /// The face plane, normalised (see [`plane::normalize`]); `n . p <= 0`
    /// inside.
    pub plane: DVec4,
    /// The face it is identified with (itself for a mirror).
    pub partner: usize,
    /// Glued or mirror.
    pub kind: FaceKind,
    /// `T_i`: carries the region beyond this face onto the domain, this face
    /// onto its partner.
    pub pairing: DMat4,
}

/// A space: a geometry, a fundamental polyhedron and its face pairings,
/// with everything derived from them (vertices, edges, edge cycles, radii,
/// volume, how copies of the domain are numbered). Cheap to query, built
/// once; validated on construction.
///
/// ```
/// use bevy_manifold_core::space::catalog;
/// let sw = catalog::seifert_weber();
/// assert_eq!(sw.vertices().len(), 20);
/// assert_eq!(sw.edge_cycles().len(), 6);
/// assert!((sw.volume() - 11.199065).abs() < 1e-5);
/// ```
#[derive(Clone, Debug)]
pub struct Space {
    name: String,
    geometry: Geometry,
    faces: Vec<Face>,
    poly: Polyhedron,
    /// The lens or hemisphere the faces bound, for a spherical domain
    /// without vertices ([`lens`]).
    lens: Option<lens::LensShape>,
    /// The chart's place in the generators' coordinates ([`frame`]).
    file_frame: DMat4,
    cycles: Vec<EdgeCycle>,
    inradius: f64,
    circumradius: f64,
    volume: f64,
    cells: CellScheme,
    cover: cover::CoverCache,
}

impl Space {
    /// Builds a space from its faces and validates it.
    ///
    /// # Errors
    /// The first property that fails, as a [`SpaceError`] naming the face.
    pub fn new(name: impl Into<String>, geometry: Geometry, faces: Vec<Face>) -> Result<Self, SpaceError> {
        let mut space = Self::build(name.into(), geometry, faces)?;
        // Pairings first: the edge-cycle walk relies on them mapping faces
        // onto faces, and their errors name the face that is wrong.
        space.check_pairings()?;
        space.cycles = cycles::edge_cycles(&space)?;
        cycles::check_cycles(&space.cycles)?;
        if let Some(shape) = space.lens {
            lens::check(shape, &space.faces)?;
        }
        space.cells = CellScheme::for_space(&space);
        Ok(space)
    }

    /// Derives the polyhedron, radii and volume from the planes; the
    /// pairings, edge cycles and cells are checked and derived by `new`.
    fn build(name: String, geometry: Geometry, mut faces: Vec<Face>) -> Result<Self, SpaceError> {
        if faces.is_empty() || (faces.len() < 4 && geometry != Geometry::Spherical) || faces.len() == 3 {
            return Err(SpaceError::TooFewFaces { count: faces.len() });
        }
        if faces.len() > MAX_FACES {
            return Err(SpaceError::TooManyFaces {
                count: faces.len(),
                max: MAX_FACES,
            });
        }
        for (i, f) in faces.iter_mut().enumerate() {
            if !f.plane.is_finite() {
                return Err(SpaceError::NonFinite { face: i, what: "plane" });
            }
            if !f.pairing.is_finite() {
                return Err(SpaceError::NonFinite {
                    face: i,
                    what: "pairing",
                });
            }
            f.plane = plane::normalize(geometry, f.plane).ok_or(SpaceError::NotAPlane {
                face: i,
                plane: f.plane.to_array(),
                geometry: geometry.name(),
            })?;
            let value = f.plane.w;
            if value >= -1e-12 {
                return Err(SpaceError::OriginOutside { face: i, value });
            }
        }
        let count = faces.len();
        for (i, f) in faces.iter().enumerate() {
            if f.partner >= count {
                return Err(SpaceError::PartnerOutOfRange {
                    face: i,
                    partner: f.partner,
                    count,
                });
            }
            let back = faces[f.partner].partner;
            if back != i {
                return Err(SpaceError::PartnerNotMutual {
                    face: i,
                    partner: f.partner,
                    back,
                });
            }
            match (f.kind, f.partner == i) {
                // The hemisphere's face, glued to itself by the antipodal
                // map (checked by lens::check).
                (FaceKind::Glue, true) if count == 1 => {}
                (FaceKind::Mirror, false) => {
                    return Err(SpaceError::KindPartner {
                        face: i,
                        kind: "mirror",
                        partner: f.partner,
                        rule: "must be its own partner",
                    });
                }
                (FaceKind::Glue, true) => {
                    return Err(SpaceError::KindPartner {
                        face: i,
                        kind: "glue",
                        partner: f.partner,
                        rule: "must be glued to another face",
                    });
                }
                _ => {}
            }
        }
        let planes: Vec<DVec4> = faces.iter().map(|f| f.plane).collect();
        let lens = if planes.len() < 4 {
            Some(lens::shape(geometry, &planes).ok_or_else(|| SpaceError::NotCompact {
                detail: format!(
                    "{} faces bound no lens (two faces meeting in the great circle a quarter turn from the origin) or hemisphere (the one face w = 0)",
                    planes.len()
                ),
            })?)
        } else {
            None
        };
        let poly = match lens {
            Some(_) => Polyhedron::without_vertices(planes.len()),
            None => Polyhedron::from_planes(geometry, &planes)?,
        };
        let origin = DVec4::W;
        let inradius = planes
            .iter()
            .map(|&n| -plane::signed_distance(geometry, n, origin))
            .fold(f64::INFINITY, f64::min);
        // A lens's rim (and the hemisphere's face) is a quarter turn from
        // the origin.
        let circumradius = match lens {
            Some(_) => core::f64::consts::FRAC_PI_2,
            None => poly
                .vertices
                .iter()
                .map(|v| geometry.distance::<f64>(origin, v.point))
                .fold(0.0, f64::max),
        };
        let points: Vec<DVec4> = poly.vertices.iter().map(|v| v.point).collect();
        let volume = match lens {
            Some(shape) => shape.volume(),
            None => volume::polyhedron_volume(geometry, &planes, &points, &poly.face_vertices),
        };
        let space = Space {
            lens,
            file_frame: DMat4::IDENTITY,
            name,
            geometry,
            faces,
            poly,
            cycles: Vec::new(),
            inradius,
            circumradius,
            volume,
            cells: CellScheme::Hashed { quantum: 1.0 },
            cover: cover::CoverCache::default(),
        };
        Ok(space)
    }

    /// Checks every property a space must have, returning the first that
    /// fails: each pairing preserves the form, maps its face onto the
    /// partner face (vertices onto vertices, the inside to the outside),
    /// `T_partner * T_i = I`, a mirror is the reflection in its face, and the
    /// dihedral angles around each edge cycle add up to `2 pi / k`.
    ///
    /// # Errors
    /// The [`SpaceError`] that names the face or edge cycle and the property.
    pub fn validate(&self) -> Result<(), SpaceError> {
        self.check_pairings()?;
        cycles::check_cycles(&cycles::edge_cycles(self)?)?;
        match self.lens {
            Some(shape) => lens::check(shape, &self.faces),
            None => Ok(()),
        }
    }

    fn check_pairings(&self) -> Result<(), SpaceError> {
        let g = self.geometry;
        for (i, f) in self.faces.iter().enumerate() {
            let error = isometry::isometry_error(g, f.pairing);
            if error.is_nan() || error >= 1e-8 {
                return Err(SpaceError::NotIsometry {
                    face: i,
                    geometry: g.name(),
                    error,
                });
            }
            let partner = &self.faces[f.partner];
            // T_i^T n_j must be a negative multiple of n_i: face i goes onto
            // face j, and the domain goes to the far side of face j.
            let pulled = f.pairing.transpose() * partner.plane;
            let scale = -pulled.dot(f.plane) / f.plane.dot(f.plane);
            if scale.is_nan() || scale <= 0.0 || (pulled + f.plane * scale).length() > 1e-8 * scale.abs().max(1.0) {
                return Err(SpaceError::FaceNotMapped {
                    face: i,
                    partner: f.partner,
                    detail:
                        "the plane of the face is not carried onto the partner's plane with the inside turned outwards"
                            .into(),
                });
            }
            for &v in &self.poly.face_vertices[i] {
                let image = f.pairing * self.poly.vertices[v].point;
                match self.poly.vertex_at(image) {
                    Some(w) if self.poly.face_vertices[f.partner].contains(&w) => {}
                    _ => {
                        return Err(SpaceError::FaceNotMapped {
                            face: i,
                            partner: f.partner,
                            detail: format!(
                                "vertex {v} goes to {:?}, which is not a vertex of face {}",
                                image.to_array(),
                                f.partner
                            ),
                        });
                    }
                }
            }
            let product = partner.pairing * f.pairing;
            let error = max_abs_diff(product, DMat4::IDENTITY);
            if f.kind == FaceKind::Mirror {
                if error > 1e-8 {
                    return Err(SpaceError::NotReflection {
                        face: i,
                        detail: format!("T * T differs from the identity by {error:.3e}"),
                    });
                }
                let fixed = self.poly.face_vertices[i]
                    .iter()
                    .map(|&v| (f.pairing * self.poly.vertices[v].point - self.poly.vertices[v].point).length())
                    .fold(0.0, f64::max);
                if fixed > 1e-8 {
                    return Err(SpaceError::NotReflection {
                        face: i,
                        detail: format!("it moves the face's own vertices by up to {fixed:.3e}"),
                    });
                }
            } else if error > 1e-8 {
                return Err(SpaceError::NotInverse {
                    face: i,
                    partner: f.partner,
                    error,
                });
            }
        }
        Ok(())
    }

    /// The space's name.
    #[must_use]
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The model geometry.
    #[must_use]
    pub fn geometry(&self) -> Geometry {
        self.geometry
    }

    /// The faces, with planes, partners, kinds and pairings.
    #[must_use]
    pub fn faces(&self) -> &[Face] {
        &self.faces
    }

    /// The polyhedron: vertices, edges, face polygons.
    #[must_use]
    pub fn polyhedron(&self) -> &Polyhedron {
        &self.poly
    }

    /// The lens or hemisphere the domain is when it has no vertices
    /// (lens spaces about a point of an orbit circle, RP3); `None` for a
    /// polyhedron.
    #[must_use]
    pub fn lens(&self) -> Option<lens::LensShape> {
        self.lens
    }

    /// The vertices of the fundamental polyhedron.
    #[must_use]
    pub fn vertices(&self) -> &[Vertex] {
        &self.poly.vertices
    }

    /// The edges of the fundamental polyhedron.
    #[must_use]
    pub fn edges(&self) -> &[Edge] {
        &self.poly.edges
    }

    /// The edge cycles: classes of edges identified by the pairings.
    #[must_use]
    pub fn edge_cycles(&self) -> &[EdgeCycle] {
        &self.cycles
    }

    /// Distance from the chart origin to the nearest face.
    #[must_use]
    pub fn inradius(&self) -> f64 {
        self.inradius
    }

    /// Distance from the chart origin to the farthest vertex.
    #[must_use]
    pub fn circumradius(&self) -> f64 {
        self.circumradius
    }

    /// Area of the fundamental polyhedron's boundary (its faces).
    ///
    /// ```
    /// use bevy_manifold_core::prelude::*;
    /// // The cube of edge 2: six faces of area 4.
    /// assert!((catalog::torus(2.0).surface_area() - 24.0).abs() < 1e-9);
    /// ```
    #[must_use]
    pub fn surface_area(&self) -> f64 {
        if let Some(shape) = self.lens {
            return shape.area();
        }
        let points: Vec<_> = self.poly.vertices.iter().map(|v| v.point).collect();
        polyhedron_area(self.geometry, &points, &self.poly.face_vertices)
    }

    /// Volume of the fundamental polyhedron (so of the space).
    #[must_use]
    pub fn volume(&self) -> f64 {
        self.volume
    }

    /// True when every face is glued and every edge cycle closes after one
    /// turn: the quotient is a manifold (otherwise an orbifold).
    #[must_use]
    pub fn is_manifold(&self) -> bool {
        self.faces.iter().all(|f| f.kind == FaceKind::Glue) && self.cycles.iter().all(|c| c.order == 1)
    }

    /// How copies of the domain in the cover are numbered.
    #[must_use]
    pub fn cells(&self) -> &CellScheme {
        &self.cells
    }

    /// Order of the group generated by the pairings, when finite (spherical
    /// spaces).
    #[must_use]
    pub fn group_order(&self) -> Option<usize> {
        match &self.cells {
            CellScheme::Finite { elements, .. } => Some(elements.len()),
            _ => None,
        }
    }

    /// The path-independent id of the copy `g(D)` of the domain.
    #[must_use]
    pub fn cell_id(&self, g: &DMat4) -> CellId {
        self.cells.id_of(g)
    }

    /// What a ray's group element is multiplied by (on the right) when it
    /// crosses face `i`: `T_i^-1`, which is `T_partner`.
    #[must_use]
    pub fn crossing(&self, face: usize) -> DMat4 {
        self.faces[self.faces[face].partner].pairing
    }

    /// The first homology group of the quotient (abelianised orbifold
    /// fundamental group), from the face pairings and edge-cycle relations.
    /// `None` when the integer elimination would leave `i128` (checked,
    /// never wrapped; not seen for any space within [`MAX_FACES`]).
    #[must_use]
    pub fn first_homology(&self) -> Option<Homology> {
        cycles::first_homology(self)
    }

    /// The abelianised group's generators and relations, from which
    /// [`Space::first_homology`] is computed: a homomorphism of the group
    /// onto an abelian group is a choice per generator that every row
    /// sends to 0.
    #[must_use]
    pub fn abelian_relations(&self) -> AbelianRelations {
        cycles::abelian_relations(self)
    }

    /// Index of the face whose half-space `p` violates most, if any violates
    /// it by more than `eps` (chart units).
    ///
    /// A point with `w <= 0` (S3's far hemisphere, or a non-finite point)
    /// is outside every domain, which lies in `w > 0`: dividing by its `w`
    /// would show its antipode instead, inside for the antipode of a
    /// point inside. The test is homogeneous (`plane . p` against
    /// `eps * w`), and for `w <= 0` the face with the largest `plane . p`
    /// (positive for some face, as the domain's cone holds no point with
    /// `w <= 0`) is the answer.
    #[must_use]
    pub fn outside_face(&self, p: DVec4, eps: f64) -> Option<usize> {
        most_outside(self.faces.iter().map(|f| f.plane), p, eps)
    }

    /// Brings an isometry placed anywhere in the cover back into the domain:
    /// while its image of the origin lies outside some face, applies that
    /// face's pairing. Returns the wrapped isometry and the group element
    /// `g` with `g * wrapped = placement` (the cell it was in). Gives up
    /// after `max_steps` steps, returning what it has.
    #[must_use]
    pub fn wrap(&self, placement: DMat4, max_steps: usize) -> (DMat4, DMat4) {
        self.wrap_with(placement, max_steps, &mut |_| {})
    }

    /// [`Space::wrap`], calling `on_face` with each face it carries the
    /// placement through.
    pub fn wrap_with(&self, placement: DMat4, max_steps: usize, on_face: &mut dyn FnMut(usize)) -> (DMat4, DMat4) {
        let g = self.geometry;
        let mut m = placement;
        let mut cell = DMat4::IDENTITY;
        for _ in 0..max_steps {
            let Some(f) = self.outside_face(m.w_axis, 1e-12) else {
                break;
            };
            m = isometry::orthonormalize(g, self.faces[f].pairing * m);
            cell *= self.crossing(f);
            on_face(f);
        }
        (m, cell)
    }
}

/// [`Space::outside_face`] over the face planes `planes`: shared with the
/// exact walk home of [`cells::ExactCells::locate`].
pub(crate) fn most_outside(planes: impl Iterator<Item = DVec4>, p: DVec4, eps: f64) -> Option<usize> {
    let mut best = None;
    if p.w > 0.0 {
        let mut worst = eps;
        for (i, f) in planes.enumerate() {
            let s = f.dot(p) / p.w;
            if s > worst {
                worst = s;
                best = Some(i);
            }
        }
    } else {
        let mut worst = f64::NEG_INFINITY;
        for (i, f) in planes.enumerate() {
            let s = f.dot(p);
            if s > worst || best.is_none() {
                worst = s;
                best = Some(i);
            }
        }
    }
    best
}

pub(crate) fn max_abs_diff(a: DMat4, b: DMat4) -> f64 {
    (a - b).to_cols_array().iter().fold(0.0f64, |m, x| m.max(x.abs()))
}
