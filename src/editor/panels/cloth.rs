//! The Cloth panel: the cloth's size, grid, texture and stretch limit (its toon
//! style's look in `cloth_toon_rows`), the fabric of the key
//! being edited, its pins in the 2D grid editor, exact pin positions, and what
//! holds the selected pins to a reference (`pin_attach_rows`).
//! Every change goes through the document, so it is undoable and validated.

use eframe::egui::{self, Response};
use glam::DVec3;

use crate::editor::number_field::{number_field, number_slider};

use super::cloth_toon_rows::toon_section_ui;
use super::grid_editor::GridAction;
use super::grid_editor::GridEditor;
use super::node_picker::NodePicker;
use super::pin_attach_rows::attachment_ui;
use crate::editor::attach;
use crate::editor::edits;
use crate::editor::pin_clipboard;
use crate::editor::workspace::Workspace;
use crate::scene::{
    ClothTexture, Follow, Key, MAX_ELASTICITY, MAX_FRICTION, MAX_GRID_SIDE, MAX_RELAX_ITERATIONS, MAX_RELAX_TOLERANCE,
    MAX_STRETCH_LIMIT, MAX_THICKNESS_M, MIN_ELASTICITY, MIN_GRID_SIDE, Pin, Scene,
};
use crate::shape::contact::crossing_advice;

/// What clicks and drags do in the grid editor.
pub(in crate::editor) const GRID_EDITOR_HINT: &str =
    "Click: pin, or select a pin · Shift: add · Ctrl: toggle · Drag: box-select · Delete: unpin";

/// Width of the "Add key at N" button, points: wide enough for any frame, so the row holds still.
const ADD_KEY_WIDTH: f32 = 96.0;

/// The Cloth panel's own state: the grid editor's view, the node list of
/// "Attach to node…" and that of "Follow node…".
#[derive(Default)]
pub struct ClothPanel {
    grid_editor: GridEditor,
    node_picker: NodePicker,
    follow_picker: NodePicker,
}

impl ClothPanel {
    pub(in crate::editor) fn ui(&mut self, ui: &mut egui::Ui, w: &mut Workspace) {
        egui::ScrollArea::vertical().show(ui, |ui| {
            ui.strong("Cloth");
            cloth_section(ui, w);
            toon_section_ui(ui, w);
            self.follow_ui(ui, w);
            ui.separator();
            fabric_section(ui, w);
            ui.separator();
            self.pins_section(ui, w);
        });
    }

    /// What the cloth follows: a node of a reference (its keys carried as the
    /// node moves), chosen from the node list, or nothing. Greyed in a scene
    /// without references, so adding one moves nothing below.
    fn follow_ui(&mut self, ui: &mut egui::Ui, w: &mut Workspace) {
        let scene = w.doc.scene();
        let has_references = !scene.references.is_empty();
        let follow = scene.follow.clone();
        let mut picker_button = None;
        ui.horizontal(|ui| {
            ui.label("Follows");
            let shown = match &follow {
                Some(f) => format!("{} · {}", f.reference, f.node),
                None => "nothing".to_owned(),
            };
            ui.monospace(shown);
            let hint = "Carry the whole cloth with a node (a joint) of a reference: each key is where the node \
                        is at the key's frame, and the cloth moves as the node does";
            let button = egui::Button::new("Follow node…").selected(self.follow_picker.is_open());
            let response = ui.add_enabled(has_references, button).on_hover_text(hint);
            let response =
                response.on_disabled_hover_text("Add a reference (References panel) to follow one of its nodes");
            if response.clicked() {
                self.follow_picker.toggle();
            }
            picker_button = Some(response);
            let stop = ui.add_enabled(follow.is_some(), egui::Button::new("Stop"));
            if stop.on_hover_text("The cloth no longer follows the node").clicked() {
                w.apply("Stop following", |s| s.follow = None);
            }
        });
        let references = w.doc.scene().references.clone();
        if let Some(button) = picker_button
            && let Some((index, node)) = self.follow_picker.pick_ui(ui, &button, &references)
        {
            let reference = references[index].name.clone();
            w.apply("Follow node", |s| s.follow = Some(Follow { reference, node }));
        }
    }

