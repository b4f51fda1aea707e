//! A scene's visible references at a frame as solids for the renderer: one
//! set per mesh, in its material's base colour and texture.

use crate::animate::references_at::reference_at;
use crate::render::{SolidTexture, Solids};
use crate::scene::Scene;

/// Every mesh of every visible, read reference of `scene` at `frame`, at
/// `opacity` (1: opaque, casting shadows).
pub fn reference_solids(scene: &Scene, frame: f64, opacity: f32) -> Vec<Solids> {
    let mut sets = Vec::new();
    for (index, reference) in scene.references.iter().enumerate() {
        if !reference.visible {
            continue;
        }
        let Some(posed) = reference_at(scene, index, frame) else { continue };
        for (mesh, placed) in posed.rig.meshes().iter().zip(posed.meshes()) {
            let [r, g, b, a] = mesh.color;
            sets.push(Solids {
                positions: placed.positions.iter().map(|p| p.as_vec3()).collect(),
                normals: placed.normals.iter().map(|n| n.as_vec3()).collect(),
                indices: mesh.indices.clone(),
                color: [r, g, b],
                opacity: opacity * a,
                texture: mesh.texture.clone().map(SolidTexture),
                uvs: mesh.uvs.clone(),
            });
        }
    }
    sets
}
