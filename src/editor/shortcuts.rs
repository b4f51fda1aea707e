//! The editor's keyboard shortcuts, written once: the key handling consumes
//! their chords, the menus show their keys, and Help ▸ Keyboard shortcuts
//! lists them all.

use eframe::egui::{self, Key as KeyCode, KeyboardShortcut, Modifiers};

/// The keys of a shortcut.
pub enum Keys {
    /// Chords with modifiers, consumed whatever has the focus; any of them
    /// does it (the menus show the first).
    Chords(&'static [KeyboardShortcut]),
    /// Two chords for the two halves of one action (copy / paste).
    Pair(KeyboardShortcut, KeyboardShortcut),
    /// Plain keys and mouse gestures, as the help names them.
    Described(&'static str),
}

/// A row of Help ▸ Keyboard shortcuts: the keys and what they do.
pub struct Shortcut {
    pub keys: Keys,
    pub action: &'static str,
}

impl Shortcut {
    /// The first chord, for the key handling; `None` for described keys.
    pub fn chord(&self) -> Option<&KeyboardShortcut> {
        match &self.keys {
            Keys::Chords([first, ..]) | Keys::Pair(first, _) => Some(first),
            Keys::Chords([]) | Keys::Described(_) => None,
        }
    }

    /// Whether one of its chords was pressed this frame (taking the key
    /// press, so a text field does not get it too).
    pub fn consume(&self, ctx: &egui::Context) -> bool {
        let Keys::Chords(chords) = &self.keys else { return false };
        chords.iter().any(|chord| ctx.input_mut(|i| i.consume_shortcut(chord)))
    }

    /// The keys as a menu item shows them (its first chord).
    pub fn menu_text(&self, ctx: &egui::Context) -> String {
        match (&self.keys, self.chord()) {
            (Keys::Described(text), _) => (*text).to_owned(),
            (_, Some(chord)) => ctx.format_shortcut(chord),
            (_, None) => String::new(),
        }
    }

    /// The second half's keys of a pair as a menu item shows them.
    pub fn second_menu_text(&self, ctx: &egui::Context) -> String {
        match &self.keys {
            Keys::Pair(_, second) => ctx.format_shortcut(second),
            _ => self.menu_text(ctx),
        }
    }

    /// The keys as the help lists them: every chord.
    pub fn help_text(&self, ctx: &egui::Context) -> String {
        match &self.keys {
            Keys::Chords(chords) => chords.iter().map(|c| ctx.format_shortcut(c)).collect::<Vec<_>>().join(", "),
            Keys::Pair(first, second) => format!("{} / {}", ctx.format_shortcut(first), ctx.format_shortcut(second)),
            Keys::Described(text) => (*text).to_owned(),
        }
    }
}

const fn command(key: KeyCode) -> KeyboardShortcut {
    KeyboardShortcut::new(Modifiers::COMMAND, key)
}

const fn command_shift(key: KeyCode) -> KeyboardShortcut {
    KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::SHIFT), key)
}

const fn described(keys: &'static str, action: &'static str) -> Shortcut {
    Shortcut { keys: Keys::Described(keys), action }
}

pub const NEW: Shortcut = Shortcut { keys: Keys::Chords(&[command(KeyCode::N)]), action: "New scene" };
pub const OPEN: Shortcut = Shortcut { keys: Keys::Chords(&[command(KeyCode::O)]), action: "Open a scene" };
pub const SAVE: Shortcut = Shortcut { keys: Keys::Chords(&[command(KeyCode::S)]), action: "Save" };
pub const SAVE_AS: Shortcut = Shortcut { keys: Keys::Chords(&[command_shift(KeyCode::S)]), action: "Save as" };
pub const RENDER: Shortcut = Shortcut {
    keys: Keys::Chords(&[command(KeyCode::R)]),
    action: "Render a PNG, a PNG sequence or a GIF (the File menu's Render…)",
};
pub const UNDO: Shortcut = Shortcut { keys: Keys::Chords(&[command(KeyCode::Z)]), action: "Undo" };
pub const REDO: Shortcut =
    Shortcut { keys: Keys::Chords(&[command_shift(KeyCode::Z), command(KeyCode::Y)]), action: "Redo" };
pub const DELETE: Shortcut = described(
    "Delete",
    "Unpin the selected pins (or remove the selected collider, or delete the key selected on the timeline)",
);
pub const ADD_KEY: Shortcut = described("K", "Add a rest-shape key at the playhead, from the current pose");
pub const COPY_PASTE: Shortcut = Shortcut {
    keys: Keys::Pair(command(KeyCode::C), command(KeyCode::V)),
    action: "Copy the selected pins' positions / paste them on the key being edited",
};
pub const FRAME_ALL: Shortcut = described("F", "Frame the cloth and what it touches in the viewport");

/// Every shortcut, in the order Help ▸ Keyboard shortcuts lists them.
pub const SHORTCUTS: &[Shortcut] = &[
    NEW,
    OPEN,
    SAVE,
    SAVE_AS,
    RENDER,
    UNDO,
    REDO,
    DELETE,
    ADD_KEY,
    COPY_PASTE,
    FRAME_ALL,
    described("Space", "Play / pause"),
    described("Left / Right", "Step one frame back / forward"),
    described("Up / Down", "Next / previous key (rest-shape keys and the selected collider's or layer's keys)"),
    described("Home / End", "First / last frame"),
    described("Middle-drag, Alt+left-drag", "Orbit"),
    described("Shift+middle-drag", "Pan"),
    described("Mouse wheel", "Dolly"),
    described("Click a cloth point", "Pin it where it is (Shift+click: and select it)"),
    described("Click a pin", "Select it alone (viewport and grid editor)"),
    described("Shift+click a pin", "Add it to the selection"),
    described("Ctrl+click a pin", "Toggle it in the selection"),
    described("Drag on empty space", "Box-select pins (Shift adds, Ctrl toggles)"),
    described("Click on empty space", "Clear the selection"),
    described("Drag a pin", "Move the selected pins in the view plane"),
    described("Drag a gizmo arrow", "Move the selected pins (or collider) along X (red), Y (green) or Z (blue)"),
    described("Click a collider", "Select it: outlined, its numbers in the Colliders panel"),
    described("Drag a collider", "Move it in the view plane, at the playhead (keyed numbers get a key there)"),
    described("X / Y / Z while dragging", "Lock the move to that axis (again: unlock)"),
    described("Esc while dragging", "Put the pins (or the collider) back"),
    described("Click a reference (Attach by clicking)", "Attach the selected pin to that point of its skin"),
    described("Esc while attaching by clicking", "Attach nothing"),
];
