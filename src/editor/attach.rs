//! Attaching pins to references and letting them go: the verbs, as plain
//! functions on the scene, and the workspace's undoable steps that use them.
//!
//! An attached pin sits on its attachment at every frame, and its key's rest
//! shape holds it where the attachment is at the key's frame; `pos` only
//! records that place. So every verb here works at the key's frame: attaching
//! to a node keeps the pin where it is then (the offset is the pin in the
//! node's coordinates), detaching leaves it there, and moving a node-attached
//! pin moves its offset. A surface point cannot be dragged along the skin, so
//! moving a surface-attached pin lets it go.

use glam::{DMat4, DVec3};

use super::viewport::reference_pick::SurfaceHit;
use super::workspace::Workspace;
use crate::animate::attachments::attachment_at;
use crate::animate::references_at::reference_at;
use crate::scene::{Attachment, Key, NodeAttachment, Pin, Scene, SurfaceAttachment};

/// Where `pin` of `key` is at the key's frame: where its attachment holds
/// it, else (loose, or its reference not read) its `pos`.
pub fn pin_at_key(scene: &Scene, key: &Key, pin: &Pin) -> DVec3 {
    let attached = pin.attach.as_ref().and_then(|a| attachment_at(scene, a, f64::from(key.frame)));
    attached.unwrap_or(DVec3::from(pin.pos))
}

/// Where pin `grid` of key `key` is at the key's frame ([`pin_at_key`]);
/// None when the key or the pin is not there.
pub fn pin_place(scene: &Scene, key: usize, grid: (u32, u32)) -> Option<DVec3> {
    let k = scene.keys.get(key)?;
    Some(pin_at_key(scene, k, k.pins.iter().find(|p| p.grid == grid)?))
}

/// How the Cloth panel names an attachment: `walker · node chest`,
/// `walker · surface (mesh 0, triangle 1234)`.
pub fn describe(attachment: &Attachment) -> String {
    match attachment {
        Attachment::Node(node) => format!("{} · node {}", node.reference, node.node),
        Attachment::Surface(s) => format!("{} · surface (mesh {}, triangle {})", s.reference, s.mesh, s.triangle),
    }
}

/// Node `node` of reference `reference`'s transform into the scene at `frame`.
fn scene_from_node(scene: &Scene, reference: usize, node: &str, frame: f64) -> Option<DMat4> {
    let posed = reference_at(scene, reference, frame)?;
    posed.scene_from_node(posed.rig.node_named(node)?)
}

/// The attachment to node `node` of reference `reference` that holds the
/// scene point `at` at `frame`: `at` in the node's coordinates. None when the
/// reference is not read, has no such node, or the node is squashed flat.
pub fn node_attachment(scene: &Scene, reference: usize, node: &str, frame: f64, at: DVec3) -> Option<NodeAttachment> {
    let from_node = scene_from_node(scene, reference, node, frame)?;
    if from_node.determinant().abs() < 1e-18 {
        return None;
    }
    let offset = from_node.inverse().transform_point3(at);
    offset.is_finite().then(|| NodeAttachment {
        reference: scene.references[reference].name.clone(),
        node: node.to_owned(),
        offset: offset.into(),
    })
}

/// Lets go of the attachments of key `key`'s pins at `grids`, each left
/// where its attachment holds it at the key's frame, so none moves.
/// Returns how many were attached.
pub fn detach(scene: &mut Scene, key: usize, grids: &[(u32, u32)]) -> usize {
    let Some(k) = scene.keys.get(key) else { return 0 };
    let places: Vec<((u32, u32), DVec3)> = k
        .pins
        .iter()
        .filter(|p| p.attach.is_some() && grids.contains(&p.grid))
        .map(|p| (p.grid, pin_at_key(scene, k, p)))
        .collect();
    for (grid, at) in &places {
        if let Some(pin) = scene.keys[key].pins.iter_mut().find(|p| p.grid == *grid) {
            pin.attach = None;
            pin.pos = (*at).into();
        }
    }
    places.len()
}

