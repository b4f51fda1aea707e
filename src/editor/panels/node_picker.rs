//! The Cloth panel's node list for "Attach to node…" and "Follow node…": the
//! reference (when the scene has several), a filter, and the reference's
//! node names to pick from. It only picks; attaching is the workspace's.
//!
//! The list floats beside the button that opened it, over the viewport,
//! so opening and closing it moves nothing in the panel, and the pointer
//! that picked a name is left over the viewport, not over another button.

use eframe::egui;

use crate::scene::Reference;

/// Height of the list of node names, points: a rig's twenty nodes scroll.
const LIST_HEIGHT: f32 = 150.0;
/// Width of the floating list, points.
const LIST_WIDTH: f32 = 200.0;

/// The open list's state.
#[derive(Default)]
pub struct NodePicker {
    open: bool,
    /// The reference whose nodes are listed (an index into the scene's).
    reference: usize,
    /// Only names containing this (any case) are listed.
    filter: String,
}

impl NodePicker {
    pub fn is_open(&self) -> bool {
        self.open
    }

    /// Opens the list afresh (no filter), or closes it when open.
    pub fn toggle(&mut self) {
        self.open = !self.open;
        self.filter.clear();
    }

    pub fn close(&mut self) {
        self.open = false;
    }

    /// The list when open, floating at the height of `button` (what opened
    /// it) just right of `ui`'s panel, over the viewport; returns the
    /// reference (index) and node picked this frame, and closes. Cancel, Esc
    /// or a click elsewhere close it without a pick.
    pub fn pick_ui(
        &mut self,
        ui: &egui::Ui,
        button: &egui::Response,
        references: &[Reference],
    ) -> Option<(usize, String)> {
        if !self.open || references.is_empty() {
            return None;
        }
        let mut open = true;
        // Beside the panel rather than the button: a pick then leaves the pointer over
        // the viewport, not over the panel's grid editor or buttons.
        let beside = egui::Rect::from_x_y_ranges(button.rect.left()..=ui.clip_rect().right(), button.rect.y_range());
        let shown = egui::Popup::from_response(button)
            .anchor(beside)
            .id(button.id.with("node list"))
            .open_bool(&mut open)
            .close_behavior(egui::PopupCloseBehavior::CloseOnClickOutside)
            .align(egui::RectAlign::RIGHT_START)
            .width(LIST_WIDTH)
            .show(|ui| self.contents_ui(ui, references));
        self.open &= open;
        shown.and_then(|shown| shown.inner)
    }

    /// The reference, the filter, the names and Cancel; the pick, if any.
    fn contents_ui(&mut self, ui: &mut egui::Ui, references: &[Reference]) -> Option<(usize, String)> {
        self.reference = self.reference.min(references.len() - 1);
        if references.len() > 1 {
            self.reference_ui(ui, references);
        }
        let hint = "Filter nodes";
        let field = egui::TextEdit::singleline(&mut self.filter).hint_text(hint).desired_width(LIST_WIDTH);
        ui.add(field).accessible_name(hint);
        let reference = &references[self.reference];
        let picked = match reference.rig.0.as_deref() {
            Some(rig) => self.names_ui(ui, rig.nodes().iter().map(|n| n.name.as_str())),
            None => {
                ui.weak(format!("The file of {} is not read: no nodes to list.", reference.label(self.reference)));
                None
            }
        };
        if ui.button("Cancel").clicked() {
            self.open = false;
        }
        let picked = picked.map(|name| (self.reference, name));
        if picked.is_some() {
            self.open = false;
        }
        picked
    }

    /// The reference to list the nodes of, chosen first when there are several
    /// (buttons, not a drop-down: a second floating list would close this one).
    fn reference_ui(&mut self, ui: &mut egui::Ui, references: &[Reference]) {
        ui.horizontal_wrapped(|ui| {
            ui.label("Reference");
            for (index, reference) in references.iter().enumerate() {
                ui.selectable_value(&mut self.reference, index, reference.label(index));
            }
        });
    }

    /// The names passing the filter, in a scrolled list; the one clicked.
    fn names_ui<'a>(&self, ui: &mut egui::Ui, names: impl Iterator<Item = &'a str>) -> Option<String> {
        let filter = self.filter.trim().to_lowercase();
        let shown: Vec<&str> = names.filter(|n| n.to_lowercase().contains(&filter)).collect();
        if shown.is_empty() {
            ui.weak("No node matches.");
            return None;
        }
        let mut picked = None;
        egui::ScrollArea::vertical()
            .id_salt("node list")
            .max_height(LIST_HEIGHT)
            .min_scrolled_height(LIST_HEIGHT)
            .show(ui, |ui| {
                for name in shown {
                    if ui.selectable_label(false, name).on_hover_text("Attach the selected pins here").clicked() {
                        picked = Some(name.to_owned());
                    }
                }
            });
        picked
    }
}
