//! The viewport's side of the shot camera: looking through it at the
//! playhead, and the View menu's items ([`super::shot_view`] has the verbs).

use eframe::egui;

use super::plate_view::PlateShown;
use super::shot_view::{camera_from_view, frame_rect, key_camera, through};
use super::viewport_panel::ViewportPanel;
use super::workspace::Workspace;
use crate::animate::track::sample;
use crate::render::RenderOptions;

impl ViewportPanel {
    /// While looking through the shot camera, the viewport's camera is the
    /// shot camera at the playhead; without a camera in the scene the look
    /// is turned off.
    pub(super) fn look_through_shot(&mut self, w: &Workspace, rect: egui::Rect) {
        if !self.toggles.shot_camera {
            return;
        }
        match &w.doc.scene().camera {
            Some(camera) => self.camera = through(camera, w.frame(), rect),
            None => self.toggles.shot_camera = false,
        }
    }

    /// The View menu's shot-camera items: look through it, set it from the
    /// view, key it at the playhead.
    pub fn shot_camera_menu_ui(&mut self, ui: &mut egui::Ui, w: &mut Workspace) {
        let has = w.doc.scene().camera.is_some();
        let look = egui::Button::new("Look through camera").selected(self.toggles.shot_camera);
        let toggle = ui.add_enabled(has, look);
        if toggle.on_hover_text("The viewport shows the shot camera's picture (orbiting leaves it)").clicked() {
            self.toggles.shot_camera = !self.toggles.shot_camera;
            ui.close();
        }
        let label = if has { "Camera from view" } else { "Add camera from view" };
        let hint = "The shot camera looks from where the viewport does, at what it looks at \
                    (keyed at the playhead where its numbers are keyed, or with Auto key)";
        if ui.add_enabled(!self.toggles.shot_camera, egui::Button::new(label)).on_hover_text(hint).clicked() {
            camera_from_view(w, &self.camera);
            ui.close();
        }
        let key = ui.add_enabled(has, egui::Button::new("Key camera at playhead"));
        if key.on_hover_text("Key its position, target and focal length where they are now").clicked() {
            key_camera(w);
            ui.close();
        }
    }

    /// Paints the background plate behind where the cloth will be drawn,
    /// filling the shot camera's frame, when looking through the camera with
    /// the plate on; returns whether it did (the cloth then comes over it
    /// with alpha). While the first picture loads, or when the plate cannot
    /// be read, the frame says so instead.
    pub(super) fn plate_backdrop_ui(&mut self, ui: &egui::Ui, w: &Workspace, rect: egui::Rect) -> bool {
        if !self.toggles.shot_camera || !self.toggles.plate {
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
