//! The Colliders panel: add, remove, rename and enable what the cloth rests
//! on, and every number of the selected collider with a key toggle beside
//! it, as the Layers panel does for parameters: values show what the number
//! is at the playhead, editing a keyed number keys it there, and the diamond
//! adds or removes the key at the playhead. Every change is one undo step.

use std::sync::Arc;

use eframe::egui;

use super::add_menu::add_menu_ui;
use super::keyed_number::{KeyedNumber, NumberRange, Owner};
use super::list_row;
use crate::editor::files::dialog::{FileDialog, FileDialogMode, FileDialogOutcome, file_row_ui};
use crate::editor::timeline::curve_view::{Curve, CurveView};
use crate::editor::workspace::Workspace;
use crate::scene::{
    Collider, ColliderNumber, Loaded, MAX_PIN_COORD_M, MAX_THICKNESS_M, Measure, MeshCollider, Param, read_mesh,
};

/// The Colliders panel's own state: the file dialog picking a mesh (for a
/// new collider, or the one at an index). Which collider's numbers it shows
/// is the session's, since the viewport picks colliders too.
#[derive(Default)]
pub struct CollidersPanel {
    mesh_dialog: Option<(FileDialog, Option<usize>)>,
    /// The curve of one of the selected collider's numbers, under them.
    curve: CurveView,
}

impl CollidersPanel {
    pub(in crate::editor) fn ui(&mut self, ui: &mut egui::Ui, w: &mut Workspace) {
        ui.heading("Colliders");
        self.mesh_dialog_ui(ui.ctx(), w);
        add_menu_ui(ui, "Add collider", |ui| {
            for &kind in Collider::KINDS {
                let Some(mut collider) = Collider::with_start_values(kind) else { continue };
                if kind == "Mesh" {
                    if ui.button("Mesh…").on_hover_text(kind_hint(kind)).clicked() {
                        self.mesh_dialog = Some((mesh_dialog(w), None));
                        ui.close();
                    }
                    continue;
                }
                if ui.button(kind).on_hover_text(kind_hint(kind)).clicked() {
                    let at = w.doc.scene().colliders.len();
                    *collider.name_mut() = start_name(kind, &w.doc.scene().colliders);
                    w.apply("Add collider", |s| s.colliders.push(collider));
                    // Refused (the scene's limit): nothing new to select.
                    if w.doc.scene().colliders.len() > at {
                        w.session.select_collider(Some(at));
                    }
                    ui.close();
                }
            }
        });
        let colliders = w.doc.scene().colliders.clone();
        if colliders.is_empty() {
            ui.weak("None: the cloth hangs in empty space. A collider is something it rests on and never enters.");
            return;
        }
        for (index, collider) in colliders.iter().enumerate() {
            ui.horizontal(|ui| self.row_ui(ui, w, index, collider));
        }
        let Some(index) = w.session.selected_collider().filter(|i| *i < colliders.len()) else { return };
        ui.separator();
        if let Collider::Mesh(mesh) = &colliders[index]
            && file_row_ui(ui, "File", &mesh.file, "Read the mesh from another OBJ or glTF file")
        {
            self.mesh_dialog = Some((mesh_dialog(w), Some(index)));
        }
        self.details_ui(ui, w, index, &colliders[index]);
    }

    /// The selected collider's name, thickness and numbers, and the curve of one of them.
    fn details_ui(&mut self, ui: &mut egui::Ui, w: &mut Workspace, index: usize, collider: &Collider) {
        let frame = w.frame().round() as i32;
        let mut name = collider.name().to_owned();
        ui.horizontal(|ui| {
            let label = ui.label("Name").id;
            let field = egui::TextEdit::singleline(&mut name).desired_width(140.0).hint_text(title(collider, index));
            if ui.add(field).labelled_by(label).changed() {
                w.apply("Rename collider", |s| *s.colliders[index].name_mut() = name.clone());
            }
        });
        thickness_ui(ui, w, index, collider, frame);
        ui.weak(format!("Values at frame {frame}. The diamond keys a number here (filled: keyed at this frame)."));
        let shown = self.curve.shown_for_collider(index, collider);
        egui::Grid::new("collider numbers").num_columns(4).show(ui, |ui| {
            for number in collider.numbers() {
                let Some(param) = collider.param(number) else { continue };
                number_row_ui(ui, w, frame, &number.label(), param, number_range(number), |s| {
                    s.colliders.get_mut(index).and_then(|c| c.param_mut(number))
                });
                let curve = Curve::Collider(index, number);
                self.curve.button_ui(ui, curve, shown == Some(curve));
                ui.end_row();
            }
        });
        if let Some(curve) = shown {
            self.curve.plot_ui(ui, w, curve);
        }
    }

