//! Spaces given by their generators: a list of isometries that generate the
//! group, read from Jeff Weeks' Curved Spaces `.gen` files or from the
//! project's JSON generator lists, the geometry recognised from the
//! matrices. [`super::dirichlet`] turns them into a space.
//!
//! **`.gen`** (Curved Spaces): 4x4 matrices, one row of four numbers a line,
//! `#` starts a comment, blank lines between matrices. The matrices act on
//! row vectors from the right (`v * M`); in flat spaces the translation is
//! the bottom row, in hyperbolic spaces the last coordinate is time-like.
//! Two comment lines are read as directives (Curved Spaces skips them as
//! comments): `# @basepoint x y z w` centres the Dirichlet domain there,
//! `# @manifold` refuses a group that does not act freely.
//!
//! **Generator lists** (JSON, the project's column-vector convention, the
//! same as space files):
//!
//! ```text
//! {"name": "...", "geometry": "spherical",      // optional: recognised
//!  "generators": [[[..4..],[..4..],[..4..],[..4..]], ...],   // row-major
//!  "basepoint": [x, y, z, w],                    // optional
//!  "manifold": true}                             // optional: refuse orbifolds
//! ```
//!
//! Only geometry recognition is ambiguous: a rotation about the origin is
//! an isometry of all three geometries, so a set of generators must contain
//! one that tells them apart (a translation does).
//!
//! A file written transposed (column vectors where Curved Spaces expects
//! rows) is caught in flat spaces, where the translation lands in the last
//! column. In S3 and H3 the transpose of an isometry is the inverse of an
//! isometry (S3), or its conjugate by the point reflection in the origin
//! (H3), so the transposed list generates the same group or its mirror
//! image: the same space up to orientation, never a wrong one.
//!
//! ```
//! use bevy_manifold_core::{geometry::Geometry, space::generators::Generators};
//! // Curved Spaces' cubic 3-torus: translations in the bottom row.
//! let text = "1 0 0 0\n0 1 0 0\n0 0 1 0\n1 0 0 1\n\n\
//!            1 0 0 0\n0 1 0 0\n0 0 1 0\n0 1 0 1\n\n\
//!            1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 1 1\n";
//! let gens = Generators::parse_gen(text, "cube").unwrap();
//! assert_eq!(gens.geometry, Geometry::Euclidean);
//! assert_eq!(gens.matrices[0].w_axis, glam::DVec4::new(1.0, 0.0, 0.0, 1.0));
//! let space = gens.dirichlet_domain().unwrap();
//! assert_eq!(space.faces().len(), 6);
//! assert!((space.volume() - 1.0).abs() < 1e-12);
//! ```

use super::file::{from_rows, to_rows};
use super::{DisplayPath, SpaceError, SpaceFileError, SpaceFileErrorKind};
use crate::geometry::{Geometry, isometry};
use glam::{DMat4, DVec4};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Largest number of generators a file may list.
pub const MAX_GENERATORS: usize = 64;

/// How far from an isometry a generator may be (largest entry of
/// `M^T J M - J`); files print about 20 digits, hand-made ones fewer.
pub const ISOMETRY_TOLERANCE: f64 = 1e-7;

/// A list of isometries generating a group, in the column-vector
/// convention, and the geometry they act on.
///
/// ```
/// use bevy_manifold_core::geometry::Geometry;
/// use bevy_manifold_core::space::generators::Generators;
/// // The quaternionic space S3/Q8: left multiplication by i and j.
/// use bevy_manifold_core::space::library::left_multiplication;
/// let gens = Generators::new("quaternionic", vec![
///     left_multiplication([0.0, 1.0, 0.0, 0.0]),
///     left_multiplication([0.0, 0.0, 1.0, 0.0]),
/// ]).unwrap();
/// assert_eq!(gens.geometry, Geometry::Spherical);
/// let space = gens.dirichlet_domain().unwrap();
/// assert_eq!(space.group_order(), Some(8));
/// assert_eq!(space.faces().len(), 6); // a cube
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Generators {
    /// The space's name.
    pub name: String,
    /// The geometry the matrices are isometries of.
    pub geometry: Geometry,
    /// The generators, acting on column vectors.
    pub matrices: Vec<DMat4>,
    /// Where the Dirichlet domain is centred (the origin when `None`, or a
    /// generic point when an element fixes the origin).
    pub basepoint: Option<DVec4>,
    /// Refuse the group unless it acts freely (a manifold, not an orbifold).
    pub manifold: bool,
}

