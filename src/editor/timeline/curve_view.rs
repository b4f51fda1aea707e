//! The curve view under the Layers, Colliders and References panels' numbers:
//! one parameter of the selected layer (or number of the selected collider or
//! reference) over
//! the timeline's range, drawn with the evaluator's own [`sample`] (eases
//! included), with the playhead and the keys as handles.
//! Drag a key to change its value and frame, double-click to add a key on the
//! curve, right-click a key for the easing that arrives at it or to delete it.

use eframe::egui::{self, Color32, Pos2, Rect, Sense, Stroke, Vec2};

use super::bezier_handles;
pub use super::shot_number::ShotNumber;
use crate::animate::track::sample;
use crate::editor::document::Document;
use crate::editor::param_edit::{key_at, param_mut, param_names, toggle_key};
use crate::editor::workspace::Workspace;
use crate::scene::{Collider, ColliderNumber, Ease, Layer, Param, ParamKey, Reference, Scene, Timeline};

/// Height of the plot, points.
const HEIGHT: f32 = 120.0;
/// Radius of a key handle, and how near a press must be to grab one, points.
const HANDLE: f32 = 4.5;
const GRAB: f32 = 8.0;
/// Room left above and below the values, as a share of their span.
const MARGIN: f64 = 0.2;
const CURVE_COLOR: Color32 = Color32::from_rgb(90, 200, 255);

/// An animatable number of the scene the view can show: a layer's
/// parameter by name, a collider's number, or a reference's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Curve {
    Layer(usize, &'static str),
    Collider(usize, ColliderNumber),
    Reference(usize, ReferenceNumber),
    Shot(ShotNumber),
}

/// An animatable number of a reference: its centre or rotation along an
/// axis (0 x, 1 y, 2 z), or its scale.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReferenceNumber {
    Center(usize),
    Rotation(usize),
    Scale,
}

impl ReferenceNumber {
    /// Every number, in panel order.
    pub const ALL: [ReferenceNumber; 7] = [
        ReferenceNumber::Center(0),
        ReferenceNumber::Center(1),
        ReferenceNumber::Center(2),
        ReferenceNumber::Rotation(0),
        ReferenceNumber::Rotation(1),
        ReferenceNumber::Rotation(2),
        ReferenceNumber::Scale,
    ];

    /// Its name as its row shows it ("centre y", "rotation x", "scale").
    pub fn label(self) -> String {
        let axis = |a: usize| ["x", "y", "z"].get(a).copied().unwrap_or("?");
        match self {
            ReferenceNumber::Center(a) => format!("centre {}", axis(a)),
            ReferenceNumber::Rotation(a) => format!("rotation {}", axis(a)),
            ReferenceNumber::Scale => "scale".to_owned(),
        }
    }

    /// The number in `reference`; `None` for an axis past z.
    pub fn param(self, reference: &Reference) -> Option<&Param> {
        match self {
            ReferenceNumber::Center(a) => {
                let (x, y, z) = &reference.center;
                [x, y, z].get(a).copied()
            }
            ReferenceNumber::Rotation(a) => {
                let (x, y, z) = &reference.rotation_deg;
                [x, y, z].get(a).copied()
            }
            ReferenceNumber::Scale => Some(&reference.scale),
        }
    }

    pub fn param_mut(self, reference: &mut Reference) -> Option<&mut Param> {
        match self {
            ReferenceNumber::Center(a) => {
                let (x, y, z) = &mut reference.center;
                [x, y, z].into_iter().nth(a)
            }
            ReferenceNumber::Rotation(a) => {
                let (x, y, z) = &mut reference.rotation_deg;
                [x, y, z].into_iter().nth(a)
            }
            ReferenceNumber::Scale => Some(&mut reference.scale),
        }
    }
}

impl Curve {
    /// The number as `scene` holds it, if it has it.
    pub fn param(self, scene: &Scene) -> Option<Param> {
        match self {
            Curve::Layer(index, name) => scene.layers.get(index)?.param(name).cloned(),
            Curve::Collider(index, number) => scene.colliders.get(index)?.param(number).cloned(),
            Curve::Reference(index, number) => number.param(scene.references.get(index)?).cloned(),
            Curve::Shot(number) => number.param(scene).cloned(),
        }
    }

    pub fn param_mut(self, scene: &mut Scene) -> Option<&mut Param> {
        match self {
            Curve::Layer(index, name) => param_mut(scene.layers.get_mut(index)?, name),
            Curve::Collider(index, number) => scene.colliders.get_mut(index)?.param_mut(number),
            Curve::Reference(index, number) => number.param_mut(scene.references.get_mut(index)?),
            Curve::Shot(number) => number.param_mut(scene),
        }
    }

