//! The editor window: a 3D viewport in the centre, view options on the left,
//! a timeline to scrub and play along the bottom.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use eframe::egui::{self, Key, PointerButton, Sense};
use eframe::egui_wgpu;
use glam::Vec2;

use super::viewport::{self, ViewportFrame};
use crate::animate::{Evaluator, frame_time_secs};
use crate::mesh::Mesh;
use crate::render::camera::bounds;
use crate::render::headless::{SceneOverlays, key_overlay, scene_bounds};
use crate::render::{Ground, OrbitCamera, Overlay, RenderOptions};
use crate::scene::{ClothTexture, Scene};

/// The scene the editor opens with when none is given: the paper's magic carpet.
pub const DEFAULT_SCENE: &str = include_str!("../../scenes/magic_carpet.ron");

/// Mouse-wheel points per dolly step.
const POINTS_PER_DOLLY_STEP: f32 = 50.0;

/// What the viewport shows besides the cloth.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ViewToggles {
    pub wireframe: bool,
    pub texture: bool,
    pub pins: bool,
    pub catenaries: bool,
    pub triangulation: bool,
    pub ground: bool,
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
        }
    }
}

pub struct DrapeApp {
    scene: Scene,
    /// Where the scene came from; `None` for the built-in default.
    path: Option<PathBuf>,
    evaluator: Evaluator,
    mesh: Arc<Mesh>,
    /// The frame the mesh shows (fractional while playing).
    frame: f64,
    mesh_frame: Option<f64>,
    playing: bool,
    play_started: Option<(Instant, f64)>,
    camera: OrbitCamera,
    ground: Ground,
    pub toggles: ViewToggles,
    /// CPU time of the last update, for the readout.
    last_update_ms: f64,
    /// Whether the GPU viewport is available (false only without wgpu, e.g. in some tests).
    has_viewport: bool,
    /// Frame the cloth once the viewport's shape is known (a scene without a saved view).
    frame_all_pending: bool,
}

impl DrapeApp {
    /// Opens `scene`, framing the camera on its keys (or using its saved view).
    pub fn new(scene: Scene, path: Option<PathBuf>, render_state: Option<&egui_wgpu::RenderState>) -> DrapeApp {
        if let Some(render_state) = render_state {
            viewport::install(render_state);
        }
        let mut evaluator = Evaluator::new();
        let (min, max) = scene_bounds(&mut evaluator, &scene);
        let camera = match &scene.view {
            Some(view) => OrbitCamera::from_view(view),
            None => OrbitCamera::framing(min, max, 16.0 / 9.0),
        };
        let scene_view_missing = scene.view.is_none();
        let frame = scene.timeline.start as f64;
        let mesh = Arc::new(evaluator.evaluate(&scene, frame_time_secs(&scene.timeline, frame)));
        DrapeApp {
            ground: Ground::under(min, max),
            scene,
            path,
            evaluator,
            mesh,
            frame,
            mesh_frame: Some(frame),
            playing: false,
            play_started: None,
            camera,
            toggles: ViewToggles::default(),
            last_update_ms: 0.0,
            has_viewport: render_state.is_some(),
            frame_all_pending: scene_view_missing,
        }
    }

    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    pub fn camera(&self) -> &OrbitCamera {
        &self.camera
    }

    pub fn frame(&self) -> f64 {
        self.frame
    }

    /// The mesh on screen: `evaluate` at [`DrapeApp::frame`].
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// Moves the playhead; the mesh follows on the next update.
    pub fn set_frame(&mut self, frame: f64) {
        let timeline = &self.scene.timeline;
        self.frame = frame.clamp(timeline.start as f64, timeline.end as f64);
        if self.playing {
            self.play_started = Some((Instant::now(), self.frame));
        }
    }

    fn refresh_mesh(&mut self) {
        if self.mesh_frame != Some(self.frame) {
            let t_secs = frame_time_secs(&self.scene.timeline, self.frame);
            // The last frame's paint callback has let go of the mesh by now, so this rarely copies.
            let mesh = Arc::make_mut(&mut self.mesh);
            self.evaluator.evaluate_into(&self.scene, t_secs, Default::default(), mesh);
            self.mesh_frame = Some(self.frame);
        }
    }

