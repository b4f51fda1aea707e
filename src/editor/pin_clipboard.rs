//! Copy, paste and mirror of pins (Ctrl+C / Ctrl+V, Mirror): whole pins,
//! attachments included, so a pin bound to a character's shoulder pastes
//! bound to it on another key.

use glam::DVec3;

use super::attach::{self, pin_at_key, pin_place};
use super::workspace::Workspace;
use crate::scene::Pin;

/// Copies the selected pins of the key being edited (Ctrl+C), each with
/// where it is at the key's frame and its attachment; returns them as
/// the scene file writes pins, for the system clipboard (`None` with
/// nothing selected).
pub fn copy_selected_pins(w: &mut Workspace) -> Option<String> {
    let scene = w.doc.scene();
    let key = &scene.keys[w.edit_key_index()];
    let copied: Vec<Pin> = key
        .pins
        .iter()
        .filter(|p| w.session.selection().contains(&p.grid))
        .map(|p| Pin { pos: pin_at_key(scene, key, p).into(), ..p.clone() })
        .collect();
    if copied.is_empty() {
        return None;
    }
    let plural = if copied.len() == 1 { "" } else { "s" };
    w.report(format!("Copied {} pin{plural}.", copied.len()), false);
    let text = ron::to_string(&copied).ok();
    w.session.copy_pins(copied);
    text
}

/// Puts copied pins on the key being edited (Ctrl+V): `text` from the
/// clipboard when it holds pins as the scene file writes them (copied
/// here, or from a scene file), else the pins copied last. Each grid
/// point is pinned as the copy was (its position and its attachment, if
/// any; a pin already there is replaced), and the pasted pins become the
/// selection.
pub fn paste_pins(w: &mut Workspace, text: Option<&str>) {
    if let Some(pins) = text.and_then(|t| ron::from_str::<Vec<Pin>>(t.trim().trim_end_matches(',')).ok())
        && !pins.is_empty()
    {
        w.session.copy_pins(pins);
    }
    let copied = w.session.copied_pins().to_vec();
    if copied.is_empty() {
        return;
    }
    let Some(index) = w.key_to_edit("Paste pins") else { return };
    w.apply("Paste pins", |s| {
        let key = &mut s.keys[index];
        for pin in &copied {
            match key.pins.iter_mut().find(|p| p.grid == pin.grid) {
                Some(there) => *there = pin.clone(),
                None => key.pins.push(pin.clone()),
            }
        }
    });
    w.session.select_only(&copied.iter().map(|p| p.grid).collect::<Vec<_>>());
}

/// The selected pins go where their partners across the cloth's middle
/// column are at the key's frame, reflected in x = 0 (pins on the middle
/// column reflect their own x; a pin without a partner stays). They move
/// as any moved pin does: a node-attached pin stays attached, a
/// surface-attached one is let go (the status line says so).
pub fn mirror_selected_pins(w: &mut Workspace) {
    let selection = w.session.selection().to_vec();
    if selection.is_empty() {
        return;
    }
    let cols = w.doc.scene().cloth.grid.0;
    let Some(index) = w.key_to_edit("Mirror pins") else { return };
    let scene = w.doc.scene();
    let moves: Vec<((u32, u32), DVec3)> = selection
        .iter()
        .filter(|grid| scene.keys[index].pins.iter().any(|p| p.grid == **grid))
        .filter_map(|&grid| {
            let partner = (cols.saturating_sub(1).saturating_sub(grid.0), grid.1);
            let there = pin_place(scene, index, partner)?;
            Some((grid, DVec3::new(-there.x, there.y, there.z)))
        })
        .collect();
    attach::move_pins(w, "Mirror pins", index, &moves);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Attachment;

    fn cape() -> Workspace {
        Workspace::new(crate::scene::load(std::path::Path::new("scenes/cape.ron")).unwrap(), None)
    }

    #[test]
    fn an_attached_pin_pastes_attached_and_mirrors_keeping_its_node() {
        let mut w = cape();
        let edge = (0, 0);
        w.session.select_only(&[edge]);
        let text = copy_selected_pins(&mut w).expect("a pin");
        assert!(text.contains("attach:"), "the attachment travels with the copy: {text}");
        // Paste it onto the middle of the top edge: the same attachment, the same place.
        let copied = w.session.copied_pins()[0].clone();
        w.session.copy_pins(vec![Pin { grid: (9, 0), ..copied.clone() }]);
        paste_pins(&mut w, None);
        let pasted = w.doc.scene().keys[0].pins.iter().find(|p| p.grid == (9, 0)).unwrap().clone();
        assert_eq!((pasted.pos, &pasted.attach), (copied.pos, &copied.attach));
        w.undo();
        // Mirror the right edge pin from the left one: still on the chest, at the reflection.
        let left = pin_place(w.doc.scene(), 0, edge).unwrap();
        w.session.select_only(&[(18, 0)]);
        mirror_selected_pins(&mut w);
        let right = pin_place(w.doc.scene(), 0, (18, 0)).unwrap();
        assert!(right.distance(DVec3::new(-left.x, left.y, left.z)) < 1e-9, "{right} vs {left}");
        let pin = w.doc.scene().keys[0].pins.iter().find(|p| p.grid == (18, 0)).unwrap();
        assert!(matches!(&pin.attach, Some(Attachment::Node(node)) if node.node == "chest"));
    }

    #[test]
    fn mirroring_reflects_partners_and_leaves_pins_without_one() {
        let mut w = cape();
        let loose = |w: &mut Workspace| {
            w.apply("Let go", |s| s.keys[0].pins.iter_mut().for_each(|p| p.attach = None));
        };
        loose(&mut w);
        w.apply("A pin without a partner", |s| s.keys[0].pins.push(Pin::at((3, 5), (0.3, 1.0, -0.2))));
        w.session.select_only(&[(4, 0), (9, 0), (3, 5)]);
        let before = w.doc.scene().keys[0].pins.clone();
        mirror_selected_pins(&mut w);
        let pos = |w: &Workspace, grid| w.doc.scene().keys[0].pins.iter().find(|p| p.grid == grid).unwrap().pos;
        let partner = before.iter().find(|p| p.grid == (14, 0)).unwrap().pos;
        assert_eq!(pos(&w, (4, 0)), (-partner.0, partner.1, partner.2), "takes (14, 0) reflected");
        let middle = before.iter().find(|p| p.grid == (9, 0)).unwrap().pos;
        assert_eq!(pos(&w, (9, 0)), (-middle.0, middle.1, middle.2), "the middle column reflects itself");
        assert_eq!(pos(&w, (3, 5)), (0.3, 1.0, -0.2), "no partner at (15, 5): stays");
    }
}
