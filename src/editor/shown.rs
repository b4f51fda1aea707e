//! What the viewport draws: the latest version of the document whose rest
//! shapes are all relaxed, the mesh at the playhead and the onion-skin ghosts.
//!
//! Edits go to the document at once; their relaxation runs on the
//! [`Shaper`]'s worker and the shown scene catches up when it is done, so the
//! UI never waits for a relaxation and the last good shape stays on screen.

use std::borrow::Cow;
use std::sync::{Arc, OnceLock};
use std::time::{Duration, Instant};

use eframe::egui;

use super::document::Document;
use super::shaper::{Shaper, ShaperStatus};
use crate::animate::detours::SegmentAsk;
use crate::animate::{self, Evaluator};
use crate::mesh::Mesh;
use crate::picture::{SceneOverlays, key_overlay, scene_bounds};
use crate::render::overlay::PinState;
use crate::render::{Ghost, Overlay};
use crate::scene::{Cloth, Key, Scene};
use crate::shape::rest_shape::RestShape;
use crate::world::Obstacle;

/// A key and the colliders at its frame: what its rest shape is built from.
type KeyAmong = (Key, Vec<Obstacle>);

/// Onion skin: ghosts of the `frames` frames before and after the playhead, `spacing` frames apart.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OnionSkin {
    pub frames: u32,
    pub spacing: u32,
}

pub struct Shown {
    /// The latest version of the document whose rest shapes are all relaxed.
    scene: Scene,
    evaluator: Evaluator,
    shaper: Shaper,
    /// The context the worker wakes when a shape is ready (set on the first frame).
    repaint_context: Arc<OnceLock<egui::Context>>,
    /// The shapes last asked of the worker, so a request is made once per change.
    requested: Option<(Cloth, Vec<KeyAmong>)>,
    /// Shapes were asked for a document other than the scene on screen,
    /// and the worker may still be relaxing them.
    asked_elsewhere: bool,
    /// Versions of the document asked of the worker during a drag and not
    /// shown yet: the oldest (likely the one being solved) and the newest.
    /// Each is shown as soon as its shapes are in, so a drag shows the cloth
    /// catching up while it goes on.
    asked_during_drag: Vec<Scene>,
    /// The cloth at the playhead, in the stage shown.
    mesh: Arc<Mesh>,
    /// What `mesh` shows: (frame, stage, solo layer); `None` when it must be rebuilt.
    mesh_of: Option<(f64, animate::Stage, Option<usize>)>,
    ghosts: Arc<Vec<Ghost<Arc<Mesh>>>>,
    ghosts_of: Option<GhostsOf>,
    /// Counts changes of `scene`.
    version: u64,
    /// Frame the cloth (and move the ground under it) once a newly opened scene is relaxed.
    frame_when_shown: bool,
    /// Whether `scene`'s rest shapes are in. Not yet for the scene the window
    /// opens with: its shapes come from the worker like any other's, and the
    /// cloth meanwhile is drawn where each key's solve starts (greyed).
    shaped: bool,
    /// The bounds of a newly opened scene just shown, until the viewport takes them.
    opened_bounds: Option<(glam::Vec3, glam::Vec3)>,
    /// The shown version whose shapes the worker was last asked to count crossings of.
    crossings_asked: Option<u64>,
    /// The segments whose paths the worker was last asked to work out.
    paths_asked: Vec<SegmentAsk>,
}

/// What the onion-skin ghosts were made for.
#[derive(Clone, Copy, Debug, PartialEq)]
struct GhostsOf {
    frame: f64,
    onion: OnionSkin,
    version: u64,
    solo: Option<usize>,
}