    /// The open mesh dialog; a picked file is read at once and becomes a new
    /// Mesh collider or the chosen one's file (one undo step), or its problem is shown.
    fn mesh_dialog_ui(&mut self, ctx: &egui::Context, w: &mut Workspace) {
        let Some((dialog, target)) = &mut self.mesh_dialog else { return };
        let Some(outcome) = dialog.show(ctx) else { return };
        let target = *target;
        self.mesh_dialog = None;
        let FileDialogOutcome::Picked(path) = outcome else { return };
        let solid = match read_mesh(&path) {
            Ok(solid) => Loaded(Some(Arc::new(solid))),
            Err(why) => {
                w.report(format!("Cannot use {} as a collider: {why}", path.display()), true);
                return;
            }
        };
        let file = w.doc.name_for_file(&path);
        match target {
            None => {
                let at = w.doc.scene().colliders.len();
                let name = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
                let Some(Collider::Mesh(start)) = Collider::with_start_values("Mesh") else { return };
                let mesh = MeshCollider { name, file, solid, ..start };
                w.apply("Add collider", |s| s.colliders.push(Collider::Mesh(mesh)));
                if w.doc.scene().colliders.len() > at {
                    w.session.select_collider(Some(at));
                }
            }
            Some(index) => w.apply("Collider file", |s| {
                if let Some(Collider::Mesh(mesh)) = s.colliders.get_mut(index) {
                    mesh.file = file;
                    mesh.solid = solid;
                }
            }),
        }
    }

    /// One collider in the list: its switch, its title (click to select) and ×.
    fn row_ui(&mut self, ui: &mut egui::Ui, w: &mut Workspace, index: usize, collider: &Collider) {
        let label = collider.label(index);
        let mut enabled = collider.enabled();
        let checkbox = ui.checkbox(&mut enabled, "").on_hover_text("Enabled: the cloth keeps out of it");
        checkbox
            .widget_info(|| egui::WidgetInfo::selected(egui::Role::CheckBox, true, enabled, format!("Enable {label}")));
        if checkbox.changed() {
            w.apply("Enable collider", |s| *s.colliders[index].enabled_mut() = enabled);
        }
        let selected = w.session.selected_collider() == Some(index);
        let (title, remove) =
            list_row::title_and_remove_ui(ui, selected, title(collider, index), "Remove the collider");
        if title.on_hover_text(&label).clicked() {
            w.session.select_collider(if selected { None } else { Some(index) });
        }
        remove.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Button, true, format!("Remove {label}")));
        if remove.clicked() {
            w.apply("Remove collider", |s| {
                s.colliders.remove(index);
            });
            w.session.collider_removed(index);
        }
    }
}

/// The collider's own thickness, or the key's: a switch and, when its own, its value.
fn thickness_ui(ui: &mut egui::Ui, w: &mut Workspace, index: usize, collider: &Collider, frame: i32) {
    let hint = "How far the cloth keeps from this collider; off: the key's thickness.";
    let mut own = collider.thickness().is_some();
    let switch = ui.checkbox(&mut own, "Own thickness").on_hover_text(hint);
    if switch.changed() {
        // Starts at the thickness the key in effect keeps, so the cloth does not move.
        let start = w.doc.scene().keys[w.edit_key_index()].thickness;
        w.apply("Collider thickness", |s| {
            *s.colliders[index].thickness_mut() = own.then_some(Param::Constant(start));
        });
    }
    let Some(param) = collider.thickness() else { return };
    egui::Grid::new("collider thickness").num_columns(3).show(ui, |ui| {
        let range = NumberRange { min: 0.0, max: MAX_THICKNESS_M, speed: 0.0005, unit: " m" };
        number_row_ui(ui, w, frame, "thickness", param, range, |s| {
            s.colliders.get_mut(index).and_then(|c| c.thickness_mut().as_mut())
        });
        ui.end_row();
    });
}

