//! The game's rules, free of windows and rendering: what a shot, a target,
//! an enemy and the player are, how a fixed tick moves them, and what
//! counts as a hit. [`GamePlugin`] runs it all in Bevy's fixed-timestep
//! schedules, so a game is a pure function of its [`GameConfig`] and the
//! input of each tick ([`crate::input`]): the tests play it headless with
//! `MinimalPlugins`, the window version adds `crate::view` on top.
//!
//! The parts a game developer would copy:
//! - shots are entities with a [`GeodesicVelocity`]; the placement plugin
//!   moves them along geodesics and wraps them through the faces exactly;
//! - [`crate::combat::sweep_shots`] sweeps each shot's ball along its whole step
//!   ([`ManifoldRayCast::shape_cast`]) before it moves, so no speed tunnels and every
//!   image of every target is hit through the faces, under the space's
//!   per-cell rule (an image in an "off" cell is passed through);
//! - the plugin's nearest image ([`bevy_manifold::contact::nearest_image`]) is the
//!   shortest route through the faces, which the enemies fly and aim along, and its
//!   contact queries ([`ManifoldContacts`]) say when an enemy rams the player.

use crate::combat::{enemies_fly_and_fire, enemies_ram, sweep_shots};
use crate::input::{InputSource, TickInput};
use bevy::prelude::*;
use bevy_manifold::motion::advance_placement;
use bevy_manifold::placement::WrapOrigin;
use bevy_manifold::prelude::*;
use bevy_manifold::space::FaceKind;
use bevy_manifold::space::rule::{CellRule, OnOff};
use glam::{DVec3, DVec4};

/// Ticks per second of the game's clock (Bevy's `Time<Fixed>`).
pub const TICK_HZ: f64 = 60.0;

/// How hard the game is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Difficulty {
    /// Slow enemies that rarely fire.
    Easy,
    /// The default.
    Normal,
    /// More enemies, faster, firing more often.
    Hard,
}

impl Difficulty {
    /// Every difficulty, in the menu's order.
    pub const ALL: [Difficulty; 3] = [Difficulty::Easy, Difficulty::Normal, Difficulty::Hard];

    /// Its name in the menu and on the command line.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Difficulty::Easy => "easy",
            Difficulty::Normal => "normal",
            Difficulty::Hard => "hard",
        }
    }

    /// The difficulty named `name`.
    #[must_use]
    pub fn by_name(name: &str) -> Option<Difficulty> {
        Difficulty::ALL.into_iter().find(|d| d.name() == name)
    }

    fn factor(self) -> f64 {
        match self {
            Difficulty::Easy => 0.6,
            Difficulty::Normal => 1.0,
            Difficulty::Hard => 1.5,
        }
    }
}

/// What a game is started with: the same config and the same inputs give
/// the same game.
#[derive(Resource, Clone, Debug, PartialEq)]
pub struct GameConfig {
    /// A catalog space's name.
    pub space: String,
    /// Fixes the spawns and the cell rule.
    pub seed: u64,
    /// How hard.
    pub difficulty: Difficulty,
    /// Spawn targets and enemies (off in tests that place their own).
    pub spawn: bool,
}

impl Default for GameConfig {
    fn default() -> Self {
        GameConfig {
            space: "torus".into(),
            seed: 1,
            difficulty: Difficulty::Normal,
            spawn: true,
        }
    }
}

/// Sizes and speeds, in units of the space's inradius `r` so every space
/// plays alike (the torus of period 1 has `r = 1/2`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rules {
    /// The player's collider radius.
    pub player_radius: f64,
    /// Flight speed at full thrust, per second.
    pub player_speed: f64,
    /// Turn rate at full stick, radians per second.
    pub turn_rate: f64,
    /// A shot's speed, per second.
    pub shot_speed: f64,
    /// A shot's radius.
    pub shot_radius: f64,
    /// Seconds a shot lives.
    pub shot_life: f64,
    /// Seconds after firing in which a shot cannot hit its owner.
    pub grace: f64,
    /// Seconds between two of the player's shots.
    pub fire_interval: f64,
    /// A target's radius.
    pub target_radius: f64,
    /// An enemy's radius.
    pub enemy_radius: f64,
    /// An enemy's speed, per second.
    pub enemy_speed: f64,
    /// Seconds between an enemy's shots.
    pub enemy_fire_interval: f64,
    /// An enemy fires when the player's nearest image is this close.
    pub enemy_fire_range: f64,
}

