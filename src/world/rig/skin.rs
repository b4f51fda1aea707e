//! A rig's meshes at a pose: morph targets added to the bind positions,
//! then linear-blend skinning (glTF §3.7.3): a skinned vertex is
//! Σ weightᵢ · world_from_jointᵢ · inverse_bindᵢ · position; an unskinned
//! mesh goes where its node is.

use glam::{DMat4, DVec3};

use super::{Pose, Rig};

/// One mesh of a rig placed at a pose, in the file's world coordinates.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PosedMesh {
    pub positions: Vec<DVec3>,
    /// Unit, area-weighted over the triangles round each vertex; +Y where
    /// a vertex touches no triangle with area.
    pub normals: Vec<DVec3>,
}

impl Rig {
    /// The vertices of mesh `mesh` (an index into [`Rig::meshes`]) at
    /// `pose`, written over `out`. Nothing for an index out of range.
    pub fn posed_positions(&self, mesh: usize, pose: &Pose, out: &mut Vec<DVec3>) {
        out.clear();
        let Some(mesh) = self.meshes.get(mesh) else { return };
        out.extend_from_slice(&mesh.positions);
        let weights = &pose.morph_weights[mesh.node];
        for (target, &weight) in mesh.morph_targets.iter().zip(weights) {
            if weight != 0.0 {
                out.iter_mut().zip(target).for_each(|(p, d)| *p += weight * *d);
            }
        }
        let Some(skin) = mesh.skin.map(|s| &self.skins[s]) else {
            let world_from_mesh = pose.world_from_node[mesh.node];
            out.iter_mut().for_each(|p| *p = world_from_mesh.transform_point3(*p));
            return;
        };
        let joint_matrices: Vec<DMat4> = skin
            .joints
            .iter()
            .zip(&skin.inverse_bind)
            .map(|(&joint, bind)| pose.world_from_node[joint] * *bind)
            .collect();
        let influences = &mesh.influences;
        for (v, p) in out.iter_mut().enumerate() {
            let range = influences.start[v] as usize..influences.start[v + 1] as usize;
            let mut skinned = DVec3::ZERO;
            for (&joint, &weight) in influences.joint[range.clone()].iter().zip(&influences.weight[range]) {
                skinned += weight * joint_matrices[joint as usize].transform_point3(*p);
            }
            *p = skinned;
        }
    }

    /// Vertex `vertex` of mesh `mesh` at `pose`, in the file's world: the
    /// same number [`Rig::posed_positions`] gives it. The origin for an
    /// index out of range.
    pub fn posed_vertex(&self, mesh: usize, vertex: usize, pose: &Pose) -> DVec3 {
        let Some(mesh) = self.meshes.get(mesh) else { return DVec3::ZERO };
        let Some(&bind) = mesh.positions.get(vertex) else { return DVec3::ZERO };
        let mut p = bind;
        for (target, &weight) in mesh.morph_targets.iter().zip(&pose.morph_weights[mesh.node]) {
            if weight != 0.0 {
                p += weight * target[vertex];
            }
        }
        let Some(skin) = mesh.skin.map(|s| &self.skins[s]) else {
            return pose.world_from_node[mesh.node].transform_point3(p);
        };
        let influences = &mesh.influences;
        let range = influences.start[vertex] as usize..influences.start[vertex + 1] as usize;
        let mut skinned = DVec3::ZERO;
        for (&joint, &weight) in influences.joint[range.clone()].iter().zip(&influences.weight[range]) {
            let joint = joint as usize;
            skinned +=
                weight * (pose.world_from_node[skin.joints[joint]] * skin.inverse_bind[joint]).transform_point3(p);
        }
        skinned
    }

    /// Every mesh of the rig at `pose`, in [`Rig::meshes`] order.
    pub fn posed_meshes(&self, pose: &Pose) -> Vec<PosedMesh> {
        (0..self.meshes.len())
            .map(|index| {
                let mut positions = Vec::new();
                self.posed_positions(index, pose, &mut positions);
                let normals = smooth_normals(&positions, &self.meshes[index].indices);
                PosedMesh { positions, normals }
            })
            .collect()
    }
}

