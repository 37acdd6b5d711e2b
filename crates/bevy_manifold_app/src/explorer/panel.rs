//! The explorer's window: an egui side panel with every
//! setting, the frame times, the adapter and the camera's cell, and the
//! traced view filling the rest of the window at the render scale.

use super::progress::SampleClock;
use super::settings::{CellMode, ExplorerSettings, MAX_LEVEL, MIN_SCALE, TARGET_FPS};
use super::tour::ExplorerTour;
use super::tour_panel;
use super::view::{ExplorerCamera, ExplorerStatus, ExplorerView, ExplorerWorld, describe_cell};
use super::{ExplorerPlugin, KEYS};
use bevy::prelude::*;
use bevy::render::renderer::RenderAdapterInfo;
use bevy_egui::egui::{self, Color32, LayerId, Ui, UiBuilder};
use bevy_egui::{
    EguiContexts, EguiGlobalSettings, EguiPlugin, EguiPrimaryContextPass, EguiTextureHandle, PrimaryEguiContext,
};
use bevy_manifold::camera::{AccumulationProgress, AdaptiveRenderScale, ManifoldAccumulation, ManifoldRenderScale};
use bevy_manifold::geometry::Geometry;
use bevy_manifold::placement::{DomainCell, Placement};
use bevy_manifold::product::ProductCamera;
use bevy_manifold::space::product::ProductSpace;
use bevy_manifold::space::product_cells::ProductElement;
use bevy_manifold::space::{catalog, library};
use bevy_manifold::tour::FaceWord;
use bevy_manifold::trace::SuzanneMode;
use bevy_manifold::trace::{MAX_PATH_DEPTH, MAX_REFLECTIONS};

/// The panel and the view in the primary window. Needs
/// [`ExplorerPlugin`] (added when missing) and a window.
#[derive(Clone, Copy, Debug, Default)]
pub struct ExplorerPanelPlugin;

impl Plugin for ExplorerPanelPlugin {
    fn build(&self, app: &mut App) {
        if !app.is_plugin_added::<ExplorerPlugin>() {
            app.add_plugins(ExplorerPlugin::default());
        }
        // The window's own camera carries egui, not the first camera
        // spawned (the manifold camera, which renders offscreen); keys
        // typed into the panel (a file path) do not fly the camera.
        app.insert_resource(EguiGlobalSettings {
            auto_create_primary_context: false,
            enable_absorb_bevy_input_system: true,
            ..default()
        })
        .add_plugins(EguiPlugin::default())
        .init_resource::<PanelState>()
        .add_systems(Startup, setup_window_camera)
        .add_systems(EguiPrimaryContextPass, panel);
    }
}

/// The panel's own state: the space-file path being typed and the view's
/// texture in egui.
#[derive(Resource, Default)]
struct PanelState {
    path: String,
    texture: Option<(AssetId<Image>, egui::TextureId)>,
    clock: SampleClock,
}

/// The window's own camera: it draws egui (and clears); the manifold
/// camera renders offscreen into the view image the panel shows.
fn setup_window_camera(mut commands: Commands) {
    commands.spawn((Camera2d, PrimaryEguiContext));
}

