//! The editor window: menus on top, the Cloth panel on the left, the 3D
//! viewport in the centre, a status bar and the timeline along the bottom.
//!
//! The document (the scene being edited) and what is drawn are kept apart:
//! `shown` is the latest version of the document whose rest shapes are all
//! relaxed. Edits go to the document at once; their relaxation runs on the
//! [`Shaper`]'s worker, and `shown` catches up when it is done, so the UI
//! never waits for a relaxation and the last good shape stays on screen.

use std::path::PathBuf;
use std::sync::{Arc, OnceLock};
use std::time::{Duration, Instant};

use eframe::egui::{self, Key as KeyCode, KeyboardShortcut, Modifiers, Sense};
use eframe::egui_wgpu;

use super::document::Document;
use super::export_window::ExportWindow;
use super::files::Files;
use super::grid_editor::GridEditor;
use super::recent::default_config_dir;
use super::recovery::default_state_dir;
use super::shaper::Shaper;
use super::viewport::{self, ViewportFrame};
use super::viewport_input::{AxisLock, PinDrag};
use crate::animate::{self, Evaluator};
use crate::mesh::Mesh;
use crate::picture::{SceneOverlays, key_overlay, scene_bounds};
use crate::render::camera::bounds;
use crate::render::overlay::{Marker, PIN_RADIUS_PX, PinState, Segment, colors};
use crate::render::{Ghost, Ground, OrbitCamera, Overlay, RenderOptions};
use crate::scene::{Cloth, ClothTexture, Key, Scene};
use crate::shape::RelaxReport;

/// The scene the editor opens with when none is given: the paper's magic carpet.
pub const DEFAULT_SCENE: &str = include_str!("../../scenes/magic_carpet.ron");

pub const SHORTCUT_NEW: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, KeyCode::N);
pub const SHORTCUT_OPEN: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, KeyCode::O);
pub const SHORTCUT_SAVE: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, KeyCode::S);
pub const SHORTCUT_SAVE_AS: KeyboardShortcut =
    KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::SHIFT), KeyCode::S);
pub const SHORTCUT_UNDO: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, KeyCode::Z);
pub const SHORTCUT_REDO: KeyboardShortcut =
    KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::SHIFT), KeyCode::Z);
pub const SHORTCUT_REDO_ALT: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, KeyCode::Y);

/// Every shortcut, for Help ▸ Shortcuts: (keys, what they do).
pub const SHORTCUTS: &[(&str, &str)] = &[
    ("Ctrl+N", "New scene"),
    ("Ctrl+O", "Open a scene"),
    ("Ctrl+S", "Save"),
    ("Ctrl+Shift+S", "Save as"),
    ("Ctrl+Z", "Undo"),
    ("Ctrl+Shift+Z, Ctrl+Y", "Redo"),
    ("Delete", "Unpin the selected pins (or delete the key selected on the timeline)"),
    ("K", "Add a rest-shape key at the playhead, from the current pose"),
    ("F", "Frame the cloth in the viewport"),
    ("Space", "Play / pause"),
    ("Left / Right", "Step one frame back / forward"),
    ("Home / End", "First / last frame"),
    ("Middle-drag, Alt+left-drag", "Orbit"),
    ("Shift+middle-drag", "Pan"),
    ("Mouse wheel", "Dolly"),
    ("Click a cloth point", "Pin it where it is (or select its pin)"),
    ("Shift+click a pin", "Add it to the selection"),
    ("Drag a pin", "Move the selected pins in the view plane"),
    ("X / Y / Z while dragging", "Lock the move to that axis (again: unlock)"),
    ("Esc while dragging", "Put the pins back"),
];

/// What the viewport shows besides the cloth.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ViewToggles {
    pub wireframe: bool,
    pub texture: bool,
    pub pins: bool,
    pub catenaries: bool,
    pub triangulation: bool,
    pub ground: bool,
    /// Onion skin: ghosts of the `onion_frames` frames before and after, `onion_spacing` frames apart.
    pub onion: bool,
    pub onion_frames: u32,
    pub onion_spacing: u32,
    /// The camera moves with the cloth's centre, keeping how it looks at it.
    pub follow: bool,
}

impl Default for ViewToggles {
    fn default() -> Self {
        ViewToggles {
            wireframe: false,
            texture: true,
            pins: true,
            catenaries: false,
            triangulation: false,
            ground: true,
            onion: false,
            onion_frames: 2,
            onion_spacing: 4,
            follow: false,
        }
    }
}

/// Which stage of the method the viewport shows (the paper's Fig. 3 b–f).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Stage {
    /// The animation at the playhead: blended rest shapes and the layer stack.
    #[default]
    Animation,
    /// The relaxed rest shape of the key being edited.
    Relaxed,
    /// The surface approximated from the catenary network, before relaxation.
    Approximated,
    /// The catenary network, its conflicts and the triangulation, over the approximated surface.
    Catenaries,
}

impl Stage {
    pub const ALL: [Stage; 4] = [Stage::Animation, Stage::Relaxed, Stage::Approximated, Stage::Catenaries];

    pub fn label(self) -> &'static str {
        match self {
            Stage::Animation => "Animation",
            Stage::Relaxed => "Relaxed rest shape",
            Stage::Approximated => "Approximated surface",
            Stage::Catenaries => "Catenary network",
        }
    }

    /// The cloth's shape under this stage's drawing.
    pub fn mesh_stage(self) -> animate::Stage {
        match self {
            Stage::Animation => animate::Stage::Animated,
            Stage::Relaxed => animate::Stage::Relaxed,
            Stage::Approximated | Stage::Catenaries => animate::Stage::Approx,
        }
    }
}