impl Shown {
    /// Shows `scene` once the worker has its rest shapes, where each key's
    /// solve starts until then ([`Shown::is_shaped`]), and frames it then.
    pub fn new(scene: Scene) -> Shown {
        let repaint_context: Arc<OnceLock<egui::Context>> = Arc::default();
        let wake = repaint_context.clone();
        let shaper = Shaper::new(move || {
            if let Some(ctx) = wake.get() {
                ctx.request_repaint();
            }
        });
        Shown {
            scene,
            evaluator: Evaluator::new(),
            shaper,
            repaint_context,
            requested: None,
            asked_elsewhere: false,
            asked_during_drag: Vec::new(),
            mesh: Arc::default(),
            mesh_of: None,
            ghosts: Arc::default(),
            ghosts_of: None,
            version: 0,
            frame_when_shown: true,
            shaped: false,
            opened_bounds: None,
            crossings_asked: None,
            paths_asked: Vec::new(),
        }
    }

    /// The scene on screen.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// Whether the scene on screen has its rest shapes; not yet while the
    /// scene the window opened with is being solved.
    pub fn is_shaped(&self) -> bool {
        self.shaped
    }

    /// The cloth on screen at the playhead, in the stage shown.
    pub fn mesh(&self) -> &Arc<Mesh> {
        &self.mesh
    }

    /// The onion-skin ghosts on screen.
    pub fn ghosts(&self) -> &Arc<Vec<Ghost<Arc<Mesh>>>> {
        &self.ghosts
    }

    /// A newly opened scene: once its shapes are shown, the viewport frames
    /// it ([`Shown::take_opened_bounds`]).
    pub fn frame_once_shown(&mut self) {
        self.frame_when_shown = true;
    }

    /// `scene` at `frame` with the rest shapes shown (a key added from the pose on screen).
    pub fn evaluate_frame(&mut self, scene: &Scene, frame: f64) -> Mesh {
        self.evaluator.evaluate_frame(scene, frame)
    }

    /// The overlays `show` asks for on the cloth on screen, for the key in
    /// effect at `frame`, each pin as `pin_state` says.
    pub fn key_overlay(
        &mut self,
        frame: f64,
        show: SceneOverlays,
        pin_state: impl Fn((u32, u32)) -> PinState,
    ) -> Overlay {
        // Catenaries and triangulation are the shape's: none before it is in.
        let show = if self.shaped { show } else { SceneOverlays { catenaries: false, triangulation: false, ..show } };
        key_overlay(&mut self.evaluator, &self.scene, frame, &self.mesh, show, pin_state)
    }

    /// An evaluator for a job on another thread (an export), holding the
    /// rest shapes shown, so keys already relaxed on screen are not relaxed again.
    pub fn job_evaluator(&self) -> Evaluator {
        Evaluator::with_cache(self.evaluator.cache().clone())
    }

    /// The bounding box of the shown scene's keys (min, max), metres.
    pub fn bounds(&mut self) -> (glam::Vec3, glam::Vec3) {
        if !self.shaped {
            return first_guesses_bounds(&self.scene);
        }
        scene_bounds(&mut self.evaluator, &self.scene)
    }

    /// Counts the versions of the document shown (each with all its rest shapes relaxed).
    pub fn version(&self) -> u64 {
        self.version
    }

    /// Whether the shown scene's cloth travels much farther than its size
    /// ([`crate::picture::framing::travels`]): views without a saved camera follow it.
    pub fn travels(&mut self) -> bool {
        self.shaped && crate::picture::framing::travels(&mut self.evaluator, &self.scene)
    }

    /// Remembers the window's context, so the worker can wake it.
    pub fn set_context(&self, ctx: &egui::Context) {
        let _ = self.repaint_context.set(ctx.clone());
    }

    /// The window's context once the first frame has run.
    pub fn context(&self) -> Option<egui::Context> {
        self.repaint_context.get().cloned()
    }

    /// Forgets the last request, so the next sync asks the worker again (an undo, a finished gesture).
    pub fn forget_requests(&mut self) {
        self.requested = None;
    }

    /// Stops relaxing what was asked last (the document went back to the
    /// scene on screen); the next sync asks afresh for whatever is missing.
    pub fn stop_relaxing(&mut self) {
        self.shaper.cancel();
        self.requested = None;
        self.asked_elsewhere = false;
    }

    /// A new document: nothing asked of the worker, the mesh rebuilt.
    pub fn forget_document(&mut self) {
        self.requested = None;
        self.asked_during_drag.clear();
        self.mesh_of = None;
    }

