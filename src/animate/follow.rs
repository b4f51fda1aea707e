//! The cloth following a node of a reference (`follow` in the scene): a
//! carpet on a flight path, a cape on a chest bone.
//!
//! Each key is authored where the node is at the key's frame. At any frame
//! the two keys' rest shapes are taken into the node's coordinates (each by
//! the node's transform at its own key's frame), blended there, and carried
//! out by the node's transform at this frame. On a key's frame the cloth is
//! exactly that key's rest shape; between keys it moves as the node does.

use glam::{DMat4, DVec3};

use super::cache::KeyShape;
use super::references_at::reference_at;
use crate::mesh::PointArrays;
use crate::scene::Scene;

/// The followed node's transform into the scene at `frame`; None when the
/// scene follows nothing, or its reference or node is missing or not read.
pub fn followed_node_at(scene: &Scene, frame: f64) -> Option<DMat4> {
    let follow = scene.follow.as_ref()?;
    let index = scene.references.iter().position(|r| r.name == follow.reference)?;
    let posed = reference_at(scene, index, frame)?;
    posed.scene_from_node(posed.rig.node_named(&follow.node)?)
}

/// Writes into `points` the blend of keys `a` and `b` (`eased` of the way)
/// carried by the followed node from each key's frame to `frame`. Returns
/// false, touching nothing, when the scene follows no node it can place.
pub fn carry_with_node(
    scene: &Scene,
    shapes: &[std::sync::Arc<KeyShape>],
    (a, b, eased): (usize, usize, f64),
    frame: f64,
    points: &mut PointArrays,
) -> bool {
    let Some(now) = followed_node_at(scene, frame) else { return false };
    let at_key = |k: usize| followed_node_at(scene, f64::from(scene.keys[k].frame));
    let (Some(node_a), Some(node_b)) = (at_key(a), at_key(b)) else { return false };
    // Each key's shape in node coordinates, carried to now: now · node⁻¹ · p.
    let (carry_a, carry_b) = (now * node_a.inverse(), now * node_b.inverse());
    let (pa, pb) = (&shapes[a].points, &shapes[b].points);
    for k in 0..points.len() {
        let point = |p: &PointArrays| DVec3::new(p.x[k].into(), p.y[k].into(), p.z[k].into());
        let from = carry_a.transform_point3(point(pa));
        let p = if a == b { from } else { from + (carry_b.transform_point3(point(pb)) - from) * eased };
        (points.x[k], points.y[k], points.z[k]) = (p.x as f32, p.y as f32, p.z as f32);
    }
    true
}
