//! The desktop editor (eframe: egui on winit with egui-wgpu). The only module
//! that knows egui; it draws through [`crate::render`] like headless code does.

pub mod app;
pub mod bezier_handles;
mod cloth_panel;
pub mod curve_view;
pub mod document;
pub mod edits;
mod export_window;
pub mod file_dialog;
pub mod files;
pub mod grid_editor;
mod layers_panel;
pub mod param_edit;
pub mod picking;
pub mod prompt;
pub mod recent;
pub mod recovery;
pub mod shaper;
mod timeline;
#[cfg(test)]
mod ui_driver;
pub mod viewport;
mod viewport_input;

pub use app::{DEFAULT_SCENE, DrapeApp, run};