impl Rules {
    /// The rules in `space` at `difficulty`.
    #[must_use]
    pub fn new(space: &Space, difficulty: Difficulty) -> Rules {
        Rules::scaled(space.inradius(), difficulty)
    }

    /// The rules for a space of inradius `r` at `difficulty`.
    #[must_use]
    pub fn scaled(r: f64, difficulty: Difficulty) -> Rules {
        let f = difficulty.factor();
        Rules {
            player_radius: 0.12 * r,
            player_speed: 1.2 * r,
            turn_rate: 1.6,
            shot_speed: 2.0 * r,
            shot_radius: 0.03 * r,
            shot_life: 3.0,
            grace: 0.25,
            fire_interval: 0.2,
            target_radius: 0.2 * r,
            enemy_radius: 0.15 * r,
            enemy_speed: 0.35 * r * f,
            enemy_fire_interval: 3.0 / f,
            enemy_fire_range: 3.0 * r,
        }
    }
}

/// Where the game is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// The start menu: the space is shown, nothing moves.
    Menu,
    /// Playing.
    Playing,
    /// Paused: nothing moves.
    Paused,
    /// Health ran out.
    Over,
}

/// Something that happened, in the game's log (what a replay must repeat).
#[derive(Clone, Debug, PartialEq)]
pub enum GameEvent {
    /// The player fired.
    Fired,
    /// An enemy fired.
    EnemyFired,
    /// A shot hit a target's image: `distance` is how far the shot had
    /// flown, `faces` how many faces it crossed in its last step.
    TargetHit {
        /// The shot's distance flown at the hit.
        distance: f64,
        /// Faces the last step's ray crossed before the hit.
        faces: usize,
        /// The cell the image hit is in.
        cell: CellId,
    },
    /// A shot hit an enemy.
    EnemyHit {
        /// The shot's distance flown at the hit.
        distance: f64,
    },
    /// A shot hit the player: its own (after the grace period) or an enemy's.
    PlayerHit {
        /// The player's own shot.
        own: bool,
        /// The shot's distance flown at the hit.
        distance: f64,
    },
    /// An enemy flew into the player.
    Rammed,
    /// A level began.
    Level(u32),
    /// Health ran out.
    GameOver,
}

/// The game's state: score, level, health, and the log of events.
#[derive(Resource, Debug)]
pub struct Game {
    /// Where the game is.
    pub phase: Phase,
    /// Points.
    pub score: u64,
    /// The level, from 1.
    pub level: u32,
    /// Health, from 100 down to 0.
    pub health: f64,
    /// Targets hit in this level.
    pub hits: u32,
    /// Ticks played.
    pub tick: u64,
    /// What happened, by tick.
    pub log: Vec<(u64, GameEvent)>,
    /// The space's root entity.
    pub root: Entity,
    /// The player.
    pub player: Entity,
    /// The rules of the space and difficulty.
    pub rules: Rules,
    /// The player's next shot is allowed at this tick.
    next_fire: u64,
    pub(crate) rng: SplitMix,
}

impl Game {
    /// Targets to hit to finish `level`.
    #[must_use]
    pub fn targets_for(level: u32) -> u32 {
        2 + level
    }

    /// The fraction of cells that are on in `level`: all in the first,
    /// then fewer, down to 30% (the paper's rule that gives "increasing
    /// challenge").
    #[must_use]
    pub fn on_fraction(level: u32) -> f32 {
        (1.0 - 0.15 * (level.saturating_sub(1)) as f32).max(0.3)
    }

    pub(crate) fn event(&mut self, e: GameEvent) {
        self.log.push((self.tick, e));
    }
}

