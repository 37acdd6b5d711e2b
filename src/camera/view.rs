//! How a camera looks into a manifold, whatever draws it: fog and
//! per-cell shading. These are view components in the main world that
//! exist without the `render` feature (the CPU reference reads the same
//! settings, through [`ManifoldFog::to_fog`] and [`CellShading::tint`]);
//! the render pass extracts them from each `ManifoldCamera`.

use crate::space::cells::{CellId, CellTint};
use crate::trace::Fog;
use bevy::color::{Color, LinearRgba};
use bevy::prelude::*;

/// How a view tells the copies of the domain apart (per-cell shading, the
/// paper's §7.2), on a camera beside `ManifoldCamera`. The tint itself is [`crate::space::cells::CellTint`], shared with
/// the CPU reference.
///
/// ```
/// use bevy_manifold::prelude::*;
/// use bevy_manifold::space::cells::CellTint;
/// assert_eq!(CellShading::Off.tint(), None);
/// assert_eq!(CellShading::ByCell.tint(), Some(CellTint::ByCell));
/// assert!(CellShading::Pattern { on_fraction: 0.3 }.tint().is_some());
/// ```
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Reflect)]
#[reflect(Component, Debug, Default)]
pub enum CellShading {
    /// Every copy looks the same.
    #[default]
    Off,
    /// Each copy's albedo is tinted by a colour hashed from its
    /// path-independent cell id (the origin copy stays white).
    ByCell,
    /// One copy, by its [`crate::space::cells::CellId`] (the `u64` inside), is
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

/// Exponential fog on a camera (beside `ManifoldCamera`): light that travelled `d` keeps
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
    /// The tracer's fog (density and linear colour), or `None` when the
    /// density is not positive (no fog): the one conversion the pass, the
    /// CPU reference and the apps share.
    ///
    /// ```
    /// use bevy::prelude::*;
    /// use bevy_manifold::prelude::*;
    /// let fog = ManifoldFog { density: 0.5, color: Color::WHITE }.to_fog().unwrap();
    /// assert_eq!((fog.density, fog.color), (0.5, [1.0, 1.0, 1.0]));
    /// assert!(ManifoldFog { density: 0.0, ..default() }.to_fog().is_none());
    /// ```
    #[must_use]
    pub fn to_fog(&self) -> Option<Fog> {
        let LinearRgba { red, green, blue, .. } = self.color.to_linear();
        (self.density > 0.0).then_some(Fog {
            density: self.density,
            color: [red, green, blue],
        })
    }

    /// The fog of a tracer scene, as a component.
    #[must_use]
    pub fn from_fog(fog: &Fog) -> Self {
        let [r, g, b] = fog.color;
        ManifoldFog {
            density: fog.density,
            color: Color::linear_rgb(r, g, b),
        }
    }
}
