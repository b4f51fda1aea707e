//! The layer stack on the right: add Sway / Wave / Gusts / Follow-through,
//! rename, reorder, enable, and every parameter with a key toggle (a diamond) beside
//! it. Values show what the parameter is at the playhead; editing a keyed
//! parameter keys it there.

use eframe::egui;

use crate::editor::number_field::number_field;

use super::add_menu::add_menu_ui;
use super::list_row;
use crate::animate::track::sample;
use crate::editor::icons::{Icon, icon_button};
use crate::editor::param_edit::{key_at, param_mut, param_names, set_at_keying, toggle_key};
use crate::editor::timeline::curve_view::{Curve, CurveView};
use crate::editor::workspace::Workspace;
use crate::scene::{FollowThrough, Layer, Param, WaveAxis};

/// A new layer of `kind` with gentle defaults that show its effect at once
/// (the schema's start values); an unknown kind gives a follow-through.
pub(in crate::editor) fn new_layer(kind: &str) -> Layer {
    Layer::with_start_values(kind).unwrap_or_else(|| Layer::FollowThrough(FollowThrough::with_start_values()))
}

/// The Layers panel's own state: a row dragged by its grip, and the curve view.
#[derive(Default)]
pub struct LayersPanel {
    /// The layer being dragged by its grip in the layer list.
    layer_drag: Option<usize>,
    curve: CurveView,
}

