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
use super::selection::{self, Pick};
use super::shown::Shown;
use crate::animate::KeyShape;
use crate::scene::{Pin, Scene};

/// How long a status message stays, seconds.
pub const MESSAGE_SECS: f64 = 8.0;

/// A line in the status bar.
pub struct Message {
    pub text: String,
    pub error: bool,
    pub at: Instant,
}

/// The playhead and the selections of the open document.
#[derive(Default)]
pub struct Session {
    /// The frame the playhead is on (fractional while playing).
    pub frame: f64,
    pub playing: bool,
    /// When playback started and from which frame.
    pub play_started: Option<(Instant, f64)>,
    /// Selected pins of the key being edited (grid points).
    pub selection: Vec<(u32, u32)>,
    /// The rest-shape key selected on the timeline.
    pub selected_key: Option<usize>,
    /// The layer whose parameters the Layers panel shows (and whose keys the timeline shows).
    pub selected_layer: Option<usize>,
    /// The collider the Colliders panel shows, drawn outlined in the viewport
    /// (picked there or in the panel).
    pub selected_collider: Option<usize>,
    /// A layer shown alone (the others off in the viewport only; the scene keeps them).
    pub solo_layer: Option<usize>,
    /// The cloth point under the mouse in the viewport, and in the grid editor.
    pub hovered: Option<(u32, u32)>,
    pub grid_hovered: Option<(u32, u32)>,
    /// The viewport's camera moves with the cloth's centre, keeping how it
    /// looks at it (saved with the view).
    pub follow: bool,
    /// The viewport looks through the scene's shot camera (View ▸ Camera);
    /// saved with the view.
    pub through_camera: bool,
    /// Auto-key: an edit off a key adds a key at the playhead and changes
    /// that one (rest-shape keys, and layer parameters). Kept across documents.
    pub auto_key: bool,
    /// Pin positions copied from a key (grid point, metres), to paste on another.
    pub copied_pins: Vec<Pin>,
    /// Attach by clicking: the pin (grid point) the next click on a
    /// reference in the viewport attaches there; Esc leaves the mode.
    pub attaching: Option<(u32, u32)>,
}

impl Session {
    /// Selects layer `index` (or none). The timeline's dot row shows one
    /// thing's keys, so selecting a layer lets go of the selected collider.
    pub fn select_layer(&mut self, index: Option<usize>) {
        self.selected_layer = index;
        if index.is_some() {
            self.selected_collider = None;
        }
    }

    /// Selects collider `index` (or none), letting go of the selected layer.
    pub fn select_collider(&mut self, index: Option<usize>) {
        self.selected_collider = index;
        if index.is_some() {
            self.selected_layer = None;
        }
    }

    /// A fresh session on `scene`: the playhead, Follow and the look
    /// through the shot camera as its saved view had them (the playhead kept
    /// on the timeline); without a saved view at the timeline's start with
    /// Follow off, looking through the shot camera if there is one (the
    /// picture the scene was made for).
    pub fn opening(scene: &Scene) -> Session {
        let timeline = &scene.timeline;
        let frame = scene.view.as_ref().and_then(|v| v.frame).unwrap_or(timeline.start);
        let mut session = Session::at(f64::from(frame.clamp(timeline.start, timeline.end)));
        session.follow = scene.view.as_ref().is_some_and(|v| v.follow);
        session.through_camera = scene.camera.is_some() && scene.view.as_ref().is_none_or(|v| v.through_camera);
        session
    }

    /// A fresh session with the playhead at `frame`.
    pub fn at(frame: f64) -> Session {
        Session { frame, ..Session::default() }
    }
}

pub struct Workspace {
    pub doc: Document,
    pub shown: Shown,
    pub session: Session,
    /// The status bar's message.
    pub message: Option<Message>,
    /// A problem shown in a dialog until dismissed (a file that cannot be opened, a failed export).
    pub alert: Option<String>,
}

