//! The table's rules, free of windows and rendering: balls that roll
//! along geodesics and slow down, strike each other through the faces,
//! and drop into the pockets at the domain's corners. [`TablePlugin`] runs
//! them in Bevy's fixed-timestep schedules, so a game is a pure function
//! of the strokes played: the tests play it headless with
//! `MinimalPlugins` (`tests/billiards.rs`).
//!
//! The "table" is the whole manifold: there is no cushion, a ball that
//! leaves through a face comes back through its partner, and the pockets
//! sit at the vertices of the fundamental domain, where every copy of the
//! domain meets. In the 3-torus the eight corners of the cube are one
//! point, so a ball heading for any corner drops into the one pocket.
//!
//! The parts a game developer would copy:
//! - [`collide`]: two balls meet through the pairing the contact query
//!   names; the velocity of the far one is carried to the near one along
//!   the geodesic between them (parallel transport), the exchange happens
//!   in one tangent space, and the result is carried back;
//! - the contact queries ([`contact::ball_contacts`],
//!   [`contact::images_within`]) find every touching image, not just the
//!   one in the chart.

use bevy::prelude::*;
use bevy_manifold::contact;
use bevy_manifold::geometry::{Geometry, isometry};
use bevy_manifold::prelude::*;
use glam::{DMat4, DVec3, DVec4};

/// Ticks per second of the table's clock (Bevy's `Time<Fixed>`).
pub const TICK_HZ: f64 = 60.0;

/// Sizes and speeds, in units of the space's inradius `r` so every space
/// plays alike.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rules {
    /// A ball's radius.
    pub ball_radius: f64,
    /// A ball whose centre comes this close to a pocket drops in.
    pub pocket_radius: f64,
    /// A full stroke's speed, per second: a ball never goes faster, so in
    /// one tick it moves less than its radius and cannot pass through
    /// another.
    pub max_speed: f64,
    /// Rolling friction: speed falls by `e^(-drag t)`.
    pub drag: f64,
    /// Below this speed a ball stops.
    pub rest_speed: f64,
    /// The cue's reach: the player strikes the cue ball within it.
    pub reach: f64,
}

impl Rules {
    /// The rules in `space`.
    #[must_use]
    pub fn new(space: &Space) -> Rules {
        let r = space.inradius();
        Rules {
            ball_radius: 0.07 * r,
            pocket_radius: 0.16 * r,
            max_speed: 1.6 * r,
            drag: 0.35,
            rest_speed: 0.01 * r,
            reach: 0.6 * r,
        }
    }
}

/// A ball on the table: number 0 is the cue ball.
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq)]
pub struct Ball(pub u8);

/// A pocket: one for each class of vertices of the domain.
#[derive(Component, Clone, Copy, Debug)]
pub struct Pocket;

/// The player: flies around the table; the camera rides on it.
#[derive(Component, Clone, Copy, Debug)]
pub struct Player;

/// Something that happened, in the table's log.
#[derive(Clone, Debug, PartialEq)]
pub enum TableEvent {
    /// The cue ball was struck at this speed.
    Struck {
        /// Its speed after the stroke.
        speed: f64,
    },
    /// Two balls met.
    Collision {
        /// The two balls' numbers.
        balls: (u8, u8),
        /// They met through the faces (the image met is not the ball in
        /// the chart).
        through_faces: bool,
        /// Where they touched (in the domain's chart, next to the first
        /// ball: maybe outside the domain).
        point: DVec4,
        /// How fast they closed in, along the line of centres.
        speed: f64,
    },
    /// A ball dropped into a pocket.
    Sunk(u8),
    /// The cue ball dropped in: it comes back to its spot, and the stroke
    /// costs one more.
    Scratch,
    /// Every numbered ball is down.
    Cleared {
        /// Strokes it took (scratches count one more each).
        strokes: u32,
    },
}

/// The table's state.
#[derive(Resource, Debug)]
pub struct Table {
    /// The space's root entity.
    pub root: Entity,
    /// The player.
    pub player: Entity,
    /// The cue ball.
    pub cue_ball: Entity,
    /// Sizes and speeds.
    pub rules: Rules,
    /// Strokes played, scratches counted as one more.
    pub strokes: u32,
    /// Numbered balls still on the table.
    pub left: u32,
    /// Ticks played.
    pub tick: u64,
    /// What happened, by tick.
    pub log: Vec<(u64, TableEvent)>,
    /// Where the cue ball goes back to after a scratch.
    pub cue_spot: Placement,
}

