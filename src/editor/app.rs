//! The editor window: menus on top, the Cloth panel on the left, the view bar
//! over the 3D viewport in the centre, the Layers, Colliders and References panels on
//! the right, a status bar and the timeline along the bottom.
//!
//! The app is thin: it owns the [`Workspace`] (the document, what is shown,
//! this document's playhead and selections) and one struct per panel, each
//! with its own state and a `ui` entry taking the workspace. A new document
//! gets a new session and new per-document panels, so nothing of the old one
//! lingers.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use eframe::egui::{self, Key as KeyCode};
use eframe::egui_wgpu;

use super::attach;
use super::document::Document;
use super::files::recent::default_config_dir;
use super::files::recovery::default_state_dir;
use super::files::window_size::{self, DEFAULT_WINDOW_SIZE, MIN_WINDOW_SIZE, WINDOW_SIZE_NAME};
use super::files::{FileWindow, Files};
use super::panels::cloth::{ClothPanel, GRID_EDITOR_HINT};
use super::panels::colliders::CollidersPanel;
use super::panels::layers::LayersPanel;
use super::panels::references::ReferencesPanel;
use super::panels::shot::ShotPanel;
use super::pin_clipboard;
use super::shaper::ShaperStatus;
use super::shortcuts::{self, SHORTCUTS};
use super::timeline::TimelinePanel;
use super::typing_pace::TypingPace;
use super::viewport::ViewportPanel;
use super::viewport::gpu;
use super::windows::export::ExportWindow;
use super::windows::render::RenderWindow;
use super::workspace::{MESSAGE_SECS, TakeBack, Workspace};
use crate::mesh::Mesh;
use crate::render::OrbitCamera;
use crate::scene::Scene;

/// The scene the editor opens with when none is given: the paper's magic carpet.
pub const DEFAULT_SCENE: &str = include_str!("../../scenes/magic_carpet.ron");

pub struct DrapeApp {
    work: Workspace,
    viewport: ViewportPanel,
    panels: DocumentPanels,
    cloth: ClothPanel,
    files: Files,
    export: ExportWindow,
    render: RenderWindow,
    show_shortcuts: bool,
    manual: super::windows::manual::Manual,
    /// CPU time of the last update and the smoothed time between frames, for the readout.
    last_update_ms: f64,
    frame_interval_ms: f64,
    last_frame_at: Option<Instant>,
    /// Close the window after this many frames (`--quit-after-frames`).
    quit_after_frames: Option<u64>,
    frames_drawn: u64,
    /// The window title last sent.
    sent_title: String,
    /// Where the status bar was drawn last frame (points).
    status_rect: egui::Rect,
    /// Typing and focus moves that arrived together, taken one frame at a time.
    typing: TypingPace,
    /// Where the window's size is kept between runs (`None`: not kept).
    window_size_file: Option<PathBuf>,
    /// The window's inner size last frame, saved on exit.
    window_size: Option<egui::Vec2>,
    /// The window was fitted to its screen (once, when the screen's size is first known).
    window_fitted: bool,
    /// The size asked of the window that it has not reached yet, and the
    /// frames waited for it: the viewport judges a saved view only after.
    window_resizing: Option<(egui::Vec2, u32)>,
}

impl DrapeApp {
    /// Opens `scene`, framing the camera on its keys (or using its saved view).
    pub fn new(scene: Scene, path: Option<PathBuf>, render_state: Option<&egui_wgpu::RenderState>) -> DrapeApp {
        if let Some(render_state) = render_state {
            gpu::install(render_state);
        }
        // The first shapes are relaxed before the window shows anything: there is no older shape to show.
        let mut work = Workspace::new(scene, path);
        let viewport = ViewportPanel::new(&mut work, render_state.is_some());
        viewport.refresh(&mut work);
        DrapeApp {
            panels: DocumentPanels::new(work.document_number(), TimelinePanel::default()),
            work,
            viewport,
            cloth: ClothPanel::default(),
            files: Files::new(default_config_dir(), default_state_dir()),
            export: ExportWindow::default(),
            render: RenderWindow::default(),
            show_shortcuts: false,
            manual: super::windows::manual::Manual::default(),
            last_update_ms: 0.0,
            frame_interval_ms: 0.0,
            last_frame_at: None,
            quit_after_frames: None,
            frames_drawn: 0,
            sent_title: String::new(),
            status_rect: egui::Rect::NOTHING,
            typing: TypingPace::default(),
            window_size_file: default_config_dir().map(|dir| dir.join(WINDOW_SIZE_NAME)),
            window_size: None,
            window_fitted: false,
            window_resizing: None,
        }
    }

    /// Keeps recent files in `config_dir` and the recovery file in `state_dir`
    /// instead of the user's (tests, scripted runs); `None` turns that feature off.
    pub fn with_file_dirs(mut self, config_dir: Option<PathBuf>, state_dir: Option<PathBuf>) -> Self {
        self.window_size_file = config_dir.as_ref().map(|dir| dir.join(WINDOW_SIZE_NAME));
        self.files = Files::new(config_dir, state_dir);
        self
    }