    /// The number's name as its row shows it ("magnitude", "center y").
    pub fn name(self) -> String {
        match self {
            Curve::Layer(_, name) => name.replace('_', " "),
            Curve::Collider(_, number) => number.label(),
            Curve::Reference(_, number) => number.label(),
            Curve::Shot(number) => number.label(),
        }
    }
}

/// What the curve view remembers between frames.
#[derive(Default)]
pub struct CurveView {
    /// The number chosen with its curve button.
    chosen: Option<Curve>,
    drag: Option<KeyDrag>,
    /// The key last grabbed, added or right-clicked (its menu's key).
    selected: Option<(Curve, usize)>,
}

/// A key being dragged, and the value range frozen when the drag began (so the
/// plot does not rescale under the pointer).
#[derive(Clone, Copy)]
struct KeyDrag {
    curve: Curve,
    key: usize,
    values: (f64, f64),
    /// From the pointer to the key's centre when it was grabbed.
    grab: Vec2,
}

/// The vertical range that shows `values` with a margin. All equal: a range
/// around the value; none finite: -1..1.
pub fn fit_range(values: impl IntoIterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .into_iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if lo > hi {
        return (-1.0, 1.0);
    }
    let span = hi - lo;
    if span > 1e-9 * lo.abs().max(hi.abs()).max(1e-300) && span.is_finite() {
        let pad = span * MARGIN;
        return (lo - pad, hi + pad);
    }
    // Flat: half the value either side (one either side of zero).
    let pad = if lo == 0.0 { 1.0 } else { lo.abs() * 0.5 };
    (lo - pad, hi + pad)
}

/// The frame key `index` may move to: `frame` kept strictly between its neighbours.
pub fn clamp_frame(keys: &[ParamKey], index: usize, frame: i32) -> i32 {
    let low = if index > 0 { keys[index - 1].frame.saturating_add(1) } else { i32::MIN };
    let high = keys.get(index + 1).map_or(i32::MAX, |k| k.frame.saturating_sub(1));
    if low > high { keys[index].frame } else { frame.clamp(low, high) }
}

/// `value` rounded to the decimal step just under `per_point` (what one point
/// of the plot is worth), so dragged values read 0.125, not 0.12498374.
pub fn round_to_resolution(value: f64, per_point: f64) -> f64 {
    if !(per_point.is_finite() && per_point > 0.0 && value.is_finite()) {
        return value;
    }
    let exponent = per_point.log10().floor() as i32;
    if exponent < 0 {
        let scale = 10f64.powi(-exponent.max(-300));
        (value * scale).round() / scale
    } else {
        let step = 10f64.powi(exponent.min(300));
        (value / step).round() * step
    }
}

/// The parameter the view shows unless another is chosen: the first keyed one, else the first.
pub fn default_param(layer: &Layer) -> Option<&'static str> {
    let mut copy = layer.clone();
    let names = param_names(layer);
    let keyed = names.iter().find(|(name, _)| matches!(param_mut(&mut copy, name), Some(Param::Keys(_))));
    keyed.or(names.first()).map(|(name, _)| *name)
}

/// The mapping between (frame, value) and the plot on screen.
#[derive(Clone, Copy, Debug)]
pub struct Plot {
    /// The frames and values' extent (the drawing less room for the handles).
    inner: Rect,
    frames: (f64, f64),
    values: (f64, f64),
}

impl Plot {
    /// A plot in `rect` of `frames` (at least one frame wide) and `values` (refit when degenerate).
    pub fn new(rect: Rect, frames: (f64, f64), values: (f64, f64)) -> Plot {
        let start = if frames.0.is_finite() { frames.0 } else { 0.0 };
        let end = if frames.1.is_finite() && frames.1 > start { frames.1 } else { start + 1.0 };
        let values = if values.0.is_finite() && values.1.is_finite() && values.1 > values.0 {
            values
        } else {
            fit_range([values.0, values.1])
        };
        Plot { inner: rect.shrink(HANDLE + 2.0), frames: (start, end), values }
    }

    /// The plot the view draws of `param` over `timeline` in `rect` when no key is being dragged.
    pub fn of(rect: Rect, timeline: &Timeline, param: &Param) -> Plot {
        let frames = (f64::from(timeline.start), f64::from(timeline.end));
        let samples = Plot::new(rect, frames, (0.0, 1.0)).samples(param);
        let keys = keys_of(param).iter().map(|k| k.value);
        Plot::new(rect, frames, fit_range(samples.iter().map(|(_, v)| *v).chain(keys)))
    }

