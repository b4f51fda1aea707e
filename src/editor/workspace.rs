//! What every panel works on: the document, the shapes on screen, this
//! document's playhead and selections, and the status line.
//!
//! Panels own their own state and take a `&mut Workspace` for the rest. A new
//! document gets a new [`Session`], so what belonged to the old one resets by
//! construction.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use super::document::Document;
use super::edits;
use super::selection::Pick;
use super::session::Session;
use super::shown::Shown;
use crate::animate::KeyShape;
use crate::scene::Scene;

/// How long a status message stays, seconds.
pub const MESSAGE_SECS: f64 = 8.0;

/// A line in the status bar.
pub struct Message {
    pub text: String,
    pub error: bool,
    pub at: Instant,
}

/// How Cancel in the status bar brings the document back to the scene on screen.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TakeBack {
    /// Undo this many edits, which asked for the relaxation.
    Edits(usize),
    /// Redo this many undos, which asked for it.
    Undos(usize),
}

pub struct Workspace {
    pub doc: Document,
    pub shown: Shown,
    pub session: Session,
    /// The status bar's message.
    message: Option<Message>,
    /// A problem shown in a dialog until dismissed (a file that cannot be opened, a failed export).
    alert: Option<String>,
    /// Counts the documents opened here: state made for one document (a
    /// panel's, a drag's) tells from it that the document was replaced.
    document: u64,
}

impl Workspace {
    pub fn new(scene: Scene, path: Option<PathBuf>) -> Workspace {
        Workspace {
            session: Session::opening(&scene),
            shown: Shown::new(scene.clone()),
            doc: Document::new(scene, path),
            message: None,
            alert: None,
            document: 0,
        }
    }

    /// Replaces the document (New, Open, Restore): a new session (see
    /// [`Session::opening`]), nothing asked of the worker.
    pub fn replace_document(&mut self, scene: Scene, path: Option<PathBuf>) {
        self.session.for_next_document(&scene);
        self.doc = Document::new(scene, path);
        self.shown.forget_document();
        self.document += 1;
    }

    /// Which document this is: changes when New, Open or Restore replaces it.
    pub fn document_number(&self) -> u64 {
        self.document
    }

    pub fn frame(&self) -> f64 {
        self.session.frame()
    }

    /// Moves the playhead, kept on the timeline.
    pub fn set_frame(&mut self, frame: f64) {
        let timeline = &self.doc.scene().timeline;
        self.session.move_playhead(frame.clamp(f64::from(timeline.start), f64::from(timeline.end)));
    }

    /// Moves the playhead to the next (`later`) or previous key: a rest-shape
    /// key, or a key of the selected collider (else the selected layer), as
    /// the timeline's dots show them. Stays put past the last.
    pub fn jump_to_key(&mut self, later: bool) {
        let scene = self.doc.scene();
        let mut frames: Vec<i32> = scene.keys.iter().map(|k| k.frame).collect();
        let (layer, collider) = (self.session.selected_layer(), self.session.selected_collider());
        if let Some(keyed) = super::param_edit::Keyed::selected(scene, layer, collider) {
            frames.extend(keyed.key_frames(scene));
        }
        let here = self.frame().round() as i32;
        let target = if later {
            frames.into_iter().filter(|f| *f > here).min()
        } else {
            frames.into_iter().filter(|f| *f < here).max()
        };
        if let Some(frame) = target {
            self.set_frame(f64::from(frame));
        }
    }

    pub fn toggle_play(&mut self) {
        self.session.toggle_play();
    }

    /// Whether the shown cloth has the document's grid, so a grid point means the same vertex in both.
    pub fn shown_grid_is_current(&self) -> bool {
        self.shown.scene().cloth.grid == self.doc.scene().cloth.grid
    }

    /// The index of the key being edited: the one in effect at the playhead.
    pub fn edit_key_index(&self) -> usize {
        let keys = &self.doc.scene().keys;
        keys.iter().rposition(|k| f64::from(k.frame) <= self.session.frame()).unwrap_or(0)
    }

