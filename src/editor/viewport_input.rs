//! The viewport's mouse and keys: camera navigation (Blender's conventions),
//! hovering a cloth point, clicking to pin and select, dragging pins in the
//! view plane or along a locked axis.

use eframe::egui::{self, Key, PointerButton, Response};
use glam::{Vec2, Vec3};

use super::app::DrapeApp;
use super::{edits, picking};

/// Mouse-wheel points per dolly step.
const POINTS_PER_DOLLY_STEP: f32 = 50.0;
/// How close (in points) the pointer must be to a cloth point to hover it.
const PICK_RADIUS_PT: f32 = 10.0;

/// A world axis a dragged pin is locked to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AxisLock {
    X,
    Y,
    Z,
}

impl AxisLock {
    pub fn vector(self) -> Vec3 {
        match self {
            AxisLock::X => Vec3::X,
            AxisLock::Y => Vec3::Y,
            AxisLock::Z => Vec3::Z,
        }
    }
}

/// A pin being dragged: its grid point and its position when the drag began.
pub type MovingPin = ((u32, u32), (f64, f64, f64));

/// A drag of one or more pins, from where they were when it began.
pub struct PinDrag {
    /// The pin under the mouse and its start position.
    pub grabbed: (u32, u32),
    pub anchor: Vec3,
    /// Every moving pin with its start position.
    pub pins: Vec<MovingPin>,
    pub lock: Option<AxisLock>,
    /// Key index the pins belong to.
    pub key: usize,
}

