//! A rig's nodes at a moment: every node's transform through its parents,
//! and the morph weights, with one clip playing (or none: the rest pose).

use glam::DMat4;

use super::{Property, Rig, Trs};

/// Where every node of a rig is at one moment.
#[derive(Clone, Debug, PartialEq)]
pub struct Pose {
    /// Per node, the matrix from its coordinates to the file's world.
    pub world_from_node: Vec<DMat4>,
    /// Per node, the weights of its mesh's morph targets.
    pub morph_weights: Vec<Vec<f64>>,
}

impl Rig {
    /// Every node as the file places it, no clip playing.
    pub fn rest_pose(&self) -> Pose {
        self.pose(None, 0.0)
    }

    /// Every node with clip `clip` (an index into [`Rig::clips`]) at
    /// `t_secs` of its clock; the rest pose for None or an index out of
    /// range. Properties the clip does not key keep their rest values.
    pub fn pose(&self, clip: Option<usize>, t_secs: f64) -> Pose {
        self.pose_clips(clip.as_slice(), t_secs)
    }

    /// Every node with the clips `clips` playing together at `t_secs` of one
    /// clock (a file's skeleton action and shape-key action, as Blender
    /// exports them); where two key the same property, the later in
    /// `clips` wins. Indices out of range are left out.
    pub fn pose_clips(&self, clips: &[usize], t_secs: f64) -> Pose {
        let mut local: Vec<Trs> = self.nodes.iter().map(|n| n.rest).collect();
        let mut morph_weights: Vec<Vec<f64>> = self.nodes.iter().map(|n| n.morph_weights.clone()).collect();
        for clip in clips.iter().filter_map(|&c| self.clips.get(c)) {
            for channel in &clip.channels {
                let node = channel.node;
                match channel.property {
                    Property::Translation => local[node].translation = channel.sample_vec3(t_secs),
                    Property::Rotation => local[node].rotation = channel.sample_quat(t_secs),
                    Property::Scale => local[node].scale = channel.sample_vec3(t_secs),
                    Property::MorphWeights => channel.sample_into(t_secs, &mut morph_weights[node]),
                }
            }
        }
        let mut world_from_node = vec![DMat4::IDENTITY; self.nodes.len()];
        for &index in &self.order {
            let parent_from_local = local[index].parent_from_local();
            world_from_node[index] = match self.nodes[index].parent {
                Some(parent) => world_from_node[parent] * parent_from_local,
                None => parent_from_local,
            };
        }
        Pose { world_from_node, morph_weights }
    }
}

#[cfg(test)]
mod tests {
    use glam::{DQuat, DVec3};

    use super::super::{Channel, Clip, Interpolation, RigNode};
    use super::*;

    fn node(name: &str, parent: Option<usize>, translation: DVec3) -> RigNode {
        RigNode { name: name.into(), parent, rest: Trs { translation, ..Trs::IDENTITY }, morph_weights: vec![] }
    }

    /// shoulder (at (0, 1.5, 0)) → elbow (0.3 along x) → hand (0.25 along x);
    /// the clip turns the shoulder 0° → 90° about Z over 1 s (CUBICSPLINE,
    /// zero tangents) and bends the elbow 0° → 90° about Y (LINEAR).
    fn arm() -> Rig {
        let nodes = vec![
            node("shoulder", None, DVec3::new(0.0, 1.5, 0.0)),
            node("elbow", Some(0), DVec3::new(0.3, 0.0, 0.0)),
            node("hand", Some(1), DVec3::new(0.25, 0.0, 0.0)),
        ];
        let z90 = DQuat::from_rotation_z(90f64.to_radians()).to_array();
        let y90 = DQuat::from_rotation_y(90f64.to_radians()).to_array();
        let zero = [0.0; 4];
        let identity = DQuat::IDENTITY.to_array();
        let cubic: Vec<f64> = [zero, identity, zero, zero, z90, zero].concat();
        let shoulder = Channel {
            node: 0,
            property: Property::Rotation,
            interpolation: Interpolation::CubicSpline,
            times_secs: vec![0.0, 1.0],
            values: cubic,
            width: 4,
        };
        let elbow = Channel {
            node: 1,
            property: Property::Rotation,
            interpolation: Interpolation::Linear,
            times_secs: vec![0.0, 1.0],
            values: [identity, y90].concat(),
            width: 4,
        };
        let clip = Clip { name: "raise".into(), channels: vec![shoulder, elbow] };
        Rig::new(nodes, vec![], vec![], vec![clip]).unwrap()
    }