/// Deterministic random numbers (splitmix64): spawns and the cell rule.
#[derive(Clone, Debug)]
pub(crate) struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`.
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform on the unit sphere.
    fn direction(&mut self) -> DVec3 {
        let z = 2.0 * self.unit() - 1.0;
        let a = std::f64::consts::TAU * self.unit();
        let s = (1.0 - z * z).sqrt();
        DVec3::new(s * a.cos(), s * a.sin(), z)
    }
}

/// The player: flies, fires, has health. The camera rides on it.
#[derive(Component, Debug)]
pub struct Player;

/// A shot in flight.
#[derive(Component, Clone, Copy, Debug)]
pub struct Shot {
    /// Who fired it.
    pub owner: Entity,
    /// Fired by the player (else by an enemy).
    pub by_player: bool,
    /// Distance flown so far.
    pub flown: f64,
    /// Seconds since it was fired.
    pub age: f64,
}

/// A target: one entity, an image of it in every cell; hitting any image
/// that is on counts.
#[derive(Component, Debug)]
pub struct Target;

/// An enemy: flies to the player's nearest image and fires along it.
#[derive(Component, Debug)]
pub struct Enemy {
    /// It starts moving at this tick (a moment after it appears).
    pub wake: u64,
    /// It may fire from this tick on.
    pub next_fire: u64,
}

/// The colours things are drawn in.
pub mod colors {
    use bevy::prelude::Color;
    /// The player's shots (glowing).
    pub const SHOT: Color = Color::srgb(1.0, 0.85, 0.35);
    /// The enemies' shots (glowing).
    pub const ENEMY_SHOT: Color = Color::srgb(1.0, 0.25, 0.2);
    /// Targets.
    pub const TARGET: Color = Color::srgb(0.25, 0.85, 0.55);
    /// Enemies.
    pub const ENEMY: Color = Color::srgb(0.75, 0.2, 0.8);
}

/// The game's systems, in the fixed-timestep schedules; the placement
/// plugin must run in `FixedPostUpdate` (add
/// `ManifoldPlugins::in_schedule(FixedPostUpdate)`) so shots move by
/// exactly one tick after being swept.
#[derive(Debug, Clone, Default)]
pub struct GamePlugin {
    /// The game to start with.
    pub config: GameConfig,
}

impl Plugin for GamePlugin {
    fn build(&self, app: &mut App) {
        app.insert_resource(self.config.clone())
            .insert_resource(Time::<Fixed>::from_hz(TICK_HZ))
            .init_resource::<InputSource>()
            .add_systems(Startup, start_game)
            .add_systems(
                FixedUpdate,
                (control_player, enemies_fly_and_fire).chain().run_if(playing),
            )
            .add_systems(
                FixedPostUpdate,
                (sweep_shots, enemies_ram, next_level, count_tick)
                    .chain()
                    .run_if(playing)
                    .before(ManifoldSystems::Integrate),
            );
    }
}

/// True while the game is being played.
pub fn playing(game: Option<Res<Game>>) -> bool {
    game.is_some_and(|g| g.phase == Phase::Playing)
}

/// Starts (or restarts) the game the [`GameConfig`] describes: despawns
/// any old one, spawns the space, the player and the first level. A
/// system, and a function game code calls to restart.
pub fn start_game(mut commands: Commands, config: Res<GameConfig>, old: Option<Res<Game>>) {
    if let Some(old) = old {
        commands.entity(old.root).despawn();
    }
    let space = catalog::by_name(&config.space).unwrap_or_else(|| {
        warn!("shooter: no space {:?}; playing in the torus", config.space);
        catalog::torus(1.0)
    });
    let rules = Rules::new(&space, config.difficulty);
    let root = commands
        .spawn((
            ManifoldSpace::new(space.clone()),
            DomainEdges {
                radius: 0.01 * space.inradius(),
            },
        ))
        .id();
    let player = commands
        .spawn((
            ChildOf(root),
            Player,
            Name::new("Player"),
            Placement::default(),
            GeodesicVelocity::default(),
            ManifoldCollider::Ball {
                radius: rules.player_radius,
            },
        ))
        .id();
    commands.spawn((
        ChildOf(root),
        ManifoldLight {
            intensity: 0.5 * space.inradius() * space.inradius(),
            ..default()
        },
        Placement::at(&space, DVec3::new(0.3, 0.5, 0.2) * space.inradius()),
    ));
    let mut game = Game {
        phase: Phase::Playing,
        score: 0,
        level: 0,
        health: 100.0,
        hits: 0,
        tick: 0,
        log: Vec::new(),
        root,
        player,
        rules,
        next_fire: 0,
        rng: SplitMix(config.seed),
    };
    begin_level(&mut commands, &mut game, &space, &config, (1, DVec4::W));
    commands.insert_resource(game);
}

/// Sets the cell rule for `level` and spawns its targets and enemies.
fn begin_level(
    commands: &mut Commands,
    game: &mut Game,
    space: &Space,
    config: &GameConfig,
    (level, player_at): (u32, DVec4),
) {
    game.level = level;
    game.hits = 0;
    game.event(GameEvent::Level(level));
    let rule = CellRule {
        hidden: (level > 1).then(|| OnOff {
            on_fraction: Game::on_fraction(level),
            seed: (config.seed as u32) ^ level.wrapping_mul(0x9e37_79b9),
        }),
        walls: None,
    };
    let root = game.root;
    commands.queue(move |world: &mut World| {
        if let Some(mut ms) = world.get_mut::<ManifoldSpace>(root) {
            ms.set_rule(rule);
        }
    });
    if !config.spawn {
        return;
    }
    for _ in 0..3 {
        let p = random_placement(&mut game.rng, space, player_at);
        spawn_target(commands, game, p);
    }
    let enemies = (level - 1).min(5) + u32::from(config.difficulty == Difficulty::Hard);
    for _ in 0..enemies {
        let p = random_placement(&mut game.rng, space, player_at);
        spawn_enemy(commands, game, p, DomainCell::default());
    }
}

/// A placement inside the domain, away from its faces: of eight random
/// ones, the farthest from every image of the player at `player_at`.
pub(crate) fn random_placement(rng: &mut SplitMix, space: &Space, player_at: DVec4) -> Placement {
    let r = space.inradius();
    let mut best = (f64::NEG_INFINITY, Placement::default());
    for _ in 0..8 {
        let d = r * (0.2 + 0.65 * rng.unit());
        let p = Placement::at(space, rng.direction() * d);
        let away = bevy_manifold::contact::nearest_image(space, p.position(), player_at).map_or(0.0, |i| i.distance);
        if away > best.0 {
            best = (away, p);
        }
    }
    best.1
}

/// Spawns a target at `placement`, in the origin cell.
pub fn spawn_target(commands: &mut Commands, game: &Game, placement: Placement) -> Entity {
    let r = game.rules.target_radius;
    commands
        .spawn((
            ChildOf(game.root),
            Target,
            Name::new("Target"),
            placement,
            TracedBall::new(r, colors::TARGET),
            ManifoldCollider::Ball { radius: r },
            // A slow spin, so the lighting moves.
            GeodesicVelocity {
                angular: DVec3::new(0.0, 0.7, 0.0),
                ..default()
            },
        ))
        .id()
}

/// Spawns an enemy at `placement` in `cell`.
pub fn spawn_enemy(commands: &mut Commands, game: &Game, placement: Placement, cell: DomainCell) -> Entity {
    let r = game.rules.enemy_radius;
    commands
        .spawn((
            ChildOf(game.root),
            Enemy {
                wake: game.tick + (1.5 * TICK_HZ) as u64,
                next_fire: game.tick + (2.5 * TICK_HZ) as u64,
            },
            Name::new("Enemy"),
            placement,
            cell,
            TracedBall::new(r, colors::ENEMY).glowing(0.3),
            ManifoldCollider::Ball { radius: r },
            GeodesicVelocity::default(),
        ))
        .id()
}

/// Spawns a shot fired by `owner` (the player's when `by_player`) from
/// `from` (a placement and its cell) along its forward direction (local
/// -z), starting `ahead` along it: moved there exactly, through the faces
/// on the way, and counted as flown.
pub fn spawn_shot(
    commands: &mut Commands,
    game: &Game,
    ms: &ManifoldSpace,
    (owner, by_player): (Entity, bool),
    (placement, cell): (Placement, DomainCell),
    ahead: f64,
) -> Entity {
    let rules = &game.rules;
    let space = ms.space();
    let (moved, _) = advance_placement(
        space,
        ms.tables(),
        placement.isometry,
        DVec3::NEG_Z * ahead,
        DVec3::ZERO,
        1.0,
    );
    let mut cell = cell;
    let mut mirrored = placement.mirrored;
    for &f in &moved.faces {
        cell = DomainCell::new(space, space.cross_cell(&cell.cell, f));
        mirrored ^= space.faces()[f].kind == FaceKind::Mirror;
    }
    let placement = Placement {
        isometry: moved.placement,
        mirrored,
    };
    let color = if by_player { colors::SHOT } else { colors::ENEMY_SHOT };
    commands
        .spawn((
            ChildOf(game.root),
            Shot {
                owner,
                by_player,
                flown: ahead,
                age: 0.0,
            },
            WrapOrigin(Some(placement.isometry)),
            Name::new("Shot"),
            placement,
            cell,
            TracedBall::new(rules.shot_radius, color).glowing(2.5),
            GeodesicVelocity {
                linear: DVec3::NEG_Z * rules.shot_speed,
                ..default()
            },
        ))
        .id()
}

/// The tick's input moves and turns the player, and fires.
pub fn control_player(
    mut commands: Commands,
    mut game: ResMut<Game>,
    mut source: ResMut<InputSource>,
    spaces: Query<&ManifoldSpace>,
    mut player: Query<(&Placement, &DomainCell, &mut GeodesicVelocity), With<Player>>,
) {
    let input: TickInput = source.take(game.tick);
    let Ok((placement, cell, mut velocity)) = player.get_mut(game.player) else {
        return;
    };
    let rules = game.rules;
    velocity.linear = input.thrust.clamp(DVec3::splat(-1.0), DVec3::splat(1.0)) * rules.player_speed;
    velocity.angular = input.turn.clamp(DVec3::splat(-1.0), DVec3::splat(1.0)) * rules.turn_rate;
    if input.fire && game.tick >= game.next_fire {
        game.next_fire = game.tick + (rules.fire_interval * TICK_HZ).round() as u64;
        let (p, c) = (*placement, cell.clone());
        let player = game.player;
        if let Ok(ms) = spaces.get(game.root) {
            // It leaves from just in front of the player's face, so the
            // eye is not inside it.
            let ahead = rules.player_radius + 2.0 * rules.shot_radius;
            spawn_shot(&mut commands, &game, ms, (player, true), (p, c), ahead);
            game.event(GameEvent::Fired);
        }
    }
}

/// The level is won when enough targets were hit; the game is over when
/// health runs out.
#[expect(clippy::type_complexity, reason = "a Bevy query")]
fn next_level(
    mut commands: Commands,
    mut game: ResMut<Game>,
    config: Res<GameConfig>,
    spaces: Query<&ManifoldSpace>,
    player: Query<&Placement, With<Player>>,
    leftovers: Query<Entity, Or<(With<Target>, With<Enemy>, With<Shot>)>>,
) {
    if game.health <= 0.0 {
        game.health = 0.0;
        game.phase = Phase::Over;
        game.event(GameEvent::GameOver);
        return;
    }
    if !config.spawn || game.hits < Game::targets_for(game.level) {
        return;
    }
    let Some(space) = spaces.get(game.root).ok().map(|m| m.space().clone()) else {
        return;
    };
    for e in &leftovers {
        commands.entity(e).despawn();
    }
    let level = game.level + 1;
    game.score += 250 * u64::from(game.level);
    game.health = (game.health + 20.0).min(100.0);
    let player_at = player.get(game.player).map_or(DVec4::W, Placement::position);
    begin_level(&mut commands, &mut game, &space, &config, (level, player_at));
}

fn count_tick(mut game: ResMut<Game>) {
    game.tick += 1;
}
