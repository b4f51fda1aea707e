//! File ▸ Render…: pictures of the scene as a PNG still at the playhead, a
//! numbered PNG sequence in a folder or a GIF, rendered on a worker thread
//! with a device of its own (the viewport's is never waited on) through
//! the same [`crate::render_job`] as `drape render`. The window shows the
//! progress with Cancel, then what was written or why not; a render past
//! 8 GiB or the free disk space is held back until the user asks to render
//! anyway, and a sequence into a folder holding frames of an earlier
//! sequence that it would leave mixed with its own until the user asks to
//! replace the old sequence. A cancelled or failed render leaves no file
//! behind.

use std::path::{Path, PathBuf};
use std::time::Duration;

use eframe::egui;

use super::worker_job::WorkerJob;
use crate::editor::document::Document;
use crate::editor::files::dialog::{FileDialog, FileDialogMode, FileDialogOutcome};
use crate::editor::number_field::number_field;
use crate::editor::workspace::Workspace;
use crate::export::sequence::file_stem_for;
use crate::picture::SceneOverlays;
use crate::render_job::{
    MAX_SIDE_PX, RenderJobError, RenderKind, RenderRequest, RenderSummary, default_size_px, render_to_files,
};
use crate::scene::Scene;

/// A render running on its worker, and what it was asked.
struct Job {
    worker: WorkerJob<Result<RenderSummary, RenderJobError>>,
    request: RenderRequest,
}

/// What the last render came to, shown under the settings until they
/// change (a stale "could not write" would mislead).
struct Outcome {
    text: String,
    tone: Tone,
    /// The request it came from, without what the user allowed.
    request: RenderRequest,
    /// What the user had allowed it (past the size, replacing old frames),
    /// kept when allowing more.
    allowed: Allowed,
}

/// What the user allowed a render held back.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Allowed {
    force: bool,
    replace: bool,
}

impl Allowed {
    fn of(request: &RenderRequest) -> Allowed {
        Allowed { force: request.force, replace: request.replace_sequence }
    }

    fn and(self, more: Allowed) -> Allowed {
        Allowed { force: self.force || more.force, replace: self.replace || more.replace }
    }

