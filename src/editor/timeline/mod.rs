//! The timeline along the bottom: transport (play / pause, loop), the frame,
//! fps and range fields, and the track — a ruler with frame numbers, the
//! playhead to scrub, and the rest-shape keys as diamonds to select, drag to
//! retime, and right-click for their easing and in-between relaxation.
//! Under them, one thin lane per shown reference marks where its animation
//! plays (the track grows by those lanes only when the scene has some).
//!
//! Every frame is computed directly, so scrubbing shows the frame at once.

pub mod bezier_handles;
pub mod curve_view;
mod shot_number;
mod zoom;

use eframe::egui::{self, Color32, Pos2, Rect, Sense, Stroke, Vec2};

use self::zoom::TimelineZoom;
use super::number_field::number_field;
use super::param_edit::Keyed;
use super::session::Repaint;
use super::workspace::Workspace;
use crate::scene::{Ease, MAX_FPS, MAX_INBETWEEN_RELAX, MAX_TIMELINE_FRAME, Scene};

/// Widths (points) that hold the transport row still while the playhead moves.
const PLAY_BUTTON_WIDTH: f32 = 56.0;
const FRAME_FIELD_WIDTH: f32 = 48.0;
const SECONDS_WIDTH: f32 = 56.0;
/// Auto key is red while on, as in other animation tools: edits are keying.
const AUTO_KEY_RED: Color32 = Color32::from_rgb(170, 40, 40);

/// Height of the track, points: the ruler with its labels, then a row for the
/// selected layer's parameter keys, then one for the rest-shape keys, so a
/// dot and a diamond on one frame never hide each other or a label.
const TRACK_HEIGHT: f32 = 46.0;
/// Half the width of a key diamond, points.
const DIAMOND: f32 = 6.0;
/// Labels on the ruler at least this far apart, points.
const MIN_LABEL_GAP: f32 = 44.0;
/// Height of the references' band under the keys, points, kept whether or
/// not a reference is shown so adding one moves nothing; its lanes share it.
/// The most lanes (more references share them, in turn).
const REFERENCE_BAND: f32 = 12.0;
const MAX_LANES: usize = 4;
/// A muted violet: the references' bars, apart from keys (white, yellow) and layer dots (blue).
const REFERENCE_BAR: Color32 = Color32::from_rgba_premultiplied(96, 84, 128, 150);

/// Where one shown reference's animation plays, as its lane draws it.
#[derive(Clone, Debug, PartialEq)]
struct ReferenceBar {
    /// The reference's name, or "reference N".
    name: String,
    clip: crate::scene::ClipFrames,
    lane: usize,
}

/// A bar for every visible reference of `scene` whose clip is known, in
/// scene order, each in its lane.
fn reference_bars(scene: &Scene) -> Vec<ReferenceBar> {
    let shown = scene.references.iter().enumerate().filter(|(_, r)| r.visible);
    let clips = shown.filter_map(|(index, r)| {
        let name = if r.name.trim().is_empty() { format!("reference {}", index + 1) } else { r.name.clone() };
        Some((name, r.clip_frames(scene.timeline.fps)?))
    });
    clips.enumerate().map(|(n, (name, clip))| ReferenceBar { name, clip, lane: n % MAX_LANES }).collect()
}

/// Height of each lane `bars` fill, points: the band split among them.
fn lane_height(bars: &[ReferenceBar]) -> f32 {
    REFERENCE_BAND / bars.len().clamp(1, MAX_LANES) as f32
}

/// The frames a bar covers: its clip's first play, and with repeat on
/// until the end of the timeline.
fn bar_frames(bar: &ReferenceBar, timeline_end: f64) -> (f64, f64) {
    let (first, last) = bar.clip.frames;
    if bar.clip.repeat && last > first { (first, last.max(timeline_end)) } else { (first, last) }
}

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

/// The timeline's own state: how it plays, its zoom, and a key being dragged.
pub struct TimelinePanel {
    /// Playback wraps round to the start (else it stops at the end).
    looping: bool,
    /// Playback shows every frame, one after another, even when the display
    /// cannot keep up (else it keeps the scene's clock and skips frames).
    every_frame: bool,
    /// The part of the timeline the track shows.
    zoom: TimelineZoom,
    /// The rest-shape key being dragged.
    key_drag: Option<usize>,
    /// The frame of the selected layer's parameter keys being dragged.
    param_key_drag: Option<i32>,
}

