//! File ▸ Export: the evaluated animation of a frame range as PC2, MDD,
//! glTF, USD or an OBJ sequence, written on a worker thread with a progress
//! bar and Cancel, through the same exporter as `drape export`. The window
//! shows the export's estimated size; one past 8 GiB or the free disk space
//! is held back with the reason until the user asks to export anyway (the
//! command line's `--force`).

use std::ops::RangeInclusive;
use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;
use std::time::Duration;

use eframe::egui;

use super::document::Document;
use super::file_dialog::{FileDialog, FileDialogMode, FileDialogOutcome};
use super::number_field::number_field;
use super::worker_job::WorkerJob;
use super::workspace::Workspace;
use crate::export::{
    AnimationFormat, ExportError, ExportSummary, MAX_EXPORT_BYTES, SizeEstimate, check_export_size, export_animation,
};
use crate::scene::{Scene, readable_bytes};

/// An export running on its worker.
type Job = WorkerJob<Result<ExportSummary, ExportError>>;

/// The Export window's settings and the running export.
pub(super) struct ExportWindow {
    open: bool,
    format: AnimationFormat,
    first: i32,
    last: i32,
    output: String,
    dialog: Option<FileDialog>,
    job: Option<Job>,
    /// Why the last Export was held back, and the settings it was for; shown
    /// with an "Export anyway" button until the settings change.
    refused: Option<(String, Settings)>,
}

/// What an export writes: format, frames and file.
type Settings = (AnimationFormat, i32, i32, String);

impl Default for ExportWindow {
    fn default() -> Self {
        ExportWindow {
            open: false,
            format: AnimationFormat::Glb,
            first: 0,
            last: 0,
            output: String::new(),
            dialog: None,
            job: None,
            refused: None,
        }
    }
}

/// Starts exporting `scene` on a worker thread.
fn start(
    scene: Scene,
    frames: RangeInclusive<i32>,
    output: PathBuf,
    format: AnimationFormat,
    ctx: egui::Context,
) -> Job {
    WorkerJob::start(ctx, move |progress, cancel| {
        let mut progress = |done: usize, total: usize| {
            progress(done as u64, total.max(1) as u64);
            !cancel.load(Ordering::Relaxed)
        };
        export_animation(&scene, frames, &output, format, &mut progress)
    })
}

/// Why exporting `frames` of `scene` as `format` to `output` should not go
/// ahead without asking: its estimated size is over [`MAX_EXPORT_BYTES`] or
/// over the free space on the disk it goes to. `None` when it may go ahead.
fn size_refusal(scene: &Scene, frames: &RangeInclusive<i32>, output: &Path, format: AnimationFormat) -> Option<String> {
    let estimate = SizeEstimate::animation(scene, format, frame_count(frames));
    check_export_size(&estimate, output, MAX_EXPORT_BYTES).err().map(|error| error.to_string())
}

fn frame_count(frames: &RangeInclusive<i32>) -> u64 {
    (i64::from(*frames.end()) - i64::from(*frames.start()) + 1).max(0) as u64
}

/// `path` with its extension replaced by `format`'s.
fn with_format_extension(path: &str, format: AnimationFormat) -> String {
    if path.trim().is_empty() {
        return String::new();
    }
    Path::new(path).with_extension(format.extension()).display().to_string()
}

