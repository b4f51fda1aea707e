//! The desktop editor (eframe: egui on winit with egui-wgpu). The only module
//! that knows egui; it draws through [`crate::render`] like headless code does.

pub mod app;
pub mod file_dialog;
pub mod prompt;
pub mod recent;
pub mod recovery;
#[cfg(test)]
mod ui_driver;
pub mod viewport;

pub use app::{DEFAULT_SCENE, DrapeApp, run};
