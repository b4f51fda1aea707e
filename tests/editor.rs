//! The editor driven like a user would: egui_kittest runs the real app with
//! the wgpu renderer (Mesa's llvmpipe or lavapipe; `WGPU_BACKEND` picks), so
//! the 3D viewport is drawn exactly as in the window.
//!
//! Snapshots live in `tests/snapshots/`; `UPDATE_SNAPSHOTS=1` rewrites them.
//! Tolerance: a pixel fails when its YIQ distance exceeds [`PIXEL_THRESHOLD`]
//! (egui's own default); at most [`MAX_FAILED_PIXELS`] of the 792 000 may
//! fail. Measured: snapshots taken on lavapipe differ from llvmpipe's in
//! 335–382 pixels, all on the cloth's silhouette and the pins' rims
//! (anti-aliasing); pinning one point changes 42 000.

use std::path::{Path, PathBuf};
use std::time::Duration;

use drape::editor::DrapeApp;
use drape::editor::files::new_scene;
use drape::editor::files::window_size;
use drape::editor::panels::grid_editor::GridEditor;
use drape::scene::{self, Scene};
use eframe::App as _;
use eframe::egui::accesskit::Role;
use eframe::egui::{self, Event, Key, Modifiers, PointerButton, Pos2};
use egui_kittest::kittest::{NodeT as _, Queryable};
use egui_kittest::{Harness, SnapshotOptions};

const SIZE: egui::Vec2 = egui::vec2(1100.0, 720.0);
const PIXEL_THRESHOLD: f32 = 0.6;
const MAX_FAILED_PIXELS: usize = 1000;
const RELAX_TIMEOUT: Duration = Duration::from_secs(120);

/// Takes snapshot `name`, with the status bar (timings, temporary paths) masked.
fn snapshot(harness: &mut Harness<'_, DrapeApp>, name: &str) {
    let status = harness.state().status_rect();
    harness.mask(status);
    harness.snapshot_options(name, &snapshot_options());
}

fn snapshot_options() -> SnapshotOptions {
    SnapshotOptions::new().threshold(PIXEL_THRESHOLD).max_failed_pixels(MAX_FAILED_PIXELS)
}

/// A scratch folder with the magic carpet copied in, and private config/state folders.
struct Workspace {
    dir: tempfile::TempDir,
}

impl Workspace {
    fn new() -> Workspace {
        let dir = tempfile::tempdir().unwrap();
        std::fs::copy("scenes/magic_carpet.ron", dir.path().join("carpet.ron")).unwrap();
        Workspace { dir }
    }

    fn path(&self, name: &str) -> PathBuf {
        self.dir.path().join(name)
    }
}

fn open_editor(workspace: &Workspace, scene: Scene, path: Option<PathBuf>) -> Harness<'static, DrapeApp> {
    let (config, state) = (workspace.path("config"), workspace.path("state"));
    let mut harness = Harness::builder().with_size(SIZE).wgpu().build_eframe(move |cc| {
        DrapeApp::new(scene, path, cc.wgpu_render_state.as_ref()).with_file_dirs(Some(config), Some(state))
    });
    settle(&mut harness);
    harness
}

/// A scene opened with the window is solved on the worker like any edit:
/// the first frame comes at once and says so, the cloth drawn grey where its
/// solve starts, and the solved cloth follows in colour.
#[test]
fn a_scene_opened_with_the_window_is_solved_on_the_worker() {
    let workspace = Workspace::new();
    let table = scene::load(Path::new("scenes/round_table.ron")).unwrap();
    let opened = table.clone();
    let (config, state) = (workspace.path("config"), workspace.path("state"));
    let mut harness = Harness::builder().with_size(SIZE).wgpu().build_eframe(move |cc| {
        DrapeApp::new(table, None, cc.wgpu_render_state.as_ref()).with_file_dirs(Some(config), Some(state))
    });
    harness.step();
    assert!(harness.state().is_relaxing(), "the keys are being solved after the first frame");
    assert!(harness.state().cloth_drawn_stale(), "the cloth is drawn grey meanwhile");
    assert!(harness.query_by_label_contains("opening: the grey cloth").is_some(), "and the status bar says why");
    settle(&mut harness);
    assert_eq!(harness.state().shown_scene(), &opened);
    assert!(!harness.state().is_relaxing());
    assert!(!harness.state().cloth_drawn_stale(), "the solved cloth in colour");
    assert!(harness.query_by_label_contains("opening: the grey cloth").is_none());
}

/// The editor on the workspace's copy of the bundled carpet, opened from
/// its file, in the orbiting view: the *Camera* toggle turned off (the
/// carpet opens looking through its shot camera).
fn open_carpet(workspace: &Workspace) -> Harness<'static, DrapeApp> {
    let carpet = workspace.path("carpet.ron");
    let mut harness = open_editor(workspace, scene::load(&carpet).unwrap(), Some(carpet));
    leave_shot_camera(&mut harness);
    harness
}

/// Turns the *Camera* toggle off when the viewport looks through the shot
/// camera: the orbiting view, framing the cloth, as a scene without one opens.
fn leave_shot_camera(harness: &mut Harness<'_, DrapeApp>) {
    if harness.state().looks_through_shot_camera() {
        harness.get_by_role_and_label(Role::Button, "Camera").click();
        harness.run_ok();
    }
}

/// Lets the worker finish relaxing and the UI draw the result. Between
/// settles, frames run with `run_ok`: while a relaxation runs the status
/// bar's spinner keeps asking for frames, as it should.
fn settle(harness: &mut Harness<'_, DrapeApp>) {
    for _ in 0..3 {
        assert!(harness.state_mut().wait_for_shapes(RELAX_TIMEOUT), "relaxation finished");
        harness.run();
    }
}

/// A click at `pos` with `modifiers` held from before the press until after the release.
fn click_at(harness: &mut Harness<'_, DrapeApp>, pos: Pos2, modifiers: Modifiers) {
    harness.event(Event::ModifiersChanged(modifiers));
    harness.event(Event::PointerMoved(pos));
    harness.run_ok();
    for pressed in [true, false] {
        harness.event(Event::PointerButton { pos, button: PointerButton::Primary, pressed, modifiers });
        harness.run_ok();
    }
    harness.event(Event::ModifiersChanged(Modifiers::NONE));
    harness.run_ok();
}

/// Presses at `from`, moves to `to` in a few steps, releases: a drag as a hand makes it.
fn drag(harness: &mut Harness<'_, DrapeApp>, from: Pos2, to: Pos2) {
    drag_holding(harness, from, to, Modifiers::NONE);
}

/// A drag with `modifiers` held throughout.
fn drag_holding(harness: &mut Harness<'_, DrapeApp>, from: Pos2, to: Pos2, modifiers: Modifiers) {
    harness.event(Event::ModifiersChanged(modifiers));
    harness.event(Event::PointerMoved(from));
    harness.run_ok();
    let press = |pressed, pos| Event::PointerButton { pos, button: PointerButton::Primary, pressed, modifiers };
    harness.event(press(true, from));
    harness.run_ok();
    for step in 1..=6 {
        harness.event(Event::PointerMoved(from.lerp(to, step as f32 / 6.0)));
        harness.run_ok();
    }
    harness.event(press(false, to));
    harness.run_ok();
    harness.event(Event::ModifiersChanged(Modifiers::NONE));
    harness.run_ok();
}

/// Puts `events` into one frame, as a fast typist on a slow display does,
/// and runs frames the way eframe does: each frame's input passes through
/// the app's `raw_input_hook` before egui sees it (kittest does not call it).
fn in_one_frame(harness: &mut Harness<'_, DrapeApp>, events: Vec<Event>) {
    harness.input_mut().events.extend(events);
    for _ in 0..8 {
        let ctx = harness.ctx.clone();
        let mut raw = std::mem::take(harness.input_mut());
        harness.state_mut().raw_input_hook(&ctx, &mut raw);
        *harness.input_mut() = raw;
        harness.step();
    }
    harness.run_ok();
}

fn key_event(key: Key) -> Event {
    Event::Key { key, physical_key: None, pressed: true, repeat: false, modifiers: Modifiers::NONE }
}

/// The grid editor's rect once scrolled into view, as a user scrolls the Cloth panel to it.
fn grid_editor_rect(harness: &mut Harness<'_, DrapeApp>) -> egui::Rect {
    harness.get_by_label("Grid editor").scroll_to_me();
    harness.run_ok();
    harness.get_by_label("Grid editor").rect()
}

fn pin_pos(scene: &Scene, key: usize, grid: (u32, u32)) -> (f64, f64, f64) {
    scene.keys[key].pins.iter().find(|p| p.grid == grid).map(|p| p.pos).expect("pinned")
}

fn open_through_the_menu(harness: &mut Harness<'_, DrapeApp>, path: &Path) {
    harness.get_by_label("File").click();
    harness.run_ok();
    harness.get_by_label_contains("Open…").click();
    harness.run_ok();
    pick_in_file_dialog(harness, path);
    settle(harness);
}

/// Types `path` into the open file dialog's name field and presses Enter.
fn pick_in_file_dialog(harness: &mut Harness<'_, DrapeApp>, path: &Path) {
    let field = harness.get_by_label("File name");
    field.focus();
    field.type_text(&path.display().to_string());
    harness.run_ok();
    harness.key_press(Key::Enter);
    harness.run_ok();
}

#[test]
fn model_undo_save_and_reopen() {
    let workspace = Workspace::new();
    let carpet = workspace.path("carpet.ron");
    let mut harness = open_editor(&workspace, new_scene(), None);

    // Open a scene with File ▸ Open.
    open_through_the_menu(&mut harness, &carpet);
    leave_shot_camera(&mut harness);
    let opened = scene::load(&carpet).unwrap();
    assert_eq!(harness.state().scene(), &opened);
    assert_eq!(harness.state().document().path(), Some(carpet.as_path()));
    assert!(harness.state().title().starts_with("carpet.ron — "), "{}", harness.state().title());
    snapshot(&mut harness, "editor_opened");

    // Pin the middle of the cloth in the grid editor: it is pinned where the cloth hangs.
    let grid_rect = grid_editor_rect(&mut harness);
    let middle = (10, 16);
    let cols = opened.cloth.cols();
    let hanging = harness.state().mesh().positions[middle.1 as usize * cols + middle.0 as usize];
    click_at(&mut harness, GridEditor::point_in(grid_rect, &opened.cloth, middle), Modifiers::NONE);
    let pinned = pin_pos(harness.state().scene(), 0, middle);
    assert_eq!(pinned, (hanging.x as f64, hanging.y as f64, hanging.z as f64));
    assert!(harness.state().selection().is_empty(), "a new pin is not left selected");
    assert!(harness.state().title().contains('*'), "the title marks unsaved work");
    settle(&mut harness);
    snapshot(&mut harness, "editor_pinned");

    // Drag a corner pin up in the viewport: it moves, nothing else does, one undo step.
    let corner = (0, 0);
    let before = harness.state().scene().clone();
    let start = pin_pos(&before, 0, corner);
    let on_screen =
        harness.state().screen_pos(glam::Vec3::new(start.0 as f32, start.1 as f32, start.2 as f32)).unwrap();
    drag(&mut harness, on_screen, on_screen - egui::vec2(0.0, 80.0));
    let moved = pin_pos(harness.state().scene(), 0, corner);
    assert!(moved.1 > start.1 + 0.05, "the pin went up: {start:?} → {moved:?}");
    for pin in &before.keys[0].pins {
        if pin.grid != corner {
            assert_eq!(pin_pos(harness.state().scene(), 0, pin.grid), pin.pos);
        }
    }
    assert_eq!(harness.state().document().undo_label(), Some("Move pin"));
    settle(&mut harness);
    let after_drag = harness.state().scene().clone();

    // Change the fabric's elasticity.
    harness.get_by_role_and_label(Role::Slider, "Elasticity").set_value_accesskit(1.3);
    harness.run_ok();
    assert_eq!(harness.state().scene().keys[0].elasticity, 1.3);
    settle(&mut harness);
    assert_eq!(harness.state().shown_scene(), harness.state().scene(), "the new shape is on screen");
    snapshot(&mut harness, "editor_edited");
    let edited = harness.state().scene().clone();

    // Undo twice (elasticity, then the drag as one step), redo both.
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.run_ok();
    assert_eq!(harness.state().scene(), &after_drag);
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.run_ok();
    assert_eq!(pin_pos(harness.state().scene(), 0, corner), start, "one undo takes the whole drag back");
    harness.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::Z);
    harness.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::Z);
    harness.run_ok();
    assert_eq!(harness.state().scene(), &edited);
    settle(&mut harness);

    // Save (Ctrl+S writes the scene's own file) and read it back.
    harness.key_press_modifiers(Modifiers::COMMAND, Key::S);
    harness.run_ok();
    assert!(!harness.state().document().is_dirty());
    assert!(!harness.state().title().contains('*'));
    let saved = scene::load(&carpet).unwrap();
    assert_eq!(&saved, harness.state().scene());
    let mut without_view = saved.clone();
    without_view.view = None;
    let mut expected = edited.clone();
    expected.view = None;
    assert_eq!(without_view, expected, "the file holds the edits");

    // Reopen it in a fresh editor: the same scene, the same camera.
    let camera = *harness.state().camera();
    let reopened = open_editor(&workspace, saved.clone(), Some(carpet.clone()));
    assert_eq!(reopened.state().scene(), &saved);
    let view = reopened.state().camera().to_view();
    assert!((view.yaw_deg - camera.to_view().yaw_deg).abs() < 1e-9);
}

#[test]
fn a_scene_that_fails_to_load_leaves_the_work_alone() {
    let workspace = Workspace::new();
    let mut harness = open_editor(&workspace, new_scene(), None);
    harness.get_by_role_and_label(Role::Slider, "Elasticity").set_value_accesskit(1.5);
    harness.run_ok();
    settle(&mut harness);
    let work = harness.state().scene().clone();
    let broken = workspace.path("broken.ron");
    std::fs::write(&broken, "(version: 1, cloth: (size: (1.0, 1.0), grid: (4, 4)),\n keys: [(frame: 0, pins: [])])")
        .unwrap();
    // Unsaved work: the editor asks first; "Don't Save" goes on to the dialog.
    harness.key_press_modifiers(Modifiers::COMMAND, Key::O);
    harness.run_ok();
    harness.get_by_label("Don't Save").click();
    harness.run_ok();
    pick_in_file_dialog(&mut harness, &broken);
    assert!(harness.query_by_label_contains("broken.ron:2:").is_some(), "the error names the file and line");
    assert_eq!(harness.state().scene(), &work);
    assert!(harness.state().document().is_dirty());
    harness.get_by_label("OK").click();
    harness.run_ok();
    assert!(harness.query_by_label_contains("broken.ron:2:").is_none());
}

/// A cloth whose folds cannot be kept apart (four pins far out of line)
/// keeps its drape through itself: with a thickness to keep, the Cloth
/// panel calls it not settled rather than settled.
#[test]
fn the_cloth_panel_says_a_shape_through_itself_is_not_settled() {
    let workspace = Workspace::new();
    let text = "(version: 1, cloth: (size: (1.0, 1.0), grid: (33, 33)), keys: [(frame: 0, elasticity: 1.05, \
                stiffness: 0.2, pins: [(grid: (0, 0), pos: (-0.5, 1.5, 0.0)), (grid: (32, 0), pos: (0.5, 1.5, 0.0)), \
                (grid: (0, 32), pos: (-0.5, 1.0, 0.5)), \
                (grid: (32, 32), pos: (0.4994271231268916, 0.45001577848317753, 1.7077784640244735e-6))])])";
    let harness = open_editor(&workspace, scene::parse(text, "crumpled.ron").unwrap(), None);
    let verdict = harness.query_by_label_contains("NOT settled").map(|node| node.accesskit_node().value());
    let Some(Some(line)) = verdict else { panic!("no verdict saying it is not settled") };
    assert_eq!(line, "NOT settled: passes through itself");
    assert!(harness.query_by_label_contains("Settled").is_none(), "nothing calls it settled");
}