    fn origin(pose: &Pose, node: usize) -> DVec3 {
        pose.world_from_node[node].transform_point3(DVec3::ZERO)
    }

    #[test]
    fn a_parent_chain_carries_its_children() {
        let rig = arm();
        let rest = rig.rest_pose();
        assert!(origin(&rest, 2).abs_diff_eq(DVec3::new(0.55, 1.5, 0.0), 1e-12));
        // At 1 s the shoulder has turned the arm up (x → y) and the elbow
        // bent the forearm about its own Y: x → −z in the elbow's frame,
        // which the shoulder's turn leaves as −z.
        let end = rig.pose(Some(0), 1.0);
        assert!(origin(&end, 1).abs_diff_eq(DVec3::new(0.0, 1.8, 0.0), 1e-12), "{}", origin(&end, 1));
        assert!(origin(&end, 2).abs_diff_eq(DVec3::new(0.0, 1.8, -0.25), 1e-12), "{}", origin(&end, 2));
        // Halfway: zero tangents make the cubic blend symmetric (45°), the
        // linear elbow is at 45° too.
        let half = rig.pose(Some(0), 0.5);
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let elbow = DVec3::new(0.3 * s, 1.5 + 0.3 * s, 0.0);
        assert!(origin(&half, 1).abs_diff_eq(elbow, 1e-12), "{}", origin(&half, 1));
        // The forearm: (0.25, 0, 0) turned 45° about Y is (0.25 s, 0, −0.25 s),
        // then 45° about Z: x part splits into x and y.
        let hand = elbow + DVec3::new(0.25 * s * s, 0.25 * s * s, -0.25 * s);
        assert!(origin(&half, 2).abs_diff_eq(hand, 1e-12), "{}", origin(&half, 2));
    }

    #[test]
    fn no_clip_or_a_wrong_clip_is_the_rest_pose() {
        let rig = arm();
        assert_eq!(rig.pose(None, 0.7), rig.rest_pose());
        assert_eq!(rig.pose(Some(5), 0.7), rig.rest_pose());
        assert_eq!(rig.pose(Some(0), -3.0), rig.rest_pose(), "before the first key: the first values");
    }

    #[test]
    fn parents_that_loop_or_point_nowhere_are_refused() {
        let looped = vec![node("a", Some(1), DVec3::ZERO), node("b", Some(0), DVec3::ZERO)];
        assert!(Rig::new(looped, vec![], vec![], vec![]).unwrap_err().contains("loop"));
        let nowhere = vec![node("a", Some(7), DVec3::ZERO)];
        assert!(Rig::new(nowhere, vec![], vec![], vec![]).unwrap_err().contains("cannot be"));
        let itself = vec![node("a", Some(0), DVec3::ZERO)];
        assert!(Rig::new(itself, vec![], vec![], vec![]).is_err());
    }

    #[test]
    fn channels_that_do_not_fit_their_node_are_refused() {
        let mut rig_parts = arm();
        let mut clip = rig_parts.clips[0].clone();
        clip.channels[1].times_secs = vec![1.0, 0.0];
        let err = Rig::new(rig_parts.nodes.clone(), vec![], vec![], vec![clip]).unwrap_err();
        assert!(err.contains("increasing"), "{err}");
        rig_parts.clips[0].channels[1].values.pop();
        let err = Rig::new(rig_parts.nodes, vec![], vec![], rig_parts.clips).unwrap_err();
        assert!(err.contains("numbers for 2 keys"), "{err}");
    }
}