/// A line in the status bar.
pub(super) struct Message {
    pub text: String,
    pub error: bool,
    pub at: Instant,
}

/// How long a status message stays.
const MESSAGE_SECS: f64 = 8.0;

pub struct DrapeApp {
    pub(super) doc: Document,
    /// The latest version of the document whose rest shapes are all relaxed: what is drawn.
    pub(super) shown: Scene,
    pub(super) evaluator: Evaluator,
    shaper: Shaper,
    /// The context the worker wakes when a shape is ready (set on the first frame).
    repaint_context: Arc<OnceLock<egui::Context>>,
    /// The shapes last asked of the worker, so a request is made once per change.
    requested: Option<(Cloth, Vec<Key>)>,
    pub(super) mesh: Arc<Mesh>,
    /// Onion-skin ghosts and what they show.
    ghosts: Arc<Vec<Ghost<Arc<Mesh>>>>,
    ghosts_of: Option<GhostsOf>,
    /// Counts changes of `shown`.
    shown_version: u64,
    /// What `mesh` shows: (frame, stage, solo layer); `None` when it must be rebuilt.
    mesh_of: Option<(f64, Stage, Option<usize>)>,
    /// The frame the playhead is on (fractional while playing).
    frame: f64,
    playing: bool,
    /// Playback wraps round to the start (else it stops at the end).
    pub(super) looping: bool,
    /// The rest-shape key selected on the timeline, and the one being dragged there.
    pub(super) selected_key: Option<usize>,
    /// The layer whose parameters the Layers panel shows.
    pub(super) selected_layer: Option<usize>,
    /// The layer being dragged by its grip in the layer list.
    pub(super) layer_drag: Option<usize>,
    /// The cloth's centre when the camera last followed it.
    follow_anchor: Option<glam::Vec3>,
    /// A layer shown alone (the others off in the viewport only; the scene keeps them).
    pub(super) solo_layer: Option<usize>,
    pub(super) key_drag: Option<usize>,
    /// The frame of the selected layer's parameter keys being dragged on the timeline.
    pub(super) param_key_drag: Option<i32>,
    /// The Layers panel's curve view: the parameter it shows and a key being dragged.
    pub(super) curve: super::curve_view::CurveView,
    play_started: Option<(Instant, f64)>,
    pub(super) camera: OrbitCamera,
    ground: Ground,
    pub toggles: ViewToggles,
    pub stage: Stage,
    /// Selected pins of the key being edited (grid points).
    pub(super) selection: Vec<(u32, u32)>,
    /// The cloth point under the mouse in the viewport, and in the grid editor.
    pub(super) hovered: Option<(u32, u32)>,
    pub(super) grid_hovered: Option<(u32, u32)>,
    pub(super) pin_drag: Option<PinDrag>,
    pub(super) grid_editor: GridEditor,
    pub(super) message: Option<Message>,
    show_shortcuts: bool,
    /// CPU time of the last update and the smoothed time between frames, for the readout.
    last_update_ms: f64,
    frame_interval_ms: f64,
    last_frame_at: Option<Instant>,
    /// Whether the GPU viewport is available (false only in tests without wgpu).
    has_viewport: bool,
    /// Frame the cloth once the viewport's shape is known (a scene without a saved view).
    frame_all_pending: bool,
    /// Close the window after this many frames (`--quit-after-frames`).
    quit_after_frames: Option<u64>,
    frames_drawn: u64,
    pub(super) files: Files,
    pub(super) export: ExportWindow,
    /// Where the viewport was drawn last frame (points).
    viewport_rect: egui::Rect,
    /// The window title last sent.
    sent_title: String,
    /// Where the status bar was drawn last frame (points).
    status_rect: egui::Rect,
    /// Frame the cloth (and move the ground under it) once a newly opened scene is relaxed.
    pub(super) frame_when_shown: bool,
}

impl DrapeApp {
    /// Opens `scene`, framing the camera on its keys (or using its saved view).
    pub fn new(scene: Scene, path: Option<PathBuf>, render_state: Option<&egui_wgpu::RenderState>) -> DrapeApp {
        if let Some(render_state) = render_state {
            viewport::install(render_state);
        }
        let mut evaluator = Evaluator::new();
        // The first shapes are relaxed before the window shows anything: there is no older shape to show.
        let (min, max) = scene_bounds(&mut evaluator, &scene);
        let camera = match &scene.view {
            Some(view) => OrbitCamera::from_view(view),
            None => OrbitCamera::framing(min, max, 16.0 / 9.0),
        };
        let repaint_context: Arc<OnceLock<egui::Context>> = Arc::default();
        let wake = repaint_context.clone();
        let shaper = Shaper::new(move || {
            if let Some(ctx) = wake.get() {
                ctx.request_repaint();
            }
        });
        DrapeApp {
            ground: Ground::under(min, max),
            frame: scene.timeline.start as f64,
            frame_all_pending: scene.view.is_none(),
            shown: scene.clone(),
            doc: Document::new(scene, path),
            evaluator,
            shaper,
            repaint_context,
            requested: None,
            mesh: Arc::default(),
            mesh_of: None,
            ghosts: Arc::default(),
            ghosts_of: None,
            shown_version: 0,
            playing: false,
            looping: true,
            selected_key: None,
            selected_layer: None,
            layer_drag: None,
            follow_anchor: None,
            solo_layer: None,
            key_drag: None,
            param_key_drag: None,
            curve: Default::default(),
            play_started: None,
            camera,
            toggles: ViewToggles::default(),
            stage: Stage::default(),
            selection: Vec::new(),
            hovered: None,
            grid_hovered: None,
            pin_drag: None,
            grid_editor: GridEditor::default(),
            message: None,
            show_shortcuts: false,
            last_update_ms: 0.0,
            frame_interval_ms: 0.0,
            last_frame_at: None,
            has_viewport: render_state.is_some(),
            quit_after_frames: None,
            frames_drawn: 0,
            files: Files::new(default_config_dir(), default_state_dir()),
            export: ExportWindow::default(),
            viewport_rect: egui::Rect::NOTHING,
            sent_title: String::new(),
            status_rect: egui::Rect::NOTHING,
            frame_when_shown: false,
        }
        .with_mesh()
    }

