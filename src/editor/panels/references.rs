//! The References panel: add glTF files (a character, a prop) to the scene,
//! show, hide, rename and remove them, and for the selected one its file,
//! which animation plays and when, and its placement. The placement's
//! numbers have key toggles as the Colliders panel's do: values show what
//! the number is at the playhead, editing a keyed number keys it there, and
//! the diamond adds or removes the key at the playhead. Every change is one
//! undo step.

use std::collections::BTreeSet;
use std::path::Path;
use std::sync::Arc;

use eframe::egui;

use super::keyed_number::{KeyedNumber, NumberRange, Owner};
use crate::animate::track::sample;
use crate::editor::files::dialog::{FileDialog, FileDialogMode, FileDialogOutcome, file_row_ui};
use crate::editor::number_field::number_field;
use crate::editor::param_edit::set_at_keying;
use crate::editor::timeline::curve_view::{Curve, CurveView, ReferenceNumber};
use crate::editor::workspace::Workspace;
use crate::scene::{
    Attachment, Loaded, LoadedRig, MAX_PIN_COORD_M, MAX_REFERENCE_SPEED, MAX_THICKNESS_M, MAX_TIMELINE_FRAME, Param,
    Reference, Scene, read_rig, readable_number,
};
use crate::world::rig::Rig;

/// Room kept beside a name field for the row's switch and ×, points.
const ROW_BUTTONS_WIDTH: f32 = 56.0;

/// The References panel's own state: the file dialog, which reference it
/// shows, a name being typed and the curve view.
#[derive(Default)]
pub struct ReferencesPanel {
    /// The file dialog picking a glTF file: for a new reference (`None`), or
    /// for reference `Some(index)`'s file.
    dialog: Option<(FileDialog, Option<usize>)>,
    /// The reference whose file, timing and numbers show.
    selected: Option<usize>,
    /// The name typed so far into reference `.0`'s field: it becomes the
    /// reference's name (one undo step) when the field lets go.
    name_draft: Option<(usize, String)>,
    /// The curve of one of the selected reference's numbers, under them.
    curve: CurveView,
}

impl ReferencesPanel {
    pub(in crate::editor) fn ui(&mut self, ui: &mut egui::Ui, w: &mut Workspace) {
        ui.heading("References");
        self.dialog_ui(ui.ctx(), w);
        let hint = "A glTF 2.0 file (.glb, or .gltf with its .bin): drawn with the cloth, its animation played";
        if ui.button("Add reference…").on_hover_text(hint).clicked() {
            self.dialog = Some((reference_dialog(w), None));
        }
        let references = w.doc.scene().references.clone();
        if references.is_empty() {
            ui.weak(
                "None. A reference is a glTF character or prop from Blender, Maya or Houdini, \
                 drawn with the cloth and played on its timeline.",
            );
            return;
        }
        for (index, reference) in references.iter().enumerate() {
            self.row_ui(ui, w, index, reference);
        }
        // An undo or a removal may have taken the selected one away.
        let count = w.doc.scene().references.len();
        self.selected = self.selected.filter(|i| *i < count);
        let Some(index) = self.selected else { return };
        let Some(reference) = w.doc.scene().references.get(index).cloned() else { return };
        ui.separator();
        self.details_ui(ui, w, index, &reference);
    }

    /// Reads the glTF file at `path` and adds a reference to it named after
    /// the file (made unique), selected; one undo step. A file that cannot be
    /// read is reported and nothing changes.
    fn add_from_file(&mut self, w: &mut Workspace, path: &Path) {
        let Some(rig) = read_or_report(w, path) else { return };
        let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        let name = unique_name(w.doc.scene(), &stem);
        let file = w.doc.name_for_file(path);
        let Some(reference) = new_reference(name, file, rig) else { return };
        let at = w.doc.scene().references.len();
        w.apply("Add reference", |s| s.references.push(reference));
        // Refused (the scene's limit): nothing new to select.
        if w.doc.scene().references.len() > at {
            self.selected = Some(at);
        }
    }

