//! The shot camera (`camera` in the scene, DESIGN.md's names): the camera a
//! film's shot is seen through, every number animatable like a layer's.

use serde::{Deserialize, Serialize};

use super::colliders::ParamVec3;
use super::param::Param;

/// Looks from `position` at `target` with +Y up; horizontal field of view
/// = 2·atan(sensor_width_mm / (2·focal_length_mm)); pictures `image_size`
/// pixels. Where `position` and `target` meet, it looks along −Z.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShotCamera {
    pub position: ParamVec3,
    pub target: ParamVec3,
    /// Greater than 0.
    #[serde(default = "default_focal_length")]
    pub focal_length_mm: Param,
    /// Greater than 0; 36 (full frame) by default.
    #[serde(default = "default_sensor_width")]
    pub sensor_width_mm: Param,
    /// (width, height) in pixels of what it pictures.
    #[serde(default = "default_image_size")]
    pub image_size: (u32, u32),
}

/// The focal length a camera gets when its file names none (mm).
pub const DEFAULT_FOCAL_LENGTH_MM: f64 = 35.0;
/// The sensor width a camera gets when its file names none (mm, full frame).
pub const DEFAULT_SENSOR_WIDTH_MM: f64 = 36.0;

fn default_focal_length() -> Param {
    Param::Constant(DEFAULT_FOCAL_LENGTH_MM)
}

fn default_sensor_width() -> Param {
    Param::Constant(DEFAULT_SENSOR_WIDTH_MM)
}

fn default_image_size() -> (u32, u32) {
    (1280, 720)
}

/// The horizontal field of view (degrees) of a lens of `focal_length_mm` on
/// a sensor `sensor_width_mm` wide; NaN where either is not positive.
pub fn horizontal_fov_deg(focal_length_mm: f64, sensor_width_mm: f64) -> f64 {
    if !(focal_length_mm > 0.0 && sensor_width_mm > 0.0) {
        return f64::NAN;
    }
    2.0 * (sensor_width_mm / (2.0 * focal_length_mm)).atan().to_degrees()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_full_frame_50_mm_lens_sees_about_40_degrees_across() {
        // 2·atan(18 / 50) = 39.6°.
        assert!((horizontal_fov_deg(50.0, 36.0) - 39.597_752_709_049_88).abs() < 1e-9);
        assert!((horizontal_fov_deg(18.0, 36.0) - 90.0).abs() < 1e-9, "a focal length of half the sensor: 90°");
        assert!(horizontal_fov_deg(0.0, 36.0).is_nan() && horizontal_fov_deg(50.0, f64::NAN).is_nan());
    }

    #[test]
    fn a_camera_needs_only_where_it_is_and_what_it_looks_at() {
        let camera: ShotCamera = ron::from_str("(position: (0.0, 1.5, 4.0), target: (0.0, 1.0, 0.0))").unwrap();
        assert_eq!(camera.focal_length_mm, Param::Constant(35.0));
        assert_eq!(camera.sensor_width_mm, Param::Constant(36.0));
        assert_eq!(camera.image_size, (1280, 720));
    }
}
