//! Tours of the product spaces (H2xR, S2xR): the default scene of a
//! space of [`ProductSpace::NAMES`] and legs flown from its view, each
//! exactly: a `fly` moves the eye along its geodesic through the faces
//! with its frame carried by parallel transport ([`ProductView::moved`]),
//! at the leg's constant speed, [`MAX_LEG_DISTANCE`] at most; a `turn` turns the frame in place at a
//! constant rate ([`ProductView::turned`], [`ProductView::rolled`]; a
//! turn of 0 seconds sets the view at once). The eye's copy of the prism
//! is kept exactly as it flies, so per-cell shading follows it.
//!
//! The file (`*.product-tour.json`; `product --tour` renders one):
//!
//! ```
//! use bevy_manifold_core::tour::product::ProductTourDesc;
//! let text = r#"{"product_space": "s2xs1", "length": 2, "legs": [
//!     {"turn": {"seconds": 0, "pitch_degrees": 90}, "caption": "straight up the circle"},
//!     {"fly": {"seconds": 4, "speed": 1}, "cells": true}
//! ]}"#;
//! let tour = ProductTourDesc::parse(text, "inline").unwrap().build("inline").unwrap();
//! assert_eq!(tour.duration(), 4.0);
//! // Up 4: twice round the circle of length 2, two copies up.
//! let end = tour.view_at(4.0);
//! assert_eq!(end.cell.map(|c| c.steps()), Some(2));
//! assert_eq!(tour.caption_at(1.0), Some("straight up the circle"));
//! ```

use super::file::{FlyDesc, MAX_KEYFRAMES, MAX_SECONDS, TourError, TurnDesc, parse_json, read_json};
use crate::space::cells::CellTint;
use crate::space::product::ProductSpace;
use crate::trace::product::{ProductBall, ProductLight, ProductLighting, ProductScene, ProductView};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// A product tour file as written.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProductTourDesc {
    /// The space: one of [`ProductSpace::NAMES`].
    pub product_space: String,
    /// The length of its circle (or interval).
    #[serde(default = "length")]
    pub length: f64,
    /// The twist of the twisted spaces ([`ProductSpace::named`]).
    #[serde(default = "twist")]
    pub twist: u32,
    /// Vertical field of view in degrees.
    #[serde(default = "fov")]
    pub fov_y_degrees: f64,
    /// The balls lit by the two point lights of the space's lit scene
    /// ([`ProductScene::lit_for`]: every image of each, with shadows)
    /// instead of from the eye.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub lights: bool,
    /// The legs, in order, from the default scene's view.
    pub legs: Vec<ProductLegDesc>,
}

fn length() -> f64 {
    2.0
}

fn twist() -> u32 {
    3
}

fn fov() -> f64 {
    70.0
}

/// One leg of a product tour: a fly or a turn, with the caption and the
/// per-cell shading that start with it.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProductLegDesc {
    /// Fly straight ahead.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fly: Option<FlyDesc>,
    /// Turn in place (yaw left, pitch up, roll; 0 seconds: at once).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub turn: Option<TurnDesc>,
    /// A caption shown from here until the next (`""` ends it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub caption: Option<String>,
    /// Each copy of the prism in its own colour from here on, or not.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cells: Option<bool>,
}

/// The longest fly of one leg: it is flown in steps of at most half the
/// prism's height (or 1/2), each through a few faces, from the leg's
/// start for each frame.
pub const MAX_LEG_DISTANCE: f64 = 1000.0;

/// A leg, checked.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Leg {
    /// Seconds and speed.
    Fly(f64, f64),
    /// Seconds and yaw (to the right), pitch and roll, in radians.
    Turn(f64, [f64; 3]),
}

impl Leg {
    fn seconds(self) -> f64 {
        match self {
            Leg::Fly(s, _) | Leg::Turn(s, _) => s,
        }
    }

    /// `view` after `fraction` of the leg.
    fn apply(self, space: &ProductSpace, view: &ProductView, fraction: f64) -> ProductView {
        match self {
            Leg::Fly(s, speed) => {
                // In steps short enough that none meets more than a few
                // faces (`moved` crosses 64 at most).
                let distance = speed.abs() * s * fraction;
                let step = space.height.min(1.0) / 2.0;
                let n = (distance / step).ceil().max(1.0);
                (0..n as usize).fold(*view, |v, _| v.moved(space, [speed.signum(), 0.0, 0.0], distance / n))
            }
            Leg::Turn(_, [yaw, pitch, roll]) => {
                let g = space.geometry;
                view.turned(g, yaw * fraction, pitch * fraction)
                    .rolled(g, roll * fraction)
            }
        }
    }
}

