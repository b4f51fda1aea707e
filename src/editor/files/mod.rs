//! File ▸ New / Open / Open Recent / Save / Save As, the question before
//! unsaved work is thrown away (also when the window closes), load errors,
//! autosave to the recovery file and the offer to restore it. A scene from
//! the bundled examples' folder is a template: Save asks where, like Save As.

pub mod dialog;
pub mod prompt;
pub mod recent;
pub mod recovery;
pub mod window_size;

use std::path::{Path, PathBuf};
use std::time::{Instant, SystemTime};

use eframe::egui;

use self::dialog::{FileDialog, FileDialogMode, FileDialogOutcome};
use self::prompt::{DiscardChoice, discard_prompt};
use self::recent::RecentFiles;
use self::recovery::{AutosaveClock, DEFAULT_AUTOSAVE_INTERVAL, RecoveredScene, Recovery};
use super::shortcuts::{self, Shortcut};
use super::workspace::Workspace;
use crate::render::OrbitCamera;
use crate::scene::{self, Ease, Key, Pin, RelaxSettings, Scene, View};

/// What waits for the answer to "save changes?".
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Pending {
    New,
    Open,
    OpenPath(PathBuf),
    Quit,
}

/// What a file dialog was opened for.
#[derive(Clone, Debug, PartialEq)]
enum Purpose {
    Open,
    /// Save As, then carry on with the pending action (if the save came from the prompt).
    SaveAs(Option<Pending>),
}

/// The editor's file state.
pub(super) struct Files {
    dialog: Option<(FileDialog, Purpose)>,
    /// An action waiting on the save-changes prompt.
    prompt: Option<Pending>,
    recent: RecentFiles,
    recovery: Option<Recovery>,
    autosave: AutosaveClock,
    /// A scene that failed to load or save: the message, shown until dismissed.
    /// Unsaved work from a session that did not end cleanly, offered at start.
    recovered: Option<RecoveredScene>,
    /// The user chose to close: the next close request goes through.
    closing: bool,
    /// The bundled examples' folder: scenes there open as templates, and Save asks where.
    examples_dir: PathBuf,
}

/// The folder of the bundled example scenes, in the source tree Drape was built from.
pub fn bundled_examples_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes")
}

/// Whether `path` names a scene file directly in `examples_dir` (whatever way it is spelled).
fn is_example(path: &Path, examples_dir: &Path) -> bool {
    let folder = |p: &Path| std::fs::canonicalize(p).ok();
    let parent = std::path::absolute(path).ok().and_then(|p| p.parent().and_then(folder));
    parent.is_some() && parent == folder(examples_dir)
}

/// A window the File menu opens, which the app owns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum FileWindow {
    /// File ▸ Export… was chosen.
    Export,
    /// File ▸ Render… was chosen.
    Render,
}

impl Files {
    /// Recent files live in `config_dir`, the recovery file in `state_dir`; `None` keeps them off.
    pub(super) fn new(config_dir: Option<PathBuf>, state_dir: Option<PathBuf>) -> Files {
        let recent_file = config_dir.map(|dir| dir.join("recent.txt"));
        Files {
            dialog: None,
            prompt: None,
            recent: recent_file.map(|f| RecentFiles::load(&f)).unwrap_or_else(|| RecentFiles::load(Path::new(""))),
            recovery: state_dir.map(Recovery::new),
            autosave: AutosaveClock::new(DEFAULT_AUTOSAVE_INTERVAL, Instant::now()),
            recovered: None,
            closing: false,
            examples_dir: bundled_examples_dir(),
        }
    }

    /// Treats the scenes in `dir` as the bundled examples (tests, scripted runs).
    pub(super) fn set_examples_dir(&mut self, dir: PathBuf) {
        self.examples_dir = dir;
    }

    /// Whether the document is one of the bundled examples, a template that Save does not write over.
    pub(super) fn is_template(&self, w: &Workspace) -> bool {
        w.doc.path().is_some_and(|path| is_example(path, &self.examples_dir))
    }
}

/// File ▸ New: the default scene's cloth (1 m square, a 33 × 33 grid) hanging from its two top corners.
pub fn new_scene() -> Scene {
    let pin = |grid, x| Pin::at(grid, (x, 1.5, 0.0));
    Scene {
        keys: vec![Key {
            frame: 0,
            pins: vec![pin((0, 0), -0.5), pin((32, 0), 0.5)],
            elasticity: 1.05,
            stiffness: 0.2,
            relax: RelaxSettings::default(),
            ease: Ease::EaseInOut,
            inbetween_relax: 0,
            thickness: crate::scene::DEFAULT_THICKNESS_M,
            friction: crate::scene::DEFAULT_FRICTION,
            placement: None,
        }],
        ..Scene::default()
    }
}

