//! The shot's animatable numbers (the camera's and the plate's), as the
//! Shot panel's rows and the curve view name them.

use crate::scene::{Param, Scene};

/// One of the shot camera's numbers (an axis 0 x, 1 y, 2 z of its position
/// or target, its lens, its sensor), or the plate's opacity.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShotNumber {
    Position(usize),
    Target(usize),
    FocalLength,
    SensorWidth,
    PlateOpacity,
}

impl ShotNumber {
    /// The camera's numbers, in panel order.
    pub const CAMERA: [ShotNumber; 8] = [
        ShotNumber::Position(0),
        ShotNumber::Position(1),
        ShotNumber::Position(2),
        ShotNumber::Target(0),
        ShotNumber::Target(1),
        ShotNumber::Target(2),
        ShotNumber::FocalLength,
        ShotNumber::SensorWidth,
    ];

    /// Its name as its row shows it ("position y", "focal length").
    pub fn label(self) -> String {
        let axis = |a: usize| ["x", "y", "z"].get(a).copied().unwrap_or("?");
        match self {
            ShotNumber::Position(a) => format!("position {}", axis(a)),
            ShotNumber::Target(a) => format!("target {}", axis(a)),
            ShotNumber::FocalLength => "focal length".to_owned(),
            ShotNumber::SensorWidth => "sensor width".to_owned(),
            ShotNumber::PlateOpacity => "plate opacity".to_owned(),
        }
    }

    /// The number in `scene`; `None` without a camera (or plate), or for an axis past z.
    pub fn param(self, scene: &Scene) -> Option<&Param> {
        let camera = scene.camera.as_ref();
        match self {
            ShotNumber::Position(a) => {
                camera.and_then(|c| [&c.position.0, &c.position.1, &c.position.2].get(a).copied())
            }
            ShotNumber::Target(a) => camera.and_then(|c| [&c.target.0, &c.target.1, &c.target.2].get(a).copied()),
            ShotNumber::FocalLength => camera.map(|c| &c.focal_length_mm),
            ShotNumber::SensorWidth => camera.map(|c| &c.sensor_width_mm),
            ShotNumber::PlateOpacity => scene.plate.as_ref().map(|p| &p.opacity),
        }
    }

    pub fn param_mut(self, scene: &mut Scene) -> Option<&mut Param> {
        if self == ShotNumber::PlateOpacity {
            return scene.plate.as_mut().map(|p| &mut p.opacity);
        }
        let camera = scene.camera.as_mut()?;
        match self {
            ShotNumber::Position(a) => {
                let (x, y, z) = &mut camera.position;
                [x, y, z].into_iter().nth(a)
            }
            ShotNumber::Target(a) => {
                let (x, y, z) = &mut camera.target;
                [x, y, z].into_iter().nth(a)
            }
            ShotNumber::FocalLength => Some(&mut camera.focal_length_mm),
            ShotNumber::SensorWidth => Some(&mut camera.sensor_width_mm),
            ShotNumber::PlateOpacity => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_number_is_found_where_the_scene_keeps_it() {
        let mut scene = crate::scene::parse(
            "(version: 1, cloth: (size: (1.0, 1.0), grid: (2, 2)), \
             keys: [(frame: 0, pins: [(grid: (0, 0), pos: (0.0, 1.0, 0.0))])], \
             camera: (position: (1.0, 2.0, 3.0), target: (4.0, 5.0, 6.0), focal_length_mm: 50.0))",
            "shot.ron",
        )
        .unwrap();
        let values: Vec<Param> = ShotNumber::CAMERA.iter().map(|n| n.param(&scene).unwrap().clone()).collect();
        let expected = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 50.0, 36.0].map(Param::Constant);
        assert_eq!(values, expected);
        assert!(ShotNumber::PlateOpacity.param(&scene).is_none(), "no plate");
        *ShotNumber::Target(1).param_mut(&mut scene).unwrap() = Param::Constant(9.0);
        assert_eq!(scene.camera.as_ref().unwrap().target.1, Param::Constant(9.0));
        assert!(ShotNumber::Position(3).param(&scene).is_none());
        assert_eq!(ShotNumber::FocalLength.label(), "focal length");
    }
}