/// What is wrong with a list of generators, or with the domain they give.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum GeneratorError {
    /// A token that is not a number.
    #[error("line {line}: '{token}' is not a number")]
    NotANumber {
        /// 1-based line.
        line: usize,
        /// The token.
        token: String,
    },
    /// A line of a `.gen` file with other than four numbers.
    #[error("line {line}: a matrix row has four numbers, this line has {count}")]
    RowLength {
        /// 1-based line.
        line: usize,
        /// How many numbers it holds.
        count: usize,
    },
    /// The numbers do not make whole 4x4 matrices.
    #[error("matrix {matrix} is incomplete: it has {rows} of its 4 rows")]
    Incomplete {
        /// 0-based matrix.
        matrix: usize,
        /// Rows it has.
        rows: usize,
    },
    /// No generators at all, or too many.
    #[error("{count} generators: a space needs between 1 and {MAX_GENERATORS}")]
    Count {
        /// How many were given.
        count: usize,
    },
    /// A NaN or infinite entry.
    #[error("matrix {matrix}: entry ({row}, {col}) is NaN or infinite")]
    NonFinite {
        /// 0-based matrix.
        matrix: usize,
        /// Row (0-based, as written).
        row: usize,
        /// Column (0-based, as written).
        col: usize,
    },
    /// A matrix that is an isometry of no geometry.
    #[error("matrix {matrix} is not an isometry of E3, S3 or H3 ({detail})")]
    NotIsometry {
        /// 0-based matrix.
        matrix: usize,
        /// The smallest departure found, per geometry.
        detail: String,
    },
    /// A flat-space matrix written transposed.
    #[error(
        "matrix {matrix}: its translation is in the last column, not the bottom row: the file looks transposed (Curved Spaces files act on row vectors, v * M)"
    )]
    Transposed {
        /// 0-based matrix.
        matrix: usize,
    },
    /// Matrices of different geometries.
    #[error(
        "matrix {matrix} is an isometry of {this} only, but matrix {other} is one of {that} only: mixed geometries"
    )]
    MixedGeometries {
        /// 0-based matrix.
        matrix: usize,
        /// The geometries it fits.
        this: String,
        /// An earlier matrix.
        other: usize,
        /// The geometries that one fits.
        that: String,
    },
    /// A declared geometry the matrices do not fit.
    #[error("matrix {matrix} is not an isometry of {geometry} space (error {error:.3e})")]
    WrongGeometry {
        /// 0-based matrix.
        matrix: usize,
        /// The declared geometry.
        geometry: &'static str,
        /// Its isometry error.
        error: f64,
    },
    /// Every generator fixes the origin: the geometry cannot be told and the
    /// quotient is no compact space.
    #[error("every generator fixes the origin: the group has a fixed point and no compact quotient")]
    AllFixOrigin,
    /// A basepoint that is no point of the geometry.
    #[error("the basepoint {point:?} is not a point of {geometry} space")]
    BadBasepoint {
        /// The point.
        point: [f64; 4],
        /// The geometry.
        geometry: &'static str,
    },
    /// A non-identity element fixing a point, in a list that must act freely.
    #[error(
        "element {word} has finite order and fixes a point ({what}): the group does not act freely, so the quotient is an orbifold, not the manifold the file declares"
    )]
    NotFree {
        /// The element as a word in the generators (`g0 g3^-1 ...`).
        word: String,
        /// What it fixes.
        what: String,
    },
    /// Elements pile up: the group is not discrete (or the basepoint is
    /// special in a way no generic point avoids).
    #[error("the group is not discrete within the search radius: {detail}")]
    NotDiscrete {
        /// What was seen.
        detail: String,
    },
    /// The domain is not compact: unbounded, reaching infinity (H3) or the
    /// far hemisphere (S3).
    #[error("the Dirichlet domain is not compact: {detail}")]
    NotCompact {
        /// What was seen.
        detail: String,
    },
    /// A face paired with itself by an isometry that is not the mirror in it.
    #[error(
        "face {face} is paired with itself by a half-turn about an axis in it: such orbifolds are not supported (only mirrors pair a face with itself)"
    )]
    SelfPairedHalfTurn {
        /// The face of the built domain.
        face: usize,
    },
    /// The polyhedron the bisectors bound fails a property of a space.
    #[error("the Dirichlet domain is not a valid space: {0}")]
    Domain(#[from] SpaceError),
    /// A generator that the domain's face pairings do not produce: the group
    /// is larger than the domain says, so the search was incomplete or the
    /// group is not discrete.
    #[error("generator {matrix} is not a product of the domain's face pairings ({detail})")]
    NotGenerated {
        /// 0-based matrix.
        matrix: usize,
        /// Where its reduction stopped.
        detail: String,
    },
    /// A malformed JSON generator list.
    #[error("not a generator list: {0}")]
    Json(String),
}

