//! The Cloth panel's rows about the selected pins' attachments: what holds
//! them (and Detach), and the two ways to attach them to a reference: a node
//! picked from a list, or a skin point clicked on in the viewport.

use eframe::egui;

use super::attach::describe;
use super::node_picker::NodePicker;
use super::workspace::Workspace;
use crate::scene::Pin;

/// What the `selected` pins (of the key being edited) are attached to, with
/// Detach; then, in a scene with references, Attach to node… (its list
/// below) and Attach by clicking.
pub fn attachment_ui(ui: &mut egui::Ui, w: &mut Workspace, selected: &[Pin], picker: &mut NodePicker) {
    attached_line_ui(ui, w, selected);
    let references = w.doc.scene().references.clone();
    if references.is_empty() {
        return;
    }
    ui.horizontal(|ui| {
        let any = !selected.is_empty();
        let hint = "Attach the selected pins to a node (a joint) of a reference, where they are";
        let button = egui::Button::new("Attach to node…").selected(picker.is_open() && any);
        if ui.add_enabled(any, button).on_hover_text(hint).on_disabled_hover_text("Select pins to attach").clicked() {
            picker.toggle();
        }
        let one = selected.len() == 1;
        let attaching = w.session.attaching.is_some();
        let hint = "Then click on a reference in the viewport: the pin is attached to that point of its skin";
        let button = egui::Button::new("Attach by clicking").selected(attaching);
        let response = ui.add_enabled(one || attaching, button).on_hover_text(hint);
        let response = response.on_disabled_hover_text("Select exactly one pin to attach by clicking");
        if response.clicked() {
            if attaching { w.cancel_attach_by_click() } else { w.start_attach_by_click() }
        }
    });
    if selected.is_empty() {
        picker.close();
        return;
    }
    if let Some((reference, node)) = picker.pick_ui(ui, &references) {
        w.attach_selected_to_node(reference, &node);
    }
}

/// One pin's attachment and Detach, or how many of several are attached and
/// Detach N; nothing when none is.
fn attached_line_ui(ui: &mut egui::Ui, w: &mut Workspace, selected: &[Pin]) {
    let attached: Vec<&Pin> = selected.iter().filter(|p| p.attach.is_some()).collect();
    let (text, button) = match (selected, attached.as_slice()) {
        (_, []) => return,
        ([_], [pin]) => {
            let Some(attachment) = &pin.attach else { return };
            (format!("Attached to {}", describe(attachment)), "Detach".to_owned())
        }
        (many, attached) => {
            (format!("{} of {} attached", attached.len(), many.len()), format!("Detach {}", attached.len()))
        }
    };
    ui.horizontal(|ui| {
        // The button first, so a long name is cut rather than pushing it out of the panel.
        let hint = "Let go of the reference: the pin stays where it is at the key's frame";
        if ui.button(button).on_hover_text(hint).clicked() {
            w.detach_selected_pins();
        }
        ui.add(egui::Label::new(&text).truncate()).on_hover_text(&text);
    });
}