#[expect(clippy::too_many_arguments, reason = "a system's parameters")]
fn panel(
    mut contexts: EguiContexts,
    mut settings: ResMut<ExplorerSettings>,
    mut view: ResMut<ExplorerView>,
    mut state: ResMut<PanelState>,
    mut status: ResMut<ExplorerStatus>,
    world: Res<ExplorerWorld>,
    cameras: Query<(&DomainCell, &Placement, &FaceWord), With<ExplorerCamera>>,
    products: Query<&ProductCamera, With<ExplorerCamera>>,
    scales: Query<(Option<&ManifoldRenderScale>, Option<&AdaptiveRenderScale>), With<ExplorerCamera>>,
    adapter: Option<Res<RenderAdapterInfo>>,
    mut tour: ResMut<ExplorerTour>,
    (progress, time): (Query<&AccumulationProgress, With<ExplorerCamera>>, Res<Time>),
) -> Result {
    // The view's texture in egui follows the image (replaced on resize).
    let texture = match state.texture {
        Some((id, tex)) if id == view.image.id() => tex,
        old => {
            if let Some((id, _)) = old {
                contexts.remove_image(id);
            }
            let tex = contexts.add_image(EguiTextureHandle::Strong(view.image.clone()));
            state.texture = Some((view.image.id(), tex));
            tex
        }
    };
    let ctx = contexts.ctx_mut()?;
    let mut root = Ui::new(
        ctx.clone(),
        "explorer".into(),
        UiBuilder::new()
            .layer_id(LayerId::background())
            .max_rect(ctx.viewport_rect()),
    );
    // The still view's samples, and the time they took.
    let samples = settings
        .accumulation()
        .zip(progress.get(world.camera).ok())
        .map(|(wanted, p)| {
            let spent = state.clock.tick(p.samples(), wanted.samples, time.delta());
            SampleClock::line(p.samples(), wanted.samples, spent)
        });
    // Edit a copy, so the settings change (and are saved, and applied)
    // only when a widget changed something.
    let mut s = settings.clone();
    if s.panel {
        egui::Panel::left("settings")
            .resizable(true)
            .default_size(300.0)
            .show(&mut root, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| {
                    let camera = cameras.get(world.camera).ok();
                    let cell = camera.map(|c| c.0);
                    let product_cell = products.get(world.camera).ok().map(|c| c.view.cell);
                    let scale = scales.get(world.camera).ok();
                    egui::CollapsingHeader::new("Tour").default_open(true).show(ui, |ui| {
                        if world.product.is_some() {
                            ui.label("Tours of the product spaces play from the command line (product --tour).");
                        } else {
                            let pose = camera.map(|(_, p, w)| (p.isometry, w.0.as_slice()));
                            tour_panel::section(ui, &mut tour, &mut s, &mut status, &world, pose);
                        }
                    });
                    contents(
                        ui,
                        &mut s,
                        &mut state.path,
                        &mut status,
                        &world,
                        (cell, product_cell),
                        adapter.as_deref(),
                        &view,
                        (scale, samples.as_deref()),
                    );
                });
            });
    }
    // The rest of the window is the view.
    let rect = root.available_rect_before_wrap();
    // egui's points are logical pixels: times pixels-per-point they are
    // the window's physical pixels.
    let px = rect.size() * ctx.pixels_per_point() * s.render_scale;
    view.wanted = UVec2::new(px.x.round().max(1.0) as u32, px.y.round().max(1.0) as u32);
    root.put(
        rect,
        egui::Image::new(egui::load::SizedTexture::new(texture, rect.size())).sense(egui::Sense::hover()),
    );
    tour_panel::caption_overlay(&root, rect, &tour);
    if s != *settings {
        *settings = s;
    }
    Ok(())
}

/// The camera's render scale components, as the panel reads them.
type ScaleOf<'a> = Option<(Option<&'a ManifoldRenderScale>, Option<&'a AdaptiveRenderScale>)>;

/// What the panel says of the pixels traced: the image's size, and under
/// a held frame rate the scale chosen and the smoothed frame time.
fn scale_line(size: UVec2, scale: Option<(Option<&ManifoldRenderScale>, Option<&AdaptiveRenderScale>)>) -> String {
    let (chosen, adaptive) = scale.unwrap_or((None, None));
    let chosen = chosen.copied().unwrap_or_default();
    let traced = chosen.traced_size(size);
    match adaptive {
        Some(a) => format!(
            "scale chosen {:.2}: {} x {} px traced of {} x {}{}",
            chosen.get(),
            traced.x,
            traced.y,
            size.x,
            size.y,
            a.smoothed_ms()
                .map(|ms| format!(", frames {ms:.1} ms (target {:.1})", a.target_frame_ms))
                .unwrap_or_default()
        ),
        None => format!("{} x {} px traced", traced.x, traced.y),
    }
}

