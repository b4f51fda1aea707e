//! A scene's colliders at a frame as solids for the renderer.

use crate::animate::colliders_at::shape_at;
use crate::render::Solids;
use crate::scene::Scene;
use crate::world::TriangleMesh;

/// The enabled colliders of `scene` at `frame` as one set of solids, in
/// the prop colour, opaque or at `opacity`. The ground has no edge to draw
/// and is left to the renderer's ground.
pub fn collider_solids(scene: &Scene, frame: f64, opacity: f32) -> Solids {
    let mut mesh = TriangleMesh::default();
    // The scene's colliders only: references that collide are drawn as themselves.
    for shape in scene.colliders.iter().filter(|c| c.enabled()).filter_map(|c| shape_at(c, frame)) {
        mesh.append(&shape.triangles());
    }
    Solids {
        positions: mesh.positions.iter().map(|p| p.as_vec3()).collect(),
        normals: mesh.normals.iter().map(|n| n.as_vec3()).collect(),
        indices: mesh.indices,
        color: Solids::PROP_COLOR,
        opacity,
        ..Solids::NONE
    }
}