    /// Reads the glTF file at `path` into reference `index`, keeping its
    /// name, timing and placement (its animation too, unless the new file
    /// lacks it); one undo step. A file that cannot be read changes nothing.
    fn use_file(&mut self, w: &mut Workspace, index: usize, path: &Path) {
        let Some(rig) = read_or_report(w, path) else { return };
        let file = w.doc.name_for_file(path);
        let Some(reference) = w.doc.scene().references.get(index) else { return };
        let lost =
            reference.animation.clone().filter(|name| rig.0.as_ref().is_some_and(|r| r.clip_named(name).is_none()));
        w.apply("Reference file", |s| {
            if let Some(r) = s.references.get_mut(index) {
                r.file = file;
                r.rig = rig;
                if lost.is_some() {
                    r.animation = None;
                }
            }
        });
        let applied = w.doc.scene().references.get(index).is_some_and(|r| r.animation.is_none());
        if let Some(name) = lost.filter(|_| applied) {
            w.report(format!("The new file has no animation {name:?}: the reference plays its first."), false);
        }
    }

    /// The open file dialog; a picked file is read at once (see
    /// [`ReferencesPanel::add_from_file`], [`ReferencesPanel::use_file`]).
    fn dialog_ui(&mut self, ctx: &egui::Context, w: &mut Workspace) {
        let Some((dialog, target)) = &mut self.dialog else { return };
        let Some(outcome) = dialog.show(ctx) else { return };
        let target = *target;
        self.dialog = None;
        let FileDialogOutcome::Picked(path) = outcome else { return };
        match target {
            None => self.add_from_file(w, &path),
            Some(index) => self.use_file(w, index, &path),
        }
    }

    /// One reference in the list: its visibility, its name to edit and ×;
    /// a click on the row (or into its name) selects it.
    fn row_ui(&mut self, ui: &mut egui::Ui, w: &mut Workspace, index: usize, reference: &Reference) {
        let selected = self.selected == Some(index);
        let fill =
            if selected { ui.visuals().selection.bg_fill.gamma_multiply(0.35) } else { egui::Color32::TRANSPARENT };
        let row = ui.scope_builder(egui::UiBuilder::new().sense(egui::Sense::click()), |ui| {
            egui::Frame::new().fill(fill).corner_radius(3.0).inner_margin(egui::Margin::symmetric(2, 1)).show(
                ui,
                |ui| {
                    // The whole width, so a click anywhere beside the widgets selects.
                    ui.set_min_width(ui.available_width());
                    ui.horizontal(|ui| self.row_widgets_ui(ui, w, index, reference)).inner
                },
            )
        });
        let label = reference.label(index);
        row.response
            .widget_info(|| egui::WidgetInfo::selected(egui::Role::Button, true, selected, format!("Select {label}")));
        if row.response.clicked() || row.inner.inner {
            self.selected = Some(index);
        }
    }