impl Workspace {
    pub fn new(scene: Scene, path: Option<PathBuf>) -> Workspace {
        Workspace {
            session: Session::opening(&scene),
            shown: Shown::new(scene.clone()),
            doc: Document::new(scene, path),
            message: None,
            alert: None,
        }
    }

    /// Replaces the document (New, Open, Restore): a new session (see
    /// [`Session::opening`]), nothing asked of the worker.
    pub fn replace_document(&mut self, scene: Scene, path: Option<PathBuf>) {
        let (auto_key, copied_pins) = (self.session.auto_key, std::mem::take(&mut self.session.copied_pins));
        self.session = Session::opening(&scene);
        (self.session.auto_key, self.session.copied_pins) = (auto_key, copied_pins);
        self.doc = Document::new(scene, path);
        self.shown.forget_document();
    }

    pub fn frame(&self) -> f64 {
        self.session.frame
    }

    /// Moves the playhead, kept on the timeline.
    pub fn set_frame(&mut self, frame: f64) {
        let timeline = &self.doc.scene().timeline;
        self.session.frame = frame.clamp(f64::from(timeline.start), f64::from(timeline.end));
        if self.session.playing {
            self.session.play_started = Some((Instant::now(), self.session.frame));
        }
    }

    /// Moves the playhead to the next (`later`) or previous key: a rest-shape
    /// key, or a key of the selected collider (else the selected layer), as
    /// the timeline's dots show them. Stays put past the last.
    pub fn jump_to_key(&mut self, later: bool) {
        let scene = self.doc.scene();
        let mut frames: Vec<i32> = scene.keys.iter().map(|k| k.frame).collect();
        let (layer, collider) = (self.session.selected_layer, self.session.selected_collider);
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
        self.session.playing = !self.session.playing;
        self.session.play_started = None;
    }

    /// Whether the shown cloth has the document's grid, so a grid point means the same vertex in both.
    pub fn shown_grid_is_current(&self) -> bool {
        self.shown.scene.cloth.grid == self.doc.scene().cloth.grid
    }

    /// The index of the key being edited: the one in effect at the playhead.
    pub fn edit_key_index(&self) -> usize {
        let keys = &self.doc.scene().keys;
        keys.iter().rposition(|k| f64::from(k.frame) <= self.session.frame).unwrap_or(0)
    }

    /// Applies an edit to the document, reporting a rejected one in the status bar.
    pub fn apply(&mut self, label: &str, change: impl FnOnce(&mut Scene)) {
        match self.doc.edit(label, change) {
            Ok(()) => {
                let pins = &self.doc.scene().keys[self.edit_key_index()].pins;
                self.session.selection.retain(|s| pins.iter().any(|p| p.grid == *s));
            }
            Err(rejected) => self.report(format!("Not applied: {rejected}"), true),
        }
    }