/// A curtain gathered to a tenth of its width with no thickness relaxes
/// through itself (`drape check` warns of it): the Cloth panel says so too,
/// once the worker has counted; at the default thickness it folds without
/// crossing and no such warning shows.
#[test]
fn the_cloth_panel_says_when_the_rest_shape_passes_through_itself() {
    let workspace = Workspace::new();
    let gathered = |thickness: &str| {
        let text = format!(
            "(version: 1, cloth: (size: (1.0, 1.0), grid: (17, 17)), keys: [(frame: 0, {thickness} pins: [\
             (grid: (0, 0), pos: (-0.05, 2.0, 0.0)), (grid: (16, 0), pos: (0.05, 2.0, 0.0))])])"
        );
        scene::parse(&text, "gathered.ron").unwrap()
    };
    // With no thickness the gathered folds pass through the cloth: said, with why.
    let harness = open_editor(&workspace, gathered("thickness: 0.0,"), None);
    let warning = harness.query_by_label_contains("Passes through itself").map(|node| node.accesskit_node().value());
    let Some(Some(line)) = warning else { panic!("no warning in the Cloth panel") };
    assert!(line.contains("Settled"), "the verdict stays beside it: {line}");
    drop(harness);
    // At the default thickness they fold without crossing.
    let harness = open_editor(&workspace, gathered(""), None);
    assert!(harness.query_by_label_contains("Passes through itself").is_none());
    assert!(harness.query_by_label_contains("Settled").is_some());
}

#[test]
fn delete_unpins_the_selected_pins_and_the_last_pin_stays() {
    let workspace = Workspace::new();
    let mut harness = open_editor(&workspace, new_scene(), None);
    let grid_rect = grid_editor_rect(&mut harness);
    let cloth = harness.state().scene().cloth.clone();
    // Select both top corners with Shift+click, then Delete: one of them must stay (a key needs a pin).
    click_at(&mut harness, GridEditor::point_in(grid_rect, &cloth, (0, 0)), Modifiers::SHIFT);
    assert_eq!(harness.state().selection(), [(0, 0)]);
    click_at(&mut harness, GridEditor::point_in(grid_rect, &cloth, (32, 0)), Modifiers::SHIFT);
    assert_eq!(harness.state().selection(), [(0, 0), (32, 0)]);
    harness.key_press(Key::Delete);
    harness.run_ok();
    assert_eq!(harness.state().scene().keys[0].pins.len(), 2, "an edit leaving no pin is refused");
    assert!(harness.query_by_label_contains("at least one pin").is_some());
    // One pin selected (Ctrl+click takes the other out): Delete unpins it.
    click_at(&mut harness, GridEditor::point_in(grid_rect, &cloth, (0, 0)), Modifiers::COMMAND);
    assert_eq!(harness.state().selection(), [(32, 0)]);
    harness.key_press(Key::Delete);
    harness.run_ok();
    let pins: Vec<_> = harness.state().scene().keys[0].pins.iter().map(|p| p.grid).collect();
    assert_eq!(pins, [(0, 0)]);
}

#[test]
fn file_export_writes_the_animation_beside_the_scene() {
    let workspace = Workspace::new();
    let carpet = workspace.path("carpet.ron");
    let mut harness = open_editor(&workspace, scene::load(&carpet).unwrap(), Some(carpet.clone()));
    harness.get_by_label("File").click();
    harness.run_ok();
    harness.get_by_label("Export…").click();
    harness.run_ok();
    // The window offers the whole timeline as glTF next to the scene.
    assert!(harness.query_by_label_contains("121 frames").is_some());
    harness.get_by_label("Export").click();
    let glb = workspace.path("carpet.glb");
    let deadline = std::time::Instant::now() + Duration::from_secs(120);
    while harness.query_by_label_contains("Exported 121 frames").is_none() {
        assert!(std::time::Instant::now() < deadline, "the export finished");
        harness.step();
        std::thread::sleep(Duration::from_millis(20));
    }
    let bytes = std::fs::read(&glb).unwrap();
    assert_eq!(&bytes[..4], b"glTF");
    assert!(harness.query_by_label("Export animation").is_none(), "the window closes when done");
}

/// The window manager's close button: a close request for the root viewport.
fn request_close(harness: &mut Harness<'_, DrapeApp>) {
    let root = harness.input_mut().viewports.entry(egui::ViewportId::ROOT).or_default();
    root.events.push(egui::ViewportEvent::Close);
}

/// Whether the last frame sent `command` to the window.
fn sent(harness: &Harness<'_, DrapeApp>, command: &egui::ViewportCommand) -> bool {
    harness.output().viewport_output.get(&egui::ViewportId::ROOT).is_some_and(|v| v.commands.contains(command))
}

#[test]
fn closing_the_window_with_unsaved_work_asks_first() {
    let workspace = Workspace::new();
    let mut harness = open_editor(&workspace, new_scene(), None);
    harness.get_by_role_and_label(Role::Slider, "Elasticity").set_value_accesskit(1.2);
    harness.run_ok();
    settle(&mut harness);

    request_close(&mut harness);
    harness.step();
    assert!(sent(&harness, &egui::ViewportCommand::CancelClose), "the close is held back");
    harness.run_ok();
    assert!(harness.query_by_label("Don't Save").is_some(), "the question is asked");

    // Cancel: the window stays, the work too.
    harness.get_by_label("Cancel").click();
    harness.run_ok();
    assert!(harness.query_by_label("Don't Save").is_none());
    assert!(harness.state().document().is_dirty());

    // Don't Save: the window closes.
    request_close(&mut harness);
    harness.run_ok();
    harness.get_by_label("Don't Save").click();
    harness.step();
    assert!(sent(&harness, &egui::ViewportCommand::Close), "Don't Save closes the window");
}

/// A bundled example opens as a template: Save asks where instead of
/// writing over it, and in the unsaved-changes question Enter is the safe
/// Cancel, neither Save nor Don't Save. A copy saved elsewhere saves in place.
#[test]
fn an_example_opens_as_a_template_and_enter_in_the_question_cancels() {
    let workspace = Workspace::new();
    let examples = workspace.path("examples");
    std::fs::create_dir(&examples).unwrap();
    let table = examples.join("round_table.ron");
    std::fs::copy("scenes/round_table.ron", &table).unwrap();
    let original = std::fs::read(&table).unwrap();
    let (config, state) = (workspace.path("config"), workspace.path("state"));
    let (scene, path) = (scene::load(&table).unwrap(), table.clone());
    let mut harness = Harness::builder().with_size(SIZE).wgpu().build_eframe(move |cc| {
        DrapeApp::new(scene, Some(path), cc.wgpu_render_state.as_ref())
            .with_file_dirs(Some(config), Some(state))
            .with_examples_dir(examples)
    });
    settle(&mut harness);
    harness.state_mut().apply("Elasticity", |s| s.keys[0].elasticity = 1.1);
    harness.run_ok();

    harness.key_press_modifiers(Modifiers::COMMAND, Key::S);
    harness.run_ok();
    assert!(harness.query_by_label("File name").is_some(), "Save asks where");
    assert_eq!(std::fs::read(&table).unwrap(), original, "the example is not written over");
    harness.key_press(Key::Escape);
    harness.run_ok();
    assert!(harness.query_by_label("File name").is_none());

    request_close(&mut harness);
    harness.run_ok();
    assert!(harness.query_by_label("Don't Save").is_some(), "the question is asked");
    harness.key_press(Key::Enter);
    harness.step();
    assert!(!sent(&harness, &egui::ViewportCommand::Close), "Enter is not Don't Save");
    harness.run_ok();
    assert!(harness.query_by_label("Don't Save").is_none(), "answered");
    assert!(harness.query_by_label("File name").is_none(), "Enter is not Save");
    assert!(harness.state().document().is_dirty(), "the work is kept");
    assert_eq!(std::fs::read(&table).unwrap(), original);

    let copy = workspace.path("my_table.ron");
    assert!(harness.state_mut().save_to(&copy));
    harness.state_mut().apply("Elasticity", |s| s.keys[0].elasticity = 1.2);
    harness.key_press_modifiers(Modifiers::COMMAND, Key::S);
    harness.run_ok();
    assert!(harness.query_by_label("File name").is_none(), "a copy of one's own saves in place");
    assert_eq!(scene::load(&copy).unwrap().keys[0].elasticity, 1.2);
    settle(&mut harness);
}

/// The window opens at the size it was left at, fitted to the screen it is
/// on, and keeps the size it is closed at for the next start.
#[test]
fn the_window_fits_the_screen_and_remembers_its_size() {
    use drape::editor::files::window_size::WINDOW_SIZE_NAME;
    let workspace = Workspace::new();
    let saved = workspace.path("config").join(WINDOW_SIZE_NAME);
    std::fs::create_dir_all(saved.parent().unwrap()).unwrap();
    std::fs::write(&saved, "1500 900\n").unwrap();
    let mut harness = open_carpet(&workspace);
    let window = |harness: &mut Harness<'_, DrapeApp>, inner: egui::Vec2| {
        let root = harness.input_mut().viewports.entry(egui::ViewportId::ROOT).or_default();
        root.monitor_size = Some(egui::vec2(1366.0, 768.0));
        root.inner_rect = Some(egui::Rect::from_min_size(Pos2::ZERO, inner));
    };
    window(&mut harness, SIZE);
    harness.step();
    assert!(
        sent(&harness, &egui::ViewportCommand::InnerSize(egui::vec2(1326.0, 688.0))),
        "the saved size, fitted to a 1366 × 768 screen"
    );
    window(&mut harness, egui::vec2(1250.0, 700.0));
    harness.step();
    assert!(
        !harness
            .output()
            .viewport_output
            .get(&egui::ViewportId::ROOT)
            .is_some_and(|v| v.commands.iter().any(|c| matches!(c, egui::ViewportCommand::InnerSize(_))))
    );
    harness.state_mut().on_exit();
    assert_eq!(std::fs::read_to_string(&saved).unwrap(), "1250 700\n", "the size it was left at");
}

/// The grid editor gives a tall cloth room (the cape's 19 × 36 grid), and
/// the strip under it makes it taller; the panel scrolls with it so the pin
/// rows under it stay in view.
#[test]
fn the_grid_editor_is_roomy_and_its_height_is_dragged() {
    let workspace = Workspace::new();
    let mut harness = open_cape(&workspace);
    let before = grid_editor_rect(&mut harness);
    assert!(before.height() >= 220.0, "a tall cloth gets room: {before:?}");
    let strip = harness.get_by_label("Grid editor height").rect().center();
    drag(&mut harness, strip, strip + egui::vec2(0.0, 120.0));
    let after = harness.get_by_label("Grid editor").rect();
    assert!((after.height() - before.height() - 120.0).abs() < 1.0, "{before:?} → {after:?}");
    let panel_bottom = harness.state().status_rect().top();
    for label in ["Grid editor height", "Unpin", "Mirror"] {
        let rect = harness.get_by_label(label).rect();
        assert!(rect.bottom() <= panel_bottom, "{label} at {rect:?} is below the panel's end at {panel_bottom}");
    }
}

/// On a 1600 × 1000 screen the window opens at 1560 × 920: there the cape's
/// grid editor and the pin rows under it are in reach without scrolling the
/// Cloth panel.
#[test]
fn on_a_1000_pixel_screen_the_pins_are_in_reach_without_scrolling() {
    let workspace = Workspace::new();
    let mut harness = open_cape(&workspace);
    let screen = egui::vec2(1600.0, 1000.0);
    harness.set_size(window_size::fitted(window_size::DEFAULT_WINDOW_SIZE, screen));
    harness.run();
    let panel_bottom = harness.state().status_rect().top();
    let grid = harness.get_by_label("Grid editor").rect();
    assert!(grid.height() >= 220.0, "the grid editor keeps its room: {grid:?}");
    for label in ["Grid editor", "Grid editor height", "Unpin", "Mirror"] {
        let rect = harness.get_by_label(label).rect();
        assert!(rect.bottom() <= panel_bottom, "{label} at {rect:?} is below the panel's end at {panel_bottom}");
    }
}

/// A right click at `pos` (opens a context menu).
fn right_click(harness: &mut Harness<'_, DrapeApp>, pos: Pos2) {
    harness.event(Event::PointerMoved(pos));
    harness.run_ok();
    for pressed in [true, false] {
        harness.event(Event::PointerButton {
            pos,
            button: PointerButton::Secondary,
            pressed,
            modifiers: Modifiers::NONE,
        });
        harness.run_ok();
    }
}

/// Height of the timeline's track above the references' band, points: the
/// ruler and the rows of keys.
const TRACK_BODY: f32 = 46.0;

/// Where frame `frame` is on the timeline's track (8 points of margin each
/// side), halfway down the ruler and the keys' rows.
fn timeline_pos(harness: &Harness<'_, DrapeApp>, frame: f64) -> Pos2 {
    let rect = harness.get_by_label("Timeline").rect();
    let timeline = &harness.state().scene().timeline;
    let inner = rect.shrink2(egui::vec2(8.0, 0.0));
    let fraction = (frame - f64::from(timeline.start)) / f64::from(timeline.end - timeline.start);
    Pos2::new(inner.left() + fraction as f32 * inner.width(), rect.top() + TRACK_BODY / 2.0)
}

#[test]
fn the_timeline_scrubs_adds_a_key_and_eases_it() {
    let workspace = Workspace::new();
    let carpet = workspace.path("carpet.ron");
    let mut harness = open_editor(&workspace, scene::load(&carpet).unwrap(), Some(carpet.clone()));
    leave_shot_camera(&mut harness);
    let keys_before = harness.state().scene().keys.clone();

    // Scrub: drag the playhead along the track; the mesh is evaluate at that frame.
    let (from, to) = (timeline_pos(&harness, 10.0), timeline_pos(&harness, 60.0));
    drag(&mut harness, from, to);
    settle(&mut harness);
    assert_eq!(harness.state().frame(), 60.0);
    let scene = harness.state().scene().clone();
    let expected = drape::animate::evaluate(&scene, drape::animate::frame_time_secs(&scene.timeline, 60.0));
    assert_eq!(*harness.state().mesh(), expected);

    // K: a key at frame 60 holding the pose on screen.
    harness.key_press(Key::K);
    harness.run_ok();
    settle(&mut harness);
    let keys = &harness.state().scene().keys;
    assert_eq!(keys.len(), keys_before.len() + 1);
    let added = keys.iter().find(|k| k.frame == 60).expect("a key at frame 60");
    let cols = scene.cloth.cols();
    for pin in &added.pins {
        let p = expected.positions[pin.grid.1 as usize * cols + pin.grid.0 as usize];
        assert_eq!(pin.pos, (f64::from(p.x), f64::from(p.y), f64::from(p.z)));
    }
    // The new key holds the pose: the frame looks the same as before it was added.
    assert_eq!(harness.state().mesh().positions.len(), expected.positions.len());

    // Onion skin: two ghosts each side, four frames apart.
    harness.get_by_label("Onion skin").click();
    harness.run_ok();
    assert_eq!(harness.state().ghost_count(), 4);
    harness.key_press(Key::F);
    harness.run_ok();
    snapshot(&mut harness, "editor_onion");
    harness.get_by_label("Onion skin").click();
    harness.run_ok();
    assert_eq!(harness.state().ghost_count(), 0);

    // Right-click the key: its segment eases linearly now.
    let index = harness.state().scene().keys.iter().position(|k| k.frame == 60).unwrap();
    let diamond = timeline_pos(&harness, 60.0) + egui::vec2(0.0, 8.0);
    right_click(&mut harness, diamond);
    harness.get_by_label("Linear").click();
    harness.run_ok();
    assert_eq!(harness.state().scene().keys[index].ease, drape::scene::Ease::Linear);

    // The menu's number field takes a click and typing (a click inside must not close the menu).
    right_click(&mut harness, diamond);
    let field = harness.get_by_role_and_label(Role::SpinButton, "Re-relax in-betweens").rect().center();
    click_at(&mut harness, field, Modifiers::NONE);
    harness.event(Event::Text("12".into()));
    harness.run_ok();
    harness.key_press(Key::Enter);
    harness.run_ok();
    assert_eq!(harness.state().scene().keys[index].inbetween_relax, 12);
    harness.key_press(Key::Escape);
    harness.run_ok();
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.run_ok();

    // Duplicate the key from its menu: the playhead has a key, so the copy goes to the next free frame.
    right_click(&mut harness, diamond);
    harness.get_by_label("Duplicate key").click();
    harness.run_ok();
    let keys = &harness.state().scene().keys;
    let copy = keys.iter().find(|k| k.frame == 61).expect("a copy at frame 61");
    let original = keys.iter().find(|k| k.frame == 60).unwrap();
    assert_eq!((&copy.pins, copy.elasticity), (&original.pins, original.elasticity));
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.run_ok();

    // Undo twice: no easing change, no key.
    harness.key_press(Key::Escape);
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.run_ok();
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.run_ok();
    assert_eq!(harness.state().scene().keys, keys_before);
}