impl ExportWindow {
    /// Opens the Export window on the whole timeline, next to the scene's file.
    pub(super) fn open_for(&mut self, doc: &Document) {
        let scene = doc.scene();
        let window = self;
        window.open = true;
        window.first = scene.timeline.start;
        window.last = scene.timeline.end;
        if window.output.is_empty() {
            let stem = doc
                .path()
                .and_then(Path::file_stem)
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "cloth".to_owned());
            let dir = doc.path().and_then(Path::parent).map(Path::to_path_buf).unwrap_or_default();
            window.output = dir.join(format!("{stem}.{}", window.format.extension())).display().to_string();
        }
    }

    pub(super) fn window_ui(&mut self, ctx: &egui::Context, w: &mut Workspace) {
        self.finish(w);
        if !self.open {
            return;
        }
        let timeline = w.doc.scene().timeline.clone();
        let mut open = true;
        let mut start_now = false;
        let mut force_now = false;
        let mut choose = false;
        let busy = self.job.is_some();
        let scene = w.doc.scene();
        egui::Window::new("Export animation").open(&mut open).collapsible(false).resizable(false).show(ctx, |ui| {
            let window = &mut *self;
            ui.add_enabled_ui(!busy, |ui| {
                egui::Grid::new("export").num_columns(2).show(ui, |ui| {
                    let label = ui.label("Format").id;
                    let before = window.format;
                    let combo = egui::ComboBox::from_id_salt("export format")
                        .selected_text(format!("{} (.{})", before.description(), before.extension()))
                        .show_ui(ui, |ui| {
                            for format in AnimationFormat::ALL {
                                let text = format!("{} (.{})", format.description(), format.extension());
                                ui.selectable_value(&mut window.format, format, text);
                            }
                        });
                    let _ = combo.response.labelled_by(label);
                    if window.format != before {
                        window.output = with_format_extension(&window.output, window.format);
                    }
                    ui.end_row();

                    ui.label("Frames");
                    ui.horizontal(|ui| {
                        let range = timeline.start..=timeline.end;
                        ui.add(number_field(&mut window.first).range(range.clone()))
                            .widget_info(|| egui::WidgetInfo::labeled(egui::Role::SpinButton, true, "First frame"));
                        ui.label("to");
                        ui.add(number_field(&mut window.last).range(range))
                            .widget_info(|| egui::WidgetInfo::labeled(egui::Role::SpinButton, true, "Last frame"));
                        window.last = window.last.max(window.first);
                        let seconds = f64::from(window.last - window.first + 1) / timeline.fps;
                        let frames = window.first..=window.last;
                        let estimate = SizeEstimate::animation(scene, window.format, frame_count(&frames));
                        ui.weak(format!(
                            "{} frames, {seconds:.2} s at {} fps, about {}",
                            window.last - window.first + 1,
                            timeline.fps,
                            readable_bytes(estimate.bytes)
                        ));
                    });
                    ui.end_row();

                    let label = ui.label("File").id;
                    ui.horizontal(|ui| {
                        let field = egui::TextEdit::singleline(&mut window.output).desired_width(320.0);
                        let _ = ui.add(field).labelled_by(label);
                        choose = ui.button("Choose…").clicked();
                    });
                    ui.end_row();
                });
            });
            ui.separator();
            match &window.job {
                Some(job) => job.progress_ui(ui, "frame evaluations", "Starting"),
                None => {
                    let settings = (window.format, window.first, window.last, window.output.clone());
                    if window.refused.as_ref().is_some_and(|(_, held)| *held != settings) {
                        window.refused = None;
                    }
                    if let Some((reason, _)) = &window.refused {
                        ui.colored_label(ui.visuals().warn_fg_color, format!("Not exported: {reason}."));
                    }
                    ui.horizontal(|ui| {
                        let ready = !window.output.trim().is_empty();
                        start_now = ui.add_enabled(ready, egui::Button::new("Export")).clicked();
                        if window.refused.is_some() && ui.button("Export anyway").clicked() {
                            force_now = true;
                        }
                    });
                }
            }
        });
        if choose {
            let (dir, name) = split_output(&self.output);
            let extension = self.format.extension();
            self.dialog = Some(FileDialog::new(FileDialogMode::Save, "Export to", &dir, &name, extension));
        }
        if let Some(dialog) = &mut self.dialog
            && let Some(outcome) = dialog.show(ctx)
        {
            if let FileDialogOutcome::Picked(path) = outcome {
                self.output = path.display().to_string();
            }
            self.dialog = None;
        }
        if start_now || force_now {
            let output = PathBuf::from(self.output.trim());
            let frames = self.first..=self.last;
            let format = self.format;
            let refusal = if force_now { None } else { size_refusal(w.doc.scene(), &frames, &output, format) };
            match refusal {
                Some(reason) => {
                    let settings = (format, self.first, self.last, self.output.clone());
                    self.refused = Some((reason, settings));
                }
                None => {
                    self.refused = None;
                    self.job = Some(start(w.doc.scene().clone(), frames, output, format, ctx.clone()));
                }
            }
        }
        if !open {
            // Closing the window cancels an export in progress.
            if let Some(job) = &self.job {
                job.cancel();
            }
            self.open = false;
        }
        if self.job.is_some() {
            ctx.request_repaint_after(Duration::from_millis(100));
        }
    }

    /// Reports a finished export.
    fn finish(&mut self, w: &mut Workspace) {
        let Some(job) = self.job.take_if(|job| job.is_finished()) else { return };
        let (result, elapsed) = job.join();
        match result {
            Ok(Ok(summary)) => {
                let file = summary.files.first().map(|f| f.display().to_string()).unwrap_or_default();
                let seconds = elapsed.as_secs_f64();
                w.report(format!("Exported {} frames to {file} in {seconds:.1} s", summary.frame_count), false);
                self.open = false;
            }
            Ok(Err(ExportError::Cancelled)) => w.report("Export cancelled; nothing was written.".to_owned(), false),
            Ok(Err(error)) => w.alert = Some(format!("Could not export:\n{error}")),
            Err(_) => w.alert = Some("The export stopped unexpectedly; nothing was written.".to_owned()),
        }
    }
}