    /// The row's widgets; true when its name field took the focus (selecting it).
    fn row_widgets_ui(&mut self, ui: &mut egui::Ui, w: &mut Workspace, index: usize, reference: &Reference) -> bool {
        let label = reference.label(index);
        let mut visible = reference.visible;
        let checkbox = ui.checkbox(&mut visible, "").on_hover_text("Shown in the viewport and in renders");
        checkbox
            .widget_info(|| egui::WidgetInfo::selected(egui::Role::CheckBox, true, visible, format!("Show {label}")));
        if checkbox.changed() {
            w.apply("Show reference", |s| s.references[index].visible = visible);
        }
        let focused = self.name_ui(ui, w, index, reference);
        let remove = ui.small_button("×").on_hover_text("Remove the reference (its file stays)");
        remove.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Button, true, format!("Remove {label}")));
        if remove.clicked() {
            self.remove(w, index);
        }
        focused
    }

    /// Reference `index`'s name field: typing goes to a draft, which becomes
    /// the name (one undo step) when the field lets go. True when it took the focus.
    fn name_ui(&mut self, ui: &mut egui::Ui, w: &mut Workspace, index: usize, reference: &Reference) -> bool {
        let mut text = match &self.name_draft {
            Some((i, draft)) if *i == index => draft.clone(),
            _ => reference.name.clone(),
        };
        let width = (ui.available_width() - ROW_BUTTONS_WIDTH).max(60.0);
        let field =
            egui::TextEdit::singleline(&mut text).desired_width(width).hint_text(format!("reference {}", index + 1));
        let response = ui.add(field).accessible_name(format!("Name of reference {}", index + 1));
        if response.has_focus() {
            self.name_draft = Some((index, text));
        } else if self.name_draft.as_ref().is_some_and(|(i, _)| *i == index) {
            self.name_draft = None;
            if text != reference.name {
                rename(w, index, text);
            }
        }
        response.gained_focus()
    }

    /// Removes reference `index` (one undo step), keeping the selection on
    /// the same reference. Refused, saying which, while pins are attached to it.
    fn remove(&mut self, w: &mut Workspace, index: usize) {
        if let Some(holding) = holding_pins(w.doc.scene(), index) {
            w.report(holding, true);
            return;
        }
        let count = w.doc.scene().references.len();
        w.apply("Remove reference", |s| {
            s.references.remove(index);
        });
        if w.doc.scene().references.len() == count {
            return; // Refused (pins attached to it): the message says why.
        }
        self.name_draft = None;
        self.selected = match self.selected {
            Some(s) if s == index => None,
            Some(s) if s > index => Some(s - 1),
            other => other,
        };
    }

    /// The selected reference's file, animation, timing and numbers, the curve of one of them, and what its file holds.
    fn details_ui(&mut self, ui: &mut egui::Ui, w: &mut Workspace, index: usize, reference: &Reference) {
        self.file_ui(ui, w, index, reference);
        animation_ui(ui, w, index, reference);
        timing_ui(ui, w, index, reference);
        let frame = w.frame().round() as i32;
        collider_ui(ui, w, index, reference, frame);
        ui.weak(format!("Values at frame {frame}. The diamond keys a number here (filled: keyed at this frame)."));
        let shown = self.curve.shown_for_reference(index, reference);
        egui::Grid::new("reference numbers").num_columns(4).show(ui, |ui| {
            for number in ReferenceNumber::ALL {
                let Some(param) = number.param(reference) else { continue };
                number_row_ui(ui, w, frame, number, param, |s| {
                    s.references.get_mut(index).and_then(|r| number.param_mut(r))
                });
                let curve = Curve::Reference(index, number);
                self.curve.button_ui(ui, curve, shown == curve);
                ui.end_row();
            }
        });
        self.curve.plot_ui(ui, w, shown);
        ui.weak(summary(reference, w.doc.scene().timeline.fps));
    }

    /// The file's name (cut to the panel, whole on hover) and Choose… to read another.
    fn file_ui(&mut self, ui: &mut egui::Ui, w: &mut Workspace, index: usize, reference: &Reference) {
        if file_row_ui(ui, "File", &reference.file, "Read the reference from another glTF file") {
            self.dialog = Some((reference_dialog(w), Some(index)));
        }
    }
}

/// Which of the file's animations play: all together (the default), or one by name.
fn animation_ui(ui: &mut egui::Ui, w: &mut Workspace, index: usize, reference: &Reference) {
    let clips: Vec<String> =
        reference.rig.0.as_ref().map(|rig| rig.clips().iter().map(|c| c.name.clone()).collect()).unwrap_or_default();
    let first = match clips.len() {
        0 if reference.rig.0.is_some() => "All (the file has none)".to_owned(),
        0 => "All".to_owned(),
        _ => format!("All ({})", clips.join(", ")),
    };
    let shown = match &reference.animation {
        None => first.clone(),
        Some(name) if clips.contains(name) || reference.rig.0.is_none() => name.clone(),
        Some(name) => format!("{name} (not in the file)"),
    };
    let mut chosen = reference.animation.clone();
    ui.horizontal(|ui| {
        let label = ui.label("Animation").id;
        let combo =
            egui::ComboBox::from_id_salt(("reference animation", index)).selected_text(shown).show_ui(ui, |ui| {
                ui.selectable_value(&mut chosen, None, first);
                for name in &clips {
                    ui.selectable_value(&mut chosen, Some(name.clone()), name);
                }
            });
        combo.response.labelled_by(label).on_hover_text("Which of the file's animations play: all together (a skeleton's and a shape key's, as Blender exports them), or one");
    });
    if chosen != reference.animation {
        w.apply("Reference animation", |s| s.references[index].animation = chosen);
    }
}