impl Table {
    fn event(&mut self, e: TableEvent) {
        self.log.push((self.tick, e));
    }
}

/// What the table is set up with.
#[derive(Resource, Clone, Debug, PartialEq)]
pub struct TableConfig {
    /// A catalog space's name.
    pub space: String,
    /// Rack the numbered balls (off in tests that place their own).
    pub rack: bool,
}

impl Default for TableConfig {
    fn default() -> Self {
        TableConfig {
            space: "torus".into(),
            rack: true,
        }
    }
}

/// The stroke asked for this tick: the input (keyboard, mouse, script)
/// sets it, the table takes it at the next tick.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq)]
pub struct Cue {
    /// Strike the cue ball with this fraction of a full stroke (0 to 1).
    pub strike: Option<f64>,
}

/// The balls' colours, by number (0 is the cue ball), after pool's.
pub const COLORS: [Color; 11] = [
    Color::srgb(0.95, 0.93, 0.88),
    Color::srgb(0.95, 0.78, 0.1),
    Color::srgb(0.1, 0.3, 0.85),
    Color::srgb(0.85, 0.12, 0.1),
    Color::srgb(0.45, 0.15, 0.6),
    Color::srgb(0.95, 0.45, 0.1),
    Color::srgb(0.1, 0.55, 0.25),
    Color::srgb(0.5, 0.12, 0.12),
    Color::srgb(0.08, 0.08, 0.08),
    Color::srgb(0.95, 0.85, 0.4),
    Color::srgb(0.4, 0.6, 0.95),
];

/// The table's systems, in the fixed-timestep schedules; the placement
/// plugin must run in `FixedPostUpdate` (add
/// `ManifoldPlugins::in_schedule(FixedPostUpdate)`), so balls move by
/// exactly one tick after the table has resolved their contacts.
#[derive(Debug, Clone, Default)]
pub struct TablePlugin {
    /// The table to set up.
    pub config: TableConfig,
}

impl Plugin for TablePlugin {
    fn build(&self, app: &mut App) {
        app.insert_resource(self.config.clone())
            .insert_resource(Time::<Fixed>::from_hz(TICK_HZ))
            .init_resource::<Cue>()
            .add_systems(Startup, set_up_table)
            .add_systems(
                FixedPostUpdate,
                (take_stroke, roll, collide_balls, drop_into_pockets, count_tick)
                    .chain()
                    .run_if(resource_exists::<Table>)
                    .before(ManifoldSystems::Integrate),
            );
    }
}

/// Sets up (or sets up again) the table the [`TableConfig`] describes:
/// despawns any old one, spawns the space, the player, the pockets, the
/// cue ball and the rack. A system, and a function game code calls to
/// rack again.
pub fn set_up_table(mut commands: Commands, config: Res<TableConfig>, old: Option<Res<Table>>) {
    if let Some(old) = old {
        commands.entity(old.root).despawn();
    }
    let space = catalog::by_name(&config.space).unwrap_or_else(|| {
        warn!("billiards: no space {:?}; playing in the torus", config.space);
        catalog::torus(1.0)
    });
    let rules = Rules::new(&space);
    let r = space.inradius();
    let root = commands
        .spawn((ManifoldSpace::new(space.clone()), DomainEdges { radius: 0.008 * r }))
        .id();
    // The cue ball's spot, and the player a little above and behind it,
    // looking at it: the first stroke breaks the rack.
    let cue_spot = Placement::at(&space, DVec3::new(0.0, 0.0, -0.3) * r);
    let eye = Placement::at(&space, DVec3::new(0.0, 0.1, 0.2) * r).isometry;
    let player = commands
        .spawn((
            ChildOf(root),
            Player,
            Name::new("Player"),
            Placement::from_isometry(looking_at(space.geometry(), eye, cue_spot.position())),
            GeodesicVelocity::default(),
        ))
        .id();
    commands.spawn((
        ChildOf(root),
        ManifoldLight {
            intensity: 0.6 * r * r,
            ..default()
        },
        Placement::at(&space, DVec3::new(0.2, 0.55, 0.1) * r),
    ));
    for at in pocket_points(&space) {
        commands.spawn((
            ChildOf(root),
            Pocket,
            Name::new("Pocket"),
            Placement::from_isometry(isometry::translation_to(space.geometry(), at)),
            TracedBall::new(0.6 * rules.pocket_radius, Color::srgb(0.05, 0.02, 0.08)).glowing(0.4),
        ));
    }
    let cue_ball = spawn_ball(&mut commands, root, &rules, 0, cue_spot);
    let mut left = 0;
    if config.rack {
        for (i, at) in rack(rules.ball_radius, DVec3::new(0.0, 0.0, -0.65) * r)
            .into_iter()
            .enumerate()
        {
            spawn_ball(&mut commands, root, &rules, i as u8 + 1, Placement::at(&space, at));
            left += 1;
        }
    }
    commands.insert_resource(Table {
        root,
        player,
        cue_ball,
        rules,
        strokes: 0,
        left,
        tick: 0,
        log: Vec::new(),
        cue_spot,
    });
}

