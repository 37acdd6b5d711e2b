//! The games' heads-up display (the shooter's and the billiards', each
//! takes it with `#[path]`): a line of text at the bottom left, a
//! centred message, and a crosshair, as UI nodes that each game fills in
//! its own systems and points at its player's camera.

use bevy::prelude::*;

/// The line at the bottom left: score, strokes, the keys.
#[derive(Component)]
pub struct HudText;

/// The centred message: menus, pauses, the end.
#[derive(Component)]
pub struct CenterText;

/// The crosshair in the middle of the view.
#[derive(Component)]
pub struct Crosshair;

/// Spawns the three, empty but for the crosshair.
pub fn spawn_hud(mut commands: Commands) {
    commands.spawn((
        Text::new(""),
        HudText,
        TextFont::from_font_size(14.0),
        Node {
            position_type: PositionType::Absolute,
            bottom: px(8.0),
            left: px(10.0),
            ..default()
        },
    ));
    commands.spawn((
        Text::new(""),
        CenterText,
        TextFont::from_font_size(20.0),
        TextLayout::justify(Justify::Center),
        Node {
            position_type: PositionType::Absolute,
            top: percent(30.0),
            width: percent(100.0),
            ..default()
        },
    ));
    commands.spawn((
        Text::new("+"),
        Crosshair,
        TextFont::from_font_size(28.0),
        TextColor(Color::srgba(1.0, 1.0, 1.0, 0.8)),
        TextLayout::justify(Justify::Center),
        Node {
            position_type: PositionType::Absolute,
            top: percent(50.0),
            margin: UiRect::top(px(-17.0)),
            width: percent(100.0),
            ..default()
        },
    ));
}