impl Default for TimelinePanel {
    fn default() -> Self {
        TimelinePanel {
            looping: true,
            every_frame: false,
            zoom: TimelineZoom::default(),
            key_drag: None,
            param_key_drag: None,
        }
    }
}

impl TimelinePanel {
    /// The same panel for a new document: its drags and zoom dropped, how it plays kept.
    pub fn for_new_document(&self) -> TimelinePanel {
        TimelinePanel { looping: self.looping, every_frame: self.every_frame, ..TimelinePanel::default() }
    }

    pub(super) fn ui(&mut self, ui: &mut egui::Ui, w: &mut Workspace) {
        self.transport_ui(ui, w);
        ui.add_space(2.0);
        self.track_ui(ui, w);
    }

    /// Moves the playhead while playing, holding whole frames like the scene's
    /// clock, or (every frame) one frame per frame time at most.
    pub fn advance_playback(&self, ctx: &egui::Context, w: &mut Workspace) {
        let timeline = &w.doc.scene().timeline;
        match w.session.advance_playback(timeline, self.looping, self.every_frame) {
            Repaint::No => {}
            Repaint::Now => ctx.request_repaint(),
            Repaint::After(wait) => ctx.request_repaint_after(wait),
        }
    }

    fn transport_ui(&mut self, ui: &mut egui::Ui, w: &mut Workspace) {
        let timeline = w.doc.scene().timeline.clone();
        ui.horizontal(|ui| {
            // Fixed widths: Play/Pause and the frame readouts do not push the fields along.
            let label = if w.session.playing() { "Pause" } else { "Play" };
            if ui
                .add(egui::Button::new(label).min_size(egui::vec2(PLAY_BUTTON_WIDTH, 0.0)))
                .on_hover_text("Space")
                .clicked()
            {
                w.toggle_play();
            }
            ui.toggle_value(&mut self.looping, "Loop").on_hover_text("Play the range over and over");
            let auto_key = egui::Button::selectable(w.session.auto_key(), "Auto key").fill(if w.session.auto_key() {
                AUTO_KEY_RED
            } else {
                Color32::TRANSPARENT
            });
            if ui
                .add(auto_key)
                .on_hover_text(
                    "Edits off a key add a key at the playhead and change that one \
                     (pins, fabric, layer parameters)",
                )
                .clicked()
            {
                w.session.toggle_auto_key();
            }
            ui.toggle_value(&mut self.every_frame, "Every frame").on_hover_text(
                "Play every frame, slower than real time if the display cannot keep up \
                 (off: keep the scene's clock, skipping frames)",
            );
            ui.separator();
            let label = ui.label("Frame").id;
            let mut frame = w.frame().round() as i32;
            let field = number_field(ui.ctx(), &mut frame).range(timeline.start..=timeline.end);
            let r = ui.add_sized([FRAME_FIELD_WIDTH, ui.spacing().interact_size.y], field).labelled_by(label);
            if r.changed() {
                w.set_frame(f64::from(frame));
            }
            let seconds = egui::Label::new(format!("{:.2} s", w.frame() / timeline.fps));
            ui.add_sized([SECONDS_WIDTH, ui.spacing().interact_size.y], seconds);
            ui.separator();
            let mut fps = timeline.fps;
            let label = ui.label("fps").id;
            let r = ui.add(number_field(ui.ctx(), &mut fps).range(1.0..=MAX_FPS).speed(0.1).max_decimals(3));
            let r = r.labelled_by(label);
            timeline_field(w, &r, "Frame rate", |s| s.timeline.fps = fps);
            let (mut start, mut end) = (timeline.start, timeline.end);
            let label = ui.label("Start").id;
            let r = ui.add(number_field(ui.ctx(), &mut start).range(-MAX_TIMELINE_FRAME..=end)).labelled_by(label);
            timeline_field(w, &r, "Timeline start", |s| s.timeline.start = start);
            let label = ui.label("End").id;
            let r = ui.add(number_field(ui.ctx(), &mut end).range(start..=MAX_TIMELINE_FRAME)).labelled_by(label);
            timeline_field(w, &r, "Timeline end", |s| s.timeline.end = end);
            ui.separator();
            if ui.button("Add key").on_hover_text("K: a rest-shape key here, from the current pose").clicked() {
                w.add_key_here();
            }
            let selected = w.session.selected_key().is_some();
            if ui.add_enabled(selected, egui::Button::new("Delete key")).clicked() {
                w.delete_selected_key();
            }
            ui.separator();
            let hint = "Show the whole timeline (Ctrl+wheel over the track zooms, the wheel or a middle drag pans)";
            if ui
                .add_enabled(self.zoom.is_zoomed(), egui::Button::new("Fit"))
                .on_hover_text(hint)
                .on_disabled_hover_text(hint)
                .clicked()
            {
                self.zoom.reset();
            }
        });
    }