/// A generator list as written in JSON (column vectors, row-major rows).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GeneratorsDesc {
    /// The space's name.
    pub name: String,
    /// The geometry; recognised from the matrices when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub geometry: Option<Geometry>,
    /// The generators, row-major.
    pub generators: Vec<[[f64; 4]; 4]>,
    /// Centre of the Dirichlet domain (the origin when absent).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub basepoint: Option<[f64; 4]>,
    /// Refuse the list unless the group acts freely.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub manifold: bool,
}

impl Generators {
    /// Generators of a geometry recognised from the matrices.
    ///
    /// # Errors
    /// A matrix that is no isometry, mixed geometries, or a list that
    /// cannot be told apart (every generator fixes the origin).
    pub fn new(name: impl Into<String>, matrices: Vec<DMat4>) -> Result<Self, GeneratorError> {
        let geometry = recognise(&matrices)?;
        Ok(Self::unchecked(name.into(), geometry, matrices))
    }

    /// Generators taken as given (the library's, computed here), centred at
    /// the origin, orbifolds allowed.
    pub(crate) fn unchecked(name: String, geometry: Geometry, matrices: Vec<DMat4>) -> Self {
        Generators {
            name,
            geometry,
            matrices,
            basepoint: None,
            manifold: false,
        }
    }

    /// Generators of a declared geometry, each checked against it.
    ///
    /// # Errors
    /// A matrix that is not an isometry of `geometry`.
    pub fn of_geometry(
        name: impl Into<String>,
        geometry: Geometry,
        matrices: Vec<DMat4>,
    ) -> Result<Self, GeneratorError> {
        check_count(matrices.len())?;
        for (i, m) in matrices.iter().enumerate() {
            check_finite(i, m)?;
            let error = geometry_error(geometry, *m);
            if error.is_nan() || error >= ISOMETRY_TOLERANCE {
                return Err(GeneratorError::WrongGeometry {
                    matrix: i,
                    geometry: geometry.name(),
                    error,
                });
            }
        }
        Ok(Self::unchecked(name.into(), geometry, matrices))
    }

    /// Reads a Curved Spaces `.gen` text (row vectors) into column-vector
    /// generators.
    ///
    /// # Errors
    /// A token that is no number, a row without four numbers, an incomplete
    /// matrix, or any error of [`Generators::new`].
    pub fn parse_gen(text: &str, name: impl Into<String>) -> Result<Self, GeneratorError> {
        let mut matrices = Vec::new();
        let mut rows: Vec<[f64; 4]> = Vec::new();
        let (mut basepoint, mut manifold) = (None, false);
        for (n, line) in crate::text::without_bom(text).lines().enumerate() {
            if let Some(directive) = line.trim_start().strip_prefix("# @") {
                let mut words = directive.split_whitespace();
                match words.next() {
                    Some("manifold") => manifold = true,
                    Some("basepoint") => {
                        let mut p = [0.0; 4];
                        let numbers: Vec<&str> = words.collect();
                        if numbers.len() != 4 {
                            return Err(GeneratorError::RowLength {
                                line: n + 1,
                                count: numbers.len(),
                            });
                        }
                        for (slot, token) in p.iter_mut().zip(&numbers) {
                            *slot = token.parse::<f64>().map_err(|_| GeneratorError::NotANumber {
                                line: n + 1,
                                token: (*token).chars().take(40).collect(),
                            })?;
                        }
                        basepoint = Some(p);
                    }
                    _ => {}
                }
                continue;
            }
            let line = line.split('#').next().unwrap_or("");
            let tokens: Vec<&str> = line.split_whitespace().collect();
            if tokens.is_empty() {
                continue;
            }
            if tokens.len() != 4 {
                return Err(GeneratorError::RowLength {
                    line: n + 1,
                    count: tokens.len(),
                });
            }
            let mut row = [0.0; 4];
            for (slot, token) in row.iter_mut().zip(&tokens) {
                *slot = token.parse::<f64>().map_err(|_| GeneratorError::NotANumber {
                    line: n + 1,
                    token: (*token).chars().take(40).collect(),
                })?;
            }
            rows.push(row);
            if rows.len() == 4 {
                if matrices.len() == MAX_GENERATORS {
                    return Err(GeneratorError::Count {
                        count: MAX_GENERATORS + 1,
                    });
                }
                // v' = v M: M's rows are the columns of our matrix.
                let cols = [rows[0], rows[1], rows[2], rows[3]];
                matrices.push(DMat4::from_cols_array_2d(&cols));
                rows.clear();
            }
        }
        if !rows.is_empty() {
            return Err(GeneratorError::Incomplete {
                matrix: matrices.len(),
                rows: rows.len(),
            });
        }
        // A transposed flat matrix puts its translation in our bottom row.
        for (i, m) in matrices.iter().enumerate() {
            let bottom = m.row(3);
            let right = m.w_axis;
            let flat_transposed = right.truncate().length() < 1e-12
                && (right.w - 1.0).abs() < 1e-12
                && bottom.truncate().length() > 1e-9
                && isometry_error_of(Geometry::Euclidean, m.transpose()) < ISOMETRY_TOLERANCE;
            if flat_transposed {
                return Err(GeneratorError::Transposed { matrix: i });
            }
        }
        let mut gens = Self::new(name, matrices)?;
        gens.set_basepoint(basepoint)?;
        gens.manifold = manifold;
        Ok(gens)
    }