    fn pins_section(&mut self, ui: &mut egui::Ui, w: &mut Workspace) {
        let index = w.edit_key_index();
        let scene = w.doc.scene().clone();
        let key = &scene.keys[index];
        // How to use the grid editor is said in the status bar while it is hovered.
        ui.strong(format!("Pins ({})", key.pins.len())).on_hover_text(GRID_EDITOR_HINT);
        let (actions, hovered) = self.grid_editor.show(
            ui,
            &scene.cloth,
            key,
            w.session.selection(),
            w.session.hovered().or(w.session.grid_hovered()),
        );
        w.session.hover_grid(hovered);
        for action in actions {
            match action {
                GridAction::Pin(point, how) => w.pin_here(point, how),
                GridAction::PickPin(point, how) => w.session.pick_pins(&[point], how),
                GridAction::SelectBox { pins, how } => w.session.pick_pins(&pins, how),
                GridAction::ClickNothing(how) => w.session.click_on_nothing(how),
            }
        }
        let rows = ui.scope(|ui| selected_pin_fields(ui, w, &mut self.node_picker)).response.rect;
        // A taller editor never pushes the pin rows out of view: the panel
        // scrolls instead.
        if self.grid_editor.is_resizing() {
            ui.scroll_to_rect(rows, None);
        }
    }
}

/// Applies `change` to the key being edited when `response` changed the
/// value (with auto-key off a key, to a new key at the playhead); a drag on
/// the widget is one undo step.
fn key_field(w: &mut Workspace, response: &Response, label: &str, change: impl FnOnce(&mut Key)) {
    if response.drag_started() {
        w.doc.begin_gesture(label);
    }
    if response.changed()
        && let Some(index) = w.key_to_edit(label)
    {
        w.apply(label, |s| change(&mut s.keys[index]));
    }
}

/// Moves pins of the key being edited when `response` changed the value (with
/// auto-key off a key, of a new key at the playhead) to where `moves` puts
/// them, given the scene and that key's index; attached pins as
/// [`Workspace::move_pins`] moves them. A drag on the widget is one undo step.
fn pins_field(
    w: &mut Workspace,
    response: &Response,
    label: &str,
    moves: impl FnOnce(&Scene, usize) -> Vec<((u32, u32), DVec3)>,
) {
    if response.drag_started() {
        w.doc.begin_gesture(label);
    }
    if response.changed()
        && let Some(index) = w.key_to_edit(label)
    {
        let moves = moves(w.doc.scene(), index);
        attach::move_pins(w, label, index, &moves);
    }
}

/// Applies `change` when `response` changed the value; a drag on the widget is one undo step.
fn field(w: &mut Workspace, response: &Response, label: &str, change: impl FnOnce(&mut Scene)) {
    if response.drag_started() {
        w.doc.begin_gesture(label);
    }
    if response.changed() {
        w.apply(label, change);
    }
}