#[expect(clippy::too_many_arguments, reason = "a system's parameters")]
fn contents(
    ui: &mut Ui,
    s: &mut ExplorerSettings,
    path: &mut String,
    status: &mut ExplorerStatus,
    world: &ExplorerWorld,
    (cell, product_cell): (Option<&DomainCell>, Option<Option<ProductElement>>),
    adapter: Option<&RenderAdapterInfo>,
    view: &ExplorerView,
    (scale, samples): (ScaleOf, Option<&str>),
) {
    // What only the spaces of E3, H3 and S3 take (the product spaces'
    // camera has its own tracer, without these).
    let manifold = world.product.is_none();
    ui.heading("bevy_manifold");
    ui.label("Space");
    egui::ComboBox::from_id_salt("space")
        .selected_text(world.name())
        .show_ui(ui, |ui| {
            ui.label("The paper's spaces");
            for name in catalog::NAMES {
                ui.selectable_value(&mut s.space, (*name).to_string(), name.to_string());
            }
            // The library, by geometry: built from generators on selection.
            for (geometry, title) in [
                (Geometry::Spherical, "Spherical (from generators)"),
                (Geometry::Euclidean, "Flat (from generators)"),
                (Geometry::Hyperbolic, "Hyperbolic (from generators)"),
            ] {
                let names: Vec<String> = library::names()
                    .into_iter()
                    .filter(|n| library::by_name(n).is_some_and(|g| g.geometry == geometry))
                    .collect();
                if names.is_empty() {
                    continue;
                }
                ui.separator();
                ui.label(title);
                for name in names {
                    ui.selectable_value(&mut s.space, name.clone(), name);
                }
            }
            ui.separator();
            ui.label("Product geometries (H2xR, S2xR)");
            for name in ProductSpace::NAMES {
                ui.selectable_value(&mut s.space, name.to_string(), name);
            }
        });
    match &world.product {
        Some(p) => ui.label(format!(
            "{:?} · {} faces · volume {:.4} · circle {}",
            p.geometry,
            p.face_count(),
            p.volume(),
            p.height
        )),
        None => {
            let space = &world.space;
            ui.label(format!(
                "{} · {} faces · volume {:.4} · group {}",
                space.geometry(),
                space.faces().len(),
                space.volume(),
                space
                    .group_order()
                    .map_or("infinite".into(), |n| format!("of order {n}"))
            ))
        }
    };
    ui.collapsing("Open a space file (.json, .gen)…", |ui| {
        ui.horizontal(|ui| {
            ui.text_edit_singleline(path);
            if ui.button("Open").clicked() {
                match catalog::resolve(path.trim()) {
                    Ok(_) => s.space = path.trim().to_string(),
                    Err(e) => status.say(e, true),
                }
            }
        });
    });
    ui.separator();
    ui.add(egui::Slider::new(&mut s.levels, 1..=MAX_LEVEL).text("max level"));
    ui.add(
        egui::Slider::new(&mut s.max_distance, 0.5..=200.0)
            .logarithmic(true)
            .text("max distance"),
    );
    ui.horizontal(|ui| {
        ui.checkbox(&mut s.fog, "fog");
        ui.add_enabled(s.fog, egui::Slider::new(&mut s.fog_density, 0.0..=3.0).text("density"));
        let mut c = s.fog_color.map(|v| (v * 255.0).round() as u8);
        ui.add_enabled_ui(s.fog && manifold, |ui| {
            if ui.color_edit_button_srgb(&mut c).changed() {
                s.fog_color = c.map(|v| f32::from(v) / 255.0);
            }
        });
    });
    ui.checkbox(&mut s.cells, "per-cell shading");
    ui.add_enabled_ui(s.cells, |ui| {
        for m in CellMode::ALL {
            ui.radio_value(&mut s.cell_mode, m, m.label());
        }
        if s.cell_mode == CellMode::Pattern {
            ui.add(egui::Slider::new(&mut s.pattern_on, 0.0..=1.0).text("cells on"));
        }
        if s.cell_mode == CellMode::Highlight {
            ui.horizontal(|ui| {
                if ui.button("Pin the camera's cell").clicked()
                    && let Some(c) = cell
                {
                    s.highlight = c.id.0;
                }
                ui.label(format!("{:x}", s.highlight));
            });
        }
    });
    ui.add_enabled(
        !manifold,
        egui::Checkbox::new(&mut s.lights, "point lights, with shadows (product spaces)"),
    );
    // The rest of the scene and the tracer's options: E3, H3 and S3.
    ui.add_enabled_ui(manifold, |ui| manifold_options(ui, s));
    ui.separator();
    ui.add(egui::Slider::new(&mut s.render_scale, MIN_SCALE..=1.0).text("render scale"));
    ui.add_enabled_ui(manifold, |ui| tracer_options(ui, s, view, scale, samples));
    if let Some(ms) = status.mean_frame_ms() {
        ui.label(format!("frame {ms:.1} ms ({:.1} fps)", 1000.0 / ms.max(0.001)));
    }
    frame_plot(ui, status);
    if let Some(a) = adapter {
        ui.label(format!("adapter: {} ({:?})", a.name, a.backend));
    }
    ui.separator();
    if let Some(c) = cell {
        ui.label(format!("cell: {}", describe_cell(&world.space, c)));
    }
    if let Some(c) = product_cell {
        ui.label(match c {
            Some(e) => format!(
                "copy: {} circles up{}",
                e.steps(),
                if e.flips() { ", turned over" } else { "" }
            ),
            None => "copy: too far to name".into(),
        });
    }
    ui.label(format!(
        "last face crossed: {}",
        status.last_face.map_or("none".to_string(), |f| f.to_string())
    ));
    if let Some((m, error)) = &status.message {
        let color = if *error {
            Color32::from_rgb(255, 120, 100)
        } else {
            ui.visuals().text_color()
        };
        ui.colored_label(color, m);
    }
    ui.collapsing("Keys", |ui| {
        egui::Grid::new("keys").striped(true).show(ui, |ui| {
            for (k, what) in KEYS {
                ui.label(*k);
                ui.label(*what);
                ui.end_row();
            }
        });
    });
}