#[test]
fn a_wave_is_added_keyed_and_reordered() {
    let workspace = Workspace::new();
    let carpet = workspace.path("carpet.ron");
    let mut harness = open_editor(&workspace, scene::load(&carpet).unwrap(), Some(carpet.clone()));
    leave_shot_camera(&mut harness);
    let layers_before = harness.state().scene().layers.len();

    // Add a wave, key its magnitude at frame 0, then raise it at frame 48: a ramp.
    let index = add_keyed_wave(&mut harness);
    assert_eq!(index, layers_before);
    assert_eq!(harness.state().scene().layers.len(), layers_before + 1);
    assert_eq!(harness.state().scene().layers[index].kind(), "Wave");
    let drape::scene::Layer::Wave(wave) = &harness.state().scene().layers[index] else { panic!("a wave") };
    let keys: Vec<_> = match &wave.magnitude {
        drape::scene::Param::Keys(keys) => keys.iter().map(|k| (k.frame, k.value)).collect(),
        other => panic!("keyed, not {other:?}"),
    };
    assert_eq!(keys, [(0, 0.03), (48, 0.2)]);
    // The mesh on screen includes the new layer.
    let scene = harness.state().scene().clone();
    let expected = drape::animate::evaluate(&scene, drape::animate::frame_time_secs(&scene.timeline, 48.0));
    assert_eq!(*harness.state().mesh(), expected);

    harness.key_press(Key::F);
    harness.run_ok();
    snapshot(&mut harness, "editor_wave");

    // Solo: the viewport shows the wave alone; the scene keeps every layer on.
    let solo = format!("Solo {}", scene.layers[index].label(index));
    harness.get_by_label(&solo).click();
    harness.run_ok();
    let mut alone = scene.clone();
    for (i, layer) in alone.layers.iter_mut().enumerate() {
        *layer.enabled_mut() = i == index;
    }
    let expected_alone = drape::animate::evaluate(&alone, drape::animate::frame_time_secs(&alone.timeline, 48.0));
    assert_eq!(*harness.state().mesh(), expected_alone);
    assert_eq!(harness.state().scene(), &scene, "solo is a view, not an edit");
    harness.get_by_label(&solo).click();
    harness.run_ok();
    assert_eq!(*harness.state().mesh(), expected);

    // Move it up one place: the stack order changes, one undo puts it back.
    let label = format!("Move {} up", scene.layers[index].label(index));
    harness.get_by_label(&label).click();
    harness.run_ok();
    assert_eq!(harness.state().scene().layers[index - 1].kind(), "Wave");
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.run_ok();
    assert_eq!(harness.state().scene().layers[index].kind(), "Wave");

    // Drag it by its grip above the first layer: it is applied first now, the others keep their order.
    let grip = |harness: &Harness<'_, DrapeApp>, i: usize| {
        let layer = &harness.state().scene().layers[i];
        harness.get_by_label(&format!("Drag {} to reorder", layer.label(i))).rect().center()
    };
    let (from, top) = (grip(&harness, index), grip(&harness, 0) - egui::vec2(0.0, 8.0));
    drag(&mut harness, from, top);
    let order: Vec<_> = harness.state().scene().layers.iter().map(|l| l.kind()).collect();
    let mut expected_order: Vec<_> = scene.layers.iter().map(|l| l.kind()).collect();
    let moved = expected_order.remove(index);
    expected_order.insert(0, moved);
    assert_eq!(order, expected_order);
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.run_ok();
    assert_eq!(harness.state().scene(), &scene, "one drag, one undo step");

    // The selected wave's keys show on the timeline; drag the one at 48 to 60.
    let dot = |harness: &Harness<'_, DrapeApp>, frame: f64| {
        let rect = harness.get_by_label("Timeline").rect();
        Pos2::new(timeline_pos(harness, frame).x, rect.top() + TRACK_BODY - 6.0 - 3.0 - 6.0 - 5.0)
    };
    let (from, to) = (dot(&harness, 48.0), dot(&harness, 60.0));
    drag(&mut harness, from, to);
    let drape::scene::Layer::Wave(wave) = &harness.state().scene().layers[index] else { panic!("a wave") };
    let frames: Vec<_> = match &wave.magnitude {
        drape::scene::Param::Keys(keys) => keys.iter().map(|k| (k.frame, k.value)).collect(),
        other => panic!("keyed, not {other:?}"),
    };
    assert_eq!(frames, [(0, 0.03), (60, 0.2)]);
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.run_ok();
    assert_eq!(harness.state().scene(), &scene, "one drag, one undo step");
}

#[test]
fn keys_and_layers_survive_save_and_reopen() {
    let workspace = Workspace::new();
    let carpet = workspace.path("carpet.ron");
    let mut harness = open_editor(&workspace, scene::load(&carpet).unwrap(), Some(carpet.clone()));

    // A key at 30 with its own easing, and a wave with a keyed magnitude.
    harness.state_mut().set_frame(30.0);
    harness.run_ok();
    harness.key_press(Key::K);
    harness.run_ok();
    settle(&mut harness);
    assert!(harness.state().scene().keys.iter().any(|k| k.frame == 30), "K keyed frame 30");
    let diamond = timeline_pos(&harness, 30.0) + egui::vec2(0.0, 8.0);
    right_click(&mut harness, diamond);
    harness.get_by_label("Bounce").click();
    harness.run_ok();
    harness.key_press(Key::Escape);
    add_keyed_wave(&mut harness);
    let edited = harness.state().scene().clone();
    assert!(edited.keys.iter().any(|k| k.frame == 30 && k.ease == drape::scene::Ease::Bounce));

    harness.key_press_modifiers(Modifiers::COMMAND, Key::S);
    harness.run_ok();
    assert!(!harness.state().document().is_dirty());
    let saved = scene::load(&carpet).unwrap();
    assert!(saved.view.is_some(), "the camera is saved with the scene");
    assert_eq!(Scene { view: None, ..saved.clone() }, Scene { view: None, ..edited }, "the file holds the edits");

    // A fresh editor opening the file shows the same scene and the same frame-30 mesh.
    let mut reopened = open_editor(&workspace, new_scene(), None);
    open_through_the_menu(&mut reopened, &carpet);
    assert_eq!(reopened.state().scene(), &saved);
    reopened.state_mut().set_frame(30.0);
    settle(&mut reopened);
    harness.state_mut().set_frame(30.0);
    settle(&mut harness);
    assert_eq!(reopened.state().mesh(), harness.state().mesh());
}

#[test]
fn follow_keeps_the_travelling_cloth_where_it_was_on_screen() {
    let workspace = Workspace::new();
    let mut harness = open_carpet(&workspace);
    let centre = |harness: &Harness<'_, DrapeApp>| {
        let (min, max) = drape::render::camera::bounds(&harness.state().mesh().positions).unwrap();
        (min + max) * 0.5
    };
    let at_start = centre(&harness);
    let on_screen = harness.state().screen_pos(at_start).unwrap();

    // The carpet travels and the scene has no saved camera: Follow starts on, as in `drape render`.
    assert!(harness.state().follows_cloth());
    harness.state_mut().set_frame(120.0);
    settle(&mut harness);
    let at_end = centre(&harness);
    assert!(at_end.distance(at_start) > 4.0, "the carpet flies {} m", at_end.distance(at_start));
    let followed = harness.state().screen_pos(at_end).unwrap();
    assert!(followed.distance(on_screen) < 0.5, "the centre stays at {on_screen:?}, not {followed:?}");

    // Off again: the camera stays, and the cloth moves on screen.
    harness.get_by_label("Follow").click();
    harness.run_ok();
    harness.state_mut().set_frame(0.0);
    settle(&mut harness);
    let back = harness.state().screen_pos(centre(&harness)).unwrap();
    assert!(back.distance(on_screen) > 50.0, "without Follow the carpet leaves the spot: {back:?}");
}

/// The keys of parameter `name` of layer `index`: (frame, value).
fn param_keys(harness: &Harness<'_, DrapeApp>, index: usize, name: &str) -> Vec<drape::scene::ParamKey> {
    let mut layer = harness.state().scene().layers[index].clone();
    match drape::editor::param_edit::param_mut(&mut layer, name) {
        Some(drape::scene::Param::Keys(keys)) => keys.clone(),
        other => panic!("{name} keyed, not {other:?}"),
    }
}

/// Adds a wave whose magnitude is keyed at frames 0 (0.03) and 48 (0.2); returns its index.
fn add_keyed_wave(harness: &mut Harness<'_, DrapeApp>) -> usize {
    let index = harness.state().scene().layers.len();
    harness.get_by_label("Add layer").click();
    harness.run_ok();
    harness.get_by_label("Wave").click();
    harness.run_ok();
    harness.get_by_label("Key magnitude").click();
    harness.run_ok();
    harness.state_mut().set_frame(48.0);
    harness.run_ok();
    harness.get_by_role_and_label(Role::SpinButton, "magnitude").set_value_accesskit(0.2);
    harness.run_ok();
    settle(harness);
    index
}

#[test]
fn the_curve_view_drags_a_parameter_key_and_eases_it_with_bezier_handles() {
    use drape::editor::timeline::bezier_handles::Square;
    use drape::editor::timeline::curve_view::Plot;
    use drape::scene::Ease;

    let workspace = Workspace::new();
    let carpet = workspace.path("carpet.ron");
    let mut harness = open_editor(&workspace, scene::load(&carpet).unwrap(), Some(carpet.clone()));
    leave_shot_camera(&mut harness);
    let index = add_keyed_wave(&mut harness);
    let keyed = param_keys(&harness, index, "magnitude");
    assert_eq!(keyed.iter().map(|k| (k.frame, k.value)).collect::<Vec<_>>(), [(0, 0.03), (48, 0.2)]);

    // Show the frequency's curve, then the magnitude's (the keyed one, shown by default too).
    harness.get_by_label("Show the frequency curve").click();
    harness.run_ok();
    assert!(harness.query_by_label("Curve of frequency").is_some());
    harness.get_by_label("Show the magnitude curve").click();
    harness.run_ok();

    // Drag the key at frame 48 up and to the right: its value and frame follow, in one undo step.
    let rect = harness.get_by_label("Curve of magnitude").rect();
    let timeline = harness.state().scene().timeline.clone();
    let param = drape::scene::Param::Keys(keyed.clone());
    let plot = Plot::of(rect, &timeline, &param);
    let key = plot.pos(48.0, 0.2);
    let to = plot.pos(60.0, 0.2) - egui::vec2(0.0, 25.0);
    drag(&mut harness, key, to);
    let moved = param_keys(&harness, index, "magnitude");
    assert_eq!(moved[0], keyed[0], "the other key stays");
    assert_eq!(moved[1].frame, 60, "whole frames, where the pointer went");
    assert!(moved[1].value > 0.25, "the key went up: {}", moved[1].value);
    assert!(
        (moved[1].value - plot.value(to.y)).abs() < 0.01,
        "{} under the pointer at {}",
        moved[1].value,
        plot.value(to.y)
    );
    assert_eq!(harness.state().document().undo_label(), Some("Move parameter key"));
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.run_ok();
    assert_eq!(param_keys(&harness, index, "magnitude"), keyed, "one undo takes the whole drag back");

    // Right-click the key: Bézier easing arriving at it, then drag the first handle.
    settle(&mut harness);
    right_click(&mut harness, key);
    harness.get_by_label("Bézier").click();
    harness.run_ok();
    let Ease::Bezier(x1, y1, x2, y2) = param_keys(&harness, index, "magnitude")[1].ease else { panic!("Bézier") };
    let eased = param_keys(&harness, index, "magnitude");
    harness.key_press(Key::F);
    harness.run_ok();
    snapshot(&mut harness, "editor_curve_view");
    let square = Square::of(harness.get_by_label("Bézier handles").rect(), [x1, y1, x2, y2]);
    let handle = square.pos(x1, y1);
    let target = square.pos(0.1, 0.6);
    drag(&mut harness, handle, target);
    let Ease::Bezier(nx1, ny1, nx2, ny2) = param_keys(&harness, index, "magnitude")[1].ease else { panic!("Bézier") };
    assert!((nx1 - 0.1).abs() < 0.02 && (ny1 - 0.6).abs() < 0.02, "the handle followed: ({nx1}, {ny1})");
    assert_eq!((nx2, ny2), (x2, y2), "the other handle stays");
    assert_eq!(harness.state().document().undo_label(), Some("Bézier handles"));
    harness.key_press(Key::Escape);
    harness.run_ok();
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.run_ok();
    assert_eq!(param_keys(&harness, index, "magnitude"), eased, "one undo takes the handle drag back");
}

#[test]
fn a_bezier_handle_in_the_timeline_key_menu_changes_the_easing() {
    use drape::editor::timeline::bezier_handles::Square;
    use drape::scene::Ease;

    let workspace = Workspace::new();
    let carpet = workspace.path("carpet.ron");
    let mut harness = open_editor(&workspace, scene::load(&carpet).unwrap(), Some(carpet.clone()));
    let frame = harness.state().scene().keys[0].frame;
    let diamond = timeline_pos(&harness, f64::from(frame)) + egui::vec2(0.0, 8.0);
    right_click(&mut harness, diamond);
    harness.get_by_label("Bézier").click();
    harness.run_ok();
    let Ease::Bezier(x1, y1, x2, y2) = harness.state().scene().keys[0].ease else { panic!("Bézier") };
    let before = harness.state().scene().clone();

    // Choosing closes the timeline's menu: open it again for the handles.
    right_click(&mut harness, diamond);
    let square = Square::of(harness.get_by_label("Bézier handles").rect(), [x1, y1, x2, y2]);
    drag(&mut harness, square.pos(x2, y2), square.pos(0.9, 1.3));
    let Ease::Bezier(nx1, ny1, nx2, ny2) = harness.state().scene().keys[0].ease else { panic!("Bézier") };
    assert_eq!((nx1, ny1), (x1, y1), "the first handle stays");
    assert!((nx2 - 0.9).abs() < 0.02 && (ny2 - 1.3).abs() < 0.02, "the second handle followed: ({nx2}, {ny2})");
    assert!(harness.query_by_label("Bézier handles").is_some(), "the menu stays open while dragging");

    // Past the square: x stops at 1.
    let square = Square::of(harness.get_by_label("Bézier handles").rect(), [nx1, ny1, nx2, ny2]);
    drag(&mut harness, square.pos(nx2, ny2), square.pos(1.5, 1.0));
    let Ease::Bezier(_, _, x, _) = harness.state().scene().keys[0].ease else { panic!("Bézier") };
    assert_eq!(x, 1.0);

    harness.key_press(Key::Escape);
    harness.run_ok();
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.run_ok();
    assert_eq!(harness.state().scene(), &before, "each drag is one undo step");
}

#[test]
fn an_editor_left_alone_autosaves_on_time() {
    let workspace = Workspace::new();
    let carpet = workspace.path("carpet.ron");
    let scene = scene::load(&carpet).unwrap();
    let (config, state) = (workspace.path("config"), workspace.path("state"));
    let recovery_file = state.join("recovery.ron");
    let interval = Duration::from_secs(3);
    let mut harness = Harness::builder().with_size(SIZE).wgpu().build_eframe(move |cc| {
        DrapeApp::new(scene, Some(carpet), cc.wgpu_render_state.as_ref())
            .with_file_dirs(Some(config), Some(state))
            .with_autosave_interval(interval)
    });
    settle(&mut harness);

    // One edit, then no more input.
    harness.get_by_role_and_label(Role::Slider, "Elasticity").set_value_accesskit(1.3);
    let edited = std::time::Instant::now();
    harness.run_ok();
    settle(&mut harness);
    assert!(!recovery_file.exists(), "nothing is written before the interval is up");
    // egui draws only on input or when asked: the app asks to be woken when
    // autosave is due, and a frame drawn then (with no input) writes the file.
    let wake_after = |harness: &Harness<'_, DrapeApp>| {
        harness.output().viewport_output.values().map(|v| v.repaint_delay).min().expect("a viewport")
    };
    while !recovery_file.exists() {
        let wait = wake_after(&harness);
        assert!(wait <= interval, "asked to be woken after {wait:?}, more than the autosave interval");
        assert!(edited.elapsed() < interval * 3, "no autosave {:?} after the edit", edited.elapsed());
        std::thread::sleep(wait);
        harness.step();
    }
    assert!(edited.elapsed() >= interval, "written only once the interval was up");
    let recovered = scene::load(&recovery_file).expect("the recovery file holds a scene");
    assert_eq!(recovered.keys[0].elasticity, 1.3, "with the edit");
}

