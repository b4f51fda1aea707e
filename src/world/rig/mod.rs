//! A rig: the nodes, skinned meshes, cameras and animation clips of a glTF
//! 2.0 file, posed at any time as a pure function of that time.
//!
//! A [`Rig`] is checked once when it is made ([`Rig::new`]): parents form a
//! forest, every index points at something, key times increase and every
//! number is finite. Posing and skinning then cannot fail. Reading a file
//! into a rig is `scene`'s (it knows where files are); here is only the math:
//! node transforms through the parent chain ([`pose`]), clips ([`clip`]), and
//! linear-blend skinning with morph targets ([`skin`]), and where a camera
//! on a node looks from ([`camera`]), by the glTF spec.

mod camera;
mod clip;
mod pose;
mod skin;

use std::sync::Arc;

use glam::{DMat4, DQuat, DVec3};

use crate::image::RgbaImage;

pub use camera::{CameraPose, Projection, RigCamera};
pub use clip::{Channel, Clip, Interpolation, Property};
pub use pose::Pose;
pub use skin::PosedMesh;

/// A node's own transform: translation · rotation · scale.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trs {
    pub translation: DVec3,
    pub rotation: DQuat,
    pub scale: DVec3,
}

impl Trs {
    pub const IDENTITY: Trs = Trs { translation: DVec3::ZERO, rotation: DQuat::IDENTITY, scale: DVec3::ONE };

    /// The matrix that takes the node's coordinates into its parent's.
    pub fn parent_from_local(&self) -> DMat4 {
        DMat4::from_scale_rotation_translation(self.scale, self.rotation, self.translation)
    }
}

/// A node of the file's hierarchy.
#[derive(Clone, Debug, PartialEq)]
pub struct RigNode {
    /// The file's name for it; may be empty.
    pub name: String,
    pub parent: Option<usize>,
    /// Its transform when no clip animates it.
    pub rest: Trs,
    /// Its mesh's morph-target weights when no clip animates them (the
    /// node's, else the mesh's, else zeros); empty without morph targets.
    pub morph_weights: Vec<f64>,
}

/// A skin: the joints that move a mesh's vertices.
#[derive(Clone, Debug, PartialEq)]
pub struct Skin {
    /// Node index of each joint.
    pub joints: Vec<usize>,
    /// Per joint, the matrix that takes a mesh point at bind time into the
    /// joint's coordinates (the identity where the file gives none).
    pub inverse_bind: Vec<DMat4>,
}

/// The joints moving each vertex of a skinned mesh, with their weights.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Influences {
    /// Vertex v's influences are `start[v]..start[v + 1]`.
    pub start: Vec<u32>,
    /// Index into the skin's joints.
    pub joint: Vec<u16>,
    pub weight: Vec<f64>,
}

/// One triangle primitive of a mesh as a node draws it.
#[derive(Clone, Debug, PartialEq)]
pub struct RigMesh {
    /// The mesh's name in the file; may be empty.
    pub name: String,
    /// The node that instances it.
    pub node: usize,
    /// Its skin, if skinned; then the node's own transform is ignored (glTF
    /// §3.7.3.3) and the joints place every vertex.
    pub skin: Option<usize>,
    /// Bind-time positions, in the mesh's coordinates.
    pub positions: Vec<DVec3>,
    /// Three per triangle, counter-clockwise seen from outside.
    pub indices: Vec<u32>,
    /// Empty unless skinned.
    pub influences: Influences,
    /// Per morph target, a displacement per vertex.
    pub morph_targets: Vec<Vec<DVec3>>,
    /// Base colour (linear RGBA) of its material.
    pub color: [f32; 4],
    /// Its material's base-colour texture (sRGB), if any, multiplied by `color`.
    pub texture: Option<Arc<RgbaImage>>,
    /// Texture coordinates per vertex (glTF's: (0, 0) the image's top
    /// left); empty without a texture.
    pub uvs: Vec<[f32; 2]>,
}

/// A checked rig, ready to pose. Equal rigs hold equal nodes, meshes,
/// skins, clips and cameras; its `Debug` says only how large it is.
#[derive(Clone, PartialEq)]
pub struct Rig {
    nodes: Vec<RigNode>,
    meshes: Vec<RigMesh>,
    skins: Vec<Skin>,
    clips: Vec<Clip>,
    /// Empty unless [`Rig::with_cameras`] gave some.
    cameras: Vec<RigCamera>,
    /// Every node, each after its parent.
    order: Vec<usize>,
}

/// Most nodes, skins' joints, cameras, morph targets per mesh, or influences per vertex a rig may have.
pub const MAX_RIG_ITEMS: usize = 1 << 16;

