//! The side panels: Cloth on the left (the fabric, the pins of the key
//! being edited, with the [`grid_editor`]), and on the right Layers,
//! Colliders, References and Shot. Each holds only its own state (open rows,
//! pickers, file dialogs) and draws from the workspace; none imports
//! another. A keyed number row ([`keyed_number`]) is the one way a panel
//! shows a number that can be keyed.

mod add_menu;
pub(super) mod cloth;
mod cloth_toon_rows;
pub(super) mod colliders;
pub mod grid_editor;
mod keyed_number;
pub(super) mod layers;
mod list_row;
mod node_picker;
mod pin_attach_rows;
pub(super) mod references;
pub(super) mod shot;