/// When and how the animation plays: its start frame, speed and repeat.
fn timing_ui(ui: &mut egui::Ui, w: &mut Workspace, index: usize, reference: &Reference) {
    ui.horizontal(|ui| {
        let mut start = reference.start_frame;
        let label = ui.label("Start frame").id;
        let field = number_field(ui.ctx(), &mut start).range(-MAX_TIMELINE_FRAME..=MAX_TIMELINE_FRAME);
        let response =
            ui.add(field).labelled_by(label).on_hover_text("The scene frame where the animation's time 0 plays");
        field_edit(w, &response, "Reference start frame", |s| s.references[index].start_frame = start);
        let mut speed = reference.speed;
        let label = ui.label("Speed").id;
        let field = number_field(ui.ctx(), &mut speed)
            .range(0.001..=MAX_REFERENCE_SPEED)
            .speed(0.01)
            .max_decimals(3)
            .suffix("×");
        let response = ui.add(field).labelled_by(label).on_hover_text("1: as authored; 0.5: half as fast");
        field_edit(w, &response, "Reference speed", |s| s.references[index].speed = speed);
    });
    let mut repeat = reference.repeat;
    let hint = "Play the animation over and over (a walk cycle); off: hold its first and last poses outside it";
    if ui.checkbox(&mut repeat, "Repeat").on_hover_text(hint).changed() {
        w.apply("Reference repeat", |s| s.references[index].repeat = repeat);
    }
}

/// Whether its meshes keep the cloth out, and how far (its own thickness,
/// keyable, or the key's).
fn collider_ui(ui: &mut egui::Ui, w: &mut Workspace, index: usize, reference: &Reference, frame: i32) {
    let mut collider = reference.collider;
    let hint = "Its meshes keep the cloth out at every frame's pose, like a mesh collider";
    if ui.checkbox(&mut collider, "Collider").on_hover_text(hint).changed() {
        w.apply("Reference collider", |s| s.references[index].collider = collider);
    }
    // Shown greyed when it is no collider, so ticking Collider moves no row under the mouse.
    ui.add_enabled_ui(reference.collider, |ui| own_thickness_ui(ui, w, index, reference, frame));
}

/// The reference's own thickness, keyable, or the key's.
fn own_thickness_ui(ui: &mut egui::Ui, w: &mut Workspace, index: usize, reference: &Reference, frame: i32) {
    ui.horizontal(|ui| {
        let mut own = reference.thickness.is_some();
        let hint = "How far the cloth keeps from it; off: the key's thickness";
        if ui.checkbox(&mut own, "Own thickness").on_hover_text(hint).changed() {
            // Starts at the thickness the key in effect keeps, so the cloth does not move.
            let start = w.doc.scene().keys[w.edit_key_index()].thickness;
            w.apply("Reference thickness", |s| s.references[index].thickness = own.then_some(Param::Constant(start)));
        }
        let Some(param) = &reference.thickness else { return };
        let mut value = sample(param, f64::from(frame));
        let field =
            number_field(ui.ctx(), &mut value).range(0.0..=MAX_THICKNESS_M).speed(0.0005).max_decimals(4).suffix(" m");
        let response = ui.add(field).on_hover_text("Keyed thicknesses change at the playhead");
        let auto_key = w.session.auto_key();
        field_edit(w, &response, "Reference thickness", |s| {
            if let Some(p) = s.references.get_mut(index).and_then(|r| r.thickness.as_mut()) {
                set_at_keying(p, frame, value, auto_key);
            }
        });
    });
}