/// Attaches key `key`'s pins at `grids` to node `node` of reference
/// `reference`, each where it is at the key's frame, so none moves. Returns
/// how many were attached: none when the node cannot be posed.
pub fn attach_to_node(scene: &mut Scene, key: usize, grids: &[(u32, u32)], reference: usize, node: &str) -> usize {
    let Some(k) = scene.keys.get(key) else { return 0 };
    let frame = f64::from(k.frame);
    let mut attached = Vec::new();
    for pin in k.pins.iter().filter(|p| grids.contains(&p.grid)) {
        let at = pin_at_key(scene, k, pin);
        let Some(attachment) = node_attachment(scene, reference, node, frame, at) else { return 0 };
        attached.push((pin.grid, at, attachment));
    }
    for (grid, at, attachment) in &attached {
        if let Some(pin) = scene.keys[key].pins.iter_mut().find(|p| p.grid == *grid) {
            pin.pos = (*at).into();
            pin.attach = Some(Attachment::Node(attachment.clone()));
        }
    }
    attached.len()
}

/// The surface attachment naming the skin point `hit`, lifted off the skin
/// by `lift_m` (the key's thickness, so the cloth sits on it, not in it).
pub fn surface_attachment(scene: &Scene, hit: &SurfaceHit, lift_m: f64) -> Option<SurfaceAttachment> {
    Some(SurfaceAttachment {
        reference: scene.references.get(hit.reference)?.name.clone(),
        mesh: hit.mesh,
        triangle: hit.triangle,
        barycentric: hit.barycentric,
        lift_m,
    })
}

/// Attaches pin `grid` of key `key` to the skin point `hit` names, a key's
/// thickness off the skin; its `pos` becomes where that point is at the key's
/// frame. False (nothing changed) when there is no such pin or the point
/// cannot be placed.
pub fn attach_to_surface(scene: &mut Scene, key: usize, grid: (u32, u32), hit: &SurfaceHit) -> bool {
    let Some(k) = scene.keys.get(key) else { return false };
    let Some(surface) = surface_attachment(scene, hit, k.thickness) else { return false };
    let attachment = Attachment::Surface(surface);
    let Some(at) = attachment_at(scene, &attachment, f64::from(k.frame)) else { return false };
    let Some(pin) = scene.keys[key].pins.iter_mut().find(|p| p.grid == grid) else { return false };
    pin.pos = at.into();
    pin.attach = Some(attachment);
    true
}

/// Moves pin `grid` of key `key` so it is at `to` at the key's frame. A
/// node-attached pin stays attached, its offset taking the move; a
/// surface-attached one is let go and moved. Returns the name of the
/// reference a pin was let go from.
pub fn move_pin(scene: &mut Scene, key: usize, grid: (u32, u32), to: DVec3) -> Option<String> {
    let k = scene.keys.get(key)?;
    let frame = f64::from(k.frame);
    let attach = k.pins.iter().find(|p| p.grid == grid)?.attach.clone();
    let (attach, detached) = match attach {
        Some(Attachment::Node(node)) => {
            let reference = scene.references.iter().position(|r| r.name == node.reference);
            let moved = reference.and_then(|r| node_attachment(scene, r, &node.node, frame, to));
            // A rig not read cannot say where the node is: the offset stays, as the file has it.
            (Some(Attachment::Node(moved.unwrap_or(node))), None)
        }
        Some(Attachment::Surface(surface)) => (None, Some(surface.reference)),
        None => (None, None),
    };
    let pin = scene.keys[key].pins.iter_mut().find(|p| p.grid == grid)?;
    pin.pos = to.into();
    pin.attach = attach;
    detached
}

/// Lets go of the selected pins' attachments in the key being edited
/// (with auto-key off a key, a new key here); one undo step, no pin moves.
pub fn detach_selected_pins(w: &mut Workspace) {
    let selection = w.session.selection().to_vec();
    let label = if selection.len() == 1 { "Detach pin" } else { "Detach pins" };
    let Some(index) = w.key_to_edit(label) else { return };
    w.apply(label, |s| {
        detach(s, index, &selection);
    });
}

