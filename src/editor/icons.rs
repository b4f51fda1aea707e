//! Small drawn icon buttons for the side panels: key diamonds, arrows, a drag grip.

use eframe::egui;

/// The small drawn icons of the side panels (the default fonts have no such glyphs).
#[derive(Clone, Copy)]
pub(super) enum Icon {
    /// A key: filled when the parameter is keyed at this frame.
    Diamond {
        filled: bool,
    },
    Up,
    Down,
    /// Three bars: drag the row by it.
    Grip,
}

/// A 16-point icon button with an accessible `label`.
pub(super) fn icon_button(ui: &mut egui::Ui, icon: Icon, enabled: bool, label: &str) -> egui::Response {
    let sense = match icon {
        _ if !enabled => egui::Sense::hover(),
        Icon::Grip => egui::Sense::drag(),
        _ => egui::Sense::click(),
    };
    let (rect, response) = ui.allocate_exact_size(egui::vec2(16.0, 16.0), sense);
    response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Button, enabled, label));
    let visuals = ui.style().interact(&response);
    let color = if enabled { visuals.fg_stroke.color } else { ui.visuals().weak_text_color().gamma_multiply(0.5) };
    let c = rect.center();
    let r = 5.0;
    let points = match icon {
        Icon::Diamond { .. } => {
            vec![c + egui::vec2(0.0, -r), c + egui::vec2(r, 0.0), c + egui::vec2(0.0, r), c + egui::vec2(-r, 0.0)]
        }
        Icon::Up => vec![c + egui::vec2(0.0, -r), c + egui::vec2(r, r * 0.7), c + egui::vec2(-r, r * 0.7)],
        Icon::Down => vec![c + egui::vec2(0.0, r), c + egui::vec2(-r, -r * 0.7), c + egui::vec2(r, -r * 0.7)],
        Icon::Grip => {
            for dy in [-3.5, 0.0, 3.5] {
                let y = c.y + dy;
                ui.painter()
                    .line_segment([egui::pos2(c.x - r, y), egui::pos2(c.x + r, y)], egui::Stroke::new(1.2, color));
            }
            return response;
        }
    };
    let fill = match icon {
        Icon::Diamond { filled: true } => egui::Color32::from_rgb(255, 200, 20),
        Icon::Diamond { filled: false } => egui::Color32::TRANSPARENT,
        _ => color,
    };
    ui.painter().add(egui::Shape::convex_polygon(points, fill, egui::Stroke::new(1.2, color)));
    response
}
