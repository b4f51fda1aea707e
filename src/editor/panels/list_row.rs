//! The end of a row in a panel's list: its title, cut short to leave room,
//! and its × at the row's right end, away from the row's start, where an Add
//! menu's items lie over the rows as it closes.

use eframe::egui;

/// Room the × takes at the row's end, points.
const REMOVE_WIDTH: f32 = 22.0;

/// The row's selectable title, cut short with "…" so the row never grows
/// wider than the panel, then the × at the right end. Returns the title's
/// response and the ×'s.
pub(super) fn title_and_remove_ui(
    ui: &mut egui::Ui,
    selected: bool,
    title: String,
    remove_hint: &str,
) -> (egui::Response, egui::Response) {
    let room = (ui.available_width() - REMOVE_WIDTH - ui.spacing().item_spacing.x).max(0.0);
    let size = egui::vec2(room, ui.spacing().interact_size.y);
    let title = ui.allocate_ui(size, |ui| ui.add(egui::Button::selectable(selected, title).truncate())).inner;
    let remove = ui
        .with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
            ui.small_button("×").on_hover_text(remove_hint)
        })
        .inner;
    (title, remove)
}