    /// Shows `text` in the status bar for a while.
    pub fn report(&mut self, text: String, error: bool) {
        self.message = Some(Message { text, error, at: Instant::now() });
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

    /// How many edits Cancel in the status bar takes back to stop the
    /// running relaxation: those since the scene on screen. `None` when
    /// there is nothing to take back (the scene on screen is the document,
    /// or not in the undo history).
    pub fn edits_being_relaxed(&self) -> Option<usize> {
        self.doc.undo_steps_to(&self.shown.scene).filter(|steps| *steps > 0)
    }

    /// Stops the running relaxation by taking back the edits that asked for
    /// it (they stay on Redo), so the scene on screen is the document again.
    pub fn cancel_relaxation(&mut self) {
        let Some(steps) = self.edits_being_relaxed() else { return };
        for _ in 0..steps {
            self.doc.undo();
        }
        self.shown.stop_relaxing();
        let (edits, them) = if steps == 1 { ("edit", "it") } else { ("edits", "them") };
        self.report(format!("Relaxation cancelled: {steps} {edits} taken back (Redo brings {them} back)."), false);
    }

    /// The key an edit of the key in effect (`label`) goes to: that key, or
    /// with auto-key on and the playhead off it, a new key at the playhead
    /// holding the pose there, made in the same undo step as the edit.
    /// `None` (with a message) when the new key cannot be made yet.
    pub fn key_to_edit(&mut self, label: &str) -> Option<usize> {
        let index = self.edit_key_index();
        let playhead = self.frame().round() as i32;
        if !self.session.auto_key || self.doc.scene().keys[index].frame == playhead {
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
        self.session.selection.retain(|p| *p != point);
    }

    /// Pins grid point `point` of the key being edited where the cloth is now;
    /// `how` (the click's modifiers) says what the selection does
    /// ([`selection::after_pinning`]).
    pub fn pin_here(&mut self, point: (u32, u32), how: Pick) {
        let Some(index) = self.key_to_edit("Pin") else { return };
        let cloth = &self.shown.scene.cloth;
        let vertex = point.1 as usize * cloth.cols() + point.0 as usize;
        let same_grid = self.shown_grid_is_current();
        let Some(p) = self.shown.mesh.positions.get(vertex).copied().filter(|_| same_grid) else {
            self.report("Wait for the cloth to finish relaxing before pinning.".to_owned(), true);
            return;
        };
        let pos = (f64::from(p.x), f64::from(p.y), f64::from(p.z));
        self.apply("Pin", |s| edits::pin_point(&mut s.keys[index], point, pos));
        selection::after_pinning(&mut self.session.selection, point, how);
    }

    pub fn delete_selected_pins(&mut self) {
        if self.session.selection.is_empty() {
            return;
        }
        let selection = self.session.selection.clone();
        let label = if selection.len() == 1 { "Unpin" } else { "Unpin pins" };
        let Some(index) = self.key_to_edit(label) else { return };
        self.apply(label, |s| edits::unpin(&mut s.keys[index], &selection));
    }

    /// Removes the selected collider (Delete with no pin selected).
    pub fn delete_selected_collider(&mut self) {
        let Some(index) = self.session.selected_collider.take() else { return };
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
            self.session.selected_key = Some(index);
            self.report(format!("There is already a key at frame {frame}."), false);
            return;
        }
        if self.shown.scene != scene {
            self.report("Wait for the cloth to finish relaxing before adding a key.".to_owned(), true);
            return;
        }
        let mut key = scene.key_in_effect(f64::from(frame)).clone();
        key.frame = frame;
        // The evaluated mesh at a whole frame holds the pins where this frame puts them.
        let mesh = self.shown.evaluator.evaluate_frame(&scene, f64::from(frame));
        let cols = scene.cloth.cols();
        for pin in &mut key.pins {
            let p = mesh.positions[pin.grid.1 as usize * cols + pin.grid.0 as usize];
            pin.pos = (f64::from(p.x), f64::from(p.y), f64::from(p.z));
        }
        let at = scene.keys.iter().position(|k| k.frame > frame).unwrap_or(scene.keys.len());
        self.apply("Add key", |s| s.keys.insert(at, key));
        self.session.selected_key = Some(at);
    }

    pub fn delete_selected_key(&mut self) {
        let Some(index) = self.session.selected_key else { return };
        if self.doc.scene().keys.len() <= 1 {
            self.report("A scene needs at least one key.".to_owned(), true);
            return;
        }
        self.apply("Delete key", |s| {
            s.keys.remove(index);
        });
        self.session.selected_key = None;
    }

    /// The rest shape of the key in effect at the playhead, once relaxed
    /// (its relaxation report; its self-crossings once counted).
    pub fn shown_key_shape(&self) -> Option<Arc<KeyShape>> {
        self.shown.key_shape(self.session.frame)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn selecting_a_layer_lets_go_of_the_collider_and_the_other_way_round() {
        let mut session = Session::at(0.0);
        session.select_layer(Some(1));
        session.select_collider(Some(0));
        assert_eq!((session.selected_layer, session.selected_collider), (None, Some(0)));
        session.select_layer(Some(2));
        assert_eq!((session.selected_layer, session.selected_collider), (Some(2), None));
        // Letting go of one keeps the other.
        session.select_collider(None);
        assert_eq!(session.selected_layer, Some(2));
    }
}