/// Spawns ball `number` at `placement`.
pub fn spawn_ball(commands: &mut Commands, root: Entity, rules: &Rules, number: u8, placement: Placement) -> Entity {
    let color = COLORS[usize::from(number) % COLORS.len()];
    commands
        .spawn((
            ChildOf(root),
            Ball(number),
            Name::new(format!("Ball {number}")),
            placement,
            TracedBall::new(rules.ball_radius, color).with_pbr(0.0, 0.15),
            ManifoldCollider::Ball {
                radius: rules.ball_radius,
            },
            GeodesicVelocity::default(),
        ))
        .id()
}

/// The ten balls of a triangular pyramid (layers of 1, 3 and 6), its apex
/// at `apex` pointing along +z, each ball `radius` apart from its
/// neighbours by a hair (so the rack does not start in contact).
#[must_use]
pub fn rack(radius: f64, apex: DVec3) -> Vec<DVec3> {
    let e = 2.0 * radius * 1.02;
    // Along a layer's rows x and y; from layer to layer the pyramid's
    // height step, e sqrt(2/3).
    let (row, height) = (e * 3f64.sqrt() / 2.0, e * (2.0f64 / 3.0).sqrt());
    let mut balls = Vec::new();
    for layer in 0..3 {
        // Layer n is a triangle of side n; its centroid on the axis.
        let centroid_y = row * f64::from(layer) * 2.0 / 3.0;
        for i in 0..=layer {
            for j in 0..=i {
                let x = e * (f64::from(j) - f64::from(i) / 2.0);
                let y = row * f64::from(i) - centroid_y;
                balls.push(apex + DVec3::new(x, y, -height * f64::from(layer)));
            }
        }
    }
    balls
}

/// One point for each class of vertices of the domain (the vertices that
/// the pairings glue into one point of the space), in the chart.
#[must_use]
pub fn pocket_points(space: &Space) -> Vec<DVec4> {
    let mut points: Vec<DVec4> = Vec::new();
    for v in space.vertices() {
        let known = points.iter().any(|&p| {
            contact::images_within(space, p, v.point, 1e-6)
                .first()
                .is_some_and(|i| i.distance < 1e-6)
        });
        if !known {
            points.push(v.point);
        }
    }
    points
}

/// The unit direction at the origin of the geodesic to the normalised
/// point `q`, and the translation along it that carries the origin to
/// `q`: applied to a tangent vector at the origin, it is that vector's
/// parallel transport to `q`. In all three models the geodesics through
/// the origin are lines, so the direction is `q`'s spatial part.
fn line_to(g: Geometry, q: DVec4) -> (DVec3, DMat4) {
    (q.truncate().normalize_or_zero(), isometry::translation_to(g, q))
}

/// A tangent vector `v` at the origin carried along the geodesic to the
/// other body (`along`, the translation [`line_to`] gives) and read in
/// that body's own frame (`rel`, its isometry seen from the origin's).
fn carried(g: Geometry, rel: DMat4, along: DMat4, v: DVec3) -> DVec3 {
    (isometry::inverse(g, rel) * along * v.extend(0.0)).truncate()
}

