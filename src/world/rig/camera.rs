//! The cameras of a rig: a glTF camera hung on a node, which looks down the
//! node's −Z with its +Y up (glTF 2.0 §3.10), wherever the node is posed.

use glam::{DMat4, DVec3};

use super::{Pose, Rig};

/// How a glTF camera projects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    Perspective {
        /// Vertical field of view (radians), in (0, π).
        yfov_rad: f64,
        /// Width over height the file asks for; None: the picture's own.
        aspect_ratio: Option<f64>,
        /// Distance to the near clipping plane (the file's units), > 0.
        znear: f64,
    },
    /// Parallel rays: kept so that choosing one can be refused by name.
    Orthographic,
}

/// A camera on a node of the file's default scene.
#[derive(Clone, Debug, PartialEq)]
pub struct RigCamera {
    /// Its node's name (what Blender's outliner shows), else the camera's
    /// own name, else "camera N" (N its index in the file, from 1).
    pub name: String,
    /// The node it hangs on.
    pub node: usize,
    pub projection: Projection,
}

/// A camera at one pose: where it is and which way it looks, in the
/// coordinates of the matrix it was posed with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraPose {
    pub eye: DVec3,
    /// Unit vector it looks along: the node's −Z.
    pub forward: DVec3,
    /// Unit vector up in its picture: the node's +Y (a roll tilts it).
    pub up: DVec3,
}

impl CameraPose {
    /// The camera of a node whose coordinates `world_from_node` takes into
    /// the world. A node scaled flat along an axis (a zero scale) leaves no
    /// direction: −Z and +Y of the world stand in for it.
    pub fn of_node(world_from_node: DMat4) -> CameraPose {
        let eye = world_from_node.transform_point3(DVec3::ZERO);
        let forward = world_from_node.transform_vector3(DVec3::NEG_Z).try_normalize().unwrap_or(DVec3::NEG_Z);
        let up = world_from_node.transform_vector3(DVec3::Y).try_normalize().unwrap_or(DVec3::Y);
        CameraPose { eye, forward, up }
    }

    /// How far it is turned about its line of sight from level (degrees;
    /// positive: its up leans left as it looks, the world in its picture
    /// turned clockwise); 0 for a camera looking straight up or down, where
    /// no level exists.
    pub fn roll_deg(&self) -> f64 {
        let Some(level_right) = self.forward.cross(DVec3::Y).try_normalize() else { return 0.0 };
        let level_up = level_right.cross(self.forward);
        let up = self.up - self.forward * self.up.dot(self.forward);
        (-up.dot(level_right)).atan2(up.dot(level_up)).to_degrees()
    }
}

impl Rig {
    /// The camera named `name` (the first, if several share it), or None.
    pub fn camera_named(&self, name: &str) -> Option<&RigCamera> {
        self.cameras.iter().find(|c| c.name == name)
    }

    /// Camera `camera` (an index into [`Rig::cameras`]) at `pose`, in the
    /// file's coordinates; None for an index out of range.
    pub fn camera_pose(&self, camera: usize, pose: &Pose) -> Option<CameraPose> {
        let node = self.cameras.get(camera)?.node;
        Some(CameraPose::of_node(*pose.world_from_node.get(node)?))
    }
}