    fn advance_playback(&mut self, ctx: &egui::Context) {
        if !self.playing {
            return;
        }
        let timeline = &self.scene.timeline;
        let (started_at, started_frame) = *self.play_started.get_or_insert((Instant::now(), self.frame));
        let length = (timeline.end - timeline.start) as f64 + 1.0;
        let played = started_at.elapsed().as_secs_f64() * timeline.fps;
        // Loops over start..=end, holding whole frames like the scene's clock.
        let offset = (started_frame - timeline.start as f64 + played).rem_euclid(length).floor();
        self.frame = timeline.start as f64 + offset;
        ctx.request_repaint();
    }

    fn frame_all(&mut self, aspect: f32) {
        if let Some((min, max)) = bounds(&self.mesh.positions) {
            self.camera.frame_bounds(min, max, aspect);
        }
    }

    fn overlay(&mut self) -> Overlay {
        let show = SceneOverlays {
            wireframe: self.toggles.wireframe,
            pins: self.toggles.pins,
            catenaries: self.toggles.catenaries,
            triangulation: self.toggles.triangulation,
        };
        key_overlay(&mut self.evaluator, &self.scene, self.frame, &self.mesh, show)
    }

    fn render_options(&self) -> RenderOptions {
        let texture = if self.toggles.texture { self.scene.cloth.texture } else { ClothTexture::Plain };
        RenderOptions {
            wireframe: self.toggles.wireframe,
            ground: self.toggles.ground.then_some(self.ground),
            ..RenderOptions::default()
        }
        .with_texture(texture)
    }

    fn title(&self) -> String {
        let name = if self.scene.name.is_empty() { "untitled" } else { &self.scene.name };
        match &self.path {
            Some(path) => format!("{name} — {} — Drape", path.display()),
            None => format!("{name} — Drape"),
        }
    }

    fn view_panel(&mut self, ui: &mut egui::Ui) {
        ui.heading("View");
        ui.checkbox(&mut self.toggles.texture, "Texture");
        ui.checkbox(&mut self.toggles.wireframe, "Wireframe");
        ui.checkbox(&mut self.toggles.pins, "Pins");
        ui.checkbox(&mut self.toggles.catenaries, "Catenary network");
        ui.checkbox(&mut self.toggles.triangulation, "Triangulation");
        ui.checkbox(&mut self.toggles.ground, "Ground");
        ui.separator();
        ui.label("Middle-drag: orbit · Shift+middle-drag: pan");
        ui.label("Alt+left-drag: orbit · Wheel: dolly · F: frame all");
        ui.label("Space: play · Left/Right: step a frame · Home/End: first/last frame");
        ui.separator();
        ui.label(format!("Update {:.1} ms (CPU)", self.last_update_ms));
        let cloth = &self.scene.cloth;
        let plural = |n: usize, word: &str| format!("{n} {word}{}", if n == 1 { "" } else { "s" });
        let (keys, layers) = (plural(self.scene.keys.len(), "key"), plural(self.scene.layers.len(), "layer"));
        ui.label(format!("{} × {} grid, {keys}, {layers}", cloth.cols(), cloth.rows()));
    }

    fn timeline_panel(&mut self, ui: &mut egui::Ui) {
        let timeline = self.scene.timeline.clone();
        ui.horizontal(|ui| {
            let label = if self.playing { "Pause" } else { "Play" };
            if ui.button(label).clicked() {
                self.toggle_play();
            }
            let mut frame = self.frame.round() as i32;
            let slider = egui::Slider::new(&mut frame, timeline.start..=timeline.end).text("frame");
            ui.spacing_mut().slider_width = (ui.available_width() - 200.0).max(100.0);
            if ui.add(slider).changed() {
                self.set_frame(frame as f64);
            }
            ui.label(format!("{:.2} s @ {} fps", frame_time_secs(&timeline, self.frame), timeline.fps));
        });
    }

