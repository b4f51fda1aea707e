//! The 2D grid editor (the paper's Fig. 3a): the cloth's grid seen flat, its
//! pins as red dots. Click a point to pin it, click a pin to select it
//! (Shift adds, Ctrl toggles), drag a box to select the pins inside it.
//!
//! The widget only reports what the user did; the app turns that into edits.

use eframe::egui::{self, Color32, Pos2, Rect, Sense, Stroke, StrokeKind, Vec2};

use crate::editor::selection::Pick;
use crate::scene::{Cloth, Key};

/// What the user did in the grid editor this frame; the [`Pick`] says
/// what it does to the selection (see [`crate::editor::selection`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum GridAction {
    /// A click on an unpinned point: pin it where the cloth is now.
    Pin((u32, u32), Pick),
    /// A click on a pin.
    PickPin((u32, u32), Pick),
    /// A box was dragged round these pins.
    SelectBox { pins: Vec<(u32, u32)>, how: Pick },
    /// A click on no grid point.
    ClickNothing(Pick),
}

/// Drawing sizes in points. A tall cloth's editor stops at its height, which
/// starts here and is dragged between the two limits below.
pub const DEFAULT_HEIGHT: f32 = 224.0;
const MIN_HEIGHT: f32 = 120.0;
const MAX_HEIGHT: f32 = 900.0;
/// Height of the strip under the editor that resizes it.
const RESIZE_STRIP: f32 = 8.0;
const PIN_RADIUS: f32 = 4.5;
/// Grid lines closer than this are thinned out, so a 256² grid stays readable.
const MIN_LINE_GAP: f32 = 6.0;

/// The editor's state between frames: where a box drag started, and the
/// height a tall cloth's editor may take (dragged with the strip under it).
pub struct GridEditor {
    box_start: Option<Pos2>,
    max_height: f32,
    /// Whether the strip under it is being dragged.
    resizing: bool,
}

impl Default for GridEditor {
    fn default() -> Self {
        GridEditor { box_start: None, max_height: DEFAULT_HEIGHT, resizing: false }
    }
}

/// The modifiers held when the primary button was last released this frame
/// (else now): on a slow frame, a Shift released right after the click must
/// still count.
pub fn click_modifiers(ui: &egui::Ui) -> egui::Modifiers {
    ui.input(|i| {
        i.events
            .iter()
            .rev()
            .find_map(|event| match event {
                egui::Event::PointerButton {
                    button: egui::PointerButton::Primary, pressed: false, modifiers, ..
                } => Some(*modifiers),
                _ => None,
            })
            .unwrap_or(i.modifiers)
    })
}

/// Where grid point `(i, j)` is drawn in `rect` (j = 0 on the top edge).
fn point_pos(rect: Rect, grid: (u32, u32), (i, j): (u32, u32)) -> Pos2 {
    let fx = i as f32 / (grid.0.max(2) - 1) as f32;
    let fy = j as f32 / (grid.1.max(2) - 1) as f32;
    Pos2::new(rect.left() + fx * rect.width(), rect.top() + fy * rect.height())
}

/// The grid point nearest to `pos`, if `pos` is on the grid (within half a cell or a few points).
fn nearest_point(rect: Rect, grid: (u32, u32), pos: Pos2) -> Option<(u32, u32)> {
    let (cols, rows) = (grid.0.max(2), grid.1.max(2));
    let fx = (pos.x - rect.left()) / rect.width() * (cols - 1) as f32;
    let fy = (pos.y - rect.top()) / rect.height() * (rows - 1) as f32;
    if !(fx.is_finite() && fy.is_finite()) {
        return None;
    }
    let i = fx.round().clamp(0.0, (cols - 1) as f32) as u32;
    let j = fy.round().clamp(0.0, (rows - 1) as f32) as u32;
    let reach = (rect.width() / (cols - 1) as f32).max(rect.height() / (rows - 1) as f32).max(2.0 * PIN_RADIUS);
    (point_pos(rect, grid, (i, j)).distance(pos) <= reach).then_some((i, j))
}

