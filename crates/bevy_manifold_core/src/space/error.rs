//! What can be wrong with a space, each case naming the face or edge and
//! the property that fails.

use std::path::PathBuf;

/// A broken space: the property that fails and where.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SpaceError {
    /// Fewer faces than any compact polyhedron has.
    #[error(
        "a space needs at least 4 faces (in S3 also the 2 of a lens or the 1 of a hemisphere), this one has {count}"
    )]
    TooFewFaces {
        /// How many faces were given.
        count: usize,
    },
    /// A lens or hemisphere (a spherical domain without vertices) whose
    /// gluing fails Poincaré's condition ([`super::lens`]).
    #[error("the lens: {detail}")]
    Lens {
        /// What fails.
        detail: String,
    },
    /// A file frame ([`super::frame`]) that is not an isometry.
    #[error("the file frame: {detail}")]
    FileFrame {
        /// What fails.
        detail: String,
    },
    /// More faces than a space may have (the polyhedron's construction is
    /// quartic in them).
    #[error("a space may have at most {max} faces, this one has {count}")]
    TooManyFaces {
        /// How many were given.
        count: usize,
        /// The cap, [`super::MAX_FACES`].
        max: usize,
    },
    /// A NaN or infinite number in a face's plane or pairing.
    #[error("face {face}: its {what} has a NaN or infinite entry")]
    NonFinite {
        /// The face.
        face: usize,
        /// "plane" or "pairing".
        what: &'static str,
    },
    /// A covector that is no plane of the geometry.
    #[error("face {face}: {plane:?} is not a plane of {geometry} space")]
    NotAPlane {
        /// The face.
        face: usize,
        /// The offending covector.
        plane: [f64; 4],
        /// The geometry's name.
        geometry: &'static str,
    },
    /// The chart origin must lie strictly inside the domain.
    #[error(
        "face {face}: the chart origin (0,0,0,1) is not strictly on its inner side (n . origin = {value:.3e}); put the domain around the origin and orient planes with n . p <= 0 inside"
    )]
    OriginOutside {
        /// The face.
        face: usize,
        /// `n . origin`, which must be negative.
        value: f64,
    },
    /// A partner index past the face list.
    #[error("face {face}: partner {partner} does not exist (there are {count} faces)")]
    PartnerOutOfRange {
        /// The face.
        face: usize,
        /// The partner it names.
        partner: usize,
        /// How many faces there are.
        count: usize,
    },
    /// Partners must name each other.
    #[error("face {face}: its partner is {partner}, but face {partner}'s partner is {back}")]
    PartnerNotMutual {
        /// The face.
        face: usize,
        /// Its partner.
        partner: usize,
        /// The partner's partner.
        back: usize,
    },
    /// A mirror is its own partner; a glued face is not.
    #[error("face {face}: a {kind} face {rule} (partner is {partner})")]
    KindPartner {
        /// The face.
        face: usize,
        /// Its kind.
        kind: &'static str,
        /// Its partner.
        partner: usize,
        /// The broken rule in words.
        rule: &'static str,
    },
    /// The pairing matrix does not preserve the geometry's form.
    #[error("face {face}: the pairing is not an isometry of {geometry} space (form error {error:.3e})")]
    NotIsometry {
        /// The face.
        face: usize,
        /// The geometry's name.
        geometry: &'static str,
        /// Largest entry of `M^T J M - J`.
        error: f64,
    },
    /// The pairing does not carry face i onto its partner.
    #[error("face {face}: the pairing does not map it onto its partner face {partner}: {detail}")]
    FaceNotMapped {
        /// The face.
        face: usize,
        /// Its partner.
        partner: usize,
        /// What went wrong.
        detail: String,
    },
    /// `T_partner * T_i` is not the identity.
    #[error("face {face}: T_{partner} * T_{face} is not the identity (error {error:.3e})")]
    NotInverse {
        /// The face.
        face: usize,
        /// Its partner.
        partner: usize,
        /// Largest entry of `T_partner T_i - I`.
        error: f64,
    },
    /// A mirror's matrix is not a reflection in its face.
    #[error("face {face}: a mirror must be the reflection in its face ({detail})")]
    NotReflection {
        /// The face.
        face: usize,
        /// What went wrong.
        detail: String,
    },
    /// The faces do not close up into a compact polyhedron.
    #[error("the faces do not bound a compact convex polyhedron: {detail}")]
    NotCompact {
        /// What went wrong.
        detail: String,
    },
    /// A face that touches the polyhedron in fewer than three vertices.
    #[error(
        "face {face}: it touches the polyhedron in {vertices} vertices, not a polygon (a redundant or misplaced face)"
    )]
    RedundantFace {
        /// The face.
        face: usize,
        /// How many vertices lie on it.
        vertices: usize,
    },
    /// More than two faces along one edge.
    #[error("faces {faces:?}: {detail}")]
    DegenerateVertex {
        /// The faces involved.
        faces: Vec<usize>,
        /// What went wrong.
        detail: String,
    },
    /// A vertex listed in a file that is not a vertex of the faces' polyhedron.
    #[error("vertex {index}: {detail}")]
    VertexMismatch {
        /// The vertex's index in the file.
        index: usize,
        /// What went wrong.
        detail: String,
    },
    /// An edge cycle whose dihedral angles do not add up to 2 pi / k.
    #[error("edge cycle through edges {edges:?} (faces {faces:?}): {detail}")]
    EdgeCycle {
        /// The edges visited.
        edges: Vec<usize>,
        /// The faces crossed.
        faces: Vec<usize>,
        /// What went wrong.
        detail: String,
    },
    /// A volume given in a file that does not match the computed one.
    #[error("the file gives volume {given}, but the faces bound volume {computed}")]
    VolumeMismatch {
        /// The file's value.
        given: f64,
        /// The computed value.
        computed: f64,
    },
}

/// A space file that could not be loaded, with the file's name.
#[derive(Debug, thiserror::Error)]
#[error("{path}: {kind}")]
pub struct SpaceFileError {
    /// The file.
    pub path: DisplayPath,
    /// What went wrong.
    pub kind: SpaceFileErrorKind,
}

/// What went wrong while loading a space file.
#[derive(Debug, thiserror::Error)]
pub enum SpaceFileErrorKind {
    /// The file could not be read.
    #[error("cannot read: {0}")]
    Io(#[from] std::io::Error),
    /// The JSON is malformed or a field is missing.
    #[error("not a space file: {0}")]
    Json(String),
    /// The space it describes is broken.
    #[error("invalid space: {0}")]
    Invalid(#[from] SpaceError),
    /// A generator file (`.gen` or a JSON generator list) that is malformed
    /// or whose group gives no space.
    #[error("{0}")]
    Generators(#[from] super::generators::GeneratorError),
}

/// A path that displays as the user wrote it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DisplayPath(pub PathBuf);

impl core::fmt::Display for DisplayPath {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "{}", self.0.display())
    }
}