/// The cell rules and the paper's scene (E3, H3 and S3 only).
fn manifold_options(ui: &mut Ui, s: &mut ExplorerSettings) {
    ui.label("cell rules (from the exact cell ids)");
    ui.checkbox(&mut s.hidden, "on/off: objects in off cells hidden");
    ui.add_enabled_ui(s.hidden, |ui| {
        ui.add(egui::Slider::new(&mut s.hidden_on, 0.0..=1.0).text("cells on"));
        ui.add(egui::Slider::new(&mut s.hidden_seed, 0..=99).text("seed"));
    });
    ui.checkbox(&mut s.walls, "walls between cells (a maze)");
    ui.add_enabled_ui(s.walls, |ui| {
        ui.add(egui::Slider::new(&mut s.wall_density, 0.0..=1.0).text("faces walled"));
        ui.add(egui::Slider::new(&mut s.wall_seed, 0..=99).text("seed"));
    });
    ui.separator();
    ui.checkbox(&mut s.edges, "domain edges");
    ui.horizontal(|ui| {
        ui.label("Suzanne");
        ui.radio_value(&mut s.suzanne, SuzanneMode::Attached, "attached");
        ui.radio_value(&mut s.suzanne, SuzanneMode::Free, "free");
        ui.radio_value(&mut s.suzanne, SuzanneMode::Hidden, "hidden");
    });
    ui.checkbox(&mut s.hands, "hands");
    ui.checkbox(&mut s.vehicle, "ride the vehicle (W/S throttle, arrows steer)");
    // A mirror is seen with reflections on: ticking it turns one on.
    if ui
        .checkbox(&mut s.mirror, "mirror ball (the paper's Fig. 11)")
        .changed()
        && s.mirror
        && s.reflections == 0
    {
        s.reflections = 1;
    }
    ui.add(egui::Slider::new(&mut s.reflections, 0..=MAX_REFLECTIONS).text("reflections"));
}

/// Holding a frame rate, cone tracing, path tracing and refining a still
/// view (E3, H3 and S3 only).
fn tracer_options(ui: &mut Ui, s: &mut ExplorerSettings, view: &ExplorerView, scale: ScaleOf, samples: Option<&str>) {
    ui.checkbox(&mut s.hold_frame_rate, "hold a frame rate (trace fewer pixels)");
    let ms = 1000.0 / s.target_fps;
    ui.add_enabled_ui(s.hold_frame_rate, |ui| {
        ui.add(
            egui::Slider::new(&mut s.target_fps, TARGET_FPS)
                .logarithmic(true)
                .text(format!("fps target ({ms:.1} ms)")),
        );
    });
    ui.label(scale_line(view.size, scale));
    ui.checkbox(&mut s.smooth_detail, "smooth far detail (cone tracing)");
    ui.checkbox(&mut s.path_trace, "path traced (converges while still)");
    ui.add_enabled_ui(s.path_trace, |ui| {
        ui.add(egui::Slider::new(&mut s.path_depth, 1..=MAX_PATH_DEPTH).text("bounces a path"));
        ui.add(
            egui::Slider::new(&mut s.path_samples, 2..=ManifoldAccumulation::MAX_SAMPLES)
                .logarithmic(true)
                .text("path samples"),
        );
    });
    if let Some(line) = samples {
        ui.label(line);
    }
    ui.checkbox(&mut s.refine_still, "refine while still (anti-aliasing)");
    ui.add_enabled_ui(s.refine_still, |ui| {
        ui.add(
            egui::Slider::new(&mut s.still_samples, 2..=ManifoldAccumulation::MAX_SAMPLES)
                .logarithmic(true)
                .text("samples per pixel"),
        );
    });
}

/// The last seconds of frame times, as a line (0 at the bottom, the
/// slowest frame at the top).
fn frame_plot(ui: &mut Ui, status: &ExplorerStatus) {
    let (rect, _) = ui.allocate_exact_size(egui::vec2(ui.available_width(), 48.0), egui::Sense::hover());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 2.0, Color32::from_gray(24));
    let Some(&(last, _)) = status.frame_times.back() else {
        return;
    };
    let top = status.frame_times.iter().map(|f| f.1).fold(1.0f32, f32::max);
    let span = ExplorerStatus::HISTORY_SECS as f32;
    let points: Vec<egui::Pos2> = status
        .frame_times
        .iter()
        .map(|&(t, ms)| {
            let x = rect.right() - (last - t) as f32 / span * rect.width();
            egui::pos2(x, rect.bottom() - ms / top * rect.height())
        })
        .collect();
    painter.add(egui::Shape::line(
        points,
        egui::Stroke::new(1.0, Color32::from_rgb(120, 200, 255)),
    ));
    painter.text(
        rect.left_top() + egui::vec2(4.0, 2.0),
        egui::Align2::LEFT_TOP,
        format!("{top:.0} ms"),
        egui::FontId::monospace(10.0),
        Color32::GRAY,
    );
}