    fn with_mesh(mut self) -> Self {
        self.refresh_mesh();
        self
    }

    /// Keeps recent files in `config_dir` and the recovery file in `state_dir`
    /// instead of the user's (tests, scripted runs); `None` turns that feature off.
    pub fn with_file_dirs(mut self, config_dir: Option<PathBuf>, state_dir: Option<PathBuf>) -> Self {
        self.files = Files::new(config_dir, state_dir);
        self
    }

    /// Where the viewport was drawn in the last frame, in points.
    pub fn viewport_rect(&self) -> egui::Rect {
        self.viewport_rect
    }

    /// Where the status bar (messages, timings) was drawn in the last frame, in points.
    pub fn status_rect(&self) -> egui::Rect {
        self.status_rect
    }

    /// Where a world point appears on screen (points), `None` behind the camera.
    pub fn screen_pos(&self, world: glam::Vec3) -> Option<egui::Pos2> {
        let rect = self.viewport_rect;
        // Projected at one pixel per point: the camera only needs the aspect ratio.
        let size = (rect.width().round().max(1.0) as u32, rect.height().round().max(1.0) as u32);
        let at = self.camera.project(world, size)?;
        Some(rect.min + egui::vec2(at.x * rect.width() / size.0 as f32, at.y * rect.height() / size.1 as f32))
    }

    /// The window's context once the first frame has run.
    pub(super) fn context(&self) -> Option<egui::Context> {
        self.repaint_context.get().cloned()
    }

    /// Resets what belonged to the previous document after New / Open / Restore.
    pub(super) fn after_document_change(&mut self) {
        self.selection.clear();
        self.pin_drag = None;
        self.hovered = None;
        self.requested = None;
        self.playing = false;
        self.play_started = None;
        self.selected_key = None;
        self.selected_layer = None;
        self.layer_drag = None;
        self.solo_layer = None;
        self.key_drag = None;
        self.param_key_drag = None;
        self.curve = Default::default();
        self.frame = self.doc.scene().timeline.start as f64;
        self.mesh_of = None;
    }

    /// Closes the window after `frames` frames (a scripted smoke test).
    pub fn quit_after_frames(mut self, frames: u64) -> Self {
        self.quit_after_frames = Some(frames);
        self
    }

    /// The document's scene (what a save writes).
    pub fn scene(&self) -> &Scene {
        self.doc.scene()
    }

    pub fn document(&self) -> &Document {
        &self.doc
    }

    /// The scene on screen: the document once its shapes are relaxed.
    pub fn shown_scene(&self) -> &Scene {
        &self.shown
    }

    pub fn camera(&self) -> &OrbitCamera {
        &self.camera
    }

    pub fn frame(&self) -> f64 {
        self.frame
    }

    /// The mesh on screen: for [`Stage::Animation`], `evaluate` of the shown scene at [`DrapeApp::frame`].
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// How many onion-skin ghosts the viewport draws now.
    pub fn ghost_count(&self) -> usize {
        self.ghosts.len()
    }

    pub fn selection(&self) -> &[(u32, u32)] {
        &self.selection
    }

    /// Whether a relaxation is pending or running.
    pub fn is_relaxing(&self) -> bool {
        self.shaper.is_busy() || *self.doc.scene() != self.shown
    }

    /// Blocks until the document's shapes are relaxed and shown and the worker is idle (tests and scripts).
    pub fn wait_for_shapes(&mut self, timeout: Duration) -> bool {
        let deadline = Instant::now() + timeout;
        loop {
            self.sync_shapes();
            if *self.doc.scene() == self.shown {
                self.refresh_mesh();
                // The worker clears its status (the spinner) just after sending its last
                // shape; wait for that too, so the next frames are quiet.
                return self.shaper.wait_idle(deadline.saturating_duration_since(Instant::now()));
            }
            if Instant::now() > deadline {
                return false;
            }
            std::thread::sleep(Duration::from_millis(2));
        }
    }

    /// Moves the playhead; the mesh follows on the next update.
    pub fn set_frame(&mut self, frame: f64) {
        let timeline = &self.doc.scene().timeline;
        self.frame = frame.clamp(timeline.start as f64, timeline.end as f64);
        if self.playing {
            self.play_started = Some((Instant::now(), self.frame));
        }
    }

    /// The index of the key being edited: the one in effect at the playhead.
    pub fn edit_key_index(&self) -> usize {
        let keys = &self.doc.scene().keys;
        keys.iter().rposition(|k| k.frame as f64 <= self.frame).unwrap_or(0)
    }

