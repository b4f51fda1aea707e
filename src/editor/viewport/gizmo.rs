//! The translate gizmo on the selected pins: three arrows (X red, Y green,
//! Z blue) from the pins' centre; dragging an arrow moves the pins along
//! that axis (the drag itself is [`super::pin_drag`]'s, locked to the axis).
//!
//! Screen geometry only, in points within the viewport, so hit tests and
//! drawing agree.

use eframe::egui::{self, Color32, Pos2, Stroke, Vec2};
use glam::Vec3;

use super::pin_drag::AxisLock;
use crate::render::OrbitCamera;

/// Arrow length on screen, points.
pub const ARROW_LENGTH_PT: f32 = 70.0;
/// How near the pointer must be to an arrow to grab it, points.
const GRAB_RADIUS_PT: f32 = 7.0;
/// An axis pointing at the viewer closer than this (fraction of the arrow
/// length on screen) is not drawn: it could not be dragged along.
const MIN_FORESHORTENING: f32 = 0.15;

const AXES: [AxisLock; 3] = [AxisLock::X, AxisLock::Y, AxisLock::Z];

/// The gizmo as drawn this frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Gizmo {
    /// The selected pins' centre, in world and on screen.
    pub origin: Vec3,
    origin_pt: Pos2,
    /// Each axis's arrow tip on screen, `None` for an axis seen end-on.
    tips_pt: [Option<Pos2>; 3],
}

impl Gizmo {
    /// The gizmo at world point `origin` seen by `camera` in a viewport at
    /// `rect` (points) rendered at `size_px`; `None` when `origin` is behind
    /// the camera or not finite.
    pub fn at(origin: Vec3, camera: &OrbitCamera, rect: egui::Rect, size_px: (u32, u32)) -> Option<Gizmo> {
        if !origin.is_finite() {
            return None;
        }
        let to_pt = |px: glam::Vec2| {
            rect.min
                + Vec2::new(
                    px.x * rect.width() / size_px.0.max(1) as f32,
                    px.y * rect.height() / size_px.1.max(1) as f32,
                )
        };
        let origin_pt = to_pt(camera.project(origin, size_px)?);
        // A short step along each axis, seen on screen, gives each arrow's direction and foreshortening.
        let step_m = camera.metres_per_pixel(size_px.1 as f32) * 20.0;
        let along =
            AXES.map(|axis| camera.project(origin + axis.vector() * step_m, size_px).map(|p| to_pt(p) - origin_pt));
        let longest = along.iter().flatten().map(|v| v.length()).fold(0.0f32, f32::max);
        if !(longest > 0.0) {
            return None;
        }
        let tips_pt = along.map(|v| {
            let v = v?;
            let seen = v.length() / longest;
            (seen >= MIN_FORESHORTENING).then(|| origin_pt + v.normalized() * ARROW_LENGTH_PT * seen)
        });
        Some(Gizmo { origin, origin_pt, tips_pt })
    }

    /// The axis whose arrow is under `pos` (points), if any; the nearest wins.
    /// None at the gizmo's middle, where a drag grabs what the gizmo sits on
    /// (a pin, a collider) and moves it freely.
    pub fn axis_at(&self, pos: Pos2) -> Option<AxisLock> {
        if pos.distance(self.origin_pt) <= GRAB_RADIUS_PT {
            return None;
        }
        AXES.iter()
            .zip(self.tips_pt)
            .filter_map(|(axis, tip)| Some((*axis, distance_to_segment(pos, self.origin_pt, tip?))))
            .filter(|(_, d)| *d <= GRAB_RADIUS_PT)
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(axis, _)| axis)
    }

    /// Where the arrow of `axis` ends on screen (tests, scripts).
    pub fn tip(&self, axis: AxisLock) -> Option<Pos2> {
        self.tips_pt[axis as usize]
    }

    /// Draws the arrows; `hot` (hovered or dragged) is drawn brighter and thicker.
    pub fn paint(&self, painter: &egui::Painter, hot: Option<AxisLock>) {
        for (axis, tip) in AXES.iter().zip(self.tips_pt) {
            let Some(tip) = tip else { continue };
            let is_hot = hot == Some(*axis);
            let color = axis_color(*axis, is_hot);
            let stroke = Stroke::new(if is_hot { 3.5 } else { 2.5 }, color);
            painter.line_segment([self.origin_pt, tip], stroke);
            let dir = (tip - self.origin_pt).normalized();
            let side = Vec2::new(-dir.y, dir.x) * 5.0;
            let head = vec![tip + dir * 9.0, tip + side, tip - side];
            painter.add(egui::Shape::convex_polygon(head, color, Stroke::NONE));
        }
        painter.circle_filled(self.origin_pt, 3.5, Color32::WHITE);
    }
}

/// The colour of `axis`'s arrow, brighter when `hot` (hovered or dragged).
pub fn axis_color(axis: AxisLock, hot: bool) -> Color32 {
    let (r, g, b) = match axis {
        AxisLock::X => (225, 60, 60),
        AxisLock::Y => (90, 200, 70),
        AxisLock::Z => (70, 120, 235),
    };
    if hot { Color32::from_rgb(r.max(250), g.max(230), b.max(120)) } else { Color32::from_rgb(r, g, b) }
}

fn distance_to_segment(p: Pos2, a: Pos2, b: Pos2) -> f32 {
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.length_sq().max(1e-6)).clamp(0.0, 1.0);
    p.distance(a + ab * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> OrbitCamera {
        OrbitCamera { target: Vec3::ZERO, yaw_deg: 30.0, pitch_deg: 20.0, distance_m: 5.0, fov_y_deg: 40.0 }
    }

    const RECT: egui::Rect = egui::Rect { min: Pos2::new(100.0, 50.0), max: Pos2::new(900.0, 650.0) };

    #[test]
    fn arrows_point_along_their_axes_on_screen() {
        let gizmo = Gizmo::at(Vec3::ZERO, &camera(), RECT, (1600, 1200)).unwrap();
        let origin = gizmo.origin_pt;
        assert!((origin - RECT.center()).length() < 0.5, "the target is drawn at the centre: {origin:?}");
        let up = gizmo.tip(AxisLock::Y).unwrap() - origin;
        assert!(up.y < -60.0 && up.x.abs() < 1.0, "Y points up the screen: {up:?}");
        let x = gizmo.tip(AxisLock::X).unwrap() - origin;
        assert!(x.x > 0.0, "X points right from the front-right: {x:?}");
        for axis in AXES {
            let tip = gizmo.tip(axis).unwrap();
            let middle = origin + (tip - origin) * 0.6;
            assert_eq!(gizmo.axis_at(middle), Some(axis));
        }
        assert_eq!(gizmo.axis_at(origin + Vec2::new(-60.0, 60.0)), None);
    }

    #[test]
    fn an_axis_seen_end_on_is_not_drawn_and_bad_origins_give_none() {
        let front = OrbitCamera { yaw_deg: 0.0, pitch_deg: 0.0, ..camera() };
        let gizmo = Gizmo::at(Vec3::ZERO, &front, RECT, (800, 600)).unwrap();
        assert!(gizmo.tip(AxisLock::Z).is_none(), "looking along −Z");
        assert!(gizmo.tip(AxisLock::X).is_some() && gizmo.tip(AxisLock::Y).is_some());
        assert!(Gizmo::at(Vec3::NAN, &front, RECT, (800, 600)).is_none());
        assert!(Gizmo::at(Vec3::new(0.0, 0.0, 10.0), &front, RECT, (800, 600)).is_none(), "behind the camera");
    }
}
