//! The shooter: a game in a closed universe, where your shots come back
//! around. Hit the green targets (any image of a target counts, in every
//! copy of the domain where the level's cell rule shows it); the violet
//! enemies fly at you by the shortest route through the faces and fire
//! back; and in a compact space your own shot returns from behind: in the
//! 3-torus after one period, in Seifert-Weber along a closed geodesic
//! turned by the gluing.
//!
//! ```text
//! cargo run --release --example shooter [-- --space seifert-weber]
//!     [--difficulty easy|normal|hard] [--seed N] [--levels N]
//!     [--record FILE.json] [--play FILE.json [--headless]]
//!     [--screenshot FILE.png [--size WxH]] [--bot] [--headless [--ticks N]]
//! cargo run --release --features xr --example shooter -- --xr [--world-scale M]
//!     [--frames N --xr-capture DIR]
//! ```
//!
//! The flags are parsed as the CLI's are (`args.rs`, `--help`): an
//! unknown one is named and the game does not start. Without a display
//! (no `DISPLAY` or `WAYLAND_DISPLAY`) it says so and renders the opening
//! view to `shooter.png` instead of opening a window.
//!
//! The game's rules are `game.rs` (no rendering: the tests play it
//! headless, `tests/shooter.rs`), its inputs and scripts `input.rs`, and
//! the window, HUD, map and controls `view.rs`. `--record` writes the game
//! played as a script; `--play` replays one (in the window, or with
//! `--headless` as fast as it can, printing the score and the events).
//! `--xr` plays in a headset (`xr.rs`); without an OpenXR runtime it says
//! so and plays on the desktop. In the product spaces (`--space
//! genus2xs1`, `s2xs1`, ...) the game is `product.rs`: targets, your
//! shots coming back around, no enemies yet, on the desktop.

mod args;
mod bot;
mod combat;
mod game;
mod input;
mod product;
#[cfg(feature = "audio")]
mod sound;
mod view;
#[cfg(feature = "xr")]
mod xr;

#[path = "../support/hud.rs"]
mod hud;
#[path = "../support/showcase.rs"]
#[allow(dead_code, reason = "the shooter uses its screenshot part only")]
mod showcase;

use bevy::prelude::*;
use bevy_manifold::prelude::*;
use bevy_manifold::render::offscreen;
use game::{Difficulty, Game, GameConfig, GamePlugin};
use glam::DVec3;
use input::{InputSource, Script, ScriptEntry, TickInput};
use std::path::PathBuf;
use std::time::Duration;
use view::{ViewPlugin, ViewSettings};

fn main() -> AppExit {
    match run() {
        Ok(exit) => exit,
        Err(e) => {
            eprintln!("error: {e}");
            AppExit::error()
        }
    }
}