/// A dragged field is one undo step per drag; a typed one, one per value.
fn field_edit(w: &mut Workspace, response: &egui::Response, label: &str, change: impl FnOnce(&mut Scene)) {
    if response.drag_started() {
        w.doc.begin_gesture(label);
    }
    if response.changed() {
        w.apply(label, change);
    }
}

/// One of the reference's animatable numbers as a row ([`KeyedNumber`]).
fn number_row_ui(
    ui: &mut egui::Ui,
    w: &mut Workspace,
    frame: i32,
    number: ReferenceNumber,
    param: &Param,
    param_of: impl Fn(&mut Scene) -> Option<&mut Param>,
) {
    let owner = Owner { diamond_prefix: "reference ", noun: "Reference" };
    let label = number.label();
    KeyedNumber { owner, label: &label, param, range: number_range(number) }.row_ui(ui, w, frame, param_of);
}

/// A number's bounds (validation's), drag speed and unit.
fn number_range(number: ReferenceNumber) -> NumberRange {
    let (min, max, speed, unit) = match number {
        ReferenceNumber::Center(_) => (-MAX_PIN_COORD_M, MAX_PIN_COORD_M, 0.005, " m"),
        ReferenceNumber::Rotation(_) => (-36_000.0, 36_000.0, 0.5, "°"),
        ReferenceNumber::Scale => (1e-4, MAX_PIN_COORD_M, 0.005, ""),
    };
    NumberRange { min, max, speed, unit }
}

/// What the file holds and where its clip plays:
/// "N vertices, M joints; clip NAME a–b s (frames X–Y on this timeline)".
fn summary(reference: &Reference, fps: f64) -> String {
    let Some(rig) = reference.rig.0.as_deref() else {
        return "The file is not read: reopen the scene from its file, or choose the file again.".to_owned();
    };
    let clip = match reference.clip_frames(fps) {
        Some(clip) => {
            let (a, b) = clip.secs;
            let (x, y) = clip.frames;
            let again = if clip.repeat { ", then over and over" } else { "" };
            format!(
                "clip {} {}–{} s (frames {}–{} on this timeline{again})",
                clip.name,
                short(a),
                short(b),
                short(x),
                short(y)
            )
        }
        None => match &reference.animation {
            Some(name) if !rig.clips().is_empty() => format!("no clip {name:?} in the file"),
            _ => "no animation: it holds its rest pose".to_owned(),
        },
    };
    format!("{} vertices, {} joints; {clip}", rig.vertex_count(), joint_count(rig))
}

/// How many nodes some skin of `rig` moves its vertices by.
fn joint_count(rig: &Rig) -> usize {
    rig.skins().iter().flat_map(|skin| skin.joints.iter().copied()).collect::<BTreeSet<usize>>().len()
}

/// `value` with at most two decimals, trailing zeros dropped.
fn short(value: f64) -> String {
    readable_number((value * 100.0).round() / 100.0)
}

/// Why reference `index` cannot be removed yet: the pins attached to it
/// (the first few, and the keys holding them), and what to do; None when none is.
fn holding_pins(scene: &Scene, index: usize) -> Option<String> {
    let name = &scene.references.get(index)?.name;
    let mut pins = Vec::new();
    let mut frames = Vec::new();
    for key in &scene.keys {
        for pin in key.pins.iter().filter(|p| p.attach.as_ref().is_some_and(|a| a.reference() == name)) {
            pins.push(format!("({}, {})", pin.grid.0, pin.grid.1));
            if frames.last() != Some(&key.frame) {
                frames.push(key.frame);
            }
        }
    }
    let (count, verb, them) = match pins.len() {
        0 => return None,
        1 => ("pin".to_owned(), "is", "it"),
        n => (format!("{n} pins"), "are", "them"),
    };
    let more = if pins.len() > 3 { ", …" } else { "" };
    let listed = pins[..pins.len().min(3)].join(", ");
    let keys = match frames[..] {
        [frame] => format!("the key at frame {frame}"),
        _ => format!("the keys at frames {}", frames.iter().map(i32::to_string).collect::<Vec<_>>().join(", ")),
    };
    let label = scene.references[index].label(index);
    Some(format!("Cannot remove {label}: {count} {listed}{more} of {keys} {verb} attached to it. Detach {them} first."))
}

