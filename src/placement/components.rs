//! The components game code touches: the space at the root of a hierarchy,
//! and for each entity in it a placement, a cell, a velocity, a collider.

use crate::geometry::isometry;
use crate::space::Space;
use crate::space::cells::CellId;
use crate::space::element::CellElement;
use crate::space::rule::CellRule;
use crate::trace::FaceTables;
use bevy::prelude::*;
use glam::{DMat4, DVec3, DVec4};
use std::sync::Arc;

/// The space a hierarchy of entities lives in. Put it on a root entity;
/// every descendant with a [`Placement`] lives in this space. Cheap to
/// clone (shared). Several spaces may exist at once.
///
/// ```
/// use bevy::prelude::*;
/// use bevy_manifold::prelude::*;
/// let mut world = World::new();
/// let root = world.spawn(ManifoldSpace::new(catalog::poincare())).id();
/// let ship = world.spawn((Placement::default(), ChildOf(root))).id();
/// assert_eq!(world.get::<ManifoldSpace>(root).unwrap().space().group_order(), Some(120));
/// # let _ = ship;
/// ```
// A root has a transform (and, with a renderer, a visibility) like any
// Bevy parent, so what is below it propagates as Bevy expects.
#[derive(Component, Clone)]
#[cfg_attr(feature = "render", require(Transform, bevy::camera::visibility::Visibility))]
#[cfg_attr(not(feature = "render"), require(Transform))]
pub struct ManifoldSpace {
    space: Arc<Space>,
    tables: Arc<FaceTables<f64>>,
    rule: CellRule,
}

impl ManifoldSpace {
    /// Wraps a space for the ECS.
    #[must_use]
    pub fn new(space: Space) -> Self {
        Self::from_shared(Arc::new(space))
    }

    /// Wraps a space already shared (a loaded [`crate::assets::SpaceAsset`]'s).
    #[must_use]
    pub fn from_shared(space: Arc<Space>) -> Self {
        let tables = Arc::new(FaceTables::new(&space));
        ManifoldSpace {
            space,
            tables,
            rule: CellRule::default(),
        }
    }

    /// The same space under per-cell rules ([`crate::space::rule`]):
    /// objects in off cells hidden from ray casts, walls between cells
    /// that block ray casts and moving entities (a [`WallHit`] says so).
    /// The render pass draws them (the CPU tracer reads them through
    /// `TraceSettings::cell_rule`).
    ///
    /// ```
    /// use bevy_manifold::prelude::*;
    /// use bevy_manifold::space::rule::{CellRule, Walls};
    /// let maze = CellRule { walls: Some(Walls { density: 0.7, seed: 3 }), ..Default::default() };
    /// let ms = ManifoldSpace::new(catalog::seifert_weber()).with_rule(maze);
    /// assert_eq!(*ms.rule(), maze);
    /// ```
    #[must_use]
    pub fn with_rule(mut self, rule: CellRule) -> Self {
        self.rule = rule;
        self
    }

    /// The per-cell rules.
    #[must_use]
    pub fn rule(&self) -> &CellRule {
        &self.rule
    }

    /// Changes the per-cell rules.
    pub fn set_rule(&mut self, rule: CellRule) {
        self.rule = rule;
    }

    /// The space.
    #[must_use]
    pub fn space(&self) -> &Space {
        &self.space
    }

    /// The space, shared: the same `Arc` while the space is the same one
    /// (the render world repacks the space's buffers when it is not).
    #[must_use]
    pub fn shared(&self) -> &Arc<Space> {
        &self.space
    }

    /// Its per-face tables in f64, for walks through the faces.
    #[must_use]
    pub fn tables(&self) -> &FaceTables<f64> {
        &self.tables
    }
}

impl core::fmt::Debug for ManifoldSpace {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("ManifoldSpace")
            .field("space", &self.space.name())
            .finish()
    }
}

/// Where an entity is in its space, in f64: the isometry carrying the
/// origin and its frame to the entity's position and frame, inside the
/// fundamental domain. The wrap system keeps it inside.
///
/// ```
/// use bevy_manifold::prelude::*;
/// use glam::DVec3;
/// let sw = catalog::seifert_weber();
/// let p = Placement::at(&sw, DVec3::new(0.0, 0.0, 0.5));
/// assert!((sw.geometry().distance::<f64>(glam::DVec4::W, p.position()) - 0.5).abs() < 1e-12);
/// ```
#[derive(Component, Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Component, Debug, Default)]
#[require(DomainCell, WrapOrigin, Transform)]
pub struct Placement {
    /// Carries the origin's frame to the entity's (columns: the frame's
    /// three axes, then the position).
    pub isometry: DMat4,
    /// True after an odd number of mirror crossings: the frame is
    /// left-handed (an orbifold's mirror image).
    pub mirrored: bool,
}

