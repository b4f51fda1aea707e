//! The viewport's drawing style: lit, or toon in the scene's `cloth.toon`
//! settings (edited in the Cloth panel). Chosen in View ▸ Style and in the
//! view bar; a view setting, not part of the document.

use eframe::egui;

use super::ViewportPanel;
use crate::editor::workspace::Workspace;
use crate::render::{Style, ToonLook};

/// What the style choices are called and what they say when hovered.
const STYLES: [(bool, &str, &str); 2] = [
    (false, "Lit", "Key, fill and rim lights, soft shading"),
    (true, "Toon", "Flat tone bands and ink lines, as the Cloth panel's Toon rows say"),
];

impl ViewportPanel {
    /// The style the viewport draws in, for the scene shown.
    pub(super) fn style(&self, w: &Workspace) -> Style {
        if self.toggles.toon { Style::Toon(ToonLook::from_settings(&w.shown.scene().cloth.toon)) } else { Style::Lit }
    }

    /// The View menu's style items: flat buttons in the menu itself (a
    /// nested menu's items missed real clicks), under a "Style" label.
    pub fn style_menu_ui(&mut self, ui: &mut egui::Ui) {
        ui.label("Style");
        for (toon, label, hint) in STYLES {
            let button = egui::Button::new(label).selected(self.toggles.toon == toon);
            if ui.add(button).on_hover_text(hint).clicked() {
                self.toggles.toon = toon;
                ui.close();
            }
        }
    }

    /// The view bar's style choice: Lit or Toon side by side.
    pub(super) fn style_ui(&mut self, ui: &mut egui::Ui) {
        // One by one into the bar's wrapping row, so the bar may wrap between them.
        ui.label("Style");
        for (toon, label, hint) in STYLES {
            ui.selectable_value(&mut self.toggles.toon, toon, label).on_hover_text(hint);
        }
    }
}
