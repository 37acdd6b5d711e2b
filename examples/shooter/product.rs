//! The shooter in the product spaces (H2xR and S2xR: `--space s2xs1`,
//! `genus2xs1`, `twisted-s2xs1`, `twisted-genus2xs1`, `mirrored-prism`).
//!
//! The same inputs fly the player ([`TickInput`]: thrust along its axes,
//! turn about them), the same scripts record and replay it. The player is
//! a [`ProductCamera`]'s view, flown along geodesics through the faces
//! ([`ProductView::moved`]); the targets are balls of the product metric
//! ([`ProductBody`]); a shot is a ball too, flown along its geodesic
//! through the faces by the core's `flow` at each fixed tick. Each tick a
//! shot's whole step is swept before it moves: a ray along it against
//! every image of every target (and, once the shot is old enough, of the
//! player), each grown by the shot's radius, so no shot tunnels and a
//! target seen through a face is hit through it. A target hit scores and
//! moves on to the seed's next place. Your own shots come back around: up
//! the circle after its length, round the sphere of S2 x S1 after 2 pi.
//! These spaces have targets and no enemies yet.

use crate::game::{Difficulty, GameConfig, Rules};
use crate::input::{InputSource, TickInput};
use bevy::prelude::*;
use bevy_manifold::geometry::product::{ProductPoint, ProductTangent};
use bevy_manifold::product::{ProductBody, ProductCamera, ProductSpaceRoot};
use bevy_manifold::space::product::ProductSpace;
use bevy_manifold::trace::product::{
    ProductBall, ProductEdges, ProductObjects, ProductRay, ProductScene, ProductView, flow, hits_in, images,
};
use glam::DVec3;
use std::sync::Arc;

/// The rules in the product spaces: the other spaces' at an inradius of
/// 1 (their prisms are 2 high and 1 to 1.5 across), the shots living 4
/// seconds (8 units: round the sphere of S2 x S1 and back).
#[must_use]
pub fn product_rules(difficulty: Difficulty) -> Rules {
    Rules {
        shot_life: 4.0,
        ..Rules::scaled(1.0, difficulty)
    }
}

/// Targets in play.
pub const TARGETS: usize = 6;

/// What happened, by tick.
#[derive(Clone, Debug, PartialEq)]
pub enum ProductEvent {
    /// The player fired.
    Fired,
    /// A shot hit a target, after flying `distance` through `faces` faces.
    TargetHit {
        /// The shot's distance flown to the hit.
        distance: f64,
        /// Faces it crossed on the way.
        faces: usize,
    },
    /// One of the player's own shots came back around and hit it.
    PlayerHit {
        /// The shot's distance flown to the hit.
        distance: f64,
        /// Faces it crossed on the way.
        faces: usize,
    },
}

/// The game in a product space.
#[derive(Resource, Debug)]
pub struct ProductGame {
    /// The space's root.
    pub root: Entity,
    /// The player: its `ProductCamera`'s view is where it is.
    pub player: Entity,
    /// The space.
    pub space: Arc<ProductSpace>,
    /// The rules.
    pub rules: Rules,
    /// Ticks played.
    pub tick: u64,
    /// Targets hit.
    pub score: u32,
    /// Hits taken from one's own shots.
    pub hits_taken: u32,
    /// What happened, by tick.
    pub log: Vec<(u64, ProductEvent)>,
    /// The tick of the last shot fired.
    last_fired: Option<u64>,
    /// The seed's generator: where targets go.
    rng: u64,
}

/// A target's object id: green ([`bevy_manifold::trace::product::palette`]).
pub const TARGET_ID: u32 = 2;
/// A shot's: yellow.
pub const SHOT_ID: u32 = 4;

/// A target.
#[derive(Component, Debug)]
pub struct ProductTarget;

/// A shot: its velocity (a tangent at its centre), its age and how far
/// it has flown and through how many faces.
#[derive(Component, Debug)]
pub struct ProductShot {
    /// Its velocity.
    pub velocity: ProductTangent,
    /// Seconds since it was fired.
    pub age: f64,
    /// Distance flown.
    pub flown: f64,
    /// Faces crossed.
    pub faces: usize,
}