    fn track_ui(&mut self, ui: &mut egui::Ui, w: &mut Workspace) {
        let timeline = w.doc.scene().timeline.clone();
        let width = ui.available_width();
        let bars = reference_bars(w.doc.scene());
        let height = TRACK_HEIGHT + REFERENCE_BAND;
        let (rect, response) = ui.allocate_exact_size(Vec2::new(width, height), Sense::click_and_drag());
        // The ruler and the keys' rows; the references' lanes below.
        let body = Rect::from_min_size(rect.min, Vec2::new(rect.width(), TRACK_HEIGHT));
        response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Slider, true, "Timeline"));
        let inner = rect.shrink2(Vec2::new(DIAMOND + 2.0, 0.0));
        self.zoom_and_pan(ui, &response, inner, &timeline);
        if w.session.playing() {
            self.zoom.keep_in_view(w.frame(), timeline.start, timeline.end);
        }
        let (shown_start, shown_end) = self.zoom.shown(timeline.start, timeline.end);
        let track = Track { rect: inner, start: shown_start, end: shown_end };
        let painter = ui.painter_at(rect);
        let visuals = ui.visuals().clone();
        painter.rect_filled(rect, 3.0, visuals.extreme_bg_color);

        // Ruler.
        let points_per_frame = inner.width() / (shown_end - shown_start).max(1.0) as f32;
        let step = ruler_step(points_per_frame);
        let minor = if step >= 10 { step / 5 } else { 1 };
        let (first_shown, last_shown) = (shown_start.ceil() as i32, shown_end.floor() as i32);
        let weak = visuals.weak_text_color();
        let font = egui::FontId::proportional(10.0);
        let mut at = first_shown.div_euclid(minor) * minor;
        while at <= last_shown {
            if at >= first_shown {
                let x = track.x(f64::from(at));
                let major = at.rem_euclid(step) == 0;
                let height = if major { 9.0 } else { 4.0 };
                painter.line_segment(
                    [Pos2::new(x, rect.top()), Pos2::new(x, rect.top() + height)],
                    Stroke::new(1.0, weak),
                );
                if major {
                    // Right of its tick, or left of it where the label would run off the track.
                    let galley = painter.layout_no_wrap(at.to_string(), font.clone(), weak);
                    let left =
                        if x + 2.0 + galley.size().x <= rect.right() { x + 2.0 } else { x - 2.0 - galley.size().x };
                    painter.galley(Pos2::new(left, rect.top() + 8.0), galley, weak);
                }
            }
            at += minor;
        }

        // Keys.
        let keys = w.doc.scene().keys.clone();
        let center_y = body.bottom() - DIAMOND - 3.0;
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
            let selected = w.session.selected_key() == Some(index);
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
                    let mut name = key.ease.label().to_owned();
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

        // The selected collider's (else the selected layer's) keys, as dots
        // along the top of the keys' row: yellow as its outline, blue for a layer.
        let keyed = Keyed::selected(w.doc.scene(), w.session.selected_layer(), w.session.selected_collider());
        let param_frames = keyed.map_or_else(Vec::new, |k| k.key_frames(w.doc.scene()));
        let dot_y = center_y - DIAMOND - 5.0;
        let dot_under = |pos: Pos2| {
            // Above the diamonds' tips the dots win; below, the rest-shape keys.
            if pos.y >= center_y - DIAMOND || (pos.y - dot_y).abs() > 6.0 {
                return None;
            }
            param_frames.iter().copied().find(|f| (pos.x - track.x(f64::from(*f))).abs() <= 5.0)
        };
        let color = match keyed {
            Some(Keyed::Collider(_)) => Color32::from_rgb(255, 200, 20),
            _ => Color32::from_rgb(90, 200, 255),
        };
        for frame in &param_frames {
            let dragged = self.param_key_drag == Some(*frame);
            let radius = if dragged { 4.0 } else { 3.0 };
            painter.circle_filled(Pos2::new(track.x(f64::from(*frame)), dot_y), radius, color);
        }

        paint_reference_bars(&painter, &track, body.bottom(), &bars, f64::from(timeline.end));

        // Playhead.
        let x = track.x(w.frame());
        let red = Color32::from_rgb(230, 60, 50);
        painter.line_segment([Pos2::new(x, rect.top()), Pos2::new(x, rect.bottom())], Stroke::new(2.0, red));

        // Interaction: a press on a key selects it and a drag retimes it; elsewhere it scrubs.
        if response.drag_started_by(egui::PointerButton::Primary) || response.clicked() || response.secondary_clicked()
        {
            let origin = ui.input(|i| i.pointer.press_origin()).or(pointer);
            self.param_key_drag = origin.and_then(dot_under);
            self.key_drag = if self.param_key_drag.is_some() { None } else { origin.and_then(key_under) };
            if let Some(index) = self.key_drag {
                w.session.select_key(index);
            } else if !response.secondary_clicked() {
                w.session.let_go_of_key();
            }
        }
        if let Some(pos) = pointer
            && (response.dragged_by(egui::PointerButton::Primary) || response.clicked())
        {
            let frame = track.frame(pos.x).round();
            match (self.key_drag, self.param_key_drag, keyed) {
                (Some(index), _, _) if response.dragged() => retime_key(w, index, frame as i32),
                (Some(_), _, _) => {}
                (None, Some(from), Some(keyed)) if response.dragged() => {
                    let to = frame.clamp(track.start, track.end) as i32;
                    self.retime_param_keys(w, keyed, from, to);
                }
                (None, Some(from), _) => w.set_frame(f64::from(from)),
                (None, None, _) => w.set_frame(frame),
            }
        }
        if response.drag_stopped() {
            self.key_drag = None;
            self.param_key_drag = None;
            w.end_gesture();
        }
        if let Some(pos) = response.hover_pos() {
            let frame = track.frame(pos.x).round().clamp(track.start, track.end);
            let text = match bar_under(&track, body.bottom(), &bars, f64::from(timeline.end), pos) {
                Some(bar) => format!("frame {frame} · {}", bar_text(bar)),
                None => format!("frame {frame}"),
            };
            response.clone().on_hover_text_at_pointer(text);
        }
        if let Some(index) = w.session.selected_key().filter(|i| *i < keys.len()) {
            // Clicks inside must not close it: its number fields take a click to type into.
            egui::Popup::context_menu(&response)
                .close_behavior(egui::PopupCloseBehavior::CloseOnClickOutside)
                .show(|ui| key_menu(ui, w, index));
        }
    }

    /// Ctrl+wheel over the track zooms about the frame under the mouse; the
    /// wheel and a middle drag pan a zoomed track.
    fn zoom_and_pan(
        &mut self,
        ui: &egui::Ui,
        response: &egui::Response,
        inner: Rect,
        timeline: &crate::scene::Timeline,
    ) {
        let (start, end) = self.zoom.shown(timeline.start, timeline.end);
        let frames_per_point = (end - start) / f64::from(inner.width().max(1.0));
        if let Some(pos) = response.hover_pos() {
            let (zoom, scroll) = ui.input(|i| (i.zoom_delta(), i.smooth_scroll_delta));
            if zoom != 1.0 {
                let track = Track { rect: inner, start, end };
                self.zoom.zoom_about(f64::from(zoom), track.frame(pos.x), timeline.start, timeline.end);
            } else {
                let along = if scroll.x != 0.0 { scroll.x } else { scroll.y };
                if along != 0.0 {
                    self.zoom.pan(-f64::from(along) * frames_per_point, timeline.start, timeline.end);
                }
            }
        }
        if response.dragged_by(egui::PointerButton::Middle) {
            self.zoom.pan(-f64::from(response.drag_delta().x) * frames_per_point, timeline.start, timeline.end);
        }
    }

    /// Moves the parameter keys of layer `layer` at frame `from` towards `to`
    /// (one undo step per drag); the drag follows them to where they landed.
    fn retime_param_keys(&mut self, w: &mut Workspace, keyed: Keyed, from: i32, to: i32) {
        let mut moved = w.doc.scene().clone();
        let landed = keyed.move_keys(&mut moved, from, to);
        if landed != from {
            let label = match keyed {
                Keyed::Layer(_) => "Move layer keys",
                Keyed::Collider(_) => "Move collider keys",
            };
            w.doc.begin_gesture(label);
            w.apply(label, |s| *s = moved);
            if keyed.key_frames(w.doc.scene()).contains(&landed) {
                self.param_key_drag = Some(landed);
            }
        }
    }
}

