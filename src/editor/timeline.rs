//! The timeline along the bottom: transport (play / pause, loop), the frame,
//! fps and range fields, and the track — a ruler with frame numbers, the
//! playhead to scrub, and the rest-shape keys as diamonds to select, drag to
//! retime, and right-click for their easing and in-between relaxation.
//!
//! Every frame is computed directly, so scrubbing shows the frame at once.

use eframe::egui::{self, Color32, Pos2, Rect, Sense, Stroke, Vec2};

use super::app::DrapeApp;
use super::param_edit::{key_frames, move_keys};
use crate::scene::{Ease, MAX_FPS, MAX_INBETWEEN_RELAX, MAX_TIMELINE_FRAME};

/// Height of the track (ruler and keys), points.
const TRACK_HEIGHT: f32 = 34.0;
/// Half the width of a key diamond, points.
const DIAMOND: f32 = 6.0;
/// Labels on the ruler at least this far apart, points.
const MIN_LABEL_GAP: f32 = 44.0;

/// The easing choices of a segment, in menu order.
pub(super) const EASES: [(&str, Ease); 9] = [
    ("Linear", Ease::Linear),
    ("Step", Ease::Step),
    ("Ease in", Ease::EaseIn),
    ("Ease out", Ease::EaseOut),
    ("Ease in-out", Ease::EaseInOut),
    ("Bézier", Ease::Bezier(0.42, 0.0, 0.58, 1.0)),
    ("Back", Ease::Back),
    ("Elastic", Ease::Elastic),
    ("Bounce", Ease::Bounce),
];

/// A ruler step (1, 2, 5, 10, 20, 50, …) that keeps labels `MIN_LABEL_GAP` apart.
pub fn ruler_step(points_per_frame: f32) -> i32 {
    let mut step = 1;
    for factor in [2, 5, 10].into_iter().cycle() {
        if step as f32 * points_per_frame >= MIN_LABEL_GAP || step > 1_000_000 {
            return step;
        }
        step = match factor {
            2 => step * 2,
            5 => step / 2 * 5,
            _ => step / 5 * 10,
        };
    }
    unreachable!("the cycle never ends")
}

/// The track's mapping between frames and x.
#[derive(Clone, Copy)]
struct Track {
    rect: Rect,
    start: f64,
    end: f64,
}

impl Track {
    fn x(&self, frame: f64) -> f32 {
        let span = (self.end - self.start).max(1.0);
        self.rect.left() + ((frame - self.start) / span) as f32 * self.rect.width()
    }

    fn frame(&self, x: f32) -> f64 {
        let span = (self.end - self.start).max(1.0);
        self.start + f64::from((x - self.rect.left()) / self.rect.width().max(1.0)) * span
    }
}

fn ease_name(ease: &Ease) -> &'static str {
    EASES.iter().find(|(_, e)| std::mem::discriminant(e) == std::mem::discriminant(ease)).map_or("?", |(n, _)| n)
}

impl DrapeApp {
    pub(super) fn timeline_panel(&mut self, ui: &mut egui::Ui) {
        self.transport(ui);
        ui.add_space(2.0);
        self.track(ui);
    }