#[test]
fn a_number_typed_and_tabbed_in_one_frame_lands_in_its_field() {
    let workspace = Workspace::new();
    let mut harness = open_editor(&workspace, new_scene(), None);
    let fps = harness.state().scene().timeline.fps;
    // A field scrolled into view first, as a user scrolls the panel to it.
    let spin = |harness: &mut Harness<'_, DrapeApp>, label: &str| {
        harness.get_by_role_and_label(Role::SpinButton, label).scroll_to_me();
        harness.run_ok();
        harness.get_by_role_and_label(Role::SpinButton, label).rect().center()
    };

    // A new pin's X and Y typed in one frame: both land, each in its own axis.
    let grid_rect = grid_editor_rect(&mut harness);
    let cloth = harness.state().scene().cloth.clone();
    click_at(&mut harness, GridEditor::point_in(grid_rect, &cloth, (10, 2)), Modifiers::NONE);
    settle(&mut harness);
    let z = pin_pos(harness.state().scene(), 0, (10, 2)).2;
    click_at(&mut harness, GridEditor::point_in(grid_rect, &cloth, (10, 2)), Modifiers::NONE);
    assert_eq!(harness.state().selection(), [(10, 2)]);
    let field = spin(&mut harness, "X");
    click_at(&mut harness, field, Modifiers::NONE);
    let typed = vec![Event::Text("0.25".into()), key_event(Key::Tab), Event::Text("-0.75".into()), key_event(Key::Tab)];
    in_one_frame(&mut harness, typed);
    assert_eq!(pin_pos(harness.state().scene(), 0, (10, 2)), (0.25, -0.75, z));

    // Frame, then Tab to fps: 30 goes to Frame, 12 to fps, one undo step for the rate.
    // (Settled first: while the cloth relaxes every frame asks for the next, and kittest's
    // clock would turn a click into a long press.)
    settle(&mut harness);
    let field = spin(&mut harness, "Frame");
    click_at(&mut harness, field, Modifiers::NONE);
    let typed = vec![Event::Text("30".into()), key_event(Key::Tab), Event::Text("12".into()), key_event(Key::Enter)];
    in_one_frame(&mut harness, typed);
    assert_eq!(harness.state().frame(), 30.0);
    assert_eq!(harness.state().scene().timeline.fps, 12.0);
    assert_eq!(harness.state().document().undo_label(), Some("Frame rate"));
    harness.state_mut().undo();
    assert_eq!(harness.state().scene().timeline.fps, fps);

    // Escape restores what the field had.
    let field = spin(&mut harness, "fps");
    click_at(&mut harness, field, Modifiers::NONE);
    in_one_frame(&mut harness, vec![Event::Text("99".into()), key_event(Key::Escape)]);
    assert_eq!(harness.state().scene().timeline.fps, fps);

    // A unit after the number is read; text that is no number keeps the value, and says so.
    for (typed, expected) in [("25 fps", 25.0), ("2.51.0", 25.0)] {
        settle(&mut harness);
        let field = spin(&mut harness, "fps");
        click_at(&mut harness, field, Modifiers::NONE);
        in_one_frame(&mut harness, vec![Event::Text(typed.into()), key_event(Key::Enter)]);
        harness.run_ok();
        let said: Vec<String> = harness.query_all_by_label_contains("not a number").map(|n| format!("{n:?}")).collect();
        assert_eq!(harness.state().scene().timeline.fps, expected, "{typed}: {said:?}");
    }
    assert!(harness.query_by_label_contains("“2.51.0” is not a number").is_some(), "said in the status bar");
}

/// Whether the centre of the shown cloth is drawn inside the viewport.
fn cloth_on_screen(harness: &Harness<'_, DrapeApp>) -> bool {
    let (min, max) = drape::render::camera::bounds(&harness.state().mesh().positions).unwrap();
    harness.state().screen_pos((min + max) * 0.5).is_some_and(|p| harness.state().viewport_rect().contains(p))
}

fn orbit_angles(harness: &Harness<'_, DrapeApp>) -> (f32, f32) {
    (harness.state().camera().yaw_deg, harness.state().camera().pitch_deg)
}

#[test]
fn f_frames_the_cloth_and_keeps_the_orbit_angles() {
    let workspace = Workspace::new();
    let mut harness = open_carpet(&workspace);

    // Follow off, orbit with the middle button, then fly the carpet out of view.
    harness.get_by_label("Follow").click();
    harness.run_ok();
    assert!(!harness.state().follows_cloth());
    let centre = harness.state().viewport_rect().center();
    let before = orbit_angles(&harness);
    harness.event(Event::PointerMoved(centre));
    harness.run_ok();
    let middle =
        |pressed, pos| Event::PointerButton { pos, button: PointerButton::Middle, pressed, modifiers: Modifiers::NONE };
    harness.event(middle(true, centre));
    harness.run_ok();
    for step in 1..=4 {
        harness.event(Event::PointerMoved(centre + egui::vec2(-30.0, 10.0) * step as f32));
        harness.run_ok();
    }
    harness.event(middle(false, centre + egui::vec2(-120.0, 40.0)));
    harness.run_ok();
    let orbited = orbit_angles(&harness);
    assert!((orbited.0 - before.0).abs() > 5.0 && (orbited.1 - before.1).abs() > 1.0, "{before:?} → {orbited:?}");
    harness.state_mut().set_frame(120.0);
    settle(&mut harness);
    assert!(!cloth_on_screen(&harness), "at frame 120 the carpet has flown off");

    harness.key_press(Key::F);
    harness.run_ok();
    assert!(cloth_on_screen(&harness), "F brings the carpet back into view");
    assert_eq!(orbit_angles(&harness), orbited, "F keeps the orbit angles");
    // Room for a gizmo's 70-point arrow on a pin at the cloth's edge.
    let room = cloth_room_pt(&harness);
    assert!(room >= 80.0, "the carpet keeps {room:.0} points clear round it");
}

/// The least room between the shown cloth and the viewport's edges, points;
/// negative when some of it is outside.
fn cloth_room_pt(harness: &Harness<'_, DrapeApp>) -> f32 {
    let view = harness.state().viewport_rect();
    let mut room = f32::INFINITY;
    for point in &harness.state().mesh().positions {
        let Some(at) = harness.state().screen_pos(*point) else { return -1.0 };
        let (dx, dy) = ((at.x - view.left()).min(view.right() - at.x), (at.y - view.top()).min(view.bottom() - at.y));
        room = room.min(dx).min(dy);
    }
    room
}

#[test]
fn a_scene_saved_mid_flight_opens_with_the_cloth_in_view() {
    let workspace = Workspace::new();
    let carpet = workspace.path("carpet.ron");
    let mut harness = open_editor(&workspace, scene::load(&carpet).unwrap(), Some(carpet.clone()));

    // Frame the carpet at frame 96, with Follow on, and save.
    harness.state_mut().set_frame(96.0);
    settle(&mut harness);
    harness.key_press(Key::F);
    harness.run_ok();
    assert!(harness.state().follows_cloth(), "a travelling cloth is followed");
    assert!(cloth_on_screen(&harness));
    harness.key_press_modifiers(Modifiers::COMMAND, Key::S);
    harness.run_ok();
    let saved = scene::load(&carpet).unwrap();
    let view = saved.view.clone().expect("the view is saved");
    assert_eq!((view.frame, view.follow), (Some(96), true), "the playhead and Follow are saved with the view");

    // Reopened: at frame 96, Follow on, the same camera, the carpet in view.
    let mut reopened = open_editor(&workspace, new_scene(), None);
    open_through_the_menu(&mut reopened, &carpet);
    settle(&mut reopened);
    assert_eq!(reopened.state().frame(), 96.0);
    assert!(reopened.state().follows_cloth(), "Follow is on again");
    assert_eq!(reopened.state().camera().to_view(), drape::scene::View { frame: None, follow: false, ..view.clone() });
    assert!(cloth_on_screen(&reopened));

    // A view that does not see the cloth at the opened frame (written by hand, no frame):
    // the camera frames the cloth, orbit angles kept.
    let without_frame = Scene { view: Some(drape::scene::View { frame: None, ..view.clone() }), ..saved };
    scene::save(&without_frame, &carpet).unwrap();
    open_through_the_menu(&mut reopened, &carpet);
    settle(&mut reopened);
    assert_eq!(reopened.state().frame(), 0.0);
    assert!(cloth_on_screen(&reopened), "the carpet at frame 0 is brought into view");
    assert_eq!(orbit_angles(&reopened), (view.yaw_deg as f32, view.pitch_deg as f32));
}

#[test]
fn the_panels_hold_still_while_scrubbing_playing_and_relaxing() {
    let workspace = Workspace::new();
    let mut harness = open_carpet(&workspace);
    let places = |harness: &Harness<'_, DrapeApp>| {
        [
            harness.get_by_label("Grid editor").rect(),
            harness.get_by_role_and_label(Role::SpinButton, "fps").rect(),
            harness.get_by_role_and_label(Role::SpinButton, "Start").rect(),
            harness.get_by_label("Add key").rect(),
        ]
    };
    let on_key = places(&harness);

    // Off a key (the notice), on the last frame (a wider number), onion skin on.
    harness.state_mut().set_frame(30.0);
    settle(&mut harness);
    assert_eq!(places(&harness), on_key, "off a key");
    harness.state_mut().set_frame(120.0);
    settle(&mut harness);
    assert_eq!(places(&harness), on_key, "at frame 120");
    harness.get_by_label("Onion skin").click();
    settle(&mut harness);
    assert_eq!(places(&harness), on_key, "with onion skin");

    // Playing (Pause in place of Play).
    harness.key_press(Key::Space);
    harness.step();
    assert!(harness.state().playing());
    assert_eq!(places(&harness), on_key, "while playing");
    harness.key_press(Key::Space);
    harness.step();

    // While a new rest shape relaxes (no verdict yet).
    harness.state_mut().set_frame(0.0);
    harness.state_mut().apply("Elasticity", |s| s.keys[0].elasticity = 1.1);
    harness.step();
    assert_eq!(places(&harness), on_key, "while relaxing");
}

/// Where the Cloth panel's controls are: the size fields, the grid editor,
/// the selected pin's X field and the Unpin button.
fn cloth_panel_places(harness: &Harness<'_, DrapeApp>) -> [egui::Rect; 5] {
    [
        harness.get_by_role_and_label(Role::SpinButton, "Width").rect(),
        harness.get_by_role_and_label(Role::SpinButton, "Height").rect(),
        harness.get_by_label("Grid editor").rect(),
        harness.get_by_role_and_label(Role::SpinButton, "X").rect(),
        harness.get_by_label("Unpin").rect(),
    ]
}

/// Nothing moves under the mouse when the scene or the selection changes:
/// adding a reference, pinning a point (the selection stays) and attaching
/// the selected pin to a node leave every control of the Cloth panel where
/// it was, and the pointer that picked the node is over none of its buttons.
#[test]
fn the_cloth_panel_holds_still_when_a_reference_is_added_a_point_pinned_and_a_pin_attached() {
    let workspace = Workspace::new();
    let mut harness = open_carpet(&workspace);
    let cloth = harness.state().scene().cloth.clone();
    harness.state_mut().select_pins(&[(0, 0)]);
    harness.run_ok();
    let grid_rect = grid_editor_rect(&mut harness);
    let before = cloth_panel_places(&harness);
    let timeline_places = |harness: &Harness<'_, DrapeApp>| {
        [harness.get_by_label("Timeline").rect(), harness.get_by_label("Add key").rect()]
    };
    let timeline_before = timeline_places(&harness);

    harness.get_by_label("Add reference…").click();
    harness.run_ok();
    pick_in_file_dialog(&mut harness, &std::fs::canonicalize("assets/walker.glb").unwrap());
    assert_eq!(harness.state().scene().references.len(), 1, "added");
    settle(&mut harness);
    assert_eq!(cloth_panel_places(&harness), before, "after adding a reference");
    assert_eq!(timeline_places(&harness), timeline_before, "the timeline, its bar in the reserved lane");

    click_at(&mut harness, GridEditor::point_in(grid_rect, &cloth, (10, 16)), Modifiers::NONE);
    assert!(edits_pinned(&harness, (10, 16)));
    assert_eq!(harness.state().selection(), [(0, 0)], "pinning keeps the selection");
    settle(&mut harness);
    assert_eq!(cloth_panel_places(&harness), before, "after pinning");

    harness.get_by_label("Attach to node…").scroll_to_me();
    harness.run_ok();
    let before = cloth_panel_places(&harness);
    let buttons: Vec<egui::Rect> =
        ["Unpin", "Copy", "Paste", "Mirror", "Detach", "Attach to node…", "Attach by clicking"]
            .into_iter()
            .map(|label| harness.get_by_label(label).rect())
            .collect();
    harness.get_by_label("Attach to node…").click();
    harness.run_ok();
    harness.get_by_label("chest").click();
    harness.run_ok();
    assert!(pin_of(harness.state().scene(), 0, (0, 0)).attach.is_some(), "attached");
    assert!(harness.query_by_label("chest").is_none(), "the list closed");
    settle(&mut harness);
    assert_eq!(cloth_panel_places(&harness), before, "after attaching");
    let pointer = harness.ctx.pointer_latest_pos().expect("the pointer picked the node");
    assert!(!buttons.iter().any(|rect| rect.contains(pointer)), "the pointer at {pointer:?} is over a button");
    assert!(harness.state().viewport_rect().contains(pointer), "the list floats over the viewport: {pointer:?}");
}

/// Clicks `item` in the open menu of the button `menu`: the item level with
/// the button, not the view bar's toggle of the same name.
fn choose_in_menu(harness: &mut Harness<'_, DrapeApp>, menu: &str, item: &str) {
    let top = harness.get_by_label(menu).rect().top();
    let Some(choice) = harness
        .query_all_by_label(item)
        .min_by(|a, b| (a.rect().top() - top).abs().total_cmp(&(b.rect().top() - top).abs()))
    else {
        panic!("no {item} in the {menu} menu")
    };
    choice.click();
    harness.run_ok();
}

/// Choosing from an Add menu leaves the pointer over no row's Remove button:
/// the menu opens beside the panel, over the viewport, so a second click
/// there removes nothing.
#[test]
fn after_adding_from_a_menu_the_pointer_is_over_no_remove_button() {
    let workspace = Workspace::new();
    let mut harness = open_carpet(&workspace);
    let layers = harness.state().scene().layers.len();
    let choices = [
        ("Add collider", "Box"),
        ("Add collider", "Ground"),
        ("Add collider", "Cylinder"),
        ("Add layer", "Sway"),
        ("Add layer", "Wave"),
        ("Add layer", "Follow-through"),
    ];
    for (menu, item) in choices {
        harness.get_by_label(menu).click();
        harness.run_ok();
        let panel_left = harness.get_by_label(menu).rect().left();
        choose_in_menu(&mut harness, menu, item);
        let pointer = harness.ctx.pointer_latest_pos().expect("the pointer chose the item");
        assert!(pointer.x < panel_left, "the menu opened beside the panel: {pointer:?}");
        let under: Vec<String> = harness
            .query_all_by_label_contains("Remove ")
            .filter(|node| node.rect().contains(pointer))
            .map(|node| format!("{node:?}"))
            .collect();
        assert!(under.is_empty(), "after {menu} ▸ {item} the pointer at {pointer:?} is over {under:?}");
    }
    assert_eq!(harness.state().scene().colliders.len(), 3);
    assert_eq!(harness.state().scene().layers.len(), layers + 3);
}

/// The right panel keeps its width and its rows their place sideways when a
/// layer's wide rows and curves open in it and it comes to scroll.
#[test]
fn the_right_panel_holds_still_when_a_layer_s_rows_open_in_it() {
    let workspace = Workspace::new();
    let mut harness = open_carpet(&workspace);
    let places = |harness: &Harness<'_, DrapeApp>| {
        [harness.get_by_label("Add layer").rect(), harness.get_by_label("Add collider").rect()].map(|r| r.left())
    };
    let before = places(&harness);
    for kind in ["Wave", "Gusts", "Sway", "Follow-through"] {
        harness.get_by_label("Add layer").click();
        harness.run_ok();
        choose_in_menu(&mut harness, "Add layer", kind);
        settle(&mut harness);
        assert_eq!(places(&harness), before, "with a {kind} layer's rows open");
        for curve in ["Show the frequency curve", "Show the magnitude curve", "Show the speed curve"] {
            let Some(button) = harness.query_by_label(curve) else { continue };
            button.click();
            harness.run_ok();
            settle(&mut harness);
            assert_eq!(places(&harness), before, "with a {kind} layer's {curve:?} open");
        }
    }
    for kind in ["Box", "Cylinder", "Ground"] {
        harness.get_by_label("Add collider").scroll_to_me();
        harness.run_ok();
        harness.get_by_label("Add collider").click();
        harness.run_ok();
        choose_in_menu(&mut harness, "Add collider", kind);
        settle(&mut harness);
        assert_eq!(places(&harness), before, "with a {kind} collider's rows open");
    }
}

