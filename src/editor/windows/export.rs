//! File ▸ Export: the evaluated animation of a frame range as PC2, MDD,
//! glTF, USD or an OBJ sequence, written on a worker thread with a progress
//! bar and Cancel, through the same exporter as `drape export`. The window
//! shows the export's estimated size; one past 8 GiB or the free disk space
//! is held back with the reason until the user asks to export anyway (the
//! command line's `--force`). An OBJ sequence into a folder holding frames
//! of an earlier sequence that it would leave mixed with its own is held
//! back, naming them, until the user asks to replace the old sequence (the
//! command line's `--replace-sequence`); an output that is the scene's own
//! file, or one the scene reads, is refused.

use std::ops::RangeInclusive;
use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;
use std::time::Duration;

use eframe::egui;

use super::worker_job::WorkerJob;
use crate::animate::Evaluator;
use crate::editor::document::Document;
use crate::editor::files::dialog::{FileDialog, FileDialogMode, FileDialogOutcome};
use crate::editor::number_field::number_field;
use crate::editor::workspace::Workspace;
use crate::export::{
    AnimationFormat, ExportError, ExportOptions, ExportSummary, MAX_EXPORT_BYTES, SizeEstimate, check_export_size,
    check_output, export_animation_using,
};
use crate::scene::{Scene, readable_bytes};

/// An export running on its worker, and what it was started with.
struct Job {
    worker: WorkerJob<Result<ExportSummary, ExportError>>,
    settings: Settings,
    allowed: Allowed,
}

/// What the user allowed an export held back: to go past the size limit
/// or the free space, to replace an earlier sequence's frames.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Allowed {
    force: bool,
    replace: bool,
}

/// Why an export was held back.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Hold {
    /// Its size: "Export anyway" goes ahead.
    Size,
    /// An earlier sequence's frames: "Replace the old sequence" goes ahead.
    OldFrames,
    /// The output cannot be written (a file the scene reads): only other settings help.
    Output,
}

/// Why the last Export was held back, for the settings it was for; shown
/// with the button that goes ahead until the settings change.
struct Refusal {
    reason: String,
    hold: Hold,
    settings: Settings,
    /// What the user had allowed already, kept when allowing more.
    allowed: Allowed,
}

