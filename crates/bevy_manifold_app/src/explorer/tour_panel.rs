//! The panel's tour section (the window's half of [`super::tour`]):
//! open a shipped tour or a file, play, pause, scrub, speed; start a tour,
//! add the current view as a keyframe, edit times and captions, delete,
//! save; and the caption drawn over the view.

use super::settings::ExplorerSettings;
use super::tour::{ExplorerTour, shipped_tours};
use super::view::{ExplorerStatus, ExplorerWorld};
use bevy_egui::egui::{self, Color32, Ui};
use glam::DMat4;

/// The camera's pose as the recorder takes it: its placement in its copy
/// and the face word naming that copy.
pub type Pose<'a> = (DMat4, &'a [usize]);

/// The field of view new tours get (the explorer's camera's).
const FOV_Y_DEGREES: f64 = 60.0;

/// The tour section of the panel.
pub fn section(
    ui: &mut Ui,
    tour: &mut ExplorerTour,
    s: &mut ExplorerSettings,
    status: &mut ExplorerStatus,
    world: &ExplorerWorld,
    pose: Option<Pose>,
) {
    let report = |status: &mut ExplorerStatus, r: Result<String, String>| match r {
        Ok(m) => status.say(m, false),
        Err(e) => status.say(e, true),
    };
    egui::ComboBox::from_id_salt("shipped tours")
        .selected_text("a shipped tour…")
        .show_ui(ui, |ui| {
            for path in shipped_tours() {
                let name = path
                    .file_name()
                    .map_or(String::new(), |n| n.to_string_lossy().into_owned());
                if ui
                    .selectable_label(false, name.trim_end_matches(".tour.json"))
                    .clicked()
                {
                    let r = tour.open(&path, s).map(|()| format!("playing {}", path.display()));
                    report(status, r);
                }
            }
        });
    ui.horizontal(|ui| {
        ui.add(
            egui::TextEdit::singleline(&mut tour.path)
                .desired_width(150.0)
                .hint_text("tour file"),
        );
        if ui.button("Open").clicked() {
            let path = tour.path.trim().to_string();
            let r = tour.open(&path, s).map(|()| format!("playing {path}"));
            report(status, r);
        }
        if ui.add_enabled(tour.desc.is_some(), egui::Button::new("Save")).clicked() {
            let r = tour.save().map(|()| format!("tour saved to {}", tour.path.trim()));
            report(status, r);
        }
    });
    if tour.tour.is_some() {
        playback(ui, tour);
    }
    ui.separator();
    let shown = world.applied.space == s.space;
    ui.horizontal(|ui| {
        if ui.button("New tour here").clicked() {
            tour.start_new(s, FOV_Y_DEGREES);
            status.say(
                format!("a new tour in {}: add views as keyframes", world.space.name()),
                false,
            );
        }
        ui.add(
            egui::DragValue::new(&mut tour.gap)
                .range(0.1..=600.0)
                .suffix(" s apart"),
        );
    });
    let recording = tour.desc.is_some() && shown && tour.space == s.space;
    if ui
        .add_enabled(
            recording && pose.is_some(),
            egui::Button::new("Add the current view as a keyframe"),
        )
        .clicked()
        && let Some((placement, word)) = pose
    {
        let time = if tour.desc.as_ref().is_some_and(|d| d.keyframes.is_empty()) {
            0.0
        } else {
            tour.duration() + tour.gap
        };
        let r = tour
            .record(&world.space, time, word, placement)
            .map(|i| format!("keyframe {i} at {time:.2} s (cell word of {} faces)", word.len()));
        report(status, r);
    }
    if recording {
        let r = entries(ui, tour).then(|| tour.rebuild(&world.space).map(|()| "tour updated".to_string()));
        if let Some(r) = r {
            report(status, r);
        }
    }
}

/// Play, pause, the timeline, the speed.
fn playback(ui: &mut Ui, tour: &mut ExplorerTour) {
    let duration = tour.duration();
    ui.horizontal(|ui| {
        if ui.button(if tour.playing { "Pause" } else { "Play" }).clicked() {
            tour.toggle_play();
        }
        ui.checkbox(&mut tour.follow, "camera on the tour");
        ui.checkbox(&mut tour.looping, "loop");
    });
    let mut time = tour.time;
    if ui
        .add(egui::Slider::new(&mut time, 0.0..=duration).text("s").fixed_decimals(1))
        .changed()
    {
        tour.seek(time);
        tour.follow = true;
    }
    ui.add(egui::Slider::new(&mut tour.speed, -4.0..=4.0).text("speed"));
    ui.checkbox(&mut tour.apply_settings, "follow the tour's settings");
}

/// The tour's entries, times and captions editable: true when one changed.
fn entries(ui: &mut Ui, tour: &mut ExplorerTour) -> bool {
    let mut changed = false;
    let mut go = None;
    let mut delete = None;
    let Some(desc) = tour.desc.as_mut() else {
        return false;
    };
    egui::ScrollArea::vertical()
        .id_salt("tour entries")
        .max_height(180.0)
        .show(ui, |ui| {
            egui::Grid::new("tour entries grid").striped(true).show(ui, |ui| {
                for (i, e) in desc.keyframes.iter_mut().enumerate() {
                    match e.time.as_mut() {
                        Some(t) => {
                            changed |= ui.add(egui::DragValue::new(t).speed(0.1).suffix(" s")).changed();
                            if ui.small_button("go").clicked() {
                                go = Some(*t);
                            }
                        }
                        None => {
                            let kind = if e.fly.is_some() {
                                "fly"
                            } else if e.turn.is_some() {
                                "turn"
                            } else {
                                "loop"
                            };
                            ui.label(kind);
                            ui.label("");
                        }
                    }
                    let mut caption = e.caption.clone().unwrap_or_default();
                    if ui
                        .add(
                            egui::TextEdit::singleline(&mut caption)
                                .desired_width(110.0)
                                .hint_text("caption"),
                        )
                        .changed()
                    {
                        e.caption = (!caption.is_empty()).then_some(caption);
                        changed = true;
                    }
                    if ui.small_button("✕").clicked() {
                        delete = Some(i);
                    }
                    ui.end_row();
                }
            });
        });
    if let Some(i) = delete {
        desc.keyframes.remove(i);
        changed = true;
    }
    if let Some(t) = go {
        tour.seek(t);
        tour.follow = true;
    }
    changed
}

/// The caption at the tour's time, over the bottom of the view.
pub fn caption_overlay(ui: &Ui, rect: egui::Rect, tour: &ExplorerTour) {
    let Some(caption) = tour.caption().filter(|c| !c.is_empty()) else {
        return;
    };
    let painter = ui.painter_at(rect);
    let galley = painter.layout(
        caption.to_owned(),
        egui::FontId::proportional(18.0),
        Color32::WHITE,
        rect.width() * 0.8,
    );
    let size = galley.size();
    let at = egui::pos2(rect.center().x - size.x / 2.0, rect.bottom() - size.y - 24.0);
    painter.rect_filled(
        egui::Rect::from_min_size(at, size).expand(8.0),
        4.0,
        Color32::from_black_alpha(170),
    );
    painter.galley(at, galley, Color32::WHITE);
}
