//! Looking through the scene's shot camera in the viewport (the View
//! panel's Camera toggle, or View ▸ Look through camera):
//! the camera at the playhead, its picture's frame drawn with action-safe
//! (90 %) and title-safe (80 %) guides; and setting the camera from the view
//! or keying it at the playhead, each one undo step.

use eframe::egui;
use glam::DVec3;

use super::param_edit::set_at_keying;
use super::workspace::Workspace;
use crate::animate::track::sample;
use crate::picture::shot_camera_at;
use crate::render::OrbitCamera;
use crate::scene::{Param, ParamVec3, Scene, ShotCamera};

/// Share of the viewport's shorter fit the camera's frame takes, so its border shows.
const FRAME_SHARE: f32 = 0.92;

/// The shot camera's frame inside a viewport `rect`: centred, of the
/// picture's shape, as large as [`FRAME_SHARE`] of the viewport allows.
pub fn frame_rect(camera: &ShotCamera, rect: egui::Rect) -> egui::Rect {
    let (width, height) = camera.image_size;
    let image_aspect = width.max(1) as f32 / height.max(1) as f32;
    let view_aspect = rect.width() / rect.height().max(1.0);
    let size = if image_aspect > view_aspect {
        egui::vec2(rect.width(), rect.width() / image_aspect)
    } else {
        egui::vec2(rect.height() * image_aspect, rect.height())
    } * FRAME_SHARE;
    egui::Rect::from_center_size(rect.center(), size)
}

/// The viewport's camera that shows `camera` at `frame` with its picture
/// filling [`frame_rect`] of `rect`: the shot camera's, its vertical field of
/// view widened by the viewport's height over the frame's.
pub fn through(camera: &ShotCamera, frame: f64, rect: egui::Rect) -> OrbitCamera {
    let mut view = shot_camera_at(camera, frame, camera.image_size);
    let inner = frame_rect(camera, rect);
    let half = (view.fov_y_deg.to_radians() * 0.5).tan() * rect.height() / inner.height().max(1.0);
    view.fov_y_deg = 2.0 * half.atan().to_degrees();
    view
}

/// The frame's border and its safe-area guides over the viewport.
pub fn paint_frame(painter: &egui::Painter, camera: &ShotCamera, rect: egui::Rect) {
    let frame = frame_rect(camera, rect);
    // Outside the picture is dimmed, as a camera's viewfinder shows it.
    let dim = egui::Color32::from_black_alpha(110);
    for outside in [
        egui::Rect::from_min_max(rect.min, egui::pos2(rect.max.x, frame.min.y)),
        egui::Rect::from_min_max(egui::pos2(rect.min.x, frame.max.y), rect.max),
        egui::Rect::from_min_max(egui::pos2(rect.min.x, frame.min.y), egui::pos2(frame.min.x, frame.max.y)),
        egui::Rect::from_min_max(egui::pos2(frame.max.x, frame.min.y), egui::pos2(rect.max.x, frame.max.y)),
    ] {
        painter.rect_filled(outside, 0.0, dim);
    }
    let line = |share: f32, alpha: u8| {
        let r = egui::Rect::from_center_size(frame.center(), frame.size() * share);
        painter.rect_stroke(
            r,
            0.0,
            egui::Stroke::new(1.0, egui::Color32::from_white_alpha(alpha)),
            egui::StrokeKind::Middle,
        );
    };
    line(1.0, 200);
    line(0.9, 90);
    line(0.8, 60);
}

/// Sets the shot camera to look from `view`'s eye at its target at the
/// playhead (making one, 35 mm on 36 mm at 1280 × 720, if there is none);
/// one undo step.
pub fn camera_from_view(w: &mut Workspace, view: &OrbitCamera) {
    let frame = w.frame().round() as i32;
    let auto_key = w.session.auto_key;
    let (eye, target) = (view.eye().as_dvec3(), view.target.as_dvec3());
    w.apply("Camera from view", |s: &mut Scene| {
        let camera = s.camera.get_or_insert_with(|| ShotCamera {
            position: constant(eye),
            target: constant(target),
            focal_length_mm: Param::Constant(crate::scene::DEFAULT_FOCAL_LENGTH_MM),
            sensor_width_mm: Param::Constant(crate::scene::DEFAULT_SENSOR_WIDTH_MM),
            image_size: (1280, 720),
        });
        set_vector(&mut camera.position, eye, frame, auto_key);
        set_vector(&mut camera.target, target, frame, auto_key);
    });
}

/// Keys the camera's position, target and focal length where they are at
/// the playhead; one undo step.
pub fn key_camera(w: &mut Workspace) {
    let frame = w.frame().round() as i32;
    w.apply("Key camera", |s: &mut Scene| {
        let Some(camera) = s.camera.as_mut() else { return };
        let (p, t) = (&mut camera.position, &mut camera.target);
        for param in [&mut p.0, &mut p.1, &mut p.2, &mut t.0, &mut t.1, &mut t.2, &mut camera.focal_length_mm] {
            let value = sample(param, f64::from(frame));
            set_at_keying(param, frame, value, true);
        }
    });
}

fn constant(v: DVec3) -> ParamVec3 {
    (Param::Constant(v.x), Param::Constant(v.y), Param::Constant(v.z))
}

fn set_vector(vector: &mut ParamVec3, to: DVec3, frame: i32, auto_key: bool) {
    set_at_keying(&mut vector.0, frame, to.x, auto_key);
    set_at_keying(&mut vector.1, frame, to.y, auto_key);
    set_at_keying(&mut vector.2, frame, to.z, auto_key);
}