impl Default for Placement {
    fn default() -> Self {
        Placement {
            isometry: DMat4::IDENTITY,
            mirrored: false,
        }
    }
}

impl Placement {
    /// A placement from an isometry (its handedness sets `mirrored`).
    #[must_use]
    pub fn from_isometry(isometry: DMat4) -> Self {
        Placement {
            isometry,
            mirrored: isometry::is_orientation_reversing(isometry),
        }
    }

    /// The placement reached from the origin by the tangent vector `v`
    /// (its frame parallel to the origin's).
    #[must_use]
    pub fn at(space: &Space, v: DVec3) -> Self {
        Self::from_isometry(isometry::translation(space.geometry(), v))
    }

    /// The position (normalised point).
    #[must_use]
    pub fn position(&self) -> DVec4 {
        self.isometry.w_axis
    }

    /// The unit tangent the entity faces (its local -z, Bevy's forward).
    #[must_use]
    pub fn forward(&self) -> DVec4 {
        -self.isometry.z_axis
    }

    /// The same placement turned by `rotation` in its own frame.
    #[must_use]
    pub fn rotated(self, rotation: DMat4) -> Self {
        Placement {
            isometry: self.isometry * rotation,
            ..self
        }
    }
}

/// Which copy of the fundamental domain an entity is in: the group element
/// `element` that carries the domain onto that copy, and its
/// path-independent id (see [`crate::space::cells`]). The entity's point in the
/// cover is `element * placement`.
///
/// `cell` is the same element as exactly as the space names it (exact
/// golden arithmetic in the Seifert-Weber space and the mirrored
/// dodecahedron, [`crate::space::exact`]): the wrap system crosses it
/// face by face, so an entity that flies any distance away and back by
/// another route is in the same cell with the same `id`. `element` is its
/// `f64` rounding, for drawing; game logic compares `id` or `cell`.
#[derive(Component, Clone, Debug, PartialEq, Reflect)]
#[reflect(Component, Debug, Default)]
pub struct DomainCell {
    /// The path-independent id of the copy.
    #[reflect(ignore)]
    pub id: CellId,
    /// The group element, rounded to `f64`.
    pub element: DMat4,
    /// The group element, exact where the space's ids are.
    #[reflect(ignore)]
    pub cell: CellElement,
}

impl Default for DomainCell {
    fn default() -> Self {
        DomainCell {
            id: CellId(0),
            element: DMat4::IDENTITY,
            cell: CellElement::default(),
        }
    }
}

impl DomainCell {
    /// The cell `cell` of `space`, with its id and rounded element.
    #[must_use]
    pub fn new(space: &Space, cell: CellElement) -> Self {
        DomainCell {
            id: space.cell_id_of(&cell),
            element: space.cell_matrix(&cell),
            cell,
        }
    }
}

/// Constant-velocity motion along geodesics, in the entity's own frame, per
/// second: `linear` (distance, along the local axes) and `angular` (radians,
/// about the local axes). Integrated exactly by the isometry exponential.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Reflect)]
#[reflect(Component, Debug, Default)]
#[require(Placement)]
pub struct GeodesicVelocity {
    /// Linear velocity in the local frame (local -z is forward).
    pub linear: DVec3,
    /// Angular velocity in the local frame.
    pub angular: DVec3,
}

/// A shape that [`crate::placement::ManifoldRayCast`] can hit.
#[derive(Component, Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Component, Debug)]
#[require(Placement)]
pub enum ManifoldCollider {
    /// A metric ball around the entity's position.
    Ball {
        /// Radius in the space's distance.
        radius: f64,
    },
}

impl ManifoldCollider {
    /// How far the shape reaches from the entity's position.
    #[must_use]
    pub fn radius(&self) -> f64 {
        match *self {
            ManifoldCollider::Ball { radius } => radius,
        }
    }
}

/// Where the wrap system last left the entity: the chord of the next motion
/// starts here. Kept by the plugin; game code can ignore it.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq)]
pub struct WrapOrigin(pub Option<DMat4>);

/// Sent when a wall of the space's rule ([`ManifoldSpace::with_rule`])
/// stops a moving entity: it stays where it was before the step.
#[derive(Message, Clone, Copy, Debug, PartialEq)]
pub struct WallHit {
    /// The entity.
    pub entity: Entity,
    /// The face it would have left through.
    pub face: usize,
    /// Its cell.
    pub cell: CellId,
}

/// Sent when an entity crosses a face of the domain.
#[derive(Message, Clone, Copy, Debug, PartialEq)]
pub struct FaceCrossed {
    /// The entity.
    pub entity: Entity,
    /// The face it left through.
    pub face: usize,
    /// Its cell before.
    pub old_cell: CellId,
    /// Its cell after.
    pub new_cell: CellId,
}