/// The folder and file name of a typed output path (the working directory for a bare name).
fn split_output(output: &str) -> (PathBuf, String) {
    let path = Path::new(output.trim());
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let dir = path.parent().filter(|d| d.is_dir()).map(Path::to_path_buf);
    (dir.or_else(|| std::env::current_dir().ok()).unwrap_or_default(), name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn changing_the_format_changes_the_extension() {
        assert_eq!(with_format_extension("/a/carpet.glb", AnimationFormat::Pc2), "/a/carpet.pc2");
        assert_eq!(with_format_extension("carpet", AnimationFormat::Usda), "carpet.usda");
        assert_eq!(with_format_extension("  ", AnimationFormat::Usda), "");
    }

    #[test]
    fn a_huge_export_is_held_back_with_its_estimate() {
        let mut scene = crate::scene::parse(include_str!("../../scenes/curtain.ron"), "curtain.ron").unwrap();
        let dir = tempfile::tempdir().unwrap();
        let output = dir.path().join("curtain.usda");
        assert_eq!(size_refusal(&scene, &(0..=120), &output, AnimationFormat::Usda), None);
        scene.cloth.grid = (512, 512);
        assert_eq!(size_refusal(&scene, &(0..=120), &output, AnimationFormat::Usda), None, "about 2.4 GiB");
        let reason = size_refusal(&scene, &(0..=499), &output, AnimationFormat::Usda).expect("held back");
        assert!(
            reason
                == "the export (USD (text) of 262 144 points × 500 frames) would take about 9.8 GiB, more than the \
                    8.0 GiB limit: export fewer frames or a coarser grid",
            "{reason}"
        );
    }

    #[test]
    fn a_typed_path_splits_into_folder_and_name() {
        let (dir, name) = split_output("/tmp/carpet.glb");
        assert_eq!((dir, name.as_str()), (PathBuf::from("/tmp"), "carpet.glb"));
        let (dir, name) = split_output("/no/such/folder/x.pc2");
        assert_eq!(name, "x.pc2");
        assert_eq!(dir, std::env::current_dir().unwrap());
    }
}
