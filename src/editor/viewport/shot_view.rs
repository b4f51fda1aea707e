//! Looking through the scene's shot camera in the viewport (the View
//! panel's Camera toggle, or View ▸ Look through camera):
//! the camera at the playhead, its picture's frame drawn with action-safe
//! (90 %) and title-safe (80 %) guides; and setting the camera from the view,
//! keying it at the playhead, making it follow a reference's glTF camera or
//! letting go of one, each one undo step.

use eframe::egui;
use glam::DVec3;

use crate::animate::track::sample;
use crate::editor::param_edit::set_at_keying;
use crate::editor::workspace::Workspace;
use crate::picture::{look_camera, shot_look_at};
use crate::render::OrbitCamera;
use crate::scene::{MAX_IMAGE_SIDE_PX, Param, ParamVec3, ReferenceCamera, Scene, ShotCamera};
use crate::world::rig::Projection;

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

/// The viewport's camera that shows `camera` (of `scene`, whose references
/// it may follow) at `frame` with its picture filling [`frame_rect`] of
/// `rect`: the shot camera's, its vertical field of view widened by the
/// viewport's height over the frame's.
pub fn through(scene: &Scene, camera: &ShotCamera, frame: f64, rect: egui::Rect) -> OrbitCamera {
    let mut view = look_camera(&shot_look_at(scene, camera, frame), camera.image_size);
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
    let auto_key = w.session.auto_key();
    let (eye, target) = (view.eye().as_dvec3(), view.target.as_dvec3());
    w.apply("Camera from view", |s: &mut Scene| {
        let camera = s.camera.get_or_insert_with(|| ShotCamera {
            from_reference: None,
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

/// The perspective cameras of `scene`'s references, as the shot camera's
/// `from_reference` names them, in reference order then file order. A
/// reference whose file is not read, or without a name, offers none.
pub fn reference_cameras(scene: &Scene) -> Vec<ReferenceCamera> {
    let mut cameras = Vec::new();
    for reference in scene.references.iter().filter(|r| !r.name.trim().is_empty()) {
        let Some(rig) = reference.rig.0.as_deref() else { continue };
        for camera in rig.cameras() {
            // Several nodes may carry cameras of one name: the first is the one found.
            let first = rig.camera_named(&camera.name).is_some_and(|c| c.node == camera.node);
            if first && matches!(camera.projection, Projection::Perspective { .. }) {
                cameras.push(ReferenceCamera { reference: reference.name.clone(), camera: camera.name.clone() });
            }
        }
    }
    cameras
}

/// Makes the shot camera follow `from` (a camera of one of the scene's
/// references); one undo step. Without a shot camera, one is made, 1280
/// pixels wide and as high as the glTF camera's aspect ratio asks (720
/// where it names none). Its own numbers are kept, unused, until it lets go.
pub fn camera_from_reference(w: &mut Workspace, from: ReferenceCamera) {
    let aspect = w
        .doc
        .scene()
        .references
        .iter()
        .find(|r| r.name == from.reference)
        .and_then(|r| r.rig.0.as_deref()?.camera_named(&from.camera).map(|c| c.projection))
        .and_then(|p| match p {
            Projection::Perspective { aspect_ratio, .. } => aspect_ratio,
            Projection::Orthographic => None,
        });
    let height = aspect.map_or(720, |a| (1280.0 / a).round().clamp(1.0, f64::from(MAX_IMAGE_SIDE_PX)) as u32);
    w.apply("Camera from reference", |s: &mut Scene| {
        let camera = s.camera.get_or_insert_with(|| ShotCamera {
            from_reference: None,
            position: constant(DVec3::ZERO),
            target: constant(DVec3::ZERO),
            focal_length_mm: Param::Constant(crate::scene::DEFAULT_FOCAL_LENGTH_MM),
            sensor_width_mm: Param::Constant(crate::scene::DEFAULT_SENSOR_WIDTH_MM),
            image_size: (1280, height),
        });
        camera.from_reference = Some(from);
    });
}

/// Lets the shot camera go of the reference's camera it follows, leaving a
/// camera of its own where that one is at the playhead: its position, aim
/// and focal length as constants (nothing is keyed; the reference's motion
/// is not baked); one undo step.
pub fn detach_camera(w: &mut Workspace) {
    let frame = w.frame();
    let Some(camera) = w.doc.scene().camera.as_ref() else { return };
    let look = shot_look_at(w.doc.scene(), camera, frame);
    w.apply("Detach camera from reference", |s: &mut Scene| {
        let Some(camera) = s.camera.as_mut() else { return };
        camera.from_reference = None;
        camera.position = constant(look.position);
        camera.target = constant(look.target);
        if look.focal_length_mm.is_finite() {
            camera.focal_length_mm = Param::Constant(look.focal_length_mm);
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A curtain with `assets/layout_camera.glb` as reference "layout" (its
    /// dolly moves "ShotCam" from x = −1 to +1 over frames 0–24) and no camera.
    fn layout() -> Workspace {
        let dir = tempfile::tempdir().unwrap();
        let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/layout_camera.glb");
        let text = format!(
            "(version: 1, cloth: (size: (1.0, 1.0), grid: (5, 5)), \
             keys: [(frame: 0, pins: [(grid: (0, 0), pos: (0.0, 1.5, 0.0))])], \
             references: [(name: \"layout\", file: {:?})])",
            file.display().to_string()
        );
        let path = dir.path().join("layout.ron");
        std::fs::write(&path, text).unwrap();
        Workspace::new(crate::scene::load(&path).unwrap(), None)
    }

    fn shot_cam() -> ReferenceCamera {
        ReferenceCamera { reference: "layout".into(), camera: "ShotCam".into() }
    }

    #[test]
    fn the_references_perspective_cameras_are_offered() {
        let w = layout();
        let names: Vec<String> = reference_cameras(w.doc.scene()).into_iter().map(|c| c.camera).collect();
        assert_eq!(names, ["ShotCam", "Dutch"], "the orthographic \"Plan\" is not");
    }

    #[test]
    fn following_a_reference_camera_and_letting_go_are_one_undo_step_each() {
        let mut w = layout();
        camera_from_reference(&mut w, shot_cam());
        let camera = w.doc.scene().camera.clone().expect("a camera made");
        assert_eq!((camera.from_reference, camera.image_size), (Some(shot_cam()), (1280, 720)));
        assert_eq!(w.doc.undo_label(), Some("Camera from reference"));

        // Frame 6: the dolly at x = −0.5, so the camera at (−0.5, 1.5, 4), tilted 10° down.
        w.set_frame(6.0);
        let rect = egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(800.0, 600.0));
        let scene = w.doc.scene();
        let view = through(scene, scene.camera.as_ref().unwrap(), 6.0, rect);
        assert!(view.eye().abs_diff_eq(glam::Vec3::new(-0.5, 1.5, 4.0), 1e-5), "{}", view.eye());
        detach_camera(&mut w);
        let plain = w.doc.scene().camera.clone().unwrap();
        assert_eq!(plain.from_reference, None);
        assert_eq!(w.doc.undo_label(), Some("Detach camera from reference"));
        let (Param::Constant(x), Param::Constant(focal)) = (&plain.position.0, &plain.focal_length_mm) else {
            panic!("constants: {plain:?}")
        };
        assert!((x + 0.5).abs() < 1e-6, "{x}");
        assert!((focal - 36.0 / (2.0 * 0.25f64.tan() * 16.0 / 9.0)).abs() < 1e-6, "{focal}");
        // The picture does not jump when it lets go.
        let scene = w.doc.scene();
        let after = through(scene, scene.camera.as_ref().unwrap(), 6.0, rect);
        assert!(after.eye().abs_diff_eq(view.eye(), 1e-5) && (after.fov_y_deg - view.fov_y_deg).abs() < 1e-4);
        assert!(after.target.abs_diff_eq(view.target, 1e-4), "{} vs {}", after.target, view.target);

        w.undo();
        assert_eq!(w.doc.scene().camera.as_ref().unwrap().from_reference, Some(shot_cam()));
        w.undo();
        assert_eq!(w.doc.scene().camera, None);
    }
}