    /// Treats the scenes in `dir` as the bundled examples, which open as
    /// templates (tests, scripted runs; the source tree's `scenes/` otherwise).
    pub fn with_examples_dir(mut self, dir: PathBuf) -> Self {
        self.files.set_examples_dir(dir);
        self
    }

    /// Writes the recovery file this often while there are unsaved changes.
    pub fn with_autosave_interval(mut self, interval: Duration) -> Self {
        self.files.set_autosave_interval(interval);
        self
    }

    /// Closes the window after `frames` frames (a scripted smoke test).
    pub fn quit_after_frames(mut self, frames: u64) -> Self {
        self.quit_after_frames = Some(frames);
        self
    }

    /// Where the viewport was drawn in the last frame, in points.
    pub fn viewport_rect(&self) -> egui::Rect {
        self.viewport.rect()
    }

    /// Where the status bar (messages, timings) was drawn in the last frame, in points.
    pub fn status_rect(&self) -> egui::Rect {
        self.status_rect
    }

    /// Where a world point appears on screen (points), `None` behind the camera.
    pub fn screen_pos(&self, world: glam::Vec3) -> Option<egui::Pos2> {
        self.viewport.screen_pos(world)
    }

    /// The document's scene (what a save writes).
    pub fn scene(&self) -> &Scene {
        self.work.doc.scene()
    }

    pub fn document(&self) -> &Document {
        &self.work.doc
    }

    /// The scene on screen: the document once its shapes are relaxed.
    pub fn shown_scene(&self) -> &Scene {
        self.work.shown.scene()
    }

    /// The translate gizmo on the selected pins, as drawn last frame.
    pub fn gizmo(&self) -> Option<super::viewport::gizmo::Gizmo> {
        self.viewport.drawn_gizmo(&self.work)
    }

    pub fn camera(&self) -> &OrbitCamera {
        self.viewport.camera()
    }

    pub fn frame(&self) -> f64 {
        self.work.frame()
    }

    /// Whether the viewport looks through the scene's shot camera (View ▸ Camera).
    pub fn looks_through_shot_camera(&self) -> bool {
        self.work.session.through_camera()
    }

    /// Whether the viewport's camera follows the cloth (Follow).
    pub fn follows_cloth(&self) -> bool {
        self.work.session.follow()
    }

    pub fn playing(&self) -> bool {
        self.work.session.playing()
    }

    /// The mesh on screen: for [`Stage::Animation`](super::viewport::Stage::Animation), `evaluate` of the shown scene at [`DrapeApp::frame`].
    pub fn mesh(&self) -> &Mesh {
        self.work.shown.mesh()
    }

    /// How many onion-skin ghosts the viewport draws now.
    pub fn ghost_count(&self) -> usize {
        self.work.shown.ghosts().len()
    }

    pub fn selection(&self) -> &[(u32, u32)] {
        self.work.session.selection()
    }

    /// The pin the next click on a reference attaches, while attaching by clicking.
    pub fn attaching(&self) -> Option<(u32, u32)> {
        self.work.session.attaching()
    }

    /// The collider the Colliders panel shows and the viewport outlines.
    pub fn selected_collider(&self) -> Option<usize> {
        self.work.session.selected_collider()
    }

    /// Whether the viewport drew the cloth as stale last frame: grey, the
    /// old shape on screen while the document's new one is solved.
    pub fn cloth_drawn_stale(&self) -> bool {
        self.viewport.cloth_drawn_stale()
    }

    /// Whether a relaxation is pending or running.
    pub fn is_relaxing(&self) -> bool {
        self.work.shown.is_relaxing(&self.work.doc)
    }

    /// Blocks until the document's shapes are relaxed and shown and the worker is idle (tests and scripts).
    pub fn wait_for_shapes(&mut self, timeout: Duration) -> bool {
        let shown = self.work.shown.wait_for(&self.work.doc, timeout);
        self.viewport.refresh(&mut self.work);
        shown
    }

    /// Moves the playhead; the mesh follows on the next update.
    pub fn set_frame(&mut self, frame: f64) {
        self.work.set_frame(frame);
    }

    /// The index of the key being edited: the one in effect at the playhead.
    pub fn edit_key_index(&self) -> usize {
        self.work.edit_key_index()
    }

    /// Applies an edit to the document, reporting a rejected one in the status bar.
    pub fn apply(&mut self, label: &str, change: impl FnOnce(&mut Scene)) {
        self.work.apply(label, change);
    }

    /// Pins grid point `point` of the key being edited where the cloth is now, or unpins it.
    pub fn toggle_pin(&mut self, point: (u32, u32)) {
        self.work.toggle_pin(point);
    }

    pub fn copy_selected_pins(&mut self) -> Option<String> {
        pin_clipboard::copy_selected_pins(&mut self.work)
    }