    /// Applies an edit to the document, reporting a rejected one in the status bar.
    pub fn apply(&mut self, label: &str, change: impl FnOnce(&mut Scene)) {
        match self.doc.edit(label, change) {
            Ok(()) => {
                let pins = &self.doc.scene().keys[self.edit_key_index()].pins;
                self.selection.retain(|s| pins.iter().any(|p| p.grid == *s));
            }
            Err(rejected) => self.report(format!("Not applied: {rejected}"), true),
        }
    }

    pub(super) fn report(&mut self, text: String, error: bool) {
        self.message = Some(Message { text, error, at: Instant::now() });
    }

    /// Ends the open gesture (one undo step) and lets the final state's relaxation cancel stale ones.
    pub(super) fn end_gesture(&mut self) {
        if self.doc.in_gesture() {
            self.doc.end_gesture();
            self.requested = None;
        }
    }

    /// Pins grid point `point` of the key being edited where the cloth is now, or unpins it.
    pub(super) fn toggle_pin(&mut self, point: (u32, u32)) {
        let index = self.edit_key_index();
        if super::edits::is_pinned(&self.doc.scene().keys[index], point) {
            self.apply("Unpin", |s| super::edits::unpin(&mut s.keys[index], &[point]));
            self.selection.retain(|p| *p != point);
            return;
        }
        let cloth = &self.shown.cloth;
        let vertex = point.1 as usize * cloth.cols() + point.0 as usize;
        let Some(p) = self.mesh.positions.get(vertex).copied().filter(|_| cloth.grid == self.doc.scene().cloth.grid)
        else {
            self.report("Wait for the cloth to finish relaxing before pinning.".to_owned(), true);
            return;
        };
        let pos = (p.x as f64, p.y as f64, p.z as f64);
        self.apply("Pin", |s| super::edits::pin_point(&mut s.keys[index], point, pos));
        self.selection = vec![point];
    }

    pub(super) fn delete_selected_pins(&mut self) {
        if self.selection.is_empty() {
            return;
        }
        let index = self.edit_key_index();
        let selection = self.selection.clone();
        let label = if selection.len() == 1 { "Unpin" } else { "Unpin pins" };
        self.apply(label, |s| super::edits::unpin(&mut s.keys[index], &selection));
    }

    pub(super) fn undo(&mut self) {
        self.pin_drag = None;
        if self.doc.undo() {
            self.requested = None;
        }
    }

    pub(super) fn redo(&mut self) {
        self.pin_drag = None;
        if self.doc.redo() {
            self.requested = None;
        }
    }

    /// Takes finished shapes from the worker and asks it for the ones the document still lacks.
    fn sync_shapes(&mut self) {
        for built in self.shaper.take_built() {
            self.evaluator.cache_mut().insert(&built.cloth, &built.key, built.shape);
        }
        let scene = self.doc.scene();
        if *scene == self.shown {
            return;
        }
        let cache = self.evaluator.cache();
        let missing: Vec<Key> = scene.keys.iter().filter(|k| cache.get(&scene.cloth, k).is_none()).cloned().collect();
        if missing.is_empty() {
            self.shown = scene.clone();
            self.shown_version += 1;
            self.mesh_of = None;
            self.requested = None;
            if std::mem::take(&mut self.frame_when_shown) {
                let (min, max) = scene_bounds(&mut self.evaluator, &self.shown);
                self.ground = Ground::under(min, max);
                self.frame_all_pending = true;
            }
            return;
        }
        let request = (scene.cloth.clone(), missing);
        if self.requested.as_ref() != Some(&request) {
            // The moves of a drag in progress do not cancel each other; anything else does.
            let supersede = !self.doc.in_gesture();
            self.shaper.request(&request.0, request.1.clone(), supersede);
            self.requested = Some(request);
        }
    }

    fn refresh_mesh(&mut self) {
        if self.mesh_of == Some((self.frame, self.stage, self.solo_layer)) {
            return;
        }
        let shown = soloed(&self.shown, self.solo_layer);
        // The last frame's paint callback has let go of the mesh by now, so this rarely copies.
        let mesh = Arc::make_mut(&mut self.mesh);
        self.evaluator.stage_mesh_into(&shown, self.frame, self.stage.mesh_stage(), Default::default(), mesh);
        self.mesh_of = Some((self.frame, self.stage, self.solo_layer));
    }

    /// Onion-skin ghosts around the playhead: earlier frames tinted blue,
    /// later ones orange, fainter further away; none outside the timeline.
    fn refresh_ghosts(&mut self) {
        let toggles = self.toggles;
        if !toggles.onion || self.stage != Stage::Animation {
            self.ghosts = Arc::default();
            self.ghosts_of = None;
            return;
        }
        let wanted = GhostsOf {
            frame: self.frame,
            frames: toggles.onion_frames,
            spacing: toggles.onion_spacing,
            shown_version: self.shown_version,
            solo: self.solo_layer,
        };
        if self.ghosts_of == Some(wanted) {
            return;
        }
        let timeline = self.shown.timeline.clone();
        let shown = soloed(&self.shown, self.solo_layer).into_owned();
        let mut ghosts = Vec::new();
        for step in 1..=toggles.onion_frames {
            let offset = f64::from(step * toggles.onion_spacing.max(1));
            let opacity = 0.45 / step as f32;
            for (frame, tint) in [(self.frame - offset, [0.35, 0.55, 1.0]), (self.frame + offset, [1.0, 0.6, 0.3])] {
                if frame < f64::from(timeline.start) || frame > f64::from(timeline.end) {
                    continue;
                }
                let mesh = self.evaluator.evaluate_frame(&shown, frame);
                ghosts.push(Ghost { mesh: Arc::new(mesh), tint, opacity });
            }
        }
        self.ghosts = Arc::new(ghosts);
        self.ghosts_of = Some(wanted);
    }