impl std::fmt::Debug for Rig {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "rig of {} nodes, {} vertices", self.nodes.len(), self.vertex_count())
    }
}

impl Rig {
    /// Checks the parts and makes a rig of them, or says, in a user's words,
    /// what is wrong.
    pub fn new(nodes: Vec<RigNode>, meshes: Vec<RigMesh>, skins: Vec<Skin>, clips: Vec<Clip>) -> Result<Rig, String> {
        if nodes.len() > MAX_RIG_ITEMS {
            return Err(format!("it has {} nodes; Drape reads at most {MAX_RIG_ITEMS}", nodes.len()));
        }
        let order = parents_first(&nodes)?;
        for (index, node) in nodes.iter().enumerate() {
            let trs = &node.rest;
            let numbers =
                trs.translation.to_array().into_iter().chain(trs.rotation.to_array()).chain(trs.scale.to_array());
            if !numbers.chain(node.morph_weights.iter().copied()).all(f64::is_finite) {
                return Err(format!("node {index} ({:?}) has a number that is not finite", node.name));
            }
        }
        for (index, skin) in skins.iter().enumerate() {
            if skin.joints.len() != skin.inverse_bind.len() || skin.joints.len() > MAX_RIG_ITEMS {
                return Err(format!(
                    "skin {index} has {} joints and {} inverse bind matrices",
                    skin.joints.len(),
                    skin.inverse_bind.len()
                ));
            }
            if let Some(bad) = skin.joints.iter().find(|&&j| j >= nodes.len()) {
                return Err(format!("skin {index} names node {bad}, and there are {}", nodes.len()));
            }
            if !skin.inverse_bind.iter().all(|m| m.is_finite()) {
                return Err(format!("skin {index} has an inverse bind matrix that is not finite"));
            }
        }
        for mesh in &meshes {
            check_mesh(mesh, &nodes, &skins)?;
        }
        for clip in &clips {
            for channel in &clip.channels {
                check_channel(clip, channel, &nodes)?;
            }
        }
        Ok(Rig { nodes, meshes, skins, clips, cameras: Vec::new(), order })
    }

    /// The rig with `cameras` on its nodes, or why one cannot be (a node it
    /// does not have, a field of view outside (0, π), a near plane not
    /// greater than 0).
    pub fn with_cameras(mut self, cameras: Vec<RigCamera>) -> Result<Rig, String> {
        if cameras.len() > MAX_RIG_ITEMS {
            return Err(format!("it has {} cameras; Drape reads at most {MAX_RIG_ITEMS}", cameras.len()));
        }
        for camera in &cameras {
            camera::check_camera(camera, self.nodes.len())?;
        }
        self.cameras = cameras;
        Ok(self)
    }

    pub fn nodes(&self) -> &[RigNode] {
        &self.nodes
    }

    pub fn meshes(&self) -> &[RigMesh] {
        &self.meshes
    }

    pub fn skins(&self) -> &[Skin] {
        &self.skins
    }

    pub fn clips(&self) -> &[Clip] {
        &self.clips
    }

    /// The cameras on the nodes of the file's default scene, in the order read.
    pub fn cameras(&self) -> &[RigCamera] {
        &self.cameras
    }

    /// The clip named `name`, or None.
    pub fn clip_named(&self, name: &str) -> Option<usize> {
        self.clips.iter().position(|c| c.name == name)
    }

    /// The node named `name` (the first, if several share it), or None.
    pub fn node_named(&self, name: &str) -> Option<usize> {
        self.nodes.iter().position(|n| n.name == name)
    }

    /// How many vertices all its meshes have together.
    pub fn vertex_count(&self) -> usize {
        self.meshes.iter().map(|m| m.positions.len()).sum()
    }
}

/// The node indices with every parent before its children, or why the
/// parents do not form a forest.
fn parents_first(nodes: &[RigNode]) -> Result<Vec<usize>, String> {
    let mut children = vec![Vec::new(); nodes.len()];
    let mut roots = Vec::new();
    for (index, node) in nodes.iter().enumerate() {
        match node.parent {
            None => roots.push(index),
            Some(parent) if parent < nodes.len() && parent != index => children[parent].push(index),
            Some(parent) => return Err(format!("node {index} names node {parent} as its parent, which cannot be")),
        }
    }
    let mut order = Vec::with_capacity(nodes.len());
    let mut stack: Vec<usize> = roots.into_iter().rev().collect();
    while let Some(index) = stack.pop() {
        order.push(index);
        stack.extend(children[index].iter().rev());
    }
    if order.len() != nodes.len() {
        return Err("its nodes' parents form a loop".to_owned());
    }
    Ok(order)
}

