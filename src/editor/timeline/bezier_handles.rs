//! A Bézier easing edited by hand: the CSS `cubic-bezier(x1, y1, x2, y2)` curve
//! from (0, 0) to (1, 1) drawn in a small square, its two control points as
//! handles to drag, and the four numbers below for exact values.
//!
//! The curve is drawn with the evaluator's own [`ease::apply`], so what is seen
//! is what plays.

use eframe::egui::{self, Color32, Pos2, Rect, Sense, Stroke, Vec2};

use crate::animate::ease;
use crate::editor::number_field::number_field;
use crate::scene::Ease;

/// Size of the drawing, points: taller than wide, for room above and below the unit square.
const SIZE: Vec2 = Vec2::new(150.0, 200.0);
/// Room around the unit square for the handles, points.
const PAD: f32 = 8.0;
/// Radius of a handle, and how near a press must be to grab it, points.
const HANDLE: f32 = 5.0;
const GRAB: f32 = 10.0;
/// How far a control point's y may be dragged (x stays in [0, 1], as CSS and validation require).
pub const Y_LIMITS: (f64, f64) = (-1.0, 2.0);
/// The numbers may go further than a handle is dragged.
const FIELD_Y_LIMITS: (f64, f64) = (-2.0, 3.0);
/// The y range always shown, so a handle can be dragged past 0 and 1 without
/// leaving the drawing (the range holds still during a drag).
const VIEW_Y: (f64, f64) = (-0.4, 1.4);
/// Margin of the shown y range around handles beyond that.
const VIEW_MARGIN: f64 = 0.1;

/// What the editor did this frame: a drag began (open an undo gesture), the numbers changed.
#[derive(Clone, Copy, Debug, Default)]
pub struct BezierEdit {
    pub began: bool,
    pub changed: bool,
}

/// The y range shown: [`VIEW_Y`], widened to both handles with a margin.
/// Non-finite handles are left out.
pub fn view_range(y1: f64, y2: f64) -> (f64, f64) {
    let finite = [y1, y2].into_iter().filter(|y| y.is_finite());
    let lo = finite.clone().fold(f64::INFINITY, f64::min).max(Y_LIMITS.0) - VIEW_MARGIN;
    let hi = finite.fold(f64::NEG_INFINITY, f64::max).min(Y_LIMITS.1) + VIEW_MARGIN;
    (lo.min(VIEW_Y.0), hi.max(VIEW_Y.1))
}

/// A control point dragged to (x, y): x within [0, 1], y within [`Y_LIMITS`]; NaN reads 0.
pub fn clamp_handle(x: f64, y: f64) -> (f64, f64) {
    let x = if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) };
    let y = if y.is_nan() { 0.0 } else { y.clamp(Y_LIMITS.0, Y_LIMITS.1) };
    (x, y)
}

/// The mapping between curve coordinates (x right, y up) and the screen.
#[derive(Clone, Copy, Debug)]
pub struct Square {
    /// The unit interval's x extent and the shown y range's extent, on screen.
    inner: Rect,
    lo: f64,
    hi: f64,
}

impl Square {
    /// The mapping of a drawing in `rect` showing y from `lo` to `hi`.
    pub fn new(rect: Rect, (lo, hi): (f64, f64)) -> Square {
        let (lo, hi) = if lo.is_finite() && hi.is_finite() && hi > lo { (lo, hi) } else { (0.0, 1.0) };
        Square { inner: rect.shrink(PAD), lo, hi }
    }

    /// The mapping the widget in `rect` uses for `handles` when nothing is being dragged.
    pub fn of(rect: Rect, handles: [f64; 4]) -> Square {
        Square::new(rect, view_range(handles[1], handles[3]))
    }

    pub fn pos(&self, x: f64, y: f64) -> Pos2 {
        let fy = ((y - self.lo) / (self.hi - self.lo)) as f32;
        Pos2::new(self.inner.left() + x as f32 * self.inner.width(), self.inner.bottom() - fy * self.inner.height())
    }

