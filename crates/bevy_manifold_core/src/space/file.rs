//! Space files: the JSON that `space export` writes and every loader reads.
//!
//! ```text
//! {"name": "...", "geometry": "euclidean" | "hyperbolic" | "spherical",
//!  "faces": [{"plane": [a,b,c,d], "partner": j, "kind": "glue" | "mirror",
//!             "pairing": [[..4..],[..4..],[..4..],[..4..]]}, ...],
//!  "vertices": [[x,y,z,w], ...], "volume": v,
//!  "file_frame": [[..4..],[..4..],[..4..],[..4..]]}
//! ```
//! Matrices are row-major and act on column vectors, `w` last. `vertices`
//! and `volume` are derived from the faces; when present they are checked.
//! `file_frame` (optional, the identity when absent) places the chart in
//! the coordinates of the generators the space was built from
//! ([`super::frame`]).

use super::{DisplayPath, Face, FaceKind, Generators, Space, SpaceError, SpaceFileError, SpaceFileErrorKind};
use glam::{DMat4, DVec4};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// One face as written in a space file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FaceDesc {
    /// The plane covector `[a, b, c, d]`, `a x + b y + c z + d w <= 0` inside.
    pub plane: [f64; 4],
    /// Index of the partner face.
    pub partner: usize,
    /// "glue" or "mirror".
    pub kind: FaceKind,
    /// `T_i`, row-major.
    pub pairing: [[f64; 4]; 4],
}

/// A space as written in a space file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpaceDesc {
    /// The space's name.
    pub name: String,
    /// The model geometry.
    pub geometry: crate::geometry::Geometry,
    /// The faces.
    pub faces: Vec<FaceDesc>,
    /// The polyhedron's vertices, normalised points (optional on input).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vertices: Option<Vec<[f64; 4]>>,
    /// The volume (optional on input).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub volume: Option<f64>,
    /// The chart's place in its generators' coordinates, row-major
    /// (optional; the identity when absent).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file_frame: Option<[[f64; 4]; 4]>,
}

/// Row-major array of a matrix acting on column vectors.
#[must_use]
pub fn to_rows(m: DMat4) -> [[f64; 4]; 4] {
    m.transpose().to_cols_array_2d()
}

/// The matrix of a row-major array.
#[must_use]
pub fn from_rows(r: [[f64; 4]; 4]) -> DMat4 {
    DMat4::from_cols_array_2d(&r).transpose()
}

impl SpaceDesc {
    /// Builds and validates the space the description names.
    ///
    /// # Errors
    /// The first broken property, as [`SpaceError`].
    pub fn build(&self) -> Result<Space, SpaceError> {
        let faces = self
            .faces
            .iter()
            .map(|f| Face {
                plane: DVec4::from_array(f.plane),
                partner: f.partner,
                kind: f.kind,
                pairing: from_rows(f.pairing),
            })
            .collect();
        let mut space = Space::new(self.name.clone(), self.geometry, faces)?;
        if let Some(rows) = self.file_frame {
            space = space.with_file_frame(from_rows(rows))?;
        }
        if let Some(vs) = &self.vertices {
            check_vertices(&space, vs)?;
        }
        if let Some(v) = self.volume {
            let close = (v - space.volume()).abs() <= 1e-6 * space.volume().max(1.0);
            if !close {
                return Err(SpaceError::VolumeMismatch {
                    given: v,
                    computed: space.volume(),
                });
            }
        }
        Ok(space)
    }

    /// Parses and builds a space from JSON text; `path` names it in errors.
    ///
    /// # Errors
    /// Malformed JSON, missing fields, or a broken space, with the path.
    pub fn parse(text: &str, path: &Path) -> Result<Space, SpaceFileError> {
        let err = |kind| SpaceFileError {
            path: DisplayPath(path.to_path_buf()),
            kind,
        };
        let desc: SpaceDesc = serde_json::from_str(crate::text::without_bom(text))
            .map_err(|e| err(SpaceFileErrorKind::Json(e.to_string())))?;
        desc.build().map_err(|e| err(SpaceFileErrorKind::Invalid(e)))
    }
}