/// The references' lanes under the keys' row (whose bottom is `top`): a
/// thin bar from where each clip starts to where it ends, bracketed; one
/// that repeats carries on to the timeline's end, a tick at its first
/// cycle's end.
fn paint_reference_bars(painter: &egui::Painter, track: &Track, top: f32, bars: &[ReferenceBar], end: f64) {
    let lane = lane_height(bars);
    let half_tick = (lane * 0.4).min(3.0);
    for bar in bars {
        let mid = top + lane * (bar.lane as f32 + 0.5);
        let (from, to) = bar_frames(bar, end);
        let (x0, x1) = (track.x(from), track.x(to));
        let line = Rect::from_min_max(Pos2::new(x0, mid - 1.0), Pos2::new(x1.max(x0 + 1.0), mid + 1.0));
        painter.rect_filled(line, 0.0, REFERENCE_BAR);
        let tick = |x: f32| {
            painter.line_segment(
                [Pos2::new(x, mid - half_tick), Pos2::new(x, mid + half_tick)],
                Stroke::new(1.0, REFERENCE_BAR),
            )
        };
        tick(x0);
        tick(track.x(bar.clip.frames.1));
    }
}

/// The bar under `pos` in the references' lanes below `top` (the last drawn wins).
fn bar_under<'a>(track: &Track, top: f32, bars: &'a [ReferenceBar], end: f64, pos: Pos2) -> Option<&'a ReferenceBar> {
    if pos.y < top {
        return None;
    }
    let lane = ((pos.y - top) / lane_height(bars)) as usize;
    bars.iter().rev().filter(|b| b.lane == lane).find(|bar| {
        let (from, to) = bar_frames(bar, end);
        pos.x >= track.x(from) - 3.0 && pos.x <= track.x(to) + 3.0
    })
}

