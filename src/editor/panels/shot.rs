//! The Shot panel: the shot camera's numbers (position, target, lens,
//! sensor, picture size) and the background plate (its file or sequence,
//! frame offset and opacity). The animatable numbers have key diamonds and
//! a curve as the References panel's do; every change is one undo step.

use std::path::{Path, PathBuf};

use eframe::egui;

use super::keyed_number::{KeyedNumber, NumberRange, Owner};
use crate::editor::files::dialog::{FileDialog, FileDialogMode, FileDialogOutcome, file_row_ui};
use crate::editor::number_field::number_field;
use crate::editor::timeline::curve_view::{Curve, CurveView, ShotNumber};
use crate::editor::workspace::Workspace;
use crate::scene::{
    MAX_IMAGE_SIDE_PX, MAX_LENS_MM, MAX_PIN_COORD_M, MAX_PLATE_FRAME_OFFSET, Param, Plate, PlateFiles, PlatePattern,
    frame_list, horizontal_fov_deg,
};

/// The Shot panel's own state: the plate's file dialog, the curve shown,
/// and what was last found of the plate's files.
#[derive(Default)]
pub struct ShotPanel {
    dialog: Option<FileDialog>,
    curve: CurveView,
    /// The plate and folder last scanned, and what the scan said: scanning
    /// a folder every frame would cost more than the panel.
    scanned: Option<((String, i32, PathBuf), String)>,
}

impl ShotPanel {
    pub(in crate::editor) fn ui(&mut self, ui: &mut egui::Ui, w: &mut Workspace) {
        ui.heading("Shot");
        self.dialog_ui(ui.ctx(), w);
        let frame = w.frame().round() as i32;
        // Only what the panel shows is copied, not the scene: the rows edit through `w`.
        let (camera, plate) = (w.doc.scene().camera.clone(), w.doc.scene().plate.clone());
        let shown = self.curve.shown_for_shot(w.doc.scene());
        match &camera {
            None => {
                ui.weak("No shot camera. The View menu's Add camera from view sets one where the viewport looks from.");
            }
            Some(camera) => {
                ui.horizontal(|ui| {
                    ui.strong("Camera");
                    if ui.small_button("Remove camera").on_hover_text("The scene without a shot camera").clicked() {
                        w.apply("Remove camera", |s| s.camera = None);
                    }
                });
                let lens = horizontal_fov_deg(
                    crate::animate::track::sample(&camera.focal_length_mm, f64::from(frame)),
                    crate::animate::track::sample(&camera.sensor_width_mm, f64::from(frame)),
                );
                if camera.from_reference.is_none() {
                    ui.weak(format!("Values at frame {frame}: {lens:.1}° across."));
                }
                image_size_ui(ui, w, camera.image_size);
            }
        }
        match camera.as_ref().map(|c| &c.from_reference) {
            None => {}
            // Its own numbers are not used while it follows a glTF camera: only the sensor is.
            Some(Some(source)) => {
                ui.weak(format!(
                    "Follows camera {:?} of reference {:?}: it moves and zooms as that one does. \
                     The View menu's Detach camera from reference makes it a camera of its own.",
                    source.camera, source.reference
                ));
                egui::Grid::new("shot camera numbers").num_columns(4).show(ui, |ui| {
                    self.number_row_ui(ui, w, frame, ShotNumber::SensorWidth, shown);
                });
            }
            Some(None) => {
                egui::Grid::new("shot camera numbers").num_columns(4).show(ui, |ui| {
                    for number in ShotNumber::CAMERA {
                        self.number_row_ui(ui, w, frame, number, shown);
                    }
                });
            }
        }
        ui.add_space(6.0);
        self.plate_ui(ui, w, plate.as_ref(), frame, shown);
        if shown.param(w.doc.scene()).is_some() {
            self.curve.plot_ui(ui, w, shown);
        }
    }

