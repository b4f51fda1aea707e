//! The scene's shot camera at a frame as the renderer's camera: where it
//! stands, what it looks at and its lens, each number sampled at the frame,
//! or a referenced glTF camera posed at the frame ([`scene_shot_camera_at`]).

use glam::DVec3;

use crate::animate::references_at::reference_camera_at;
use crate::animate::track::{sample, sample_vec3};
use crate::render::OrbitCamera;
use crate::scene::{Scene, ShotCamera, focal_length_from_yfov, horizontal_fov_deg};
use crate::world::rig::Projection;

/// How far ahead of a reference's camera its aim point is, in its near
/// planes: the renderer's near plane is 1/100 of the distance to the aim
/// point, so this puts it where the glTF camera's is.
const AIM_IN_NEAR_PLANES: f64 = 100.0;
/// The aim point of a reference's camera is this far ahead at least and at
/// most (m), whatever its near plane, so depth stays usable.
const AIM_DISTANCE_M: (f64, f64) = (0.1, 1000.0);

/// What a shot camera does at one frame, in a camera of its own's numbers:
/// it looks from `position` at `target` through `focal_length_mm` on
/// `sensor_width_mm`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShotLook {
    pub position: DVec3,
    pub target: DVec3,
    pub focal_length_mm: f64,
    pub sensor_width_mm: f64,
    /// How far the reference's camera it follows is rolled (degrees, see
    /// [`crate::world::rig::CameraPose::roll_deg`]): the picture is shown
    /// level, without it. 0 for a camera of its own.
    pub roll_deg: f64,
    /// Whether it comes from a reference's camera (false where it follows
    /// none, or one that cannot be found: see [`shot_look_at`]).
    pub from_reference: bool,
}

/// `camera` of `scene` at `frame`. A camera of its own: its numbers sampled.
/// One following a reference's camera (`from_reference`): it stands where
/// that camera's node is, posed with the reference's clock and placement,
/// and aims down the node's −Z (at a point 100 near planes ahead, within
/// 0.1–1000 m); its focal length sees the glTF vertical field of view across
/// the height of a picture of `camera.image_size`
/// ([`focal_length_from_yfov`]); its roll is left out (+Y stays up). Where
/// that camera cannot be found or posed (a scene parsed from text, whose
/// files are not read; a reference renamed since), or is orthographic, the
/// camera's own numbers stand in.
pub fn shot_look_at(scene: &Scene, camera: &ShotCamera, frame: f64) -> ShotLook {
    let sensor_width_mm = sample(&camera.sensor_width_mm, frame);
    let posed = camera.from_reference.as_ref().and_then(|from| reference_camera_at(scene, from, frame));
    if let Some(posed) = posed
        && let Projection::Perspective { yfov_rad, znear, .. } = posed.projection
    {
        let (width, height) = camera.image_size;
        let aspect = f64::from(width.max(1)) / f64::from(height.max(1));
        let distance = (znear * AIM_IN_NEAR_PLANES).clamp(AIM_DISTANCE_M.0, AIM_DISTANCE_M.1);
        return ShotLook {
            position: posed.pose.eye,
            target: posed.pose.eye + posed.pose.forward * distance,
            focal_length_mm: focal_length_from_yfov(yfov_rad, aspect, sensor_width_mm),
            sensor_width_mm,
            roll_deg: posed.pose.roll_deg(),
            from_reference: true,
        };
    }
    own_look(camera, frame)
}

/// `camera`'s own numbers at `frame`, whatever it follows.
fn own_look(camera: &ShotCamera, frame: f64) -> ShotLook {
    ShotLook {
        position: sample_vec3(&camera.position, frame),
        target: sample_vec3(&camera.target, frame),
        focal_length_mm: sample(&camera.focal_length_mm, frame),
        sensor_width_mm: sample(&camera.sensor_width_mm, frame),
        roll_deg: 0.0,
        from_reference: false,
    }
}

/// The scene's shot camera at `frame` as the renderer's camera, picturing
/// `size_px` (see [`shot_camera_at`]), following a reference's camera where
/// it does ([`shot_look_at`]); None when the scene has no shot camera.
pub fn scene_shot_camera_at(scene: &Scene, frame: f64, size_px: (u32, u32)) -> Option<OrbitCamera> {
    let camera = scene.camera.as_ref()?;
    Some(look_camera(&shot_look_at(scene, camera, frame), size_px))
}

/// Steepest a shot camera looks up or down (degrees): straight down, +Y up
/// leaves no way to turn the picture.
const MAX_PITCH_DEG: f64 = 89.9;

/// `camera`'s own numbers at `frame`, picturing `size_px` (its
/// `image_size`, or what a render asks for instead: the horizontal field of
/// view is the lens's, the vertical one follows from the picture's shape).
/// It does not look at `from_reference`, which needs the scene:
/// [`scene_shot_camera_at`] does.
pub fn shot_camera_at(camera: &ShotCamera, frame: f64, size_px: (u32, u32)) -> OrbitCamera {
    look_camera(&own_look(camera, frame), size_px)
}

