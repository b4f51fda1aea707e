//! The Cloth panel's rows about the selected pins' attachments: what holds
//! them (and Detach), and the two ways to attach them to a reference: a node
//! picked from a list, or a skin point clicked on in the viewport.

use eframe::egui;

use super::node_picker::NodePicker;
use crate::editor::attach::{self, describe};
use crate::editor::workspace::Workspace;
use crate::scene::Pin;

/// What the `selected` pins (of the key being edited) are attached to, with
/// Detach; then Attach to node… (its list floating beside it) and Attach by
/// clicking. Both rows are there, greyed, with no pin selected, nothing
/// attached or no reference in the scene, so nothing below them moves when
/// that changes.
pub fn attachment_ui(ui: &mut egui::Ui, w: &mut Workspace, selected: &[Pin], picker: &mut NodePicker) {
    attached_line_ui(ui, w, selected);
    let references = w.doc.scene().references.clone();
    let has_references = !references.is_empty();
    let any = !selected.is_empty();
    let node_button = ui
        .horizontal(|ui| {
            let hint = "Attach the selected pins to a node (a joint) of a reference, where they are";
            let why_not = if has_references { "Select pins to attach" } else { "Add a reference to attach pins to it" };
            let button = egui::Button::new("Attach to node…").selected(picker.is_open() && any);
            let node_button = ui.add_enabled(any && has_references, button).on_hover_text(hint);
            let node_button = node_button.on_disabled_hover_text(why_not);
            if node_button.clicked() {
                picker.toggle();
            }
            let one = selected.len() == 1;
            let attaching = w.session.attaching().is_some();
            let hint = "Then click on a reference in the viewport: the pin is attached to that point of its skin";
            let why_not = if has_references {
                "Select exactly one pin to attach by clicking"
            } else {
                "Add a reference to attach pins to it"
            };
            let button = egui::Button::new("Attach by clicking").selected(attaching);
            let response = ui.add_enabled((one && has_references) || attaching, button).on_hover_text(hint);
            if response.on_disabled_hover_text(why_not).clicked() {
                if attaching { attach::cancel_attach_by_click(w) } else { attach::start_attach_by_click(w) }
            }
            node_button
        })
        .inner;
    if !any {
        picker.close();
        return;
    }
    if let Some((reference, node)) = picker.pick_ui(ui, &node_button, &references) {
        attach::attach_selected_to_node(w, reference, &node);
    }
}

/// One pin's attachment and Detach, or how many of several are attached and
/// Detach N; "Not attached" beside a greyed Detach when none is.
fn attached_line_ui(ui: &mut egui::Ui, w: &mut Workspace, selected: &[Pin]) {
    let attached: Vec<&Pin> = selected.iter().filter(|p| p.attach.is_some()).collect();
    let (text, button) = match (selected, attached.as_slice()) {
        (_, []) => (String::new(), "Detach".to_owned()),
        ([_], [pin]) => {
            let held_by = pin.attach.as_ref().map(describe).unwrap_or_default();
            (format!("Attached to {held_by}"), "Detach".to_owned())
        }
        (many, attached) => {
            (format!("{} of {} attached", attached.len(), many.len()), format!("Detach {}", attached.len()))
        }
    };
    ui.horizontal(|ui| {
        // The button first, so a long name is cut rather than pushing it out of the panel.
        let hint = "Let go of the reference: the pin stays where it is at the key's frame";
        let button = ui.add_enabled(!attached.is_empty(), egui::Button::new(button)).on_hover_text(hint);
        if button.clicked() {
            attach::detach_selected_pins(w);
        }
        if text.is_empty() {
            ui.weak(if selected.is_empty() { "Attached to: —" } else { "Not attached" });
        } else {
            ui.add(egui::Label::new(&text).truncate()).on_hover_text(&text);
        }
    });
}
