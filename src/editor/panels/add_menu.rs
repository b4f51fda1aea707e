//! An Add menu of the right panel. It opens beside the panel, over the
//! viewport, so choosing an item leaves the pointer over none of the rows the
//! new item joins.

use eframe::egui;

/// The button `label` and, while open, its menu to the left of the panel,
/// level with the button; closes when an item is clicked.
pub(super) fn add_menu_ui(ui: &mut egui::Ui, label: &str, add_contents: impl FnOnce(&mut egui::Ui)) {
    let button = ui.button(label);
    let beside = egui::Rect::from_x_y_ranges(ui.clip_rect().left()..=button.rect.right(), button.rect.y_range());
    egui::Popup::menu(&button)
        .anchor(beside)
        .align(egui::RectAlign::LEFT_START)
        .align_alternatives(&[egui::RectAlign::LEFT_END])
        .show(add_contents);
}