impl GridEditor {
    /// Where grid point `point` of `cloth` is drawn when the widget occupies `widget_rect` (tests, scripts).
    pub fn point_in(widget_rect: Rect, cloth: &Cloth, point: (u32, u32)) -> Pos2 {
        point_pos(widget_rect.shrink(PIN_RADIUS + 1.0), cloth.grid, point)
    }

    /// Draws the grid of `cloth` with the pins of `key`; `selected` pins are
    /// ringed, `highlight` (a point hovered here or in the viewport) is marked.
    /// Returns the user's actions and the point under the pointer.
    pub fn show(
        &mut self,
        ui: &mut egui::Ui,
        cloth: &Cloth,
        key: &Key,
        selected: &[(u32, u32)],
        highlight: Option<(u32, u32)>,
    ) -> (Vec<GridAction>, Option<(u32, u32)>) {
        let grid = cloth.grid;
        let aspect = (cloth.width_m() / cloth.height_m()) as f32;
        // Clear of the panel's edge, where dragging resizes the panel instead.
        let width = (ui.available_width() - 16.0).max(80.0);
        let size = Vec2::new(width, width / aspect);
        // From the panel's width, the cloth and the chosen height alone, never from where the
        // panel is scrolled to, so the editor keeps its size and place while the rows around it change.
        let size = if size.y > self.max_height { size * (self.max_height / size.y) } else { size };
        let size = size.max(Vec2::splat(24.0));
        let padding = Vec2::splat(2.0 * PIN_RADIUS + 2.0);
        // The chosen height is kept whatever the cloth's shape, so the rows
        // under the editor stay put when Width or Height is typed; a wide
        // cloth's grid sits at the top of it.
        let room = Vec2::new(size.x, size.y.max(self.max_height));
        let (room, response) = ui.allocate_exact_size(room + padding, Sense::click_and_drag());
        let outer = Rect::from_min_size(room.min, size + padding);
        response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Canvas, true, "Grid editor"));
        let rect = outer.shrink(PIN_RADIUS + 1.0);
        let painter = ui.painter_at(outer);
        let visuals = ui.visuals();
        painter.rect_filled(outer, 2.0, visuals.extreme_bg_color);

        let line = Stroke::new(1.0, visuals.weak_text_color().gamma_multiply(0.5));
        let step = |count: u32, length: f32| {
            let gap = length / (count.max(2) - 1) as f32;
            ((MIN_LINE_GAP / gap).ceil() as u32).max(1)
        };
        let (step_i, step_j) = (step(grid.0, rect.width()), step(grid.1, rect.height()));
        for i in (0..grid.0).step_by(step_i as usize).chain([grid.0 - 1]) {
            painter.line_segment([point_pos(rect, grid, (i, 0)), point_pos(rect, grid, (i, grid.1 - 1))], line);
        }
        for j in (0..grid.1).step_by(step_j as usize).chain([grid.1 - 1]) {
            painter.line_segment([point_pos(rect, grid, (0, j)), point_pos(rect, grid, (grid.0 - 1, j))], line);
        }
        painter.rect_stroke(rect, 0.0, Stroke::new(1.0, visuals.text_color()), StrokeKind::Middle);

        let pin_color = Color32::from_rgb(220, 30, 20);
        let selected_color = Color32::from_rgb(255, 200, 20);
        for pin in &key.pins {
            let at = point_pos(rect, grid, pin.grid);
            painter.circle_filled(at, PIN_RADIUS, pin_color);
            if selected.contains(&pin.grid) {
                painter.circle_stroke(at, PIN_RADIUS + 1.5, Stroke::new(2.0, selected_color));
            }
        }

        let pointer = response.hover_pos();
        let hovered = pointer.and_then(|p| nearest_point(rect, grid, p));
        if let Some(point) = hovered.or(highlight) {
            let at = point_pos(rect, grid, point);
            painter.circle_stroke(at, PIN_RADIUS + 2.5, Stroke::new(1.5, visuals.strong_text_color()));
        }
        if let Some((i, j)) = hovered {
            let pinned = key.pins.iter().any(|p| p.grid == (i, j));
            let text = format!("({i}, {j}){}", if pinned { " pinned" } else { "" });
            response.clone().on_hover_text_at_pointer(text);
        }

        let mut actions = Vec::new();
        let how = Pick::from_modifiers(click_modifiers(ui));
        if response.drag_started() {
            // From where the button went down, not where egui first called it a drag.
            self.box_start = ui.input(|i| i.pointer.press_origin()).or(response.interact_pointer_pos());
        }
        if let (Some(start), Some(now)) = (self.box_start, response.interact_pointer_pos()) {
            let selection = Rect::from_two_pos(start, now);
            painter.rect(
                selection,
                0.0,
                selected_color.gamma_multiply(0.15),
                Stroke::new(1.0, selected_color),
                StrokeKind::Middle,
            );
            if response.drag_stopped() {
                let pins = key
                    .pins
                    .iter()
                    .filter(|p| selection.expand(PIN_RADIUS).contains(point_pos(rect, grid, p.grid)))
                    .map(|p| p.grid)
                    .collect();
                actions.push(GridAction::SelectBox { pins, how });
                self.box_start = None;
            }
        }
        if !response.dragged() && !response.drag_stopped() {
            self.box_start = None;
        }
        if response.clicked() {
            let point = response.interact_pointer_pos().and_then(|p| nearest_point(rect, grid, p));
            actions.push(match point {
                Some(point) if key.pins.iter().any(|p| p.grid == point) => GridAction::PickPin(point, how),
                Some(point) => GridAction::Pin(point, how),
                None => GridAction::ClickNothing(how),
            });
        }
        self.resize_strip_ui(ui, outer.width());
        (actions, hovered)
    }

    /// Whether the strip under the editor is being dragged.
    pub fn is_resizing(&self) -> bool {
        self.resizing
    }

    /// The strip under the editor: dragging it makes a tall cloth's editor taller or shorter.
    fn resize_strip_ui(&mut self, ui: &mut egui::Ui, width: f32) {
        let (strip, response) = ui.allocate_exact_size(Vec2::new(width, RESIZE_STRIP), Sense::drag());
        response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Splitter, true, "Grid editor height"));
        let response = response.on_hover_cursor(egui::CursorIcon::ResizeVertical);
        self.resizing = response.dragged();
        if response.dragged() {
            self.max_height = (self.max_height + response.drag_delta().y).clamp(MIN_HEIGHT, MAX_HEIGHT);
        }
        let visuals = ui.visuals();
        let color = if response.hovered() || response.dragged() {
            visuals.strong_text_color()
        } else {
            visuals.weak_text_color().gamma_multiply(0.5)
        };
        let y = strip.center().y;
        for dx in [-6.0, 0.0, 6.0] {
            ui.painter().circle_filled(Pos2::new(strip.center().x + dx, y), 1.5, color);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const RECT: Rect = Rect { min: Pos2::new(10.0, 20.0), max: Pos2::new(210.0, 120.0) };

    #[test]
    fn corners_are_drawn_at_the_rect_corners_and_found_again() {
        let grid = (33, 17);
        assert_eq!(point_pos(RECT, grid, (0, 0)), RECT.min);
        assert_eq!(point_pos(RECT, grid, (32, 16)), RECT.max);
        for point in [(0, 0), (32, 16), (16, 8), (5, 11)] {
            assert_eq!(nearest_point(RECT, grid, point_pos(RECT, grid, point)), Some(point));
        }
    }

    #[test]
    fn far_off_the_grid_is_no_point() {
        assert_eq!(nearest_point(RECT, (9, 9), Pos2::new(400.0, 400.0)), None);
        assert_eq!(nearest_point(RECT, (9, 9), Pos2::new(f32::NAN, 30.0)), None);
        // Just outside a corner still finds the corner.
        assert_eq!(nearest_point(RECT, (9, 9), Pos2::new(8.0, 18.0)), Some((0, 0)));
    }
}