    /// Applies an edit to the document, reporting a rejected one in the status bar.
    pub fn apply(&mut self, label: &str, change: impl FnOnce(&mut Scene)) {
        match self.doc.edit(label, change) {
            Ok(()) => {
                let pins = &self.doc.scene().keys[self.edit_key_index()].pins;
                self.session.keep_selected_among(pins);
            }
            Err(rejected) => self.report(format!("Not applied: {rejected}"), true),
        }
    }

    /// Shows `text` in the status bar for a while.
    pub fn report(&mut self, text: String, error: bool) {
        self.message = Some(Message { text, error, at: Instant::now() });
    }

    /// The status bar's last message (shown for [`MESSAGE_SECS`]).
    pub fn message(&self) -> Option<&Message> {
        self.message.as_ref()
    }

    /// Clears the status bar, so it says what the mode just entered asks for.
    pub fn clear_message(&mut self) {
        self.message = None;
    }

    /// Shows `problem` in a dialog until the user dismisses it.
    pub fn show_alert(&mut self, problem: String) {
        self.alert = Some(problem);
    }

    /// The problem the dialog shows, if any.
    pub fn alert(&self) -> Option<&str> {
        self.alert.as_deref()
    }

    /// OK in the problem's dialog.
    pub fn dismiss_alert(&mut self) {
        self.alert = None;
    }

    /// Ends the open gesture (one undo step) and lets the final state's relaxation cancel stale ones.
    pub fn end_gesture(&mut self) {
        if self.doc.in_gesture() {
            self.doc.end_gesture();
            self.shown.forget_requests();
        }
    }

    pub fn undo(&mut self) {
        if self.doc.undo() {
            self.shown.forget_requests();
        }
    }

    pub fn redo(&mut self) {
        if self.doc.redo() {
            self.shown.forget_requests();
        }
    }

    /// What Cancel in the status bar does to stop the running relaxation:
    /// take back the edits since the scene on screen, or redo the undos that
    /// left it. `None` when neither leads back to it (the scene on screen is
    /// the document, or not in the history).
    pub fn relaxation_take_back(&self) -> Option<TakeBack> {
        let shown = self.shown.scene();
        if let Some(steps) = self.doc.undo_steps_to(shown).filter(|steps| *steps > 0) {
            return Some(TakeBack::Edits(steps));
        }
        self.doc.redo_steps_to(shown).map(TakeBack::Undos)
    }

    /// Stops the running relaxation by bringing the document back to the
    /// scene on screen ([`Workspace::relaxation_take_back`]): edits taken
    /// back stay on Redo, undos redone stay on Undo.
    pub fn cancel_relaxation(&mut self) {
        let Some(back) = self.relaxation_take_back() else { return };
        let message = match back {
            TakeBack::Edits(steps) => {
                for _ in 0..steps {
                    self.doc.undo();
                }
                let (edits, them) = if steps == 1 { ("edit", "it") } else { ("edits", "them") };
                format!("Relaxation cancelled: {steps} {edits} taken back (Redo brings {them} back).")
            }
            TakeBack::Undos(steps) => {
                for _ in 0..steps {
                    self.doc.redo();
                }
                let (undos, them) = if steps == 1 { ("undo", "it") } else { ("undos", "them") };
                format!("Relaxation cancelled: {steps} {undos} redone (Undo takes {them} back again).")
            }
        };
        self.shown.stop_relaxing();
        self.report(message, false);
    }

    /// The key an edit of the key in effect (`label`) goes to: that key, or
    /// with auto-key on and the playhead off it, a new key at the playhead
    /// holding the pose there, made in the same undo step as the edit.
    /// `None` (with a message) when the new key cannot be made yet.
    pub fn key_to_edit(&mut self, label: &str) -> Option<usize> {
        let index = self.edit_key_index();
        let playhead = self.frame().round() as i32;
        if !self.session.auto_key() || self.doc.scene().keys[index].frame == playhead {
            return Some(index);
        }
        self.doc.begin_gesture(label);
        let keys_before = self.doc.scene().keys.len();
        self.add_key_here();
        (self.doc.scene().keys.len() > keys_before).then(|| self.edit_key_index())
    }