impl LayersPanel {
    pub(in crate::editor) fn ui(&mut self, ui: &mut egui::Ui, w: &mut Workspace) {
        ui.heading("Layers");
        add_menu_ui(ui, "Add layer", |ui| {
            for (kind, label) in
                [("Sway", "Sway"), ("Wave", "Wave"), ("Gusts", "Gusts"), ("FollowThrough", "Follow-through")]
            {
                if ui.button(label).clicked() {
                    let at = w.doc.scene().layers.len();
                    w.apply("Add layer", |s| s.layers.push(new_layer(kind)));
                    w.session.select_layer(Some(at));
                }
            }
        });
        ui.weak("Applied top to bottom.");
        let layers = w.doc.scene().layers.clone();
        let mut rows = Vec::with_capacity(layers.len());
        let mut dropped = false;
        for (index, layer) in layers.iter().enumerate() {
            let row = ui.horizontal(|ui| {
                let grip = icon_button(ui, Icon::Grip, true, &format!("Drag {} to reorder", layer.label(index)));
                let grip = grip.on_hover_cursor(egui::CursorIcon::Grab);
                if grip.drag_started() {
                    self.layer_drag = Some(index);
                }
                dropped |= grip.drag_stopped();
                let mut enabled = layer.enabled();
                let checkbox = ui.checkbox(&mut enabled, "").on_hover_text("Enabled");
                let label = layer.label(index);
                checkbox.widget_info(|| {
                    egui::WidgetInfo::selected(egui::Role::CheckBox, true, enabled, format!("Enable {label}"))
                });
                if checkbox.changed() {
                    w.apply("Enable layer", |s| *s.layers[index].enabled_mut() = enabled);
                }
                let label = layer.label(index);
                let last = index + 1 == layers.len();
                let up = icon_button(ui, Icon::Up, index > 0, &format!("Move {label} up")).on_hover_text("Earlier");
                if up.clicked() {
                    move_layer(w, index, index - 1);
                }
                let down = icon_button(ui, Icon::Down, !last, &format!("Move {label} down")).on_hover_text("Later");
                if down.clicked() {
                    move_layer(w, index, index + 1);
                }
                let mut solo = w.session.solo_layer() == Some(index);
                let solo_toggle = ui.toggle_value(&mut solo, "S").on_hover_text("Solo: show this layer alone");
                solo_toggle.widget_info(|| {
                    egui::WidgetInfo::selected(egui::Role::Switch, true, solo, format!("Solo {label}"))
                });
                if solo_toggle.changed() {
                    w.session.solo(solo.then_some(index));
                }
                let selected = w.session.selected_layer() == Some(index);
                let (title, remove) =
                    list_row::title_and_remove_ui(ui, selected, title(layer, index), "Remove the layer");
                if title.on_hover_text(&label).clicked() {
                    w.session.select_layer(if selected { None } else { Some(index) });
                }
                remove.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Button, true, format!("Remove {label}")));
                if remove.clicked() {
                    w.apply("Remove layer", |s| {
                        s.layers.remove(index);
                    });
                    w.session.layer_removed();
                }
            });
            rows.push(row.response.rect);
        }
        self.layer_drop(ui, w, &rows, dropped);
        let Some(index) = w.session.selected_layer().filter(|i| *i < layers.len()) else { return };
        ui.separator();
        self.layer_details(ui, w, index, &layers[index]);
    }

    /// While a row is dragged by its grip: a line where it would land; on release, the move.
    fn layer_drop(&mut self, ui: &mut egui::Ui, w: &mut Workspace, rows: &[egui::Rect], dropped: bool) {
        let Some(from) = self.layer_drag.filter(|i| *i < rows.len()) else {
            self.layer_drag = None;
            return;
        };
        let Some(pointer) = ui.input(|i| i.pointer.interact_pos()) else { return };
        let centers: Vec<f32> = rows.iter().map(|r| r.center().y).collect();
        let slot = drop_slot(&centers, pointer.y);
        let y = match slot {
            0 => rows[0].top(),
            s if s == rows.len() => rows[s - 1].bottom(),
            s => (rows[s - 1].bottom() + rows[s].top()) / 2.0,
        };
        let x = rows[0].x_range();
        ui.painter().hline(x, y, egui::Stroke::new(2.0, ui.visuals().selection.stroke.color));
        if dropped {
            self.layer_drag = None;
            move_layer(w, from, moved_to(from, slot));
        }
    }

    fn layer_details(&mut self, ui: &mut egui::Ui, w: &mut Workspace, index: usize, layer: &Layer) {
        let frame = w.frame().round() as i32;
        let mut name = layer.name().to_owned();
        ui.horizontal(|ui| {
            let label = ui.label("Name").id;
            // An unnamed layer shows the title the list gives it, greyed, until it is named.
            let field = egui::TextEdit::singleline(&mut name).desired_width(140.0).hint_text(title(layer, index));
            let edit = ui.add(field).labelled_by(label);
            if edit.changed() {
                w.apply("Rename layer", |s| *s.layers[index].name_mut() = name.clone());
            }
        });
        ui.weak(format!("Values at frame {frame}. The diamond keys a parameter here (filled: keyed at this frame)."));
        let shown = self.curve.shown_for_layer(index, layer);
        // Columns no wider than their buttons: the first frame's wide guess
        // of the last column would widen the panel for good.
        egui::Grid::new("layer parameters").num_columns(4).min_col_width(16.0).show(ui, |ui| {
            for (param, unit) in param_names(layer) {
                let mut copy = layer.clone();
                let Some(current) = param_mut(&mut copy, param) else { continue };
                let keyed_here = key_at(current, frame).is_some();
                let keyed = matches!(current, Param::Keys(_));
                let mut value = sample(current, f64::from(frame));
                let label = ui.label(param.replace('_', " ")).id;
                let drag = number_field(ui.ctx(), &mut value).speed(0.01).max_decimals(4);
                let drag = if unit.is_empty() { drag } else { drag.suffix(format!(" {unit}")) };
                let response = ui.add(drag).labelled_by(label);
                let hint = if keyed {
                    "Keyed: click to add or remove the key at this frame"
                } else {
                    "Key this parameter here"
                };
                let toggle = icon_button(ui, Icon::Diamond { filled: keyed_here }, true, &format!("Key {param}"));
                let toggle = toggle.on_hover_text(hint);
                let curve = Curve::Layer(index, param);
                self.curve.button_ui(ui, curve, shown == Some(curve));
                ui.end_row();
                let what = format!("Layer {}", param.replace('_', " "));
                if response.drag_started() {
                    w.doc.begin_gesture(&what);
                }
                if response.changed() {
                    let auto_key = w.session.auto_key();
                    w.apply(&what, |s| {
                        if let Some(p) = param_mut(&mut s.layers[index], param) {
                            set_at_keying(p, frame, value, auto_key);
                        }
                    });
                }
                if toggle.clicked() {
                    w.apply("Key parameter", |s| {
                        if let Some(p) = param_mut(&mut s.layers[index], param) {
                            toggle_key(p, frame);
                        }
                    });
                }
            }
        });
        if let Some(curve) = shown {
            self.curve.plot_ui(ui, w, curve);
        }
        layer_vectors(ui, w, index, layer);
    }
}

/// Moves layer `from` to position `to` as one undo step; selection and solo follow their layers.
fn move_layer(w: &mut Workspace, from: usize, to: usize) {
    if from == to || to >= w.doc.scene().layers.len() {
        return;
    }
    w.apply("Reorder layers", |s| {
        let layer = s.layers.remove(from);
        s.layers.insert(to, layer);
    });
    w.session.layer_moved(from, to);
}

