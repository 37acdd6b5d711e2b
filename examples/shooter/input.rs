//! The input of each game tick, from the devices or from a script, and
//! the recording of it: a game is replayed exactly from its
//! [`crate::game::GameConfig`] and the inputs of its ticks.
//!
//! A script is JSON: the game's config and the input held from each tick
//! on (until the next entry):
//!
//! ```json
//! {"space": "torus", "seed": 7, "difficulty": "normal",
//!  "inputs": [{"at": 0, "thrust": [0, 0, -1]},
//!             {"at": 30, "turn": [0, 0.5, 0], "fire": true},
//!             {"at": 90}],
//!  "ticks": 600}
//! ```
//!
//! `thrust` is along the player's own axes (-z forward), `turn` about
//! them (y: yaw, x: pitch, z: roll), each in `[-1, 1]`; `fire` holds the
//! trigger.

use crate::game::{Difficulty, GameConfig, GamePlugin};
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bevy_manifold::prelude::*;
use glam::DVec3;
use std::path::Path;
use std::time::Duration;

/// What the player does in one tick.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TickInput {
    /// Thrust along the local axes, each in `[-1, 1]`.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub thrust: DVec3,
    /// Turn rate about the local axes, each in `[-1, 1]`.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub turn: DVec3,
    /// The trigger is held.
    #[serde(default, skip_serializing_if = "is_false")]
    pub fire: bool,
}

fn is_zero(v: &DVec3) -> bool {
    *v == DVec3::ZERO
}

fn is_false(b: &bool) -> bool {
    !*b
}

/// An input held from tick `at` on.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScriptEntry {
    /// The first tick it holds for.
    pub at: u64,
    /// The input.
    #[serde(flatten)]
    pub input: TickInput,
}

/// A recorded or written game: its config and its inputs (in a catalog
/// space, or a product space: `crate::product`).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Script {
    /// A catalog space.
    pub space: String,
    /// The game's seed.
    pub seed: u64,
    /// How hard.
    pub difficulty: Difficulty,
    /// The inputs, by increasing `at`.
    pub inputs: Vec<ScriptEntry>,
    /// How many ticks the script lasts.
    pub ticks: u64,
}

/// Most entries and ticks a script may have (an hour at 60 Hz).
pub const MAX_TICKS: u64 = 60 * 60 * 60;

impl Script {
    /// The config it plays.
    #[must_use]
    pub fn config(&self) -> GameConfig {
        GameConfig {
            space: self.space.clone(),
            seed: self.seed,
            difficulty: self.difficulty,
            spawn: true,
        }
    }

    /// The input held at `tick`.
    #[must_use]
    pub fn at(&self, tick: u64) -> TickInput {
        let k = self.inputs.partition_point(|e| e.at <= tick);
        k.checked_sub(1)
            .map_or_else(TickInput::default, |k| self.inputs[k].input)
    }

    /// Reads a script, with errors naming the file and the field.
    ///
    /// # Errors
    /// An unreadable file, bad JSON, an unknown space, entries out of
    /// order or past [`MAX_TICKS`], an input out of `[-1, 1]`.
    pub fn read(path: &Path) -> Result<Script, String> {
        let name = path.display();
        let text = std::fs::read_to_string(path).map_err(|e| format!("{name}: {e}"))?;
        Script::parse(&text).map_err(|e| format!("{name}: {e}"))
    }

    /// [`Script::read`] from text.
    ///
    /// # Errors
    /// As [`Script::read`].
    pub fn parse(text: &str) -> Result<Script, String> {
        let s: Script = serde_json::from_str(text).map_err(|e| e.to_string())?;
        let product = bevy_manifold::space::product::ProductSpace::NAMES.contains(&s.space.as_str());
        if catalog::by_name(&s.space).is_none() && !product {
            return Err(format!(
                "space: no catalog space {:?} (one of {}), nor a product space ({})",
                s.space,
                catalog::NAMES.join(", "),
                bevy_manifold::space::product::ProductSpace::NAMES.join(", ")
            ));
        }
        if s.ticks > MAX_TICKS {
            return Err(format!("ticks: at most {MAX_TICKS}, got {}", s.ticks));
        }
        for (i, e) in s.inputs.iter().enumerate() {
            if i > 0 && e.at <= s.inputs[i - 1].at {
                return Err(format!(
                    "inputs[{i}].at: {} does not come after {}",
                    e.at,
                    s.inputs[i - 1].at
                ));
            }
            if e.at > MAX_TICKS {
                return Err(format!("inputs[{i}].at: at most {MAX_TICKS}, got {}", e.at));
            }
            for (field, v) in [("thrust", e.input.thrust), ("turn", e.input.turn)] {
                if v.abs().max_element() > 1.0 {
                    return Err(format!("inputs[{i}].{field}: each component in [-1, 1], got {v:?}"));
                }
            }
        }
        Ok(s)
    }

    /// The script as JSON.
    #[must_use]
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("a script serialises")
    }
}

/// Where the game's [`TickInput`] comes from, and what was recorded.
#[derive(Resource, Debug, Default)]
pub struct InputSource {
    /// A script to play (the devices are then ignored).
    pub script: Option<Script>,
    /// The devices' input, set each frame by the view.
    pub live: TickInput,
    /// Every change of input, by tick: a script of the game so far.
    pub recorded: Vec<ScriptEntry>,
}

impl InputSource {
    /// The input of `tick`, recorded.
    pub fn take(&mut self, tick: u64) -> TickInput {
        let input = self.script.as_ref().map_or(self.live, |s| s.at(tick));
        if self.recorded.last().is_none_or(|e| e.input != input) {
            self.recorded.push(ScriptEntry { at: tick, input });
        }
        input
    }

    /// What was played, as a script of `config` lasting `ticks`.
    #[must_use]
    pub fn recording(&self, config: &GameConfig, ticks: u64) -> Script {
        Script {
            space: config.space.clone(),
            seed: config.seed,
            difficulty: config.difficulty,
            inputs: self.recorded.clone(),
            ticks,
        }
    }
}

/// A game with no window: `MinimalPlugins`, the manifold's systems in the
/// fixed schedule, the game, and a clock that advances one tick per
/// `update` (so `n` updates play exactly `n` ticks, at `dt` seconds each).
pub fn headless_app(config: GameConfig, script: Option<Script>, dt: Duration) -> App {
    let mut app = App::new();
    app.add_plugins((
        MinimalPlugins,
        ManifoldPlugins::in_schedule(FixedPostUpdate),
        GamePlugin { config },
    ));
    app.insert_resource(Time::<Fixed>::from_duration(dt))
        .insert_resource(TimeUpdateStrategy::ManualDuration(dt))
        .insert_resource(InputSource { script, ..default() });
    // The first update starts the clock (no tick), and spawns the game.
    app.update();
    app
}
