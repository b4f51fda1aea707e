//! The viewport's side of the shot camera: looking through it at the
//! playhead, and the View menu's items ([`super::shot_view`] has the verbs).

use eframe::egui;

use super::shot_view::{camera_from_view, key_camera, through};
use super::viewport_panel::ViewportPanel;
use super::workspace::Workspace;

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
}