/// A product tour, checked and ready to play: the space, its balls, and
/// the view at any time ([`ProductTour::view_at`]).
#[derive(Clone, Debug)]
pub struct ProductTour {
    /// The space.
    pub space: ProductSpace,
    /// The balls (the space's default scene's).
    pub balls: Vec<ProductBall>,
    /// The lights (none: the balls are lit from the eye).
    pub lights: Vec<ProductLight>,
    /// How the lights light the balls.
    pub lighting: ProductLighting,
    /// Each leg with its start time and the view it starts from.
    legs: Vec<(f64, ProductView, Leg)>,
    /// The end: its time and view.
    end: (f64, ProductView),
    /// Captions and per-cell shading, each from its time on.
    captions: Vec<(f64, String)>,
    cells: Vec<(f64, bool)>,
}

impl ProductTourDesc {
    /// Reads a product tour file.
    ///
    /// # Errors
    /// Unreadable file or malformed JSON, named by the file.
    pub fn load(path: impl AsRef<Path>) -> Result<Self, TourError> {
        read_json(path.as_ref())
    }

    /// Parses product tour JSON; `path` names it in errors.
    ///
    /// # Errors
    /// Malformed JSON, a missing or unknown field.
    pub fn parse(text: &str, path: &str) -> Result<Self, TourError> {
        parse_json(text, path)
    }

    /// The tour, its space made and its legs checked and flown once (the
    /// view at each leg's start is kept, so any time is one leg away).
    ///
    /// # Errors
    /// The field that is wrong: an unknown space, a length or field of
    /// view out of range, a leg that is not one fly or one turn, times
    /// or speeds that are not finite, too many legs or too long a tour.
    pub fn build(&self, path: &str) -> Result<ProductTour, TourError> {
        let field = |field: String, message: String| TourError::Field {
            path: path.into(),
            field,
            message,
        };
        if !(self.length.is_finite() && self.length > 0.01 && self.length <= 100.0) {
            return Err(field(
                "length".into(),
                format!("must be in (0.01, 100], got {}", self.length),
            ));
        }
        if !(self.fov_y_degrees.is_finite() && self.fov_y_degrees > 1.0 && self.fov_y_degrees < 179.0) {
            return Err(field(
                "fov_y_degrees".into(),
                format!("must be in (1, 179), got {}", self.fov_y_degrees),
            ));
        }
        if !(1..=64).contains(&self.twist) {
            return Err(field("twist".into(), format!("must be in 1..=64, got {}", self.twist)));
        }
        let space = ProductSpace::named(&self.product_space, self.length, self.twist).ok_or_else(|| {
            field(
                "product_space".into(),
                format!(
                    "\"{}\" is not one of {}",
                    self.product_space,
                    ProductSpace::NAMES.join(", ")
                ),
            )
        })?;
        if self.legs.len() > MAX_KEYFRAMES {
            return Err(field(
                "legs".into(),
                format!("{} legs, more than {MAX_KEYFRAMES}", self.legs.len()),
            ));
        }
        let mut scene = if self.lights {
            ProductScene::lit_for(&space)
        } else {
            ProductScene::default_for(&space)
        };
        scene.view.fov_y_degrees = self.fov_y_degrees;
        let (mut t, mut view) = (0.0, scene.view);
        let (mut legs, mut captions, mut cells) = (Vec::new(), Vec::new(), Vec::new());
        for (i, desc) in self.legs.iter().enumerate() {
            let name = |f: &str| format!("legs[{i}]{f}");
            let leg = match (&desc.fly, &desc.turn) {
                (Some(f), None) => {
                    if !(f.seconds.is_finite() && f.seconds > 0.0) {
                        return Err(field(
                            name(".fly.seconds"),
                            format!("must be positive, got {}", f.seconds),
                        ));
                    }
                    if !(f.speed.is_finite() && f.speed.abs() <= 100.0) {
                        return Err(field(
                            name(".fly.speed"),
                            format!("must be within 100, got {}", f.speed),
                        ));
                    }
                    if f.speed.abs() * f.seconds > MAX_LEG_DISTANCE {
                        return Err(field(
                            name(".fly"),
                            format!(
                                "flies {:.0} units: too far for one leg ({MAX_LEG_DISTANCE} at most)",
                                f.speed.abs() * f.seconds
                            ),
                        ));
                    }
                    Leg::Fly(f.seconds, f.speed)
                }
                (None, Some(turn)) => {
                    let angles = [-turn.yaw_degrees, turn.pitch_degrees, turn.roll_degrees];
                    if !(turn.seconds.is_finite() && turn.seconds >= 0.0) {
                        return Err(field(
                            name(".turn.seconds"),
                            format!("must be 0 or more, got {}", turn.seconds),
                        ));
                    }
                    if angles.iter().any(|a| !(a.is_finite() && a.abs() <= 3600.0)) {
                        return Err(field(
                            name(".turn"),
                            "angles must be finite, within 3600 degrees".into(),
                        ));
                    }
                    Leg::Turn(turn.seconds, angles.map(f64::to_radians))
                }
                _ => return Err(field(name(""), "must be one leg: a fly or a turn".into())),
            };
            if let Some(c) = &desc.caption {
                captions.push((t, c.clone()));
            }
            if let Some(c) = desc.cells {
                cells.push((t, c));
            }
            legs.push((t, view, leg));
            view = leg.apply(&space, &view, 1.0);
            t += leg.seconds();
            if t > MAX_SECONDS {
                return Err(field(name(""), format!("the tour passes {MAX_SECONDS} seconds")));
            }
        }
        Ok(ProductTour {
            space,
            balls: scene.balls,
            lights: scene.lights,
            lighting: scene.lighting,
            legs,
            end: (t, view),
            captions,
            cells,
        })
    }
}

