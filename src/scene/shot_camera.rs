//! The shot camera (`camera` in the scene, DESIGN.md's names): the camera a
//! film's shot is seen through, every number animatable like a layer's, or
//! a camera of a referenced glTF file followed at every frame
//! (`from_reference`).

use serde::{Deserialize, Serialize};

use super::colliders::{ParamVec3, zeros};
use super::param::Param;

/// Looks from `position` at `target` with +Y up; horizontal field of view
/// = 2·atan(sensor_width_mm / (2·focal_length_mm)); pictures `image_size`
/// pixels. Where `position` and `target` meet, it looks along −Z.
///
/// With `from_reference` it is that glTF camera instead: where it stands,
/// where it looks and its lens come from the reference at every frame, and
/// `position`, `target` and `focal_length_mm` are not used. A file may then
/// leave them out (they read as zeros and 35 mm, and such values are not
/// written back); without `from_reference`, `position` and `target` are
/// required.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "ShotCameraFields", into = "ShotCameraFields")]
pub struct ShotCamera {
    /// Follows a camera of a reference's glTF file; None: a camera of its own.
    pub from_reference: Option<ReferenceCamera>,
    pub position: ParamVec3,
    pub target: ParamVec3,
    /// Greater than 0.
    pub focal_length_mm: Param,
    /// Greater than 0; 36 (full frame) by default.
    pub sensor_width_mm: Param,
    /// (width, height) in pixels of what it pictures.
    pub image_size: (u32, u32),
}

/// A camera of a referenced glTF file (`camera.from_reference`): it stands
/// and looks where the camera's node is at each frame, posed with the
/// reference's clock and placement, and sees the file's vertical field of
/// view across the picture's height (see [`focal_length_from_yfov`]). The
/// renderer's camera cannot roll: a rolled glTF camera is shown level.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceCamera {
    /// The reference's `name`.
    pub reference: String,
    /// The camera's name in the file: its node's name, else the glTF camera's own.
    pub camera: String,
}

/// [`ShotCamera`] as the file writes it: where it stands and looks may be
/// left out when it follows a reference's camera.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ShotCameraFields {
    #[serde(default, with = "present", skip_serializing_if = "Option::is_none")]
    from_reference: Option<ReferenceCamera>,
    #[serde(default, with = "present", skip_serializing_if = "Option::is_none")]
    position: Option<ParamVec3>,
    #[serde(default, with = "present", skip_serializing_if = "Option::is_none")]
    target: Option<ParamVec3>,
    #[serde(default, with = "present", skip_serializing_if = "Option::is_none")]
    focal_length_mm: Option<Param>,
    #[serde(default = "default_sensor_width")]
    sensor_width_mm: Param,
    #[serde(default = "default_image_size")]
    image_size: (u32, u32),
}

/// An optional field written as its value alone (`position: (0.0, 1.0, 2.0)`,
/// not `Some(…)`), whether or not the reader takes implicit `Some`s.
mod present {
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    pub fn deserialize<'de, D: Deserializer<'de>, T: Deserialize<'de>>(from: D) -> Result<Option<T>, D::Error> {
        T::deserialize(from).map(Some)
    }

    pub fn serialize<S: Serializer, T: Serialize>(value: &Option<T>, to: S) -> Result<S::Ok, S::Error> {
        match value {
            Some(value) => value.serialize(to),
            None => to.serialize_none(),
        }
    }
}

impl TryFrom<ShotCameraFields> for ShotCamera {
    type Error = String;

    /// A camera of its own needs `position` and `target`; one following a
    /// reference's camera needs neither.
    fn try_from(fields: ShotCameraFields) -> Result<ShotCamera, String> {
        if fields.from_reference.is_none() {
            let missing: Vec<&str> = [("`position`", fields.position.is_none()), ("`target`", fields.target.is_none())]
                .into_iter()
                .filter_map(|(name, missing)| missing.then_some(name))
                .collect();
            if !missing.is_empty() {
                let (names, verb) =
                    if missing.len() == 2 { ("`position` and `target`", "are") } else { (missing[0], "is") };
                return Err(format!(
                    "camera: {names} {verb} missing: a camera looks from `position` at `target`, \
                     or follows a reference's camera with `from_reference: (reference: \"…\", camera: \"…\")`"
                ));
            }
        }
        Ok(ShotCamera {
            from_reference: fields.from_reference,
            position: fields.position.unwrap_or_else(zeros),
            target: fields.target.unwrap_or_else(zeros),
            focal_length_mm: fields.focal_length_mm.unwrap_or_else(default_focal_length),
            sensor_width_mm: fields.sensor_width_mm,
            image_size: fields.image_size,
        })
    }
}