    pub fn x(&self, frame: f64) -> f32 {
        let (start, end) = self.frames;
        self.inner.left() + ((frame - start) / (end - start)) as f32 * self.inner.width()
    }

    pub fn frame(&self, x: f32) -> f64 {
        let (start, end) = self.frames;
        start + f64::from((x - self.inner.left()) / self.inner.width().max(1.0)) * (end - start)
    }

    pub fn y(&self, value: f64) -> f32 {
        let (lo, hi) = self.values;
        self.inner.bottom() - ((value - lo) / (hi - lo)) as f32 * self.inner.height()
    }

    pub fn value(&self, y: f32) -> f64 {
        let (lo, hi) = self.values;
        lo + f64::from((self.inner.bottom() - y) / self.inner.height().max(1.0)) * (hi - lo)
    }

    pub fn pos(&self, frame: f64, value: f64) -> Pos2 {
        Pos2::new(self.x(frame), self.y(value))
    }

    /// What one point of height is worth in value.
    fn value_per_point(&self) -> f64 {
        (self.values.1 - self.values.0) / f64::from(self.inner.height().max(1.0))
    }

    /// The parameter at every point's width across the frames: (frame, value).
    fn samples(&self, param: &Param) -> Vec<(f64, f64)> {
        let n = (self.inner.width().round() as usize).clamp(2, 4096);
        let (start, end) = self.frames;
        (0..=n)
            .map(|i| {
                let frame = start + (end - start) * i as f64 / n as f64;
                (frame, sample(param, frame))
            })
            .collect()
    }
}

/// The index of the key nearest `pos` within `radius` points, if any.
pub fn nearest_key(plot: &Plot, keys: &[ParamKey], pos: Pos2, radius: f32) -> Option<usize> {
    keys.iter()
        .enumerate()
        .map(|(index, k)| (index, plot.pos(f64::from(k.frame), k.value).distance(pos)))
        .filter(|(_, d)| *d <= radius)
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(index, _)| index)
}

fn keys_of(param: &Param) -> &[ParamKey] {
    match param {
        Param::Keys(keys) => keys,
        Param::Constant(_) => &[],
    }
}

/// A value for the plot's labels: short, in the way the fields show numbers.
fn label(value: f64) -> String {
    let a = value.abs();
    if a != 0.0 && !(0.001..10_000.0).contains(&a) { format!("{value:.2e}") } else { format!("{value:.3}") }
}

impl CurveView {
    /// The parameter shown for layer `index`: the chosen one, else [`default_param`].
    pub(in crate::editor) fn shown_for_layer(&self, index: usize, layer: &Layer) -> Option<Curve> {
        match self.chosen {
            Some(Curve::Layer(i, name)) if i == index && param_names(layer).iter().any(|(n, _)| *n == name) => {
                Some(Curve::Layer(index, name))
            }
            _ => default_param(layer).map(|name| Curve::Layer(index, name)),
        }
    }

    /// The number shown for collider `index`: the chosen one, else its first
    /// keyed number, else its first.
    pub(in crate::editor) fn shown_for_collider(&self, index: usize, collider: &Collider) -> Option<Curve> {
        let numbers = collider.numbers();
        match self.chosen {
            Some(Curve::Collider(i, number)) if i == index && numbers.contains(&number) => {
                Some(Curve::Collider(i, number))
            }
            _ => {
                let keyed = numbers.iter().find(|n| matches!(collider.param(**n), Some(Param::Keys(_))));
                keyed.or(numbers.first()).map(|n| Curve::Collider(index, *n))
            }
        }
    }

    /// The number shown for reference `index`: the chosen one, else its first
    /// keyed number, else its centre x.
    pub(in crate::editor) fn shown_for_reference(&self, index: usize, reference: &Reference) -> Curve {
        if let Some(Curve::Reference(i, number)) = self.chosen
            && i == index
        {
            return Curve::Reference(i, number);
        }
        let keyed = ReferenceNumber::ALL.into_iter().find(|n| matches!(n.param(reference), Some(Param::Keys(_))));
        Curve::Reference(index, keyed.unwrap_or(ReferenceNumber::ALL[0]))
    }

    /// The shot number shown: the chosen one, else the camera's first keyed
    /// number (the plate's opacity counted last), else its position x.
    pub(in crate::editor) fn shown_for_shot(&self, scene: &Scene) -> Curve {
        if let Some(Curve::Shot(number)) = self.chosen
            && number.param(scene).is_some()
        {
            return Curve::Shot(number);
        }
        let numbers = ShotNumber::CAMERA.into_iter().chain([ShotNumber::PlateOpacity]);
        let keyed = numbers.clone().find(|n| matches!(n.param(scene), Some(Param::Keys(_))));
        let first = numbers.clone().find(|n| n.param(scene).is_some()).unwrap_or(ShotNumber::CAMERA[0]);
        Curve::Shot(keyed.unwrap_or(first))
    }
}