    pub fn paste_pins(&mut self, clipboard_text: Option<&str>) {
        pin_clipboard::paste_pins(&mut self.work, clipboard_text);
    }

    pub fn mirror_selected_pins(&mut self) {
        pin_clipboard::mirror_selected_pins(&mut self.work);
    }

    pub fn select_pins(&mut self, pins: &[(u32, u32)]) {
        self.work.session.select_only(pins);
    }

    pub fn delete_selected_pins(&mut self) {
        self.work.delete_selected_pins();
    }

    pub fn undo(&mut self) {
        self.viewport.abandon_pin_drag();
        self.work.undo();
    }

    pub fn redo(&mut self) {
        self.viewport.abandon_pin_drag();
        self.work.redo();
    }

    /// Opens the scene at `path` (a problem is shown in a dialog, the current work kept).
    pub fn open_path(&mut self, path: &Path) {
        self.files.open_path(&mut self.work, self.viewport.camera_mut(), path);
    }

    /// Saves the document to `path`; false (with the problem shown) when it could not be written.
    pub fn save_to(&mut self, path: &Path) -> bool {
        self.files.save_to(&mut self.work, self.viewport.camera(), path)
    }

    /// Shows a file problem in a dialog until the user dismisses it.
    pub fn show_file_error(&mut self, message: String) {
        self.work.show_alert(message);
    }

    /// Adds the opened scene to the recent files.
    pub fn remember_opened(&mut self) {
        self.files.remember_opened(&mut self.work);
    }

    /// Offers to restore the work a crash left in the recovery file.
    pub fn offer_recovery(&mut self) {
        self.files.offer_recovery(&mut self.work);
    }

    fn menu_bar(&mut self, ui: &mut egui::Ui) {
        egui::MenuBar::new().ui(ui, |ui| {
            let file =
                ui.menu_button("File", |ui| self.files.file_menu_ui(ui, &mut self.work, self.viewport.camera_mut()));
            match file.inner.flatten() {
                Some(FileWindow::Export) => self.export.open_for(&self.work.doc),
                Some(FileWindow::Render) => self.render.open_for(&self.work.doc, self.viewport.toon()),
                None => {}
            }
            ui.menu_button("Edit", |ui| {
                let ctx = ui.ctx().clone();
                let undo = match self.work.doc.undo_label() {
                    Some(label) => format!("Undo {label}"),
                    None => "Undo".to_owned(),
                };
                let button = egui::Button::new(undo).shortcut_text(shortcuts::UNDO.menu_text(&ctx));
                if ui.add_enabled(self.work.doc.undo_label().is_some(), button).clicked() {
                    self.undo();
                }
                let redo = match self.work.doc.redo_label() {
                    Some(label) => format!("Redo {label}"),
                    None => "Redo".to_owned(),
                };
                let button = egui::Button::new(redo).shortcut_text(shortcuts::REDO.menu_text(&ctx));
                if ui.add_enabled(self.work.doc.redo_label().is_some(), button).clicked() {
                    self.redo();
                }
                ui.separator();
                let selected = !self.work.session.selection().is_empty();
                let button = egui::Button::new("Unpin selected").shortcut_text(shortcuts::DELETE.menu_text(&ctx));
                if ui.add_enabled(selected, button).clicked() {
                    self.work.delete_selected_pins();
                }
                if ui
                    .add_enabled(
                        selected,
                        egui::Button::new("Copy pin positions").shortcut_text(shortcuts::COPY_PASTE.menu_text(&ctx)),
                    )
                    .clicked()
                    && let Some(text) = pin_clipboard::copy_selected_pins(&mut self.work)
                {
                    ctx.copy_text(text);
                }
                let copied = !self.work.session.copied_pins().is_empty();
                if ui
                    .add_enabled(
                        copied,
                        egui::Button::new("Paste pin positions")
                            .shortcut_text(shortcuts::COPY_PASTE.second_menu_text(&ctx)),
                    )
                    .clicked()
                {
                    pin_clipboard::paste_pins(&mut self.work, None);
                }
                if ui.add_enabled(selected, egui::Button::new("Mirror pins (x to −x)")).clicked() {
                    pin_clipboard::mirror_selected_pins(&mut self.work);
                }
            });
            ui.menu_button("View", |ui| {
                if ui
                    .add(egui::Button::new("Frame all").shortcut_text(shortcuts::FRAME_ALL.menu_text(ui.ctx())))
                    .clicked()
                {
                    self.viewport.frame_all_from_menu(&mut self.work);
                }
                ui.separator();
                self.viewport.stage_menu_ui(ui);
                ui.separator();
                // The shot camera's items in the menu itself: a nested menu's items missed real clicks.
                self.viewport.shot_camera_menu_ui(ui, &mut self.work);
                ui.separator();
                self.viewport.style_menu_ui(ui);
            });
            ui.menu_button("Help", |ui| {
                if ui.button("Keyboard shortcuts").clicked() {
                    self.show_shortcuts = true;
                }
                ui.separator();
                self.manual.menu_ui(ui);
            });
        });
    }