/// The layer's fixed settings: directions, the wave's axis, the gusts' octaves and seed.
fn layer_vectors(ui: &mut egui::Ui, w: &mut Workspace, index: usize, layer: &Layer) {
    let direction = match layer {
        Layer::Sway(l) => Some(l.direction),
        Layer::Gusts(l) => Some(l.direction),
        _ => None,
    };
    if let Some(mut d) = direction {
        ui.horizontal(|ui| {
            ui.label("Direction");
            let mut changed = false;
            for (value, axis) in [(&mut d.0, "x"), (&mut d.1, "y"), (&mut d.2, "z")] {
                let field = ui.add(number_field(ui.ctx(), value).speed(0.01).max_decimals(3));
                changed |= field.accessible_name(format!("Direction {axis}")).changed();
            }
            if changed {
                w.apply("Layer direction", |s| match &mut s.layers[index] {
                    Layer::Sway(l) => l.direction = d,
                    Layer::Gusts(l) => l.direction = d,
                    _ => {}
                });
            }
        });
    }
    if let Layer::Wave(wave) = layer {
        let mut fixed = matches!(wave.axis, WaveAxis::Fixed(_));
        let mut axis = match wave.axis {
            WaveAxis::Fixed(v) => v,
            WaveAxis::Normal => (0.0, 1.0, 0.0),
        };
        ui.horizontal(|ui| {
            let mut changed =
                ui.checkbox(&mut fixed, "Fixed axis").on_hover_text("Else along the surface normal").changed();
            if fixed {
                for (value, name) in [(&mut axis.0, "x"), (&mut axis.1, "y"), (&mut axis.2, "z")] {
                    let field = ui.add(number_field(ui.ctx(), value).speed(0.01).max_decimals(3));
                    changed |= field.accessible_name(format!("Axis {name}")).changed();
                }
            }
            if changed {
                let new = if fixed { WaveAxis::Fixed(axis) } else { WaveAxis::Normal };
                w.apply("Wave axis", |s| {
                    if let Layer::Wave(l) = &mut s.layers[index] {
                        l.axis = new;
                    }
                });
            }
        });
    }
    if let Layer::Gusts(gusts) = layer {
        let (mut octaves, mut seed) = (gusts.octaves, gusts.seed);
        ui.horizontal(|ui| {
            let label = ui.label("Octaves").id;
            let field = number_field(ui.ctx(), &mut octaves).range(1..=crate::scene::MAX_GUST_OCTAVES);
            let a = ui.add(field).labelled_by(label).changed();
            let label = ui.label("Seed").id;
            let b = ui.add(number_field(ui.ctx(), &mut seed)).labelled_by(label).changed();
            if a || b {
                w.apply("Gusts", |s| {
                    if let Layer::Gusts(l) = &mut s.layers[index] {
                        l.octaves = octaves;
                        l.seed = seed;
                    }
                });
            }
        });
    }
}

/// Where a row dropped at height `y` goes, as a gap between rows: 0 above the
/// first, `centers.len()` below the last. Rows are in order, top to bottom.
fn drop_slot(centers: &[f32], y: f32) -> usize {
    centers.iter().take_while(|c| **c < y).count()
}

/// The index a row taken from `from` ends up at when dropped into gap `slot`.
fn moved_to(from: usize, slot: usize) -> usize {
    if slot > from { slot - 1 } else { slot }
}

/// The layer's name in the list, or for an unnamed one its kind and place ("Wave 4").
fn title(layer: &Layer, index: usize) -> String {
    if !layer.name().is_empty() {
        return layer.name().to_owned();
    }
    let kind = if layer.kind() == "FollowThrough" { "Follow-through" } else { layer.kind() };
    format!("{kind} {}", index + 1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::editor::session::index_after_move;

    #[test]
    fn a_drop_lands_in_the_gap_under_the_pointer() {
        let centers = [10.0, 30.0, 50.0];
        assert_eq!(drop_slot(&centers, 0.0), 0);
        assert_eq!(drop_slot(&centers, 25.0), 1);
        assert_eq!(drop_slot(&centers, 99.0), 3);
        assert_eq!(drop_slot(&centers, f32::NAN), 0, "no pointer height: the top, never a panic");
        assert_eq!(drop_slot(&[], 5.0), 0);
    }

    #[test]
    fn dropping_next_to_itself_is_no_move() {
        assert_eq!(moved_to(1, 1), 1);
        assert_eq!(moved_to(1, 2), 1);
        assert_eq!(moved_to(0, 3), 2);
        assert_eq!(moved_to(2, 0), 0);
    }

    #[test]
    fn other_layers_keep_their_identity_through_a_move() {
        for (from, to) in [(0, 3), (3, 0), (1, 2), (2, 1), (2, 2)] {
            let mut order: Vec<usize> = (0..4).collect();
            let moved = order.remove(from);
            order.insert(to, moved);
            for original in 0..4 {
                let now = index_after_move(original, from, to);
                assert_eq!(order[now], original, "layer {original} after moving {from} to {to}");
            }
        }
    }
}