impl CurveView {
    /// The small curve button beside `curve`'s row (`shown`: its curve is
    /// the one below): shows its curve below.
    pub(in crate::editor) fn button_ui(&mut self, ui: &mut egui::Ui, curve: Curve, shown: bool) {
        let name = match curve {
            Curve::Layer(_, name) => name.to_owned(),
            Curve::Collider(..) | Curve::Reference(..) | Curve::Shot(..) => curve.name(),
        };
        let (rect, response) = ui.allocate_exact_size(Vec2::splat(16.0), Sense::click());
        response.widget_info(|| {
            egui::WidgetInfo::selected(egui::Role::Button, true, shown, format!("Show the {name} curve"))
        });
        let visuals = ui.style().interact(&response);
        if shown {
            ui.painter().rect_filled(rect.shrink(1.0), 3.0, ui.visuals().selection.bg_fill);
        }
        // A little ease-in-out stroke.
        let r = rect.shrink(4.0);
        let points: Vec<Pos2> = (0..=8)
            .map(|i| {
                let t = i as f32 / 8.0;
                let s = t * t * (3.0 - 2.0 * t);
                Pos2::new(r.left() + t * r.width(), r.bottom() - s * r.height())
            })
            .collect();
        ui.painter().add(egui::Shape::line(points, Stroke::new(1.4, visuals.fg_stroke.color)));
        if response.on_hover_text("Show this parameter's curve below").clicked() {
            self.chosen = Some(curve);
        }
    }

