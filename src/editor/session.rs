//! The playhead and the selections of the open document: what one panel
//! changes for another. Every change is a method named for what the user
//! did, so this file is the one place that writes them.

use std::time::{Duration, Instant};

use super::selection::{self, Pick};
use crate::scene::{Pin, Scene, Timeline};

/// The playhead and the selections of the open document.
#[derive(Default)]
pub struct Session {
    /// The frame the playhead is on (fractional while playing).
    frame: f64,
    playing: bool,
    /// When playback started and from which frame.
    play_started: Option<(Instant, f64)>,
    /// Selected pins of the key being edited (grid points).
    selection: Vec<(u32, u32)>,
    /// The rest-shape key selected on the timeline.
    selected_key: Option<usize>,
    /// The layer whose parameters the Layers panel shows (and whose keys the timeline shows).
    selected_layer: Option<usize>,
    /// The collider the Colliders panel shows, drawn outlined in the viewport
    /// (picked there or in the panel).
    selected_collider: Option<usize>,
    /// A layer shown alone (the others off in the viewport only; the scene keeps them).
    solo_layer: Option<usize>,
    /// The cloth point under the mouse in the viewport, and in the grid editor.
    hovered: Option<(u32, u32)>,
    grid_hovered: Option<(u32, u32)>,
    /// The viewport's camera moves with the cloth's centre, keeping how it
    /// looks at it (saved with the view).
    follow: bool,
    /// The viewport looks through the scene's shot camera (View ▸ Camera);
    /// saved with the view.
    through_camera: bool,
    /// Auto-key: an edit off a key adds a key at the playhead and changes
    /// that one (rest-shape keys, and layer parameters). Kept across documents.
    auto_key: bool,
    /// Pin positions copied from a key (grid point, metres), to paste on another.
    /// Kept across documents.
    copied_pins: Vec<Pin>,
    /// Attach by clicking: the pin (grid point) the next click on a
    /// reference in the viewport attaches there; Esc leaves the mode.
    attaching: Option<(u32, u32)>,
}

/// What playback asks of the window after a step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Repaint {
    /// Nothing: playback is off or has stopped.
    No,
    /// Draw again now: the playhead moved.
    Now,
    /// Draw again after this long: the next frame is not due yet.
    After(Duration),
}

impl Session {
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

    /// The session of the next document opened (New, Open, Restore): a fresh
    /// one, keeping auto-key and the copied pins.
    pub fn for_next_document(&mut self, scene: &Scene) {
        let mut next = Session::opening(scene);
        next.auto_key = self.auto_key;
        next.copied_pins = std::mem::take(&mut self.copied_pins);
        *self = next;
    }

    pub fn frame(&self) -> f64 {
        self.frame
    }

    pub fn playing(&self) -> bool {
        self.playing
    }

    pub fn selection(&self) -> &[(u32, u32)] {
        &self.selection
    }

    pub fn selected_key(&self) -> Option<usize> {
        self.selected_key
    }

    pub fn selected_layer(&self) -> Option<usize> {
        self.selected_layer
    }

    pub fn selected_collider(&self) -> Option<usize> {
        self.selected_collider
    }

    pub fn solo_layer(&self) -> Option<usize> {
        self.solo_layer
    }

    pub fn hovered(&self) -> Option<(u32, u32)> {
        self.hovered
    }

    pub fn grid_hovered(&self) -> Option<(u32, u32)> {
        self.grid_hovered
    }

    pub fn follow(&self) -> bool {
        self.follow
    }

    pub fn through_camera(&self) -> bool {
        self.through_camera
    }

    pub fn auto_key(&self) -> bool {
        self.auto_key
    }

    pub fn copied_pins(&self) -> &[Pin] {
        &self.copied_pins
    }

    pub fn attaching(&self) -> Option<(u32, u32)> {
        self.attaching
    }

    /// Moves the playhead to `frame` (the caller keeps it on the timeline);
    /// playing, the clock restarts from there.
    pub fn move_playhead(&mut self, frame: f64) {
        self.frame = frame;
        if self.playing {
            self.play_started = Some((Instant::now(), frame));
        }
    }

    /// Play or Pause.
    pub fn toggle_play(&mut self) {
        self.playing = !self.playing;
        self.play_started = None;
    }

    /// Moves the playhead on while playing: by the scene's clock (looping
    /// over the timeline or stopping at its end), or with `every_frame` one
    /// frame per frame time at most, so a slow frame delays the next instead
    /// of skipping it.
    pub fn advance_playback(&mut self, timeline: &Timeline, looping: bool, every_frame: bool) -> Repaint {
        if !self.playing {
            return Repaint::No;
        }
        let (started_at, started_frame) = *self.play_started.get_or_insert((Instant::now(), self.frame));
        let start = f64::from(timeline.start);
        let end = f64::from(timeline.end);
        let length = end - start + 1.0;
        if every_frame {
            let frame_secs = 1.0 / timeline.fps;
            let waited = started_at.elapsed().as_secs_f64();
            if waited < frame_secs {
                return Repaint::After(Duration::from_secs_f64(frame_secs - waited));
            }
            let next = started_frame.round() + 1.0;
            if next > end && !looping {
                self.stop_at(end);
                return Repaint::No;
            }
            self.frame = if next > end { start } else { next };
            self.play_started = Some((Instant::now(), self.frame));
            return Repaint::Now;
        }
        let played = started_at.elapsed().as_secs_f64() * timeline.fps;
        let offset = started_frame - start + played;
        if !looping && offset >= length - 1.0 {
            self.stop_at(end);
            return Repaint::No;
        }
        self.frame = start + offset.rem_euclid(length).floor();
        Repaint::Now
    }