/// Typing the cloth's Width or Height changes its shape in the grid editor,
/// not the room the editor takes: the rows under it stay where they were.
#[test]
fn the_rows_under_the_grid_editor_stay_put_when_the_cloths_shape_changes() {
    let workspace = Workspace::new();
    let mut harness = open_carpet(&workspace);
    harness.state_mut().select_pins(&[(0, 0)]);
    harness.run_ok();
    let before = cloth_panel_places(&harness);
    for (width_m, height_m) in [(1.6, 1.2), (2.0, 0.8), (1.0, 1.0), (0.6, 1.8)] {
        harness.state_mut().apply("Size", |s| s.cloth.size = (width_m, height_m));
        settle(&mut harness);
        let after = cloth_panel_places(&harness);
        assert_eq!(after[3..], before[3..], "at {width_m} × {height_m} m");
        assert_eq!(after[2].height(), before[2].height(), "at {width_m} × {height_m} m");
    }
}

/// A long relaxation keeps its progress and its Cancel in the status bar
/// while the pointer hovers the cloth, the grid point shown beside them;
/// Cancel stops it by taking the edit back, and Redo offers the edit again.
#[test]
fn a_relaxation_keeps_its_progress_and_cancel_while_the_cloth_is_hovered() {
    let workspace = Workspace::new();
    let mut harness = open_carpet(&workspace);
    let opened = harness.state().scene().clone();
    let middle = harness.state().mesh().positions[16 * opened.cloth.cols() + 10];
    let on_screen = harness.state().screen_pos(middle).unwrap();
    // A fabric that cannot settle soon: the most sweeps, to a tolerance no sweep reaches.
    harness.state_mut().apply("Elasticity", |s| {
        for key in &mut s.keys {
            key.elasticity = 1.2;
            key.relax.iterations = drape::scene::MAX_RELAX_ITERATIONS;
            key.relax.tolerance = 1e-15;
        }
    });
    harness.event(Event::PointerMoved(on_screen));
    for _ in 0..4 {
        harness.step();
    }
    assert!(harness.state().is_relaxing());
    assert!(harness.query_by_label_contains("Relaxing…").is_some(), "the progress");
    assert!(harness.query_by_label_contains("Grid point (").is_some(), "the hovered point, beside it");
    let cancel = harness.get_by_label("Cancel");
    assert!(!cancel.accesskit_node().is_disabled());
    assert!(harness.state().status_rect().contains(cancel.rect().center()), "Cancel is in the status bar");

    let at = cancel.rect().center();
    click_while_relaxing(&mut harness, at);
    assert_eq!(harness.state().scene(), &opened, "the edit is taken back");
    assert!(harness.state_mut().wait_for_shapes(Duration::from_secs(10)), "the relaxation stops at once");
    assert_eq!(harness.state().document().redo_label(), Some("Elasticity"));
    assert!(harness.query_by_label_contains("Relaxation cancelled").is_some(), "the status says so");
}

/// A click at `at` one frame per event: the spinner keeps asking for frames,
/// and a press held longer is no click.
fn click_while_relaxing(harness: &mut Harness<'_, DrapeApp>, at: Pos2) {
    harness.event(Event::PointerMoved(at));
    harness.step();
    for pressed in [true, false] {
        harness.event(Event::PointerButton {
            pos: at,
            button: PointerButton::Primary,
            pressed,
            modifiers: Modifiers::NONE,
        });
        harness.step();
    }
}

/// An undo can ask for a slow relaxation too (it brings back a fabric that
/// does not settle): Cancel then redoes the undo, and so does a plain Redo,
/// which stops the relaxation the undo asked for.
#[test]
fn a_relaxation_an_undo_asked_for_is_cancelled_by_redoing_it() {
    let workspace = Workspace::new();
    let mut harness = open_carpet(&workspace);
    let opened = harness.state().scene().clone();
    harness.state_mut().apply("Elasticity", |s| {
        for key in &mut s.keys {
            key.elasticity = 1.2;
            key.relax.iterations = drape::scene::MAX_RELAX_ITERATIONS;
            key.relax.tolerance = 1e-15;
        }
    });
    harness.state_mut().apply("Tolerance", |s| {
        for (key, was) in s.keys.iter_mut().zip(&opened.keys) {
            key.relax = was.relax.clone();
        }
    });
    assert!(harness.state_mut().wait_for_shapes(Duration::from_secs(120)), "the second edit settles");
    let settled = harness.state().scene().clone();

    harness.state_mut().undo();
    for _ in 0..4 {
        harness.step();
    }
    assert!(harness.state().is_relaxing(), "the undo asks for the fabric that does not settle");
    let cancel = harness.get_by_label("Cancel");
    assert!(!cancel.accesskit_node().is_disabled(), "Cancel can stop what an undo asked for");
    let at = cancel.rect().center();
    click_while_relaxing(&mut harness, at);
    assert_eq!(harness.state().scene(), &settled, "the undo is redone");
    assert!(harness.state_mut().wait_for_shapes(Duration::from_secs(10)), "the relaxation stops at once");
    assert_eq!(harness.state().document().undo_label(), Some("Tolerance"));
    assert!(harness.query_by_label_contains("1 undo redone").is_some(), "the status says so");

    harness.state_mut().undo();
    for _ in 0..4 {
        harness.step();
    }
    assert!(harness.state().is_relaxing());
    harness.state_mut().redo();
    harness.step();
    assert!(harness.state_mut().wait_for_shapes(Duration::from_secs(10)), "the redo stops the relaxation too");
    assert_eq!(harness.state().shown_scene(), &settled);
}

fn wheel(delta_y: f32, modifiers: Modifiers) -> Event {
    Event::MouseWheel {
        unit: egui::MouseWheelUnit::Point,
        delta: egui::vec2(0.0, delta_y),
        phase: egui::TouchPhase::Move,
        source: egui::MouseWheelSource::Wheel,
        modifiers,
    }
}

/// The frame a click at `pos` on the track scrubs to.
fn frame_clicked(harness: &mut Harness<'_, DrapeApp>, pos: Pos2) -> f64 {
    click_at(harness, pos, Modifiers::NONE);
    harness.state().frame()
}

#[test]
fn the_timeline_zooms_about_the_mouse_pans_and_jumps_between_keys() {
    let workspace = Workspace::new();
    let mut harness = open_carpet(&workspace);
    harness.state_mut().set_frame(60.0);
    settle(&mut harness);

    // Ctrl+wheel with the mouse on the playhead: the playhead stays under the mouse, the frames spread out.
    let at_60 = timeline_pos(&harness, 60.0);
    let full_frames_per_point = 60.0 / f64::from(at_60.x - timeline_pos(&harness, 0.0).x);
    harness.event(Event::PointerMoved(at_60));
    harness.run_ok();
    harness.event_modifiers(wheel(300.0, Modifiers::COMMAND), Modifiers::COMMAND);
    harness.run_ok();
    assert_eq!(frame_clicked(&mut harness, at_60), 60.0, "the playhead's frame is still under the mouse");
    let right = at_60 + egui::vec2(120.0, 0.0);
    let zoomed = frame_clicked(&mut harness, right) - 60.0;
    assert!(zoomed > 0.0 && zoomed < 0.7 * 120.0 * full_frames_per_point, "{zoomed} frames in 120 points");

    // The wheel pans a zoomed track: the frame under the mouse changes, the zoom does not.
    harness.state_mut().set_frame(60.0);
    harness.event(Event::PointerMoved(at_60));
    harness.event(wheel(-200.0, Modifiers::NONE));
    harness.run_ok();
    let panned = frame_clicked(&mut harness, at_60);
    assert!(panned > 60.0, "panned later: {panned}");

    // Fit shows the whole range again.
    harness.get_by_label("Fit").click();
    harness.run_ok();
    let at_30 = timeline_pos(&harness, 30.0);
    assert_eq!(frame_clicked(&mut harness, at_30), 30.0);

    // Up / Down: next and previous rest-shape key (0, 24, 48, 72, 120).
    harness.state_mut().set_frame(30.0);
    harness.run_ok();
    harness.key_press(Key::ArrowUp);
    harness.run_ok();
    assert_eq!(harness.state().frame(), 48.0);
    harness.key_press(Key::ArrowUp);
    harness.run_ok();
    assert_eq!(harness.state().frame(), 72.0);
    harness.key_press(Key::ArrowDown);
    harness.key_press(Key::ArrowDown);
    harness.run_ok();
    assert_eq!(harness.state().frame(), 24.0);
}

#[test]
fn every_frame_playback_never_skips_a_frame() {
    let workspace = Workspace::new();
    let mut harness = open_carpet(&workspace);
    harness.get_by_label("Every frame").click();
    harness.run_ok();
    harness.key_press(Key::Space);
    harness.step();
    assert!(harness.state().playing());
    // Each redraw comes 100 ms late (2.4 frame times at 24 fps): one frame each, none skipped.
    let mut shown = vec![harness.state().frame()];
    for _ in 0..5 {
        std::thread::sleep(Duration::from_millis(100));
        harness.step();
        shown.push(harness.state().frame());
    }
    assert_eq!(shown, [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
}

#[test]
fn auto_key_puts_an_edit_off_a_key_on_a_new_key_in_one_undo_step() {
    let workspace = Workspace::new();
    let carpet = workspace.path("carpet.ron");
    let opened = scene::load(&carpet).unwrap();
    let mut harness = open_editor(&workspace, opened.clone(), Some(carpet));
    harness.state_mut().set_frame(30.0);
    settle(&mut harness);
    let frames =
        |harness: &Harness<'_, DrapeApp>| harness.state().scene().keys.iter().map(|k| k.frame).collect::<Vec<_>>();
    assert_eq!(frames(&harness), [0, 24, 48, 72, 120]);

    // Off: the edit changes the key in effect (frame 24).
    harness.get_by_role_and_label(Role::Slider, "Stiffness").set_value_accesskit(0.5);
    harness.run_ok();
    assert_eq!(frames(&harness), [0, 24, 48, 72, 120]);
    assert_eq!(harness.state().scene().keys[1].stiffness, 0.5);
    harness.state_mut().undo();

    // On: a key at 30 holding the pose there, with the edit; the key at 24 keeps its value.
    harness.get_by_label("Auto key").click();
    harness.run_ok();
    harness.get_by_role_and_label(Role::Slider, "Stiffness").set_value_accesskit(0.5);
    harness.run_ok();
    assert_eq!(frames(&harness), [0, 24, 30, 48, 72, 120]);
    assert_eq!(harness.state().scene().keys[2].stiffness, 0.5);
    assert_eq!(harness.state().scene().keys[1], opened.keys[1]);
    assert_eq!(harness.state().document().undo_label(), Some("Stiffness"));
    settle(&mut harness);

    // On a key now: further edits change it, no more keys.
    harness.get_by_role_and_label(Role::Slider, "Stiffness").set_value_accesskit(0.6);
    harness.run_ok();
    assert_eq!(frames(&harness), [0, 24, 30, 48, 72, 120]);
    harness.state_mut().undo();
    harness.state_mut().undo();
    assert_eq!(harness.state().scene(), &opened, "one undo step took the new key and its edit");
}

#[test]
fn selection_follows_click_shift_ctrl_and_box_in_grid_editor_and_viewport() {
    let workspace = Workspace::new();
    let mut harness = open_editor(&workspace, new_scene(), None);
    let grid_rect = grid_editor_rect(&mut harness);
    let cloth = harness.state().scene().cloth.clone();
    let at = |point| GridEditor::point_in(grid_rect, &cloth, point);
    let (a, b, c) = ((0, 0), (32, 0), (16, 30));

    // A plain click on a free point pins it without selecting it, and leaves the selection as it was.
    click_at(&mut harness, at(a), Modifiers::NONE);
    assert_eq!(harness.state().selection(), [a]);
    click_at(&mut harness, at(c), Modifiers::NONE);
    settle(&mut harness);
    assert!(edits_pinned(&harness, c));
    assert_eq!(harness.state().selection(), [a]);

    // Shift adds (twice still once), Ctrl toggles, a plain click selects only that pin.
    click_at(&mut harness, at(a), Modifiers::SHIFT);
    click_at(&mut harness, at(b), Modifiers::SHIFT);
    click_at(&mut harness, at(b), Modifiers::SHIFT);
    assert_eq!(harness.state().selection(), [a, b]);
    click_at(&mut harness, at(c), Modifiers::COMMAND);
    click_at(&mut harness, at(a), Modifiers::COMMAND);
    assert_eq!(harness.state().selection(), [b, c]);
    click_at(&mut harness, at(a), Modifiers::NONE);
    assert_eq!(harness.state().selection(), [a]);

    // A box round the top row selects its two pins; Shift+box adds.
    drag(&mut harness, at(a) - egui::vec2(3.0, 3.0), at((32, 3)) + egui::vec2(3.0, 0.0));
    assert_eq!(harness.state().selection(), [a, b]);
    drag_holding(&mut harness, at((14, 28)), at((18, 32)), Modifiers::SHIFT);
    assert_eq!(harness.state().selection(), [a, b, c]);

    // In the viewport: a click on a pin selects it alone, a click on the empty background clears.
    let pin_on_screen = |harness: &Harness<'_, DrapeApp>, (i, j): (u32, u32)| {
        let p = harness.state().mesh().positions[j as usize * 33 + i as usize];
        harness.state().screen_pos(p).unwrap()
    };
    let b_on_screen = pin_on_screen(&harness, b);
    click_at(&mut harness, b_on_screen, Modifiers::NONE);
    assert_eq!(harness.state().selection(), [b]);
    let a_on_screen = pin_on_screen(&harness, a);
    click_at(&mut harness, a_on_screen, Modifiers::SHIFT);
    assert_eq!(harness.state().selection(), [b, a]);
    let corner = harness.state().viewport_rect().left_top() + egui::vec2(8.0, 8.0);
    click_at(&mut harness, corner, Modifiers::NONE);
    assert!(harness.state().selection().is_empty());

    // A box in the viewport round the two top pins selects them.
    let (lo, hi) = (a_on_screen.min(b_on_screen), a_on_screen.max(b_on_screen));
    drag(&mut harness, lo - egui::vec2(12.0, 12.0), hi + egui::vec2(12.0, 12.0));
    let mut selected = harness.state().selection().to_vec();
    selected.sort();
    assert_eq!(selected, [a, b]);
}

fn edits_pinned(harness: &Harness<'_, DrapeApp>, point: (u32, u32)) -> bool {
    harness.state().scene().keys[0].pins.iter().any(|p| p.grid == point)
}

#[test]
fn the_gizmo_moves_the_selected_pin_along_the_dragged_axis() {
    use drape::editor::viewport::pin_drag::AxisLock;
    let workspace = Workspace::new();
    let mut harness = open_editor(&workspace, new_scene(), None);
    let grid_rect = grid_editor_rect(&mut harness);
    let cloth = harness.state().scene().cloth.clone();
    assert!(harness.state().gizmo().is_none(), "nothing selected, no gizmo");
    click_at(&mut harness, GridEditor::point_in(grid_rect, &cloth, (0, 0)), Modifiers::NONE);
    let gizmo = harness.state().gizmo().expect("a gizmo on the selected pin");
    let before = pin_pos(harness.state().scene(), 0, (0, 0));

    // Drag the red arrow along itself and off to the side: the pin moves along X only.
    let origin = harness.state().screen_pos(gizmo.origin).unwrap();
    let along = gizmo.tip(AxisLock::X).unwrap() - origin;
    let grab = origin + along * 0.7;
    drag(&mut harness, grab, grab + along * 0.8 + egui::vec2(0.0, 40.0));
    let after = pin_pos(harness.state().scene(), 0, (0, 0));
    assert!(after.0 > before.0 + 0.05, "along +X: {before:?} → {after:?}");
    assert_eq!((after.1, after.2), (before.1, before.2), "locked to X");
    assert_eq!(harness.state().document().undo_label(), Some("Move pin"));
    assert_eq!(harness.state().selection(), [(0, 0)], "the drag keeps the selection");

    // A click on an arrow does not pin the cloth behind it.
    settle(&mut harness);
    let pins = harness.state().scene().keys[0].pins.len();
    let gizmo = harness.state().gizmo().unwrap();
    let x_tip = gizmo.tip(AxisLock::X).unwrap();
    let on_arrow = x_tip + (harness.state().screen_pos(gizmo.origin).unwrap() - x_tip) * 0.4;
    click_at(&mut harness, on_arrow, Modifiers::NONE);
    assert_eq!(harness.state().scene().keys[0].pins.len(), pins);
    assert_eq!(harness.state().selection(), [(0, 0)]);
}

/// A modal dialog covers the translate gizmo: its arrows, plainly visible
/// before, are dimmed under the Save dialog's backdrop like the rest of the
/// viewport (they were painted on a foreground layer of their own, over it).
#[test]
fn the_save_dialog_covers_the_gizmo() {
    use drape::editor::viewport::gizmo::axis_color;
    use drape::editor::viewport::pin_drag::AxisLock;
    let workspace = Workspace::new();
    let mut harness = open_editor(&workspace, new_scene(), None);
    let grid_rect = grid_editor_rect(&mut harness);
    let cloth = harness.state().scene().cloth.clone();
    click_at(&mut harness, GridEditor::point_in(grid_rect, &cloth, (0, 0)), Modifiers::NONE);
    click_at(&mut harness, GridEditor::point_in(grid_rect, &cloth, (32, 0)), Modifiers::SHIFT);
    settle(&mut harness);
    let gizmo = harness.state().gizmo().expect("a gizmo on the selected pins");
    let origin = harness.state().screen_pos(gizmo.origin).unwrap();
    // Points along the middle of each arrow, with the arrow's colour.
    let along: Vec<(Pos2, [u8; 3])> = [AxisLock::X, AxisLock::Y, AxisLock::Z]
        .into_iter()
        .filter_map(|axis| Some((gizmo.tip(axis)?, axis_color(axis, false).to_array())))
        .flat_map(|(tip, [r, g, b, _])| (3..8).map(move |i| (origin + (tip - origin) * (i as f32 / 10.0), [r, g, b])))
        .collect();
    assert!(along.len() >= 10, "at least two arrows on screen");
    let arrow_pixels_seen = |harness: &mut Harness<'_, DrapeApp>| {
        let scale = harness.ctx.pixels_per_point();
        let image = harness.render().expect("a rendered frame");
        along
            .iter()
            .filter(|(at, color)| {
                let (x, y) = ((at.x * scale) as u32, (at.y * scale) as u32);
                let pixel = image.get_pixel(x.min(image.width() - 1), y.min(image.height() - 1)).0;
                (0..3).all(|c| pixel[c].abs_diff(color[c]) <= 40)
            })
            .count()
    };
    let before = arrow_pixels_seen(&mut harness);
    assert!(before * 2 >= along.len(), "the arrows are drawn: {before} of {}", along.len());
    harness.get_by_label("File").click();
    harness.run_ok();
    harness.get_by_label_contains("Save As…").click();
    harness.run_ok();
    assert!(harness.query_by_label("File name").is_some(), "the Save dialog is open");
    assert_eq!(arrow_pixels_seen(&mut harness), 0, "no arrow shows through the dialog");
}