impl DrapeApp {
    /// Camera navigation, hover and pin editing for this frame's pointer.
    pub(super) fn viewport_input(&mut self, ui: &egui::Ui, response: &Response, size_px: (u32, u32)) {
        let rect = response.rect;
        let delta = response.drag_delta();
        let delta = Vec2::new(delta.x, delta.y);
        let (shift, alt) = ui.input(|i| (i.modifiers.shift, i.modifiers.alt));
        if response.dragged_by(PointerButton::Middle) {
            if shift {
                self.camera.pan(delta, rect.height());
            } else {
                self.camera.orbit(delta);
            }
        } else if response.dragged_by(PointerButton::Primary) && alt && self.pin_drag.is_none() {
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

        // Hover: the cloth point under the mouse, when the grid on screen is the document's.
        let same_grid = self.shown.cloth.grid == self.doc.scene().cloth.grid;
        self.hovered = None;
        if let Some(pointer) = pointer_px
            && self.pin_drag.is_none()
            && same_grid
            && response.hovered()
        {
            self.hovered = self.point_at(pointer, size_px, pixels_per_point);
        }

        if self.pin_drag.is_some() {
            self.continue_pin_drag(ui, response, size_px, pointer_px);
            return;
        }
        if alt {
            return;
        }
        if response.drag_started_by(PointerButton::Primary) {
            // The drag starts where the button went down, a few pixels before egui calls it a drag.
            let origin = ui.input(|i| i.pointer.press_origin()).map(to_px);
            let grabbed = origin.filter(|_| same_grid).and_then(|at| self.point_at(at, size_px, pixels_per_point));
            if let Some(point) = grabbed
                && edits::is_pinned(&self.doc.scene().keys[self.edit_key_index()], point)
            {
                self.start_pin_drag(point, shift);
                self.continue_pin_drag(ui, response, size_px, pointer_px);
            }
            return;
        }
        if response.clicked_by(PointerButton::Primary) {
            let shift = super::grid_editor::click_modifiers(ui).shift;
            match self.hovered {
                Some(point) => {
                    let key = &self.doc.scene().keys[self.edit_key_index()];
                    if edits::is_pinned(key, point) {
                        self.select(point, shift);
                    } else {
                        self.toggle_pin(point);
                    }
                }
                None if !shift => self.selection.clear(),
                None => {}
            }
        }
    }

    /// The grid point under `pointer_px`: a pin of the key being edited when
    /// one is that close (pins are drawn over the cloth, so they win even
    /// behind a fold), else the nearest cloth point on the front layer.
    fn point_at(&self, pointer_px: Vec2, size_px: (u32, u32), pixels_per_point: f32) -> Option<(u32, u32)> {
        let radius_px = PICK_RADIUS_PT * pixels_per_point;
        let cols = self.shown.cloth.cols();
        let key = &self.doc.scene().keys[self.edit_key_index()];
        let pins: Vec<(u32, u32)> = key.pins.iter().map(|p| p.grid).collect();
        let pin_positions: Vec<Vec3> = pins
            .iter()
            .map(|&(i, j)| self.mesh.positions.get(j as usize * cols + i as usize).copied().unwrap_or(Vec3::NAN))
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
        let index = picking::pick_vertex(&self.camera, size_px, &self.mesh.positions, pointer_px, radius_px)?;
        Some(((index % cols) as u32, (index / cols) as u32))
    }

    fn select(&mut self, point: (u32, u32), add: bool) {
        if add {
            match self.selection.iter().position(|p| *p == point) {
                Some(at) => {
                    self.selection.remove(at);
                }
                None => self.selection.push(point),
            }
        } else {
            self.selection = vec![point];
        }
    }

    fn start_pin_drag(&mut self, grabbed: (u32, u32), add: bool) {
        if !self.selection.contains(&grabbed) {
            self.select(grabbed, add);
        }
        let index = self.edit_key_index();
        let key = &self.doc.scene().keys[index];
        let pins: Vec<_> =
            key.pins.iter().filter(|p| self.selection.contains(&p.grid)).map(|p| (p.grid, p.pos)).collect();
        let Some(&(_, start)) = pins.iter().find(|(grid, _)| *grid == grabbed) else { return };
        let anchor = Vec3::new(start.0 as f32, start.1 as f32, start.2 as f32);
        self.doc.begin_gesture(if pins.len() == 1 { "Move pin" } else { "Move pins" });
        self.pin_drag = Some(PinDrag { grabbed, anchor, pins, lock: None, key: index });
    }

    fn continue_pin_drag(&mut self, ui: &egui::Ui, response: &Response, size_px: (u32, u32), pointer: Option<Vec2>) {
        let Some(drag) = &mut self.pin_drag else { return };
        let (x, y, z, escape) = ui.input(|i| {
            (i.key_pressed(Key::X), i.key_pressed(Key::Y), i.key_pressed(Key::Z), i.key_pressed(Key::Escape))
        });
        for (pressed, axis) in [(x, AxisLock::X), (y, AxisLock::Y), (z, AxisLock::Z)] {
            if pressed {
                drag.lock = if drag.lock == Some(axis) { None } else { Some(axis) };
            }
        }
        let (key, pins) = (drag.key, drag.pins.clone());
        if escape {
            // Back where they were: the gesture then changed nothing and leaves no undo step.
            self.apply("Move pin", |s| {
                for (grid, pos) in &pins {
                    edits::move_pin(&mut s.keys[key], *grid, *pos);
                }
            });
            self.finish_pin_drag();
            return;
        }
        if let Some(pointer) = pointer {
            let drag = self.pin_drag.as_ref().expect("checked above");
            let moved = match drag.lock {
                Some(axis) => picking::drag_along_axis(&self.camera, size_px, drag.anchor, axis.vector(), pointer),
                None => picking::drag_in_view_plane(&self.camera, size_px, drag.anchor, pointer),
            };
            if let Some(moved) = moved {
                let offset = (moved - drag.anchor).as_dvec3();
                let label = if pins.len() == 1 { "Move pin" } else { "Move pins" };
                self.apply(label, |s| {
                    for (grid, pos) in &pins {
                        let to = (pos.0 + offset.x, pos.1 + offset.y, pos.2 + offset.z);
                        edits::move_pin(&mut s.keys[key], *grid, to);
                    }
                });
            }
        }
        if response.drag_stopped() || !ui.input(|i| i.pointer.primary_down()) {
            self.finish_pin_drag();
        }
    }

    fn finish_pin_drag(&mut self) {
        self.pin_drag = None;
        self.end_gesture();
    }
}