    /// Centres the Dirichlet domain at `point` (or leaves it where it is
    /// for `None`), checked to be a normalised point of the geometry.
    ///
    /// # Errors
    /// [`GeneratorError::BadBasepoint`] for a point that is not.
    pub fn set_basepoint(&mut self, point: Option<[f64; 4]>) -> Result<(), GeneratorError> {
        if let Some(p) = point {
            let point = DVec4::from_array(p);
            if !point.is_finite() || !self.geometry.is_point(point) {
                return Err(GeneratorError::BadBasepoint {
                    point: p,
                    geometry: self.geometry.name(),
                });
            }
            self.basepoint = Some(point);
        }
        Ok(())
    }

    /// Reads a JSON generator list.
    ///
    /// # Errors
    /// Malformed JSON, or the errors of [`Generators::new`] and
    /// [`Generators::of_geometry`], or a bad basepoint.
    pub fn parse_json(text: &str) -> Result<Self, GeneratorError> {
        let desc: GeneratorsDesc =
            serde_json::from_str(crate::text::without_bom(text)).map_err(|e| GeneratorError::Json(e.to_string()))?;
        desc.into_generators()
    }

    /// Reads a generator file: `.gen` (Curved Spaces) or JSON, by extension.
    ///
    /// # Errors
    /// An unreadable file or any error of the parsers, naming the file.
    pub fn load(path: impl AsRef<Path>) -> Result<Self, SpaceFileError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|e| SpaceFileError {
            path: DisplayPath(path.to_path_buf()),
            kind: SpaceFileErrorKind::Io(e),
        })?;
        Self::parse_file(&text, path)
    }

    /// Parses the text of a generator file; `path` picks the format (`.gen`
    /// or else JSON), names the space (its stem) and names the file in
    /// errors.
    ///
    /// # Errors
    /// The parser's error, naming the file.
    pub fn parse_file(text: &str, path: &Path) -> Result<Self, SpaceFileError> {
        let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("space");
        let is_gen = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("gen"));
        let parsed = if is_gen {
            Self::parse_gen(text, stem)
        } else {
            Self::parse_json(text)
        };
        parsed.map_err(|e| SpaceFileError {
            path: DisplayPath(path.to_path_buf()),
            kind: SpaceFileErrorKind::Generators(e),
        })
    }

    /// The generators as a JSON generator list.
    #[must_use]
    pub fn to_desc(&self) -> GeneratorsDesc {
        GeneratorsDesc {
            name: self.name.clone(),
            geometry: Some(self.geometry),
            generators: self.matrices.iter().map(|m| to_rows(*m)).collect(),
            basepoint: self.basepoint.map(|p| p.to_array()),
            manifold: self.manifold,
        }
    }

    /// The generators in Curved Spaces' `.gen` format (row vectors), with
    /// `header` as comment lines, then the basepoint and the manifold flag
    /// as the comment directives `# @basepoint x y z w` and `# @manifold`
    /// (comments to Curved Spaces, read back here).
    #[must_use]
    pub fn to_gen(&self, header: &str) -> String {
        let mut out = String::new();
        for line in header.lines() {
            out.push_str("# ");
            out.push_str(line);
            out.push('\n');
        }
        if let Some(p) = self.basepoint {
            let p: Vec<String> = p.to_array().iter().map(|x| format!("{:.17}", clean(*x))).collect();
            out.push_str(&format!("# @basepoint {}\n", p.join(" ")));
        }
        if self.manifold {
            out.push_str("# @manifold\n");
        }
        for m in &self.matrices {
            out.push('\n');
            // Our columns are the rows of M in v' = v M.
            for col in m.to_cols_array_2d() {
                let row: Vec<String> = col.iter().map(|x| format!("{:>23.17}", clean(*x))).collect();
                out.push_str(row.join(" ").trim_end());
                out.push('\n');
            }
        }
        out
    }
}