impl Files {
    /// The File menu's items; returns the window chosen, if any.
    pub(super) fn file_menu_ui(
        &mut self,
        ui: &mut egui::Ui,
        w: &mut Workspace,
        camera: &mut OrbitCamera,
    ) -> Option<FileWindow> {
        let ctx = ui.ctx().clone();
        let item = |label: &str, shortcut: &Shortcut| egui::Button::new(label).shortcut_text(shortcut.menu_text(&ctx));
        if ui.add(item("New", &shortcuts::NEW)).clicked() {
            self.file_new(w, camera);
        }
        if ui.add(item("Open…", &shortcuts::OPEN)).clicked() {
            self.file_open(w, camera);
        }
        let recent: Vec<PathBuf> = self.recent.paths().to_vec();
        ui.add_enabled_ui(!recent.is_empty(), |ui| {
            ui.menu_button("Open Recent", |ui| {
                for path in recent {
                    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
                    if ui.button(name).on_hover_text(path.display().to_string()).clicked() {
                        self.ask_then(w, camera, Pending::OpenPath(path));
                    }
                }
            });
        });
        ui.separator();
        if ui.add(item("Save", &shortcuts::SAVE)).clicked() {
            self.file_save(w, camera);
        }
        if ui.add(item("Save As…", &shortcuts::SAVE_AS)).clicked() {
            self.file_save_as(w);
        }
        ui.separator();
        let mut chosen = None;
        if ui.button("Export…").on_hover_text("PC2, MDD, glTF, USD or an OBJ sequence").clicked() {
            chosen = Some(FileWindow::Export);
        }
        let render = ui.add(item("Render…", &shortcuts::RENDER));
        if render.on_hover_text("A PNG still, a PNG sequence or a GIF of the scene").clicked() {
            chosen = Some(FileWindow::Render);
        }
        ui.separator();
        if ui.button("Quit").clicked() {
            self.ask_then(w, camera, Pending::Quit);
        }
        chosen
    }

    pub(super) fn file_new(&mut self, w: &mut Workspace, camera: &mut OrbitCamera) {
        self.ask_then(w, camera, Pending::New);
    }

    pub(super) fn file_open(&mut self, w: &mut Workspace, camera: &mut OrbitCamera) {
        self.ask_then(w, camera, Pending::Open);
    }

    pub(super) fn file_save(&mut self, w: &mut Workspace, camera: &mut OrbitCamera) {
        self.save_then(w, camera, None);
    }

    pub(super) fn file_save_as(&mut self, w: &mut Workspace) {
        self.open_save_dialog(w, None);
    }

    /// Runs `action` now, or after the save-changes question when there is unsaved work.
    fn ask_then(&mut self, w: &mut Workspace, camera: &mut OrbitCamera, action: Pending) {
        if w.doc.is_dirty() {
            self.prompt = Some(action);
        } else {
            self.proceed(w, camera, action);
        }
    }

    fn proceed(&mut self, w: &mut Workspace, camera: &mut OrbitCamera, action: Pending) {
        match action {
            Pending::New => self.replace_document(w, camera, new_scene(), None),
            Pending::Open => {
                let dialog = FileDialog::new(FileDialogMode::Open, "Open scene", &w.doc.folder(), "", "ron");
                self.dialog = Some((dialog, Purpose::Open));
            }
            Pending::OpenPath(path) => self.open_path(w, camera, &path),
            Pending::Quit => {
                self.closing = true;
                if let Some(ctx) = w.shown.context() {
                    ctx.send_viewport_cmd(egui::ViewportCommand::Close);
                }
            }
        }
    }

    /// Loads `path`; on failure the error is shown and the current work stays as it is.
    pub fn open_path(&mut self, w: &mut Workspace, camera: &mut OrbitCamera, path: &Path) {
        match scene::load(path) {
            Ok(scene) => {
                self.recent.push(path);
                self.save_recent(w);
                self.replace_document(w, camera, scene, Some(path.to_path_buf()));
                if self.is_template(w) {
                    w.report(
                        format!("Opened {}, a bundled example: Save asks where to keep your copy.", path.display()),
                        false,
                    );
                } else {
                    w.report(format!("Opened {}", path.display()), false);
                }
            }
            Err(error) => {
                if !path.exists() {
                    self.recent.remove(path);
                    self.save_recent(w);
                }
                w.show_alert(format!("Could not open the scene:\n{error}"));
            }
        }
    }