impl ProductTour {
    /// Reads and builds a product tour file.
    ///
    /// # Errors
    /// As [`ProductTourDesc::load`] and [`ProductTourDesc::build`].
    pub fn load(path: impl AsRef<Path>) -> Result<Self, TourError> {
        let p = path.as_ref().display().to_string();
        ProductTourDesc::load(path)?.build(&p)
    }

    /// Its length in seconds.
    #[must_use]
    pub fn duration(&self) -> f64 {
        self.end.0
    }

    /// The view at time `t` (clamped to the tour), with its per-cell
    /// shading.
    #[must_use]
    pub fn view_at(&self, t: f64) -> ProductView {
        let t = if t.is_nan() { 0.0 } else { t };
        let k = self.legs.partition_point(|(start, _, _)| *start <= t);
        let mut view = match k.checked_sub(1).map(|k| self.legs[k]) {
            Some((start, from, leg)) if t < start + leg.seconds() => {
                let fraction = if leg.seconds() > 0.0 {
                    (t - start) / leg.seconds()
                } else {
                    1.0
                };
                leg.apply(&self.space, &from, fraction)
            }
            Some(_) if k < self.legs.len() => self.legs[k].1,
            Some(_) => self.end.1,
            None => self.legs.first().map_or(self.end.1, |l| l.1),
        };
        let cells = latest(&self.cells, t).copied().unwrap_or(false);
        view.tint = cells.then_some(CellTint::ByCell);
        view
    }

    /// The caption shown at time `t`, if any.
    #[must_use]
    pub fn caption_at(&self, t: f64) -> Option<&str> {
        latest(&self.captions, t).map(String::as_str).filter(|c| !c.is_empty())
    }

    /// The scene at time `t`: the balls, the lights and the view.
    #[must_use]
    pub fn scene_at(&self, t: f64) -> ProductScene {
        ProductScene {
            balls: self.balls.clone(),
            meshes: Vec::new(),
            lights: self.lights.clone(),
            lighting: self.lighting,
            edges: None,
            view: self.view_at(t),
        }
    }
}

/// The value of the last entry at or before `t`.
fn latest<T>(entries: &[(f64, T)], t: f64) -> Option<&T> {
    let k = entries.partition_point(|(start, _)| *start <= t);
    k.checked_sub(1).map(|k| &entries[k].1)
}