/// Renames reference `index` (one undo step); pins attached to it, the
/// cloth following it and the shot camera following its camera name it
/// anew, so the rename keeps them.
fn rename(w: &mut Workspace, index: usize, name: String) {
    let Some(old) = w.doc.scene().references.get(index).map(|r| r.name.clone()) else { return };
    let sole = w.doc.scene().references.iter().filter(|r| r.name == old).count() == 1;
    w.apply("Rename reference", |s| {
        s.references[index].name = name.clone();
        if !sole {
            return;
        }
        if let Some(follow) = s.follow.as_mut().filter(|f| f.reference == old) {
            follow.reference = name.clone();
        }
        let camera = s.camera.as_mut().and_then(|c| c.from_reference.as_mut());
        if let Some(source) = camera.filter(|c| c.reference == old) {
            source.reference = name.clone();
        }
        let pins = s.keys.iter_mut().flat_map(|k| k.pins.iter_mut());
        for attachment in pins.filter_map(|p| p.attach.as_mut()).filter(|a| a.reference() == old) {
            match attachment {
                Attachment::Node(node) => node.reference = name.clone(),
                Attachment::Surface(surface) => surface.reference = name.clone(),
            }
        }
    });
}

/// The rig in the file at `path`, or `None` with the problem in the status bar.
fn read_or_report(w: &mut Workspace, path: &Path) -> Option<LoadedRig> {
    match read_rig(path) {
        Ok(rig) => Some(Loaded(Some(Arc::new(rig)))),
        Err(why) => {
            w.report(format!("Cannot use {} as a reference: {why}", path.display()), true);
            None
        }
    }
}