fn run() -> Result<AppExit, String> {
    let args = <args::Args as clap::Parser>::parse();
    let script = args.play.as_deref().map(Script::read).transpose()?;
    let mut config = script.as_ref().map_or_else(GameConfig::default, Script::config);
    if script.is_none() {
        config.space.clone_from(&args.space);
        if catalog::by_name(&config.space).is_none() && product::product_space(&config.space).is_none() {
            return Err(format!(
                "--space: no catalog space {:?} (one of {}), nor a product space ({})",
                config.space,
                catalog::NAMES.join(", "),
                bevy_manifold::space::product::ProductSpace::NAMES.join(", ")
            ));
        }
        if let Some(d) = &args.difficulty {
            config.difficulty =
                Difficulty::by_name(d).ok_or(format!("--difficulty: easy, normal or hard, not {d:?}"))?;
        }
        if let Some(s) = args.seed {
            config.seed = s;
        }
    }
    let levels = args.levels;
    let bot = args.bot;
    let size = match &args.size {
        Some(s) => showcase::parse_size(s).ok_or(format!("--size: WIDTHxHEIGHT, both at least 1, not {s:?}"))?,
        None => (640, 360),
    };
    if product::product_space(&config.space).is_some() {
        return run_product(config, &args, script, size);
    }
    if args.headless {
        if bot {
            let ticks = args.ticks.unwrap_or(36_000);
            return Ok(bot_headless(config, ticks.min(input::MAX_TICKS)));
        }
        let script = script.ok_or("--headless plays a script (--play FILE.json) or the bot (--bot)")?;
        return Ok(play_headless(config, script));
    }
    if let Some(path) = args.screenshot {
        return Ok(screenshot(config, levels, path, size));
    }
    if !args.xr
        && let Some(why) = bevy_manifold::render::offscreen::no_display()
    {
        eprintln!(
            "{why}: rendering the game's opening view to shooter.png instead of opening a window (--headless --bot plays without one)"
        );
        return Ok(screenshot(config, levels, PathBuf::from("shooter.png"), size));
    }
    let record = args.record.clone();
    let menu = script.is_none();
    let mut app = App::new();
    let plugins = DefaultPlugins.set(WindowPlugin {
        primary_window: Some(Window {
            title: "bevy_manifold shooter: your shots come back around".into(),
            resolution: (960, 540).into(),
            ..default()
        }),
        ..default()
    });
    let xr = args.xr;
    let world_scale = match args.world_scale {
        Some(v) if v.is_finite() && v > 0.0 && v <= 1e6 => v,
        Some(v) => return Err(format!("--world-scale: a positive number of metres per unit, not {v}")),
        None => 4.0,
    };
    #[cfg(feature = "xr")]
    if xr {
        // With --frames N: both eyes read back at frame N - 30.
        let capture = args
            .xr_capture
            .clone()
            .map(|d| (args.frames.unwrap_or(0).saturating_sub(30).max(1), d));
        app.add_plugins(bevy_mod_openxr::add_xr_plugins(plugins))
            .add_plugins(xr::ShooterXrPlugin { world_scale, capture });
    } else {
        app.add_plugins(plugins);
    }
    #[cfg(not(feature = "xr"))]
    {
        if xr {
            eprintln!("warning: --xr: built without the `xr` feature (add --features xr); playing on the desktop");
        }
        let _ = world_scale;
        app.add_plugins(plugins);
    }
    app.add_plugins((
        ManifoldPlugins::in_schedule(FixedPostUpdate),
        GamePlugin { config },
        ViewPlugin(ViewSettings {
            levels,
            target: None,
            menu,
        }),
    ))
    .insert_resource(InputSource { script, ..default() });
    // Sound, heard through the faces (Bevy's audio is in the window's
    // DefaultPlugins).
    #[cfg(feature = "audio")]
    app.add_plugins(sound::SoundPlugin);
    if bot {
        with_bot(&mut app);
    }
    if let Some(n) = args.frames {
        exit_after(&mut app, n);
    }
    if let Some(path) = record {
        record_on_exit(&mut app, path, |g: &Game| g.tick);
    }
    Ok(app.run())
}

/// Plays a script with no window, as fast as it goes, and prints what
/// happened.
fn play_headless(config: GameConfig, script: Script) -> AppExit {
    let ticks = script.ticks;
    let mut app = input::headless_app(config, Some(script), Duration::from_secs_f64(1.0 / game::TICK_HZ));
    while app.world().resource::<Game>().tick < ticks && app.world().resource::<Game>().phase == game::Phase::Playing {
        app.update();
    }
    let game = app.world().resource::<Game>();
    for (tick, e) in &game.log {
        println!("{tick:>6} {e:?}");
    }
    println!(
        "score {} level {} health {:.0} after {} ticks ({} events)",
        game.score,
        game.level,
        game.health,
        game.tick,
        game.log.len()
    );
    AppExit::Success
}

/// Lets the autopilot play.
fn with_bot(app: &mut App) {
    app.insert_resource(bot::Autopilot).add_systems(
        FixedUpdate,
        bot::autopilot.before(game::control_player).run_if(game::playing),
    );
}

/// The bot plays `ticks` ticks with no window, starting again after each
/// game over, and prints how each level went: the play-test.
fn bot_headless(config: GameConfig, ticks: u64) -> AppExit {
    let mut app = input::headless_app(config, None, Duration::from_secs_f64(1.0 / game::TICK_HZ));
    with_bot(&mut app);
    let mut played = 0;
    let mut games = 0;
    let mut best = 0;
    while played < ticks {
        app.update();
        let game = app.world().resource::<Game>();
        if game.phase == game::Phase::Over || played + game.tick >= ticks {
            played += game.tick;
            games += 1;
            best = best.max(game.score);
            report(game);
            // The next game: the next seed.
            app.world_mut().resource_mut::<GameConfig>().seed += 1;
            app.world_mut().run_system_cached(game::start_game).ok();
            app.update();
        }
    }
    println!(
        "{games} games in {played} ticks ({:.1} min), best score {best}",
        played as f64 / game::TICK_HZ / 60.0
    );
    AppExit::Success
}