/// Attaches the selected pins to node `node` of reference `reference`
/// where they are (with auto-key off a key, on a new key here); one undo step.
pub fn attach_selected_to_node(w: &mut Workspace, reference: usize, node: &str) {
    let selection = w.session.selection().to_vec();
    let label = if selection.len() == 1 { "Attach pin" } else { "Attach pins" };
    let Some(index) = w.key_to_edit(label) else { return };
    let mut attached = 0;
    w.apply(label, |s| attached = attach_to_node(s, index, &selection, reference, node));
    if attached == 0 {
        w.report(format!("Cannot attach to node {node}: its reference's file is not read."), true);
    }
}

/// Enters attach-by-clicking for the one selected pin: the next click
/// on a reference in the viewport attaches it there. Says why not with
/// another selection or no reference.
pub fn start_attach_by_click(w: &mut Workspace) {
    let key = &w.doc.scene().keys[w.edit_key_index()];
    let pinned: Vec<(u32, u32)> =
        w.session.selection().iter().copied().filter(|g| key.pins.iter().any(|p| p.grid == *g)).collect();
    let [grid] = pinned[..] else {
        w.report("Select exactly one pin to attach by clicking.".to_owned(), true);
        return;
    };
    if w.doc.scene().references.is_empty() {
        w.report("Add a reference to attach the pin to.".to_owned(), true);
        return;
    }
    w.session.start_attaching(grid);
    w.clear_message();
}

/// Leaves attach-by-clicking once its pin is no longer the one pin
/// selected in the key being edited (another picked, unpinned, undone,
/// the playhead on a key without it), so a click never attaches a pin
/// the user no longer means.
pub fn keep_attach_mode_on_its_pin(w: &mut Workspace) {
    let Some(grid) = w.session.attaching() else { return };
    let pinned = w.doc.scene().keys[w.edit_key_index()].pins.iter().any(|p| p.grid == grid);
    if !pinned || w.session.selection() != [grid] {
        w.session.stop_attaching();
    }
}

/// Leaves attach-by-clicking (Esc), attaching nothing.
pub fn cancel_attach_by_click(w: &mut Workspace) {
    w.session.stop_attaching();
}

/// The click of attach-by-clicking: `hit` is the reference surface under
/// it at the frame shown. Attaches the pin there (with auto-key off a
/// key, on a new key here) in one undo step and leaves the mode; a click
/// on no reference says so and stays in the mode.
pub fn attach_clicked(w: &mut Workspace, hit: Option<SurfaceHit>) {
    let Some(grid) = w.session.attaching() else { return };
    let Some(hit) = hit else {
        let text = format!("No reference there: click on a reference to attach pin {grid:?} (Esc cancels).");
        w.report(text, true);
        return;
    };
    // Still waiting when no key can be made yet (auto-key while relaxing): the message says why.
    let Some(index) = w.key_to_edit("Attach pin") else { return };
    w.session.stop_attaching();
    if !w.doc.scene().keys[index].pins.iter().any(|p| p.grid == grid) {
        w.report(format!("Grid point {grid:?} is no longer pinned: nothing attached."), true);
        return;
    }
    let mut attached = false;
    w.apply("Attach pin", |s| attached = attach_to_surface(s, index, grid, &hit));
    let name = &w.doc.scene().references[hit.reference].name;
    if attached {
        let text = format!("Attached pin {grid:?} to {name} (mesh {}, triangle {}).", hit.mesh, hit.triangle);
        w.report(text, false);
    }
}