fn check_mesh(mesh: &RigMesh, nodes: &[RigNode], skins: &[Skin]) -> Result<(), String> {
    let what = format!("mesh {:?}", mesh.name);
    let count = mesh.positions.len();
    if mesh.node >= nodes.len() {
        return Err(format!("{what} hangs from node {}, and there are {}", mesh.node, nodes.len()));
    }
    if !mesh.positions.iter().all(|p| p.is_finite()) {
        return Err(format!("{what} has a vertex that is not finite"));
    }
    if !mesh.indices.len().is_multiple_of(3) {
        return Err(format!("{what} has {} triangle indices, not a multiple of 3", mesh.indices.len()));
    }
    if let Some(bad) = mesh.indices.iter().find(|&&i| i as usize >= count) {
        return Err(format!("{what} names vertex {bad} of {count}"));
    }
    if let Some(skin) = mesh.skin {
        let Some(skin) = skins.get(skin) else {
            return Err(format!("{what} names skin {skin}, and there are {}", skins.len()));
        };
        let influences = &mesh.influences;
        let total = influences.joint.len();
        let start_ok = influences.start.len() == count + 1
            && influences.start.first() == Some(&0)
            && influences.start.windows(2).all(|w| w[0] <= w[1])
            && influences.start.last().is_some_and(|&end| end as usize == total)
            && influences.weight.len() == total;
        if !start_ok {
            return Err(format!("{what} does not give every vertex its joints and weights"));
        }
        if let Some(bad) = influences.joint.iter().find(|&&j| j as usize >= skin.joints.len()) {
            return Err(format!("{what} names joint {bad} of a skin with {}", skin.joints.len()));
        }
        if !influences.weight.iter().all(|w| w.is_finite()) {
            return Err(format!("{what} has a joint weight that is not finite"));
        }
    }
    if !mesh.uvs.is_empty() && mesh.uvs.len() != count {
        return Err(format!("{what} has {} texture coordinates for {count} vertices", mesh.uvs.len()));
    }
    if let Some(texture) = &mesh.texture
        && texture.pixels.len() as u64 != u64::from(texture.width) * u64::from(texture.height) * 4
    {
        return Err(format!("{what}: its texture's pixels do not fill {} × {}", texture.width, texture.height));
    }
    if mesh.morph_targets.len() > MAX_RIG_ITEMS {
        return Err(format!("{what} has {} morph targets", mesh.morph_targets.len()));
    }
    for (index, target) in mesh.morph_targets.iter().enumerate() {
        if target.len() != count || !target.iter().all(|d| d.is_finite()) {
            return Err(format!("{what}: morph target {index} does not move every vertex by a finite amount"));
        }
    }
    let weights = nodes[mesh.node].morph_weights.len();
    if weights != mesh.morph_targets.len() {
        return Err(format!("{what} has {} morph targets and its node {weights} weights", mesh.morph_targets.len()));
    }
    Ok(())
}

fn check_channel(clip: &Clip, channel: &Channel, nodes: &[RigNode]) -> Result<(), String> {
    let what = format!("animation {:?}", clip.name);
    let Some(node) = nodes.get(channel.node) else {
        return Err(format!("{what} animates node {}, and there are {}", channel.node, nodes.len()));
    };
    let width = match channel.property {
        Property::Translation | Property::Scale => 3,
        Property::Rotation => 4,
        Property::MorphWeights => node.morph_weights.len(),
    };
    let groups = if channel.interpolation == Interpolation::CubicSpline { 3 } else { 1 };
    let keys = channel.times_secs.len();
    if keys == 0 {
        return Err(format!("{what} has a channel without keys"));
    }
    if channel.width != width || channel.values.len() != keys * groups * width {
        return Err(format!(
            "{what}: a channel of node {} has {} numbers for {keys} keys of {width}",
            channel.node,
            channel.values.len()
        ));
    }
    if !channel.times_secs.iter().all(|t| t.is_finite()) || !channel.times_secs.windows(2).all(|w| w[0] < w[1]) {
        return Err(format!("{what}: key times must be finite and increasing"));
    }
    if !channel.values.iter().all(|v| v.is_finite()) {
        return Err(format!("{what} has a key value that is not finite"));
    }
    if channel.property == Property::Rotation {
        // Values only (a cubic spline's tangents may be zero): each must be a rotation.
        let values = channel.values.chunks_exact(4).skip(groups / 2).step_by(groups);
        if values.clone().any(|q| q.iter().map(|c| c * c).sum::<f64>() < 1e-12) {
            return Err(format!("{what}: a rotation key of node {} is not a rotation (zero length)", channel.node));
        }
    }
    Ok(())
}