    fn transport(&mut self, ui: &mut egui::Ui) {
        let timeline = self.doc.scene().timeline.clone();
        ui.horizontal(|ui| {
            let label = if self.playing() { "Pause" } else { "Play" };
            if ui.button(label).on_hover_text("Space").clicked() {
                self.toggle_play();
            }
            ui.toggle_value(&mut self.looping, "Loop").on_hover_text("Play the range over and over");
            ui.separator();
            let label = ui.label("Frame").id;
            let mut frame = self.frame().round() as i32;
            let r = ui.add(egui::DragValue::new(&mut frame).range(timeline.start..=timeline.end)).labelled_by(label);
            if r.changed() {
                self.set_frame(f64::from(frame));
            }
            ui.label(format!("{:.2} s", self.frame() / timeline.fps));
            ui.separator();
            let mut fps = timeline.fps;
            let label = ui.label("fps").id;
            let r = ui.add(egui::DragValue::new(&mut fps).range(1.0..=MAX_FPS).speed(0.1).max_decimals(3));
            let r = r.labelled_by(label);
            self.timeline_field(&r, "Frame rate", |s| s.timeline.fps = fps);
            let (mut start, mut end) = (timeline.start, timeline.end);
            let label = ui.label("Start").id;
            let r = ui.add(egui::DragValue::new(&mut start).range(-MAX_TIMELINE_FRAME..=end)).labelled_by(label);
            self.timeline_field(&r, "Timeline start", |s| s.timeline.start = start);
            let label = ui.label("End").id;
            let r = ui.add(egui::DragValue::new(&mut end).range(start..=MAX_TIMELINE_FRAME)).labelled_by(label);
            self.timeline_field(&r, "Timeline end", |s| s.timeline.end = end);
            ui.separator();
            if ui.button("Add key").on_hover_text("K: a rest-shape key here, from the current pose").clicked() {
                self.add_key_here();
            }
            let selected = self.selected_key.is_some();
            if ui.add_enabled(selected, egui::Button::new("Delete key")).clicked() {
                self.delete_selected_key();
            }
        });
    }

    fn timeline_field(
        &mut self,
        response: &egui::Response,
        label: &str,
        change: impl FnOnce(&mut crate::scene::Scene),
    ) {
        if response.drag_started() {
            self.doc.begin_gesture(label);
        }
        if response.changed() {
            self.apply(label, change);
            let frame = self.frame();
            self.set_frame(frame);
        }
    }