/// What a bar's hover says: `walker: clip Walk, frames 0–24, repeating`.
fn bar_text(bar: &ReferenceBar) -> String {
    let (first, last) = bar.clip.frames;
    let again = if bar.clip.repeat { ", repeating" } else { "" };
    let frame = |f: f64| crate::scene::readable_number((f * 10.0).round() / 10.0);
    format!("{}: clip {}, frames {}–{}{again}", bar.name, bar.clip.name, frame(first), frame(last))
}

fn timeline_field(
    w: &mut Workspace,
    response: &egui::Response,
    label: &str,
    change: impl FnOnce(&mut crate::scene::Scene),
) {
    if response.drag_started() {
        w.doc.begin_gesture(label);
    }
    if response.changed() {
        w.apply(label, change);
        let frame = w.frame();
        w.set_frame(frame);
    }
}

/// The right-click menu of key `index`: its segment's easing, in-between relaxation, delete.
fn key_menu(ui: &mut egui::Ui, w: &mut Workspace, index: usize) {
    let key = w.doc.scene().keys[index].clone();
    ui.strong(format!("Key at frame {}", key.frame));
    if index + 1 < w.doc.scene().keys.len() {
        ui.label("Easing to the next key");
        for ease in Ease::ALL {
            let name = ease.label();
            let current = std::mem::discriminant(&key.ease) == std::mem::discriminant(&ease);
            if ui.radio(current, name).clicked() {
                if !current {
                    w.apply("Easing", |s| s.keys[index].ease = ease);
                }
                // Bézier stays open to show its handles.
                if !matches!(ease, Ease::Bezier(..)) {
                    ui.close();
                }
            }
        }
        if let Ease::Bezier(x1, y1, x2, y2) = key.ease {
            let mut handles = [x1, y1, x2, y2];
            if self::bezier_handles::edit(ui, &mut handles).began {
                w.doc.begin_gesture("Bézier handles");
            }
            if handles != [x1, y1, x2, y2] {
                let [x1, y1, x2, y2] = handles;
                w.apply("Bézier handles", |s| s.keys[index].ease = Ease::Bezier(x1, y1, x2, y2));
            }
        }
        ui.horizontal(|ui| {
            let mut sweeps = key.inbetween_relax;
            let label = ui.label("Re-relax in-betweens").id;
            let drag = number_field(ui.ctx(), &mut sweeps).range(0..=MAX_INBETWEEN_RELAX).suffix(" sweeps");
            if ui.add(drag).labelled_by(label).changed() {
                w.apply("In-between relaxation", |s| s.keys[index].inbetween_relax = sweeps);
            }
        });
        ui.separator();
    }
    if ui.button("Go to key").clicked() {
        w.set_frame(f64::from(key.frame));
        ui.close();
    }
    if ui.button("Duplicate key").on_hover_text("To the playhead, or the next free frame after this key").clicked() {
        duplicate_key(w, index);
        ui.close();
    }
    if ui.button("Delete key").clicked() {
        w.delete_selected_key();
        ui.close();
    }
}