    /// The relaxation report of the shown key being edited.
    pub(super) fn shown_relax_report(&mut self) -> Option<RelaxReport> {
        let key = self.shown.key_in_effect(self.frame).clone();
        let shape = self.evaluator.cache().get(&self.shown.cloth, &key)?;
        Some(shape.rest.relax_report)
    }

    fn advance_playback(&mut self, ctx: &egui::Context) {
        if !self.playing {
            return;
        }
        let timeline = &self.doc.scene().timeline;
        let (started_at, started_frame) = *self.play_started.get_or_insert((Instant::now(), self.frame));
        let length = (timeline.end - timeline.start) as f64 + 1.0;
        let played = started_at.elapsed().as_secs_f64() * timeline.fps;
        // Loops over start..=end (or stops at the end), holding whole frames like the scene's clock.
        let offset = started_frame - timeline.start as f64 + played;
        if !self.looping && offset >= length - 1.0 {
            self.frame = timeline.end as f64;
            self.playing = false;
            return;
        }
        self.frame = timeline.start as f64 + offset.rem_euclid(length).floor();
        ctx.request_repaint();
    }

    /// With Follow on, moves the camera's target by as much as the cloth's
    /// centre moved since the last frame, so orbit and pan offsets are kept.
    fn follow_cloth(&mut self) {
        let centre = bounds(&self.mesh.positions).map(|(min, max)| (min + max) * 0.5);
        match (self.toggles.follow, centre, self.follow_anchor) {
            (true, Some(centre), Some(anchor)) => {
                self.camera.target += centre - anchor;
                self.follow_anchor = Some(centre);
            }
            (true, Some(centre), None) => self.follow_anchor = Some(centre),
            _ => self.follow_anchor = None,
        }
    }

    fn frame_all(&mut self, aspect: f32) {
        if let Some((min, max)) = bounds(&self.mesh.positions) {
            self.camera.frame_bounds(min, max, aspect);
        }
    }

    fn overlay(&mut self) -> Overlay {
        let network = self.stage == Stage::Catenaries;
        let show = SceneOverlays {
            wireframe: false,
            // Dragged pins are drawn below, where the mouse put them.
            pins: self.toggles.pins && self.pin_drag.is_none(),
            catenaries: self.toggles.catenaries || network,
            triangulation: self.toggles.triangulation || network,
        };
        let state = |grid: (u32, u32)| {
            if self.selection.contains(&grid) {
                PinState::Selected
            } else if self.hovered == Some(grid) || self.grid_hovered == Some(grid) {
                PinState::Hovered
            } else {
                PinState::Normal
            }
        };
        let mut overlay = key_overlay(&mut self.evaluator, &self.shown, self.frame, &self.mesh, show, state);
        let scene = &self.shown;
        let key = scene.key_in_effect(self.frame);
        if self.toggles.pins {
            if let Some(drag) = &self.pin_drag
                && let Some(axis) = drag.lock
            {
                // The locked axis as a line through the dragged pin, in the usual X/Y/Z colours.
                let color = match axis {
                    AxisLock::X => [0.9, 0.25, 0.2, 0.9],
                    AxisLock::Y => [0.35, 0.85, 0.25, 0.9],
                    AxisLock::Z => [0.25, 0.45, 0.95, 0.9],
                };
                let reach = axis.vector() * self.camera.distance_m * 2.0;
                overlay.segments.push(Segment { a: drag.anchor - reach, b: drag.anchor + reach, width_px: 1.5, color });
            }
            if self.pin_drag.is_some() {
                // Dragged pins are drawn where the mouse put them, before the cloth catches up.
                let doc_key = &self.doc.scene().keys[self.edit_key_index()];
                for pin in &doc_key.pins {
                    let center = glam::Vec3::new(pin.pos.0 as f32, pin.pos.1 as f32, pin.pos.2 as f32);
                    let fill = if self.selection.contains(&pin.grid) { colors::PIN_SELECTED } else { colors::PIN };
                    overlay.markers.push(Marker { center, radius_px: PIN_RADIUS_PX, fill, ring: colors::PIN_RING });
                }
            }
        }
        self.add_layer_arrow(&mut overlay);
        let highlight = self.hovered.or(self.grid_hovered);
        if let Some((i, j)) = highlight
            && !key.pins.iter().any(|p| p.grid == (i, j))
            && let Some(&center) = self.mesh.positions.get(j as usize * scene.cloth.cols() + i as usize)
            && scene.cloth.grid == self.doc.scene().cloth.grid
        {
            overlay.markers.push(Marker {
                center,
                radius_px: 4.0,
                fill: [1.0, 1.0, 1.0, 0.9],
                ring: colors::PIN_HOVERED,
            });
        }
        overlay
    }