fn cloth_section(ui: &mut egui::Ui, w: &mut Workspace) {
    let cloth = w.doc.scene().cloth.clone();
    egui::Grid::new("cloth").num_columns(2).show(ui, |ui| {
        // Width and height share a row, so the pins below stay in reach on a laptop's height.
        let (mut width, mut height) = cloth.size;
        let label = ui.label("Width").id;
        ui.horizontal(|ui| {
            let r = ui
                .add(number_field(ui.ctx(), &mut width).range(0.01..=1000.0).speed(0.01).suffix(" m"))
                .labelled_by(label);
            field(w, &r, "Cloth size", |s| s.cloth.size.0 = width);
            let label = ui.label("Height").id;
            let r = ui
                .add(number_field(ui.ctx(), &mut height).range(0.01..=1000.0).speed(0.01).suffix(" m"))
                .labelled_by(label);
            field(w, &r, "Cloth size", |s| s.cloth.size.1 = height);
        });
        ui.end_row();

        let (mut cols, mut rows) = cloth.grid;
        ui.label("Grid");
        ui.horizontal(|ui| {
            let range = MIN_GRID_SIDE..=MAX_GRID_SIDE;
            let r = ui.add(number_field(ui.ctx(), &mut cols).range(range.clone()).speed(0.2)).on_hover_text("Columns");
            r.widget_info(|| egui::WidgetInfo::labeled(egui::Role::SpinButton, true, "Grid columns"));
            field(w, &r, "Grid", |s| edits::set_grid(s, (cols, s.cloth.grid.1)));
            ui.label("×");
            let r = ui.add(number_field(ui.ctx(), &mut rows).range(range).speed(0.2)).on_hover_text("Rows");
            r.widget_info(|| egui::WidgetInfo::labeled(egui::Role::SpinButton, true, "Grid rows"));
            field(w, &r, "Grid", |s| edits::set_grid(s, (s.cloth.grid.0, rows)));
        });
        ui.end_row();

        let label = ui.label("Texture").id;
        let mut texture = cloth.texture;
        let combo = egui::ComboBox::from_id_salt("texture").selected_text(format!("{texture:?}")).show_ui(ui, |ui| {
            for option in [ClothTexture::Plain, ClothTexture::Carpet, ClothTexture::Checker] {
                ui.selectable_value(&mut texture, option, format!("{option:?}"));
            }
        });
        let _ = combo.response.labelled_by(label);
        if texture != cloth.texture {
            w.apply("Texture", |s| s.cloth.texture = texture);
        }
        ui.end_row();

        let label = ui.label("Stretch limit").id;
        let mut percent = cloth.stretch_limit * 100.0;
        let r = ui
            .add(number_field(ui.ctx(), &mut percent).range(0.0..=MAX_STRETCH_LIMIT * 100.0).speed(0.1).suffix(" %"))
            .labelled_by(label)
            .on_hover_text(
                "How much longer than its rest length the layers may make any edge of the cloth; \
                 past it the cloth bends instead of stretching. 0 turns the limit off.",
            );
        field(w, &r, "Stretch limit", |s| s.cloth.stretch_limit = percent / 100.0);
        ui.end_row();
    });
}