fn check_vertices(space: &Space, vs: &[[f64; 4]]) -> Result<(), SpaceError> {
    let g = space.geometry();
    for (index, v) in vs.iter().enumerate() {
        let p = DVec4::from_array(*v);
        if !g.is_point(p) {
            return Err(SpaceError::VertexMismatch {
                index,
                detail: format!("{v:?} is not a point of {g} space"),
            });
        }
        if let Some(f) = space.outside_face(p, 1e-7) {
            return Err(SpaceError::VertexMismatch {
                index,
                detail: format!(
                    "{v:?} lies outside face {f}: the listed vertices do not bound the convex polyhedron of the faces"
                ),
            });
        }
        if space.polyhedron().vertex_at(p).is_none() {
            return Err(SpaceError::VertexMismatch {
                index,
                detail: format!("{v:?} is not a corner of the polyhedron the faces bound"),
            });
        }
    }
    if vs.len() != space.vertices().len() {
        return Err(SpaceError::VertexMismatch {
            index: vs.len(),
            detail: format!(
                "the file lists {} vertices, the faces bound a polyhedron with {}",
                vs.len(),
                space.vertices().len()
            ),
        });
    }
    Ok(())
}

impl Space {
    /// The description of this space, as written to a file.
    #[must_use]
    pub fn to_desc(&self) -> SpaceDesc {
        SpaceDesc {
            name: self.name().to_string(),
            geometry: self.geometry(),
            faces: self
                .faces()
                .iter()
                .map(|f| FaceDesc {
                    plane: f.plane.to_array(),
                    partner: f.partner,
                    kind: f.kind,
                    pairing: to_rows(f.pairing),
                })
                .collect(),
            vertices: Some(self.vertices().iter().map(|v| v.point.to_array()).collect()),
            volume: Some(self.volume()),
            file_frame: (self.file_frame() != DMat4::IDENTITY).then(|| to_rows(self.file_frame())),
        }
    }

    /// The space as pretty JSON.
    #[must_use]
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(&self.to_desc()).unwrap_or_default()
    }

    /// Loads a space file: a space (JSON), a Curved Spaces `.gen` file or a
    /// JSON generator list (a JSON object with `"generators"`), the last
    /// two through their Dirichlet domain.
    ///
    /// # Errors
    /// Unreadable file, malformed JSON, a broken space, or generators that
    /// give none; the error names the file.
    pub fn load(path: impl AsRef<Path>) -> Result<Space, SpaceFileError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|e| SpaceFileError {
            path: DisplayPath(path.to_path_buf()),
            kind: SpaceFileErrorKind::Io(e),
        })?;
        Space::parse_file(&text, path)
    }

    /// [`Space::load`] from text already read; `path` picks the format (by
    /// extension, then by content) and names the file in errors.
    ///
    /// # Errors
    /// As [`Space::load`].
    pub fn parse_file(text: &str, path: &Path) -> Result<Space, SpaceFileError> {
        let text = crate::text::without_bom(text);
        let is_gen = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("gen"));
        let is_list =
            !is_gen && serde_json::from_str::<serde_json::Value>(text).is_ok_and(|v| v.get("generators").is_some());
        if !(is_gen || is_list) {
            return SpaceDesc::parse(text, path);
        }
        let gens = Generators::parse_file(text, path)?;
        gens.dirichlet_domain().map_err(|e| SpaceFileError {
            path: DisplayPath(path.to_path_buf()),
            kind: SpaceFileErrorKind::Generators(e),
        })
    }

    /// Writes the space file.
    ///
    /// # Errors
    /// When the file cannot be written.
    pub fn save(&self, path: impl AsRef<Path>) -> std::io::Result<()> {
        std::fs::write(path, self.to_json())
    }
}
