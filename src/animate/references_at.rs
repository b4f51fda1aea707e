//! A scene's references at a frame: each file's animation played on the
//! scene's clock, its meshes skinned and its cameras placed in the scene.

use std::sync::Arc;

use glam::{DMat4, DVec3};

use super::track::{sample, sample_vec3};
use crate::scene::{Reference, ReferenceCamera, Scene};
use crate::world::rig::{CameraPose, Pose, PosedMesh, Projection, Rig};
use crate::world::{ColliderShape, MeshSolid};

/// One reference at one frame.
pub struct PosedReference<'a> {
    pub rig: &'a Arc<Rig>,
    /// Takes the file's coordinates into the scene's.
    pub scene_from_file: DMat4,
    pub pose: Pose,
    /// The clips playing (indices into the rig's clips) and the time on their clock.
    pub clips: Vec<usize>,
    pub t_secs: f64,
}

/// Reference `index` of `scene` at `frame`; None when there is no such
/// reference or its file has not been read (a scene parsed from text).
pub fn reference_at(scene: &Scene, index: usize, frame: f64) -> Option<PosedReference<'_>> {
    let reference = scene.references.get(index)?;
    let rig = reference.rig.0.as_ref()?;
    let clips = reference.playing_clips();
    let span = reference.clip_span_secs().unwrap_or((0.0, 0.0));
    let t_secs = reference.clip_time_secs(frame, scene.timeline.fps, span);
    let scene_from_file = scene_from_file(reference, frame);
    Some(PosedReference { rig, scene_from_file, pose: rig.pose_clips(&clips, t_secs), clips, t_secs })
}

/// `center · rotation · scale` of `reference` at `frame`; a scale an
/// easing takes to 0 or below reads as a micrometre, as a mesh collider's.
pub fn scene_from_file(reference: &Reference, frame: f64) -> DMat4 {
    let turn = sample_vec3(&reference.rotation_deg, frame);
    let rotation = ColliderShape::rotation_from_deg(turn.x, turn.y, turn.z);
    let scale = sample(&reference.scale, frame).max(1e-6);
    DMat4::from_translation(sample_vec3(&reference.center, frame))
        * DMat4::from_mat3(rotation)
        * DMat4::from_scale(DVec3::splat(scale))
}

impl PosedReference<'_> {
    /// Every mesh of the file at this pose, in scene coordinates, in the
    /// rig's mesh order.
    pub fn meshes(&self) -> Vec<PosedMesh> {
        let mut meshes = self.rig.posed_meshes(&self.pose);
        for mesh in &mut meshes {
            mesh.positions.iter_mut().for_each(|p| *p = self.scene_from_file.transform_point3(*p));
            // A placement is a rotation and a uniform scale: normals turn with it.
            mesh.normals
                .iter_mut()
                .for_each(|n| *n = self.scene_from_file.transform_vector3(*n).normalize_or(DVec3::Y));
        }
        meshes
    }

    /// Node `node`'s transform into the scene at this pose (None for no such node).
    pub fn scene_from_node(&self, node: usize) -> Option<DMat4> {
        Some(self.scene_from_file * *self.pose.world_from_node.get(node)?)
    }

    /// The file's camera named `name` at this pose, in the scene (None for
    /// no such camera).
    pub fn camera(&self, name: &str) -> Option<PosedCamera> {
        let camera = self.rig.camera_named(name)?;
        Some(PosedCamera {
            pose: CameraPose::of_node(self.scene_from_node(camera.node)?),
            projection: camera.projection,
        })
    }
}

/// A reference's glTF camera at one frame, in the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PosedCamera {
    /// Where it stands and which way it looks, the reference's placement
    /// included (a placement's scale moves it, never its lens).
    pub pose: CameraPose,
    pub projection: Projection,
}

/// The camera `from` names at `frame`, its node posed with its reference's
/// clock and placement; None where the scene has no reference of that name,
/// its file has not been read (a scene parsed from text) or it has no
/// camera of that name.
pub fn reference_camera_at(scene: &Scene, from: &ReferenceCamera, frame: f64) -> Option<PosedCamera> {
    let index = scene.references.iter().position(|r| r.name == from.reference)?;
    reference_at(scene, index, frame)?.camera(&from.camera)
}

impl PosedReference<'_> {
    /// All its meshes at this pose as one solid in scene coordinates,
    /// moved from the rig's solid at rest ([`rest_solid`]) as
    /// [`PosedSolids::solid`] does with the rest solid it keeps; None when
    /// they hold no triangle with area.
    pub fn build_solid(&self) -> Option<MeshSolid> {
        self.solid_from(&rest_solid(self.rig)?)
    }

    /// All its meshes at this pose as one solid, `rest` (the rig's
    /// [`rest_solid`]) moved to this pose.
    pub fn solid_from(&self, rest: &MeshSolid) -> Option<MeshSolid> {
        let mut vertices = Vec::with_capacity(self.rig.vertex_count());
        let mut mesh_vertices = Vec::new();
        for mesh in 0..self.rig.meshes().len() {
            self.rig.posed_positions(mesh, &self.pose, &mut mesh_vertices);
            vertices.extend(mesh_vertices.iter().map(|p| self.scene_from_file.transform_point3(*p)));
        }
        rest.moved_to(&vertices).ok()
    }
}

/// All meshes of `rig` at its rest pose as one solid, each mesh welded
/// within itself only: what every pose's solid is moved from, so that one
/// pose's solid never depends on another's. None when they hold no
/// triangle with area.
pub fn rest_solid(rig: &Rig) -> Option<MeshSolid> {
    let pose = rig.rest_pose();
    let (mut vertices, mut triangles, mut parts) = (Vec::new(), Vec::new(), Vec::new());
    let mut mesh_vertices = Vec::new();
    for (index, mesh) in rig.meshes().iter().enumerate() {
        let base = vertices.len() as u32;
        rig.posed_positions(index, &pose, &mut mesh_vertices);
        vertices.extend_from_slice(&mesh_vertices);
        parts.extend(std::iter::repeat_n(index as u32, mesh_vertices.len()));
        triangles.extend(mesh.indices.chunks_exact(3).map(|t| [t[0] + base, t[1] + base, t[2] + base]));
    }
    MeshSolid::with_parts(&vertices, &triangles, &parts).ok()
}