/// `camera` names a node of `nodes` and has numbers a camera can have.
pub(super) fn check_camera(camera: &RigCamera, nodes: usize) -> Result<(), String> {
    let what = format!("camera {:?}", camera.name);
    if camera.node >= nodes {
        return Err(format!("{what} hangs on node {}, and there are {nodes}", camera.node));
    }
    if let Projection::Perspective { yfov_rad, aspect_ratio, znear } = camera.projection {
        if !(yfov_rad > 0.0 && yfov_rad < std::f64::consts::PI) {
            return Err(format!("{what}: its vertical field of view ({yfov_rad} radians) must be between 0 and π"));
        }
        if aspect_ratio.is_some_and(|a| !(a.is_finite() && a > 0.0)) {
            return Err(format!("{what}: its aspect ratio must be greater than 0"));
        }
        if !(znear.is_finite() && znear > 0.0) {
            return Err(format!("{what}: its near plane must be greater than 0"));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use glam::DQuat;

    use super::super::{RigNode, Trs};
    use super::*;

    #[test]
    fn a_camera_looks_down_its_nodes_minus_z() {
        let level = CameraPose::of_node(DMat4::from_translation(DVec3::new(1.0, 2.0, 3.0)));
        assert_eq!(level.eye, DVec3::new(1.0, 2.0, 3.0));
        assert_eq!((level.forward, level.up), (DVec3::NEG_Z, DVec3::Y));
        assert!(level.roll_deg().abs() < 1e-12);
        // Turned 90° about Y it looks along −X; pitched 30° down it looks lower.
        let turned = CameraPose::of_node(DMat4::from_rotation_y(90f64.to_radians()));
        assert!(turned.forward.abs_diff_eq(DVec3::NEG_X, 1e-12), "{}", turned.forward);
        let down = CameraPose::of_node(DMat4::from_rotation_x(-30f64.to_radians()));
        assert!(down.forward.abs_diff_eq(DVec3::new(0.0, -0.5, -(0.75f64.sqrt())), 1e-12), "{}", down.forward);
        assert!(down.roll_deg().abs() < 1e-9, "a pitch is no roll: {}", down.roll_deg());
        // Rolled 20° about its line of sight (counter-clockwise as it sees).
        let rolled = CameraPose::of_node(DMat4::from_rotation_z(20f64.to_radians()));
        assert!((rolled.roll_deg() - 20.0).abs() < 1e-9, "{}", rolled.roll_deg());
        // A node squashed flat leaves no direction: the defaults stand in.
        let flat = CameraPose::of_node(DMat4::from_scale(DVec3::ZERO));
        assert_eq!((flat.forward, flat.up), (DVec3::NEG_Z, DVec3::Y));
    }

    #[test]
    fn cameras_are_found_by_name_and_checked() {
        let node = RigNode {
            name: "cam".into(),
            parent: None,
            rest: Trs { rotation: DQuat::from_rotation_y(1.0), ..Trs::IDENTITY },
            morph_weights: vec![],
        };
        let lens = Projection::Perspective { yfov_rad: 0.5, aspect_ratio: None, znear: 0.1 };
        let camera = RigCamera { name: "cam".into(), node: 0, projection: lens };
        let rig = Rig::new(vec![node.clone()], vec![], vec![], vec![]).unwrap().with_cameras(vec![camera.clone()]);
        let rig = rig.unwrap();
        assert_eq!(rig.camera_named("cam"), Some(&camera));
        assert_eq!(rig.camera_named("other"), None);
        let pose = rig.camera_pose(0, &rig.rest_pose()).unwrap();
        assert!(pose.forward.abs_diff_eq(DQuat::from_rotation_y(1.0) * DVec3::NEG_Z, 1e-12));
        assert_eq!(rig.camera_pose(1, &rig.rest_pose()), None);

        let with = |camera: RigCamera| {
            Rig::new(vec![node.clone()], vec![], vec![], vec![]).unwrap().with_cameras(vec![camera]).unwrap_err()
        };
        assert!(with(RigCamera { node: 3, ..camera.clone() }).contains("hangs on node 3"));
        let wide = Projection::Perspective { yfov_rad: 4.0, aspect_ratio: None, znear: 0.1 };
        assert!(with(RigCamera { projection: wide, ..camera.clone() }).contains("between 0 and π"));
        let near = Projection::Perspective { yfov_rad: 0.5, aspect_ratio: Some(1.5), znear: 0.0 };
        assert!(with(RigCamera { projection: near, ..camera.clone() }).contains("near plane"));
        let flat = Projection::Perspective { yfov_rad: 0.5, aspect_ratio: Some(f64::NAN), znear: 0.1 };
        assert!(with(RigCamera { projection: flat, ..camera }).contains("aspect ratio"));
    }
}