/// One game's levels: how long each took and what happened in it.
fn report(game: &Game) {
    use game::GameEvent as E;
    let mut level_start = 0;
    let mut counts = [0u32; 6];
    let line = |level: u32, from: u64, to: u64, c: &[u32; 6]| {
        println!(
            "  level {level}: {:>5.1} s, {} shots, {} targets, {} enemies hit; hit by own shots {}, enemy shots {}, rammed {}",
            (to - from) as f64 / game::TICK_HZ,
            c[0],
            c[1],
            c[2],
            c[3],
            c[4],
            c[5]
        );
    };
    let mut level = 1;
    for (tick, e) in &game.log {
        match e {
            E::Level(l) if *l > 1 => {
                line(level, level_start, *tick, &counts);
                counts = [0; 6];
                level = *l;
                level_start = *tick;
            }
            E::Fired => counts[0] += 1,
            E::TargetHit { .. } => counts[1] += 1,
            E::EnemyHit { .. } => counts[2] += 1,
            E::PlayerHit { own: true, .. } => counts[3] += 1,
            E::PlayerHit { own: false, .. } => counts[4] += 1,
            E::Rammed => counts[5] += 1,
            _ => {}
        }
    }
    line(level, level_start, game.tick, &counts);
    println!(
        "game: score {} at level {}, health {:.0}, {:.1} s{}",
        game.score,
        game.level,
        game.health,
        game.tick as f64 / game::TICK_HZ,
        if game.phase == game::Phase::Over {
            ", game over"
        } else {
            ""
        }
    );
}

/// The game in progress for the screenshot: fly a little, turn, and fire
/// a stream of shots (2.5 s of play).
fn demo_script(config: &GameConfig) -> Script {
    let at = |at, thrust: DVec3, turn: DVec3, fire| ScriptEntry {
        at,
        input: TickInput { thrust, turn, fire },
    };
    Script {
        space: config.space.clone(),
        seed: config.seed,
        difficulty: config.difficulty,
        inputs: vec![
            at(0, DVec3::new(0.0, 0.0, -0.5), DVec3::new(0.0, 0.25, 0.0), false),
            at(40, DVec3::ZERO, DVec3::new(0.05, -0.3, 0.0), true),
            at(130, DVec3::ZERO, DVec3::ZERO, false),
        ],
        ticks: 150,
    }
}

/// Renders a frame of a game in progress offscreen and writes it: the demo
/// script is played (150 ticks in one update), then the clock stops while
/// the shaders compile, so the picture is always the same moment.
fn screenshot(config: GameConfig, levels: u32, path: PathBuf, (w, h): (u32, u32)) -> AppExit {
    let script = demo_script(&config);
    let ticks = script.ticks;
    let mut app = App::new();
    app.add_plugins(offscreen::plugins());
    let mut settings = ViewSettings {
        levels,
        target: None,
        menu: false,
    };
    app.add_plugins((
        ManifoldPlugins::in_schedule(FixedPostUpdate),
        GamePlugin { config },
        ViewPlugin(settings.clone()),
    ));
    app.finish();
    app.cleanup();
    settings.target = Some(showcase::screenshot_mode(&mut app, path, (w, h)));
    app.insert_resource(settings);
    app.insert_resource(InputSource {
        script: Some(script),
        ..default()
    });
    showcase::play_ticks(&mut app, game::TICK_HZ, 1);
    let played = app.world().resource::<Game>().tick;
    showcase::play_ticks(&mut app, game::TICK_HZ, (ticks - played) as u32);
    showcase::run(app)
}