    fn shortcuts_window(&mut self, ctx: &egui::Context) {
        egui::Window::new("Keyboard shortcuts")
            .open(&mut self.show_shortcuts)
            .resizable(false)
            .collapsible(false)
            .show(ctx, |ui| {
                egui::Grid::new("shortcuts").striped(true).num_columns(2).show(ui, |ui| {
                    for shortcut in SHORTCUTS {
                        ui.strong(shortcut.help_text(ctx));
                        ui.label(shortcut.action);
                        ui.end_row();
                    }
                });
            });
    }

    /// Shortcuts with modifiers work even while a text field has focus; plain keys only when none has.
    fn keyboard(&mut self, ctx: &egui::Context, aspect: f32) {
        let consume = |shortcut: &shortcuts::Shortcut| shortcut.consume(ctx);
        // Longest modifier sets first: Ctrl+Shift+Z must not be taken for Ctrl+Z.
        if consume(&shortcuts::REDO) {
            self.redo();
        } else if consume(&shortcuts::UNDO) {
            self.undo();
        }
        let toon = self.viewport.toon();
        let (w, camera) = (&mut self.work, self.viewport.camera_mut());
        if consume(&shortcuts::SAVE_AS) {
            self.files.file_save_as(w);
        } else if consume(&shortcuts::SAVE) {
            self.files.file_save(w, camera);
        }
        if consume(&shortcuts::OPEN) {
            self.files.file_open(w, camera);
        }
        if consume(&shortcuts::RENDER) {
            self.render.open_for(&w.doc, toon);
        }
        if consume(&shortcuts::NEW) {
            self.files.file_new(w, camera);
        }
        // Whatever has the focus: the mode is the viewport's, and Esc is how it ends.
        if self.work.session.attaching().is_some() && ctx.input(|i| i.key_pressed(KeyCode::Escape)) {
            attach::cancel_attach_by_click(&mut self.work);
        }
        if ctx.egui_wants_keyboard_input() || self.viewport.pin_drag(&self.work).is_some() {
            return;
        }
        let w = &mut self.work;
        let timeline = w.doc.scene().timeline.clone();
        let pressed = |key| ctx.input(|i| i.key_pressed(key) && i.modifiers.is_none());
        if pressed(KeyCode::Space) {
            w.toggle_play();
        }
        if pressed(KeyCode::ArrowLeft) {
            w.set_frame(w.frame().round() - 1.0);
        }
        if pressed(KeyCode::ArrowRight) {
            w.set_frame(w.frame().round() + 1.0);
        }
        if pressed(KeyCode::ArrowUp) {
            w.jump_to_key(true);
        }
        if pressed(KeyCode::ArrowDown) {
            w.jump_to_key(false);
        }
        if pressed(KeyCode::Home) {
            w.set_frame(f64::from(timeline.start));
        }
        if pressed(KeyCode::End) {
            w.set_frame(f64::from(timeline.end));
        }
        if pressed(KeyCode::F) {
            self.viewport.frame_all(w, aspect);
        }
        if pressed(KeyCode::Delete) || pressed(KeyCode::Backspace) {
            if w.session.selection().is_empty() && w.session.selected_collider().is_some() {
                w.delete_selected_collider();
            } else if w.session.selection().is_empty() && w.session.selected_key().is_some() {
                w.delete_selected_key();
            } else {
                w.delete_selected_pins();
            }
        }
        if pressed(KeyCode::K) {
            w.add_key_here();
        }
        // Ctrl+C / Ctrl+V arrive as copy and paste events (a paste only when
        // the system clipboard holds text: a copy here always puts the pins there).
        let (copy, paste) = ctx.input(|i| {
            let paste = i.events.iter().find_map(|e| match e {
                egui::Event::Paste(text) => Some(text.clone()),
                _ => None,
            });
            (i.events.iter().any(|e| matches!(e, egui::Event::Copy)), paste)
        });
        if copy && let Some(text) = pin_clipboard::copy_selected_pins(w) {
            ctx.copy_text(text);
        }
        if let Some(text) = paste {
            pin_clipboard::paste_pins(w, Some(&text));
        }
    }

    /// The viewport: its mouse input, then the keys (which may change what it shows), then the drawing.
    fn viewport_ui(&mut self, ui: &mut egui::Ui) {
        let area = self.viewport.input_ui(ui, &mut self.work);
        self.keyboard(ui.ctx(), area.aspect);
        self.viewport.draw_ui(ui, &mut self.work, area);
    }

