//! From a scene to a picture: everything between the evaluator and the
//! renderer, shared by `drape render`, the editor's viewport and the tests.
//!
//! [`crate::render`] only draws meshes, overlays and a camera; this module
//! decides what it draws:
//!
//! - [`framing`]: the camera and ground that show every key of a scene, and
//!   [`framed`]: the cloth with the references and colliders it touches, as framed;
//! - [`key_overlay`](mod@key_overlay): the overlays of the key in effect (pins, catenary
//!   network, triangulation) as plain lines and markers;
//! - [`colliders`](mod@colliders): the scene's colliders at a frame as solids to draw;
//! - [`references`](mod@references): the scene's referenced glTF files at a frame as solids;
//! - [`shot`]: the scene's shot camera at a frame;
//! - [`plate`](mod@plate): a render laid over the background plate;
//! - [`scene_renderer`]: a scene at a frame to an image, frame after frame.

pub mod colliders;
pub mod framed;
pub mod framing;
pub mod key_overlay;
pub mod plate;
pub mod references;
pub mod scene_renderer;
pub mod shot;

pub use colliders::collider_solids;
pub use framing::scene_bounds;
pub use key_overlay::{SceneOverlays, key_overlay};
pub use references::reference_solids;
pub use scene_renderer::{SceneRenderer, render_scene_frame};
pub use shot::{ShotLook, look_camera, scene_shot_camera_at, shot_camera_at, shot_look_at};