    /// What the worker is relaxing, for the status bar.
    pub fn relax_status(&self) -> Option<ShaperStatus> {
        self.shaper.status()
    }

    /// Whether a relaxation of `doc`'s shapes is pending or running.
    pub fn is_relaxing(&self, doc: &Document) -> bool {
        self.shaper.is_busy() || *doc.scene() != self.scene || !self.shaped
    }

    /// The bounds (min, max) of a newly opened scene that has just been shown,
    /// once: the viewport frames it and puts the ground under it.
    pub fn take_opened_bounds(&mut self) -> Option<(glam::Vec3, glam::Vec3)> {
        self.opened_bounds.take()
    }

    /// Takes finished shapes from the worker and asks it for the ones `doc` still lacks.
    pub fn sync(&mut self, doc: &Document) {
        let built = self.shaper.take_built();
        let paths = self.shaper.take_paths();
        let arrived = !built.is_empty() || !paths.is_empty();
        for built in built {
            self.evaluator.cache_mut().insert(&built.cloth, &built.key, &built.obstacles, built.shape);
        }
        for (segment, paths) in paths {
            self.evaluator.insert_paths(segment, paths);
        }
        let scene = doc.scene();
        if *scene == self.scene && self.shaped {
            self.asked_during_drag.clear();
            if std::mem::take(&mut self.asked_elsewhere) {
                // The document came back to the scene on screen (a redo after
                // an undo): what was asked since is stale.
                self.shaper.cancel();
                self.requested = None;
                self.crossings_asked = None;
            }
            self.count_crossings();
            return;
        }
        let missing = self.missing_shapes(scene);
        if missing.is_empty() {
            // The in-betweens' paths round the colliders come from the worker
            // too, so no frame drawn waits for them: the scene on screen stays
            // until they are in.
            let segments = self.evaluator.missing_paths(scene);
            if !segments.is_empty() {
                if arrived {
                    self.show_caught_up();
                }
                let asked_before = segments.len() == self.paths_asked.len()
                    && segments.iter().zip(&self.paths_asked).all(|(a, b)| a.same(b));
                if !asked_before && self.shaper.work_out_paths(&scene.cloth, segments.clone()) {
                    self.paths_asked = segments;
                    self.asked_elsewhere = true;
                }
                return;
            }
            self.asked_during_drag.clear();
            self.asked_elsewhere = false;
            self.scene = scene.clone();
            self.shaped = true;
            self.version += 1;
            self.mesh_of = None;
            self.requested = None;
            if std::mem::take(&mut self.frame_when_shown) {
                self.opened_bounds = Some(self.bounds());
            }
            // Now, not at the next frame: whoever waits for the worker to be idle
            // (`wait_for`) then waits for the count too.
            self.count_crossings();
            return;
        }
        if arrived {
            self.show_caught_up();
        }
        // What the running request still has to deliver needs no new one:
        // asking again would restart the key being relaxed and its count.
        let still_coming = self
            .requested
            .as_ref()
            .is_some_and(|(cloth, asked)| *cloth == scene.cloth && missing.iter().all(|key| asked.contains(key)));
        let request = (scene.cloth.clone(), missing);
        if !still_coming {
            // The moves of a drag in progress do not cancel each other; anything else does.
            let supersede = !doc.in_gesture();
            self.shaper.request(&request.0, request.1.clone(), supersede);
            self.requested = Some(request);
            self.asked_elsewhere = true;
            if supersede {
                self.asked_during_drag.clear();
            } else {
                // The pending request replaces the one before it, which will never run.
                if self.asked_during_drag.len() > 1 {
                    self.asked_during_drag.pop();
                }
                self.asked_during_drag.push(scene.clone());
            }
        }
    }

    /// The keys of `scene` whose shapes are not in the cache, each among its colliders.
    fn missing_shapes(&self, scene: &Scene) -> Vec<KeyAmong> {
        let cache = self.evaluator.cache();
        scene
            .keys
            .iter()
            .map(|k| (animate::attachments::posed_key(scene, k), self.evaluator.key_obstacles(scene, k)))
            .filter(|(k, among)| cache.get(&scene.cloth, k, among).is_none())
            .map(|(k, among)| (k.into_owned(), among))
            .collect()
    }

