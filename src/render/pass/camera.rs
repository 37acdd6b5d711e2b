//! The main-world side of the pass: the components that make a Bevy camera
//! look into a manifold.

use crate::cell::{CellId, CellTint};
use crate::placement::Placement;
use bevy::color::{Color, LinearRgba};
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::prelude::*;
use bevy::render::view::Msaa;

/// Makes a Bevy 3D camera look into the manifold it lives in: its view is
/// ray-traced (every copy of the domain, as far as `max_level` transports
/// reach) instead of rasterised. The camera goes under a
/// [`crate::placement::ManifoldSpace`] root like any placed entity; its
/// [`Placement`] and [`crate::placement::DomainCell`] say where it looks from.
///
/// Required components: `Camera3d` (so Bevy gives it a view target, and
/// ordinary meshes, gizmos and UI can still be drawn over the trace, sorted
/// by the depth the trace writes), [`Placement`], `Tonemapping::None` (the
/// tracer's colours are shown as the CPU reference computes them; set
/// another tonemapper if you like) and `Msaa::Off` (the trace is per pixel).
///
/// ```no_run
/// use bevy::prelude::*;
/// use bevy_manifold::prelude::*;
/// use glam::DVec3;
///
/// fn setup(mut commands: Commands) {
///     let space = catalog::seifert_weber();
///     let root = commands.spawn((ManifoldSpace::new(space.clone()), DomainEdges::default())).id();
///     commands.spawn((ChildOf(root), ManifoldCamera::default(), Placement::at(&space, DVec3::Z * 0.3)));
///     commands.spawn((ChildOf(root), TracedBall::new(0.2, Color::srgb(0.9, 0.4, 0.2))));
///     commands.spawn((ChildOf(root), ManifoldLight::default(), Placement::at(&space, DVec3::Y * 0.4)));
/// }
///
/// App::new().add_plugins((DefaultPlugins, ManifoldPlugin::default())).add_systems(Startup, setup).run();
/// ```
#[derive(Component, Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Component, Debug, Default)]
#[require(Camera3d, Placement, Tonemapping = Tonemapping::None, Msaa = Msaa::Off)]
pub struct ManifoldCamera {
    /// Most face transports per ray (the paper's bounces).
    pub max_level: u32,
    /// Rays stop after this distance.
    pub max_distance: f32,
    /// Per-cell shading.
    pub cell_shading: CellShading,
}

impl Default for ManifoldCamera {
    fn default() -> Self {
        ManifoldCamera {
            max_level: 8,
            max_distance: 100.0,
            cell_shading: CellShading::Off,
        }
    }
}

/// How the copies of the domain are told apart (per-cell shading, the
/// paper's §7.2). The tint itself is [`crate::cell::CellTint`], shared with
/// the CPU reference.
///
/// ```
/// use bevy_manifold::prelude::*;
/// use bevy_manifold::cell::CellTint;
/// assert_eq!(CellShading::Off.tint(), None);
/// assert_eq!(CellShading::ByCell.tint(), Some(CellTint::ByCell));
/// let camera = ManifoldCamera { cell_shading: CellShading::Pattern { on_fraction: 0.3 }, ..Default::default() };
/// assert!(camera.cell_shading.tint().is_some());
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Reflect)]
pub enum CellShading {
    /// Every copy looks the same.
    #[default]
    Off,
    /// Each copy's albedo is tinted by a colour hashed from its
    /// path-independent cell id (the origin copy stays white).
    ByCell,
    /// One copy, by its [`crate::cell::CellId`] (the `u64` inside), is
    /// tinted orange (typically the copy the camera is in:
    /// [`crate::placement::DomainCell::id`]).
    Highlight {
        /// The copy's id.
        cell: u64,
    },
    /// On/off by cell: a copy is lit with probability `on_fraction` (the
    /// same copies from every path), the others are dimmed.
    Pattern {
        /// Fraction of copies on, in `[0, 1]`.
        on_fraction: f32,
    },
}

impl CellShading {
    /// The tint, or `None` when off.
    #[must_use]
    pub fn tint(self) -> Option<CellTint> {
        match self {
            CellShading::Off => None,
            CellShading::ByCell => Some(CellTint::ByCell),
            CellShading::Highlight { cell } => Some(CellTint::Highlight(CellId(cell))),
            CellShading::Pattern { on_fraction } => Some(CellTint::Pattern { on_fraction }),
        }
    }
}

/// Exponential fog on a [`ManifoldCamera`]: light that travelled `d` keeps
/// `exp(-density d)` of itself and the rest is fog colour. Rays stop early
/// once fog hides what lies beyond (below one 8-bit step).
#[derive(Component, Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Component, Debug)]
pub struct ManifoldFog {
    /// Extinction per unit distance.
    pub density: f64,
    /// The colour light fades to.
    pub color: Color,
}

impl Default for ManifoldFog {
    fn default() -> Self {
        ManifoldFog {
            density: 0.3,
            color: Color::srgb(0.55, 0.6, 0.7),
        }
    }
}

impl ManifoldFog {
    /// Density and linear colour, or `None` when the density is not
    /// positive (no fog).
    #[must_use]
    pub fn linear(&self) -> Option<(f32, [f32; 3])> {
        let LinearRgba { red, green, blue, .. } = self.color.to_linear();
        (self.density > 0.0).then_some((self.density as f32, [red, green, blue]))
    }
}