/// The renderer's camera that looks as `look` does, picturing `size_px`.
pub fn look_camera(look: &ShotLook, size_px: (u32, u32)) -> OrbitCamera {
    let (position, target) = (look.position, look.target);
    let offset = position - target;
    // Where position and target meet, it looks along −Z from where it is.
    let (target, back, distance) = match offset.try_normalize() {
        Some(back) => (target, back, offset.length()),
        None => (position - DVec3::Z, DVec3::Z, 1.0),
    };
    let pitch_deg = back.y.clamp(-1.0, 1.0).asin().to_degrees().clamp(-MAX_PITCH_DEG, MAX_PITCH_DEG);
    let yaw_deg = back.x.atan2(back.z).to_degrees();
    let fov_x = horizontal_fov_deg(look.focal_length_mm, look.sensor_width_mm);
    let aspect = f64::from(size_px.0.max(1)) / f64::from(size_px.1.max(1));
    let fov_y_deg = 2.0 * ((fov_x.to_radians() * 0.5).tan() / aspect).atan().to_degrees();
    OrbitCamera {
        target: target.as_vec3(),
        yaw_deg: yaw_deg as f32,
        pitch_deg: pitch_deg as f32,
        distance_m: distance as f32,
        fov_y_deg: fov_y_deg as f32,
    }
}

#[cfg(test)]
mod tests {
    use glam::{Vec2, Vec3};

    use super::*;

    fn camera(text: &str) -> ShotCamera {
        ron::from_str(text).unwrap()
    }

    #[test]
    fn known_points_land_on_hand_computed_pixels() {
        // From (0, 1, 4) at (0, 1, 0), 50 mm on 36 mm, 1000 × 500: tan(fov_x / 2)
        // = 18 / 50 = 0.36, so at 4 m the picture is 2.88 m wide (347.2 px/m)
        // and, at the same scale, 1.44 m high.
        let shot = camera(
            "(position: (0.0, 1.0, 4.0), target: (0.0, 1.0, 0.0), focal_length_mm: 50.0, image_size: (1000, 500))",
        );
        let size = (1000, 500);
        let view = shot_camera_at(&shot, 0.0, size);
        let px_per_m = 500.0 / (4.0 * 0.36);
        let at = |p: Vec3| view.project(p, size).unwrap();
        assert!(at(Vec3::new(0.0, 1.0, 0.0)).abs_diff_eq(Vec2::new(500.0, 250.0), 1e-3));
        let right = at(Vec3::new(0.5, 1.0, 0.0));
        assert!((right.x - (500.0 + 0.5 * px_per_m as f32)).abs() < 0.01 && (right.y - 250.0).abs() < 0.01, "{right}");
        let up = at(Vec3::new(0.0, 1.3, 0.0));
        assert!((up.y - (250.0 - 0.3 * px_per_m as f32)).abs() < 0.01, "{up}");
        // Twice as far away, half as far from the middle.
        let far = at(Vec3::new(0.5, 1.0, -4.0));
        assert!((far.x - (500.0 + 0.25 * px_per_m as f32)).abs() < 0.01, "{far}");
        // The picture's edges: ±1.44 m at 4 m.
        assert!((at(Vec3::new(1.44, 1.0, 0.0)).x - 1000.0).abs() < 0.01);
    }

    #[test]
    fn an_animated_camera_is_sampled_at_in_between_frames() {
        let shot = camera(
            "(position: ([(frame: 0, value: -2.0), (frame: 24, value: 2.0, ease: Linear)], 1.0, 4.0), \
             target: (0.0, 1.0, 0.0), focal_length_mm: [(frame: 0, value: 35.0), (frame: 24, value: 70.0)])",
        );
        let size = (1280, 720);
        // Frame 12: halfway, x = 0 and (the key at 0 eases in and out by default) 52.5 mm.
        let view = shot_camera_at(&shot, 12.0, size);
        assert!(view.eye().abs_diff_eq(Vec3::new(0.0, 1.0, 4.0), 1e-5), "{}", view.eye());
        let fov_x = horizontal_fov_deg(52.5, 36.0);
        let fov_y = 2.0 * ((fov_x.to_radians() / 2.0).tan() * 720.0 / 1280.0).atan().to_degrees();
        assert!((f64::from(view.fov_y_deg) - fov_y).abs() < 1e-4, "{} vs {fov_y}", view.fov_y_deg);
        let start = shot_camera_at(&shot, 0.0, size);
        assert!(start.eye().abs_diff_eq(Vec3::new(-2.0, 1.0, 4.0), 1e-5));
    }

    #[test]
    fn a_camera_on_its_target_or_straight_above_it_still_pictures() {
        let on = camera("(position: (1.0, 2.0, 3.0), target: (1.0, 2.0, 3.0))");
        let view = shot_camera_at(&on, 0.0, (1280, 720));
        assert!(view.eye().abs_diff_eq(Vec3::new(1.0, 2.0, 3.0), 1e-5), "it stays where it is: {}", view.eye());
        assert!(view.view_from_world().is_finite());
        let above = camera("(position: (0.0, 5.0, 0.0), target: (0.0, 0.0, 0.0))");
        assert!(shot_camera_at(&above, 0.0, (1280, 720)).view_from_world().is_finite());
    }
}