    /// The status bar: relaxation progress with its Cancel, then a fresh
    /// message or what a pin drag or attaching asks for, beside the progress
    /// so that neither hides it. On the right the hovered grid point, the grid
    /// and timings keep their room: a long message is cut (whole on hover).
    fn status_bar(&mut self, ui: &mut egui::Ui) {
        ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
            // Frames are drawn on demand: a rate only means something while they run continuously.
            let rate = if self.work.session.playing() && self.frame_interval_ms > 0.0 {
                format!(" · {:.0} fps", 1000.0 / self.frame_interval_ms)
            } else {
                String::new()
            };
            ui.label(format!("{:.1} ms CPU{rate}", self.last_update_ms))
                .on_hover_text("The editor's CPU time for the last frame (and frames per second while playing).");
            let cloth = &self.work.shown.scene().cloth;
            ui.label(format!("{} × {} grid ·", cloth.cols(), cloth.rows()));
            // Here rather than on the left, where progress and messages would hide it or be hidden.
            if let Some((i, j)) = self.work.session.hovered() {
                ui.label(format!("Grid point ({i}, {j}) ·"));
            }
            // An id of its own: the hovered point's label comes and goes before it, and the
            // Cancel inside must keep its id for a click that starts as the mouse leaves the cloth.
            let left = egui::UiBuilder::new()
                .scope_id(ui.scope_id().with("status text"))
                .layout(egui::Layout::left_to_right(egui::Align::Center));
            ui.scope_builder(left, |ui| self.status_text_ui(ui));
        });
    }

    /// The status bar's left part: the relaxation and its Cancel, then a message or a drag's hint.
    fn status_text_ui(&mut self, ui: &mut egui::Ui) {
        let relaxing = self.is_relaxing();
        let status = self.work.shown.relax_status();
        if let Some(status) = status.as_ref().filter(|status| status.counting) {
            ui.add(egui::Spinner::new());
            ui.label(format!(
                "Checking where the rest shapes pass through themselves… ({:.1} s)",
                status.started.elapsed().as_secs_f64()
            ));
        } else if relaxing {
            ui.add(egui::Spinner::new());
            // Before the progress, whose width changes with every sweep, so it holds still under the mouse.
            let back = self.work.relaxation_take_back();
            let hint = match back {
                Some(TakeBack::Undos(_)) => {
                    "Stop relaxing: the undo that asked for it is redone (Undo takes it back again)"
                }
                _ => "Stop relaxing: the edits that asked for it are taken back (Redo brings them back)",
            };
            let cancel = ui.add_enabled(back.is_some(), egui::Button::new("Cancel").small()).on_hover_text(hint);
            if cancel.clicked() {
                self.work.cancel_relaxation();
            }
            ui.label(match &status {
                Some(ShaperStatus { paths: Some((done, total)), started, .. }) => format!(
                    "Finding the in-betweens' paths round the colliders… segment {} of {total} ({:.1} s)",
                    done + 1,
                    started.elapsed().as_secs_f64()
                ),
                Some(status) => {
                    let keys = if status.keys_total > 1 {
                        format!(" key {} of {},", status.keys_done + 1, status.keys_total)
                    } else {
                        String::new()
                    };
                    let keys = if status.among_colliders { format!("{keys} among the colliders,") } else { keys };
                    let (cols, rows) = status.level;
                    format!(
                        "Relaxing…{keys} {cols}×{rows} level, sweep {}/{} ({:.1} s)",
                        status.iteration,
                        status.max_iterations,
                        status.started.elapsed().as_secs_f64()
                    )
                }
                None => "Relaxing…".to_owned(),
            });
            if !self.work.shown.is_shaped() {
                ui.label("· opening: the grey cloth is where the solve starts")
                    .on_hover_text("The cloth is drawn in colour once its shape is solved");
            } else if self.viewport.cloth_drawn_stale() {
                ui.label("· updating: the grey cloth is the old shape")
                    .on_hover_text("The cloth is drawn in colour again once its new shape is solved");
            }
        }
        let message = self.work.message().filter(|m| m.at.elapsed().as_secs_f64() < MESSAGE_SECS);
        let (text, error) = match message {
            Some(message) => (Some(message.text.clone()), message.error),
            None => (self.pointer_status(), false),
        };
        let Some(text) = text else { return };
        if status.is_some() || relaxing {
            ui.separator();
        }
        let color = if error { ui.visuals().error_fg_color } else { ui.visuals().text_color() };
        ui.add(egui::Label::new(egui::RichText::new(&text).color(color)).truncate());
    }

    /// What the mouse is doing: dragging a pin or attaching one by clicking;
    /// over the grid editor, what clicks and drags do there.
    fn pointer_status(&self) -> Option<String> {
        if let Some(drag) = self.viewport.pin_drag(&self.work) {
            let lock = match drag.lock {
                Some(axis) => format!("locked to {axis:?}"),
                None => "in the view plane".to_owned(),
            };
            Some(format!("Moving pin {:?} {lock} — X/Y/Z lock an axis, Esc puts it back", drag.grabbed))
        } else {
            self.work
                .session
                .attaching()
                .map(|(i, j)| format!("Click on a reference to attach pin ({i}, {j}) · Esc cancels"))
                .or_else(|| self.work.session.grid_hovered().map(|_| GRID_EDITOR_HINT.to_owned()))
        }
    }

    /// `tent.ron* — /path/to — Drape`: the star marks unsaved changes.
    pub fn title(&self) -> String {
        window_title(&self.work.doc.display_name(), self.work.doc.is_dirty(), self.work.doc.path())
    }

    /// Notes the window's size for the next run and, once the screen's size
    /// is known, makes the window fit it: the size left last time (or the
    /// default), shrunk to the screen.
    fn track_window_size(&mut self, ctx: &egui::Context) {
        let (inner, screen) = ctx.input(|i| (i.viewport().inner_rect.map(|r| r.size()), i.viewport().monitor_size));
        if let Some(size) = inner {
            self.window_size = Some(size);
        }
        if let Some((target, frames)) = self.window_resizing {
            let reached = inner.is_some_and(|size| (size - target).length() <= 1.0);
            // A window manager may refuse the size: stop waiting after a while.
            self.window_resizing = (!reached && frames < WINDOW_RESIZE_FRAMES).then_some((target, frames + 1));
        }
        self.viewport.hold_saved_view(self.window_resizing.is_some());
        let Some(screen) = screen.filter(|_| !self.window_fitted) else { return };
        self.window_fitted = true;
        let wanted = self.window_size_file.as_deref().and_then(window_size::load).unwrap_or(DEFAULT_WINDOW_SIZE);
        let fitted = window_size::fitted(wanted, screen);
        if inner.is_none_or(|size| (size - fitted).length() > 1.0) {
            ctx.send_viewport_cmd(egui::ViewportCommand::InnerSize(fitted));
            self.window_resizing = Some((fitted, 0));
            self.viewport.hold_saved_view(true);
        }
    }

    fn measure_frame(&mut self) {
        let now = Instant::now();
        if let Some(last) = self.last_frame_at.replace(now) {
            let interval = now.duration_since(last).as_secs_f64() * 1e3;
            self.frame_interval_ms =
                if self.frame_interval_ms == 0.0 { interval } else { self.frame_interval_ms * 0.9 + interval * 0.1 };
        }
    }
}

