//! The viewport's mouse and keys: camera navigation (Blender's conventions),
//! hovering a cloth point or a collider, clicking to pin and select,
//! dragging pins and colliders in the view plane or along a locked axis.

use eframe::egui::{self, PointerButton, Response};
use glam::{Vec2, Vec3};

use super::picking;
use super::picking::ColliderHit;
use super::pin_drag::{AxisLock, MovingPin, PinDrag, drag_keys};
use super::{SolidLook, ViewportPanel};
use crate::editor::attach;
use crate::editor::edits;
use crate::editor::selection::Pick;
use crate::editor::workspace::Workspace;

/// Mouse-wheel points per dolly step.
const POINTS_PER_DOLLY_STEP: f32 = 50.0;
/// How far behind a collider's surface a cloth point must be to be hidden
/// by it (m): cloth resting on a table, a thickness above it, stays pickable.
const HIDDEN_BEHIND_M: f64 = 0.02;
/// How close (in points) the pointer must be to a cloth point to hover it.
const PICK_RADIUS_PT: f32 = 10.0;

impl ViewportPanel {
    /// Camera navigation, hover and pin editing for this frame's pointer.
    pub(super) fn pointer_input(&mut self, ui: &egui::Ui, w: &mut Workspace, response: &Response, size_px: (u32, u32)) {
        let rect = response.rect;
        let delta = response.drag_delta();
        let delta = Vec2::new(delta.x, delta.y);
        let (shift, alt) = ui.input(|i| (i.modifiers.shift, i.modifiers.alt));
        let navigates = response.dragged_by(PointerButton::Middle)
            || (response.dragged_by(PointerButton::Primary) && alt && self.pin_drag.is_none())
            || (response.hovered() && ui.input(|i| i.smooth_scroll_delta.y) != 0.0);
        if navigates {
            // Moving the view leaves the shot camera's (it goes on from where it was).
            if w.session.through_camera() {
                w.session.look_through_camera(false);
                self.orbit_before_shot = None;
                self.frame_all_pending = false;
                self.reveal_pending = false;
            }
        }
        if response.dragged_by(PointerButton::Middle) {
            if shift {
                self.camera.pan(delta, rect.height());
            } else {
                self.camera.orbit(delta);
            }
        } else if response.dragged_by(PointerButton::Primary)
            && alt
            && self.pin_drag.is_none()
            && self.collider_drag.is_none()
        {
            self.camera.orbit(delta);
        }
        if response.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            if scroll != 0.0 {
                self.camera.dolly(scroll / POINTS_PER_DOLLY_STEP);
            }
        }

        let pixels_per_point = ui.ctx().pixels_per_point();
        let to_px = |pos: egui::Pos2| Vec2::new(pos.x - rect.left(), pos.y - rect.top()) * pixels_per_point;
        let pointer_px = response.hover_pos().or(response.interact_pointer_pos()).map(to_px);

        // Hover: the cloth point under the mouse, when the grid on screen is
        // the document's; else the collider there.
        w.session.hover(None);
        self.hovered_collider = None;
        if let Some(pointer) = pointer_px
            && self.pin_drag.is_none()
            && self.collider_drag.is_none()
            && w.session.attaching().is_none()
            && response.hovered()
        {
            let (point, collider) = self.under_pointer(w, pointer, size_px, pixels_per_point);
            w.session.hover(point);
            self.hovered_collider = collider.map(|(index, _)| index);
        }