fn fabric_section(ui: &mut egui::Ui, w: &mut Workspace) {
    let index = w.edit_key_index();
    let key = w.doc.scene().keys[index].clone();
    // One row on a key or off it, so nothing below moves while scrubbing. Off a key, edits
    // change the key back at its own frame: the button offers a key here instead.
    let playhead = w.frame().round() as i32;
    let on_key = playhead == key.frame;
    ui.horizontal(|ui| {
        let heading = format!("Fabric · key {}", key.frame);
        let whose = "Fabric and pins belong to the rest-shape key in effect at the playhead";
        let hint = if on_key {
            format!("{whose}: edits change this key.")
        } else {
            format!("{whose}: edits change key {}, back at its frame.", key.frame)
        };
        ui.strong(heading).on_hover_text(hint);
        let button =
            egui::Button::new(format!("Add key at {playhead}")).small().min_size(egui::vec2(ADD_KEY_WIDTH, 0.0));
        let hint = "K: a rest-shape key at the playhead, from the current pose";
        if ui.add_enabled(!on_key, button).on_hover_text(hint).on_disabled_hover_text(hint).clicked() {
            w.add_key_here();
        }
    });
    egui::Grid::new("fabric").num_columns(2).show(ui, |ui| {
        let mut elasticity = key.elasticity;
        let hint = "How much longer the fabric is than its grid: 1 is taut, more sags.";
        let label = ui.label("Elasticity").on_hover_text(hint).id;
        let slider = number_slider(ui.ctx(), &mut elasticity, MIN_ELASTICITY..=MAX_ELASTICITY.min(3.0)).max_decimals(3);
        let r = ui.add(slider).labelled_by(label);
        key_field(w, &r, "Elasticity", |k| k.elasticity = elasticity);
        ui.end_row();

        let mut stiffness = key.stiffness;
        let label = ui.label("Stiffness").on_hover_text("Bending resistance: 0 folds freely, 1 curves gently.").id;
        let r = ui.add(number_slider(ui.ctx(), &mut stiffness, 0.0..=1.0).max_decimals(3)).labelled_by(label);
        key_field(w, &r, "Stiffness", |k| k.stiffness = stiffness);
        ui.end_row();

        let mut iterations = key.relax.iterations;
        let label = ui.label("Iterations").on_hover_text("Relaxation sweeps per grid level, at most.").id;
        let drag = number_field(ui.ctx(), &mut iterations).range(1..=MAX_RELAX_ITERATIONS).speed(1.0);
        let r = ui.add(drag).labelled_by(label);
        key_field(w, &r, "Relaxation iterations", |k| k.relax.iterations = iterations);
        ui.end_row();

        let mut tolerance = key.relax.tolerance;
        let hint = "Relaxation stops once no point moves more than this × the spacing in a sweep.";
        let label = ui.label("Tolerance").on_hover_text(hint).id;
        let slider = number_slider(ui.ctx(), &mut tolerance, 1e-9..=MAX_RELAX_TOLERANCE.min(0.1)).logarithmic(true);
        let r = ui.add(slider.custom_formatter(|v, _| format!("{v:.1e}"))).labelled_by(label);
        key_field(w, &r, "Relaxation tolerance", |k| k.relax.tolerance = tolerance);
        ui.end_row();

        // Thickness also keeps the cloth's own folds apart, so it is there in every scene.
        let mut thickness_mm = key.thickness * 1000.0;
        let hint = "How far the cloth keeps from the colliders' surfaces (a collider may set its own) and between its own \
            folds; 0 lets a fold pass through the cloth.";
        let label = ui.label("Thickness").on_hover_text(hint).id;
        let field = number_field(ui.ctx(), &mut thickness_mm).range(0.0..=MAX_THICKNESS_M * 1000.0).speed(0.1).suffix(" mm");
        let r = ui.add(field).labelled_by(label);
        key_field(w, &r, "Thickness", |k| k.thickness = thickness_mm / 1000.0);
        ui.end_row();

        // Greyed without colliders (not removed), so adding one moves nothing below.
        let has_colliders = !w.doc.scene().colliders.is_empty();
        let mut friction = key.friction;
        let hint = "How the cloth holds where it rests on a collider: 0 slides off, 1 holds well.";
        let label = ui.label("Friction").on_hover_text(hint).id;
        let slider = number_slider(ui.ctx(), &mut friction, 0.0..=MAX_FRICTION.min(2.0)).max_decimals(2);
        let r = ui.add_enabled(has_colliders, slider).labelled_by(label);
        let r = r.on_disabled_hover_text("The scene has no colliders to rest on (Colliders panel)");
        key_field(w, &r, "Friction", |k| k.friction = friction);
        ui.end_row();

        placement_rows_ui(ui, w, &key, has_colliders);
    });
    // One line whatever the verdict (the whole of it on hover), so the pins below hold still.
    let shape = w.shown_key_shape();
    let (mut text, mut color, mut full) = match shape.as_ref().map(|shape| shape.rest.relax_report) {
        Some(report) if report.converged => {
            (report.summary(), ui.visuals().weak_text_color(), format!("Rest shape {}", report.verdict()))
        }
        Some(report) => (report.summary(), ui.visuals().warn_fg_color, format!("Rest shape {}", report.verdict())),
        None => ("Relaxing…".to_owned(), ui.visuals().weak_text_color(), "The rest shape is being relaxed.".to_owned()),
    };
    if let Some(shape) = &shape
        && let Some(crossings @ 1..) = shape.self_crossings_if_counted()
    {
        color = ui.visuals().warn_fg_color;
        let settled = shape.rest.relax_report.converged;
        if settled && key.thickness > 0.0 {
            // Settled through itself, with a thickness to keep: not settled.
            text = "NOT settled: passes through itself".to_owned();
            full = format!("Rest shape {}", shape.verdict(key.thickness));
        } else {
            let edges = if crossings == 1 { "edge crosses" } else { "edges cross" };
            text = format!("Passes through itself · {text}");
            let advice = crossing_advice(key.thickness, settled);
            full = format!("The rest shape passes through itself: {crossings} {edges} the cloth; {advice}.\n{full}");
        }
    }
    ui.add(egui::Label::new(egui::RichText::new(text).color(color)).truncate()).on_hover_text(full);
}