/// The Colliders panel: add a box, name it, key its height at two frames,
/// switch it off, remove it; each is one undo step, and the cloth is
/// shaped among what the panel made.
#[test]
fn the_colliders_panel_adds_keys_and_removes_a_table() {
    let workspace = Workspace::new();
    let mut harness = open_carpet(&workspace);
    assert!(harness.state().scene().colliders.is_empty());
    harness.get_by_label("Add collider").click();
    harness.run_ok();
    harness.get_by_label("Box").click();
    harness.run_ok();
    assert_eq!(harness.state().scene().colliders.len(), 1);
    assert_eq!(harness.state().document().undo_label(), Some("Add collider"));
    assert_eq!(harness.state().scene().colliders[0].name(), "table", "a box starts as a table top, named so");
    // A second box is numbered; taking it back, the first is selected again from its row.
    harness.get_by_label("Add collider").click();
    harness.run_ok();
    harness.get_by_label("Box").click();
    harness.run_ok();
    assert_eq!(harness.state().scene().colliders[1].name(), "table 2");
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.run_ok();
    assert_eq!(harness.state().scene().colliders.len(), 1);
    harness.get_by_label("table").click();
    harness.run_ok();
    // Key the top's height at frame 0, then move it at frame 24: keyed there.
    harness.get_by_label("Key center y").click();
    harness.run_ok();
    harness.state_mut().set_frame(24.0);
    harness.run_ok();
    harness.get_by_role_and_label(Role::SpinButton, "center y").set_value_accesskit(0.5);
    harness.run_ok();
    let collider = &harness.state().scene().colliders[0];
    let number = collider.numbers().into_iter().find(|n| n.label() == "center y").unwrap();
    let frames: Vec<(i32, f64)> = match collider.param(number) {
        Some(scene::Param::Keys(keys)) => keys.iter().map(|k| (k.frame, k.value)).collect(),
        other => panic!("not keyed: {other:?}"),
    };
    assert_eq!(frames, [(0, 0.72), (24, 0.5)]);
    assert_eq!(harness.state().document().undo_label(), Some("Collider center y"));
    // The keyed number's curve shows under the numbers; another's by its curve button.
    assert!(harness.query_by_label("Curve of center y").is_some(), "the keyed number's curve");
    harness.get_by_label("Show the size x curve").click();
    harness.run_ok();
    assert!(harness.query_by_label("Curve of size x").is_some());
    settle(&mut harness);
    assert_eq!(harness.state().shown_scene(), harness.state().scene(), "the cloth was shaped among it");
    harness.get_by_label("Enable Box collider \"table\"").click();
    harness.run_ok();
    assert!(!harness.state().scene().colliders[0].enabled());
    harness.get_by_label("Remove Box collider \"table\"").click();
    harness.run_ok();
    assert!(harness.state().scene().colliders.is_empty());
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.run_ok();
    assert_eq!(harness.state().scene().colliders.len(), 1, "removing is undone");
    // A mesh from a file: picked in the file dialog, read at once, named after the file.
    harness.get_by_label("Add collider").click();
    harness.run_ok();
    harness.get_by_label("Mesh…").click();
    harness.run_ok();
    let table = std::fs::canonicalize("tests/data/meshes/table.obj").unwrap();
    pick_in_file_dialog(&mut harness, &table);
    let Some(scene::Collider::Mesh(mesh)) = harness.state().scene().colliders.get(1) else {
        panic!("no mesh collider: {:?}", harness.state().scene().colliders)
    };
    assert_eq!(mesh.name, "table");
    let folder = harness.state().document().path().and_then(Path::parent).unwrap().to_path_buf();
    assert!(Path::new(&mesh.file).is_relative(), "named relative to the scene: {}", mesh.file);
    assert_eq!(std::fs::canonicalize(folder.join(&mesh.file)).unwrap(), table);
    assert!(mesh.solid.0.is_some(), "the file was read");
    settle(&mut harness);
}

/// A key without pins drops from its placement: the Drop from and Turn
/// rows set it (one undo step each), and are greyed on keys with pins.
#[test]
fn a_key_without_pins_is_placed_from_the_fabric_rows() {
    let workspace = Workspace::new();
    let table = scene::load(std::path::Path::new("scenes/round_table.ron")).unwrap();
    let mut harness = open_editor(&workspace, table, None);
    let drop_y = harness.get_by_role_and_label(Role::SpinButton, "Drop from Y");
    assert!(!drop_y.accesskit_node().is_disabled(), "the key at frame 0 has no pins");
    drop_y.set_value_accesskit(0.9);
    harness.run_ok();
    let placement = harness.state().scene().keys[0].placement.expect("placed");
    assert_eq!(placement.center, (0.0, 0.9, 0.0));
    assert_eq!(harness.state().document().undo_label(), Some("Placement centre"));
    harness.get_by_role_and_label(Role::SpinButton, "Turn Y").set_value_accesskit(45.0);
    harness.run_ok();
    assert_eq!(harness.state().scene().keys[0].placement.map(|p| p.rotation_deg), Some((0.0, 45.0, 0.0)));
    settle(&mut harness);
    assert_eq!(harness.state().shown_scene(), harness.state().scene(), "the key was dropped again");
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.run_ok();
    assert_eq!(harness.state().scene().keys[0].placement.map(|p| p.rotation_deg), Some((0.0, 0.0, 0.0)), "undone");
}

/// Among colliders the fabric shows the key's thickness and friction; a
/// change is one undo step and re-shapes the key. Scenes without colliders
/// show Friction greyed, so adding a collider moves no row.
#[test]
fn the_fabric_of_a_scene_with_colliders_sets_friction_and_thickness() {
    let workspace = Workspace::new();
    let carpet = open_carpet(&workspace);
    let friction = carpet.get_by_role_and_label(Role::Slider, "Friction");
    assert!(friction.accesskit_node().is_disabled(), "no colliders, friction greyed");
    drop(carpet);
    let table = scene::load(std::path::Path::new("scenes/tablecloth_pull.ron")).unwrap();
    let mut harness = open_editor(&workspace, table, None);
    harness.get_by_role_and_label(Role::Slider, "Friction").set_value_accesskit(1.2);
    harness.run_ok();
    assert_eq!(harness.state().scene().keys[0].friction, 1.2);
    assert_eq!(harness.state().document().undo_label(), Some("Friction"));
    settle(&mut harness);
    assert_eq!(harness.state().shown_scene(), harness.state().scene(), "the key was shaped again");
    assert!(harness.query_by_label("Thickness").is_some());
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.run_ok();
    assert_eq!(harness.state().scene().keys[0].friction, 0.5, "undone");
}

/// The sphere's centre in `scene` at frame 0.
fn sphere_center(scene: &Scene) -> glam::Vec3 {
    let Some(scene::Collider::Sphere(ball)) = scene.colliders.first() else { panic!("no sphere") };
    let at = |p: &scene::Param| drape::animate::track::sample(p, 0.0) as f32;
    glam::Vec3::new(at(&ball.center.0), at(&ball.center.1), at(&ball.center.2))
}

/// A collider is picked, dragged and moved along a gizmo arrow in the
/// viewport: a click selects it (the panel shows it, the pins let go), a
/// drag on it moves it under the mouse in one undo step, the gizmo's Y
/// arrow moves it up only, and a click on nothing clears it.
#[test]
fn a_collider_is_picked_dragged_and_moved_along_an_axis_in_the_viewport() {
    let workspace = Workspace::new();
    let mut scene = new_scene();
    // A ball between the camera and the cloth's middle: it hides the cloth behind it.
    let probe = open_editor(&workspace, scene.clone(), None);
    let (min, max) = drape::render::camera::bounds(&probe.state().mesh().positions).unwrap();
    let middle = (min + max) * 0.5;
    let c = middle + (probe.state().camera().eye() - middle).normalize() * 0.6;
    drop(probe);
    let ball = format!("[Sphere((name: \"ball\", center: ({}, {}, {}), radius: 0.15))]", c.x, c.y, c.z);
    scene.colliders = ron::from_str(&ball).unwrap();
    let mut harness = open_editor(&workspace, scene, None);
    let ball = harness.state().screen_pos(sphere_center(harness.state().scene())).expect("the ball is in front");
    assert!(harness.state().viewport_rect().contains(ball), "the ball is in view at {ball:?}");
    assert_eq!(harness.state().selected_collider(), None);

    click_at(&mut harness, ball, Modifiers::NONE);
    assert_eq!(harness.state().selected_collider(), Some(0), "a click on the ball selects it");
    assert!(harness.query_by_label("Key center x").is_some(), "the panel shows its numbers");
    assert!(harness.state().gizmo().is_some(), "a gizmo on the selected collider");

    // Dragged 60 points to the right: it follows the mouse at its depth.
    let before = sphere_center(harness.state().scene());
    let to = ball + egui::vec2(60.0, 0.0);
    drag(&mut harness, ball, to);
    let after = sphere_center(harness.state().scene());
    assert!(after.distance(before) > 0.05, "moved: {before} → {after}");
    // The grabbed point of its surface followed the mouse; the centre, farther
    // away, moved less on screen (perspective), and straight along.
    let shift = harness.state().screen_pos(after).unwrap() - ball;
    assert!(shift.x > 45.0 && shift.x < 60.0 && shift.y.abs() < 1.0, "followed the mouse: {shift:?}");
    assert_eq!(harness.state().document().undo_label(), Some("Move collider"));
    assert_eq!(harness.state().selected_collider(), Some(0));

    // The gizmo's Y arrow: up only.
    settle(&mut harness);
    use drape::editor::viewport::pin_drag::AxisLock;
    let gizmo = harness.state().gizmo().expect("the collider's gizmo");
    let origin = harness.state().screen_pos(gizmo.origin).unwrap();
    let along = gizmo.tip(AxisLock::Y).unwrap() - origin;
    let grab = origin + along * 0.7;
    drag(&mut harness, grab, grab + along * 0.8 + egui::vec2(30.0, 0.0));
    let lifted = sphere_center(harness.state().scene());
    assert!(lifted.y > after.y + 0.02, "up: {after} → {lifted}");
    assert_eq!((lifted.x, lifted.z), (after.x, after.z), "locked to Y");

    // Undo puts it back where the first drag left it; Delete removes it (undone too);
    // a click on nothing clears the selection.
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.run_ok();
    assert_eq!(sphere_center(harness.state().scene()), after);
    harness.key_press(Key::Delete);
    harness.run_ok();
    assert!(harness.state().scene().colliders.is_empty(), "Delete removes the selected collider");
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.run_ok();
    let centre = harness.state().screen_pos(after).unwrap();
    click_at(&mut harness, centre, Modifiers::NONE);
    assert_eq!(harness.state().selected_collider(), Some(0));
    let corner = harness.state().viewport_rect().left_top() + egui::vec2(8.0, 8.0);
    click_at(&mut harness, corner, Modifiers::NONE);
    assert_eq!(harness.state().selected_collider(), None);
    settle(&mut harness);
}

/// A scene file in `workspace` holding the carpet and a reference to the
/// bundled walker by its absolute path; opened from the file, so the walker is read.
fn open_carpet_with_walker(workspace: &Workspace) -> Harness<'static, DrapeApp> {
    let walker = std::fs::canonicalize("assets/walker.glb").unwrap();
    let text = std::fs::read_to_string("scenes/magic_carpet.ron").unwrap();
    let reference =
        format!("    references: [(name: \"walker\", file: {:?})],\n    keys: [", walker.display().to_string());
    let path = workspace.path("walker.ron");
    std::fs::write(&path, text.replacen("    keys: [", &reference, 1)).unwrap();
    open_editor(workspace, scene::load(&path).unwrap(), Some(path))
}

/// The References panel lists a scene's reference; its speed, visibility,
/// name, animation and a keyed number change through the panel, each one
/// undo step, and undo brings the document back. The timeline's band under
/// the keys marks where the walk plays.
#[test]
fn the_references_panel_edits_a_walker_in_undoable_steps() {
    let workspace = Workspace::new();
    let mut harness = open_carpet_with_walker(&workspace);
    let opened = harness.state().scene().clone();
    assert!(opened.references[0].rig.0.is_some(), "the walker was read");
    assert!(harness.query_by_label("Show reference \"walker\"").is_some(), "listed");
    assert!(harness.query_by_label("Speed").is_none(), "nothing selected yet");
    let track = harness.get_by_label("Timeline").rect();
    assert_eq!(track.height(), TRACK_BODY + 12.0, "the references' band under the keys");

    harness.get_by_label("Select reference \"walker\"").click();
    harness.run_ok();
    assert!(
        harness.query_by_label_contains("joints; clip Walk 0–1 s (frames 0–24 on this timeline)").is_some(),
        "the summary"
    );
    harness.get_by_role_and_label(Role::SpinButton, "Speed").set_value_accesskit(2.0);
    harness.run_ok();
    assert_eq!(harness.state().scene().references[0].speed, 2.0);
    assert_eq!(harness.state().document().undo_label(), Some("Reference speed"));
    assert!(harness.query_by_label_contains("(frames 0–12 on this timeline)").is_some(), "twice as fast");

    harness.get_by_label("Show reference \"walker\"").click();
    harness.run_ok();
    assert!(!harness.state().scene().references[0].visible);
    assert_eq!(harness.state().document().undo_label(), Some("Show reference"));
    assert_eq!(harness.get_by_label("Timeline").rect(), track, "hidden: its bar gone, the band kept");

    // A name is one undo step when the field lets go, however many letters were typed.
    let name = harness.get_by_role_and_label(Role::TextInput, "Name of reference 1");
    name.focus();
    harness.run_ok();
    harness.key_press_modifiers(Modifiers::COMMAND, Key::A);
    harness.get_by_role_and_label(Role::TextInput, "Name of reference 1").type_text("hero");
    harness.run_ok();
    assert_eq!(harness.state().scene().references[0].name, "walker", "still typing");
    harness.key_press(Key::Enter);
    harness.run_ok();
    assert_eq!(harness.state().scene().references[0].name, "hero");
    assert_eq!(harness.state().document().undo_label(), Some("Rename reference"));

    harness.get_by_label("Animation").click();
    harness.run_ok();
    harness.get_by_label("Walk").click();
    harness.run_ok();
    assert_eq!(harness.state().scene().references[0].animation.as_deref(), Some("Walk"));

    // A number keyed at frame 0, then moved at frame 24: keyed there, its curve below.
    harness.get_by_label("Key reference centre y").click();
    harness.run_ok();
    harness.state_mut().set_frame(24.0);
    harness.run_ok();
    harness.get_by_role_and_label(Role::SpinButton, "centre y").set_value_accesskit(0.5);
    harness.run_ok();
    let keys: Vec<(i32, f64)> = match &harness.state().scene().references[0].center.1 {
        scene::Param::Keys(keys) => keys.iter().map(|k| (k.frame, k.value)).collect(),
        other => panic!("not keyed: {other:?}"),
    };
    assert_eq!(keys, [(0, 0.0), (24, 0.5)]);
    assert_eq!(harness.state().document().undo_label(), Some("Reference centre y"));
    assert!(harness.query_by_label("Curve of centre y").is_some(), "the keyed number's curve");

    for _ in 0..6 {
        harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
        harness.run_ok();
    }
    assert_eq!(harness.state().scene(), &opened, "every step undone");
    assert_eq!(harness.state().document().undo_label(), None);
    settle(&mut harness);
}