    /// `request` with nothing allowed, as the settings make it.
    fn cleared(request: RenderRequest) -> RenderRequest {
        RenderRequest { force: false, replace_sequence: false, ..request }
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Tone {
    /// What was written, or that nothing was (a cancel).
    Note,
    Error,
    /// Held back for its size, until the user renders anyway.
    HeldBack,
    /// Held back for an earlier sequence's frames, until the user replaces them.
    OldFrames,
}

/// The Render window's settings and the running render.
pub(in crate::editor) struct RenderWindow {
    open: bool,
    kind: RenderKind,
    first: i32,
    last: i32,
    size_px: (u32, u32),
    /// The size follows the camera and kind ([`default_size_px`]) until typed.
    size_auto: bool,
    /// Looks through the scene's shot camera (else the framing view).
    shot: bool,
    toon: bool,
    /// The cloth alone over transparency (PNGs only).
    alpha: bool,
    /// The shadow pass alone (PNGs only).
    shadow: bool,
    plate: bool,
    colliders: bool,
    references: bool,
    /// What `drape render` draws with --wireframe, --pins, --catenaries, --triangulation.
    overlays: [bool; 4],
    output: String,
    dialog: Option<FileDialog>,
    job: Option<Job>,
    outcome: Option<Outcome>,
}

impl Default for RenderWindow {
    fn default() -> Self {
        RenderWindow {
            open: false,
            kind: RenderKind::Png,
            first: 0,
            last: 0,
            size_px: crate::render_job::DEFAULT_PNG_SIZE,
            size_auto: true,
            shot: true,
            toon: false,
            alpha: false,
            shadow: false,
            plate: true,
            colliders: true,
            references: true,
            overlays: [false; 4],
            output: String::new(),
            dialog: None,
            job: None,
            outcome: None,
        }
    }
}

/// `path` made fit for `kind`: `.png` or `.gif` for a file, no extension
/// for a sequence's folder. An empty path stays empty.
fn output_for_kind(path: &str, kind: RenderKind) -> String {
    let path = Path::new(path.trim());
    if path.as_os_str().is_empty() {
        return String::new();
    }
    let extension = match kind {
        RenderKind::Png => "png",
        RenderKind::Gif => "gif",
        RenderKind::Sequence => "",
    };
    path.with_extension(extension).display().to_string()
}

/// Starts rendering on a worker thread with its own headless device.
fn start(scene: Scene, scene_path: Option<PathBuf>, request: RenderRequest, ctx: egui::Context) -> Job {
    let job_request = request.clone();
    let worker = WorkerJob::start(ctx, move |progress, cancel| {
        render_to_files(&scene, scene_path.as_deref(), &job_request, None, progress, cancel)
    });
    Job { worker, request }
}

impl RenderWindow {
    /// Opens the window on the whole timeline, through the shot camera when
    /// the scene has one, in the viewport's style (`toon`), writing next to
    /// the scene's file; other settings stay as the user left them.
    pub(in crate::editor) fn open_for(&mut self, doc: &Document, toon: bool) {
        let scene = doc.scene();
        self.open = true;
        self.first = scene.timeline.start;
        self.last = scene.timeline.end;
        self.toon = toon;
        self.shot = scene.camera.is_some();
        self.plate = scene.plate.is_some() && self.shot;
        self.size_auto = true;
        if self.output.is_empty() {
            let stem = match doc.path().and_then(Path::file_stem) {
                Some(stem) => stem.to_string_lossy().into_owned(),
                None => file_stem_for(&scene.name),
            };
            let name = output_for_kind(&stem, self.kind);
            self.output = doc.folder().join(name).display().to_string();
        }
    }

    /// The request the settings make, the PNG still at `playhead`.
    fn request(&self, scene: &Scene, playhead: i32) -> RenderRequest {
        let png = self.kind.is_png();
        let shadow = self.shadow && png;
        let alpha = self.alpha && png && !shadow;
        let frames = match self.kind {
            RenderKind::Png => playhead..=playhead,
            RenderKind::Sequence | RenderKind::Gif => self.first..=self.last,
        };
        let [wireframe, pins, catenaries, triangulation] = self.overlays;
        let overlays = SceneOverlays {
            wireframe,
            pins,
            catenaries,
            triangulation,
            hide_colliders: !self.colliders,
            hide_references: !self.references,
            view_camera: !(self.shot && scene.camera.is_some()),
            alpha,
            shadow_pass: shadow,
            toon: self.toon,
        };
        let mut request = RenderRequest::new(self.kind, PathBuf::from(self.output.trim()), frames, self.size_px);
        request.overlays = overlays;
        request.plate = self.plate && scene.plate.is_some() && !alpha && !shadow;
        request
    }

    pub(in crate::editor) fn window_ui(&mut self, ctx: &egui::Context, w: &mut Workspace) {
        self.finish(w);
        if !self.open {
            return;
        }
        let scene = w.doc.scene();
        let timeline = scene.timeline.clone();
        let playhead = (w.frame().round() as i32).clamp(timeline.start, timeline.end);
        if self.size_auto {
            self.size_px = default_size_px(scene, self.kind, !(self.shot && scene.camera.is_some()));
        }
        let mut open = true;
        let (mut render_now, mut choose) = (false, false);
        // Set by "Render anyway" or "Replace the old sequence": what the user allows now.
        let mut allow_now: Option<Allowed> = None;
        let busy = self.job.is_some();
        egui::Window::new("Render").open(&mut open).collapsible(false).resizable(false).show(ctx, |ui| {
            ui.add_enabled_ui(!busy, |ui| {
                egui::Grid::new("render settings").num_columns(2).show(ui, |ui| {
                    self.settings_ui(ui, scene, playhead);
                    let label = ui.label(if self.kind == RenderKind::Sequence { "Folder" } else { "File" }).id;
                    ui.horizontal(|ui| {
                        let field = egui::TextEdit::singleline(&mut self.output).desired_width(320.0);
                        let _ = ui.add(field).labelled_by(label);
                        choose = ui.button("Choose…").clicked();
                    });
                    ui.end_row();
                });
            });
            ui.separator();
            match &self.job {
                Some(job) => job.worker.progress_ui(ui, "frames", "Preparing the cloth's shapes and the GPU"),
                None => {
                    let request = self.request(scene, playhead);
                    if self.outcome.as_ref().is_some_and(|outcome| outcome.request != request) {
                        self.outcome = None;
                    }
                    outcome_ui(ui, self.outcome.as_ref());
                    ui.horizontal(|ui| {
                        let ready = !self.output.trim().is_empty();
                        render_now = ui.add_enabled(ready, egui::Button::new("Render")).clicked();
                        allow_now = self.outcome.as_ref().and_then(|outcome| go_ahead_ui(ui, outcome.tone));
                    });
                }
            }
        });
        if choose {
            self.dialog = Some(self.output_dialog(&w.doc));
        }
        if let Some(dialog) = &mut self.dialog
            && let Some(outcome) = dialog.show(ctx)
        {
            if let FileDialogOutcome::Picked(path) = outcome {
                self.output = path.display().to_string();
            }
            self.dialog = None;
        }
        if render_now || allow_now.is_some() {
            let scene = w.doc.scene();
            let mut request = self.request(scene, playhead);
            if let Some(more) = allow_now {
                // The outcome is for these settings (it is cleared when they change).
                let allowed = self.outcome.as_ref().map_or(Allowed::default(), |outcome| outcome.allowed).and(more);
                (request.force, request.replace_sequence) = (allowed.force, allowed.replace);
            }
            self.outcome = None;
            self.job = Some(start(scene.clone(), w.doc.path().map(Path::to_path_buf), request, ctx.clone()));
        }
        if !open {
            // Closing the window cancels a render in progress.
            if let Some(job) = &self.job {
                job.worker.cancel();
            }
            self.open = false;
        }
        if self.job.is_some() {
            ctx.request_repaint_after(Duration::from_millis(100));
        }
    }

    /// The rows above the output: kind, frames, size, camera, style, pass,
    /// alpha, plate and what else is shown.
    fn settings_ui(&mut self, ui: &mut egui::Ui, scene: &Scene, playhead: i32) {
        let timeline = &scene.timeline;
        ui.label("Write");
        ui.horizontal(|ui| {
            let before = self.kind;
            for kind in RenderKind::ALL {
                ui.radio_value(&mut self.kind, kind, kind.label());
            }
            if self.kind != before {
                self.output = output_for_kind(&self.output, self.kind);
            }
        });
        ui.end_row();

        ui.label("Frames");
        ui.horizontal(|ui| {
            if self.kind == RenderKind::Png {
                ui.label(format!("{playhead} (the playhead)"));
                return;
            }
            let range = timeline.start..=timeline.end;
            ui.add(number_field(ui.ctx(), &mut self.first).range(range.clone()))
                .widget_info(|| egui::WidgetInfo::labeled(egui::Role::SpinButton, true, "First frame"));
            ui.label("to");
            ui.add(number_field(ui.ctx(), &mut self.last).range(range))
                .widget_info(|| egui::WidgetInfo::labeled(egui::Role::SpinButton, true, "Last frame"));
            self.last = self.last.max(self.first);
            let count = self.last - self.first + 1;
            ui.weak(format!("{count} frames, {:.2} s at {} fps", f64::from(count) / timeline.fps, timeline.fps));
        });
        ui.end_row();

        ui.label("Size");
        ui.horizontal(|ui| {
            let before = self.size_px;
            let sides = 1..=MAX_SIDE_PX;
            ui.add(number_field(ui.ctx(), &mut self.size_px.0).range(sides.clone()))
                .widget_info(|| egui::WidgetInfo::labeled(egui::Role::SpinButton, true, "Picture width"));
            ui.label("×");
            ui.add(number_field(ui.ctx(), &mut self.size_px.1).range(sides))
                .widget_info(|| egui::WidgetInfo::labeled(egui::Role::SpinButton, true, "Picture height"));
            ui.label("px");
            if self.size_px != before {
                self.size_auto = false;
            }
            let default = if self.shot && scene.camera.is_some() { "the camera's image size" } else { "default" };
            if self.size_auto {
                ui.weak(format!("({default})"));
            } else if ui.small_button("Reset").on_hover_text(format!("Back to {default}")).clicked() {
                self.size_auto = true;
            }
        });
        ui.end_row();

        ui.label("Camera");
        ui.horizontal(|ui| {
            let has_camera = scene.camera.is_some();
            ui.radio_value(&mut self.shot, false, "View").on_hover_text(
                "The scene's saved view, or one that frames every key (as `drape render --camera view`)",
            );
            ui.add_enabled_ui(has_camera, |ui| {
                ui.radio_value(&mut self.shot, true, "Shot camera")
                    .on_disabled_hover_text("The scene has no shot camera (View menu: Add camera from view)");
            });
        });
        ui.end_row();

        ui.label("Style");
        ui.horizontal(|ui| {
            ui.radio_value(&mut self.toon, false, "Lit");
            ui.radio_value(&mut self.toon, true, "Toon");
        });
        ui.end_row();

        let png = self.kind.is_png();
        ui.label("Pass");
        ui.horizontal(|ui| {
            ui.radio_value(&mut self.shadow, false, "Cloth");
            ui.add_enabled_ui(png, |ui| {
                ui.radio_value(&mut self.shadow, true, "Shadow")
                    .on_hover_text("The cloth's shadow on the ground alone, black with alpha")
                    .on_disabled_hover_text("A GIF has no alpha channel: the shadow pass is written as PNGs");
            });
        });
        ui.end_row();

        ui.label("Alpha");
        let alpha_possible = png && !self.shadow;
        ui.add_enabled_ui(alpha_possible, |ui| {
            // Disabled, it shows what the render does (no alpha), keeping the choice for later.
            let mut shown = false;
            let target = if alpha_possible { &mut self.alpha } else { &mut shown };
            let text = "The cloth alone over transparency (straight alpha, as PNG stores it)";
            ui.checkbox(target, text).on_disabled_hover_text("PNGs of the cloth pass only: a GIF has no alpha channel");
        });
        ui.end_row();

        if scene.plate.is_some() {
            ui.label("Plate");
            let separate = png && (self.alpha || self.shadow);
            ui.add_enabled_ui(!separate, |ui| {
                let mut shown = false;
                let target = if separate { &mut shown } else { &mut self.plate };
                ui.checkbox(target, "Over the background plate").on_disabled_hover_text(
                    "Alpha and shadow renders are the cloth or its shadow alone, to lay over the plate later",
                );
            });
            ui.end_row();
        }

        ui.label("Show");
        ui.horizontal(|ui| {
            ui.checkbox(&mut self.colliders, "Colliders");
            ui.checkbox(&mut self.references, "References");
        });
        ui.end_row();

        ui.label("Overlays");
        ui.horizontal_wrapped(|ui| {
            let [wireframe, pins, catenaries, triangulation] = &mut self.overlays;
            ui.checkbox(wireframe, "Wireframe");
            ui.checkbox(pins, "Pins");
            ui.checkbox(catenaries, "Catenaries").on_hover_text("The key's catenary network, conflicts in magenta");
            ui.checkbox(triangulation, "Triangulation").on_hover_text("The key's triangulation of its pins");
        });
        ui.end_row();
    }

    /// The file dialog for the output: a `.png` or `.gif` file, or for a
    /// sequence the name of the folder the frames go into.
    fn output_dialog(&self, doc: &Document) -> FileDialog {
        let typed = Path::new(self.output.trim());
        let dir = typed.parent().filter(|d| d.is_dir()).map(Path::to_path_buf).unwrap_or_else(|| doc.folder());
        let name = typed.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let (title, extension) = match self.kind {
            RenderKind::Png => ("Render to", "png"),
            RenderKind::Gif => ("Render to", "gif"),
            RenderKind::Sequence => ("Render the frames into the folder", ""),
        };
        FileDialog::new(FileDialogMode::Save, title, &dir, &name, extension)
    }

    /// Takes in a finished render: what it wrote, or why not.
    fn finish(&mut self, w: &mut Workspace) {
        let Some(job) = self.job.take_if(|job| job.worker.is_finished()) else { return };
        let (text, tone) = match job.worker.join().0 {
            Ok(Ok(summary)) => {
                let text = summary_text(&summary);
                w.report(text.clone(), false);
                let warnings: String = summary.warnings.iter().map(|warning| format!("\nNote: {warning}.")).collect();
                (text + &warnings, Tone::Note)
            }
            Ok(Err(RenderJobError::Cancelled)) => ("Cancelled; nothing was written.".to_owned(), Tone::Note),
            Ok(Err(RenderJobError::TooLarge(reason))) => (format!("Not rendered: {reason}."), Tone::HeldBack),
            Ok(Err(RenderJobError::OldFrames(reason))) => (format!("Not rendered: {reason}."), Tone::OldFrames),
            Ok(Err(error)) => (format!("Could not render: {error}."), Tone::Error),
            Err(_) => ("The render stopped unexpectedly; nothing was written.".to_owned(), Tone::Error),
        };
        // Compared with the settings as they are next frame, which allow nothing.
        let allowed = Allowed::of(&job.request);
        let request = Allowed::cleared(job.request);
        self.outcome = Some(Outcome { text, tone, request, allowed });
    }
}

/// What a finished render wrote, in a sentence.
fn summary_text(summary: &RenderSummary) -> String {
    let (width, height) = summary.size_px;
    let frames = match summary.frame_count() {
        1 => format!("frame {}", summary.frames.start()),
        count => format!("{count} frames ({}..{})", summary.frames.start(), summary.frames.end()),
    };
    let removed = match summary.removed.len() {
        0 => String::new(),
        count => format!("; removed {count} frames of the earlier sequence"),
    };
    format!(
        "Rendered {frames} at {width}×{height} to {} in {:.1} s{removed}",
        summary.output.display(),
        summary.elapsed.as_secs_f64()
    )
}

/// The button that lets a held-back render go ahead, if its outcome has
/// one: what it allows when clicked.
fn go_ahead_ui(ui: &mut egui::Ui, tone: Tone) -> Option<Allowed> {
    let (label, allowed) = match tone {
        Tone::HeldBack => ("Render anyway", Allowed { force: true, replace: false }),
        Tone::OldFrames => ("Replace the old sequence", Allowed { force: false, replace: true }),
        Tone::Note | Tone::Error => return None,
    };
    ui.button(label).clicked().then_some(allowed)
}

/// The last render's result: a note in the text colour, a problem in the error colour.
fn outcome_ui(ui: &mut egui::Ui, outcome: Option<&Outcome>) {
    let Some(Outcome { text, tone, .. }) = outcome else { return };
    let color = match tone {
        Tone::Note => ui.visuals().text_color(),
        Tone::Error => ui.visuals().error_fg_color,
        Tone::HeldBack | Tone::OldFrames => ui.visuals().warn_fg_color,
    };
    ui.colored_label(color, text);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::editor::ui_driver::UiDriver;

    #[test]
    fn changing_the_kind_changes_the_extension() {
        assert_eq!(output_for_kind("/a/carpet.png", RenderKind::Gif), "/a/carpet.gif");
        assert_eq!(output_for_kind("/a/carpet.gif", RenderKind::Sequence), "/a/carpet");
        assert_eq!(output_for_kind("/a/carpet", RenderKind::Png), "/a/carpet.png");
        assert_eq!(output_for_kind("  ", RenderKind::Png), "");
    }

    #[test]
    fn alpha_and_shadow_are_for_pngs_and_leave_out_the_plate() {
        let scene = crate::scene::parse(include_str!("../../../scenes/magic_carpet.ron"), "magic_carpet.ron").unwrap();
        let mut window =
            RenderWindow { kind: RenderKind::Gif, alpha: true, output: "x.gif".into(), ..Default::default() };
        let request = window.request(&scene, 5);
        assert!(!request.overlays.alpha && request.plate == scene.plate.is_some(), "{request:?}");
        assert_eq!(request.frames, 0..=0, "a GIF renders the chosen range");
        window.kind = RenderKind::Png;
        let request = window.request(&scene, 5);
        assert!(request.overlays.alpha && !request.plate);
        assert_eq!(request.frames, 5..=5, "a still renders the playhead");
        window.shadow = true;
        let request = window.request(&scene, 5);
        assert!(request.overlays.shadow_pass && !request.overlays.alpha && !request.plate);
    }

    #[test]
    fn overlays_are_asked_for_as_drape_render_s_flags_ask() {
        let scene = crate::scene::parse(include_str!("../../../scenes/magic_carpet.ron"), "magic_carpet.ron").unwrap();
        let window = RenderWindow { overlays: [true, false, true, false], ..Default::default() };
        let overlays = window.request(&scene, 0).overlays;
        assert!(overlays.wireframe && !overlays.pins && overlays.catenaries && !overlays.triangulation);
        assert!(!RenderWindow::default().request(&scene, 0).overlays.wireframe, "none by default");
    }

    /// The Render window in an editor.
    struct Editor {
        window: RenderWindow,
        workspace: Workspace,
    }

    /// One frame of the window: what the status bar or an alert says once
    /// there is something.
    fn show(editor: &mut Editor, ctx: &egui::Context) -> Option<String> {
        editor.window.window_ui(ctx, &mut editor.workspace);
        let message = editor.workspace.message().map(|message| message.text.clone());
        message.or_else(|| editor.workspace.alert().map(str::to_owned))
    }

    /// Runs frames until the render under way has finished; returns what the
    /// status bar says by then.
    fn until_finished(driver: &mut UiDriver<Editor, String>) -> Option<String> {
        let deadline = std::time::Instant::now() + Duration::from_secs(300);
        loop {
            let message = driver.frame(Vec::new());
            if driver.state.window.job.is_none() {
                return message;
            }
            assert!(std::time::Instant::now() < deadline, "the render did not finish");
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    fn names_in(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> =
            std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        names.sort();
        names
    }

    #[test]
    fn file_render_holds_an_old_sequence_back_until_it_is_replaced() {
        let dir = tempfile::tempdir().unwrap();
        let scene_file = dir.path().join("curtain.ron");
        std::fs::write(&scene_file, include_str!("../../../scenes/curtain.ron")).unwrap();
        let folder = dir.path().join("frames");
        std::fs::create_dir(&folder).unwrap();
        for frame in 0..6 {
            std::fs::write(folder.join(format!("curtain_{frame:04}.png")), "old").unwrap();
        }
        let workspace = Workspace::new(crate::scene::load(&scene_file).unwrap(), Some(scene_file));
        let mut window = RenderWindow::default();
        window.open_for(&workspace.doc, false);
        window.kind = RenderKind::Sequence;
        (window.first, window.last, window.size_px, window.size_auto) = (0, 2, (32, 24), false);
        window.output = folder.display().to_string();
        let mut driver = UiDriver::new(Editor { window, workspace }, show);

        driver.click("Render");
        assert_eq!(until_finished(&mut driver), None, "nothing rendered");
        assert!(driver.shows("Not rendered: "), "the refusal is shown in the window");
        assert!(driver.shows("(frames 3–5: curtain_0003.png … curtain_0005.png)"));
        assert_eq!(names_in(&folder).len(), 6);

        driver.click("Replace the old sequence");
        let message = until_finished(&mut driver).expect("rendered");
        assert!(message.ends_with("; removed 3 frames of the earlier sequence"), "{message}");
        assert_eq!(names_in(&folder), ["curtain_0000.png", "curtain_0001.png", "curtain_0002.png"]);
        assert_ne!(std::fs::read(folder.join("curtain_0000.png")).unwrap(), b"old");
    }
}