    /// Shows `scene` as a fresh document: no history, nothing selected, the camera on its view.
    fn replace_document(&mut self, w: &mut Workspace, camera: &mut OrbitCamera, scene: Scene, path: Option<PathBuf>) {
        if let Some(view) = &scene.view {
            *camera = OrbitCamera::from_view(view);
        }
        // Framed once shown: always without a saved view, and with one when the cloth is out of it.
        w.shown.frame_once_shown();
        w.replace_document(scene, path);
    }

    /// Saves to the document's file (asking for one if it has none or is a
    /// bundled example), then carries on with `then`.
    fn save_then(&mut self, w: &mut Workspace, camera: &mut OrbitCamera, then: Option<Pending>) {
        match w.doc.path().map(Path::to_path_buf).filter(|_| !self.is_template(w)) {
            Some(path) => {
                if self.save_to(w, camera, &path)
                    && let Some(action) = then
                {
                    self.proceed(w, camera, action);
                }
            }
            None => self.open_save_dialog(w, then),
        }
    }

    fn open_save_dialog(&mut self, w: &Workspace, then: Option<Pending>) {
        let name = match w.doc.path() {
            Some(_) => w.doc.display_name(),
            None => "untitled.ron".to_owned(),
        };
        // A copy of an example goes where the user keeps work, not into Drape's source tree.
        let folder = match std::env::home_dir().filter(|_| self.is_template(w)) {
            Some(home) => home,
            None => w.doc.folder(),
        };
        let dialog = FileDialog::new(FileDialogMode::Save, "Save scene as", &folder, &name, "ron");
        self.dialog = Some((dialog, Purpose::SaveAs(then)));
    }

    /// Writes the scene (with the current camera) to `path` atomically; false and an error shown on failure.
    pub fn save_to(&mut self, w: &mut Workspace, camera: &OrbitCamera, path: &Path) -> bool {
        let view = View {
            frame: Some(w.frame().round() as i32),
            follow: w.session.follow(),
            through_camera: w.session.through_camera(),
            ..camera.to_view()
        };
        w.doc.set_view_quietly(Some(view));
        // Mesh files are named relative to the scene file: saved elsewhere, they are renamed to match.
        let folder_of = |file: Option<&Path>| {
            let folder = file.and_then(Path::parent).unwrap_or(Path::new(""));
            std::path::absolute(folder).unwrap_or_else(|_| folder.to_path_buf())
        };
        let (from, to) = (folder_of(w.doc.path()), folder_of(Some(path)));
        if from != to {
            w.doc.move_files_quietly(&from, &to);
        }
        match scene::save(w.doc.scene(), path) {
            Ok(()) => {
                w.doc.mark_saved(path.to_path_buf());
                self.recent.push(path);
                self.save_recent(w);
                if let Some(recovery) = &self.recovery {
                    let _ = recovery.clear();
                }
                w.report(format!("Saved {}", path.display()), false);
                true
            }
            Err(error) => {
                w.show_alert(format!("Could not save the scene; the file on disk is unchanged:\n{error}"));
                false
            }
        }
    }

    fn save_recent(&mut self, w: &mut Workspace) {
        if let Err(error) = self.recent.save()
            && !self.recent.config_file().as_os_str().is_empty()
        {
            w.report(format!("Could not remember recent files: {error}"), true);
        }
    }

    /// Dialogs, the save-changes prompt, load errors and the recovery offer, drawn every frame.
    pub(super) fn dialogs_ui(&mut self, ctx: &egui::Context, w: &mut Workspace, camera: &mut OrbitCamera) {
        if let Some((dialog, purpose)) = &mut self.dialog
            && let Some(outcome) = dialog.show(ctx)
        {
            let purpose = purpose.clone();
            self.dialog = None;
            if let FileDialogOutcome::Picked(path) = outcome {
                match purpose {
                    Purpose::Open => self.open_path(w, camera, &path),
                    Purpose::SaveAs(then) => {
                        if self.save_to(w, camera, &path)
                            && let Some(action) = then
                        {
                            self.proceed(w, camera, action);
                        }
                    }
                }
            }
        }
        if let Some(action) = self.prompt.clone() {
            let question = match action {
                Pending::Quit => "before closing",
                _ => "before continuing",
            };
            let message =
                format!("Save changes to {} {question}? Unsaved changes are lost otherwise.", w.doc.display_name());
            if let Some(choice) = discard_prompt(ctx, "Unsaved changes", &message) {
                self.prompt = None;
                match choice {
                    DiscardChoice::Save => self.save_then(w, camera, Some(action)),
                    DiscardChoice::Discard => self.proceed(w, camera, action),
                    DiscardChoice::Cancel => {}
                }
            }
        }
        Self::error_window(ctx, w);
        self.recovery_window(ctx, w, camera);
    }