    /// The plot of `curve`, with its keys to edit.
    pub(in crate::editor) fn plot_ui(&mut self, ui: &mut egui::Ui, w: &mut Workspace, curve: Curve) {
        let Some(param) = curve.param(w.doc.scene()) else { return };
        let name = match curve {
            Curve::Layer(_, name) => name.to_owned(),
            Curve::Collider(..) | Curve::Reference(..) | Curve::Shot(..) => curve.name(),
        };
        let keys = keys_of(&param).to_vec();
        let timeline = w.doc.scene().timeline.clone();
        ui.add_space(4.0);
        ui.label(format!("{} over time", curve.name()));
        let size = Vec2::new(ui.available_width().max(60.0), HEIGHT);
        let (rect, response) = ui.allocate_exact_size(size, Sense::click_and_drag());
        let what = format!("Curve of {name}");
        response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Canvas, true, &what));

        let drag = self.drag.filter(|d| d.curve == curve && d.key < keys.len());
        let plot = match drag {
            Some(d) => Plot::new(rect, (f64::from(timeline.start), f64::from(timeline.end)), d.values),
            None => Plot::of(rect, &timeline, &param),
        };
        // A press on a key grabs it; dragging moves it in value and (whole) frames.
        if response.drag_started() {
            let origin = ui.input(|i| i.pointer.press_origin());
            self.drag = origin.and_then(|pos| {
                let key = nearest_key(&plot, &keys, pos, GRAB)?;
                let at = plot.pos(f64::from(keys[key].frame), keys[key].value);
                Some(KeyDrag { curve, key, values: plot.values, grab: at - pos })
            });
            if let Some(d) = self.drag {
                self.selected = Some((curve, d.key));
                w.doc.begin_gesture("Move parameter key");
            }
        }
        if let (Some(d), Some(pos)) = (drag, response.interact_pointer_pos())
            && response.dragged()
        {
            // Frames stay on the plot; the value follows the pointer past it (the range holds still).
            let at = pos + d.grab;
            let at = Pos2::new(at.x.clamp(plot.inner.left(), plot.inner.right()), at.y);
            let frame = clamp_frame(&keys, d.key, plot.frame(at.x).round() as i32);
            let value = round_to_resolution(plot.value(at.y), plot.value_per_point());
            if (frame, value) != (keys[d.key].frame, keys[d.key].value) {
                w.apply("Move parameter key", |s| {
                    if let Some(Param::Keys(keys)) = curve.param_mut(s) {
                        keys[d.key].frame = frame;
                        keys[d.key].value = value;
                    }
                });
            }
        }
        if response.drag_stopped() {
            self.drag = None;
            w.end_gesture();
        }

        // Double-click off the keys: a key on the curve there (keying a constant).
        if response.double_clicked()
            && let Some(pos) = response.interact_pointer_pos()
            && nearest_key(&plot, &keys, pos, GRAB).is_none()
        {
            let frame = plot.frame(pos.x).round().clamp(f64::from(timeline.start), f64::from(timeline.end)) as i32;
            if key_at(&param, frame).is_none() {
                w.apply("Add parameter key", |s| {
                    if let Some(p) = curve.param_mut(s) {
                        toggle_key(p, frame);
                    }
                });
                self.selected = key_at(&param_now(&w.doc, curve), frame).map(|k| (curve, k));
            }
        }

        if response.secondary_clicked() {
            let key = response.interact_pointer_pos().and_then(|p| nearest_key(&plot, &keys, p, GRAB));
            self.selected = key.map(|k| (curve, k));
        }
        // Drawn after this frame's edits, so a drag shows where the key is now.
        let param = param_now(&w.doc, curve);
        let keys = keys_of(&param).to_vec();
        let drag = self.drag.filter(|d| d.curve == curve && d.key < keys.len());
        let plot = match drag {
            Some(d) => Plot::new(rect, plot.frames, d.values),
            None => Plot::of(rect, &timeline, &param),
        };
        let hovered = response.hover_pos().and_then(|p| nearest_key(&plot, &keys, p, GRAB));
        let hovered = drag.map(|d| d.key).or(hovered);
        let selected = self.selected.filter(|s| s.0 == curve).map(|s| s.1);
        paint_curve(ui, w.frame(), rect, &plot, &param, [hovered, selected]);
        if let Some(pos) = response.hover_pos() {
            let text = match hovered {
                Some(k) => format!("Key at frame {}: {}", keys[k].frame, label(keys[k].value)),
                None => {
                    let frame = plot.frame(pos.x).round();
                    format!("Frame {frame}: {}", label(sample(&param, frame)))
                }
            };
            response.clone().on_hover_text_at_pointer(text);
        }
        let selected = self.selected.filter(|s| s.0 == curve && s.1 < keys.len());
        if let Some((_, key)) = selected {
            egui::Popup::context_menu(&response)
                .close_behavior(egui::PopupCloseBehavior::CloseOnClickOutside)
                .show(|ui| self.param_key_menu(ui, w, curve, key));
        }
        if keys.is_empty() {
            ui.weak("A constant: key it with its diamond (or double-click the line) to shape it over time here.");
        } else {
            ui.weak("Drag a key; double-click to add one; right-click a key for its easing.");
        }
    }

    /// The right-click menu of key `key` of `curve`: the easing that arrives at it, delete.
    fn param_key_menu(&mut self, ui: &mut egui::Ui, w: &mut Workspace, curve: Curve, key: usize) {
        let param = param_now(&w.doc, curve);
        let Some(current) = keys_of(&param).get(key).cloned() else {
            ui.close();
            return;
        };
        let set_ease = |w: &mut Workspace, label: &str, ease: Ease| {
            w.apply(label, |s| {
                if let Some(Param::Keys(keys)) = curve.param_mut(s) {
                    keys[key].ease = ease;
                }
            });
        };
        ui.strong(format!("Key at frame {}: {}", current.frame, label(current.value)));
        if key > 0 {
            ui.label("Easing arriving at this key");
            for ease in Ease::ALL {
                let ease_name = ease.label();
                let selected = std::mem::discriminant(&current.ease) == std::mem::discriminant(&ease);
                if ui.radio(selected, ease_name).clicked() && !selected {
                    set_ease(w, "Easing", ease);
                }
            }
            if let Ease::Bezier(x1, y1, x2, y2) = current.ease {
                let mut handles = [x1, y1, x2, y2];
                let edit = bezier_handles::edit(ui, &mut handles);
                if edit.began {
                    w.doc.begin_gesture("Bézier handles");
                }
                if edit.changed {
                    let [x1, y1, x2, y2] = handles;
                    set_ease(w, "Bézier handles", Ease::Bezier(x1, y1, x2, y2));
                }
            }
        } else {
            ui.weak("The first key: its value holds before it.");
        }
        ui.separator();
        if ui.button("Go to key").clicked() {
            w.set_frame(f64::from(current.frame));
            ui.close();
        }
        let hint = if keys_of(&param).len() == 1 { "The last key: the parameter becomes a constant" } else { "" };
        let delete = ui.button("Delete key");
        let delete = if hint.is_empty() { delete } else { delete.on_hover_text(hint) };
        if delete.clicked() {
            w.apply("Delete parameter key", |s| {
                if let Some(p) = curve.param_mut(s) {
                    toggle_key(p, current.frame);
                }
            });
            self.selected = None;
            ui.close();
        }
    }
}