    fn stop_at(&mut self, frame: f64) {
        self.frame = frame;
        self.playing = false;
    }

    /// Auto key on the timeline.
    pub fn toggle_auto_key(&mut self) {
        self.auto_key = !self.auto_key;
    }

    /// A click or box on pins (viewport or grid editor): `how` says what
    /// happens to the selection ([`selection::pick`]).
    pub fn pick_pins(&mut self, points: &[(u32, u32)], how: Pick) {
        selection::pick(&mut self.selection, points, how);
    }

    /// A click on no pin ([`selection::click_on_nothing`]).
    pub fn click_on_nothing(&mut self, how: Pick) {
        selection::click_on_nothing(&mut self.selection, how);
    }

    /// A pin was just made at `point` by a click with `how`'s modifiers
    /// ([`selection::after_pinning`]).
    pub fn pinned(&mut self, point: (u32, u32), how: Pick) {
        selection::after_pinning(&mut self.selection, point, how);
    }

    /// Exactly these pins are selected (a paste, a script).
    pub fn select_only(&mut self, pins: &[(u32, u32)]) {
        self.selection = pins.to_vec();
    }

    /// The pin at `point` is gone from the key being edited.
    pub fn unpinned(&mut self, point: (u32, u32)) {
        self.selection.retain(|p| *p != point);
    }

    /// After an edit: only pins the key being edited has stay selected.
    pub fn keep_selected_among(&mut self, pins: &[Pin]) {
        self.selection.retain(|s| pins.iter().any(|p| p.grid == *s));
    }

    /// A click on a key's dot on the timeline: that key is selected, no pins.
    pub fn select_key(&mut self, index: usize) {
        self.selected_key = Some(index);
        self.selection.clear();
    }

    /// A key was made or kept at `index` (added, duplicated): it is selected, the pins stay.
    pub fn key_made(&mut self, index: usize) {
        self.selected_key = Some(index);
    }

    /// A click on the timeline away from keys, or the selected key deleted.
    pub fn let_go_of_key(&mut self) {
        self.selected_key = None;
    }

    /// A click on a collider in the viewport: no pins or key stay selected.
    pub fn let_go_of_pins_and_key(&mut self) {
        self.selection.clear();
        self.selected_key = None;
    }

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

    /// The selected collider was removed: none is selected. Which it was.
    pub fn take_selected_collider(&mut self) -> Option<usize> {
        self.selected_collider.take()
    }

    /// Collider `index` was removed: the selection stays on the same collider, or none.
    pub fn collider_removed(&mut self, index: usize) {
        self.selected_collider = match self.selected_collider {
            Some(s) if s == index => None,
            Some(s) if s > index => Some(s - 1),
            other => other,
        };
    }

    /// A layer was removed: none is selected or solo.
    pub fn layer_removed(&mut self) {
        self.selected_layer = None;
        self.solo_layer = None;
    }

    /// The S button: layer `index` alone, or (`None`) all layers again.
    pub fn solo(&mut self, index: Option<usize>) {
        self.solo_layer = index;
    }

    /// A layer was dragged from `from` to `to`: the selected and solo layers
    /// stay the same layers at their new places.
    pub fn layer_moved(&mut self, from: usize, to: usize) {
        self.selected_layer = self.selected_layer.map(|i| index_after_move(i, from, to));
        self.solo_layer = self.solo_layer.map(|i| index_after_move(i, from, to));
    }

    /// The mouse is over cloth point `point` in the viewport (or over none).
    pub fn hover(&mut self, point: Option<(u32, u32)>) {
        self.hovered = point;
    }

    /// The mouse is over grid point `point` in the grid editor (or over none).
    pub fn hover_grid(&mut self, point: Option<(u32, u32)>) {
        self.grid_hovered = point;
    }

    /// Follow on or off (the view bar, or a newly framed scene that travels).
    pub fn set_follow(&mut self, follow: bool) {
        self.follow = follow;
    }

    /// Look through the shot camera, or leave it (orbiting, F, a scene without one).
    pub fn look_through_camera(&mut self, through: bool) {
        self.through_camera = through;
    }

    /// Copy pin positions: these are what Paste puts on a key.
    pub fn copy_pins(&mut self, pins: Vec<Pin>) {
        self.copied_pins = pins;
    }

    /// Attach by clicking begins for the pin at `grid`.
    pub fn start_attaching(&mut self, grid: (u32, u32)) {
        self.attaching = Some(grid);
    }

    /// Attach by clicking ends (attached, cancelled, or its pin gone).
    pub fn stop_attaching(&mut self) {
        self.attaching = None;
    }
}

/// Where the item at `index` is after the item at `from` moves to `to`.
pub fn index_after_move(index: usize, from: usize, to: usize) -> usize {
    if index == from {
        to
    } else if from < index && index <= to {
        index - 1
    } else if to <= index && index < from {
        index + 1
    } else {
        index
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
        assert_eq!((session.selected_layer(), session.selected_collider()), (None, Some(0)));
        session.select_layer(Some(2));
        assert_eq!((session.selected_layer(), session.selected_collider()), (Some(2), None));
        // Letting go of one keeps the other.
        session.select_collider(None);
        assert_eq!(session.selected_layer(), Some(2));
    }
}
