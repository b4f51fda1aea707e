//! A collider dragged in the viewport: grabbed by its body (in the view
//! plane) or by a gizmo arrow (along that axis), X / Y / Z locking the drag
//! to an axis and Esc putting it back, as a pin drag does. The move is
//! written at the playhead like typing its position in the Colliders panel:
//! keyed positions get a key there, constant ones change (or are keyed, with
//! auto-key). The whole drag is one undo step.

use eframe::egui::{self, Response};
use glam::{Vec2, Vec3};

use super::ViewportPanel;
use super::collider_drag::ColliderDrag;
use super::picking;
use super::pin_drag::{AxisLock, drag_keys};
use crate::editor::edits;
use crate::editor::workspace::Workspace;

impl ViewportPanel {
    /// Starts dragging collider `index` from the world point `anchor`
    /// (selecting it alone); opens the drag's undo step.
    pub(super) fn start_collider_drag(
        &mut self,
        w: &mut Workspace,
        index: usize,
        anchor: Vec3,
        lock: Option<AxisLock>,
    ) {
        let Some(start) = w.doc.scene().colliders.get(index).cloned() else { return };
        w.session.select_collider(Some(index));
        w.session.let_go_of_pins_and_key();
        w.doc.begin_gesture("Move collider");
        let frame = w.frame().round() as i32;
        self.collider_drag = Some(ColliderDrag { index, anchor, start, frame, lock, by_gizmo: lock.is_some() });
    }

    /// Follows the mouse with the dragged collider; X / Y / Z lock or free
    /// an axis, Esc puts it back (no undo step), releasing the button ends it.
    pub(super) fn continue_collider_drag(
        &mut self,
        ui: &egui::Ui,
        w: &mut Workspace,
        response: &Response,
        size_px: (u32, u32),
        pointer: Option<Vec2>,
    ) {
        let Some(drag) = &mut self.collider_drag else { return };
        let escape = drag_keys(ui, &mut drag.lock);
        let (index, start) = (drag.index, drag.start.clone());
        if escape {
            w.apply("Move collider", |s| {
                if let Some(c) = s.colliders.get_mut(index) {
                    *c = start;
                }
            });
            self.finish_collider_drag(w);
            return;
        }
        if let Some(pointer) = pointer
            && let Some(moved) = picking::drag_point(&self.camera, size_px, drag.anchor, drag.lock, pointer)
        {
            let offset = (moved - drag.anchor).as_dvec3();
            let moved = edits::moved_collider(&start, offset, drag.frame, w.session.auto_key());
            w.apply("Move collider", |s| {
                if let Some(c) = s.colliders.get_mut(index) {
                    *c = moved;
                }
            });
        }
        if response.drag_stopped() || !ui.input(|i| i.pointer.primary_down()) {
            self.finish_collider_drag(w);
        }
    }

    fn finish_collider_drag(&mut self, w: &mut Workspace) {
        self.collider_drag = None;
        w.end_gesture();
    }
}