/// Moves pins of key `key` to where `moves` says (at the key's frame) as
/// [`move_pin`] does: node-attached pins stay attached, surface-attached
/// ones are let go, which the status line says. Part of the open gesture, if any.
pub fn move_pins(w: &mut Workspace, label: &str, key: usize, moves: &[((u32, u32), DVec3)]) {
    let mut detached = Vec::new();
    w.apply(label, |s| {
        for &(grid, to) in moves {
            if let Some(name) = move_pin(s, key, grid, to) {
                detached.push((grid, name));
            }
        }
    });
    let scene = w.doc.scene();
    let still_attached = |grid: (u32, u32)| {
        scene.keys.get(key).is_some_and(|k| k.pins.iter().any(|p| p.grid == grid && p.attach.is_some()))
    };
    // Refused edits leave the pins attached: nothing was let go.
    if let Some((grid, name)) = detached.into_iter().find(|(grid, _)| !still_attached(*grid)) {
        w.report(format!("Detached pin {grid:?} from {name} to move it."), false);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::editor::viewport::reference_pick::pick_reference_surface;

    fn cape() -> Scene {
        crate::scene::load(std::path::Path::new("scenes/cape.ron")).unwrap()
    }

    fn place(scene: &Scene, key: usize, grid: (u32, u32)) -> DVec3 {
        let k = &scene.keys[key];
        pin_at_key(scene, k, k.pins.iter().find(|p| p.grid == grid).unwrap())
    }

    #[test]
    fn detaching_and_attaching_to_a_node_move_no_pin() {
        let mut scene = cape();
        let grid = (9, 0);
        let before = place(&scene, 0, grid);
        assert_eq!(detach(&mut scene, 0, &[grid, (3, 3)]), 1);
        let pin = &scene.keys[0].pins[2];
        assert_eq!((pin.attach.as_ref(), DVec3::from(pin.pos)), (None, before));
        // Onto another node, where it is.
        assert_eq!(attach_to_node(&mut scene, 0, &[grid], 0, "head"), 1);
        let Some(Attachment::Node(node)) = &scene.keys[0].pins[2].attach else { panic!() };
        assert_eq!(node.node, "head");
        assert!(place(&scene, 0, grid).distance(before) < 1e-9);
        assert_eq!(attach_to_node(&mut scene, 0, &[grid], 0, "no such node"), 0);
        assert!(scene.validate().is_ok());
    }

    #[test]
    fn a_node_attached_pin_moves_its_offset_and_a_surface_one_lets_go() {
        let mut scene = cape();
        let to = place(&scene, 0, (0, 0)) + DVec3::new(0.05, -0.02, 0.01);
        assert_eq!(move_pin(&mut scene, 0, (0, 0), to), None);
        assert!(matches!(scene.keys[0].pins[0].attach, Some(Attachment::Node(_))));
        assert!(place(&scene, 0, (0, 0)).distance(to) < 1e-9);
        assert_eq!(DVec3::from(scene.keys[0].pins[0].pos), to);

        // Cast at the chest from behind (the cape's side): a skin point, a thickness out.
        let chest = scene_from_node(&scene, 0, "chest", 0.0).unwrap().transform_point3(DVec3::ZERO);
        let eye = chest + DVec3::new(0.0, 0.1, -2.0);
        let hit = pick_reference_surface(&scene, 0.0, eye, chest - eye).expect("the body");
        assert!(attach_to_surface(&mut scene, 0, (9, 0), &hit));
        let pin = scene.keys[0].pins[2].clone();
        let Some(Attachment::Surface(surface)) = &pin.attach else { panic!("{pin:?}") };
        assert_eq!(surface.lift_m, scene.keys[0].thickness);
        let on_skin = eye + (chest - eye) * hit.along;
        assert!((DVec3::from(pin.pos).distance(on_skin) - surface.lift_m).abs() < 1e-6, "lifted off the hit");
        assert!(DVec3::from(pin.pos).distance(eye) < on_skin.distance(eye), "outwards, towards the eye");
        assert!(scene.validate().is_ok());
        let to = DVec3::from(pin.pos) + DVec3::Y * 0.1;
        assert_eq!(move_pin(&mut scene, 0, (9, 0), to).as_deref(), Some("walker"));
        assert_eq!(scene.keys[0].pins[2].attach, None);
        assert_eq!(DVec3::from(scene.keys[0].pins[2].pos), to);
    }

    #[test]
    fn attachments_are_described_by_reference_and_what_holds_them() {
        let scene = cape();
        let pin = &scene.keys[0].pins[0];
        assert_eq!(describe(pin.attach.as_ref().unwrap()), "walker · node chest");
        let surface = Attachment::Surface(SurfaceAttachment {
            reference: "walker".into(),
            mesh: 0,
            triangle: 1234,
            barycentric: (1.0, 0.0, 0.0),
            lift_m: 0.0,
        });
        assert_eq!(describe(&surface), "walker · surface (mesh 0, triangle 1234)");
    }
}