/// A reference to `file` holding `rig`, everything else as a scene file
/// naming only its file means (at the origin, unturned, at scale 1, its
/// first animation once from frame 0, shown): parsed, so a field the format
/// gains takes its default here too.
fn new_reference(name: String, file: String, rig: LoadedRig) -> Option<Reference> {
    let mut reference: Reference = ron::from_str(r#"(file: "")"#).ok()?;
    (reference.name, reference.file, reference.rig) = (name, file, rig);
    Some(reference)
}

/// `stem`, or `stem 2`, `stem 3`… when a reference of `scene` has that name
/// already (pins attach to a reference by its name).
fn unique_name(scene: &Scene, stem: &str) -> String {
    let taken = |name: &str| scene.references.iter().any(|r| r.name == name);
    if !taken(stem) {
        return stem.to_owned();
    }
    (2..).map(|n| format!("{stem} {n}")).find(|name| !taken(name)).unwrap_or_default()
}

/// A dialog for a glTF file, starting in the scene's folder.
fn reference_dialog(w: &Workspace) -> FileDialog {
    FileDialog::new(FileDialogMode::Open, "Reference (.glb, .gltf)", &w.doc.folder(), "", "glb")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cape's pins hang on the walker; renamed, they, the cloth's follow
    /// and a camera following one of its cameras go on naming it.
    #[test]
    fn a_rename_carries_what_names_the_reference() {
        let mut w = Workspace::new(crate::scene::load(Path::new("scenes/cape.ron")).unwrap(), None);
        w.apply("setup", |s| {
            s.follow = Some(crate::scene::Follow { reference: "walker".into(), node: "hips".into() });
            if let Some(camera) = &mut s.camera {
                camera.from_reference =
                    Some(crate::scene::ReferenceCamera { reference: "walker".into(), camera: "Cam".into() });
            }
        });
        rename(&mut w, 0, "hero".to_owned());
        let scene = w.doc.scene();
        assert_eq!(scene.references[0].name, "hero");
        assert!(
            scene.keys.iter().flat_map(|k| &k.pins).filter_map(|p| p.attach.as_ref()).all(|a| a.reference() == "hero")
        );
        assert_eq!(scene.follow.as_ref().map(|f| f.reference.as_str()), Some("hero"));
    }

    fn walker() -> Reference {
        let rig = read_rig(Path::new("assets/walker.glb")).expect("the bundled walker");
        let reference = new_reference("walker".to_owned(), "walker.glb".to_owned(), Loaded(Some(Arc::new(rig))));
        reference.expect("a reference with defaults")
    }

    #[test]
    fn a_reference_holding_pins_names_them_and_says_to_detach_them() {
        let mut scene = crate::scene::parse(include_str!("../../../scenes/cape.ron"), "cape.ron").unwrap();
        let text = holding_pins(&scene, 0).expect("five pins hold the walker");
        assert_eq!(
            text,
            "Cannot remove reference \"walker\": 5 pins (0, 0), (4, 0), (9, 0), … of the key at frame 0 \
             are attached to it. Detach them first."
        );
        scene.keys[0].pins.iter_mut().skip(1).for_each(|p| p.attach = None);
        let mut second = scene.keys[0].clone();
        second.frame = 24;
        scene.keys.push(second);
        assert!(holding_pins(&scene, 0).unwrap().contains(": 2 pins (0, 0), (0, 0) of the keys at frames 0, 24 are "));
        scene.keys.pop();
        scene.keys[0].pins[0].attach = None;
        assert_eq!(holding_pins(&scene, 0), None);
    }

    #[test]
    fn a_new_reference_has_the_file_format_s_defaults() {
        let r = walker();
        assert_eq!((r.name.as_str(), r.file.as_str(), r.start_frame, r.speed), ("walker", "walker.glb", 0, 1.0));
        assert!(r.visible && !r.repeat && r.animation.is_none() && r.rig.0.is_some());
        assert_eq!(r.scale, Param::Constant(1.0));
    }

    #[test]
    fn the_clip_plays_from_start_frame_for_its_span_at_speed() {
        let mut r = walker();
        let clip = r.clip_frames(24.0).expect("the walker walks");
        assert_eq!(clip.name, "Walk");
        assert_eq!(clip.frames, (24.0 * clip.secs.0, 24.0 * clip.secs.1));
        (r.start_frame, r.speed) = (10, 0.5);
        let slow = r.clip_frames(24.0).unwrap();
        assert_eq!(slow.frames, (10.0 + 48.0 * clip.secs.0, 10.0 + 48.0 * clip.secs.1));
        // The clip clock agrees: at the last frame it is at the clip's last key.
        assert!((r.clip_time_secs(slow.frames.1, 24.0, clip.secs) - clip.secs.1).abs() < 1e-9);
        r.animation = Some("Run".to_owned());
        assert_eq!(r.clip_frames(24.0), None, "no such clip");
        r.rig = Loaded(None);
        r.animation = None;
        assert_eq!(r.clip_frames(24.0), None, "not read");
    }

    #[test]
    fn the_summary_counts_what_the_file_holds_and_says_when_it_is_not_read() {
        let mut r = walker();
        let text = summary(&r, 24.0);
        assert!(text.contains(" vertices, ") && text.contains(" joints; clip Walk 0–1 s (frames 0–24 "), "{text}");
        r.rig = Loaded(None);
        assert!(summary(&r, 24.0).contains("not read"));
    }

    #[test]
    fn a_new_name_is_unique_among_the_references() {
        let mut scene = crate::scene::parse(crate::editor::DEFAULT_SCENE, "magic_carpet.ron").unwrap();
        assert_eq!(unique_name(&scene, "walker"), "walker");
        scene.references.push(walker());
        assert_eq!(unique_name(&scene, "walker"), "walker 2");
        let mut second = walker();
        second.name = "walker 2".to_owned();
        scene.references.push(second);
        assert_eq!(unique_name(&scene, "walker"), "walker 3");
    }
}