/// Frames the viewport waits for the window to reach the size asked of it.
const WINDOW_RESIZE_FRAMES: u32 = 60;

/// The panels whose state belongs to one document (the timeline's drags
/// and zoom, the side panels' open rows and pickers): made afresh when the
/// workspace's document is replaced.
struct DocumentPanels {
    /// The document they were made for ([`Workspace::document_number`]).
    document: u64,
    timeline: TimelinePanel,
    layers: LayersPanel,
    colliders: CollidersPanel,
    references: ReferencesPanel,
    shot: ShotPanel,
}

impl DocumentPanels {
    fn new(document: u64, timeline: TimelinePanel) -> DocumentPanels {
        DocumentPanels {
            document,
            timeline,
            layers: LayersPanel::default(),
            colliders: CollidersPanel::default(),
            references: ReferencesPanel::default(),
            shot: ShotPanel::default(),
        }
    }

    /// The panels for `w`'s document: these, or fresh ones once it was
    /// replaced (the timeline keeps how it plays).
    fn for_document(&mut self, w: &Workspace) -> &mut DocumentPanels {
        if self.document != w.document_number() {
            *self = DocumentPanels::new(w.document_number(), self.timeline.for_new_document());
        }
        self
    }
}

/// `name* — /path/to — Drape` for a scene at `path` (none: not saved yet).
/// The folder is shown whole even when the scene was opened by a bare or
/// relative name (`drape tent.ron`), as it is after a Save.
fn window_title(name: &str, dirty: bool, path: Option<&std::path::Path>) -> String {
    let dirty = if dirty { "*" } else { "" };
    let folder = path.and_then(|p| std::path::absolute(p).ok()).and_then(|p| p.parent().map(|dir| dir.to_path_buf()));
    match folder {
        Some(dir) if !dir.as_os_str().is_empty() => format!("{name}{dirty} — {} — Drape", dir.display()),
        _ => format!("{name}{dirty} — Drape"),
    }
}

