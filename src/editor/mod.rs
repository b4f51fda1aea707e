//! The desktop editor (eframe: egui on winit with egui-wgpu). The only module
//! that knows egui; it draws through [`crate::render`] like headless code does.
//!
//! [`app`] is thin: it owns a [`workspace::Workspace`] (the document, the
//! shapes on screen, the playhead and selections, the status line) and one
//! struct per panel, each holding only its own state and drawn by a `ui`
//! method that takes the workspace:
//! [`viewport_panel`] (with `viewport_input` for the mouse, [`viewport`] for
//! the GPU), `timeline`, `layers_panel`, `colliders_panel` and
//! `references_panel` (with [`curve_view`]), `cloth_panel`
//! (with [`grid_editor`]), [`files`] (with [`window_size`], kept beside the
//! recent files), `export_window` and `render_window`; [`manual`] shows the manual's pages. No panel imports
//! another panel or the app; what one panel changes for another (the
//! playhead, selected pins, key or layer, Follow, auto-key) lives in the
//! workspace's session.
//!
//! Shared behaviour has one home: every typed number is a `number_field`
//! (and `typing_pace` keeps typing and Tab in separate frames), the pin
//! selection rules are [`selection`]'s, the translate gizmo's geometry
//! [`gizmo`]'s, the timeline's zoom window `timeline_zoom`'s, and attaching
//! pins to references (and moving or letting go of attached pins) [`attach`]'s,
//! with [`reference_pick`] finding the skin point a click in the viewport
//! meets (`viewport_attach_input`; the mode lives in the session).
pub mod app;
pub mod attach;
pub mod bezier_handles;
mod cloth_panel;
mod cloth_toon_rows;
mod colliders_panel;
pub mod curve_view;
pub mod document;
pub mod edits;
mod export_window;
pub mod file_dialog;
pub mod files;
pub mod grid_editor;
mod icons;
mod keyed_number;
mod layers_panel;
pub mod manual;
mod node_picker;
mod number_field;
pub mod param_edit;
mod pin_attach_rows;
mod pin_clipboard;
pub mod prompt;
pub mod recent;
pub mod recovery;
mod references_panel;
mod render_window;
pub mod selection;
pub mod session;
pub mod shaper;
pub mod shortcuts;
mod shot_number;
mod shot_panel;
pub mod shown;
mod timeline;
mod timeline_zoom;
mod typing_pace;
#[cfg(test)]
mod ui_driver;
pub mod viewport;
pub mod window_size;
mod worker_job;
pub mod workspace;

pub use app::{DEFAULT_SCENE, DrapeApp, run};
