//! Pointer to cloth and back: which grid point or collider is under the
//! mouse, and where a dragged pin or collider goes. Pure math on the camera; pixels are physical pixels of
//! the viewport (origin top left).

use glam::{Vec2, Vec3};

use super::pin_drag::AxisLock;
use crate::animate::colliders_at::shape_at;
use crate::render::OrbitCamera;
use crate::scene::{Collider, Scene};
use crate::world::{ColliderShape, ray_hit};

/// The farthest a collider is picked (m): beyond any sensible view.
const MAX_PICK_DISTANCE_M: f64 = 1e4;

/// The vertex drawn nearest to `pointer_px` within `radius_px`, preferring the
/// front layer where cloth overlaps itself: among the points that close, those
/// more than `radius_px` (measured in the world at their depth) behind the
/// nearest one are ignored. `None` when no finite vertex is that close.
pub fn pick_vertex(
    camera: &OrbitCamera,
    size_px: (u32, u32),
    positions: &[Vec3],
    pointer_px: Vec2,
    radius_px: f32,
) -> Option<usize> {
    if !pointer_px.is_finite() {
        return None;
    }
    let clip_from_world = camera.clip_from_world(size_px);
    let eye = camera.eye();
    let forward = -camera.backward();
    let size = Vec2::new(size_px.0 as f32, size_px.1 as f32);
    let mut candidates: Vec<(usize, f32, f32)> = Vec::new();
    for (index, &p) in positions.iter().enumerate() {
        let clip = clip_from_world * p.extend(1.0);
        if !(clip.w > 0.0) || !p.is_finite() {
            continue;
        }
        let ndc = clip.truncate() / clip.w;
        let pixel = Vec2::new((ndc.x * 0.5 + 0.5) * size.x, (0.5 - ndc.y * 0.5) * size.y);
        let distance_px = pixel.distance(pointer_px);
        if distance_px <= radius_px {
            candidates.push((index, distance_px, (p - eye).dot(forward)));
        }
    }
    let front = candidates.iter().map(|c| c.2).fold(f32::INFINITY, f32::min);
    let metres_per_px = camera.metres_per_pixel(size.y) * front / camera.distance_m;
    let slack = radius_px * metres_per_px;
    candidates.into_iter().filter(|c| c.2 <= front + slack).min_by(|a, b| a.1.total_cmp(&b.1)).map(|c| c.0)
}

/// A collider's index in the scene and how far along the pointer's ray it is met (m).
pub type ColliderHit = (usize, f64);