    /// The selected layer's direction as an arrow over the cloth: a sway's or
    /// the gusts' world direction from the cloth's centre, a wave's direction
    /// of travel along the surface at the centre.
    fn add_layer_arrow(&self, overlay: &mut Overlay) {
        use crate::scene::Layer;
        let Some(layer) = self.selected_layer.and_then(|i| self.shown.layers.get(i)) else { return };
        let mesh = &self.mesh;
        let (cols, rows) = (mesh.cols, mesh.rows);
        if cols < 3 || rows < 3 || mesh.positions.len() != cols * rows {
            return;
        }
        let at = |i: usize, j: usize| mesh.positions[j * cols + i];
        let (ci, cj) = (cols / 2, rows / 2);
        let centre = at(ci, cj);
        let direction = match layer {
            Layer::Sway(l) => glam::DVec3::new(l.direction.0, l.direction.1, l.direction.2).as_vec3(),
            Layer::Gusts(l) => glam::DVec3::new(l.direction.0, l.direction.1, l.direction.2).as_vec3(),
            Layer::Wave(l) => {
                let angle = crate::animate::track::sample(&l.direction_deg, self.frame).to_radians() as f32;
                let along_u = (at(ci + 1, cj) - at(ci - 1, cj)).normalize_or_zero();
                let along_v = (at(ci, cj + 1) - at(ci, cj - 1)).normalize_or_zero();
                along_u * angle.cos() + along_v * angle.sin()
            }
            Layer::FollowThrough(_) => return,
        };
        let Some(direction) = direction.try_normalize() else { return };
        let size = bounds(&mesh.positions).map_or(1.0, |(lo, hi)| (hi - lo).max_element());
        let tip = centre + direction * size * 0.45;
        let side = direction.cross(self.camera.backward()).normalize_or_zero() * size * 0.05;
        let back = tip - direction * size * 0.08;
        let color = [0.2, 0.85, 1.0, 1.0];
        for (a, b) in [(centre, tip), (tip, back + side), (tip, back - side)] {
            overlay.segments.push(Segment { a, b, width_px: 3.0, color });
        }
    }

    fn render_options(&self) -> RenderOptions {
        let texture = if self.toggles.texture { self.shown.cloth.texture } else { ClothTexture::Plain };
        RenderOptions {
            wireframe: self.toggles.wireframe || self.stage == Stage::Catenaries,
            ground: self.toggles.ground.then_some(self.ground),
            ..RenderOptions::default()
        }
        .with_texture(texture)
    }

    /// `tent.ron* — /path/to — Drape`: the star marks unsaved changes.
    pub fn title(&self) -> String {
        let dirty = if self.doc.is_dirty() { "*" } else { "" };
        let name = self.doc.display_name();
        match self.doc.path().and_then(|p| p.parent()) {
            Some(dir) if !dir.as_os_str().is_empty() => format!("{name}{dirty} — {} — Drape", dir.display()),
            _ => format!("{name}{dirty} — Drape"),
        }
    }

    fn view_panel(&mut self, ui: &mut egui::Ui) {
        ui.strong("View");
        egui::ComboBox::from_label("Stage").selected_text(self.stage.label()).show_ui(ui, |ui| {
            for stage in Stage::ALL {
                ui.selectable_value(&mut self.stage, stage, stage.label());
            }
        });
        ui.horizontal_wrapped(|ui| {
            ui.toggle_value(&mut self.toggles.texture, "Texture");
            ui.toggle_value(&mut self.toggles.wireframe, "Wireframe");
            ui.toggle_value(&mut self.toggles.pins, "Pins");
            ui.toggle_value(&mut self.toggles.catenaries, "Catenaries");
            ui.toggle_value(&mut self.toggles.triangulation, "Triangulation");
            ui.toggle_value(&mut self.toggles.ground, "Ground");
            ui.toggle_value(&mut self.toggles.onion, "Onion skin")
                .on_hover_text("Ghosts of earlier (blue) and later (orange) frames");
            ui.toggle_value(&mut self.toggles.follow, "Follow")
                .on_hover_text("The camera travels with the cloth (F frames it)");
        });
        if self.toggles.onion {
            ui.horizontal(|ui| {
                let label = ui.label("Ghosts").id;
                let drag = egui::DragValue::new(&mut self.toggles.onion_frames).range(1..=8);
                ui.add(drag).labelled_by(label).on_hover_text("Ghosts on each side of the playhead");
                let label = ui.label("every").id;
                let drag = egui::DragValue::new(&mut self.toggles.onion_spacing).range(1..=48).suffix(" frames");
                ui.add(drag).labelled_by(label);
            });
        }
    }