    /// Shows the newest version asked during the drag whose shapes are all
    /// in: the document as it was a moment ago, nearer than what is shown.
    fn show_caught_up(&mut self) {
        let Some(index) = (0..self.asked_during_drag.len()).rev().find(|&i| {
            let asked = &self.asked_during_drag[i];
            self.missing_shapes(asked).is_empty() && self.evaluator.missing_paths(asked).is_empty()
        }) else {
            return;
        };
        let caught_up = self.asked_during_drag.drain(..=index).next_back();
        let Some(scene) = caught_up else { return };
        self.scene = scene;
        self.shaped = true;
        self.version += 1;
        self.mesh_of = None;
    }

    /// Once per shown version: asks the worker to count the self-crossings of
    /// the shown keys' shapes that are not counted yet (those relaxed here,
    /// when a scene is opened, or during a drag), for the Cloth panel. Queued
    /// behind a running job, so whoever then waits for the worker to be idle
    /// waits for the count too; a newer request replaces it.
    fn count_crossings(&mut self) {
        if self.crossings_asked == Some(self.version) {
            return;
        }
        self.crossings_asked = Some(self.version);
        let cache = self.evaluator.cache();
        let uncounted: Vec<_> = self
            .scene
            .keys
            .iter()
            .filter_map(|k| {
                cache.get(
                    &self.scene.cloth,
                    &animate::attachments::posed_key(&self.scene, k),
                    &self.evaluator.key_obstacles(&self.scene, k),
                )
            })
            .filter(|shape| shape.self_crossings_if_counted().is_none())
            .collect();
        if !uncounted.is_empty() {
            self.shaper.count_crossings(&self.scene.cloth, uncounted);
        }
    }

    /// Makes `mesh` the shown scene at `frame` in `stage`, with only layer `solo` on if given.
    pub fn refresh_mesh(&mut self, frame: f64, stage: animate::Stage, solo: Option<usize>) {
        if self.mesh_of == Some((frame, stage, solo)) {
            return;
        }
        let shown = soloed(&self.scene, solo);
        // The last frame's paint callback has let go of the mesh by now, so this rarely copies.
        let mesh = Arc::make_mut(&mut self.mesh);
        if self.shaped {
            self.evaluator.stage_mesh_into(&shown, frame, stage, Default::default(), mesh);
        } else {
            let cloth = &self.scene.cloth;
            let key = animate::attachments::posed_key(&self.scene, self.scene.key_in_effect(frame));
            *mesh = Mesh::from_grid(cloth.cols(), cloth.rows(), &RestShape::first_guess(cloth, &key));
        }
        self.mesh_of = Some((frame, stage, solo));
    }

    /// Onion-skin ghosts around `frame` (none when `onion` is `None`): earlier
    /// frames tinted blue, later ones orange, fainter further away; none
    /// outside the timeline.
    pub fn refresh_ghosts(&mut self, frame: f64, onion: Option<OnionSkin>, solo: Option<usize>) {
        let Some(onion) = onion.filter(|_| self.shaped) else {
            self.ghosts = Arc::default();
            self.ghosts_of = None;
            return;
        };
        let wanted = GhostsOf { frame, onion, version: self.version, solo };
        if self.ghosts_of == Some(wanted) {
            return;
        }
        let timeline = self.scene.timeline.clone();
        let shown = soloed(&self.scene, solo).into_owned();
        let mut ghosts = Vec::new();
        for step in 1..=onion.frames {
            let offset = f64::from(step * onion.spacing.max(1));
            let opacity = 0.45 / step as f32;
            for (at, tint) in [(frame - offset, [0.35, 0.55, 1.0]), (frame + offset, [1.0, 0.6, 0.3])] {
                if at < f64::from(timeline.start) || at > f64::from(timeline.end) {
                    continue;
                }
                let mesh = self.evaluator.evaluate_frame(&shown, at);
                ghosts.push(Ghost { mesh: Arc::new(mesh), tint, opacity });
            }
        }
        self.ghosts = Arc::new(ghosts);
        self.ghosts_of = Some(wanted);
    }