/// The Export window's settings and the running export.
pub(in crate::editor) struct ExportWindow {
    open: bool,
    format: AnimationFormat,
    first: i32,
    last: i32,
    output: String,
    dialog: Option<FileDialog>,
    job: Option<Job>,
    refused: Option<Refusal>,
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

/// The export's options: the full animation, never over `scene_path` or
/// the files the scene names, replacing an earlier sequence when allowed.
fn options(scene_path: Option<&Path>, allowed: Allowed) -> ExportOptions {
    ExportOptions {
        scene_path: scene_path.map(Path::to_path_buf),
        replace_sequence: allowed.replace,
        ..ExportOptions::default()
    }
}

/// What an export job starts from: the scene, where it is saved, and an
/// evaluator holding the rest shapes on screen.
struct Start {
    scene: Scene,
    scene_path: Option<PathBuf>,
    evaluator: Evaluator,
}

/// Starts exporting on a worker thread.
fn start(from: Start, settings: Settings, allowed: Allowed, ctx: egui::Context) -> Job {
    let Start { scene, scene_path, evaluator } = from;
    let (format, first, last, output) = settings.clone();
    let worker = WorkerJob::start(ctx, move |progress, cancel| {
        let mut progress = |done: usize, total: usize| {
            progress(done as u64, total.max(1) as u64);
            !cancel.load(Ordering::Relaxed)
        };
        let options = options(scene_path.as_deref(), allowed);
        let output = PathBuf::from(output.trim());
        export_animation_using(&scene, first..=last, &output, format, &options, evaluator, &mut progress)
    });
    Job { worker, settings, allowed }
}

/// Why the export `settings` describe should not go ahead with what the
/// user has `allowed`: a file the scene reads in the way; an earlier
/// sequence's frames it would leave mixed with its own (unless replacing);
/// its size (unless forced). `None` when it may go ahead.
fn refusal(scene: &Scene, scene_path: Option<&Path>, settings: &Settings, allowed: Allowed) -> Option<(Hold, String)> {
    let (format, first, last, output) = settings;
    let (frames, output) = (*first..=*last, Path::new(output.trim()));
    if let Err(error) = check_output(scene, frames.clone(), output, *format, &options(scene_path, allowed)) {
        let hold = if matches!(error, ExportError::OldFrames { .. }) { Hold::OldFrames } else { Hold::Output };
        return Some((hold, error.to_string()));
    }
    if allowed.force {
        return None;
    }
    size_refusal(scene, &frames, output, *format).map(|reason| (Hold::Size, reason))
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
    pub(in crate::editor) fn open_for(&mut self, doc: &Document) {
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

    pub(in crate::editor) fn window_ui(&mut self, ctx: &egui::Context, w: &mut Workspace) {
        self.finish(w);
        if !self.open {
            return;
        }
        let timeline = w.doc.scene().timeline.clone();
        let mut open = true;
        let mut start_now = false;
        // Set by "Export anyway" or "Replace the old sequence": what the user allows now.
        let mut allow_now: Option<Allowed> = None;
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
                        ui.add(number_field(ui.ctx(), &mut window.first).range(range.clone()))
                            .widget_info(|| egui::WidgetInfo::labeled(egui::Role::SpinButton, true, "First frame"));
                        ui.label("to");
                        ui.add(number_field(ui.ctx(), &mut window.last).range(range))
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
                Some(job) => job.worker.progress_ui(ui, "frame evaluations", "Starting"),
                None => {
                    let settings = window.settings();
                    if window.refused.as_ref().is_some_and(|refusal| refusal.settings != settings) {
                        window.refused = None;
                    }
                    if let Some(refusal) = &window.refused {
                        ui.colored_label(ui.visuals().warn_fg_color, format!("Not exported: {}.", refusal.reason));
                    }
                    ui.horizontal(|ui| {
                        let ready = !window.output.trim().is_empty();
                        start_now = ui.add_enabled(ready, egui::Button::new("Export")).clicked();
                        allow_now = window.refused.as_ref().and_then(|refusal| go_ahead_ui(ui, refusal));
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
        if start_now || allow_now.is_some() {
            self.export_or_hold(w, allow_now.unwrap_or_default(), ctx);
        }
        if !open {
            // Closing the window cancels an export in progress.
            if let Some(job) = &self.job {
                job.worker.cancel();
            }
            self.open = false;
        }
        if self.job.is_some() {
            ctx.request_repaint_after(Duration::from_millis(100));
        }
    }

    /// The settings as they are: format, frames and file.
    fn settings(&self) -> Settings {
        (self.format, self.first, self.last, self.output.clone())
    }

    /// Starts the export the settings describe, with what the user has
    /// `allowed` now and before for these settings, or holds it back with
    /// the reason.
    fn export_or_hold(&mut self, w: &Workspace, allowed: Allowed, ctx: &egui::Context) {
        let settings = self.settings();
        let before = self.refused.as_ref().filter(|r| r.settings == settings).map_or(Allowed::default(), |r| r.allowed);
        let allowed = Allowed { force: allowed.force || before.force, replace: allowed.replace || before.replace };
        match refusal(w.doc.scene(), w.doc.path(), &settings, allowed) {
            Some((hold, reason)) => self.refused = Some(Refusal { reason, hold, settings, allowed }),
            None => {
                self.refused = None;
                let from = Start {
                    scene: w.doc.scene().clone(),
                    scene_path: w.doc.path().map(Path::to_path_buf),
                    evaluator: w.shown.job_evaluator(),
                };
                self.job = Some(start(from, settings, allowed, ctx.clone()));
            }
        }
    }

    /// Reports a finished export.
    fn finish(&mut self, w: &mut Workspace) {
        let Some(job) = self.job.take_if(|job| job.worker.is_finished()) else { return };
        let Job { worker, settings, allowed } = job;
        let (result, elapsed) = worker.join();
        match result {
            Ok(Ok(summary)) => {
                let file = summary.files.first().map(|f| f.display().to_string()).unwrap_or_default();
                let seconds = elapsed.as_secs_f64();
                let removed = match summary.removed.len() {
                    0 => String::new(),
                    count => format!("; removed {count} frames of the earlier sequence"),
                };
                let reused = match summary.rest_shapes_built {
                    0 => " (each key's shape as on screen)".to_owned(),
                    1 => " (relaxing 1 key first)".to_owned(),
                    built => format!(" (relaxing {built} keys first)"),
                };
                let count = summary.frame_count;
                w.report(format!("Exported {count} frames to {file} in {seconds:.1} s{reused}{removed}"), false);
                self.open = false;
            }
            // The folder changed while the frames were evaluated.
            Ok(Err(error @ ExportError::OldFrames { .. })) => {
                self.refused = Some(Refusal { reason: error.to_string(), hold: Hold::OldFrames, settings, allowed });
            }
            Ok(Err(ExportError::Cancelled)) => w.report("Export cancelled; nothing was written.".to_owned(), false),
            Ok(Err(error)) => w.show_alert(format!("Could not export:\n{error}")),
            Err(_) => w.show_alert("The export stopped unexpectedly; nothing was written.".to_owned()),
        }
    }
}

/// The button that lets a held-back export go ahead, if one can: what it
/// allows when clicked.
fn go_ahead_ui(ui: &mut egui::Ui, refusal: &Refusal) -> Option<Allowed> {
    let (label, allowed) = match refusal.hold {
        Hold::Size => ("Export anyway", Allowed { force: true, replace: false }),
        Hold::OldFrames => ("Replace the old sequence", Allowed { force: false, replace: true }),
        Hold::Output => return None,
    };
    ui.button(label).clicked().then_some(allowed)
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
    use crate::editor::ui_driver::UiDriver;

    #[test]
    fn changing_the_format_changes_the_extension() {
        assert_eq!(with_format_extension("/a/carpet.glb", AnimationFormat::Pc2), "/a/carpet.pc2");
        assert_eq!(with_format_extension("carpet", AnimationFormat::Usda), "carpet.usda");
        assert_eq!(with_format_extension("  ", AnimationFormat::Usda), "");
    }

    #[test]
    fn a_huge_export_is_held_back_with_its_estimate() {
        let mut scene = crate::scene::parse(include_str!("../../../scenes/curtain.ron"), "curtain.ron").unwrap();
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
    fn an_old_sequence_is_held_back_until_it_may_be_replaced() {
        let scene = crate::scene::parse(include_str!("../../../scenes/curtain.ron"), "curtain.ron").unwrap();
        let dir = tempfile::tempdir().unwrap();
        for frame in 0..10 {
            std::fs::write(dir.path().join(format!("curtain_{frame:04}.obj")), "old").unwrap();
        }
        let settings = (AnimationFormat::ObjSequence, 0, 3, dir.path().display().to_string());
        let (hold, reason) = refusal(&scene, None, &settings, Allowed::default()).expect("held back");
        assert_eq!(hold, Hold::OldFrames);
        assert!(reason.contains("6 frames of a curtain_####.obj sequence"), "{reason}");
        assert!(reason.contains("(frames 4–9: curtain_0004.obj … curtain_0009.obj)"), "{reason}");
        assert_eq!(refusal(&scene, None, &settings, Allowed { force: false, replace: true }), None);
        let longer = (AnimationFormat::ObjSequence, 0, 12, dir.path().display().to_string());
        assert_eq!(refusal(&scene, None, &longer, Allowed::default()), None, "every old frame is replaced");
    }

    #[test]
    fn the_scene_s_own_file_is_never_an_output() {
        let scene = crate::scene::parse(include_str!("../../../scenes/curtain.ron"), "curtain.ron").unwrap();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("curtain.usda");
        std::fs::write(&path, "the scene").unwrap();
        let settings = (AnimationFormat::Usda, 0, 3, path.display().to_string());
        let allowed = Allowed { force: true, replace: true };
        let (hold, reason) = refusal(&scene, Some(&path), &settings, allowed).expect("refused");
        assert_eq!(hold, Hold::Output);
        assert!(reason.contains("the same file on disk as"), "{reason}");
        assert_eq!(refusal(&scene, None, &settings, Allowed::default()), None, "an unsaved scene has no file");
    }

    /// The Export window in an editor with `scene_file` open.
    struct Editor {
        window: ExportWindow,
        workspace: Workspace,
    }

    /// One frame of the window: what the status bar or an alert says once
    /// there is something.
    fn show(editor: &mut Editor, ctx: &egui::Context) -> Option<String> {
        editor.window.window_ui(ctx, &mut editor.workspace);
        let message = editor.workspace.message().map(|message| message.text.clone());
        message.or_else(|| editor.workspace.alert().map(str::to_owned))
    }

    /// Runs frames until the export started reports how it ended.
    fn finished(driver: &mut UiDriver<Editor, String>) -> String {
        let deadline = std::time::Instant::now() + Duration::from_secs(120);
        loop {
            if let Some(message) = driver.frame(Vec::new()) {
                return message;
            }
            assert!(std::time::Instant::now() < deadline, "the export did not finish");
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    fn old_curtain_frames(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> =
            std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        names.sort();
        names
    }

    #[test]
    fn file_export_holds_an_old_sequence_back_until_it_is_replaced() {
        let dir = tempfile::tempdir().unwrap();
        let scene_file = dir.path().join("curtain.ron");
        std::fs::write(&scene_file, include_str!("../../../scenes/curtain.ron")).unwrap();
        let folder = dir.path().join("seq");
        std::fs::create_dir(&folder).unwrap();
        for frame in 0..10 {
            std::fs::write(folder.join(format!("curtain_{frame:04}.obj")), "old").unwrap();
        }
        let workspace = Workspace::new(crate::scene::load(&scene_file).unwrap(), Some(scene_file));
        let mut window = ExportWindow { format: AnimationFormat::ObjSequence, ..ExportWindow::default() };
        window.open_for(&workspace.doc);
        (window.first, window.last, window.output) = (0, 3, folder.display().to_string());
        let mut driver = UiDriver::new(Editor { window, workspace }, show);

        assert_eq!(driver.click("Export"), None);
        assert!(driver.shows("Not exported: "), "the refusal is shown in the window");
        assert!(driver.shows("(frames 4–9: curtain_0004.obj … curtain_0009.obj)"));
        assert!(driver.state.window.job.is_none(), "nothing started");
        assert_eq!(old_curtain_frames(&folder).len(), 10);

        driver.click("Replace the old sequence");
        let message = finished(&mut driver);
        assert!(message.ends_with("; removed 6 frames of the earlier sequence"), "{message}");
        let expected: Vec<String> = (0..4).map(|frame| format!("curtain_{frame:04}.obj")).collect();
        assert_eq!(old_curtain_frames(&folder), expected);
        assert_ne!(std::fs::read_to_string(folder.join("curtain_0000.obj")).unwrap(), "old");
    }

    /// The export starts from the rest shapes the editor shows: it relaxes
    /// no key again, and says so.
    #[test]
    fn file_export_uses_the_shapes_on_screen() {
        let dir = tempfile::tempdir().unwrap();
        let scene_file = dir.path().join("curtain.ron");
        std::fs::write(&scene_file, include_str!("../../../scenes/curtain.ron")).unwrap();
        let mut workspace = Workspace::new(crate::scene::load(&scene_file).unwrap(), Some(scene_file));
        assert!(workspace.shown.wait_for(&workspace.doc, Duration::from_secs(120)), "the keys relax");
        // The viewport has drawn the scene.
        workspace.shown.refresh_mesh(0.0, crate::animate::Stage::Animated, None);
        let mut window = ExportWindow { format: AnimationFormat::Pc2, ..ExportWindow::default() };
        window.open_for(&workspace.doc);
        (window.first, window.last, window.output) = (0, 3, dir.path().join("curtain.pc2").display().to_string());
        let mut driver = UiDriver::new(Editor { window, workspace }, show);
        driver.click("Export");
        let message = finished(&mut driver);
        assert!(message.starts_with("Exported 4 frames to "), "{message}");
        assert!(message.ends_with("(each key's shape as on screen)"), "{message}");
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