    fn toggle_play(&mut self) {
        self.playing = !self.playing;
        self.play_started = None;
    }

    fn keyboard(&mut self, ctx: &egui::Context, aspect: f32) {
        if ctx.egui_wants_keyboard_input() {
            return;
        }
        let timeline = self.scene.timeline.clone();
        let (space, left, right, home, end, f) = ctx.input(|i| {
            (
                i.key_pressed(Key::Space),
                i.key_pressed(Key::ArrowLeft),
                i.key_pressed(Key::ArrowRight),
                i.key_pressed(Key::Home),
                i.key_pressed(Key::End),
                i.key_pressed(Key::F),
            )
        });
        if space {
            self.toggle_play();
        }
        if left {
            self.set_frame(self.frame.round() - 1.0);
        }
        if right {
            self.set_frame(self.frame.round() + 1.0);
        }
        if home {
            self.set_frame(timeline.start as f64);
        }
        if end {
            self.set_frame(timeline.end as f64);
        }
        if f {
            self.frame_all(aspect);
        }
    }

    fn viewport(&mut self, ui: &mut egui::Ui) {
        let rect = ui.available_rect_before_wrap();
        let response = ui.allocate_rect(rect, Sense::click_and_drag());
        let aspect = rect.width() / rect.height().max(1.0);
        let delta = response.drag_delta();
        let delta = Vec2::new(delta.x, delta.y);
        let (shift, alt) = ui.input(|i| (i.modifiers.shift, i.modifiers.alt));
        if response.dragged_by(PointerButton::Middle) {
            if shift {
                self.camera.pan(delta, rect.height());
            } else {
                self.camera.orbit(delta);
            }
        } else if response.dragged_by(PointerButton::Primary) && alt {
            self.camera.orbit(delta);
        }
        if response.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            if scroll != 0.0 {
                self.camera.dolly(scroll / POINTS_PER_DOLLY_STEP);
            }
        }
        self.keyboard(ui.ctx(), aspect);
        self.refresh_mesh();
        if std::mem::take(&mut self.frame_all_pending) {
            self.frame_all(aspect);
        }
        if !self.has_viewport {
            return;
        }
        let pixels_per_point = ui.ctx().pixels_per_point();
        let size_px = (
            (rect.width() * pixels_per_point).round().max(1.0) as u32,
            (rect.height() * pixels_per_point).round().max(1.0) as u32,
        );
        let frame = ViewportFrame {
            mesh: self.mesh.clone(),
            camera: self.camera,
            options: self.render_options(),
            overlay: Arc::new(self.overlay()),
            size_px,
        };
        ui.painter().add(egui_wgpu::Callback::new_paint_callback(rect, frame));
    }
}

impl eframe::App for DrapeApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let started = Instant::now();
        let ctx = ui.ctx().clone();
        self.advance_playback(&ctx);
        ctx.send_viewport_cmd(egui::ViewportCommand::Title(self.title()));
        egui::Panel::bottom("timeline").show(ui, |ui| self.timeline_panel(ui));
        egui::Panel::left("view").show(ui, |ui| self.view_panel(ui));
        egui::CentralPanel::default().frame(egui::Frame::NONE).show(ui, |ui| self.viewport(ui));
        self.last_update_ms = started.elapsed().as_secs_f64() * 1e3;
    }
}

/// Opens the editor window on `scene` (the built-in magic carpet when `None`);
/// returns when the window closes.
pub fn run(scene: Scene, path: Option<PathBuf>) -> eframe::Result {
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default().with_inner_size([1280.0, 800.0]).with_title("Drape"),
        renderer: eframe::Renderer::Wgpu,
        ..Default::default()
    };
    eframe::run_native(
        "Drape",
        options,
        Box::new(move |cc| Ok(Box::new(DrapeApp::new(scene, path, cc.wgpu_render_state.as_ref())))),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::animate::evaluate;

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
            let expected = evaluate(app.scene(), frame_time_secs(&app.scene().timeline, frame));
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
}