    /// The shape of the shown key in effect at `frame`, once relaxed: its
    /// relaxation report, and its self-crossings once the worker has counted them.
    pub fn key_shape(&self, frame: f64) -> Option<Arc<animate::KeyShape>> {
        let key = self.scene.key_in_effect(frame);
        let posed = animate::attachments::posed_key(&self.scene, key);
        self.evaluator.cache().get(&self.scene.cloth, &posed, &self.evaluator.key_obstacles(&self.scene, key))
    }

    /// Blocks until `doc`'s shapes are relaxed and shown and the worker is idle (tests and scripts).
    pub fn wait_for(&mut self, doc: &Document, timeout: Duration) -> bool {
        let deadline = Instant::now() + timeout;
        loop {
            self.sync(doc);
            if *doc.scene() == self.scene && self.shaped {
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
}

/// The box round where every key's solve starts: the scene's bounds until
/// its rest shapes are in.
fn first_guesses_bounds(scene: &Scene) -> (glam::Vec3, glam::Vec3) {
    let points = scene.keys.iter().flat_map(|key| {
        let key = animate::attachments::posed_key(scene, key);
        RestShape::first_guess(&scene.cloth, &key).into_iter().map(|p| p.as_vec3())
    });
    let points: Vec<glam::Vec3> = points.collect();
    crate::render::camera::bounds(&points).unwrap_or((glam::Vec3::splat(-0.5), glam::Vec3::splat(0.5)))
}

/// `scene` with every layer but `solo` switched off (the scene itself when no layer is soloed).
fn soloed(scene: &Scene, solo: Option<usize>) -> Cow<'_, Scene> {
    let Some(solo) = solo.filter(|s| *s < scene.layers.len()) else { return Cow::Borrowed(scene) };
    let mut alone = scene.clone();
    for (index, layer) in alone.layers.iter_mut().enumerate() {
        *layer.enabled_mut() = index == solo;
    }
    Cow::Owned(alone)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::editor::files::new_scene;

    /// Long enough for any relaxation on a loaded machine: only a bound on waiting, never a measure.
    const WAIT: Duration = Duration::from_secs(600);

    fn lift_pin(doc: &mut Document) {
        doc.edit("Move pin", |s| s.keys[0].pins[0].pos.1 += 0.1).unwrap();
    }

    /// A cloth lying on a table at frame 0 and lifted by its middle at 24:
    /// the in-betweens go round the table's rim.
    fn lifted_off_a_table() -> Scene {
        let text = "(
    version: 1,
    cloth: (size: (1.0, 1.0), grid: (13, 13)),
    timeline: (fps: 24.0, start: 0, end: 48),
    keys: [
        (frame: 0, pins: [], placement: (center: (0.0, 0.8, 0.0))),
        (frame: 24, pins: [(grid: (6, 6), pos: (0.0, 1.3, 0.0))]),
    ],
    colliders: [Box((name: \"table\", center: (0.0, 0.72, 0.0), size: (0.6, 0.04, 0.6)))],
)";
        crate::scene::parse(text, "lifted.ron").unwrap()
    }

    /// After an edit, the worker works out the in-betweens' paths round the
    /// table with the new shapes, and the frames drawn then use them: drawing
    /// a frame works none out (it took 0.4 s on the UI thread for the round
    /// table), and the frames are those of a fresh evaluator.
    #[test]
    fn the_paths_round_a_table_are_worked_out_on_the_worker() {
        let mut doc = Document::new(lifted_off_a_table(), None);
        let mut shown = Shown::new(doc.scene().clone());
        assert!(shown.wait_for(&doc, WAIT));
        doc.edit("Move pin", |s| s.keys[1].pins[0].pos.1 += 0.05).unwrap();
        shown.sync(&doc);
        assert_ne!(shown.scene, *doc.scene(), "the old scene stays on screen while the worker works");
        assert!(shown.wait_for(&doc, WAIT));
        assert_eq!(shown.scene, *doc.scene());
        assert!(shown.evaluator.missing_paths(doc.scene()).is_empty(), "every segment's paths are in");
        let mut fresh = Evaluator::new();
        for key in &doc.scene().keys {
            fresh.key_shape(doc.scene(), key);
        }
        let segments = fresh.missing_paths(doc.scene());
        assert_eq!(segments.len(), 1);
        assert!(!segments[0].paths().detours().is_empty(), "points go round the rim");
        for frame in [6.0, 12.0, 18.0] {
            shown.refresh_mesh(frame, animate::Stage::Animated, None);
            assert_eq!(shown.mesh.positions, fresh.evaluate_frame(doc.scene(), frame).positions, "frame {frame}");
        }
        assert_eq!(shown.evaluator.paths_worked_out(), 0, "no frame drawn worked out a path");
    }

    /// While a drag goes on, each shape the worker finishes is shown at the
    /// next sync, though the document has moved on since. The worker is
    /// waited for explicitly between the moves, so the order of events is
    /// the same on any machine.
    /// A request for several keys runs to its end as their shapes come in:
    /// the keys still coming are not asked again, so the key being relaxed
    /// is not started over and the progress counts on ("key 2 of 3", never
    /// "key 1 of 2").
    #[test]
    fn the_keys_still_coming_are_not_asked_again() {
        let mut doc = Document::new(new_scene(), None);
        let mut shown = Shown::new(doc.scene().clone());
        assert!(shown.wait_for(&doc, WAIT));
        let first = doc.scene().keys[0].clone();
        let keys: Vec<_> = (1..4)
            .map(|n| {
                let mut key = first.clone();
                key.frame = 24 * n;
                for pin in &mut key.pins {
                    pin.pos.1 -= 0.1 * f64::from(n);
                }
                key
            })
            .collect();
        doc.edit("Add keys", |s| s.keys = keys.clone()).unwrap();
        let deadline = Instant::now() + WAIT;
        let mut seen = Vec::new();
        while *doc.scene() != shown.scene && Instant::now() < deadline {
            shown.sync(&doc);
            if let Some(status) = shown.shaper.status()
                && !status.counting
                && status.paths.is_none()
            {
                seen.push((status.keys_done, status.keys_total));
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        eprintln!("SEEN {} {seen:?}", seen.len());
        assert_eq!(shown.scene, *doc.scene(), "shaped");
        assert!(seen.iter().all(|&(_, total)| total == 3), "one request of three keys: {seen:?}");
        assert!(seen.windows(2).all(|w| w[0].0 <= w[1].0), "counted on, never back: {seen:?}");
        assert!(seen.iter().any(|&(done, _)| done == 2), "the third key was seen relaxing: {seen:?}");
    }

    #[test]
    fn a_drag_shows_the_cloth_catching_up_while_it_is_held() {
        let mut doc = Document::new(new_scene(), None);
        let mut shown = Shown::new(doc.scene().clone());
        assert!(shown.wait_for(&doc, WAIT), "the opened scene is relaxed");
        let opened = shown.scene.clone();

        doc.begin_gesture("Move pin");
        lift_pin(&mut doc);
        let first_move = doc.scene().clone();
        shown.sync(&doc);
        assert_eq!(shown.scene, opened, "the first move's shape is not in yet");
        assert!(shown.shaper.wait_idle(WAIT), "the first move's shape is built");

        lift_pin(&mut doc);
        let second_move = doc.scene().clone();
        shown.sync(&doc);
        assert!(doc.in_gesture());
        assert_eq!(shown.scene, first_move, "the cloth catches up with the drag while it is held");
        assert!(shown.is_relaxing(&doc), "and the second move is being shaped");

        assert!(shown.shaper.wait_idle(WAIT));
        lift_pin(&mut doc);
        shown.sync(&doc);
        assert_eq!(shown.scene, second_move, "each move shown as its shape comes in");

        doc.end_gesture();
        assert!(shown.wait_for(&doc, WAIT));
        assert_eq!(shown.scene, *doc.scene(), "where the drag ends is shown once its shape is in");
    }
}