/// Copies key `index` to the playhead's frame when no key is there, else
/// to the first free frame after it; the copy is selected.
fn duplicate_key(w: &mut Workspace, index: usize) {
    let keys = &w.doc.scene().keys;
    let playhead = w.frame().round() as i32;
    let taken = |frame: i32| keys.iter().any(|k| k.frame == frame);
    let frame = if taken(playhead) {
        (keys[index].frame + 1..).find(|f| !taken(*f)).expect("frames are unbounded")
    } else {
        playhead
    };
    let mut copy = keys[index].clone();
    copy.frame = frame;
    let at = keys.iter().position(|k| k.frame > frame).unwrap_or(keys.len());
    w.apply("Duplicate key", |s| s.keys.insert(at, copy));
    w.session.key_made(at);
}

/// Moves key `index` to `frame`, kept between its neighbours (keys keep their order).
fn retime_key(w: &mut Workspace, index: usize, frame: i32) {
    let keys = &w.doc.scene().keys;
    let low = if index > 0 { keys[index - 1].frame + 1 } else { i32::MIN / 2 };
    let high = keys.get(index + 1).map_or(i32::MAX / 2, |k| k.frame - 1);
    let frame = frame.clamp(low, high);
    if frame != keys[index].frame {
        w.doc.begin_gesture("Move key");
        w.apply("Move key", |s| s.keys[index].frame = frame);
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
    fn a_shown_reference_s_bar_spans_its_clip_and_a_repeating_one_runs_on() {
        let walker = crate::scene::read_rig(std::path::Path::new("assets/walker.glb")).expect("the bundled walker");
        let mut scene = crate::scene::parse(crate::editor::DEFAULT_SCENE, "magic_carpet.ron").unwrap();
        scene.references = ron::from_str(r#"[(name: "a", file: "a.glb", start_frame: 12), (file: "b.glb")]"#).unwrap();
        for reference in &mut scene.references {
            reference.rig = crate::scene::Loaded(Some(std::sync::Arc::new(walker.clone())));
        }
        let bars = reference_bars(&scene);
        assert_eq!(bars.iter().map(|b| (b.name.as_str(), b.lane)).collect::<Vec<_>>(), [("a", 0), ("reference 2", 1)]);
        assert_eq!(bar_frames(&bars[0], 120.0), (12.0, 36.0), "a 1 s walk at 24 fps from frame 12");
        assert_eq!(bar_text(&bars[0]), "a: clip Walk, frames 12–36");
        scene.references[0].repeat = true;
        let track = Track { rect: Rect::from_min_size(Pos2::ZERO, Vec2::new(120.0, 46.0)), start: 0.0, end: 120.0 };
        let bars = reference_bars(&scene);
        let at = |x: f32, y: f32| bar_under(&track, 46.0, &bars, 120.0, Pos2::new(x, y)).map(|b| b.name.clone());
        assert_eq!(at(60.0, 49.0), Some("a".to_owned()));
        assert_eq!(at(60.0, 40.0), None, "above the lanes: the keys' row");
        assert_eq!(at(5.0, 49.0), None, "before it starts");
        assert_eq!(at(5.0, 55.0), Some("reference 2".to_owned()), "the second lane, the band's lower half");
        assert_eq!(at(60.0, 55.0), None, "past the second clip's end");
        scene.references[1].visible = false;
        let bars = reference_bars(&scene);
        assert_eq!(bars.len(), 1, "a hidden reference has no bar");
        assert_eq!(bar_frames(&bars[0], 120.0), (12.0, 120.0), "on to the timeline's end");
        let at = |x: f32, y: f32| bar_under(&track, 46.0, &bars, 120.0, Pos2::new(x, y)).map(|b| b.name.clone());
        assert_eq!(at(60.0, 55.0), Some("a".to_owned()), "one lane fills the band");
    }
}
