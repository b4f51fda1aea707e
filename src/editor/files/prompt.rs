//! The "Save changes before closing?" question, asked before anything that
//! would throw away unsaved work: closing the window, opening another scene,
//! restoring a recovery file. Also the key handling shared by the editor's
//! modals.

use eframe::egui::{self, Align, Id, Key, Layout, Modal, Modifiers};

/// The user's answer to [`discard_prompt`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DiscardChoice {
    /// Save first, then go on.
    Save,
    /// Go on and lose the changes.
    Discard,
    /// Do not go on.
    Cancel,
}

/// Draws the question as a modal with `title` as its heading, `message` below
/// (e.g. "Save changes to tent.ron before closing?") and the buttons "Save",
/// "Don't Save" and "Cancel". Returns `Some` on the frame the user answers;
/// call it every frame until then. Enter and Escape answer Cancel (the
/// highlighted default): a key pressed out of habit neither writes over a
/// file nor loses work. Clicking beside the modal does nothing, so a stray
/// click cannot either. The prompt keeps no state of its own.
pub fn discard_prompt(ctx: &egui::Context, title: &str, message: &str) -> Option<DiscardChoice> {
    let id = Id::unique("drape discard prompt");
    let keys = take_modal_keys(ctx, id, &[]);
    let mut choice = (keys.escape || keys.enter).then_some(DiscardChoice::Cancel);
    Modal::new(id).show(ctx, |ui| {
        ui.set_max_width(420.0);
        ui.heading(title);
        ui.add_space(6.0);
        ui.label(message);
        ui.add_space(10.0);
        ui.horizontal(|ui| {
            // The destructive choice sits apart from the other two.
            if ui.button("Don't Save").clicked() {
                choice = Some(DiscardChoice::Discard);
            }
            ui.with_layout(Layout::right_to_left(Align::Center), |ui| {
                let cancel = egui::Button::new("Cancel").fill(ui.visuals().selection.bg_fill);
                if ui.add(cancel).clicked() {
                    choice = Some(DiscardChoice::Cancel);
                }
                if ui.button("Save").clicked() {
                    choice = Some(DiscardChoice::Save);
                }
            });
        });
    });
    choice
}

/// Enter and Escape pressed this frame, for a modal's default and cancel
/// actions.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct ModalKeys {
    pub enter: bool,
    pub escape: bool,
}

/// Takes Enter and Escape out of this frame's input for the modal `modal_id`
/// (an `egui::Modal` with that id), before any widget sees them, so a focused
/// text field does not also act on them. Enter is left alone while a widget
/// other than `enter_fields` has keyboard focus: a button reached with Tab
/// presses itself on Enter. Only the top modal (as of the previous frame, or
/// any modal when none was shown) gets the keys, so a prompt over a dialog
/// keeps them.
pub(crate) fn take_modal_keys(ctx: &egui::Context, modal_id: Id, enter_fields: &[Id]) -> ModalKeys {
    if !is_top_modal(ctx, modal_id) {
        return ModalKeys::default();
    }
    let enter_is_ours = ctx.memory(|m| m.focused().is_none_or(|focused| enter_fields.contains(&focused)));
    ctx.input_mut(|i| ModalKeys {
        enter: enter_is_ours && i.consume_key(Modifiers::NONE, Key::Enter),
        escape: i.consume_key(Modifiers::NONE, Key::Escape),
    })
}

/// Whether the `egui::Modal` with `modal_id` was the top modal in the
/// previous frame, or no modal was shown then (its own first frame).
pub(crate) fn is_top_modal(ctx: &egui::Context, modal_id: Id) -> bool {
    let layer = egui::LayerId::new(egui::Order::Foreground, modal_id);
    ctx.memory(|m| m.top_modal_layer().is_none_or(|top| top == layer))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::editor::ui_driver::UiDriver;

    struct Question {
        title: &'static str,
        message: &'static str,
    }

    fn prompt() -> UiDriver<Question, DiscardChoice> {
        let question = Question { title: "Unsaved changes", message: "Save changes to tent.ron before closing?" };
        UiDriver::new(question, |q, ctx| discard_prompt(ctx, q.title, q.message))
    }

    #[test]
    fn the_prompt_shows_its_question_and_three_buttons() {
        let driver = prompt();
        assert!(driver.shows("Unsaved changes"));
        assert!(driver.shows("Save changes to tent.ron before closing?"));
        for label in ["Save", "Don't Save", "Cancel"] {
            assert!(driver.exists(label), "{label} missing");
        }
    }

    #[test]
    fn each_button_gives_its_choice() {
        assert_eq!(prompt().click("Save"), Some(DiscardChoice::Save));
        assert_eq!(prompt().click("Don't Save"), Some(DiscardChoice::Discard));
        assert_eq!(prompt().click("Cancel"), Some(DiscardChoice::Cancel));
    }

    #[test]
    fn escape_and_enter_cancel() {
        assert_eq!(prompt().press(Key::Escape), Some(DiscardChoice::Cancel));
        assert_eq!(prompt().press(Key::Enter), Some(DiscardChoice::Cancel), "Enter never writes over the file");
    }

    #[test]
    fn enter_presses_a_button_reached_with_tab() {
        let mut driver = prompt();
        driver.focus("Don't Save");
        assert_eq!(driver.press(Key::Enter), Some(DiscardChoice::Discard));
    }

    #[test]
    fn nothing_is_chosen_without_input() {
        let mut driver = prompt();
        assert_eq!(driver.frame(Vec::new()), None);
        // A click beside the modal, on the backdrop, is not an answer.
        let pos = egui::pos2(5.0, 5.0);
        let button = |pressed| egui::Event::PointerButton {
            pos,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: Modifiers::NONE,
        };
        assert_eq!(driver.frame(vec![egui::Event::PointerMoved(pos), button(true), button(false)]), None);
    }

    /// A file dialog with the prompt possibly shown over it.
    struct Stacked {
        dialog: crate::editor::files::dialog::FileDialog,
        prompt_open: bool,
        choice: Option<DiscardChoice>,
    }

    fn show_stacked(
        state: &mut Stacked,
        ctx: &egui::Context,
    ) -> Option<crate::editor::files::dialog::FileDialogOutcome> {
        let outcome = state.dialog.show(ctx);
        if state.prompt_open {
            state.choice = discard_prompt(ctx, "Unsaved changes", "Save changes?");
            state.prompt_open = state.choice.is_none();
        }
        outcome
    }

    #[test]
    fn a_prompt_over_a_dialog_takes_the_keys_first() {
        use crate::editor::files::dialog::{FileDialog, FileDialogMode, FileDialogOutcome};
        let dir = tempfile::tempdir().unwrap();
        let dialog = FileDialog::new(FileDialogMode::Open, "Open Scene", dir.path(), "", "ron");
        let mut driver = UiDriver::new(Stacked { dialog, prompt_open: false, choice: None }, show_stacked);
        driver.state.prompt_open = true;
        driver.frame(Vec::new());
        assert_eq!(driver.press(Key::Escape), None, "the dialog stays open");
        assert_eq!(driver.state.choice, Some(DiscardChoice::Cancel));
        assert_eq!(driver.press(Key::Escape), Some(FileDialogOutcome::Cancelled));
    }
}