/// Add reference… reads the picked file at once and names it after the
/// file (a second one gets a new name); a file that is not glTF is
/// reported and adds nothing.
#[test]
fn a_reference_is_added_through_the_panel() {
    let workspace = Workspace::new();
    let mut harness = open_carpet(&workspace);
    assert!(harness.query_by_label_contains("None. A reference is a glTF character").is_some());
    let walker = std::fs::canonicalize("assets/walker.glb").unwrap();
    for expected in ["walker", "walker 2"] {
        harness.get_by_label("Add reference…").click();
        harness.run_ok();
        pick_in_file_dialog(&mut harness, &walker);
        let reference = harness.state().scene().references.last().expect("added").clone();
        assert_eq!(reference.name, expected);
        assert_eq!(harness.state().document().undo_label(), Some("Add reference"));
        assert!(reference.rig.0.is_some(), "the file was read");
        let folder = harness.state().document().path().and_then(Path::parent).unwrap().to_path_buf();
        assert!(Path::new(&reference.file).is_relative(), "named relative to the scene: {}", reference.file);
        assert_eq!(std::fs::canonicalize(folder.join(&reference.file)).unwrap(), walker);
    }
    assert!(harness.query_by_label("Speed").is_some(), "the new one is selected");

    let junk = workspace.path("junk.glb");
    std::fs::write(&junk, "not a glTF file").unwrap();
    harness.get_by_label("Add reference…").click();
    harness.run_ok();
    pick_in_file_dialog(&mut harness, &junk);
    assert_eq!(harness.state().scene().references.len(), 2, "nothing added");
    assert!(harness.query_by_label_contains("Cannot use").is_some(), "the problem is shown");

    harness.get_by_label("Remove reference \"walker 2\"").click();
    harness.run_ok();
    assert_eq!(harness.state().scene().references.len(), 1);
    assert_eq!(harness.state().document().undo_label(), Some("Remove reference"));
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.run_ok();
    assert_eq!(harness.state().scene().references.len(), 2, "removing is undone");
    settle(&mut harness);
}

/// A reference whose file was not read (a scene from text) shows its file
/// and numbers and says it is not read.
#[test]
fn a_reference_not_read_is_shown_without_its_rig() {
    let workspace = Workspace::new();
    let mut scene = scene::load(&workspace.path("carpet.ron")).unwrap();
    scene.references = ron::from_str(r#"[(name: "ghost", file: "ghost.glb", speed: 0.5)]"#).unwrap();
    let mut harness = open_editor(&workspace, scene, None);
    harness.get_by_label("Select reference \"ghost\"").click();
    harness.run_ok();
    assert!(harness.query_by_label_contains("not read").is_some());
    assert!(harness.query_by_label("ghost.glb").is_some(), "the file");
    assert!(harness.query_by_label("Key reference scale").is_some(), "the numbers");
    assert_eq!(harness.get_by_label("Timeline").rect().height(), TRACK_BODY + 12.0, "the references' band, kept");
    harness.get_by_role_and_label(Role::SpinButton, "Start frame").set_value_accesskit(12.0);
    harness.run_ok();
    assert_eq!(harness.state().scene().references[0].start_frame, 12);
}

/// The cape on the walker: a copy of `scenes/cape.ron` in `workspace`
/// naming the walker by its absolute path, opened from the file.
fn open_cape(workspace: &Workspace) -> Harness<'static, DrapeApp> {
    let walker = std::fs::canonicalize("assets/walker.glb").unwrap();
    let text = std::fs::read_to_string("scenes/cape.ron").unwrap();
    let text = text.replace("\"../assets/walker.glb\"", &format!("{:?}", walker.display().to_string()));
    let path = workspace.path("cape.ron");
    std::fs::write(&path, text).unwrap();
    open_editor(workspace, scene::load(&path).unwrap(), Some(path))
}

fn pin_of(scene: &Scene, key: usize, grid: (u32, u32)) -> scene::Pin {
    scene.keys[key].pins.iter().find(|p| p.grid == grid).cloned().expect("pinned")
}

/// Clicks the widget labelled `label` once scrolled into view, as a user scrolls the Cloth panel to it.
fn click_scrolled(harness: &mut Harness<'_, DrapeApp>, label: &str) {
    harness.get_by_label(label).scroll_to_me();
    harness.run_ok();
    harness.get_by_label(label).click();
    harness.run_ok();
}

/// Where pin `grid` of key `key` is held by its attachment at the key's frame.
fn attached_place(scene: &Scene, key: usize, grid: (u32, u32)) -> glam::DVec3 {
    let attachment = pin_of(scene, key, grid).attach.expect("attached");
    let frame = f64::from(scene.keys[key].frame);
    drape::animate::attachments::attachment_at(scene, &attachment, frame).expect("placed")
}

/// The Cloth panel shows what holds a selected pin and lets go of it
/// without moving it (one undo step), attaches it to a node picked from a
/// filtered list where it is, and detaches several pins at once.
#[test]
fn a_pin_is_detached_and_attached_to_a_node_in_the_cloth_panel() {
    let workspace = Workspace::new();
    let mut harness = open_cape(&workspace);
    let opened = harness.state().scene().clone();
    let grid = (9, 0);
    harness.state_mut().select_pins(&[grid]);
    harness.run_ok();
    assert!(harness.query_by_label("Attached to walker · node chest").is_some(), "the attachment is shown");
    // The walker holds pins: it cannot be removed yet, and the status says which and what to do.
    harness.get_by_label("Remove reference \"walker\"").click();
    harness.run_ok();
    assert_eq!(harness.state().scene(), &opened);
    assert!(harness.query_by_label_contains("5 pins (0, 0), (4, 0), (9, 0), … of the key at frame 0").is_some());

    let held = attached_place(&opened, 0, grid);
    click_scrolled(&mut harness, "Detach");
    let pin = pin_of(harness.state().scene(), 0, grid);
    assert_eq!(pin.attach, None);
    assert!(glam::DVec3::from(pin.pos).distance(held) < 1e-9, "stays where it was held: {:?} {held}", pin.pos);
    assert_eq!(harness.state().document().undo_label(), Some("Detach pin"));
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.run_ok();
    assert_eq!(harness.state().scene(), &opened, "undo attaches it again");

    // Loose again, then onto the chest through the node list: filtered, picked, where it is.
    click_scrolled(&mut harness, "Detach");
    let loose = glam::DVec3::from(pin_of(harness.state().scene(), 0, grid).pos);
    click_scrolled(&mut harness, "Attach to node…");
    assert!(harness.query_by_label("head").is_some(), "the walker's nodes are listed");
    let filter = harness.get_by_role_and_label(Role::TextInput, "Filter nodes");
    filter.focus();
    filter.type_text("che");
    harness.run_ok();
    assert!(harness.query_by_label("head").is_none(), "filtered out");
    click_scrolled(&mut harness, "chest");
    let pin = pin_of(harness.state().scene(), 0, grid);
    let Some(scene::Attachment::Node(node)) = &pin.attach else { panic!("not on a node: {pin:?}") };
    assert_eq!((node.reference.as_str(), node.node.as_str()), ("walker", "chest"));
    let held = attached_place(harness.state().scene(), 0, grid);
    assert!(held.distance(loose) < 1e-6 && held.distance(glam::DVec3::from(pin.pos)) < 1e-6, "no jump: {held}");
    assert_eq!(harness.state().document().undo_label(), Some("Attach pin"));
    assert!(harness.query_by_label("chest").is_none(), "the list closes once picked");

    // All five: how many are attached, and Detach 5 in one step.
    let all: Vec<(u32, u32)> = opened.keys[0].pins.iter().map(|p| p.grid).collect();
    harness.state_mut().select_pins(&all);
    harness.run_ok();
    assert!(harness.query_by_label("5 of 5 attached").is_some());
    click_scrolled(&mut harness, "Detach 5");
    assert!(harness.state().scene().keys[0].pins.iter().all(|p| p.attach.is_none()));
    assert_eq!(harness.state().document().undo_label(), Some("Detach pins"));
    settle(&mut harness);
}

/// Attach by clicking: the next click on the walker in the viewport, at a
/// frame off the key, attaches the one selected pin to that skin point
/// (the key holding it where that point is at the key's frame); a click on
/// nothing says so and waits for another, Esc cancels. Dragging the pin
/// then lets go of the skin.
#[test]
fn a_pin_is_attached_by_clicking_on_the_walker_and_let_go_to_move() {
    let workspace = Workspace::new();
    let mut harness = open_cape(&workspace);
    harness.state_mut().set_frame(10.0);
    settle(&mut harness);
    let grid = (9, 0);
    harness.state_mut().select_pins(&[grid]);
    harness.run_ok();
    click_scrolled(&mut harness, "Attach by clicking");
    assert_eq!(harness.state().attaching(), Some(grid));
    assert!(harness.query_by_label_contains("Click on a reference to attach pin (9, 0)").is_some(), "the status");
    harness.key_press(Key::Escape);
    harness.run_ok();
    assert_eq!(harness.state().attaching(), None, "Esc cancels");
    click_scrolled(&mut harness, "Attach by clicking");
    harness.state_mut().select_pins(&[(0, 0)]);
    harness.run_ok();
    assert_eq!(harness.state().attaching(), None, "another pin picked: not this one's click any more");
    harness.state_mut().select_pins(&[grid]);
    click_scrolled(&mut harness, "Attach by clicking");

    let before = harness.state().scene().clone();
    let sky = harness.state().viewport_rect().left_top() + egui::vec2(8.0, 8.0);
    click_at(&mut harness, sky, Modifiers::NONE);
    assert_eq!(harness.state().scene(), &before, "nothing attached");
    assert!(harness.query_by_label_contains("No reference there").is_some());
    assert_eq!(harness.state().attaching(), Some(grid), "still waiting for a click on a reference");

    // Where the pin hangs on screen: the ray through it meets the walker's back just behind it.
    let cols = before.cloth.cols();
    let hanging = harness.state().mesh().positions[grid.1 as usize * cols + grid.0 as usize];
    let at = harness.state().screen_pos(hanging).expect("the pin is in view");
    click_at(&mut harness, at, Modifiers::NONE);
    let pin = pin_of(harness.state().scene(), 0, grid);
    let Some(scene::Attachment::Surface(surface)) = pin.attach.clone() else { panic!("not on the skin: {pin:?}") };
    assert_eq!((surface.reference.as_str(), surface.lift_m), ("walker", before.keys[0].thickness));
    let held = attached_place(harness.state().scene(), 0, grid);
    assert!(held.distance(glam::DVec3::from(pin.pos)) < 1e-6, "pos is where it is held at the key: {held}");
    assert_eq!(harness.state().document().undo_label(), Some("Attach pin"));
    assert_eq!(harness.state().attaching(), None);
    // The skin point is the one under the mouse at the frame shown (a thickness off it).
    let attachment = scene::Attachment::Surface(surface);
    let shown = drape::animate::attachments::attachment_at(harness.state().scene(), &attachment, 10.0).unwrap();
    let on_screen = harness.state().screen_pos(shown.as_vec3()).unwrap();
    assert!(on_screen.distance(at) < 4.0, "clicked at {at:?}, attached at {on_screen:?}");

    // Dragged up at the key's frame: let go of the skin, moved, and the status says so.
    harness.state_mut().set_frame(0.0);
    settle(&mut harness);
    let cols = harness.state().scene().cloth.cols();
    let start = harness.state().mesh().positions[grid.1 as usize * cols + grid.0 as usize];
    let from = harness.state().screen_pos(start).unwrap();
    // 10 cm up, however near the view is.
    let to = harness.state().screen_pos(start + glam::Vec3::Y * 0.1).unwrap();
    drag(&mut harness, from, to);
    let pin = pin_of(harness.state().scene(), 0, grid);
    assert_eq!(pin.attach, None);
    assert!(pin.pos.1 > held.y + 0.02, "moved up: {held} → {:?}", pin.pos);
    assert!(harness.query_by_label_contains("Detached pin (9, 0) from walker to move it").is_some(), "the status");
    assert_eq!(harness.state().document().undo_label(), Some("Move pin"));
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.run_ok();
    assert_eq!(pin_of(harness.state().scene(), 0, grid).attach, Some(attachment), "undo attaches it again");
}

/// A pin attached to a node stays attached when typed or dragged to a new
/// place: its offset in the node takes the move.
#[test]
fn a_node_attached_pin_moves_by_typing_and_dragging_and_stays_attached() {
    let workspace = Workspace::new();
    let mut harness = open_cape(&workspace);
    let grid = (0, 0);
    harness.state_mut().select_pins(&[grid]);
    harness.run_ok();
    let before = attached_place(harness.state().scene(), 0, grid);
    harness.get_by_role_and_label(Role::SpinButton, "X").set_value_accesskit(before.x - 0.05);
    harness.run_ok();
    let pin = pin_of(harness.state().scene(), 0, grid);
    assert!(matches!(&pin.attach, Some(scene::Attachment::Node(n)) if n.node == "chest"), "{pin:?}");
    let typed = glam::DVec3::new(before.x - 0.05, before.y, before.z);
    assert!(attached_place(harness.state().scene(), 0, grid).distance(typed) < 1e-6);
    assert!(glam::DVec3::from(pin.pos).distance(typed) < 1e-9);
    assert_eq!(harness.state().document().undo_label(), Some("Move pin"));
    settle(&mut harness);

    let cols = harness.state().scene().cloth.cols();
    let start = harness.state().mesh().positions[grid.1 as usize * cols + grid.0 as usize];
    let from = harness.state().screen_pos(start).unwrap();
    // 10 cm up, however near the view is.
    let to = harness.state().screen_pos(start + glam::Vec3::Y * 0.1).unwrap();
    drag(&mut harness, from, to);
    let pin = pin_of(harness.state().scene(), 0, grid);
    assert!(matches!(&pin.attach, Some(scene::Attachment::Node(n)) if n.node == "chest"), "{pin:?}");
    let held = attached_place(harness.state().scene(), 0, grid);
    assert!(held.distance(glam::DVec3::from(pin.pos)) < 1e-6, "held where it was dragged: {held} {:?}", pin.pos);
    assert!(held.y > typed.y + 0.02, "dragged up: {typed} → {held}");
    assert_eq!(harness.state().document().undo_label(), Some("Move pin"));
    settle(&mut harness);
}

/// The Cloth panel's Follow row: the cloth follows a node picked from the
/// filtered list (one undo step), and Stop lets it go.
#[test]
fn the_cloth_follows_a_node_picked_in_the_cloth_panel() {
    let workspace = Workspace::new();
    let mut harness = open_cape(&workspace);
    assert_eq!(harness.state().scene().follow, None);
    assert!(harness.query_by_label("nothing").is_some(), "Follows: nothing");
    click_scrolled(&mut harness, "Follow node…");
    let filter = harness.get_by_role_and_label(Role::TextInput, "Filter nodes");
    filter.focus();
    filter.type_text("hip");
    harness.run_ok();
    click_scrolled(&mut harness, "hips");
    let follow = harness.state().scene().follow.clone().expect("following");
    assert_eq!((follow.reference.as_str(), follow.node.as_str()), ("walker", "hips"));
    assert_eq!(harness.state().document().undo_label(), Some("Follow node"));
    assert!(harness.query_by_label("walker · hips").is_some());
    click_scrolled(&mut harness, "Stop");
    assert_eq!(harness.state().scene().follow, None);
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.run_ok();
    assert!(harness.state().scene().follow.is_some(), "undo follows again");
}