/// The range of a collider's number by what it measures (validation's bounds).
fn number_range(number: ColliderNumber) -> NumberRange {
    match number.field.measure {
        Measure::Position => NumberRange { min: -MAX_PIN_COORD_M, max: MAX_PIN_COORD_M, speed: 0.005, unit: " m" },
        Measure::Length => NumberRange { min: 0.001, max: MAX_PIN_COORD_M, speed: 0.005, unit: " m" },
        Measure::Scale => NumberRange { min: 1e-4, max: MAX_PIN_COORD_M, speed: 0.005, unit: "" },
        Measure::Angle => NumberRange { min: -36_000.0, max: 36_000.0, speed: 0.5, unit: "°" },
    }
}

/// One of the collider's animatable numbers as a row ([`KeyedNumber`]).
fn number_row_ui(
    ui: &mut egui::Ui,
    w: &mut Workspace,
    frame: i32,
    label_text: &str,
    param: &Param,
    range: NumberRange,
    param_of: impl Fn(&mut crate::scene::Scene) -> Option<&mut Param>,
) {
    let owner = Owner { diamond_prefix: "", noun: "Collider" };
    KeyedNumber { owner, label: label_text, param, range }.row_ui(ui, w, frame, param_of);
}

/// A dialog for a mesh file, starting in the scene's folder.
fn mesh_dialog(w: &Workspace) -> FileDialog {
    FileDialog::new(FileDialogMode::Open, "Mesh collider (.obj, .glb, .gltf)", &w.doc.folder(), "", "obj")
}

/// What each kind is, for the Add menu.
fn kind_hint(kind: &str) -> &'static str {
    match kind {
        "Ground" => "A level floor at a height: nothing goes below it",
        "Box" => "A box, turned any way: a table top, a step, a chest",
        "Cylinder" => "A round table top, a pole or a drum (axis up before turning)",
        "Sphere" => "A ball, a head",
        "Mesh" => "A closed triangle mesh from an OBJ or glTF file: a chair, a body, a prop",
        _ => "A segment swollen by a radius: an arm, a rail, a shoulder",
    }
}

/// The name a collider added from the menu starts with: what its start
/// values make it (a table top, a floor), numbered when the scene already
/// has a collider of that name.
fn start_name(kind: &str, colliders: &[Collider]) -> String {
    let base = match kind {
        "Ground" => "floor",
        "Box" => "table",
        "Cylinder" => "round table",
        "Sphere" => "ball",
        _ => "arm",
    };
    let taken = |name: &str| colliders.iter().any(|c| c.name() == name);
    if !taken(base) {
        return base.to_owned();
    }
    (2..).map(|n| format!("{base} {n}")).find(|name| !taken(name)).expect("fewer colliders than numbers")
}

/// The collider's name in the list, or for an unnamed one its kind and place ("Box 2").
fn title(collider: &Collider, index: usize) -> String {
    if collider.name().is_empty() { format!("{} {}", collider.kind(), index + 1) } else { collider.name().to_owned() }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn added_colliders_are_named_for_what_they_start_as() {
        let mut colliders = Vec::new();
        for (kind, name) in [("Box", "table"), ("Ground", "floor"), ("Box", "table 2"), ("Cylinder", "round table")] {
            let mut collider = Collider::with_start_values(kind).unwrap();
            *collider.name_mut() = start_name(kind, &colliders);
            assert_eq!(collider.name(), name);
            colliders.push(collider);
        }
    }
}