/// Draws the plot; `highlighted` keys (hovered or dragged, selected) are filled yellow.
fn paint_curve(ui: &egui::Ui, playhead: f64, rect: Rect, plot: &Plot, param: &Param, highlighted: [Option<usize>; 2]) {
    let painter = ui.painter_at(rect);
    let visuals = ui.visuals();
    let weak = visuals.weak_text_color();
    painter.rect_filled(rect, 3.0, visuals.extreme_bg_color);
    let samples = plot.samples(param);

    // The curve's lowest and highest values, as faint lines with their numbers.
    let (lo, hi) = samples.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), (_, v)| (lo.min(*v), hi.max(*v)));
    let levels = if hi - lo > plot.value_per_point() * 12.0 { vec![hi, lo] } else { vec![hi] };
    for level in &levels {
        let y = plot.y(*level);
        let faint = Stroke::new(1.0, weak.gamma_multiply(0.3));
        painter.line_segment([Pos2::new(rect.left(), y), Pos2::new(rect.right(), y)], faint);
    }

    let points: Vec<Pos2> = samples.iter().map(|&(f, v)| plot.pos(f, v)).collect();
    painter.add(egui::Shape::line(points, Stroke::new(1.5, CURVE_COLOR)));

    let x = plot.x(playhead);
    painter.line_segment(
        [Pos2::new(x, rect.top()), Pos2::new(x, rect.bottom())],
        Stroke::new(2.0, Color32::from_rgb(230, 60, 50)),
    );

    // The numbers on a backing, over the playhead (often at the left edge).
    let font = egui::FontId::proportional(10.0);
    for (n, level) in levels.into_iter().enumerate() {
        let y = plot.y(level);
        let (anchor, at) = if n == 0 {
            (egui::Align2::LEFT_BOTTOM, Pos2::new(rect.left() + 3.0, y - 1.0))
        } else {
            (egui::Align2::LEFT_TOP, Pos2::new(rect.left() + 3.0, y + 1.0))
        };
        let galley = painter.layout_no_wrap(label(level), font.clone(), weak);
        let text_rect = anchor.anchor_size(at, galley.size());
        painter.rect_filled(text_rect.expand(1.0), 2.0, visuals.extreme_bg_color.gamma_multiply(0.85));
        painter.galley(text_rect.min, galley, weak);
    }

    for (index, key) in keys_of(param).iter().enumerate() {
        let active = highlighted.contains(&Some(index));
        let fill = if active { Color32::from_rgb(255, 200, 20) } else { Color32::from_rgb(230, 230, 230) };
        painter.circle(plot.pos(f64::from(key.frame), key.value), HANDLE, fill, Stroke::new(1.0, Color32::BLACK));
    }
}

