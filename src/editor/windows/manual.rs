//! The manual's pages (`docs/`), built into the editor so that Help shows
//! them wherever Drape is installed, as the Markdown they are written in.

use eframe::egui;

/// Each page's menu title and text.
pub const MANUAL_PAGES: [(&str, &str); 8] = [
    ("Tutorials", include_str!("../../../docs/tutorials.md")),
    ("The editor", include_str!("../../../docs/editor.md")),
    ("Command line", include_str!("../../../docs/command-line.md")),
    ("Exporting", include_str!("../../../docs/exporting.md")),
    ("Scene files", include_str!("../../../docs/scene-files.md")),
    ("Rendering", include_str!("../../../docs/rendering.md")),
    ("Blender", include_str!("../../../docs/blender.md")),
    ("How it works", include_str!("../../../docs/how-it-works.md")),
];

/// Which manual page is open, if any.
#[derive(Default)]
pub struct Manual {
    page: Option<usize>,
}

impl Manual {
    /// The Help menu's entries, one per page.
    pub fn menu_ui(&mut self, ui: &mut egui::Ui) {
        ui.label("Manual");
        for (index, (title, _)) in MANUAL_PAGES.iter().enumerate() {
            if ui.button(*title).clicked() {
                self.page = Some(index);
            }
        }
    }

    /// The open page in a window of its own, scrolled, its text selectable.
    pub fn window_ui(&mut self, ctx: &egui::Context) {
        let Some(index) = self.page else { return };
        let (title, text) = MANUAL_PAGES[index];
        let mut open = true;
        egui::Window::new(format!("Manual: {title}"))
            .id(egui::Id::unique("drape manual"))
            .open(&mut open)
            .default_size([640.0, 560.0])
            .vscroll(true)
            .show(ctx, |ui| {
                ui.label(egui::RichText::new(text).monospace());
            });
        if !open {
            self.page = None;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every page starts with its title as the one top-level heading (a
    /// `#` inside a code block is a comment, not a heading).
    #[test]
    fn every_page_has_one_title() {
        for (title, text) in MANUAL_PAGES {
            let mut in_code = false;
            let mut headings = 0;
            for line in text.lines() {
                in_code ^= line.starts_with("```");
                headings += usize::from(!in_code && line.starts_with("# "));
            }
            assert_eq!(headings, 1, "{title}: {headings} top-level headings");
            assert!(text.starts_with("# "), "{title} starts with its title");
        }
    }
}
