//! The file's frame: where a space's chart sits in the coordinates its
//! generators were given in.
//!
//! A Dirichlet domain is built about a basepoint and written with that
//! point at the chart origin, where every chart centres its domain. When
//! the basepoint is not the generators' own origin (the file names
//! another, or an element fixes the origin, which a domain then has on its
//! boundary), the chart's pairings are the group's elements conjugated by
//! the move `F` from the origin to the basepoint. The space keeps `F` as
//! its file frame, so nothing of the file is lost: `F T F^-1` is the
//! file's own element for each pairing `T` ([`Space::file_pairing`]), and
//! a placement given in the file's coordinates is `F^-1 P` in the chart's
//! ([`Space::from_file_frame`]).
//!
//! ```
//! use bevy_manifold_core::prelude::*;
//! use bevy_manifold_core::space::Generators;
//! use glam::{DVec3, DVec4};
//! // The 3-torus built about (0.3, -0.2, 0.1): the chart has that point
//! // at its origin, and its pairings are still the file's translations.
//! let e = Geometry::Euclidean;
//! let mut gens = Generators::new(
//!     "t",
//!     [DVec3::X, DVec3::Y, DVec3::Z].map(|v| isometry::translation(e, v)).to_vec(),
//! )
//! .unwrap();
//! gens.basepoint = Some(DVec4::new(0.3, -0.2, 0.1, 1.0));
//! let space = gens.dirichlet_domain().unwrap();
//! // The file's point (0.3, -0.2, 0.1) is the chart's origin.
//! let p = space.from_file_frame(isometry::translation(e, DVec3::new(0.3, -0.2, 0.1)));
//! assert!(p.w_axis.truncate().length() < 1e-12);
//! let x = isometry::translation(e, DVec3::X);
//! assert!((0..6).any(|i| space.file_pairing(i).abs_diff_eq(x, 1e-12)));
//! ```

use super::{Space, SpaceError};
use crate::geometry::isometry;
use glam::DMat4;

/// How far a file frame may be from an isometry of the space's geometry
/// (the largest entry of its form error).
pub const FRAME_TOLERANCE: f64 = 1e-9;

impl Space {
    /// The isometry `F` from this space's chart to the coordinates its
    /// generators were given in: the identity for a space written
    /// directly, or built about the generators' own origin.
    #[must_use]
    pub fn file_frame(&self) -> DMat4 {
        self.file_frame
    }

    /// This space with its file frame set to `frame` (re-orthonormalised).
    ///
    /// # Errors
    /// [`SpaceError::FileFrame`] when `frame` has a NaN or infinite entry,
    /// or is not an isometry of the space's geometry.
    pub fn with_file_frame(mut self, frame: DMat4) -> Result<Self, SpaceError> {
        let g = self.geometry;
        if !frame.is_finite() {
            return Err(SpaceError::FileFrame {
                detail: "it has a NaN or infinite entry".into(),
            });
        }
        let error = isometry::isometry_error(g, frame);
        if error > FRAME_TOLERANCE {
            return Err(SpaceError::FileFrame {
                detail: format!(
                    "it is not an isometry of {g} space (form error {error:.3e}, at most {FRAME_TOLERANCE:e})"
                ),
            });
        }
        self.file_frame = isometry::orthonormalize(g, frame);
        Ok(self)
    }

    /// Face `face`'s pairing in the file's coordinates, `F T F^-1`: an
    /// element of the group the generators gave, whatever point the chart
    /// is centred on.
    #[must_use]
    pub fn file_pairing(&self, face: usize) -> DMat4 {
        let f = self.file_frame;
        f * self.faces[face].pairing * isometry::inverse(self.geometry, f)
    }

    /// A placement (or point, as its `w_axis`) given in the file's
    /// coordinates, in the chart's: `F^-1 P`.
    #[must_use]
    pub fn from_file_frame(&self, placement: DMat4) -> DMat4 {
        isometry::inverse(self.geometry, self.file_frame) * placement
    }

    /// A placement in the chart's coordinates, in the file's: `F P`.
    #[must_use]
    pub fn to_file_frame(&self, placement: DMat4) -> DMat4 {
        self.file_frame * placement
    }
}