    fn track(&mut self, ui: &mut egui::Ui) {
        let timeline = self.doc.scene().timeline.clone();
        let width = ui.available_width();
        let (rect, response) = ui.allocate_exact_size(Vec2::new(width, TRACK_HEIGHT), Sense::click_and_drag());
        response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Slider, true, "Timeline"));
        let inner = rect.shrink2(Vec2::new(DIAMOND + 2.0, 0.0));
        let track = Track { rect: inner, start: f64::from(timeline.start), end: f64::from(timeline.end) };
        let painter = ui.painter_at(rect);
        let visuals = ui.visuals().clone();
        painter.rect_filled(rect, 3.0, visuals.extreme_bg_color);

        // Ruler.
        let points_per_frame = inner.width() / (timeline.end - timeline.start).max(1) as f32;
        let step = ruler_step(points_per_frame);
        let minor = if step >= 10 { step / 5 } else { 1 };
        let first = timeline.start.div_euclid(minor) * minor;
        let weak = visuals.weak_text_color();
        let mut at = first;
        while at <= timeline.end {
            if at >= timeline.start {
                let x = track.x(f64::from(at));
                let major = at.rem_euclid(step) == 0;
                let height = if major { 9.0 } else { 4.0 };
                painter.line_segment(
                    [Pos2::new(x, rect.top()), Pos2::new(x, rect.top() + height)],
                    Stroke::new(1.0, weak),
                );
                if major {
                    let font = egui::FontId::proportional(10.0);
                    painter.text(Pos2::new(x + 2.0, rect.top() + 8.0), egui::Align2::LEFT_TOP, at, font, weak);
                }
            }
            at += minor;
        }

        // Keys.
        let keys = self.doc.scene().keys.clone();
        let center_y = rect.bottom() - DIAMOND - 3.0;
        let pointer = response.interact_pointer_pos().or(response.hover_pos());
        let key_under = |pos: Pos2| {
            keys.iter().position(|k| {
                let x = track.x(f64::from(k.frame));
                (pos.x - x).abs() <= DIAMOND + 2.0 && (pos.y - center_y).abs() <= DIAMOND + 4.0
            })
        };
        for (index, key) in keys.iter().enumerate() {
            let x = track.x(f64::from(key.frame));
            if x < rect.left() - DIAMOND || x > rect.right() + DIAMOND {
                continue;
            }
            let selected = self.selected_key == Some(index);
            let fill = if selected { Color32::from_rgb(255, 200, 20) } else { Color32::from_rgb(230, 230, 230) };
            let c = Pos2::new(x, center_y);
            let diamond = vec![
                c + Vec2::new(0.0, -DIAMOND),
                c + Vec2::new(DIAMOND, 0.0),
                c + Vec2::new(0.0, DIAMOND),
                c + Vec2::new(-DIAMOND, 0.0),
            ];
            painter.add(egui::Shape::convex_polygon(diamond, fill, Stroke::new(1.0, Color32::BLACK)));
            if let Some(next) = keys.get(index + 1) {
                // The segment's easing, written between the keys when there is room.
                let next_x = track.x(f64::from(next.frame));
                if next_x - x > 70.0 {
                    let font = egui::FontId::proportional(10.0);
                    let mut name = ease_name(&key.ease).to_owned();
                    if key.inbetween_relax > 0 {
                        name += &format!(" · relax {}", key.inbetween_relax);
                    }
                    painter.text(
                        Pos2::new((x + next_x) / 2.0, center_y),
                        egui::Align2::CENTER_CENTER,
                        name,
                        font,
                        weak,
                    );
                }
            }
        }

        // The selected layer's parameter keys, as dots along the top of the keys' row.
        let selected_layer = self.selected_layer.filter(|i| *i < self.doc.scene().layers.len());
        let layer_frames = selected_layer.map_or_else(Vec::new, |i| key_frames(&self.doc.scene().layers[i]));
        let dot_y = center_y - DIAMOND - 5.0;
        let dot_under = |pos: Pos2| {
            // Above the diamonds' tips the dots win; below, the rest-shape keys.
            if pos.y >= center_y - DIAMOND || (pos.y - dot_y).abs() > 6.0 {
                return None;
            }
            layer_frames.iter().copied().find(|f| (pos.x - track.x(f64::from(*f))).abs() <= 5.0)
        };
        let color = Color32::from_rgb(90, 200, 255);
        for frame in &layer_frames {
            let dragged = self.param_key_drag == Some(*frame);
            let radius = if dragged { 4.0 } else { 3.0 };
            painter.circle_filled(Pos2::new(track.x(f64::from(*frame)), dot_y), radius, color);
        }

        // Playhead.
        let x = track.x(self.frame());
        let red = Color32::from_rgb(230, 60, 50);
        painter.line_segment([Pos2::new(x, rect.top()), Pos2::new(x, rect.bottom())], Stroke::new(2.0, red));

        // Interaction: a press on a key selects it and a drag retimes it; elsewhere it scrubs.
        if response.drag_started() || response.clicked() || response.secondary_clicked() {
            let origin = ui.input(|i| i.pointer.press_origin()).or(pointer);
            self.param_key_drag = origin.and_then(dot_under);
            self.key_drag = if self.param_key_drag.is_some() { None } else { origin.and_then(key_under) };
            if let Some(index) = self.key_drag {
                self.selected_key = Some(index);
                self.selection.clear();
            } else if !response.secondary_clicked() {
                self.selected_key = None;
            }
        }
        if let Some(pos) = pointer
            && (response.dragged() || response.clicked())
            && !response.secondary_clicked()
        {
            let frame = track.frame(pos.x).round();
            match (self.key_drag, self.param_key_drag, selected_layer) {
                (Some(index), _, _) if response.dragged() => self.retime_key(index, frame as i32),
                (Some(_), _, _) => {}
                (None, Some(from), Some(layer)) if response.dragged() => {
                    let to = frame.clamp(track.start, track.end) as i32;
                    self.retime_layer_keys(layer, from, to);
                }
                (None, Some(from), _) => self.set_frame(f64::from(from)),
                (None, None, _) => self.set_frame(frame),
            }
        }
        if response.drag_stopped() {
            self.key_drag = None;
            self.param_key_drag = None;
            self.end_gesture();
        }
        if let Some(pos) = response.hover_pos() {
            let frame = track.frame(pos.x).round().clamp(track.start, track.end);
            response.clone().on_hover_text_at_pointer(format!("frame {frame}"));
        }
        if let Some(index) = self.selected_key.filter(|i| *i < keys.len()) {
            // Clicks inside must not close it: its number fields take a click to type into.
            egui::Popup::context_menu(&response)
                .close_behavior(egui::PopupCloseBehavior::CloseOnClickOutside)
                .show(|ui| self.key_menu(ui, index));
        }
    }

    /// The right-click menu of key `index`: its segment's easing, in-between relaxation, delete.
    fn key_menu(&mut self, ui: &mut egui::Ui, index: usize) {
        let key = self.doc.scene().keys[index].clone();
        ui.strong(format!("Key at frame {}", key.frame));
        if index + 1 < self.doc.scene().keys.len() {
            ui.label("Easing to the next key");
            for (name, ease) in EASES {
                let current = std::mem::discriminant(&key.ease) == std::mem::discriminant(&ease);
                if ui.radio(current, name).clicked() {
                    if !current {
                        self.apply("Easing", |s| s.keys[index].ease = ease);
                    }
                    // Bézier stays open to show its handles.
                    if !matches!(ease, Ease::Bezier(..)) {
                        ui.close();
                    }
                }
            }
            if let Ease::Bezier(x1, y1, x2, y2) = key.ease {
                let mut handles = [x1, y1, x2, y2];
                if super::bezier_handles::edit(ui, &mut handles).began {
                    self.doc.begin_gesture("Bézier handles");
                }
                if handles != [x1, y1, x2, y2] {
                    let [x1, y1, x2, y2] = handles;
                    self.apply("Bézier handles", |s| s.keys[index].ease = Ease::Bezier(x1, y1, x2, y2));
                }
            }
            ui.horizontal(|ui| {
                let mut sweeps = key.inbetween_relax;
                let label = ui.label("Re-relax in-betweens").id;
                let drag = egui::DragValue::new(&mut sweeps).range(0..=MAX_INBETWEEN_RELAX).suffix(" sweeps");
                if ui.add(drag).labelled_by(label).changed() {
                    self.apply("In-between relaxation", |s| s.keys[index].inbetween_relax = sweeps);
                }
            });
            ui.separator();
        }
        if ui.button("Go to key").clicked() {
            self.set_frame(f64::from(key.frame));
            ui.close();
        }
        if ui.button("Duplicate key").on_hover_text("To the playhead, or the next free frame after this key").clicked()
        {
            self.duplicate_key(index);
            ui.close();
        }
        if ui.button("Delete key").clicked() {
            self.delete_selected_key();
            ui.close();
        }
    }

    /// Copies key `index` to the playhead's frame when no key is there, else
    /// to the first free frame after it; the copy is selected.
    fn duplicate_key(&mut self, index: usize) {
        let keys = &self.doc.scene().keys;
        let playhead = self.frame().round() as i32;
        let taken = |frame: i32| keys.iter().any(|k| k.frame == frame);
        let frame = if taken(playhead) {
            (keys[index].frame + 1..).find(|f| !taken(*f)).expect("frames are unbounded")
        } else {
            playhead
        };
        let mut copy = keys[index].clone();
        copy.frame = frame;
        let at = keys.iter().position(|k| k.frame > frame).unwrap_or(keys.len());
        self.apply("Duplicate key", |s| s.keys.insert(at, copy));
        self.selected_key = Some(at);
    }

    /// Moves key `index` to `frame`, kept between its neighbours (keys keep their order).
    fn retime_key(&mut self, index: usize, frame: i32) {
        let keys = &self.doc.scene().keys;
        let low = if index > 0 { keys[index - 1].frame + 1 } else { i32::MIN / 2 };
        let high = keys.get(index + 1).map_or(i32::MAX / 2, |k| k.frame - 1);
        let frame = frame.clamp(low, high);
        if frame != keys[index].frame {
            self.doc.begin_gesture("Move key");
            self.apply("Move key", |s| s.keys[index].frame = frame);
        }
    }

    /// Moves the parameter keys of layer `layer` at frame `from` towards `to`
    /// (one undo step per drag); the drag follows them to where they landed.
    fn retime_layer_keys(&mut self, layer: usize, from: i32, to: i32) {
        let mut moved = self.doc.scene().layers[layer].clone();
        let landed = move_keys(&mut moved, from, to);
        if landed != from {
            self.doc.begin_gesture("Move layer keys");
            self.apply("Move layer keys", |s| s.layers[layer] = moved);
            if key_frames(&self.doc.scene().layers[layer]).contains(&landed) {
                self.param_key_drag = Some(landed);
            }
        }
    }

    /// K: a new rest-shape key at the playhead's frame, holding the pose shown
    /// now (the key in effect's pins where the cloth holds them at this frame,
    /// its fabric).
    pub(super) fn add_key_here(&mut self) {
        let frame = self.frame().round() as i32;
        self.set_frame(f64::from(frame));
        let scene = self.doc.scene().clone();
        if let Some(index) = scene.keys.iter().position(|k| k.frame == frame) {
            self.selected_key = Some(index);
            self.report(format!("There is already a key at frame {frame}."), false);
            return;
        }
        if *self.shown_scene() != scene {
            self.report("Wait for the cloth to finish relaxing before adding a key.".to_owned(), true);
            return;
        }
        let mut key = scene.key_in_effect(f64::from(frame)).clone();
        key.frame = frame;
        // The evaluated mesh at a whole frame holds the pins where this frame puts them.
        let mesh = self.evaluator.evaluate_frame(&scene, f64::from(frame));
        let cols = scene.cloth.cols();
        for pin in &mut key.pins {
            let p = mesh.positions[pin.grid.1 as usize * cols + pin.grid.0 as usize];
            pin.pos = (f64::from(p.x), f64::from(p.y), f64::from(p.z));
        }
        let at = scene.keys.iter().position(|k| k.frame > frame).unwrap_or(scene.keys.len());
        self.apply("Add key", |s| s.keys.insert(at, key));
        self.selected_key = Some(at);
    }

    pub(super) fn delete_selected_key(&mut self) {
        let Some(index) = self.selected_key else { return };
        if self.doc.scene().keys.len() <= 1 {
            self.report("A scene needs at least one key.".to_owned(), true);
            return;
        }
        self.apply("Delete key", |s| {
            s.keys.remove(index);
        });
        self.selected_key = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ruler_labels_stay_apart() {
        assert_eq!(ruler_step(50.0), 1);
        assert_eq!(ruler_step(30.0), 2);
        assert_eq!(ruler_step(10.0), 5);
        assert_eq!(ruler_step(8.0), 10);
        assert_eq!(ruler_step(1.0), 50);
        assert_eq!(ruler_step(0.5), 100);
        for ppf in [0.01f32, 0.3, 3.0, 17.0, 400.0] {
            let step = ruler_step(ppf);
            assert!(step as f32 * ppf >= MIN_LABEL_GAP, "{ppf}: {step}");
        }
    }

    #[test]
    fn frames_and_x_map_both_ways() {
        let track =
            Track { rect: Rect::from_min_size(Pos2::new(10.0, 0.0), Vec2::new(200.0, 30.0)), start: 0.0, end: 100.0 };
        assert_eq!(track.x(0.0), 10.0);
        assert_eq!(track.x(100.0), 210.0);
        assert_eq!(track.frame(110.0), 50.0);
        // A one-frame range still maps without dividing by zero.
        let flat = Track { start: 5.0, end: 5.0, ..track };
        assert!(flat.x(5.0).is_finite() && flat.frame(50.0).is_finite());
    }

    #[test]
    fn every_easing_has_a_name() {
        for (name, ease) in EASES {
            assert_eq!(ease_name(&ease), name);
        }
        assert_eq!(ease_name(&Ease::Bezier(0.1, 0.2, 0.3, 0.4)), "Bézier");
    }
}
