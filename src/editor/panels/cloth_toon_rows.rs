//! The Cloth panel's Toon rows: how the toon style draws the cloth (tone
//! bands, ink width and colour, the crease angle, front and back colours).
//! Each change is an undoable edit of `cloth.toon`; the style itself is
//! chosen in View ▸ Style.

use eframe::egui::{self, Response};

use crate::editor::number_field::number_field;
use crate::editor::workspace::Workspace;
use crate::scene::{MAX_CREASE_DEG, MAX_INK_WIDTH_PX, Scene, SrgbColor, linear_to_srgb, srgb_to_linear};

/// Applies `change` when `response` changed the value; a drag on the widget is one undo step.
fn toon_field(w: &mut Workspace, response: &Response, label: &str, change: impl FnOnce(&mut Scene)) {
    if response.drag_started() {
        w.doc.begin_gesture(label);
    }
    if response.changed() {
        w.apply(label, change);
    }
}

/// A colour button for an sRGB colour (egui's picker works in linear RGB);
/// `Some` with the new colour when it was changed.
fn color_button(ui: &mut egui::Ui, color: SrgbColor, label: &str) -> Option<SrgbColor> {
    let (r, g, b) = color;
    let mut linear = [r, g, b].map(|c| srgb_to_linear(c) as f32);
    let response = ui.color_edit_button_rgb(&mut linear);
    response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Button, true, label));
    let [r, g, b] = linear.map(|c| linear_to_srgb(c as f64));
    response.changed().then_some((r, g, b))
}

/// The Toon rows, collapsed by default so the panel keeps its length.
pub(in crate::editor) fn toon_section_ui(ui: &mut egui::Ui, w: &mut Workspace) {
    egui::CollapsingHeader::new("Toon style").id_salt("toon").show(ui, |ui| {
        ui.weak("How the View menu's Toon and `drape render --style toon` draw the cloth.");
        let toon = w.doc.scene().cloth.toon.clone();
        egui::Grid::new("toon").num_columns(2).show(ui, |ui| {
            ui.label("Bands").on_hover_text("Flat tones from the key light: lit and shadow, or lit, half and shadow");
            ui.horizontal(|ui| {
                for bands in [2, 3] {
                    if ui.selectable_label(toon.bands == bands, bands.to_string()).clicked() && toon.bands != bands {
                        w.apply("Toon bands", |s| s.cloth.toon.bands = bands);
                    }
                }
            });
            ui.end_row();

            let label = ui.label("Ink").on_hover_text("Lines on the silhouette, the border and sharp creases").id;
            ui.horizontal(|ui| {
                let mut width = toon.ink_width_px;
                let drag = number_field(ui.ctx(), &mut width).range(0.0..=MAX_INK_WIDTH_PX).speed(0.05).suffix(" px");
                let r = ui.add(drag).labelled_by(label).on_hover_text("Line width in pixels; 0 draws no ink");
                toon_field(w, &r, "Ink width", |s| s.cloth.toon.ink_width_px = width);
                if let Some(color) = color_button(ui, toon.ink_color, "Ink colour") {
                    w.apply("Ink colour", |s| s.cloth.toon.ink_color = color);
                }
            });
            ui.end_row();

            let label = ui.label("Creases").id;
            let mut crease = toon.crease_deg;
            let drag = number_field(ui.ctx(), &mut crease).range(0.0..=MAX_CREASE_DEG).speed(0.5).suffix("°");
            let hint = "An edge where the cloth bends by more than this gets ink; 180° inks none";
            let r = ui.add(drag).labelled_by(label).on_hover_text(hint);
            toon_field(w, &r, "Crease angle", |s| s.cloth.toon.crease_deg = crease);
            ui.end_row();

            for (back, name) in [(false, "Front"), (true, "Back")] {
                let color = if back { toon.back } else { toon.front };
                ui.label(name);
                ui.horizontal(|ui| {
                    let mut own = color.is_some();
                    let hint = "Its own colour, multiplying the texture; off: the usual tint";
                    if ui.checkbox(&mut own, "").on_hover_text(hint).changed() {
                        // A new colour starts from a light warm grey that shows the texture.
                        let chosen = own.then_some((0.85, 0.8, 0.72));
                        w.apply(&format!("Toon {} colour", name.to_lowercase()), |s| {
                            *toon_side(s, back) = chosen;
                        });
                    }
                    if let Some(color) = color
                        && let Some(chosen) = color_button(ui, color, &format!("{name} colour"))
                    {
                        w.apply(&format!("Toon {} colour", name.to_lowercase()), |s| {
                            *toon_side(s, back) = Some(chosen);
                        });
                    }
                });
                ui.end_row();
            }
        });
    });
}

/// The toon colour of the front or the back.
fn toon_side(scene: &mut Scene, back: bool) -> &mut Option<SrgbColor> {
    if back { &mut scene.cloth.toon.back } else { &mut scene.cloth.toon.front }
}