    fn status_bar(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            if let Some(status) = self.shaper.status() {
                ui.add(egui::Spinner::new());
                let keys = if status.keys_total > 1 {
                    format!(" key {} of {},", status.keys_done + 1, status.keys_total)
                } else {
                    String::new()
                };
                let (cols, rows) = status.level;
                ui.label(format!(
                    "Relaxing…{keys} {cols}×{rows} level, sweep {}/{} ({:.1} s)",
                    status.iteration,
                    status.max_iterations,
                    status.started.elapsed().as_secs_f64()
                ));
            } else if let Some(message) = &self.message {
                if message.at.elapsed().as_secs_f64() < MESSAGE_SECS {
                    let color = if message.error { ui.visuals().error_fg_color } else { ui.visuals().text_color() };
                    ui.colored_label(color, &message.text);
                }
            } else if let Some(drag) = &self.pin_drag {
                let lock = match drag.lock {
                    Some(axis) => format!("locked to {axis:?}"),
                    None => "in the view plane".to_owned(),
                };
                ui.label(format!("Moving pin {:?} {lock} — X/Y/Z lock an axis, Esc puts it back", drag.grabbed));
            } else if let Some((i, j)) = self.hovered {
                ui.label(format!("Grid point ({i}, {j})"));
            }
            ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                // Frames are drawn on demand: a rate only means something while they run continuously.
                let rate = if self.playing && self.frame_interval_ms > 0.0 {
                    format!(" · {:.0} fps", 1000.0 / self.frame_interval_ms)
                } else {
                    String::new()
                };
                ui.label(format!("{:.1} ms CPU{rate}", self.last_update_ms))
                    .on_hover_text("The editor's CPU time for the last frame (and frames per second while playing).");
                let cloth = &self.shown.cloth;
                ui.label(format!("{} × {} grid ·", cloth.cols(), cloth.rows()));
            });
        });
    }

    pub fn playing(&self) -> bool {
        self.playing
    }

    pub(super) fn toggle_play(&mut self) {
        self.playing = !self.playing;
        self.play_started = None;
    }

    fn menu_bar(&mut self, ui: &mut egui::Ui) {
        egui::MenuBar::new().ui(ui, |ui| {
            ui.menu_button("File", |ui| self.file_menu(ui));
            ui.menu_button("Edit", |ui| {
                let ctx = ui.ctx().clone();
                let undo = match self.doc.undo_label() {
                    Some(label) => format!("Undo {label}"),
                    None => "Undo".to_owned(),
                };
                let button = egui::Button::new(undo).shortcut_text(ctx.format_shortcut(&SHORTCUT_UNDO));
                if ui.add_enabled(self.doc.undo_label().is_some(), button).clicked() {
                    self.undo();
                }
                let redo = match self.doc.redo_label() {
                    Some(label) => format!("Redo {label}"),
                    None => "Redo".to_owned(),
                };
                let button = egui::Button::new(redo).shortcut_text(ctx.format_shortcut(&SHORTCUT_REDO));
                if ui.add_enabled(self.doc.redo_label().is_some(), button).clicked() {
                    self.redo();
                }
                ui.separator();
                let button = egui::Button::new("Unpin selected").shortcut_text("Delete");
                if ui.add_enabled(!self.selection.is_empty(), button).clicked() {
                    self.delete_selected_pins();
                }
            });
            ui.menu_button("View", |ui| {
                if ui.add(egui::Button::new("Frame all").shortcut_text("F")).clicked() {
                    self.frame_all_pending = true;
                }
                ui.separator();
                for stage in Stage::ALL {
                    ui.radio_value(&mut self.stage, stage, stage.label());
                }
            });
            ui.menu_button("Help", |ui| {
                if ui.button("Keyboard shortcuts").clicked() {
                    self.show_shortcuts = true;
                }
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
                    for (keys, action) in SHORTCUTS {
                        ui.strong(*keys);
                        ui.label(*action);
                        ui.end_row();
                    }
                });
            });
    }

    /// Shortcuts with modifiers work even while a text field has focus; plain keys only when none has.
    fn keyboard(&mut self, ctx: &egui::Context, aspect: f32) {
        let consume = |shortcut: &KeyboardShortcut| ctx.input_mut(|i| i.consume_shortcut(shortcut));
        // Longest modifier sets first: Ctrl+Shift+Z must not be taken for Ctrl+Z.
        if consume(&SHORTCUT_REDO) || consume(&SHORTCUT_REDO_ALT) {
            self.redo();
        } else if consume(&SHORTCUT_UNDO) {
            self.undo();
        }
        if consume(&SHORTCUT_SAVE_AS) {
            self.file_save_as();
        } else if consume(&SHORTCUT_SAVE) {
            self.file_save();
        }
        if consume(&SHORTCUT_OPEN) {
            self.file_open();
        }
        if consume(&SHORTCUT_NEW) {
            self.file_new();
        }
        if ctx.egui_wants_keyboard_input() || self.pin_drag.is_some() {
            return;
        }
        let timeline = self.doc.scene().timeline.clone();
        let pressed = |key| ctx.input(|i| i.key_pressed(key) && i.modifiers.is_none());
        if pressed(KeyCode::Space) {
            self.toggle_play();
        }
        if pressed(KeyCode::ArrowLeft) {
            self.set_frame(self.frame.round() - 1.0);
        }
        if pressed(KeyCode::ArrowRight) {
            self.set_frame(self.frame.round() + 1.0);
        }
        if pressed(KeyCode::Home) {
            self.set_frame(timeline.start as f64);
        }
        if pressed(KeyCode::End) {
            self.set_frame(timeline.end as f64);
        }
        if pressed(KeyCode::F) {
            self.frame_all(aspect);
        }
        if pressed(KeyCode::Delete) || pressed(KeyCode::Backspace) {
            if self.selection.is_empty() && self.selected_key.is_some() {
                self.delete_selected_key();
            } else {
                self.delete_selected_pins();
            }
        }
        if pressed(KeyCode::K) {
            self.add_key_here();
        }
    }

    fn viewport(&mut self, ui: &mut egui::Ui) {
        let rect = ui.available_rect_before_wrap();
        let response = ui.allocate_rect(rect, Sense::click_and_drag());
        response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Canvas, true, "Viewport"));
        self.viewport_rect = rect;
        let aspect = rect.width() / rect.height().max(1.0);
        let pixels_per_point = ui.ctx().pixels_per_point();
        let size_px = (
            (rect.width() * pixels_per_point).round().max(1.0) as u32,
            (rect.height() * pixels_per_point).round().max(1.0) as u32,
        );
        self.viewport_input(ui, &response, size_px);
        self.keyboard(ui.ctx(), aspect);
        self.sync_shapes();
        self.refresh_mesh();
        self.refresh_ghosts();
        if std::mem::take(&mut self.frame_all_pending) {
            self.frame_all(aspect);
        }
        self.follow_cloth();
        if let Some((i, j)) = self.hovered
            && let Some(pointer) = response.hover_pos()
        {
            let pinned = self.doc.scene().keys[self.edit_key_index()].pins.iter().any(|p| p.grid == (i, j));
            let text = format!("({i}, {j}){}", if pinned { " pin" } else { "" });
            let at = pointer + egui::vec2(14.0, -18.0);
            let font = egui::FontId::proportional(13.0);
            let galley = ui.painter().layout_no_wrap(text, font, egui::Color32::WHITE);
            let bg = egui::Rect::from_min_size(at, galley.size()).expand(3.0);
            let overlay_painter = ui
                .painter()
                .clone()
                .with_layer_id(egui::LayerId::new(egui::Order::Foreground, egui::Id::unique("viewport-hover")));
            overlay_painter.rect_filled(bg, 3.0, egui::Color32::from_black_alpha(170));
            overlay_painter.galley(at, galley, egui::Color32::WHITE);
        }
        if !self.has_viewport {
            return;
        }
        let frame = ViewportFrame {
            mesh: self.mesh.clone(),
            camera: self.camera,
            options: self.render_options(),
            overlay: Arc::new(self.overlay()),
            ghosts: self.ghosts.clone(),
            size_px,
        };
        ui.painter().add(egui_wgpu::Callback::new_paint_callback(rect, frame));
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

