//! Attach by clicking, in the viewport: the click casts the pointer's ray
//! against the references as drawn at the frame shown, and the workspace
//! attaches the pin to the skin point it meets first.

use glam::Vec2;

use super::reference_pick::pick_reference_surface;
use super::{SolidLook, ViewportPanel};
use crate::editor::attach;
use crate::editor::workspace::Workspace;

impl ViewportPanel {
    /// A click at `pointer_px` while attaching by clicking: attaches the pin
    /// to the reference surface under it, or says there is none (staying in
    /// the mode). Hidden references are not clicked on.
    pub(super) fn attach_click(&self, w: &mut Workspace, pointer_px: Vec2, size_px: (u32, u32)) {
        if self.toggles.references == SolidLook::Hidden {
            w.report("References are hidden (the view bar's References): show them to click on one.".to_owned(), true);
            return;
        }
        let (origin, direction) = self.camera.ray(pointer_px, size_px);
        let hit = pick_reference_surface(w.doc.scene(), w.frame(), origin.as_dvec3(), direction.as_dvec3());
        attach::attach_clicked(w, hit);
    }
}