impl eframe::App for DrapeApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let started = Instant::now();
        let ctx = ui.ctx().clone();
        self.work.shown.set_context(&ctx);
        if self.typing.holds_events() {
            ctx.request_repaint();
        }
        self.measure_frame();
        self.track_window_size(&ctx);
        self.panels.for_document(&self.work).timeline.advance_playback(&ctx, &mut self.work);
        self.files.handle_close_request(&ctx, &self.work);
        // A viewport command asks for another frame: send the title only when it changes.
        let title = self.title();
        if title != self.sent_title {
            ctx.send_viewport_cmd(egui::ViewportCommand::Title(title.clone()));
            self.sent_title = title;
        }
        egui::Panel::top("menu").show(ui, |ui| self.menu_bar(ui));
        egui::Panel::bottom("timeline").show(ui, |ui| {
            self.panels.for_document(&self.work).timeline.ui(ui, &mut self.work);
        });
        self.status_rect = egui::Panel::bottom("status").show(ui, |ui| self.status_bar(ui)).response.rect;
        egui::Panel::left("cloth").default_size(280.0).show(ui, |ui| self.cloth.ui(ui, &mut self.work));
        egui::Panel::right("layers").default_size(270.0).min_size(220.0).show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                let panels = self.panels.for_document(&self.work);
                panels.layers.ui(ui, &mut self.work);
                ui.separator();
                panels.colliders.ui(ui, &mut self.work);
                ui.separator();
                panels.references.ui(ui, &mut self.work);
                ui.separator();
                panels.shot.ui(ui, &mut self.work);
            });
        });
        egui::Panel::top("view").show(ui, |ui| self.viewport.view_bar_ui(ui, &mut self.work));
        egui::CentralPanel::default().frame(egui::Frame::NONE).show(ui, |ui| self.viewport_ui(ui));
        attach::keep_attach_mode_on_its_pin(&mut self.work);
        self.shortcuts_window(&ctx);
        self.manual.window_ui(&ctx);
        self.export.window_ui(&ctx, &mut self.work);
        self.render.window_ui(&ctx, &mut self.work);
        self.files.dialogs_ui(&ctx, &mut self.work, self.viewport.camera_mut());
        // A gesture ends when the mouse lets go (a drag on a slider or a pin is one undo step).
        if self.viewport.pin_drag(&self.work).is_none() && !ctx.input(|i| i.pointer.any_down()) {
            self.work.end_gesture();
        }
        if self.is_relaxing() {
            ctx.request_repaint_after(Duration::from_millis(50));
        }
        self.files.autosave(&ctx, &mut self.work);
        // A number field kept its value because what was typed was no number: say so.
        if let Some(text) = super::number_field::take_refused(&ctx) {
            self.work.report(format!("“{text}” is not a number: the field kept its value."), true);
            ctx.request_repaint();
        }
        self.frames_drawn += 1;
        if self.quit_after_frames.is_some_and(|n| self.frames_drawn >= n) {
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        } else if self.quit_after_frames.is_some() {
            ctx.request_repaint();
        }
        self.last_update_ms = started.elapsed().as_secs_f64() * 1e3;
    }

    fn on_exit(&mut self) {
        self.files.clean_exit();
        if let (Some(file), Some(size)) = (&self.window_size_file, self.window_size)
            && size.x >= MIN_WINDOW_SIZE.x
            && size.y >= MIN_WINDOW_SIZE.y
        {
            // Only a convenience: a size that cannot be kept costs the next start its size, nothing more.
            let _ = window_size::save(file, size);
        }
    }

    /// eframe hands every frame's input here before egui sees it.
    /// Held events ask for the next frame from `ui`, once this frame has begun.
    fn raw_input_hook(&mut self, _ctx: &egui::Context, raw_input: &mut egui::RawInput) {
        self.typing.pace(raw_input);
    }
}