    /// Pins grid point `point` of the key being edited where the cloth is now
    /// (as a plain click does), or unpins it.
    pub fn toggle_pin(&mut self, point: (u32, u32)) {
        if !edits::is_pinned(&self.doc.scene().keys[self.edit_key_index()], point) {
            self.pin_here(point, Pick::Replace);
            return;
        }
        let Some(index) = self.key_to_edit("Unpin") else { return };
        self.apply("Unpin", |s| edits::unpin(&mut s.keys[index], &[point]));
        self.session.unpinned(point);
    }

    /// Pins grid point `point` of the key being edited where the cloth is now;
    /// `how` (the click's modifiers) says what the selection does
    /// ([`selection::after_pinning`]).
    pub fn pin_here(&mut self, point: (u32, u32), how: Pick) {
        let Some(index) = self.key_to_edit("Pin") else { return };
        let cloth = &self.shown.scene().cloth;
        let vertex = point.1 as usize * cloth.cols() + point.0 as usize;
        let same_grid = self.shown_grid_is_current();
        let Some(p) = self.shown.mesh().positions.get(vertex).copied().filter(|_| same_grid) else {
            self.report("Wait for the cloth to finish relaxing before pinning.".to_owned(), true);
            return;
        };
        let pos = (f64::from(p.x), f64::from(p.y), f64::from(p.z));
        self.apply("Pin", |s| edits::pin_point(&mut s.keys[index], point, pos));
        self.session.pinned(point, how);
    }

    pub fn delete_selected_pins(&mut self) {
        if self.session.selection().is_empty() {
            return;
        }
        let selection = self.session.selection().to_vec();
        let label = if selection.len() == 1 { "Unpin" } else { "Unpin pins" };
        let Some(index) = self.key_to_edit(label) else { return };
        self.apply(label, |s| edits::unpin(&mut s.keys[index], &selection));
    }

    /// Removes the selected collider (Delete with no pin selected).
    pub fn delete_selected_collider(&mut self) {
        let Some(index) = self.session.take_selected_collider() else { return };
        if index < self.doc.scene().colliders.len() {
            self.apply("Remove collider", |s| {
                s.colliders.remove(index);
            });
        }
    }

    /// K: a new rest-shape key at the playhead's frame, holding the pose shown
    /// now (the key in effect's pins where the cloth holds them at this frame,
    /// its fabric).
    pub fn add_key_here(&mut self) {
        let frame = self.frame().round() as i32;
        self.set_frame(f64::from(frame));
        let scene = self.doc.scene().clone();
        if let Some(index) = scene.keys.iter().position(|k| k.frame == frame) {
            self.session.key_made(index);
            self.report(format!("There is already a key at frame {frame}."), false);
            return;
        }
        if *self.shown.scene() != scene {
            self.report("Wait for the cloth to finish relaxing before adding a key.".to_owned(), true);
            return;
        }
        let mut key = scene.key_in_effect(f64::from(frame)).clone();
        key.frame = frame;
        // The evaluated mesh at a whole frame holds the pins where this frame puts them.
        let mesh = self.shown.evaluate_frame(&scene, f64::from(frame));
        let cols = scene.cloth.cols();
        for pin in &mut key.pins {
            let p = mesh.positions[pin.grid.1 as usize * cols + pin.grid.0 as usize];
            pin.pos = (f64::from(p.x), f64::from(p.y), f64::from(p.z));
        }
        let at = scene.keys.iter().position(|k| k.frame > frame).unwrap_or(scene.keys.len());
        self.apply("Add key", |s| s.keys.insert(at, key));
        self.session.key_made(at);
    }

    pub fn delete_selected_key(&mut self) {
        let Some(index) = self.session.selected_key() else { return };
        if self.doc.scene().keys.len() <= 1 {
            self.report("A scene needs at least one key.".to_owned(), true);
            return;
        }
        self.apply("Delete key", |s| {
            s.keys.remove(index);
        });
        self.session.let_go_of_key();
    }

    /// The rest shape of the key in effect at the playhead, once relaxed
    /// (its relaxation report; its self-crossings once counted).
    pub fn shown_key_shape(&self) -> Option<Arc<KeyShape>> {
        self.shown.key_shape(self.session.frame())
    }
}