impl From<ShotCamera> for ShotCameraFields {
    /// Every field of a camera of its own is written; a camera following a
    /// reference's leaves out the numbers it does not use where they are
    /// what a file leaving them out reads as, so the text reads back equal.
    fn from(camera: ShotCamera) -> ShotCameraFields {
        let following = camera.from_reference.is_some();
        let written = |unused: bool| !(following && unused);
        let (position, target) = (camera.position, camera.target);
        ShotCameraFields {
            position: written(position == zeros()).then_some(position),
            target: written(target == zeros()).then_some(target),
            focal_length_mm: written(camera.focal_length_mm == default_focal_length())
                .then_some(camera.focal_length_mm),
            from_reference: camera.from_reference,
            sensor_width_mm: camera.sensor_width_mm,
            image_size: camera.image_size,
        }
    }
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

/// The focal length (mm) that, on a sensor `sensor_width_mm` wide, sees a
/// picture `aspect` (width over height) wide with the vertical field of view
/// `yfov_rad` (a glTF camera's): the horizontal field of view is
/// hfov = 2·atan(tan(yfov/2)·aspect), and the focal length
/// sensor / (2·tan(hfov/2)) = sensor / (2·tan(yfov/2)·aspect). NaN where
/// the field of view is not within (0, π) or the sensor or aspect is not
/// greater than 0.
pub fn focal_length_from_yfov(yfov_rad: f64, aspect: f64, sensor_width_mm: f64) -> f64 {
    if !(yfov_rad > 0.0 && yfov_rad < std::f64::consts::PI && aspect > 0.0 && sensor_width_mm > 0.0) {
        return f64::NAN;
    }
    let hfov = 2.0 * ((yfov_rad / 2.0).tan() * aspect).atan();
    sensor_width_mm / (2.0 * (hfov / 2.0).tan())
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
    fn a_gltf_field_of_view_becomes_the_focal_length_that_sees_it() {
        // yfov 2·atan(0.3) on a 16:9 picture: tan(hfov/2) = 0.3·16/9 = 0.5333…,
        // so on 36 mm the focal length is 18 / 0.5333… = 33.75 mm.
        let focal = focal_length_from_yfov(2.0 * 0.3f64.atan(), 16.0 / 9.0, 36.0);
        assert!((focal - 33.75).abs() < 1e-9, "{focal}");
        // And back: that lens sees the same field of view across the picture's height.
        let hfov = horizontal_fov_deg(focal, 36.0).to_radians();
        let yfov = 2.0 * ((hfov / 2.0).tan() / (16.0 / 9.0)).atan();
        assert!((yfov - 2.0 * 0.3f64.atan()).abs() < 1e-12);
        // A square picture, 90° up and down: 90° across, half the sensor.
        assert!((focal_length_from_yfov(std::f64::consts::FRAC_PI_2, 1.0, 36.0) - 18.0).abs() < 1e-9);
        for (yfov, aspect, sensor) in [(0.0, 1.0, 36.0), (4.0, 1.0, 36.0), (0.5, 0.0, 36.0), (0.5, 1.0, -1.0)] {
            assert!(focal_length_from_yfov(yfov, aspect, sensor).is_nan(), "{yfov} {aspect} {sensor}");
        }
    }

    #[test]
    fn a_camera_following_a_reference_needs_no_position_and_reads_back_equal() {
        let text = "(from_reference: (reference: \"layout\", camera: \"ShotCam\"), image_size: (640, 360))";
        let camera: ShotCamera = ron::from_str(text).unwrap();
        let expected = ReferenceCamera { reference: "layout".into(), camera: "ShotCam".into() };
        assert_eq!(camera.from_reference, Some(expected));
        assert_eq!((camera.position.clone(), camera.focal_length_mm.clone()), (zeros(), Param::Constant(35.0)));
        let written = ron::to_string(&camera).unwrap();
        assert!(!written.contains("position") && !written.contains("focal"), "{written}");
        assert_eq!(ron::from_str::<ShotCamera>(&written).unwrap(), camera);
        // Numbers it keeps while following (set before, or written by hand) are written back.
        let kept =
            ShotCamera { position: (Param::Constant(1.0), Param::Constant(2.0), Param::Constant(3.0)), ..camera };
        let written = ron::to_string(&kept).unwrap();
        assert!(written.contains("position") && !written.contains("target"), "{written}");
        assert_eq!(ron::from_str::<ShotCamera>(&written).unwrap(), kept);
    }

    #[test]
    fn a_camera_of_its_own_says_what_it_lacks() {
        let error = |text: &str| ron::from_str::<ShotCamera>(text).unwrap_err().to_string();
        let neither = error("(image_size: (640, 360))");
        assert!(neither.contains("camera: `position` and `target` are missing"), "{neither}");
        assert!(neither.contains("from_reference"), "{neither}");
        assert!(error("(position: (0.0, 1.0, 2.0))").contains("camera: `target` is missing"));
        assert!(error("(position: (0.0, 1.0, 2.0), target: (0.0, 0.0, 0.0), focus: 3.0)").contains("focus"));
        let plain: ShotCamera = ron::from_str("(position: (0.0, 1.0, 2.0), target: (0.0, 0.0, 0.0))").unwrap();
        let written = ron::to_string(&plain).unwrap();
        assert!(written.contains("focal_length_mm") && !written.contains("from_reference"), "{written}");
    }

    #[test]
    fn a_camera_needs_only_where_it_is_and_what_it_looks_at() {
        let camera: ShotCamera = ron::from_str("(position: (0.0, 1.5, 4.0), target: (0.0, 1.0, 0.0))").unwrap();
        assert_eq!(camera.focal_length_mm, Param::Constant(35.0));
        assert_eq!(camera.sensor_width_mm, Param::Constant(36.0));
        assert_eq!(camera.image_size, (1280, 720));
        assert_eq!(camera.from_reference, None);
    }
}