    pub fn point(&self, pos: Pos2) -> (f64, f64) {
        let x = f64::from((pos.x - self.inner.left()) / self.inner.width().max(1.0));
        let fy = f64::from((self.inner.bottom() - pos.y) / self.inner.height().max(1.0));
        (x, self.lo + fy * (self.hi - self.lo))
    }
}

/// The handle (0: x1, y1; 1: x2, y2) within [`GRAB`] of `pos`, the nearer one when both are.
pub fn handle_under(square: &Square, handles: [f64; 4], pos: Pos2) -> Option<usize> {
    let distance = |n: usize| square.pos(handles[2 * n], handles[2 * n + 1]).distance(pos);
    let (d0, d1) = (distance(0), distance(1));
    let (n, d) = if d1 < d0 { (1, d1) } else { (0, d0) };
    (d <= GRAB).then_some(n)
}

/// A drag in progress: which handle and the y range frozen at its start (so
/// the drawing holds still under the pointer).
#[derive(Clone, Copy)]
struct Drag {
    handle: usize,
    range: (f64, f64),
}

/// The drawing with its handles, then the four numbers; edits `handles` in place.
pub fn edit(ui: &mut egui::Ui, handles: &mut [f64; 4]) -> BezierEdit {
    let mut edit = BezierEdit::default();
    // In a row, so a justified menu does not widen the response past the drawing.
    let (rect, response) = ui.horizontal(|ui| ui.allocate_exact_size(SIZE, Sense::drag())).inner;
    response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Canvas, true, "Bézier handles"));
    let id = response.id;
    let mut drag: Option<Drag> = ui.data(|d| d.get_temp(id));
    if response.drag_started() {
        let origin = ui.input(|i| i.pointer.press_origin());
        let square = Square::of(rect, *handles);
        drag = origin
            .and_then(|pos| handle_under(&square, *handles, pos))
            .map(|handle| Drag { handle, range: view_range(handles[1], handles[3]) });
        edit.began = drag.is_some();
    }
    let square = match drag {
        Some(d) => Square::new(rect, d.range),
        None => Square::of(rect, *handles),
    };
    if let (Some(d), Some(pos)) = (drag, response.interact_pointer_pos())
        && response.dragged()
    {
        let (x, y) = square.point(pos);
        let (x, y) = clamp_handle(x, y);
        if [x, y] != [handles[2 * d.handle], handles[2 * d.handle + 1]] {
            handles[2 * d.handle] = x;
            handles[2 * d.handle + 1] = y;
            edit.changed = true;
        }
    }
    if response.drag_stopped() {
        drag = None;
    }
    ui.data_mut(|d| match drag {
        Some(drag) => {
            d.insert_temp(id, drag);
        }
        None => d.remove::<Drag>(id),
    });
    paint(ui, rect, &square, *handles, drag.map(|d| d.handle));
    if response.hovered() || drag.is_some() {
        ui.ctx().set_cursor_icon(egui::CursorIcon::Grab);
    }

    ui.horizontal(|ui| {
        for (n, value) in handles.iter_mut().enumerate() {
            let range = if n % 2 == 0 { 0.0..=1.0 } else { FIELD_Y_LIMITS.0..=FIELD_Y_LIMITS.1 };
            let name = ["x1", "y1", "x2", "y2"][n];
            // Showing a value from a file outside the range must not change it.
            let drag = number_field(ui.ctx(), value).range(range).clamp_existing_to_range(false);
            let field = ui.add(drag.speed(0.01).max_decimals(3));
            field.widget_info(|| egui::WidgetInfo::labeled(egui::Role::SpinButton, true, format!("Bézier {name}")));
            edit.began |= field.drag_started();
            edit.changed |= field.changed();
        }
    });
    edit
}