    /// One animatable number: its row, and the button showing its curve.
    fn number_row_ui(&mut self, ui: &mut egui::Ui, w: &mut Workspace, frame: i32, number: ShotNumber, shown: Curve) {
        let Some(param) = number.param(w.doc.scene()).cloned() else { return };
        let owner = Owner { diamond_prefix: "shot ", noun: "Shot" };
        let label = number.label();
        let row = KeyedNumber { owner, label: &label, param: &param, range: number_range(number) };
        row.row_ui(ui, w, frame, |s| number.param_mut(s));
        let curve = Curve::Shot(number);
        self.curve.button_ui(ui, curve, shown == curve);
        ui.end_row();
    }

    /// The plate: Add plate… without one; with one its file, what was found
    /// of it, its frame offset and opacity.
    fn plate_ui(&mut self, ui: &mut egui::Ui, w: &mut Workspace, plate: Option<&Plate>, frame: i32, shown: Curve) {
        let Some(plate) = plate else {
            ui.horizontal(|ui| {
                let hint = "A picture, or a numbered sequence of them (PNG or JPEG), behind the cloth \
                            through the shot camera";
                if ui.button("Add plate…").on_hover_text(hint).clicked() {
                    self.dialog = Some(plate_dialog(w));
                }
            });
            return;
        };
        ui.horizontal(|ui| {
            ui.strong("Plate");
            if ui.small_button("Remove plate").on_hover_text("The scene without a background plate").clicked() {
                w.apply("Remove plate", |s| s.plate = None);
            }
        });
        // Not "File": the menu bar's File must stay the one widget of that name.
        if file_row_ui(ui, "Image", &plate.file, "Another picture or sequence") {
            self.dialog = Some(plate_dialog(w));
        }
        ui.weak(self.plate_summary(w, plate));
        ui.horizontal(|ui| {
            let label = ui.label("Frame offset").id;
            let mut offset = plate.frame_offset;
            let field = number_field(ui.ctx(), &mut offset).range(-MAX_PLATE_FRAME_OFFSET..=MAX_PLATE_FRAME_OFFSET);
            let response = ui.add(field).labelled_by(label).on_hover_text("Frame F shows file number F + offset");
            if response.changed() {
                w.apply("Plate frame offset", |s| {
                    if let Some(p) = &mut s.plate {
                        p.frame_offset = offset;
                    }
                });
            }
        });
        egui::Grid::new("plate numbers").num_columns(4).show(ui, |ui| {
            self.number_row_ui(ui, w, frame, ShotNumber::PlateOpacity, shown);
        });
    }

    /// What the plate's files are (or why they cannot be read), scanned once
    /// per plate, offset and folder.
    fn plate_summary(&mut self, w: &Workspace, plate: &Plate) -> String {
        let key = (plate.file.clone(), plate.frame_offset, w.doc.folder());
        if let Some((scanned, summary)) = &self.scanned
            && *scanned == key
        {
            return summary.clone();
        }
        let timeline = &w.doc.scene().timeline;
        let summary = match PlateFiles::scan(plate, &key.2) {
            Err(why) => why,
            Ok(files) => match files.number_range() {
                None => "One picture, at every frame.".to_owned(),
                Some((first, last)) => {
                    let missing = files.missing(timeline.start, timeline.end);
                    let held = if missing.is_empty() {
                        String::new()
                    } else {
                        format!("; frames {} show the nearest file", frame_list(&missing))
                    };
                    format!("{} files numbered {first}–{last}{held}.", files.count())
                }
            },
        };
        self.scanned = Some((key, summary.clone()));
        summary
    }

    /// The open file dialog; a picked picture becomes the plate (a
    /// numbered one the sequence it belongs to), one undo step.
    fn dialog_ui(&mut self, ctx: &egui::Context, w: &mut Workspace) {
        let Some(dialog) = &mut self.dialog else { return };
        let Some(outcome) = dialog.show(ctx) else { return };
        self.dialog = None;
        let FileDialogOutcome::Picked(path) = outcome else { return };
        let picked = sequence_of(&path).unwrap_or(path);
        let file = w.doc.name_for_file(&picked);
        w.apply("Plate file", |s| match &mut s.plate {
            Some(plate) => plate.file = file,
            None => s.plate = Some(Plate { file, frame_offset: 0, opacity: Param::Constant(1.0) }),
        });
        self.scanned = None;
    }
}

