//! Attached pins: pins bound to a node or a surface point of a reference
//! (a character's shoulder), exactly where their attachment is at every frame.
//!
//! A key's rest shape is relaxed with its attached pins where their
//! attachments are at the key's frame ([`posed_key`]). Between and beyond
//! keys the attachments move on while the blend of the keys does not know;
//! [`carry_to_attachments`] then moves the cloth so every attached pin sits
//! on its attachment, the move spread over the cloth by material distance
//! (inverse-square weights of each pin's correction, loose pins asking for
//! none), so the cloth follows smoothly and nothing pops. Scenes without
//! attached pins are left exactly as they were.

use std::borrow::Cow;

use glam::DVec3;

use super::references_at::{PosedReference, reference_at};
use crate::mesh::PointArrays;
use crate::scene::{Attachment, Key, Scene};

/// Where `attachment` is in the scene at `frame`; None when its reference
/// is missing or not read (a scene parsed without its folder), or names
/// what its file lacks (validation against the file reports that).
pub fn attachment_at(scene: &Scene, attachment: &Attachment, frame: f64) -> Option<DVec3> {
    let index = scene.references.iter().position(|r| r.name == attachment.reference())?;
    attachment_on(&reference_at(scene, index, frame)?, attachment)
}

/// Every reference of `scene` posed at `frame` (None where its file is not
/// read): several attachments at one moment pose each reference once.
fn posed_references(scene: &Scene, frame: f64) -> Vec<Option<PosedReference<'_>>> {
    (0..scene.references.len()).map(|index| reference_at(scene, index, frame)).collect()
}

/// Where `attachment` is among references already posed ([`posed_references`]).
fn attachment_among(scene: &Scene, posed: &[Option<PosedReference>], attachment: &Attachment) -> Option<DVec3> {
    let index = scene.references.iter().position(|r| r.name == attachment.reference())?;
    attachment_on(posed.get(index)?.as_ref()?, attachment)
}

/// Where `attachment` is on a reference already posed.
pub fn attachment_on(posed: &PosedReference, attachment: &Attachment) -> Option<DVec3> {
    match attachment {
        Attachment::Node(node) => {
            let index = posed.rig.node_named(&node.node)?;
            Some(posed.scene_from_node(index)?.transform_point3(DVec3::from(node.offset)))
        }
        Attachment::Surface(surface) => {
            let mesh = posed.rig.meshes().get(surface.mesh)?;
            let corners = mesh.indices.get(surface.triangle * 3..surface.triangle * 3 + 3)?;
            let [a, b, c] = [corners[0], corners[1], corners[2]].map(|v| {
                posed.scene_from_file.transform_point3(posed.rig.posed_vertex(surface.mesh, v as usize, &posed.pose))
            });
            let (u, v, w) = surface.barycentric;
            let normal = (b - a).cross(c - a).normalize_or_zero();
            Some(a * u + b * v + c * w + normal * surface.lift_m)
        }
    }
}

/// `key` with each attached pin's position where its attachment is at the
/// key's frame; `key` itself when none is attached (or none can be placed).
pub fn posed_key<'a>(scene: &Scene, key: &'a Key) -> Cow<'a, Key> {
    if key.pins.iter().all(|p| p.attach.is_none()) {
        return Cow::Borrowed(key);
    }
    let references = posed_references(scene, f64::from(key.frame));
    let mut posed = key.clone();
    for pin in &mut posed.pins {
        if let Some(at) = pin.attach.as_ref().and_then(|a| attachment_among(scene, &references, a)) {
            pin.pos = at.into();
        }
    }
    Cow::Owned(posed)
}

/// A pin's correction at a frame: where it is on the blend and where it must be.
struct Correction {
    /// Material coordinates (m).
    uv: (f64, f64),
    index: usize,
    /// How far to move it (m); zero for a loose pin.
    offset: DVec3,
}

/// Moves `points` (the blend of keys `a` and `b` of `scene` at `frame`,
/// `eased` of the way) so every pin attached in both keys sits on its
/// attachment at `frame`, and spreads each such correction over the cloth
/// by inverse-square material distance; pins loose in either key stay
/// where the blend put them. Returns false, touching nothing, when no pin
/// of the segment is attached.
pub fn carry_to_attachments(
    scene: &Scene,
    (a, b): (usize, usize),
    eased: f64,
    frame: f64,
    points: &mut PointArrays,
) -> bool {
    let (key_a, key_b) = (&scene.keys[a], &scene.keys[b]);
    if key_a.pins.iter().chain(&key_b.pins).all(|p| p.attach.is_none()) {
        return false;
    }
    let cloth = &scene.cloth;
    let cols = cloth.cols();
    let references = posed_references(scene, frame);
    let mut corrections = Vec::new();
    for pin_a in &key_a.pins {
        let Some(pin_b) = key_b.pins.iter().find(|p| p.grid == pin_a.grid) else { continue };
        let (i, j) = (pin_a.grid.0 as usize, pin_a.grid.1 as usize);
        let index = j * cols + i;
        let place = |pin: &crate::scene::Pin| -> DVec3 {
            pin.attach
                .as_ref()
                .and_then(|att| attachment_among(scene, &references, att))
                .unwrap_or(DVec3::from(pin.pos))
        };
        let attached = pin_a.attach.is_some() || pin_b.attach.is_some();
        let offset = if attached {
            let (pa, pb) = (place(pin_a), place(pin_b));
            let target = pa + (pb - pa) * eased;
            let now = DVec3::new(points.x[index].into(), points.y[index].into(), points.z[index].into());
            target - now
        } else {
            DVec3::ZERO
        };
        corrections.push(Correction { uv: cloth.material_uv(i, j), index, offset });
    }
    if corrections.iter().all(|c| c.offset == DVec3::ZERO) {
        return false;
    }
    for j in 0..cloth.rows() {
        for i in 0..cols {
            let index = j * cols + i;
            let (u, v) = cloth.material_uv(i, j);
            let mut sum = DVec3::ZERO;
            let mut weights = 0.0;
            let mut exact = None;
            for c in &corrections {
                let d2 = (u - c.uv.0).powi(2) + (v - c.uv.1).powi(2);
                if c.index == index || d2 == 0.0 {
                    exact = Some(c.offset);
                    break;
                }
                let w = 1.0 / d2;
                sum += c.offset * w;
                weights += w;
            }
            let offset = exact.unwrap_or(sum / weights);
            points.x[index] = (f64::from(points.x[index]) + offset.x) as f32;
            points.y[index] = (f64::from(points.y[index]) + offset.y) as f32;
            points.z[index] = (f64::from(points.z[index]) + offset.z) as f32;
        }
    }
    true
}