fn paint(ui: &egui::Ui, rect: Rect, square: &Square, handles: [f64; 4], dragged: Option<usize>) {
    let painter = ui.painter_at(rect);
    let visuals = ui.visuals();
    let weak = visuals.weak_text_color();
    painter.rect_filled(rect, 3.0, visuals.extreme_bg_color);
    // The unit square: where the segment starts (0) and arrives (1).
    let unit = Rect::from_two_pos(square.pos(0.0, 0.0), square.pos(1.0, 1.0));
    painter.rect_stroke(unit, 0.0, Stroke::new(1.0, weak.gamma_multiply(0.5)), egui::StrokeKind::Middle);
    let [x1, y1, x2, y2] = handles;
    let curve: Vec<Pos2> = (0..=64)
        .map(|i| {
            let x = f64::from(i) / 64.0;
            square.pos(x, ease::apply(Ease::Bezier(x1, y1, x2, y2), x))
        })
        .collect();
    painter.add(egui::Shape::line(curve, Stroke::new(2.0, Color32::from_rgb(90, 200, 255))));
    let arm = Stroke::new(1.0, visuals.text_color());
    for (n, anchor) in [(0, (0.0, 0.0)), (1, (1.0, 1.0))] {
        let handle = square.pos(handles[2 * n], handles[2 * n + 1]);
        painter.line_segment([square.pos(anchor.0, anchor.1), handle], arm);
        let fill = if dragged == Some(n) { Color32::from_rgb(255, 200, 20) } else { Color32::from_rgb(230, 230, 230) };
        painter.circle(handle, HANDLE, fill, Stroke::new(1.0, Color32::BLACK));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect() -> Rect {
        Rect::from_min_size(Pos2::new(10.0, 20.0), SIZE)
    }

    #[test]
    fn the_view_holds_the_unit_square_and_both_handles() {
        assert_eq!(view_range(0.0, 1.0), VIEW_Y);
        let (lo, hi) = view_range(-0.6, 1.6);
        assert!((lo + 0.7).abs() < 1e-12 && (hi - 1.7).abs() < 1e-12);
        assert_eq!(view_range(0.0, 1.6).0, VIEW_Y.0, "each side widens on its own");
        assert_eq!(view_range(f64::NAN, f64::INFINITY), VIEW_Y, "non-finite handles are left out");
        assert_eq!(view_range(-50.0, 50.0), (Y_LIMITS.0 - 0.1, Y_LIMITS.1 + 0.1));
    }

    #[test]
    fn handles_stay_within_their_limits() {
        assert_eq!(clamp_handle(-0.5, 0.5), (0.0, 0.5));
        assert_eq!(clamp_handle(1.5, 9.0), (1.0, Y_LIMITS.1));
        assert_eq!(clamp_handle(0.3, -9.0), (0.3, Y_LIMITS.0));
        assert_eq!(clamp_handle(f64::NAN, f64::NAN), (0.0, 0.0));
    }

    #[test]
    fn curve_points_and_the_screen_map_both_ways() {
        let square = Square::of(rect(), [0.42, 0.0, 0.58, 1.0]);
        for (x, y) in [(0.0, 0.0), (1.0, 1.0), (0.25, -0.05), (0.9, 1.05)] {
            let (bx, by) = square.point(square.pos(x, y));
            assert!((bx - x).abs() < 1e-5 && (by - y).abs() < 1e-5, "({x}, {y}) → ({bx}, {by})");
        }
        assert!(square.pos(0.0, 1.0).y < square.pos(0.0, 0.0).y, "y goes up");
        // A degenerate range falls back to the unit square.
        let flat = Square::new(rect(), (0.5, 0.5));
        assert!(flat.pos(0.0, 1.0).y.is_finite());
    }

    #[test]
    fn a_press_grabs_the_nearest_handle_or_none() {
        let handles = [0.2, 0.1, 0.8, 0.9];
        let square = Square::of(rect(), handles);
        let first = square.pos(0.2, 0.1);
        assert_eq!(handle_under(&square, handles, first + Vec2::new(3.0, 3.0)), Some(0));
        assert_eq!(handle_under(&square, handles, square.pos(0.8, 0.9)), Some(1));
        assert_eq!(handle_under(&square, handles, square.pos(0.5, 0.5)), None);
        // Both handles on one spot: the first wins.
        let same = [0.5, 0.5, 0.5, 0.5];
        assert_eq!(handle_under(&Square::of(rect(), same), same, square.pos(0.5, 0.5)), Some(0));
    }
}