/// Prints `-0` as `0`.
fn clean(x: f64) -> f64 {
    if x == 0.0 { 0.0 } else { x }
}

impl GeneratorsDesc {
    /// Checks the description and turns it into generators.
    ///
    /// # Errors
    /// As [`Generators::parse_json`].
    pub fn into_generators(self) -> Result<Generators, GeneratorError> {
        check_count(self.generators.len())?;
        for (i, rows) in self.generators.iter().enumerate() {
            for (r, row) in rows.iter().enumerate() {
                if let Some(c) = row.iter().position(|x| !x.is_finite()) {
                    return Err(GeneratorError::NonFinite {
                        matrix: i,
                        row: r,
                        col: c,
                    });
                }
            }
        }
        let matrices: Vec<DMat4> = self.generators.iter().map(|r| from_rows(*r)).collect();
        let mut gens = match self.geometry {
            Some(g) => Generators::of_geometry(self.name, g, matrices)?,
            None => Generators::new(self.name, matrices)?,
        };
        gens.set_basepoint(self.basepoint)?;
        gens.manifold = self.manifold;
        Ok(gens)
    }
}

fn check_count(count: usize) -> Result<(), GeneratorError> {
    if count == 0 || count > MAX_GENERATORS {
        return Err(GeneratorError::Count { count });
    }
    Ok(())
}

fn check_finite(i: usize, m: &DMat4) -> Result<(), GeneratorError> {
    // Rows as written: row r of the row-major form.
    for r in 0..4 {
        if let Some(c) = m.row(r).to_array().iter().position(|x| !x.is_finite()) {
            return Err(GeneratorError::NonFinite {
                matrix: i,
                row: r,
                col: c,
            });
        }
    }
    Ok(())
}

fn isometry_error_of(g: Geometry, m: DMat4) -> f64 {
    isometry::isometry_error(g, m)
}

/// How far `m` is from an isometry of `g`, counting an H3 matrix that
/// swaps the two sheets of the hyperboloid as no isometry.
fn geometry_error(g: Geometry, m: DMat4) -> f64 {
    let e = isometry::isometry_error(g, m);
    if g == Geometry::Hyperbolic && m.w_axis.w <= 0.0 {
        return f64::INFINITY;
    }
    e
}

const ALL: [Geometry; 3] = [Geometry::Euclidean, Geometry::Spherical, Geometry::Hyperbolic];

fn names(gs: &[Geometry]) -> String {
    let n: Vec<&str> = gs.iter().map(|g| g.name()).collect();
    n.join(" and ")
}

/// The one geometry every matrix is an isometry of.
fn recognise(matrices: &[DMat4]) -> Result<Geometry, GeneratorError> {
    check_count(matrices.len())?;
    let mut common: Vec<Geometry> = ALL.to_vec();
    // The first matrix that narrowed the choice, for the error message.
    let mut narrowed: Option<(usize, Vec<Geometry>)> = None;
    for (i, m) in matrices.iter().enumerate() {
        check_finite(i, m)?;
        let fits: Vec<Geometry> = ALL
            .iter()
            .copied()
            .filter(|&g| geometry_error(g, *m) < ISOMETRY_TOLERANCE)
            .collect();
        if fits.is_empty() {
            let detail: Vec<String> = ALL
                .iter()
                .map(|&g| format!("{} error {:.3e}", g.name(), geometry_error(g, *m)))
                .collect();
            return Err(GeneratorError::NotIsometry {
                matrix: i,
                detail: detail.join(", "),
            });
        }
        let next: Vec<Geometry> = common.iter().copied().filter(|g| fits.contains(g)).collect();
        if next.is_empty() {
            let (other, that) = narrowed.clone().unwrap_or((0, common.clone()));
            return Err(GeneratorError::MixedGeometries {
                matrix: i,
                this: names(&fits),
                other,
                that: names(&that),
            });
        }
        if next.len() < common.len() && narrowed.is_none() {
            narrowed = Some((i, fits));
        }
        common = next;
    }
    match common.as_slice() {
        [g] => Ok(*g),
        _ => Err(GeneratorError::AllFixOrigin),
    }
}