/// Opens the View menu and clicks its shot-camera item `item`.
fn camera_menu(harness: &mut Harness<'_, DrapeApp>, item: &str) {
    harness.get_by_role_and_label(Role::Button, "View").click();
    harness.run_ok();
    harness.get_by_label(item).click();
    harness.run_ok();
}

/// View ▸ (shot camera items): a camera is added where the viewport looks from, the
/// viewport looks through it (its eye the camera's, at the playhead), orbiting
/// leaves it, and keying writes keys at the playhead; each edit one undo step.
#[test]
fn the_viewport_looks_through_the_shot_camera_set_from_the_view() {
    let workspace = Workspace::new();
    // The carpet without its shot camera and plate.
    let path = workspace.path("carpet.ron");
    let mut carpet = scene::load(&path).unwrap();
    (carpet.camera, carpet.plate) = (None, None);
    scene::save(&carpet, &path).unwrap();
    let mut harness = open_carpet(&workspace);
    assert!(harness.state().scene().camera.is_none());
    let eye = harness.state().camera().eye();
    camera_menu(&mut harness, "Add camera from view");
    let camera = harness.state().scene().camera.clone().expect("a camera");
    let scene::Param::Constant(x) = camera.position.0 else { panic!("a constant position: {camera:?}") };
    assert!((x as f32 - eye.x).abs() < 1e-5, "{x} vs {eye}");
    assert_eq!(harness.state().document().undo_label(), Some("Camera from view"));

    camera_menu(&mut harness, "Look through camera");
    let expected = drape::picture::shot_camera_at(&camera, harness.state().frame(), camera.image_size).eye();
    assert!(
        harness.state().camera().eye().abs_diff_eq(expected, 1e-4),
        "{} vs {expected}",
        harness.state().camera().eye()
    );

    // Key it at frame 30: every position number becomes a list of keys.
    harness.state_mut().set_frame(30.0);
    harness.run_ok();
    camera_menu(&mut harness, "Key camera at playhead");
    let keyed = harness.state().scene().camera.clone().unwrap();
    assert!(matches!(&keyed.position.0, scene::Param::Keys(keys) if keys.iter().any(|k| k.frame == 30)), "{keyed:?}");
    assert_eq!(harness.state().document().undo_label(), Some("Key camera"));

    // Scrolling in the viewport moves the view, which leaves the camera's.
    let centre = harness.state().viewport_rect().center();
    harness.hover_at(centre);
    harness.event(wheel(120.0, Modifiers::NONE));
    harness.run_ok();
    let after = harness.state().camera().eye();
    assert!(!after.abs_diff_eq(expected, 1e-3), "the view moved away from the camera");
}

/// View ▸ Camera on the magic carpet: the painted plate fills the shot
/// camera's frame behind the cloth (loaded off the UI thread), the Plate
/// toggle takes it away, and a plate that is not there is a message in the
/// frame, not a crash.
#[test]
fn looking_through_the_camera_shows_the_plate_behind_the_cloth() {
    let workspace = Workspace::new();
    let path = workspace.path("carpet.ron");
    let mut carpet = scene::load(&path).unwrap();
    let plate_file = std::fs::canonicalize("assets/magic_carpet_plate.png").unwrap();
    carpet.plate.as_mut().expect("the carpet has a plate").file = plate_file.display().to_string();
    scene::save(&carpet, &path).unwrap();
    let mut harness = open_carpet(&workspace);
    harness.get_by_role_and_label(Role::Button, "Camera").click();
    // The worker decodes the plate while frames run.
    for _ in 0..100 {
        harness.run_ok();
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    snapshot(&mut harness, "editor_plate");
    harness.get_by_role_and_label(Role::Button, "Plate").click();
    harness.run_ok();
    snapshot(&mut harness, "editor_plate_off");
    drop(harness);

    // The workspace's copy names the plate relative to the bundled scene's folder: not there.
    let workspace = Workspace::new();
    let mut harness = open_carpet(&workspace);
    harness.get_by_role_and_label(Role::Button, "Camera").click();
    harness.run_ok();
    harness.run_ok();
    let said = harness.query_all_by_label_contains("plate: there is no image \"../assets/magic_carpet_plate.png\"");
    assert_eq!(said.count(), 2, "in the camera's frame and in the Shot panel");
}

/// The Shot panel edits the carpet's camera and plate: a lens typed in is one
/// undo step, a number keyed at 0 and moved at 48 is keyed at both with its
/// curve below, the picture size and frame offset are whole numbers, and
/// removing the plate is undone like any edit.
#[test]
fn the_shot_panel_edits_the_camera_and_the_plate() {
    let workspace = Workspace::new();
    let mut harness = open_carpet(&workspace);
    let opened = harness.state().scene().clone();
    assert!(harness.query_by_label_contains("54.4° across").is_some(), "the lens's field of view");
    harness.get_by_role_and_label(Role::SpinButton, "focal length").set_value_accesskit(50.0);
    harness.run_ok();
    let camera = harness.state().scene().camera.clone().unwrap();
    assert_eq!(camera.focal_length_mm, scene::Param::Constant(50.0));
    assert_eq!(harness.state().document().undo_label(), Some("Shot focal length"));
    assert!(harness.query_by_label_contains("39.6° across").is_some(), "the new field of view");

    harness.get_by_label("Key shot target y").click();
    harness.run_ok();
    harness.state_mut().set_frame(48.0);
    harness.run_ok();
    harness.get_by_role_and_label(Role::SpinButton, "target y").set_value_accesskit(1.5);
    harness.run_ok();
    let keys: Vec<(i32, f64)> = match &harness.state().scene().camera.as_ref().unwrap().target.1 {
        scene::Param::Keys(keys) => keys.iter().map(|k| (k.frame, k.value)).collect(),
        other => panic!("not keyed: {other:?}"),
    };
    assert_eq!(keys, [(0, 0.95), (48, 1.5)]);
    assert!(harness.query_by_label("Curve of position z").is_some(), "the first keyed number's curve");
    click_scrolled(&mut harness, "Show the target y curve");
    assert!(harness.query_by_label("Curve of target y").is_some(), "the chosen number's curve");

    harness.get_by_role_and_label(Role::SpinButton, "Frame offset").set_value_accesskit(12.0);
    harness.run_ok();
    assert_eq!(harness.state().scene().plate.as_ref().unwrap().frame_offset, 12);
    click_scrolled(&mut harness, "Remove plate");
    assert!(harness.state().scene().plate.is_none());
    for _ in 0..5 {
        harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
        harness.run_ok();
    }
    assert_eq!(harness.state().scene(), &opened, "every step undone");
    settle(&mut harness);
}

/// File ▸ Render…: a PNG sequence of three frames with alpha into a folder
/// typed beside Choose…, rendered on the window's worker while the editor
/// keeps drawing; each frame is transparent in its corner.
#[test]
fn file_render_writes_a_png_sequence_with_alpha() {
    let workspace = Workspace::new();
    let mut harness = open_carpet(&workspace);
    harness.get_by_role_and_label(Role::Button, "File").click();
    harness.run_ok();
    harness.get_by_label_contains("Render…").click();
    harness.run_ok();
    harness.get_by_label("PNG sequence").click();
    harness.run_ok();
    harness.get_by_role_and_label(Role::SpinButton, "First frame").set_value_accesskit(10.0);
    harness.run_ok();
    harness.get_by_role_and_label(Role::SpinButton, "Last frame").set_value_accesskit(12.0);
    harness.run_ok();
    harness.get_by_role_and_label(Role::SpinButton, "Picture width").set_value_accesskit(96.0);
    harness.run_ok();
    harness.get_by_role_and_label(Role::SpinButton, "Picture height").set_value_accesskit(54.0);
    harness.run_ok();
    harness.get_by_label_contains("straight alpha, as PNG stores it").click();
    harness.run_ok();
    let frames = workspace.path("frames");
    let field = harness.get_by_role_and_label(Role::TextInput, "Folder");
    field.focus();
    harness.run_ok();
    harness.key_press_modifiers(Modifiers::COMMAND, Key::A);
    harness.get_by_role_and_label(Role::TextInput, "Folder").type_text(&frames.display().to_string());
    harness.run_ok();
    harness.key_press(Key::Enter);
    harness.run_ok();
    harness.get_by_role_and_label(Role::Button, "Render").click();
    let deadline = std::time::Instant::now() + Duration::from_secs(240);
    while harness.query_by_label_contains("Rendered 3 frames").is_none() {
        assert!(std::time::Instant::now() < deadline, "the render finished");
        assert!(harness.query_by_label_contains("Could not render").is_none(), "the render failed");
        harness.step();
        std::thread::sleep(Duration::from_millis(20));
    }
    let mut names: Vec<String> =
        std::fs::read_dir(&frames).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    assert_eq!(names, ["carpet_0010.png", "carpet_0011.png", "carpet_0012.png"]);
    for name in names {
        let image = drape::image::RgbaImage::decode_png(&std::fs::read(frames.join(&name)).unwrap()).unwrap();
        assert_eq!((image.width, image.height), (96, 54), "{name}");
        assert_eq!(image.pixel(0, 0)[3], 0, "{name}: the corner is off the cloth, transparent");
    }
}

/// Help lists the manual's pages and shows the one chosen, in the window.
#[test]
fn help_shows_the_manuals_pages() {
    let workspace = Workspace::new();
    let mut harness = open_carpet(&workspace);
    harness.get_by_label("Help").click();
    harness.run_ok();
    let titles =
        ["Tutorials", "The editor", "Command line", "Exporting", "Scene files", "Rendering", "Blender", "How it works"];
    for title in titles {
        assert!(harness.query_by_label(title).is_some(), "Help lists {title}");
    }
    harness.get_by_label("Tutorials").click();
    harness.run_ok();
    assert!(harness.query_by_label_contains("Manual: Tutorials").is_some(), "the page's window opens");
    assert!(harness.query_by_label_contains("## Your first tablecloth (five minutes)").is_some(), "with its text");
}

/// Whether every corner of the box `min..max` is drawn inside the viewport.
fn box_on_screen(harness: &Harness<'_, DrapeApp>, (min, max): (glam::Vec3, glam::Vec3)) -> bool {
    let rect = harness.state().viewport_rect();
    drape::picture::framed::corners((min, max))
        .into_iter()
        .all(|corner| harness.state().screen_pos(corner).is_some_and(|p| rect.contains(p)))
}

/// The walker's box at `frame`, posed as drawn.
fn walker_box(scene: &Scene, frame: f64) -> (glam::Vec3, glam::Vec3) {
    let posed = drape::animate::references_at::reference_at(scene, 0, frame).expect("the walker was read");
    let points: Vec<glam::Vec3> = posed.meshes().iter().flat_map(|m| m.positions.iter().map(|p| p.as_vec3())).collect();
    drape::render::camera::bounds(&points).unwrap()
}

/// F frames the cloth with what it is pinned to: the cape with its wearer,
/// head to feet, not the cape alone.
#[test]
fn f_frames_the_cape_with_the_walker_wearing_it() {
    let workspace = Workspace::new();
    let mut harness = open_cape(&workspace);
    harness.state_mut().set_frame(9.0);
    settle(&mut harness);
    harness.key_press(Key::F);
    harness.run_ok();
    let walker = walker_box(harness.state().scene(), 9.0);
    assert!(box_on_screen(&harness, walker), "the walker is in view, head to feet: {walker:?}");
    assert!(cloth_on_screen(&harness));
}

/// The bundled cape opens on its saved view's angles, widened so that the
/// walker it is pinned to is in view head to feet, as a render of that view is.
#[test]
fn the_cape_opens_with_the_walker_whole() {
    let workspace = Workspace::new();
    let harness = open_cape(&workspace);
    let walker = walker_box(harness.state().scene(), 0.0);
    assert!(box_on_screen(&harness, walker), "the walker is in view, head to feet: {walker:?}");
    assert!(cloth_on_screen(&harness));
}

/// A scene with a shot camera opens looking through it (the bundled
/// carpet over its painted plate); turned off, it stays off while scrubbing
/// and when saved and reopened, and a scene without one opens on the
/// orbiting view.
#[test]
fn a_scene_with_a_shot_camera_opens_looking_through_it() {
    let workspace = Workspace::new();
    let carpet = workspace.path("carpet.ron");
    let mut harness = open_editor(&workspace, scene::load(&carpet).unwrap(), Some(carpet.clone()));
    assert!(harness.state().scene().camera.is_some());
    assert!(harness.state().looks_through_shot_camera(), "the carpet opens through its shot camera");
    let shot = drape::picture::scene_shot_camera_at(harness.state().scene(), 0.0, (1280, 720)).unwrap();
    assert_eq!(harness.state().camera().eye(), shot.eye(), "the viewport looks from the shot camera");
    harness.get_by_role_and_label(Role::Button, "Camera").click();
    harness.run_ok();
    assert!(!harness.state().looks_through_shot_camera());
    harness.state_mut().set_frame(60.0);
    settle(&mut harness);
    assert!(!harness.state().looks_through_shot_camera(), "the choice is kept");
    harness.key_press_modifiers(Modifiers::COMMAND, Key::S);
    harness.run_ok();
    open_through_the_menu(&mut harness, &carpet);
    settle(&mut harness);
    assert!(!harness.state().looks_through_shot_camera(), "and saved with the view");

    let without = open_editor(&workspace, new_scene(), None);
    assert!(!without.state().looks_through_shot_camera());
}

/// The round table, opened from the bundled file, with its top selected in the Colliders panel.
fn open_round_table_with_top_selected(workspace: &Workspace) -> Harness<'static, DrapeApp> {
    let path = std::fs::canonicalize("scenes/round_table.ron").unwrap();
    let mut harness = open_editor(workspace, scene::load(&path).unwrap(), Some(path));
    harness.get_by_label("top").click();
    harness.run_ok();
    assert_eq!(harness.state().selected_collider(), Some(0));
    harness
}

/// Presses the left button at `from` and moves to `to` in `steps` frames, holding it.
fn press_and_move(harness: &mut Harness<'_, DrapeApp>, from: Pos2, to: Pos2, steps: u32) {
    let press = |pressed, pos| Event::PointerButton {
        pos,
        button: PointerButton::Primary,
        pressed,
        modifiers: Modifiers::NONE,
    };
    harness.event(Event::PointerMoved(from));
    harness.step();
    harness.event(press(true, from));
    harness.step();
    for step in 1..=steps {
        harness.event(Event::PointerMoved(from.lerp(to, step as f32 / steps as f32)));
        harness.step();
    }
}

fn release(harness: &mut Harness<'_, DrapeApp>, at: Pos2) {
    harness.event(Event::PointerButton {
        pos: at,
        button: PointerButton::Primary,
        pressed: false,
        modifiers: Modifiers::NONE,
    });
    harness.step();
}

/// While a dragged collider's new cloth is solved, the old cloth is drawn
/// grey and the status bar says it is updating; once the shape is in, the
/// cloth is drawn as usual.
#[test]
fn a_dragged_collider_greys_the_old_cloth_until_the_new_shape_is_in() {
    use drape::editor::viewport::pin_drag::AxisLock;
    let workspace = Workspace::new();
    let mut harness = open_round_table_with_top_selected(&workspace);
    assert!(!harness.state().cloth_drawn_stale());
    let gizmo = harness.state().gizmo().expect("the table top's gizmo");
    let origin = harness.state().screen_pos(gizmo.origin).unwrap();
    let along = gizmo.tip(AxisLock::X).unwrap() - origin;
    let grab = origin + along * 0.7;
    let to = grab + along * 0.6;
    press_and_move(&mut harness, grab, to, 3);
    std::thread::sleep(drape::editor::viewport::stale_cloth::STALE_AFTER + Duration::from_millis(50));
    harness.step();
    assert_ne!(harness.state().scene(), harness.state().shown_scene(), "the new shape is being solved");
    assert!(harness.state().cloth_drawn_stale(), "the old cloth is drawn as stale during the drag");
    release(&mut harness, to);
    harness.step();
    assert!(harness.state().cloth_drawn_stale(), "and after it, until the shape is in");
    assert!(harness.query_by_label_contains("updating").is_some(), "the status bar says so");
    settle(&mut harness);
    assert_eq!(harness.state().scene(), harness.state().shown_scene());
    assert!(!harness.state().cloth_drawn_stale(), "the new shape is drawn as usual");
    assert!(harness.query_by_label_contains("updating").is_none());
}