    /// Shows a file problem (load, save, export) until the user dismisses it.
    fn error_window(ctx: &egui::Context, w: &mut Workspace) {
        let Some(error) = w.alert().map(str::to_owned) else { return };
        let modal = egui::Modal::new(egui::Id::unique("file-error")).show(ctx, |ui| {
            ui.set_max_width(560.0);
            ui.heading("Problem with the file");
            ui.add_space(6.0);
            ui.label(egui::RichText::new(error).monospace());
            ui.add_space(8.0);
            ui.weak("Your current work is untouched.");
            ui.button("OK").clicked()
        });
        if modal.inner || modal.should_close() {
            w.dismiss_alert();
        }
    }

    /// Adds the scene the editor was started on to the recent files.
    pub fn remember_opened(&mut self, w: &mut Workspace) {
        if let Some(path) = w.doc.path().map(Path::to_path_buf) {
            self.recent.push(&path);
            self.save_recent(w);
            if self.is_template(w) {
                w.report(format!("{} is a bundled example: Save asks where to keep your copy.", path.display()), false);
            }
        }
    }

    /// Looks for unsaved work a crashed session left; call once at start.
    pub fn offer_recovery(&mut self, w: &mut Workspace) {
        let Some(recovery) = &self.recovery else { return };
        match recovery.read() {
            Some(Ok(recovered)) => self.recovered = Some(recovered),
            Some(Err(error)) => {
                w.report(format!("A recovery file was found but cannot be read ({error}); it was kept."), true)
            }
            None => {}
        }
    }

    fn recovery_window(&mut self, ctx: &egui::Context, w: &mut Workspace, camera: &mut OrbitCamera) {
        let Some(recovered) = &self.recovered else { return };
        let text = recovered.describe(SystemTime::now());
        let modal = egui::Modal::new(egui::Id::unique("recovery")).show(ctx, |ui| {
            ui.set_max_width(460.0);
            ui.heading("Restore unsaved work?");
            ui.add_space(6.0);
            ui.label(format!("Drape did not close cleanly last time. {text}"));
            ui.add_space(10.0);
            ui.horizontal(|ui| {
                if ui.button("Restore").clicked() {
                    Some(true)
                } else if ui.button("Discard").clicked() {
                    Some(false)
                } else {
                    None
                }
            })
            .inner
        });
        let Some(restore) = modal.inner else { return };
        let Some(recovered) = self.recovered.take() else { return };
        if restore {
            self.replace_document(w, camera, recovered.scene.clone(), recovered.original.clone());
            w.doc.mark_unsaved();
            w.report("Restored the unsaved work; save it to keep it.".to_owned(), false);
        } else if let Some(recovery) = &self.recovery {
            let _ = recovery.clear();
        }
    }

    /// Writes the recovery file when the scene has unsaved changes and the clock says so.
    /// Autosaves every `interval` while there are unsaved changes instead of
    /// every [`DEFAULT_AUTOSAVE_INTERVAL`] (tests).
    pub fn set_autosave_interval(&mut self, interval: std::time::Duration) {
        self.autosave.interval = interval;
    }

    /// Writes the recovery file when it is due, and while the scene has
    /// unsaved changes asks for a frame when the next one is due: egui draws
    /// only on input, and an editor left alone must still autosave on time.
    pub(super) fn autosave(&mut self, ctx: &egui::Context, w: &mut Workspace) {
        let dirty = w.doc.is_dirty();
        let now = Instant::now();
        let due = self.autosave.due(now, dirty);
        if dirty && self.recovery.is_some() {
            ctx.request_repaint_after(self.autosave.time_until_due(now));
        }
        if !due {
            return;
        }
        if let Some(recovery) = &self.recovery
            && let Err(error) = recovery.write(w.doc.scene(), w.doc.path())
        {
            w.report(format!("Autosave failed: {error}"), true);
        }
    }

    /// A close request with unsaved work is held back until the user answers.
    pub(super) fn handle_close_request(&mut self, ctx: &egui::Context, w: &Workspace) {
        if ctx.input(|i| i.viewport().close_requested()) && w.doc.is_dirty() && !self.closing {
            ctx.send_viewport_cmd(egui::ViewportCommand::CancelClose);
            self.prompt = Some(Pending::Quit);
        }
    }

    /// The window is closing after the user's choice: no recovery is needed.
    pub(super) fn clean_exit(&mut self) {
        if let Some(recovery) = &self.recovery {
            let _ = recovery.clear();
        }
    }
}