/// Where a key without pins drops from and how it is turned; shown (greyed)
/// for keys with pins and in scenes without colliders too, so the panel
/// holds still while scrubbing and when a collider is added.
fn placement_rows_ui(ui: &mut egui::Ui, w: &mut Workspace, key: &Key, has_colliders: bool) {
    let placement = key.placement_or_default();
    let unpinned = key.pins.is_empty() && has_colliders;
    let hint = if unpinned {
        "The key has no pins: the cloth starts flat here (u along X, v along Z) and drops onto the colliders."
    } else if has_colliders {
        "For keys without pins: unpin every pin and the cloth drops from here onto the colliders."
    } else {
        "For keys without pins in a scene with colliders: the cloth drops from here onto them."
    };
    let rows = [
        ("Drop from", "Placement centre", placement.center, " m", 0.005),
        ("Turn", "Placement rotation", placement.rotation_deg, "°", 0.5),
    ];
    for (row, (name, undo_label, values, suffix, speed)) in rows.into_iter().enumerate() {
        let label = ui.label(name).on_hover_text(hint).id;
        ui.add_enabled_ui(unpinned, |ui| {
            ui.horizontal(|ui| {
                let mut edited = values;
                for (axis, value) in [("X", &mut edited.0), ("Y", &mut edited.1), ("Z", &mut edited.2)] {
                    let field = number_field(ui.ctx(), value).speed(speed).max_decimals(4).suffix(suffix);
                    let r = ui.add_sized(FIELD, field).labelled_by(label).on_hover_text(hint);
                    r.widget_info(|| {
                        egui::WidgetInfo::labeled(egui::Role::SpinButton, unpinned, format!("{name} {axis}"))
                    });
                    let value = *value;
                    key_field(w, &r, undo_label, |k| {
                        let mut now = k.placement_or_default();
                        if row == 0 {
                            now.center = pos_after(now.center, axis, value);
                        } else {
                            now.rotation_deg = pos_after(now.rotation_deg, axis, value);
                        }
                        k.placement = Some(now);
                    });
                }
            });
        });
        ui.end_row();
    }
}