/// The isometry `from`, turned (by the least rotation) so that its
/// forward direction (local -z) points along the geodesic to `target`.
#[must_use]
pub fn looking_at(g: Geometry, from: DMat4, target: DVec4) -> DMat4 {
    let (n, _) = line_to(g, g.normalize_point::<f64>(isometry::inverse(g, from) * target));
    if n == DVec3::ZERO {
        return from;
    }
    from * DMat4::from_quat(glam::DQuat::from_rotation_arc(DVec3::NEG_Z, n))
}

/// Two balls meeting: `a` and `b` are their isometries (`b` the image of
/// the second ball that touches the first, the pairing's element times
/// its placement), `va` and `vb` their velocities in their own frames.
/// When they are closing in, returns their velocities after an elastic
/// collision of equal masses, each in its own frame; `None` when they
/// are moving apart (or at one point).
///
/// The second ball's velocity is carried to the first's centre along the
/// geodesic between them; there the exchange is the Euclidean one (the
/// components along the line of centres swap), and the second's new
/// velocity is carried back. Parallel transport keeps lengths, so the
/// kinetic energy is kept exactly, in every geometry. With `paddle` the
/// second body is infinitely heavy (a hand): the first bounces off it,
/// and the second's velocity is returned unchanged.
#[must_use]
pub fn collide(g: Geometry, (a, va): (DMat4, DVec3), (b, vb): (DMat4, DVec3), paddle: bool) -> Option<(DVec3, DVec3)> {
    // Everything in the first ball's frame: it sits at the origin.
    let rel = isometry::inverse(g, a) * b;
    let q = g.normalize_point::<f64>(rel.w_axis);
    let (n, to_b) = line_to(g, q);
    if n == DVec3::ZERO {
        return None;
    }
    let from_b = isometry::inverse(g, to_b);
    // The second's velocity, at the first's centre.
    let ub = (from_b * rel * vb.extend(0.0)).truncate();
    let closing = (va - ub).dot(n);
    if closing <= 0.0 || !closing.is_finite() {
        return None;
    }
    if paddle {
        return Some((va - 2.0 * closing * n, vb));
    }
    Some((va - closing * n, carried(g, rel, to_b, ub + closing * n)))
}

/// The velocity, in the cue ball's frame, that a stroke of `speed` from
/// the eye at `eye` gives it: along the geodesic from the eye through the
/// ball's centre, continued past it. `ball` is the isometry of the image
/// of the cue ball being struck.
#[must_use]
pub fn stroke(g: Geometry, eye: DMat4, ball: DMat4, speed: f64) -> DVec3 {
    let rel = isometry::inverse(g, eye) * ball;
    let (n, to_ball) = line_to(g, g.normalize_point::<f64>(rel.w_axis));
    carried(g, rel, to_ball, n * speed)
}

/// The stroke asked for: the cue ball struck along the player's line of
/// sight when the first thing on it, within the cue's reach, is the cue
/// ball (any image of it).
fn take_stroke(
    mut table: ResMut<Table>,
    mut cue: ResMut<Cue>,
    cast: ManifoldRayCast,
    spaces: Query<&ManifoldSpace>,
    placements: Query<(&Placement, Option<&DomainCell>)>,
    mut velocities: Query<&mut GeodesicVelocity, With<Ball>>,
) {
    let Some(power) = cue.strike.take() else { return };
    let Ok(ms) = spaces.get(table.root) else { return };
    let settings = RayCastSettings {
        max_distance: table.rules.reach,
        exclude: Some(table.player),
        ..default()
    };
    let Some(hit) = cast.cast(table.player, DVec3::NEG_Z, &settings).into_iter().next() else {
        return;
    };
    let (Ok((eye, eye_cell)), Ok((ball, _))) = (placements.get(table.player), placements.get(table.cue_ball)) else {
        return;
    };
    if hit.entity != table.cue_ball {
        return;
    }
    let Ok(mut velocity) = velocities.get_mut(table.cue_ball) else {
        return;
    };
    let space = ms.space();
    let g = space.geometry();
    // The copy of the domain the ray hit the ball in, seen from the
    // player's own copy (the hit's element counts from the origin cell).
    let copy = eye_cell.map_or(hit.element, |c| isometry::inverse(g, c.element) * hit.element);
    // In that copy, the image of the ball whose surface the hit is on
    // (a ball across a face is hit in its part beyond it).
    let Some(near) = contact::nearest_image(space, hit.point, ball.position()) else {
        return;
    };
    let speed = power.clamp(0.0, 1.0) * table.rules.max_speed;
    velocity.linear = stroke(g, eye.isometry, copy * near.element * ball.isometry, speed);
    velocity.angular = DVec3::ZERO;
    table.strokes += 1;
    table.event(TableEvent::Struck { speed });
}

