//! The desktop editor (eframe: egui on winit with egui-wgpu). The only module
//! that knows egui; it draws through [`crate::render`] like headless code does.
//!
//! The folders are what the user sees: [`viewport`] (the 3D view, its mouse
//! input, picking, the gizmo, drags, the shot camera's view and the plate
//! behind it; the GPU side in `viewport::gpu`), [`timeline`] (with the curve
//! view and its zoom), [`panels`] (Cloth with the grid editor, Layers,
//! Colliders, References, Shot), [`files`] (New, Open, Save, the file
//! dialog, recent files, recovery and the window's size) and [`windows`]
//! (Export, Render, the manual).
//!
//! [`app`] is thin: it owns a [`workspace::Workspace`] and one struct per
//! panel, each holding only its own state and drawn by a `ui` method that
//! takes the workspace. The workspace holds the [`document::Document`] (the
//! scene and its undo history), [`shown::Shown`] (the shapes on screen,
//! relaxed on [`shaper`]'s worker) and the [`session::Session`] (the
//! playhead and selections); each changes its own fields through methods
//! named for what the user did. No panel imports another panel or the app;
//! what one panel changes for another lives in the session.
//!
//! Shared behaviour has one home: every typed number is a `number_field`
//! (and `typing_pace` keeps typing and Tab in separate frames), the pin
//! selection rules are [`selection`]'s, edits of the scene [`edits`]' and
//! [`param_edit`]'s, and attaching pins to references (and moving or letting
//! go of attached pins) [`attach`]'s.
pub mod app;
pub mod attach;
pub mod document;
pub mod edits;
pub mod files;
mod icons;
mod number_field;
pub mod panels;
pub mod param_edit;
mod pin_clipboard;
pub mod selection;
pub mod session;
pub mod shaper;
pub mod shortcuts;
pub mod shown;
pub mod timeline;
mod typing_pace;
#[cfg(test)]
mod ui_driver;
pub mod viewport;
pub mod windows;
pub mod workspace;

pub use app::{DEFAULT_SCENE, DrapeApp, run};