/// Opens the editor window on `scene` (the built-in magic carpet when `None`);
/// returns when the window closes. With `quit_after_frames`, it closes itself
/// after drawing that many frames.
/// Runs the editor window on `scene`; `problem`, if any, is shown in the
/// file-error dialog from the first frame (a scene that could not be opened).
pub fn run(
    scene: Scene,
    path: Option<PathBuf>,
    quit_after_frames: Option<u64>,
    problem: Option<String>,
) -> eframe::Result {
    // The size left last time; the first frame fits it to the screen once the screen is known.
    let saved = default_config_dir().and_then(|dir| window_size::load(&dir.join(WINDOW_SIZE_NAME)));
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_inner_size(saved.unwrap_or(DEFAULT_WINDOW_SIZE))
            .with_min_inner_size(MIN_WINDOW_SIZE)
            .with_title("Drape"),
        renderer: eframe::Renderer::Wgpu,
        ..Default::default()
    };
    eframe::run_native(
        "Drape",
        options,
        Box::new(move |cc| {
            let mut app = DrapeApp::new(scene, path, cc.wgpu_render_state.as_ref());
            if let Some(frames) = quit_after_frames {
                app = app.quit_after_frames(frames);
            }
            app.remember_opened();
            app.offer_recovery();
            if let Some(problem) = problem {
                app.show_file_error(problem);
            }
            Ok(Box::new(app))
        }),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::animate::Evaluator;
    use crate::editor::edits;

    /// The editor on the bundled carpet, its keys solved (on the worker, as a window opens).
    fn app() -> DrapeApp {
        let scene = crate::scene::parse(DEFAULT_SCENE, "magic_carpet.ron").unwrap();
        let mut app = DrapeApp::new(scene, None, None);
        assert!(app.wait_for_shapes(Duration::from_secs(600)), "the carpet's keys are solved");
        app
    }

    #[test]
    fn the_title_names_the_whole_folder_whatever_name_the_scene_was_opened_by() {
        let here = std::env::current_dir().unwrap();
        let bare = window_title("tent.ron", false, Some(std::path::Path::new("tent.ron")));
        assert_eq!(bare, format!("tent.ron — {} — Drape", here.display()));
        let relative = window_title("tent.ron", true, Some(std::path::Path::new("scenes/tent.ron")));
        assert_eq!(relative, format!("tent.ron* — {} — Drape", here.join("scenes").display()));
        let whole = window_title("tent.ron", false, Some(std::path::Path::new("/srv/shots/tent.ron")));
        assert_eq!(whole, "tent.ron — /srv/shots — Drape");
        assert_eq!(window_title("untitled", true, None), "untitled* — Drape");
    }

    #[test]
    fn the_mesh_at_the_playhead_is_evaluate_at_that_frame() {
        let mut app = app();
        for frame in [37.0, 5.0, 120.0, 37.0] {
            app.set_frame(frame);
            app.viewport.refresh(&mut app.work);
            let expected = Evaluator::default().evaluate_frame(app.scene(), frame);
            assert_eq!(*app.mesh(), expected, "frame {frame}");
        }
    }

    #[test]
    fn the_playhead_stays_on_the_timeline() {
        let mut app = app();
        app.set_frame(-50.0);
        assert_eq!(app.frame(), 0.0);
        app.set_frame(1e9);
        assert_eq!(app.frame(), 120.0);
    }

    #[test]
    fn an_edit_shows_once_relaxed_and_the_old_shape_stays_until_then() {
        let mut app = app();
        let before = app.mesh().clone();
        app.apply("Elasticity", |s| s.keys[0].elasticity = 1.3);
        assert_ne!(*app.scene(), *app.shown_scene(), "the edit waits for its relaxation");
        assert_eq!(*app.mesh(), before);
        assert!(app.wait_for_shapes(Duration::from_secs(60)));
        assert_eq!(app.shown_scene(), app.scene());
        let expected = Evaluator::default().evaluate_frame(app.scene(), app.frame());
        assert_eq!(*app.mesh(), expected);
    }

    #[test]
    fn pin_positions_copy_to_another_key_and_mirror_across_the_middle() {
        let mut app = app();
        let front = [(0, 0), (20, 0)];
        app.select_pins(&front);
        let text = app.copy_selected_pins().expect("pins as text");
        let copied: Vec<_> = front.iter().map(|g| pin_at(&app, 0, *g)).collect();
        // Onto the key at 48 (the carpet's stretch): its front pins take key 0's positions.
        app.set_frame(48.0);
        let index = app.edit_key_index();
        app.select_pins(&[]);
        app.paste_pins(None);
        assert_eq!(front.iter().map(|g| pin_at(&app, index, *g)).collect::<Vec<_>>(), copied);
        assert_eq!(app.selection(), front);
        assert_eq!(app.document().undo_label(), Some("Paste pins"));
        // Move the left front pin, then mirror the right one from it.
        app.apply("Move pin", |s| edits::move_pin(&mut s.keys[index], (0, 0), (-0.3, 1.4, 2.0)));
        app.select_pins(&[(20, 0)]);
        app.mirror_selected_pins();
        assert_eq!(pin_at(&app, index, (20, 0)), (0.3, 1.4, 2.0));
        app.undo();
        assert_eq!(pin_at(&app, index, (20, 0)), copied[1]);
        // The clipboard text is the scene file's pin syntax and pastes back, here onto key 120.
        assert!(text.contains("grid:(0,0)") && text.contains("pos:"), "{text}");
        app.set_frame(120.0);
        let last = app.edit_key_index();
        app.paste_pins(Some(&text));
        assert_eq!(front.iter().map(|g| pin_at(&app, last, *g)).collect::<Vec<_>>(), copied);
        // Text that is not pins pastes what was copied last.
        app.paste_pins(Some("not pins"));
        assert_eq!(app.document().undo_label(), Some("Paste pins"));
    }

    fn pin_at(app: &DrapeApp, key: usize, grid: (u32, u32)) -> (f64, f64, f64) {
        app.scene().keys[key].pins.iter().find(|p| p.grid == grid).map(|p| p.pos).expect("pinned")
    }

    #[test]
    fn pinning_a_point_pins_it_where_the_cloth_is() {
        let mut app = app();
        let cols = app.shown_scene().cloth.cols();
        let (i, j) = (5u32, 7u32);
        let at = app.mesh().positions[j as usize * cols + i as usize];
        app.toggle_pin((i, j));
        let key = &app.scene().keys[app.edit_key_index()];
        let pin = key.pins.iter().find(|p| p.grid == (i, j)).expect("pinned");
        assert_eq!(pin.pos, (at.x as f64, at.y as f64, at.z as f64));
        assert!(app.selection().is_empty(), "a new pin is not left selected");
        app.toggle_pin((i, j));
        assert!(!app.scene().keys[app.edit_key_index()].pins.iter().any(|p| p.grid == (i, j)));
        app.undo();
        assert!(app.scene().keys[app.edit_key_index()].pins.iter().any(|p| p.grid == (i, j)));
    }
}
