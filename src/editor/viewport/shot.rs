//! The viewport's side of the shot camera: looking through it at the
//! playhead, and the View menu's items ([`super::shot_view`] has the verbs),
//! a reference's cameras among them.

use eframe::egui;

use super::ViewportPanel;
use super::plate_view::PlateShown;
use super::shot_view::{
    camera_from_reference, camera_from_view, detach_camera, frame_rect, key_camera, reference_cameras, through,
};
use crate::animate::track::sample;
use crate::editor::workspace::Workspace;
use crate::render::RenderOptions;

impl ViewportPanel {
    /// While looking through the shot camera, the viewport's camera is the
    /// shot camera at the playhead (a reference's camera it follows posed
    /// there); without a camera in the scene the look is turned off.
    /// The orbiting camera is kept meanwhile, and comes back when the
    /// *Camera* toggle is turned off.
    pub(super) fn look_through_shot(&mut self, w: &mut Workspace, rect: egui::Rect) {
        if !w.session.through_camera() {
            if let Some(orbit) = self.orbit_before_shot.take() {
                self.camera = orbit;
            }
            return;
        }
        self.orbit_before_shot.get_or_insert(self.camera);
        let scene = w.doc.scene();
        match &scene.camera {
            Some(camera) => self.camera = through(scene, camera, w.frame(), rect),
            None => w.session.look_through_camera(false),
        }
    }

    /// The View menu's shot-camera items: look through it, set it from the
    /// view, key it at the playhead, follow a camera of a reference (one
    /// flat item per camera: nested submenus missed real clicks) or let go
    /// of it. Setting and keying do not apply while it follows one.
    pub fn shot_camera_menu_ui(&mut self, ui: &mut egui::Ui, w: &mut Workspace) {
        let camera = w.doc.scene().camera.as_ref();
        let has = camera.is_some();
        let following = camera.and_then(|c| c.from_reference.clone());
        let look = egui::Button::new("Look through camera").selected(w.session.through_camera());
        let toggle = ui.add_enabled(has, look);
        if toggle.on_hover_text("The viewport shows the shot camera's picture (orbiting leaves it)").clicked() {
            w.session.look_through_camera(!w.session.through_camera());
            ui.close();
        }
        let not_now = following.as_ref().map(|from| {
            format!(
                "The camera follows {} of reference {:?}: Detach camera from reference first",
                from.camera, from.reference
            )
        });
        let label = if has { "Camera from view" } else { "Add camera from view" };
        let hint = "The shot camera looks from where the viewport does, at what it looks at \
                    (keyed at the playhead where its numbers are keyed, or with Auto key)";
        let from_view = ui.add_enabled(!w.session.through_camera() && not_now.is_none(), egui::Button::new(label));
        let from_view = match &not_now {
            Some(why) => from_view.on_disabled_hover_text(why),
            None => from_view.on_hover_text(hint),
        };
        if from_view.clicked() {
            camera_from_view(w, &self.camera);
            ui.close();
        }
        let key = ui.add_enabled(has && not_now.is_none(), egui::Button::new("Key camera at playhead"));
        let key = match &not_now {
            Some(why) => key.on_disabled_hover_text(why),
            None => key.on_hover_text("Key its position, target and focal length where they are now"),
        };
        if key.clicked() {
            key_camera(w);
            ui.close();
        }
        for from in reference_cameras(w.doc.scene()) {
            let chosen = following.as_ref() == Some(&from);
            let item = egui::Button::new(format!("Camera from {} · {}", from.reference, from.camera)).selected(chosen);
            let hint = "The shot camera follows this camera of the reference at every frame \
                        (its roll is left out: the picture stays level)";
            if ui.add(item).on_hover_text(hint).clicked() {
                if !chosen {
                    camera_from_reference(w, from);
                }
                ui.close();
            }
        }
        if following.is_some() {
            let hint = "A camera of its own where the reference's camera is at the playhead (nothing keyed)";
            if ui.button("Detach camera from reference").on_hover_text(hint).clicked() {
                detach_camera(w);
                ui.close();
            }
        }
    }

    /// Paints the background plate behind where the cloth will be drawn,
    /// filling the shot camera's frame, when looking through the camera with
    /// the plate on; returns whether it did (the cloth then comes over it
    /// with alpha). While the first picture loads, or when the plate cannot
    /// be read, the frame says so instead.
    pub(super) fn plate_backdrop_ui(&mut self, ui: &egui::Ui, w: &Workspace, rect: egui::Rect) -> bool {
        if !w.session.through_camera() || !self.toggles.plate {
            return false;
        }
        let scene = w.doc.scene();
        let (Some(camera), Some(plate)) = (&scene.camera, &scene.plate) else {
            return false;
        };
        let painter = ui.painter_at(rect);
        let [r, g, b] = RenderOptions::default().background;
        painter.rect_filled(rect, 0.0, egui::Rgba::from_rgb(r, g, b));
        let frame = frame_rect(camera, rect);
        let opacity = (sample(&plate.opacity, w.frame()) as f32).clamp(0.0, 1.0) * self.plate_view.opacity;
        match self.plate_view.shown(ui.ctx(), plate, &w.doc.folder(), w.frame()) {
            PlateShown::Picture(texture, [width, height]) => {
                // Cover the frame as renders do: the picture's shape kept, the overhang cropped evenly.
                let (plate_aspect, frame_aspect) =
                    (width as f32 / height.max(1) as f32, frame.width() / frame.height().max(1.0));
                let uv = if plate_aspect > frame_aspect {
                    let inset = 0.5 * (1.0 - frame_aspect / plate_aspect);
                    egui::Rect::from_min_max(egui::pos2(inset, 0.0), egui::pos2(1.0 - inset, 1.0))
                } else {
                    let inset = 0.5 * (1.0 - plate_aspect / frame_aspect);
                    egui::Rect::from_min_max(egui::pos2(0.0, inset), egui::pos2(1.0, 1.0 - inset))
                };
                painter.image(texture, frame, uv, egui::Color32::WHITE.gamma_multiply(opacity));
            }
            PlateShown::Loading => self.plate_note = Some(("Loading the plate…".to_owned(), egui::Color32::GRAY)),
            PlateShown::Error(why) => self.plate_note = Some((why, egui::Color32::from_rgb(240, 140, 120))),
        }
        true
    }

    /// What [`Self::plate_backdrop_ui`] had to say instead of a picture, at
    /// the top of the camera's frame, over the cloth.
    pub(super) fn plate_note_ui(&mut self, ui: &mut egui::Ui, w: &Workspace, rect: egui::Rect) {
        let (Some((text, color)), Some(camera)) = (self.plate_note.take(), &w.doc.scene().camera) else {
            return;
        };
        let frame = frame_rect(camera, rect).shrink(12.0);
        let area = egui::Rect::from_min_size(frame.min, egui::vec2(frame.width(), 48.0));
        ui.put(area, egui::Label::new(egui::RichText::new(text).color(color)).wrap());
    }
}