/// Friction: every ball slows down, and stops below the rest speed.
fn roll(table: Res<Table>, time: Res<Time>, mut balls: Query<&mut GeodesicVelocity, With<Ball>>) {
    let keep = (-table.rules.drag * time.delta_secs_f64()).exp();
    for mut v in &mut balls {
        v.linear *= keep;
        if v.linear.length() < table.rules.rest_speed {
            v.linear = DVec3::ZERO;
        }
    }
}

/// Every pair of balls that touches, through any pairing, and closes in,
/// bounces.
fn collide_balls(
    mut table: ResMut<Table>,
    spaces: Query<&ManifoldSpace>,
    mut balls: Query<(&Ball, &Placement, &mut GeodesicVelocity)>,
) {
    let Ok(ms) = spaces.get(table.root) else { return };
    let space = ms.space();
    let g = space.geometry();
    let radius = table.rules.ball_radius;
    let mut pairs = balls.iter_combinations_mut();
    let mut events = Vec::new();
    while let Some([(ball_a, pa, mut va), (ball_b, pb, mut vb)]) = pairs.fetch_next() {
        if va.linear == DVec3::ZERO && vb.linear == DVec3::ZERO {
            continue;
        }
        // The deepest image that closes in is the one that bounces.
        for touch in contact::ball_contacts(space, (pa.position(), radius), (pb.position(), radius)) {
            let image = touch.image.element * pb.isometry;
            if let Some((a, b)) = collide(g, (pa.isometry, va.linear), (image, vb.linear), false) {
                // The first ball's change of velocity is the closing speed
                // along the line of centres.
                let speed = (a - va.linear).length();
                va.linear = a;
                vb.linear = b;
                let through_faces = !touch.image.element.abs_diff_eq(DMat4::IDENTITY, 1e-9);
                events.push(TableEvent::Collision {
                    balls: (ball_a.0, ball_b.0),
                    through_faces,
                    point: touch.point,
                    speed,
                });
                break;
            }
        }
    }
    for e in events {
        table.event(e);
    }
}

/// A ball whose centre comes within the pocket radius of a pocket (any
/// image of it) drops in; the cue ball comes back to its spot.
fn drop_into_pockets(
    mut commands: Commands,
    mut table: ResMut<Table>,
    spaces: Query<&ManifoldSpace>,
    pockets: Query<&Placement, (With<Pocket>, Without<Ball>)>,
    mut balls: Query<(Entity, &Ball, &mut Placement, &mut GeodesicVelocity)>,
) {
    let Ok(ms) = spaces.get(table.root) else { return };
    let space = ms.space();
    let reach = table.rules.pocket_radius;
    for (entity, ball, mut placement, mut velocity) in &mut balls {
        let p = placement.position();
        let sunk = pockets
            .iter()
            .any(|pocket| !contact::images_within(space, p, pocket.position(), reach).is_empty());
        if !sunk {
            continue;
        }
        if ball.0 == 0 {
            *placement = table.cue_spot;
            *velocity = GeodesicVelocity::default();
            table.strokes += 1;
            table.event(TableEvent::Scratch);
            continue;
        }
        commands.entity(entity).despawn();
        table.left = table.left.saturating_sub(1);
        table.event(TableEvent::Sunk(ball.0));
        if table.left == 0 {
            let strokes = table.strokes;
            table.event(TableEvent::Cleared { strokes });
        }
    }
}

fn count_tick(mut table: ResMut<Table>) {
    table.tick += 1;
}