/// The picture's size in pixels, two whole numbers; one undo step each.
fn image_size_ui(ui: &mut egui::Ui, w: &mut Workspace, (width, height): (u32, u32)) {
    ui.horizontal(|ui| {
        let label = ui.label("Picture").id;
        let (mut new_width, mut new_height) = (width, height);
        let wide = ui
            .add(number_field(ui.ctx(), &mut new_width).range(1..=MAX_IMAGE_SIDE_PX).suffix(" px"))
            .labelled_by(label);
        ui.label("×");
        let high = ui.add(number_field(ui.ctx(), &mut new_height).range(1..=MAX_IMAGE_SIDE_PX).suffix(" px"));
        if wide.changed() || high.changed() {
            w.apply("Camera picture size", |s| {
                if let Some(c) = &mut s.camera {
                    c.image_size = (new_width, new_height);
                }
            });
        }
    });
}

/// A number's bounds (validation's), drag speed and unit.
fn number_range(number: ShotNumber) -> NumberRange {
    let (min, max, speed, unit) = match number {
        ShotNumber::Position(_) | ShotNumber::Target(_) => (-MAX_PIN_COORD_M, MAX_PIN_COORD_M, 0.01, " m"),
        ShotNumber::FocalLength | ShotNumber::SensorWidth => (0.1, MAX_LENS_MM, 0.1, " mm"),
        ShotNumber::PlateOpacity => (0.0, 1.0, 0.01, ""),
    };
    NumberRange { min, max, speed, unit }
}

fn plate_dialog(w: &Workspace) -> FileDialog {
    FileDialog::new(FileDialogMode::Open, "Plate (.png, .jpg)", &w.doc.folder(), "", "png")
}

/// The sequence `path` is one frame of: its last run of digits turned into
/// `#`s, when another file in its folder matches that pattern; `None` for a
/// picture on its own.
pub fn sequence_of(path: &Path) -> Option<PathBuf> {
    let name = path.file_name()?.to_str()?;
    let stem_end = name.rfind('.').unwrap_or(name.len());
    let digits_end = name[..stem_end].rfind(|c: char| c.is_ascii_digit())? + 1;
    let digits_start = name[..digits_end].rfind(|c: char| !c.is_ascii_digit()).map_or(0, |i| i + 1);
    let pattern_name =
        format!("{}{}{}", &name[..digits_start], "#".repeat(digits_end - digits_start), &name[digits_end..]);
    let pattern = PlatePattern::parse(&pattern_name).ok()?;
    let folder = path.parent().unwrap_or(Path::new(""));
    let siblings = std::fs::read_dir(if folder.as_os_str().is_empty() { Path::new(".") } else { folder }).ok()?;
    let matching = siblings
        .filter_map(|entry| entry.ok()?.file_name().to_str().and_then(|n| pattern.number_in(n)))
        .take(2)
        .count();
    (matching > 1).then(|| folder.join(pattern_name))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_numbered_picture_among_others_is_picked_as_their_sequence() {
        let dir = tempfile::tempdir().unwrap();
        for name in ["bg_0001.png", "bg_0002.png", "sky_2.png", "logo.png"] {
            std::fs::write(dir.path().join(name), b"").unwrap();
        }
        assert_eq!(sequence_of(&dir.path().join("bg_0002.png")), Some(dir.path().join("bg_####.png")));
        assert_eq!(sequence_of(&dir.path().join("sky_2.png")), None, "alone: one picture");
        assert_eq!(sequence_of(&dir.path().join("logo.png")), None, "no number");
    }
}