/// The collider of `scene` drawn under `pointer_px` at `frame`, nearest
/// first, and how far along the ray the pointer meets it (m). Only what the
/// viewport draws is picked: enabled colliders, not the ground (it fills
/// the view behind everything; its height is set in the Colliders panel).
pub fn pick_collider(
    camera: &OrbitCamera,
    size_px: (u32, u32),
    scene: &Scene,
    frame: f64,
    pointer_px: Vec2,
) -> Option<ColliderHit> {
    if !pointer_px.is_finite() {
        return None;
    }
    let (origin, direction) = camera.ray(pointer_px, size_px);
    scene
        .colliders
        .iter()
        .enumerate()
        .filter(|(_, c)| c.enabled() && !matches!(c, Collider::Ground(_)))
        .filter_map(|(index, c)| {
            let shape = shape_at(c, frame)?;
            ray_hit(&shape, origin.as_dvec3(), direction.as_dvec3(), MAX_PICK_DISTANCE_M).map(|t| (index, t))
        })
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// Where a collider is moved from and its gizmo drawn: the middle of its box.
/// `None` for the ground (no middle) and a mesh not read.
pub fn collider_middle(collider: &Collider, frame: f64) -> Option<Vec3> {
    let shape = shape_at(collider, frame)?;
    if matches!(shape, ColliderShape::Ground { .. }) {
        return None;
    }
    let (lo, hi) = shape.bounds();
    let middle = ((lo + hi) * 0.5).as_vec3();
    middle.is_finite().then_some(middle)
}

/// Where a point dragged from `anchor` goes for the pointer at `pixel`:
/// along `lock`'s axis ([`drag_along_axis`]) or in the view plane
/// ([`drag_in_view_plane`]) when unlocked.
pub fn drag_point(
    camera: &OrbitCamera,
    size_px: (u32, u32),
    anchor: Vec3,
    lock: Option<AxisLock>,
    pixel: Vec2,
) -> Option<Vec3> {
    match lock {
        Some(axis) => drag_along_axis(camera, size_px, anchor, axis.vector(), pixel),
        None => drag_in_view_plane(camera, size_px, anchor, pixel),
    }
}

/// Where the ray through `pixel` meets the plane through `anchor` facing the
/// camera: a pin dragged there stays under the mouse. `None` when the ray runs
/// along the plane or away from it.
pub fn drag_in_view_plane(camera: &OrbitCamera, size_px: (u32, u32), anchor: Vec3, pixel: Vec2) -> Option<Vec3> {
    let (origin, direction) = camera.ray(pixel, size_px);
    let normal = camera.backward();
    let denominator = direction.dot(normal);
    if denominator.abs() < 1e-6 {
        return None;
    }
    let t = (anchor - origin).dot(normal) / denominator;
    let hit = origin + direction * t;
    (t > 0.0 && hit.is_finite()).then_some(hit)
}

/// The point on the line through `anchor` along `axis` nearest to the ray
/// through `pixel`: a pin locked to an axis follows the mouse along it. `None`
/// when the ray runs parallel to the axis.
pub fn drag_along_axis(
    camera: &OrbitCamera,
    size_px: (u32, u32),
    anchor: Vec3,
    axis: Vec3,
    pixel: Vec2,
) -> Option<Vec3> {
    let (origin, direction) = camera.ray(pixel, size_px);
    let axis = axis.try_normalize()?;
    // Closest points of two lines: anchor + s·axis and origin + t·direction.
    let w = anchor - origin;
    let b = axis.dot(direction);
    let denominator = 1.0 - b * b;
    if denominator < 1e-6 {
        return None;
    }
    let s = (b * w.dot(direction) - w.dot(axis)) / denominator;
    let hit = anchor + axis * s;
    hit.is_finite().then_some(hit)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> OrbitCamera {
        OrbitCamera { target: Vec3::ZERO, yaw_deg: 0.0, pitch_deg: 0.0, distance_m: 5.0, fov_y_deg: 40.0 }
    }

    const SIZE: (u32, u32) = (800, 600);

    #[test]
    fn the_point_under_the_pointer_is_picked() {
        let cam = camera();
        let points = [Vec3::new(-1.0, 0.0, 0.0), Vec3::ZERO, Vec3::new(1.0, 0.5, 0.0)];
        let at = cam.project(points[2], SIZE).unwrap();
        assert_eq!(pick_vertex(&cam, SIZE, &points, at + Vec2::new(3.0, -2.0), 10.0), Some(2));
        assert_eq!(pick_vertex(&cam, SIZE, &points, Vec2::new(400.0, 300.0), 10.0), Some(1));
        assert_eq!(pick_vertex(&cam, SIZE, &points, Vec2::new(10.0, 10.0), 10.0), None);
    }

    #[test]
    fn the_front_layer_wins_over_a_nearer_point_behind_it() {
        let cam = camera();
        // Looking along −Z: a point behind (z = −1) exactly under the pointer,
        // a front point (z = +1) a few pixels off.
        let back = Vec3::new(0.0, 0.0, -1.0);
        let front = Vec3::new(0.02, 0.0, 1.0);
        let pointer = cam.project(back, SIZE).unwrap();
        assert_eq!(pick_vertex(&cam, SIZE, &[back, front], pointer, 12.0), Some(1));
    }

    #[test]
    fn nothing_is_picked_from_nan_input() {
        let cam = camera();
        assert_eq!(pick_vertex(&cam, SIZE, &[Vec3::NAN, Vec3::ZERO], Vec2::new(400.0, 300.0), 10.0), Some(1));
        assert_eq!(pick_vertex(&cam, SIZE, &[Vec3::ZERO], Vec2::NAN, 10.0), None);
        assert_eq!(pick_vertex(&cam, SIZE, &[Vec3::ZERO], Vec2::INFINITY, 10.0), None);
    }

    #[test]
    fn a_point_dragged_in_the_view_plane_stays_under_the_pointer_at_its_depth() {
        let cam = camera();
        let anchor = Vec3::new(0.3, 0.2, 0.5);
        let target_px = Vec2::new(520.0, 180.0);
        let moved = drag_in_view_plane(&cam, SIZE, anchor, target_px).unwrap();
        assert!((moved.z - anchor.z).abs() < 1e-5, "same depth: {moved}");
        assert!(cam.project(moved, SIZE).unwrap().distance(target_px) < 0.01);
    }

    #[test]
    fn an_axis_lock_moves_along_the_axis_only() {
        let cam = camera();
        let anchor = Vec3::new(0.3, 0.2, 0.0);
        let moved = drag_along_axis(&cam, SIZE, anchor, Vec3::Y, Vec2::new(700.0, 100.0)).unwrap();
        assert_eq!((moved.x, moved.z), (anchor.x, anchor.z));
        assert!(moved.y > anchor.y, "up the screen is up the axis");
        // Along the view direction the axis is degenerate.
        assert_eq!(drag_along_axis(&cam, SIZE, anchor, Vec3::Z, Vec2::new(400.0, 300.0)), None);
        assert_eq!(drag_along_axis(&cam, SIZE, anchor, Vec3::ZERO, Vec2::new(700.0, 100.0)), None);
    }
}