/// `curve`'s number as the document holds it now.
fn param_now(doc: &Document, curve: Curve) -> Param {
    curve.param(doc.scene()).unwrap_or(Param::Constant(0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn keys(pairs: &[(i32, f64)]) -> Vec<ParamKey> {
        pairs.iter().map(|&(frame, value)| ParamKey { frame, value, ease: Ease::Linear }).collect()
    }

    fn rect() -> Rect {
        Rect::from_min_size(Pos2::new(900.0, 400.0), Vec2::new(250.0, HEIGHT))
    }

    #[test]
    fn frames_values_and_the_screen_map_both_ways() {
        let plot = Plot::new(rect(), (0.0, 120.0), (-0.5, 2.0));
        for (frame, value) in [(0.0, -0.5), (120.0, 2.0), (37.0, 0.3), (-10.0, 5.0)] {
            let pos = plot.pos(frame, value);
            assert!((plot.frame(pos.x) - frame).abs() < 1e-3, "{frame} → {}", plot.frame(pos.x));
            assert!((plot.value(pos.y) - value).abs() < 1e-5, "{value} → {}", plot.value(pos.y));
        }
        assert!(plot.y(2.0) < plot.y(-0.5), "values go up");
        assert!(plot.x(0.0) > rect().left() && plot.x(120.0) < rect().right(), "room for the handles");
    }

    #[test]
    fn degenerate_ranges_still_map_to_finite_points() {
        // start == end, a reversed range, NaN: the plot is one frame wide from the start.
        for frames in [(10.0, 10.0), (10.0, 5.0), (f64::NAN, f64::NAN)] {
            let plot = Plot::new(rect(), frames, (0.0, 1.0));
            assert!(plot.x(10.0).is_finite() && plot.frame(plot.x(10.0)).is_finite(), "{frames:?}");
        }
        // A flat or NaN value range is refit around its value.
        for values in [(0.3, 0.3), (f64::NAN, 1.0), (2.0, 1.0)] {
            let plot = Plot::new(rect(), (0.0, 10.0), values);
            assert!(plot.y(0.3).is_finite() && plot.value(plot.y(0.3)).is_finite(), "{values:?}");
            assert!(plot.values.1 > plot.values.0);
        }
    }

    #[test]
    fn the_range_fits_the_values_with_a_margin() {
        let (lo, hi) = fit_range([0.0, 1.0, 0.5]);
        assert!((lo + MARGIN).abs() < 1e-12 && (hi - 1.0 - MARGIN).abs() < 1e-12);
        // All keys equal: half the value either side; all zero: one either side.
        assert_eq!(fit_range([0.2, 0.2]), (0.1, 0.30000000000000004));
        assert_eq!(fit_range([0.0]), (-1.0, 1.0));
        assert_eq!(fit_range([-4.0, -4.0]), (-6.0, -2.0));
        // Nothing finite: a default range; non-finite values are left out.
        assert_eq!(fit_range([]), (-1.0, 1.0));
        assert_eq!(fit_range([f64::NAN, f64::INFINITY]), (-1.0, 1.0));
        let (lo, hi) = fit_range([f64::NAN, 1.0, 3.0]);
        assert!(lo < 1.0 && hi > 3.0 && lo.is_finite());
    }

    #[test]
    fn a_dragged_key_stays_strictly_between_its_neighbours() {
        let k = keys(&[(0, 0.0), (10, 1.0), (20, 0.0)]);
        assert_eq!(clamp_frame(&k, 1, 15), 15);
        assert_eq!(clamp_frame(&k, 1, 0), 1);
        assert_eq!(clamp_frame(&k, 1, 25), 19);
        assert_eq!(clamp_frame(&k, 0, 50), 9);
        assert_eq!(clamp_frame(&k, 0, -50), -50, "the first key is free to the left");
        assert_eq!(clamp_frame(&k, 2, 1000), 1000, "the last key is free to the right");
        // Neighbours one frame apart: no room, the key stays.
        let tight = keys(&[(0, 0.0), (1, 1.0), (2, 0.0)]);
        assert_eq!(clamp_frame(&tight, 1, 5), 1);
        let extreme = keys(&[(i32::MIN, 0.0), (i32::MAX, 1.0)]);
        assert_eq!(clamp_frame(&extreme, 0, 0), 0);
    }

    #[test]
    fn the_nearest_key_within_reach_is_hit() {
        let k = keys(&[(0, 0.0), (10, 1.0), (11, 1.0)]);
        let plot = Plot::new(rect(), (0.0, 120.0), (0.0, 1.0));
        assert_eq!(nearest_key(&plot, &k, plot.pos(0.0, 0.0) + Vec2::new(2.0, -2.0), GRAB), Some(0));
        // Frames 10 and 11 are two points apart: the nearer one wins.
        assert_eq!(nearest_key(&plot, &k, plot.pos(11.0, 1.0), GRAB), Some(2));
        assert_eq!(nearest_key(&plot, &k, plot.pos(60.0, 0.5), GRAB), None);
        assert_eq!(nearest_key(&plot, &[], plot.pos(0.0, 0.0), GRAB), None);
        let nan = Pos2::new(f32::NAN, f32::NAN);
        assert_eq!(nearest_key(&plot, &k, nan, GRAB), None);
    }

    #[test]
    fn dragged_values_round_to_what_a_point_is_worth() {
        assert_eq!(round_to_resolution(0.123_456, 0.004), 0.123);
        assert_eq!(round_to_resolution(0.123_456, 0.000_4), 0.1235);
        assert_eq!(round_to_resolution(1234.5, 20.0), 1230.0);
        assert_eq!(round_to_resolution(-0.25, 0.5), -0.3);
        assert_eq!(round_to_resolution(0.7, 0.0), 0.7, "no resolution: as is");
        assert!(round_to_resolution(f64::NAN, 0.1).is_nan());
    }

    #[test]
    fn the_view_shows_the_first_keyed_parameter_else_the_first() {
        let wave = |magnitude: Param| {
            Layer::Wave(crate::scene::Wave {
                name: String::new(),
                enabled: true,
                weight: Param::Constant(1.0),
                magnitude,
                frequency: Param::Constant(1.0),
                phase: Param::Constant(0.0),
                speed: Param::Constant(1.0),
                direction_deg: Param::Constant(0.0),
                axis: crate::scene::WaveAxis::Normal,
                falloff: Param::Constant(1.0),
            })
        };
        assert_eq!(default_param(&wave(Param::Constant(0.1))), Some("weight"));
        let keyed = wave(Param::Keys(keys(&[(0, 0.0), (10, 1.0)])));
        assert_eq!(default_param(&keyed), Some("magnitude"));
        let mut view = CurveView::default();
        assert_eq!(view.shown_for_layer(0, &keyed), Some(Curve::Layer(0, "magnitude")));
        view.chosen = Some(Curve::Layer(0, "phase"));
        assert_eq!(view.shown_for_layer(0, &keyed), Some(Curve::Layer(0, "phase")));
        assert_eq!(
            view.shown_for_layer(1, &keyed),
            Some(Curve::Layer(1, "magnitude")),
            "a choice belongs to its layer"
        );
    }

    #[test]
    fn a_collider_shows_its_first_keyed_number_else_its_first_or_the_chosen_one() {
        let mut ball: Collider = ron::from_str("Sphere((center: (0.0, 1.0, 0.0), radius: 0.3))").unwrap();
        let view = CurveView::default();
        let first = ball.numbers()[0];
        assert_eq!(view.shown_for_collider(2, &ball), Some(Curve::Collider(2, first)));
        let radius = *ball.numbers().last().unwrap();
        if let Some(p) = ball.param_mut(radius) {
            *p = Param::Keys(keys(&[(0, 0.3), (10, 0.5)]));
        }
        assert_eq!(view.shown_for_collider(2, &ball), Some(Curve::Collider(2, radius)));
        let mut scene = crate::scene::parse(crate::editor::DEFAULT_SCENE, "magic_carpet.ron").unwrap();
        scene.colliders = vec![ball];
        let curve = Curve::Collider(0, radius);
        assert_eq!(curve.name(), "radius");
        assert_eq!(curve.param(&scene), Some(Param::Keys(keys(&[(0, 0.3), (10, 0.5)]))));
        assert_eq!(Curve::Collider(1, radius).param(&scene), None, "no such collider");
    }

    #[test]
    fn the_plot_of_a_parameter_fits_its_curve_and_keys() {
        let timeline = Timeline { start: 0, end: 100, ..Timeline::default() };
        let back = Param::Keys(vec![
            ParamKey { frame: 0, value: 0.0, ease: Ease::Linear },
            ParamKey { frame: 100, value: 1.0, ease: Ease::Back },
        ]);
        let plot = Plot::of(rect(), &timeline, &back);
        assert!(plot.values.0 < -0.05 && plot.values.1 > 1.05, "the overshoot is in view: {:?}", plot.values);
        let flat = Plot::of(rect(), &timeline, &Param::Constant(0.03));
        assert!(flat.values.0 < 0.03 && flat.values.1 > 0.03);
    }

    #[test]
    fn a_reference_shows_its_first_keyed_number_else_its_centre_x_or_the_chosen_one() {
        let mut reference: Reference = ron::from_str(r#"(file: "hero.glb")"#).unwrap();
        let mut view = CurveView::default();
        assert_eq!(view.shown_for_reference(1, &reference), Curve::Reference(1, ReferenceNumber::Center(0)));
        reference.scale = Param::Keys(keys(&[(0, 1.0), (10, 2.0)]));
        assert_eq!(view.shown_for_reference(1, &reference), Curve::Reference(1, ReferenceNumber::Scale));
        view.chosen = Some(Curve::Reference(1, ReferenceNumber::Rotation(1)));
        assert_eq!(view.shown_for_reference(1, &reference), Curve::Reference(1, ReferenceNumber::Rotation(1)));
        assert_eq!(view.shown_for_reference(0, &reference), Curve::Reference(0, ReferenceNumber::Scale), "its own");
        let labels: Vec<String> = ReferenceNumber::ALL.iter().map(|n| n.label()).collect();
        assert_eq!(labels, ["centre x", "centre y", "centre z", "rotation x", "rotation y", "rotation z", "scale"]);
        let mut scene = crate::scene::parse(crate::editor::DEFAULT_SCENE, "magic_carpet.ron").unwrap();
        scene.references = vec![reference];
        let curve = Curve::Reference(0, ReferenceNumber::Rotation(2));
        if let Some(p) = curve.param_mut(&mut scene) {
            *p = Param::Constant(90.0);
        }
        assert_eq!(scene.references[0].rotation_deg.2, Param::Constant(90.0));
        assert_eq!(curve.param(&scene), Some(Param::Constant(90.0)));
        assert_eq!(Curve::Reference(1, ReferenceNumber::Scale).param(&scene), None, "no such reference");
    }
}
