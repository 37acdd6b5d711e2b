//! # bevy_manifold_core
//!
//! The math of [bevy_manifold](https://crates.io/crates/bevy_manifold),
//! free of Bevy and of the GPU (as avian keeps its math apart from the
//! ECS): non-Euclidean 3-manifolds and orbifolds as fundamental polyhedra
//! whose faces are glued in pairs, and the CPU reference ray tracer that
//! sees the whole tessellated cover through them (Velho, da Silva, Novello,
//! GI 2020).
//!
//! - [`geometry`]: E3, H3 and S3 in one projective chart; isometries; planes.
//! - [`space`]: fundamental polyhedra with face pairings, validation, the
//!   catalog of the paper's five spaces, space files, and
//!   [`space::cells`], path-independent ids for the copies of the domain.
//! - [`material`]: what a surface is made of (PBR, emission, normal
//!   maps, alpha masks) and the BRDF both tracers shade with.
//! - [`mesh`]: triangle meshes, their BVH, and glTF loading (feature `gltf`).
//! - [`trace`]: the CPU reference ray tracer (Algorithm 1), in f64 and in an
//!   f32 mode that mirrors the GPU arithmetic; geodesic flow; ray casts.
//! - [`motion`]: moving placements through the faces (the math of wrapping).
//!
//! Features: `parallel` (rayon over pixels), `gltf` (meshes from files and
//! the paper's built-in models), `png` (image output); all on by default.
//!
//! ```
//! use bevy_manifold_core::prelude::*;
//!
//! let space = catalog::poincare();
//! let scene = Scene::default_for(&space);
//! let settings = TraceSettings { width: 32, height: 18, ..TraceSettings::default() };
//! let image = render::<f64>(&space, &scene, &settings);
//! assert_eq!(image.pixels.len(), 32 * 18);
//! // The ball at the centre of the domain is seen in the middle of the view.
//! assert!(image.pixels.iter().any(|p| p.object == 1));
//! ```

pub mod contact;
pub mod geometry;
pub mod material;
pub mod mesh;
pub mod motion;
pub mod space;
pub mod text;
pub mod tour;
pub mod trace;

/// The types most users of the math need.
pub mod prelude {
    pub use crate::geometry::{Geometry, Real, isometry, plane};
    pub use crate::space::cells::CellId;
    pub use crate::space::{Face, FaceKind, Space, SpaceDesc, SpaceError, catalog};
    pub use crate::trace::{Ball, Fog, Light, Lighting, Scene, SceneMesh, TraceImage, TraceSettings, render};
}