        if self.pin_drag.is_some() {
            self.continue_pin_drag(ui, w, response, size_px, pointer_px);
            return;
        }
        if self.collider_drag.is_some() {
            self.continue_collider_drag(ui, w, response, size_px, pointer_px);
            return;
        }
        if alt {
            return;
        }
        if w.session.attaching().is_some() {
            // The mode takes the primary button: a click attaches, a drag does nothing.
            if response.clicked_by(PointerButton::Primary)
                && let Some(pointer) = pointer_px
            {
                self.attach_click(w, pointer, size_px);
            }
            return;
        }
        if self.box_select.is_some() {
            self.continue_box_select(ui, w, response, size_px);
            return;
        }
        if response.drag_started_by(PointerButton::Primary) {
            // The drag starts where the button went down, a few pixels before egui calls it a drag.
            let origin = ui.input(|i| i.pointer.press_origin());
            if let Some(press) = origin
                && let Some(gizmo) = self.gizmo(w, size_px)
                && let Some(axis) = gizmo.axis_at(press)
            {
                if w.session.selection().is_empty() {
                    // No pin selected: the gizmo is the selected collider's.
                    let along =
                        picking::drag_along_axis(&self.camera, size_px, gizmo.origin, axis.vector(), to_px(press));
                    if let (Some(index), Some(anchor)) = (w.session.selected_collider(), along) {
                        self.start_collider_drag(w, index, anchor, Some(axis));
                        self.continue_collider_drag(ui, w, response, size_px, pointer_px);
                    }
                    return;
                }
                self.start_gizmo_drag(w, gizmo.origin, axis, to_px(press), size_px);
                self.continue_pin_drag(ui, w, response, size_px, pointer_px);
                return;
            }
            let (grabbed, collider) = match origin.map(to_px) {
                Some(at) => self.under_pointer(w, at, size_px, pixels_per_point),
                None => (None, None),
            };
            match grabbed {
                Some(point) if edits::is_pinned(&w.doc.scene().keys[w.edit_key_index()], point) => {
                    self.start_pin_drag(w, point, shift);
                    self.continue_pin_drag(ui, w, response, size_px, pointer_px);
                }
                // Off the cloth, on a collider: the collider follows the mouse.
                None if let Some(press) = origin.map(to_px)
                    && let Some((index, along_m)) = collider =>
                {
                    let (eye, direction) = self.camera.ray(press, size_px);
                    self.start_collider_drag(w, index, eye + direction * along_m as f32, None);
                    self.continue_collider_drag(ui, w, response, size_px, pointer_px);
                }
                // Off the pins a drag draws a box round the pins to select.
                _ => self.box_select = origin,
            }
            return;
        }
        if response.clicked_by(PointerButton::Primary) {
            // A click on a gizmo arrow is not a click on the cloth behind it.
            let on_gizmo = response.interact_pointer_pos().zip(self.gizmo(w, size_px)).and_then(|(p, g)| g.axis_at(p));
            if on_gizmo.is_some() {
                return;
            }
            let how = Pick::from_modifiers(crate::editor::panels::grid_editor::click_modifiers(ui));
            // A plain click selects what it hits and nothing else: pins or one collider.
            let replace = how == Pick::Replace;
            match (w.session.hovered(), self.hovered_collider) {
                (Some(point), _) if edits::is_pinned(&w.doc.scene().keys[w.edit_key_index()], point) => {
                    w.session.pick_pins(&[point], how);
                    if replace {
                        w.session.select_collider(None);
                    }
                }
                (Some(point), _) => w.pin_here(point, how),
                (None, Some(index)) => {
                    if replace {
                        w.session.let_go_of_pins_and_key();
                    }
                    let again = w.session.selected_collider() == Some(index) && how == Pick::Toggle;
                    w.session.select_collider(if again { None } else { Some(index) });
                }
                (None, None) => {
                    w.session.click_on_nothing(how);
                    if replace {
                        w.session.select_collider(None);
                    }
                }
            }
        }
    }

    /// Draws the selection box while the button is held; on release, picks
    /// the pins drawn inside it (Shift adds, Ctrl toggles).
    fn continue_box_select(&mut self, ui: &egui::Ui, w: &mut Workspace, response: &Response, size_px: (u32, u32)) {
        let (Some(start), Some(now)) = (self.box_select, response.interact_pointer_pos().or(response.hover_pos()))
        else {
            self.box_select = None;
            return;
        };
        let area = egui::Rect::from_two_pos(start, now);
        let color = ui.visuals().selection.stroke.color;
        let painter = ui
            .painter()
            .clone()
            .with_layer_id(egui::LayerId::new(egui::Order::Foreground, egui::Id::unique("box-select")));
        painter.rect(area, 0.0, color.gamma_multiply(0.12), egui::Stroke::new(1.0, color), egui::StrokeKind::Middle);
        if !response.drag_stopped() && ui.input(|i| i.pointer.primary_down()) {
            return;
        }
        self.box_select = None;
        if !w.shown_grid_is_current() {
            return;
        }
        let how = Pick::from_modifiers(crate::editor::panels::grid_editor::click_modifiers(ui));
        let rect = response.rect;
        let cols = w.shown.scene().cloth.cols();
        let key = &w.doc.scene().keys[w.edit_key_index()];
        let points_per_px = rect.width() / size_px.0.max(1) as f32;
        let inside: Vec<(u32, u32)> = key
            .pins
            .iter()
            .map(|p| p.grid)
            .filter(|&(i, j)| {
                let Some(&at) = w.shown.mesh().positions.get(j as usize * cols + i as usize) else { return false };
                self.camera
                    .project(at, size_px)
                    .is_some_and(|px| area.contains(rect.min + egui::vec2(px.x, px.y) * points_per_px))
            })
            .collect();
        w.session.pick_pins(&inside, how);
    }

    /// What the pointer is over: a cloth point (see [`Self::point_at`]) or
    /// else a collider, with how far along the ray it is met (m). A collider
    /// in front of the cloth hides the cloth points behind it; pins, drawn
    /// over everything, are never hidden.
    fn under_pointer(
        &self,
        w: &Workspace,
        pointer_px: Vec2,
        size_px: (u32, u32),
        pixels_per_point: f32,
    ) -> (Option<(u32, u32)>, Option<ColliderHit>) {
        let point =
            if w.shown_grid_is_current() { self.point_at(w, pointer_px, size_px, pixels_per_point) } else { None };
        // A pin wins without tracing the colliders.
        if point.is_some_and(|grid| edits::is_pinned(&w.doc.scene().keys[w.edit_key_index()], grid)) {
            return (point, None);
        }
        let collider = self.collider_at(w, pointer_px, size_px);
        let Some(grid) = point else { return (None, collider) };
        let Some((_, along_m)) = collider else { return (point, None) };
        let cols = w.shown.scene().cloth.cols();
        let at = w.shown.mesh().positions.get(grid.1 as usize * cols + grid.0 as usize);
        let depth_m = at.map_or(f32::INFINITY, |p| p.distance(self.camera.eye()));
        if along_m + HIDDEN_BEHIND_M < f64::from(depth_m) { (None, collider) } else { (point, None) }
    }

    /// The collider drawn under `pointer_px` and how far along the ray (m);
    /// none while colliders are hidden.
    fn collider_at(&self, w: &Workspace, pointer_px: Vec2, size_px: (u32, u32)) -> Option<ColliderHit> {
        if self.toggles.colliders == SolidLook::Hidden {
            return None;
        }
        picking::pick_collider(&self.camera, size_px, w.doc.scene(), w.frame(), pointer_px)
    }

    /// The grid point under `pointer_px`: a pin of the key being edited when
    /// one is that close (pins are drawn over the cloth, so they win even
    /// behind a fold), else the nearest cloth point on the front layer.
    fn point_at(
        &self,
        w: &Workspace,
        pointer_px: Vec2,
        size_px: (u32, u32),
        pixels_per_point: f32,
    ) -> Option<(u32, u32)> {
        let radius_px = PICK_RADIUS_PT * pixels_per_point;
        let cols = w.shown.scene().cloth.cols();
        let key = &w.doc.scene().keys[w.edit_key_index()];
        let pins: Vec<(u32, u32)> = key.pins.iter().map(|p| p.grid).collect();
        let pin_positions: Vec<Vec3> = pins
            .iter()
            .map(|&(i, j)| w.shown.mesh().positions.get(j as usize * cols + i as usize).copied().unwrap_or(Vec3::NAN))
            .collect();
        let nearest_pin = pins.iter().zip(&pin_positions).enumerate().min_by(|a, b| {
            let distance =
                |p: Vec3| self.camera.project(p, size_px).map_or(f32::INFINITY, |at| at.distance(pointer_px));
            distance(*a.1.1).total_cmp(&distance(*b.1.1))
        });
        if let Some((_, (&grid, &position))) = nearest_pin
            && self.camera.project(position, size_px).is_some_and(|at| at.distance(pointer_px) <= radius_px)
        {
            return Some(grid);
        }
        let index = picking::pick_vertex(&self.camera, size_px, &w.shown.mesh().positions, pointer_px, radius_px)?;
        Some(((index % cols) as u32, (index / cols) as u32))
    }

    fn start_pin_drag(&mut self, w: &mut Workspace, grabbed: (u32, u32), add: bool) {
        if !w.session.selection().contains(&grabbed) {
            w.session.pick_pins(&[grabbed], if add { Pick::Add } else { Pick::Replace });
        }
        let Some((index, pins)) = begin_selected_pins_drag(w) else { return };
        let Some(start) = pins.iter().find(|p| p.start.grid == grabbed) else { return };
        let anchor = start.from.as_vec3();
        self.pin_drag = Some(PinDrag { grabbed, anchor, pins, lock: None, key: index, by_gizmo: false });
    }

    /// A drag on the gizmo's `axis` arrow: the selected pins move along it,
    /// from the point of the axis under `press_px`.
    fn start_gizmo_drag(
        &mut self,
        w: &mut Workspace,
        gizmo_origin: Vec3,
        axis: AxisLock,
        press_px: Vec2,
        size_px: (u32, u32),
    ) {
        let Some(anchor) = picking::drag_along_axis(&self.camera, size_px, gizmo_origin, axis.vector(), press_px)
        else {
            return;
        };
        let Some((index, pins)) = begin_selected_pins_drag(w) else { return };
        let Some(grabbed) = pins.first().map(|p| p.start.grid) else { return };
        self.pin_drag = Some(PinDrag { grabbed, anchor, pins, lock: Some(axis), key: index, by_gizmo: true });
    }

    fn continue_pin_drag(
        &mut self,
        ui: &egui::Ui,
        w: &mut Workspace,
        response: &Response,
        size_px: (u32, u32),
        pointer: Option<Vec2>,
    ) {
        let Some(drag) = &mut self.pin_drag else { return };
        let escape = drag_keys(ui, &mut drag.lock);
        let (key, pins) = (drag.key, drag.pins.clone());
        if escape {
            // Back as they were (attached too): the gesture then changed nothing and leaves no undo step.
            let starts: Vec<_> = pins.iter().map(|p| p.start.clone()).collect();
            w.apply("Move pin", |s| edits::restore_pins(&mut s.keys[key], &starts));
            self.finish_pin_drag(w);
            return;
        }
        if let Some(pointer) = pointer
            && let Some(drag) = &self.pin_drag
            && let Some(moved) = picking::drag_point(&self.camera, size_px, drag.anchor, drag.lock, pointer)
        {
            let offset = (moved - drag.anchor).as_dvec3();
            let label = if pins.len() == 1 { "Move pin" } else { "Move pins" };
            let moves: Vec<_> = pins.iter().map(|p| (p.start.grid, p.from + offset)).collect();
            attach::move_pins(w, label, key, &moves);
        }
        if response.drag_stopped() || !ui.input(|i| i.pointer.primary_down()) {
            self.finish_pin_drag(w);
        }
    }

    fn finish_pin_drag(&mut self, w: &mut Workspace) {
        self.pin_drag = None;
        w.end_gesture();
    }
}

/// Opens the undo step of a drag of the selected pins and returns the key
/// it moves (with auto-key off a key, a new key at the playhead) and the
/// selected pins as they start (attached ones where their attachments hold
/// them at the key's frame); `None` when no key can be made.
fn begin_selected_pins_drag(w: &mut Workspace) -> Option<(usize, Vec<MovingPin>)> {
    let label = if w.session.selection().len() == 1 { "Move pin" } else { "Move pins" };
    w.doc.begin_gesture(label);
    let index = w.key_to_edit(label)?;
    let key = &w.doc.scene().keys[index];
    let selected = key.pins.iter().filter(|p| w.session.selection().contains(&p.grid));
    let pins =
        selected.map(|p| MovingPin { start: p.clone(), from: attach::pin_at_key(w.doc.scene(), key, p) }).collect();
    Some((index, pins))
}