/// Exact values for the selected pins: one pin's position, or several pins'
/// shared offset, where they are at the key's frame (attached pins on their
/// attachments); then what they are attached to and the verbs to change it.
/// Every row is there with nothing selected too (greyed), so selecting,
/// pinning or attaching moves nothing under the mouse.
fn selected_pin_fields(ui: &mut egui::Ui, w: &mut Workspace, picker: &mut NodePicker) {
    let index = w.edit_key_index();
    let scene = w.doc.scene().clone();
    let key = &scene.keys[index];
    let selected: Vec<Pin> = key.pins.iter().filter(|p| w.session.selection().contains(&p.grid)).cloned().collect();
    let places: Vec<(f64, f64, f64)> = selected.iter().map(|p| attach::pin_at_key(&scene, key, p).into()).collect();
    match (selected.as_slice(), places.as_slice()) {
        ([], _) => {
            ui.weak("No pin selected: click a pin for its position.");
            ui.add_enabled_ui(false, |ui| {
                ui.horizontal(|ui| {
                    for axis in ["X", "Y", "Z"] {
                        let label = ui.label(axis).id;
                        let mut blank = 0.0;
                        let field = number_field(ui.ctx(), &mut blank).custom_formatter(|_, _| "–".to_owned());
                        ui.add_sized(FIELD, field).labelled_by(label);
                    }
                });
            });
        }
        ([pin], [place]) => {
            ui.label(format!("Pin ({}, {}), metres", pin.grid.0, pin.grid.1));
            let grid = pin.grid;
            ui.horizontal(|ui| {
                let mut pos = *place;
                for (axis, value) in [("X", &mut pos.0), ("Y", &mut pos.1), ("Z", &mut pos.2)] {
                    let label = ui.label(axis).id;
                    let r = ui
                        .add_sized(FIELD, number_field(ui.ctx(), value).speed(0.005).max_decimals(4))
                        .labelled_by(label);
                    // Set on the pin as the edited key holds it (a new auto-key holds the pose here).
                    let value = *value;
                    pins_field(w, &r, "Move pin", |s, k| {
                        let now = attach::pin_place(s, k, grid);
                        now.map(|now| (grid, DVec3::from(pos_after(now.into(), axis, value)))).into_iter().collect()
                    });
                }
            });
        }
        (many, _) => {
            // Their centre, like one pin's position: typing a value moves them all by the change.
            ui.label(format!("{} pins selected: their centre, metres", many.len()));
            let count = many.len() as f64;
            let centre =
                places.iter().fold((0.0, 0.0, 0.0), |c, p| (c.0 + p.0 / count, c.1 + p.1 / count, c.2 + p.2 / count));
            ui.horizontal(|ui| {
                let mut moved = centre;
                for (axis, value) in [("X", &mut moved.0), ("Y", &mut moved.1), ("Z", &mut moved.2)] {
                    let label = ui.label(axis).id;
                    let r = ui
                        .add_sized(FIELD, number_field(ui.ctx(), value).speed(0.005).max_decimals(4))
                        .labelled_by(label);
                    // Each pin keeps its offset from the centre; written value + offset so pins
                    // level with the centre get the typed number exactly.
                    let (value, from) = (*value, axis_of(centre, axis));
                    pins_field(w, &r, "Move pins", |s, k| {
                        let mut moves = Vec::new();
                        for pin in many {
                            let Some(now) = attach::pin_place(s, k, pin.grid).map(Into::into) else { continue };
                            let to = value + (axis_of(now, axis) - from);
                            moves.push((pin.grid, DVec3::from(pos_after(now, axis, to))));
                        }
                        moves
                    });
                }
            });
        }
    }
    attachment_ui(ui, w, &selected, picker);
    ui.horizontal(|ui| {
        let any = !selected.is_empty();
        if ui.add_enabled(any, egui::Button::new("Unpin")).on_hover_text("Unpin the selected pins (Delete)").clicked() {
            w.delete_selected_pins();
        }
        let hint = "Copy the selected pins' positions (Ctrl+C)";
        if ui.add_enabled(any, egui::Button::new("Copy")).on_hover_text(hint).clicked()
            && let Some(text) = pin_clipboard::copy_selected_pins(w)
        {
            ui.ctx().copy_text(text);
        }
        let can_paste = !w.session.copied_pins().is_empty();
        let hint = "Pin the copied grid points here as they were copied: position and attachment (Ctrl+V)";
        if ui.add_enabled(can_paste, egui::Button::new("Paste")).on_hover_text(hint).clicked() {
            pin_clipboard::paste_pins(w, None);
        }
        let hint = "The selected pins take their partners' positions across the middle column, reflected in x = 0";
        if ui.add_enabled(any, egui::Button::new("Mirror")).on_hover_text(hint).clicked() {
            pin_clipboard::mirror_selected_pins(w);
        }
    });
}

/// A pin coordinate field's size: fixed, so the fields don't shift as values are typed.
const FIELD: [f32; 2] = [62.0, 18.0];

/// One axis (`"X"`, `"Y"` or `"Z"`) of `pos`.
fn axis_of(pos: (f64, f64, f64), axis: &str) -> f64 {
    match axis {
        "X" => pos.0,
        "Y" => pos.1,
        _ => pos.2,
    }
}

/// `pos` with one axis (`"X"`, `"Y"` or `"Z"`) set to `value`.
fn pos_after(pos: (f64, f64, f64), axis: &str, value: f64) -> (f64, f64, f64) {
    match axis {
        "X" => (value, pos.1, pos.2),
        "Y" => (pos.0, value, pos.2),
        _ => (pos.0, pos.1, value),
    }
}