/// Area-weighted vertex normals of the triangles `indices` over `positions`.
pub fn smooth_normals(positions: &[DVec3], indices: &[u32]) -> Vec<DVec3> {
    let mut normals = vec![DVec3::ZERO; positions.len()];
    for t in indices.chunks_exact(3) {
        let [a, b, c] = [t[0], t[1], t[2]].map(|i| i as usize);
        let n = (positions[b] - positions[a]).cross(positions[c] - positions[a]);
        normals[a] += n;
        normals[b] += n;
        normals[c] += n;
    }
    normals.iter_mut().for_each(|n| *n = n.try_normalize().unwrap_or(DVec3::Y));
    normals
}

#[cfg(test)]
mod tests {
    use glam::DQuat;

    use super::super::{Channel, Clip, Influences, Interpolation, Property, RigMesh, RigNode, Skin, Trs};
    use super::*;

    /// Two joints along +Y: `lower` at the origin, `upper` 1 m above it;
    /// a vertex at y = 0.5 weighted half each, one at y = 1.5 on `upper`
    /// only, one at y = 0 on `lower` only. The clip turns `upper` 90° about Z
    /// over 1 s and moves `lower` by +1 along x.
    fn bent() -> Rig {
        let joint = |name: &str, parent, y| RigNode {
            name: String::from(name),
            parent,
            rest: Trs { translation: DVec3::new(0.0, y, 0.0), ..Trs::IDENTITY },
            morph_weights: vec![],
        };
        let mesh_node = RigNode { name: "body".into(), parent: None, rest: Trs::IDENTITY, morph_weights: vec![0.0] };
        let nodes = vec![joint("lower", None, 0.0), joint("upper", Some(0), 1.0), mesh_node];
        // Bind: lower's world is the identity, upper's a lift by 1.
        let skin = Skin { joints: vec![0, 1], inverse_bind: vec![DMat4::IDENTITY, DMat4::from_translation(-DVec3::Y)] };
        let mesh = RigMesh {
            name: "strip".into(),
            node: 2,
            skin: Some(0),
            positions: vec![DVec3::new(0.0, 0.5, 0.0), DVec3::new(0.0, 1.5, 0.0), DVec3::ZERO],
            indices: vec![0, 1, 2],
            influences: Influences {
                start: vec![0, 2, 3, 4],
                joint: vec![0, 1, 1, 0],
                weight: vec![0.5, 0.5, 1.0, 1.0],
            },
            // One morph target: the first vertex 0.2 along +z.
            morph_targets: vec![vec![DVec3::new(0.0, 0.0, 0.2), DVec3::ZERO, DVec3::ZERO]],
            color: [1.0; 4],
            texture: None,
            uvs: Vec::new(),
        };
        let z90 = DQuat::from_rotation_z(90f64.to_radians()).to_array();
        let channels = vec![
            Channel {
                node: 1,
                property: Property::Rotation,
                interpolation: Interpolation::Linear,
                times_secs: vec![0.0, 1.0],
                values: [DQuat::IDENTITY.to_array(), z90].concat(),
                width: 4,
            },
            Channel {
                node: 0,
                property: Property::Translation,
                interpolation: Interpolation::Linear,
                times_secs: vec![0.0, 1.0],
                values: vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0],
                width: 3,
            },
            Channel {
                node: 2,
                property: Property::MorphWeights,
                interpolation: Interpolation::Step,
                times_secs: vec![0.0, 1.0],
                values: vec![0.0, 1.0],
                width: 1,
            },
        ];
        Rig::new(nodes, vec![mesh], vec![skin], vec![Clip { name: "bend".into(), channels }]).unwrap()
    }

    #[test]
    fn the_bind_pose_leaves_the_mesh_where_it_was_modelled() {
        let rig = bent();
        let mut out = Vec::new();
        rig.posed_positions(0, &rig.rest_pose(), &mut out);
        assert_eq!(out, rig.meshes()[0].positions);
    }

    #[test]
    fn skinning_blends_the_joints_by_weight() {
        let rig = bent();
        let mut out = Vec::new();
        rig.posed_positions(0, &rig.pose(Some(0), 1.0), &mut out);
        // lower: moved to x = 1. upper: at (1, 1, 0), turned 90° about Z, so
        // a point 0.5 above it goes to 0.5 along −x.
        // Vertex 2 (lower only): (1, 0, 0).
        assert!(out[2].abs_diff_eq(DVec3::new(1.0, 0.0, 0.0), 1e-12), "{}", out[2]);
        // Vertex 1 (upper only, 0.5 above it): (1 − 0.5, 1, 0).
        assert!(out[1].abs_diff_eq(DVec3::new(0.5, 1.0, 0.0), 1e-12), "{}", out[1]);
        // Vertex 0, morphed to (0, 0.5, 0.2) at weight 1 (STEP at 1 s):
        // by lower (1, 0.5, 0.2); by upper it is 0.5 below the joint, turned:
        // (1 + 0.5, 1, 0.2); half each: (1.25, 0.75, 0.2).
        assert!(out[0].abs_diff_eq(DVec3::new(1.25, 0.75, 0.2), 1e-12), "{}", out[0]);
        // Just before 1 s the STEP weight is still 0.
        rig.posed_positions(0, &rig.pose(Some(0), 0.999), &mut out);
        assert!(out[0].z.abs() < 1e-12);
    }

    #[test]
    fn one_vertex_posed_alone_is_the_vertex_posed_with_the_rest() {
        let rig = bent();
        let pose = rig.pose(Some(0), 1.0);
        let mut all = Vec::new();
        rig.posed_positions(0, &pose, &mut all);
        for (v, p) in all.iter().enumerate() {
            assert_eq!(rig.posed_vertex(0, v, &pose), *p);
        }
        assert_eq!(rig.posed_vertex(0, 99, &pose), DVec3::ZERO);
    }

    #[test]
    fn an_unskinned_mesh_follows_its_node() {
        let node = RigNode {
            name: "prop".into(),
            parent: None,
            rest: Trs { translation: DVec3::new(0.0, 2.0, 0.0), rotation: DQuat::IDENTITY, scale: DVec3::splat(2.0) },
            morph_weights: vec![],
        };
        let mesh = RigMesh {
            name: "tri".into(),
            node: 0,
            skin: None,
            positions: vec![DVec3::ZERO, DVec3::X, DVec3::Z],
            indices: vec![0, 2, 1],
            influences: Influences::default(),
            morph_targets: vec![],
            color: [1.0; 4],
            texture: None,
            uvs: Vec::new(),
        };
        let rig = Rig::new(vec![node], vec![mesh], vec![], vec![]).unwrap();
        let posed = rig.posed_meshes(&rig.rest_pose());
        assert_eq!(
            posed[0].positions,
            vec![DVec3::new(0.0, 2.0, 0.0), DVec3::new(2.0, 2.0, 0.0), DVec3::new(0.0, 2.0, 2.0)]
        );
        // Counter-clockwise seen from above: the normal is +Y.
        assert!(posed[0].normals.iter().all(|n| n.abs_diff_eq(DVec3::Y, 1e-12)));
    }

    #[test]
    fn influences_that_point_nowhere_are_refused() {
        let rig = bent();
        let mut mesh = rig.meshes()[0].clone();
        mesh.influences.joint[0] = 9;
        let err = Rig::new(rig.nodes().to_vec(), vec![mesh.clone()], rig.skins().to_vec(), vec![]).unwrap_err();
        assert!(err.contains("joint 9"), "{err}");
        mesh.influences.joint[0] = 0;
        mesh.influences.start.pop();
        let err = Rig::new(rig.nodes().to_vec(), vec![mesh], rig.skins().to_vec(), vec![]).unwrap_err();
        assert!(err.contains("every vertex"), "{err}");
    }
}