/// The game in a product space ([`product`]): headless (a script or the
/// bot), a screenshot, or in a window.
fn run_product(
    config: GameConfig,
    args: &args::Args,
    script: Option<Script>,
    size: (u32, u32),
) -> Result<AppExit, String> {
    let tick = Duration::from_secs_f64(1.0 / game::TICK_HZ);
    if args.xr {
        eprintln!("warning: --xr: the product spaces' shooter plays on the desktop");
    }
    if args.headless {
        let (ticks, script) = if args.bot {
            (args.ticks.unwrap_or(36_000).min(input::MAX_TICKS), None)
        } else {
            let script = script.ok_or("--headless plays a script (--play FILE.json) or the bot (--bot)")?;
            (script.ticks, Some(script))
        };
        let mut app = product::product_headless_app(config, script, tick);
        if args.bot {
            product::with_product_bot(&mut app);
        }
        while app.world().resource::<product::ProductGame>().tick < ticks {
            app.update();
        }
        let game = app.world().resource::<product::ProductGame>();
        for (tick, e) in &game.log {
            println!("{tick:>6} {e:?}");
        }
        println!(
            "score {} hit by own shots {} after {} ticks ({} events)",
            game.score,
            game.hits_taken,
            game.tick,
            game.log.len()
        );
        return Ok(AppExit::Success);
    }
    let screenshot = args.screenshot.clone().or_else(|| {
        let why = bevy_manifold::render::offscreen::no_display()?;
        eprintln!("{why}: rendering the game's opening view to shooter.png instead of opening a window (--headless --bot plays without one)");
        Some(PathBuf::from("shooter.png"))
    });
    let mut app = App::new();
    let script = match screenshot {
        Some(_) => Some(demo_script(&config)),
        None => script,
    };
    let ticks = script.as_ref().map(|s| s.ticks);
    match &screenshot {
        Some(_) => {
            app.add_plugins(offscreen::plugins());
        }
        None => {
            app.add_plugins(DefaultPlugins.set(WindowPlugin {
                primary_window: Some(Window {
                    title: "bevy_manifold shooter: your shots come back around".into(),
                    resolution: (960, 540).into(),
                    ..default()
                }),
                ..default()
            }));
        }
    }
    let name = config.space.clone();
    app.add_plugins((
        ManifoldPlugins::in_schedule(FixedPostUpdate),
        product::ProductGamePlugin { config: config.clone() },
    ))
    .insert_resource(InputSource { script, ..default() })
    .add_observer(
        |add: On<Add, bevy_manifold::product::ProductCamera>, mut commands: Commands| {
            commands.entity(add.entity).insert(Camera3d::default());
        },
    )
    .add_systems(Startup, hud::spawn_hud)
    .add_systems(
        Update,
        move |game: Option<Res<product::ProductGame>>, mut hud: Query<&mut Text, With<hud::HudText>>| {
            if let (Some(game), Ok(mut text)) = (game, hud.single_mut()) {
                text.0 = format!(
                    "{name}   score {}   hit by own shots {}   WASD Space Shift fly | arrows turn | Q E roll | click, F or Ctrl fire",
                    game.score, game.hits_taken
                );
            }
        },
    );
    if args.bot {
        product::with_product_bot(&mut app);
    } else if screenshot.is_none() {
        app.add_systems(Update, view::read_devices);
    }
    if let Some(path) = screenshot {
        app.finish();
        app.cleanup();
        let target = showcase::screenshot_mode(&mut app, path, size);
        app.add_observer(
            move |add: On<Add, bevy_manifold::product::ProductCamera>, mut commands: Commands| {
                commands
                    .entity(add.entity)
                    .insert(bevy::camera::RenderTarget::Image(target.clone().into()));
            },
        );
        showcase::play_ticks(&mut app, game::TICK_HZ, 1);
        let played = app.world().resource::<product::ProductGame>().tick;
        showcase::play_ticks(
            &mut app,
            game::TICK_HZ,
            (ticks.unwrap_or(0).saturating_sub(played)) as u32,
        );
        return Ok(showcase::run(app));
    }
    if let Some(n) = args.frames {
        exit_after(&mut app, n);
    }
    if let Some(path) = args.record.clone() {
        record_on_exit(&mut app, path, |g: &product::ProductGame| g.tick);
    }
    Ok(app.run())
}

/// Exits after `n` frames: in `PostUpdate`, so the recording (in `Last`)
/// sees the exit.
fn exit_after(app: &mut App, n: u32) {
    app.add_systems(
        PostUpdate,
        move |mut frames: Local<u32>, mut exit: MessageWriter<AppExit>| {
            *frames += 1;
            if *frames >= n {
                exit.write(AppExit::Success);
            }
        },
    );
}

/// Writes the game played as a script to `path` on exit, its length the
/// game resource `G`'s ticks (`ticks`).
fn record_on_exit<G: Resource>(app: &mut App, path: PathBuf, ticks: fn(&G) -> u64) {
    app.add_systems(
        Last,
        move |exits: MessageReader<AppExit>,
              source: Res<InputSource>,
              config: Res<GameConfig>,
              game: Option<Res<G>>| {
            if !exits.is_empty() {
                let ticks = game.map_or(0, |g| ticks(&g));
                match std::fs::write(&path, source.recording(&config, ticks).to_json()) {
                    Ok(()) => println!("recorded {ticks} ticks to {}", path.display()),
                    Err(e) => eprintln!("error: --record {}: {e}", path.display()),
                }
            }
        },
    );
}