/// Runs the game in the fixed schedule: the player flies and fires, the
/// shots are swept and flown, targets hit move on.
pub struct ProductGamePlugin {
    /// The game's space (one of `ProductSpace::NAMES`), seed and
    /// difficulty.
    pub config: GameConfig,
}

impl Plugin for ProductGamePlugin {
    fn build(&self, app: &mut App) {
        app.insert_resource(self.config.clone())
            .add_systems(Startup, start_product_game)
            .add_systems(
                FixedUpdate,
                (control_product_player, sweep_product_shots, fly_product_shots).chain(),
            );
    }
}

/// The space `name` names, with the shooter's circle of 2.
#[must_use]
pub fn product_space(name: &str) -> Option<ProductSpace> {
    ProductSpace::named(name, 2.0, 3)
}

/// xorshift64*: the seed's sequence of places.
fn next(rng: &mut u64) -> f64 {
    *rng ^= *rng >> 12;
    *rng ^= *rng << 25;
    *rng ^= *rng >> 27;
    (rng.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
}

/// A target's next place: in the prism, off its walls (the polygon's
/// inner part, `0.25` to `0.6` across from its centre) and off the eye's
/// start.
fn target_place(space: &ProductSpace, rng: &mut u64) -> ProductPoint {
    let g = space.geometry;
    let angle = std::f64::consts::TAU * next(rng);
    let d = 0.25 + 0.35 * next(rng);
    let h = space.height * (next(rng) - 0.5) * 0.8;
    let (c, s) = g.trig(d);
    ProductPoint::new(DVec3::new(s * angle.cos(), s * angle.sin(), c), h)
}

/// Spawns the space, the player (the default scene's view) and the
/// targets; with `spawn` off (tests), no targets.
pub fn start_product_game(mut commands: Commands, config: Res<GameConfig>) {
    let space = Arc::new(product_space(&config.space).expect("a product space's name"));
    let rules = product_rules(config.difficulty);
    let root = commands
        .spawn((Name::new("product space"), ProductSpaceRoot(space.clone())))
        .id();
    let mut scene = ProductScene::default_for(&space);
    scene.balls.clear();
    scene.view.max_crossings = 8;
    // The prism's edges, to fly by.
    scene.edges = Some(ProductEdges::default());
    let player = commands
        .spawn((
            Name::new("player"),
            ChildOf(root),
            ProductCamera::of((*space).clone(), scene),
        ))
        .id();
    let mut rng = config.seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
    if config.spawn {
        for k in 0..TARGETS {
            commands.spawn((
                Name::new(format!("target {k}")),
                ChildOf(root),
                ProductTarget,
                ProductBody {
                    center: target_place(&space, &mut rng),
                    radius: rules.target_radius,
                    id: TARGET_ID,
                },
            ));
        }
    }
    commands.insert_resource(ProductGame {
        root,
        player,
        space,
        rules,
        tick: 0,
        score: 0,
        hits_taken: 0,
        log: Vec::new(),
        last_fired: None,
        rng,
    });
}

/// The tick's input flies and turns the player and fires.
pub fn control_product_player(
    mut commands: Commands,
    time: Res<Time>,
    mut game: ResMut<ProductGame>,
    mut source: ResMut<InputSource>,
    mut cameras: Query<&mut ProductCamera>,
) {
    let tick = game.tick;
    let input: TickInput = source.take(tick);
    game.tick += 1;
    let dt = time.delta_secs_f64();
    let rules = game.rules;
    let space = game.space.clone();
    let g = space.geometry;
    let Ok(mut camera) = cameras.get_mut(game.player) else {
        return;
    };
    let turn = input.turn * rules.turn_rate * dt;
    let mut view = camera.view.turned(g, -turn.y, turn.x).rolled(g, turn.z);
    let thrust = input.thrust;
    if thrust.length() > 0.0 {
        let d = [-thrust.z, thrust.x, thrust.y];
        view = view.moved(&space, d, thrust.length().min(1.0) * rules.player_speed * dt);
    }
    camera.view = view;
    let ready = game
        .last_fired
        .is_none_or(|t| (tick - t) as f64 * dt >= rules.fire_interval - 1e-9);
    if input.fire && ready {
        game.last_fired = Some(tick);
        game.log.push((tick, ProductEvent::Fired));
        let [forward, ..] = view.frame;
        // Fired from just ahead of the player, clear of it.
        let out = ProductRay {
            origin: view.eye,
            dir: forward,
        };
        let start = flow(&space, out, rules.player_radius + rules.shot_radius, 64).ray;
        commands.spawn((
            Name::new("shot"),
            ChildOf(game.root),
            ProductShot {
                velocity: ProductTangent::new(
                    start.dir.surface * rules.shot_speed,
                    start.dir.height * rules.shot_speed,
                ),
                age: 0.0,
                flown: 0.0,
                faces: 0,
            },
            ProductBody {
                center: start.origin,
                radius: rules.shot_radius,
                id: SHOT_ID,
            },
        ));
    }
}

/// Sweeps each shot's step before it moves: a ray along its geodesic for
/// the step against every image of every target and (past the grace) of
/// the player, each grown by the shot's radius (a shot fired into a
/// target, already in its grown ball, hits it at once). The first met is hit: a
/// target moves to its next place and scores, the player is hurt; the
/// shot is spent.
pub fn sweep_product_shots(
    mut commands: Commands,
    time: Res<Time>,
    mut game: ResMut<ProductGame>,
    shots: Query<(Entity, &ProductShot, &ProductBody), Without<ProductTarget>>,
    mut targets: Query<(Entity, &mut ProductBody), With<ProductTarget>>,
    cameras: Query<&ProductCamera>,
) {
    let dt = time.delta_secs_f64();
    let rules = game.rules;
    let space = game.space.clone();
    let g = space.geometry;
    let Ok(eye) = cameras.get(game.player).map(|c| c.view.eye) else {
        return;
    };
    let list: Vec<Entity> = targets.iter().map(|(e, _)| e).collect();
    let player_id = list.len() as u32;
    // The grown balls' images, made once a tick: the targets', then the
    // player's (for the shots past their grace).
    let grown: Vec<ProductBall> = targets
        .iter()
        .enumerate()
        .map(|(k, (_, b))| ProductBall {
            center: b.center,
            radius: b.radius + rules.shot_radius,
            id: k as u32,
        })
        .collect();
    let target_images = images(&space, &grown);
    let player = ProductBall {
        center: eye,
        radius: rules.player_radius + rules.shot_radius,
        id: player_id,
    };
    let with_player = ProductObjects {
        balls: [target_images.clone(), images(&space, &[player])].concat(),
        ..ProductObjects::default()
    };
    let without_player = ProductObjects {
        balls: target_images,
        ..ProductObjects::default()
    };
    for (entity, shot, body) in &shots {
        let speed = shot.velocity.length(g);
        if speed <= 0.0 {
            continue;
        }
        let ray = ProductRay {
            origin: body.center,
            dir: shot.velocity.unit(g),
        };
        let objects = if shot.age >= rules.grace {
            &with_player
        } else {
            &without_player
        };
        // A shot already in a grown ball (a target it was fired into)
        // hits it where it is; else the first ball its step enters.
        let inside = objects
            .balls
            .iter()
            .find(|b| g.distance(b.center, body.center) <= b.radius)
            .map(|b| (b.id, 0.0, 0));
        let entered = || {
            hits_in(&space, objects, ray, speed * dt, 64)
                .into_iter()
                .next()
                .map(|h| (h.object, h.distance, h.faces.len()))
        };
        let Some((object, along, crossed)) = inside.or_else(entered) else {
            continue;
        };
        let (distance, faces) = (shot.flown + along, shot.faces + crossed);
        commands.entity(entity).despawn();
        // The tick being played (the player's system counted it).
        let tick = game.tick.saturating_sub(1);
        if object == player_id {
            game.hits_taken += 1;
            game.log.push((tick, ProductEvent::PlayerHit { distance, faces }));
        } else {
            game.score += 1;
            game.log.push((tick, ProductEvent::TargetHit { distance, faces }));
            let place = target_place(&space, &mut game.rng);
            if let Ok((_, mut target)) = targets.get_mut(list[object as usize]) {
                target.center = place;
            }
        }
    }
}

/// Flies each shot its step along its geodesic through the faces, its
/// velocity turned as the geodesic and the gluings turn it; a shot past
/// its life is spent.
pub fn fly_product_shots(
    mut commands: Commands,
    time: Res<Time>,
    game: Res<ProductGame>,
    mut shots: Query<(Entity, &mut ProductShot, &mut ProductBody)>,
) {
    let dt = time.delta_secs_f64();
    let space = &game.space;
    let g = space.geometry;
    for (entity, mut shot, mut body) in &mut shots {
        shot.age += dt;
        let speed = shot.velocity.length(g);
        if shot.age > game.rules.shot_life || speed <= 0.0 {
            commands.entity(entity).despawn();
            continue;
        }
        let ray = ProductRay {
            origin: body.center,
            dir: shot.velocity.unit(g),
        };
        let walk = flow(space, ray, speed * dt, 64);
        body.center = walk.ray.origin;
        shot.velocity = ProductTangent::new(walk.ray.dir.surface * speed, walk.ray.dir.height * speed);
        shot.flown += speed * dt;
        shot.faces += walk.faces.len();
    }
}

/// The autopilot in a product space: turn towards the nearest image of
/// the nearest target (along the geodesic to it, in the view's frame) and
/// fire when it is lined up.
pub fn product_autopilot(
    game: Res<ProductGame>,
    mut source: ResMut<InputSource>,
    cameras: Query<&ProductCamera>,
    targets: Query<&ProductBody, With<ProductTarget>>,
) {
    let Ok(camera) = cameras.get(game.player) else {
        return;
    };
    let g = game.space.geometry;
    let view: ProductView = camera.view;
    let mut best: Option<(ProductTangent, f64)> = None;
    for target in &targets {
        let ball = ProductBall {
            center: target.center,
            radius: target.radius,
            id: 0,
        };
        for image in images(&game.space, &[ball]) {
            if let Some((dir, d)) = g.log(view.eye, image.center)
                && best.is_none_or(|b| d < b.1)
            {
                best = Some((dir, d));
            }
        }
    }
    let Some((dir, d)) = best else {
        source.live = TickInput {
            turn: DVec3::new(0.0, 0.6, 0.0),
            ..default()
        };
        return;
    };
    let [f, r, u] = view.frame;
    let local = DVec3::new(g.dot(dir, r), g.dot(dir, u), -g.dot(dir, f));
    let yaw = (-local.x).atan2(-local.z);
    let pitch = local.y.atan2(local.x.hypot(local.z));
    let off = local.angle_between(DVec3::NEG_Z);
    source.live = TickInput {
        turn: DVec3::new(pitch * 3.0, yaw * 3.0, 0.0).clamp(DVec3::splat(-1.0), DVec3::splat(1.0)),
        thrust: if d > 0.8 { DVec3::NEG_Z * 0.4 } else { DVec3::ZERO },
        fire: off < 0.7 * (game.rules.target_radius / d).atan(),
    };
}

/// A product game with no window: `MinimalPlugins`, the manifold's
/// systems, the game, and a clock that advances one tick per `update`
/// (as [`crate::input::headless_app`] for the other spaces).
pub fn product_headless_app(config: GameConfig, script: Option<crate::input::Script>, dt: std::time::Duration) -> App {
    let mut app = App::new();
    app.add_plugins((
        MinimalPlugins,
        bevy_manifold::prelude::ManifoldPlugins::in_schedule(FixedPostUpdate),
        ProductGamePlugin { config },
    ));
    app.insert_resource(Time::<Fixed>::from_duration(dt))
        .insert_resource(bevy::time::TimeUpdateStrategy::ManualDuration(dt))
        .insert_resource(InputSource { script, ..default() });
    // The first update starts the clock (no tick), and spawns the game.
    app.update();
    app
}

/// The autopilot's place: before the player reads the tick's input.
pub fn with_product_bot(app: &mut App) {
    app.add_systems(FixedUpdate, product_autopilot.before(control_product_player));
}
