//! The editor's keyboard shortcuts, for the menus, the key handling and Help ▸ Shortcuts.

use eframe::egui::{Key as KeyCode, KeyboardShortcut, Modifiers};

pub const SHORTCUT_NEW: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, KeyCode::N);
pub const SHORTCUT_OPEN: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, KeyCode::O);
pub const SHORTCUT_SAVE: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, KeyCode::S);
pub const SHORTCUT_SAVE_AS: KeyboardShortcut =
    KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::SHIFT), KeyCode::S);
pub const SHORTCUT_UNDO: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, KeyCode::Z);
pub const SHORTCUT_REDO: KeyboardShortcut =
    KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::SHIFT), KeyCode::Z);
pub const SHORTCUT_REDO_ALT: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, KeyCode::Y);
pub const SHORTCUT_RENDER: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, KeyCode::R);

/// Every shortcut, for Help ▸ Shortcuts: (keys, what they do).
pub const SHORTCUTS: &[(&str, &str)] = &[
    ("Ctrl+N", "New scene"),
    ("Ctrl+O", "Open a scene"),
    ("Ctrl+S", "Save"),
    ("Ctrl+Shift+S", "Save as"),
    ("Ctrl+R", "Render a PNG, a PNG sequence or a GIF (the File menu's Render…)"),
    ("Ctrl+Z", "Undo"),
    ("Ctrl+Shift+Z, Ctrl+Y", "Redo"),
    ("Delete", "Unpin the selected pins (or remove the selected collider, or delete the key selected on the timeline)"),
    ("K", "Add a rest-shape key at the playhead, from the current pose"),
    ("Ctrl+C / Ctrl+V", "Copy the selected pins' positions / paste them on the key being edited"),
    ("F", "Frame the cloth and what it touches in the viewport"),
    ("Space", "Play / pause"),
    ("Left / Right", "Step one frame back / forward"),
    ("Up / Down", "Next / previous key (rest-shape keys and the selected collider's or layer's keys)"),
    ("Home / End", "First / last frame"),
    ("Middle-drag, Alt+left-drag", "Orbit"),
    ("Shift+middle-drag", "Pan"),
    ("Mouse wheel", "Dolly"),
    ("Click a cloth point", "Pin it where it is (Shift+click: and select it)"),
    ("Click a pin", "Select it alone (viewport and grid editor)"),
    ("Shift+click a pin", "Add it to the selection"),
    ("Ctrl+click a pin", "Toggle it in the selection"),
    ("Drag on empty space", "Box-select pins (Shift adds, Ctrl toggles)"),
    ("Click on empty space", "Clear the selection"),
    ("Drag a pin", "Move the selected pins in the view plane"),
    ("Drag a gizmo arrow", "Move the selected pins (or collider) along X (red), Y (green) or Z (blue)"),
    ("Click a collider", "Select it: outlined, its numbers in the Colliders panel"),
    ("Drag a collider", "Move it in the view plane, at the playhead (keyed numbers get a key there)"),
    ("X / Y / Z while dragging", "Lock the move to that axis (again: unlock)"),
    ("Esc while dragging", "Put the pins (or the collider) back"),
    ("Click a reference (Attach by clicking)", "Attach the selected pin to that point of its skin"),
    ("Esc while attaching by clicking", "Attach nothing"),
];
