//! Product space files: the JSON of a [`ProductSpace`], naming its
//! geometry.
//!
//! ```text
//! {"name": "...", "geometry": "h2xr" | "s2xr", "height": L,
//!  "sides": [[nx, ny, nw], ...], "angles": [a, ...],
//!  "gluings": [{"kind": "glue" | "mirror", "partner": j,
//!               "surface": [[..3..],[..3..],[..3..]], "flip": 1 | -1,
//!               "shift": s}, ...]}
//! ```
//!
//! `sides` are the polygon's unit normal covectors (`<n, p> <= 0` inside),
//! in order round it, empty for the whole sphere; `angles` its interior
//! angles in radians (the corner between side `i` and side `i + 1`);
//! `gluings` one per face: the sides in order, then the bottom, then the
//! top. `surface` is row-major and acts on column vectors `(x, y, w)`.
//!
//! ```
//! use bevy_manifold_core::space::product::ProductSpace;
//! let space = ProductSpace::genus_two_x_s1(2.0);
//! let text = space.to_json();
//! let back = ProductSpace::from_json(&text, "genus2.json").unwrap();
//! assert_eq!(back.gluings.len(), 10);
//! assert!((back.volume() - space.volume()).abs() < 1e-12);
//! ```

use super::product::{ProductGluing, ProductSpace, ProductSpaceError};
use crate::geometry::product::{ProductGeometry, ProductIsometry};
use glam::{DMat3, DVec3};
use serde::{Deserialize, Serialize};

/// One gluing as written in a product space file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProductGluingDesc {
    /// "glue" or "mirror".
    pub kind: crate::space::FaceKind,
    /// The face it is glued to (itself for a mirror).
    pub partner: usize,
    /// The isometry's surface part, row-major.
    pub surface: [[f64; 3]; 3],
    /// 1, or -1 where the line is turned upside down.
    pub flip: f64,
    /// The translation of the line, after the flip.
    pub shift: f64,
}

/// A product space as written in a file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProductSpaceDesc {
    /// The space's name.
    pub name: String,
    /// `h2xr` or `s2xr`.
    pub geometry: ProductGeometry,
    /// The prism's height, the circle's (or interval's) length.
    pub height: f64,
    /// The polygon's sides' normals.
    pub sides: Vec<[f64; 3]>,
    /// The polygon's interior angles.
    pub angles: Vec<f64>,
    /// One gluing per face.
    pub gluings: Vec<ProductGluingDesc>,
}

/// What is wrong with a product space file: the file, the field, and
/// why.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{file}: {field}: {message}")]
pub struct ProductFileError {
    /// The file's name.
    pub file: String,
    /// The field (`gluings[3].surface`), or `json` for a syntax error.
    pub field: String,
    /// Why.
    pub message: String,
}

/// Most sides a polygon may have (a file asking for more is refused).
pub const MAX_SIDES: usize = 1024;

fn rows(m: DMat3) -> [[f64; 3]; 3] {
    m.transpose().to_cols_array_2d()
}

fn from_rows(r: [[f64; 3]; 3]) -> DMat3 {
    DMat3::from_cols_array_2d(&r).transpose()
}

impl ProductSpace {
    /// The space as a file's description.
    #[must_use]
    pub fn to_desc(&self) -> ProductSpaceDesc {
        ProductSpaceDesc {
            name: self.name.clone(),
            geometry: self.geometry,
            height: self.height,
            sides: self.sides.iter().map(|n| n.to_array()).collect(),
            angles: self.angles.clone(),
            gluings: self
                .gluings
                .iter()
                .enumerate()
                .map(|(face, gl)| {
                    let m = gl.isometry();
                    ProductGluingDesc {
                        kind: match gl {
                            ProductGluing::Paired { .. } => crate::space::FaceKind::Glue,
                            ProductGluing::Mirror(_) => crate::space::FaceKind::Mirror,
                        },
                        partner: self.partner(face),
                        surface: rows(m.surface),
                        flip: m.flip,
                        shift: m.shift,
                    }
                })
                .collect(),
        }
    }

    /// The space's file (pretty JSON).
    #[must_use]
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(&self.to_desc()).expect("a product space serialises")
    }

    /// The space a file describes, validated; `file` names it in errors.
    ///
    /// # Errors
    /// Broken JSON, an unknown field, a number that is not finite, too many
    /// sides, or what [`ProductSpace::validate`] finds, each naming the
    /// file and the field.
    pub fn from_json(text: &str, file: &str) -> Result<Self, ProductFileError> {
        let error = |field: String, message: String| ProductFileError {
            file: file.to_string(),
            field,
            message,
        };
        let desc: ProductSpaceDesc = serde_json::from_str(text).map_err(|e| error("json".into(), e.to_string()))?;
        Self::from_desc(desc).map_err(|(field, message)| error(field, message))
    }

    /// The space a description gives, validated.
    ///
    /// # Errors
    /// The field that is wrong and why.
    pub fn from_desc(desc: ProductSpaceDesc) -> Result<Self, (String, String)> {
        if desc.sides.len() > MAX_SIDES {
            return Err((
                "sides".into(),
                format!("{} sides: at most {MAX_SIDES}", desc.sides.len()),
            ));
        }
        if desc.angles.len() != desc.sides.len() {
            return Err((
                "angles".into(),
                format!("{} angles for {} sides", desc.angles.len(), desc.sides.len()),
            ));
        }
        let finite = |field: String, values: &[f64]| {
            if values.iter().all(|v| v.is_finite()) {
                Ok(())
            } else {
                Err((field, format!("{values:?} is not finite")))
            }
        };
        for (i, n) in desc.sides.iter().enumerate() {
            finite(format!("sides[{i}]"), n)?;
        }
        finite("angles".into(), &desc.angles)?;
        let mut gluings = Vec::with_capacity(desc.gluings.len());
        for (face, gl) in desc.gluings.iter().enumerate() {
            finite(format!("gluings[{face}].surface"), gl.surface.as_flattened())?;
            finite(format!("gluings[{face}]"), &[gl.flip, gl.shift])?;
            let m = ProductIsometry::new(from_rows(gl.surface), gl.flip, gl.shift);
            gluings.push(match gl.kind {
                crate::space::FaceKind::Glue => ProductGluing::Paired {
                    partner: gl.partner,
                    pairing: m,
                },
                crate::space::FaceKind::Mirror => {
                    if gl.partner != face {
                        return Err((
                            format!("gluings[{face}].partner"),
                            format!("a mirror is its own partner, not face {}", gl.partner),
                        ));
                    }
                    ProductGluing::Mirror(m)
                }
            });
        }
        let space = ProductSpace {
            name: desc.name,
            geometry: desc.geometry,
            sides: desc.sides.iter().map(|n| DVec3::from_array(*n)).collect(),
            height: desc.height,
            gluings,
            angles: desc.angles,
        };
        space.validate().map_err(|e| {
            let field = match &e {
                ProductSpaceError::BadNumber { field, .. } => (*field).to_string(),
                ProductSpaceError::GluingCount { .. } => "gluings".into(),
                ProductSpaceError::Gluing { face, .. } => format!("gluings[{face}]"),
                ProductSpaceError::VertexCycle { .. } => "angles".into(),
                ProductSpaceError::Polygon { field, .. } => (*field).to_string(),
            };
            (field, e.to_string())
        })?;
        Ok(space)
    }
}