impl eframe::App for DrapeApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let started = Instant::now();
        let ctx = ui.ctx().clone();
        let _ = self.repaint_context.set(ctx.clone());
        self.measure_frame();
        self.advance_playback(&ctx);
        self.handle_close_request(&ctx);
        // A viewport command asks for another frame: send the title only when it changes.
        let title = self.title();
        if title != self.sent_title {
            ctx.send_viewport_cmd(egui::ViewportCommand::Title(title.clone()));
            self.sent_title = title;
        }
        egui::Panel::top("menu").show(ui, |ui| self.menu_bar(ui));
        egui::Panel::bottom("timeline").show(ui, |ui| self.timeline_panel(ui));
        self.status_rect = egui::Panel::bottom("status").show(ui, |ui| self.status_bar(ui)).response.rect;
        egui::Panel::left("cloth").default_size(280.0).show(ui, |ui| {
            self.view_panel(ui);
            ui.separator();
            self.cloth_panel(ui);
        });
        egui::Panel::right("layers").default_size(270.0).min_size(220.0).show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| self.layers_panel(ui));
        });
        egui::CentralPanel::default().frame(egui::Frame::NONE).show(ui, |ui| self.viewport(ui));
        self.shortcuts_window(&ctx);
        self.export_window(&ctx);
        self.file_dialogs(&ctx);
        // A gesture ends when the mouse lets go (a drag on a slider or a pin is one undo step).
        if self.pin_drag.is_none() && !ctx.input(|i| i.pointer.any_down()) {
            self.end_gesture();
        }
        if self.is_relaxing() {
            ctx.request_repaint_after(Duration::from_millis(50));
        }
        self.autosave(&ctx);
        self.frames_drawn += 1;
        if self.quit_after_frames.is_some_and(|n| self.frames_drawn >= n) {
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        } else if self.quit_after_frames.is_some() {
            ctx.request_repaint();
        }
        self.last_update_ms = started.elapsed().as_secs_f64() * 1e3;
    }

    fn on_exit(&mut self) {
        self.clean_exit();
    }
}

/// What the onion-skin ghosts were made for: the playhead, how many frames
/// how far apart, the shown scene's version and the soloed layer.
#[derive(Clone, Copy, Debug, PartialEq)]
struct GhostsOf {
    frame: f64,
    frames: u32,
    spacing: u32,
    shown_version: u64,
    solo: Option<usize>,
}

/// `scene` with every layer but `solo` switched off (the scene itself when no layer is soloed).
fn soloed(scene: &Scene, solo: Option<usize>) -> std::borrow::Cow<'_, Scene> {
    let Some(solo) = solo.filter(|s| *s < scene.layers.len()) else { return std::borrow::Cow::Borrowed(scene) };
    let mut alone = scene.clone();
    for (index, layer) in alone.layers.iter_mut().enumerate() {
        *layer.enabled_mut() = index == solo;
    }
    std::borrow::Cow::Owned(alone)
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
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default().with_inner_size([1400.0, 860.0]).with_title("Drape"),
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

    fn app() -> DrapeApp {
        let scene = crate::scene::parse(DEFAULT_SCENE, "magic_carpet.ron").unwrap();
        DrapeApp::new(scene, None, None)
    }

    #[test]
    fn the_mesh_at_the_playhead_is_evaluate_at_that_frame() {
        let mut app = app();
        for frame in [37.0, 5.0, 120.0, 37.0] {
            app.set_frame(frame);
            app.refresh_mesh();
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
    fn pinning_a_point_pins_it_where_the_cloth_is() {
        let mut app = app();
        let cols = app.shown_scene().cloth.cols();
        let (i, j) = (5u32, 7u32);
        let at = app.mesh().positions[j as usize * cols + i as usize];
        app.toggle_pin((i, j));
        let key = &app.scene().keys[app.edit_key_index()];
        let pin = key.pins.iter().find(|p| p.grid == (i, j)).expect("pinned");
        assert_eq!(pin.pos, (at.x as f64, at.y as f64, at.z as f64));
        assert_eq!(app.selection(), [(i, j)]);
        app.delete_selected_pins();
        assert!(!app.scene().keys[app.edit_key_index()].pins.iter().any(|p| p.grid == (i, j)));
        app.undo();
        assert!(app.scene().keys[app.edit_key_index()].pins.iter().any(|p| p.grid == (i, j)));
    }
}
