//! The scene document: serde types, RON load/save, validation and errors.
//!
//! - [`Scene`] and its parts, [`Param`]: the data model; field names are fixed by DESIGN.md.
//! - [`Collider`] and its kinds: what the cloth rests on and never enters.
//! - [`ShotCamera`]: the camera the shot is seen through; [`Plate`] the picture behind
//!   the cloth in it, its files found by [`PlateFiles`] and vetted by [`check_plate`].
//! - [`Reference`]: a glTF file of the shot (a character), read into a rig by [`read_references`].
//! - [`Layer`] and its kinds ([`Sway`], [`Wave`], [`Gusts`], [`FollowThrough`]):
//!   each parameter listed once with its unit, range, default and doc
//!   ([`ParamSpec`]); reading, validation, the editor and `drape check` follow it.
//! - [`parse`], [`parse_bytes`], [`load`]: text or file → validated [`Scene`]
//!   (files up to [`MAX_SCENE_FILE_BYTES`]).
//! - [`to_ron_string`], [`save`]: [`Scene`] → pretty RON; `save` is atomic.
//! - [`Scene::validate`]: the rules serde cannot express, every limit a named
//!   constant (e.g. [`MAX_GRID_POINTS`]); each [`Issue`] names its value's path.
//! - [`SceneError`]: `FILE:LINE:COL: message` in the user's terms.
//! - [`readable_number`], [`readable_vec3`], [`shown_name`], [`escaped`]: numbers, names and
//!   quoted text as messages show them.
//! - [`locate`]: where a value path such as `keys[0].pins[2].grid` starts in the text.

mod colliders;
mod display;
mod error;
mod format;
pub mod fuzz;
mod gltf_structure;
mod io;
mod layers;
mod loaded;
mod locate;
mod mesh_files;
mod param;
mod plate;
mod plate_files;
mod plate_header;
mod read_capped;
mod reference_files;
mod references;
mod schema;
mod shot_camera;
mod toon;
mod types;
mod validate;

pub use colliders::{
    Block, Capsule, Collider, ColliderField, ColliderNumber, Cylinder, Ground, Measure, MeshCollider, ParamVec3, Sphere,
};
pub use display::{
    MAX_SHOWN_NAME_CHARS, escaped, readable_bytes, readable_number, readable_vec3, shown_name, truncated_name,
};
pub use error::SceneError;
pub use format::{MAX_LINE_CHARS, to_ron_string};
pub use io::{MAX_SCENE_FILE_BYTES, load, parse, parse_bytes, save};
pub use layers::*;
pub use loaded::{Loaded, LoadedMesh, LoadedRig};
pub use locate::{TextPosition, locate};
pub use mesh_files::{
    MAX_MESH_FILE_BYTES, mesh_from_bytes, move_referenced_files, read_mesh, read_meshes, relative_path,
};
pub use param::{Ease, Param, ParamKey};
pub use plate::{MAX_PLATE_DIGITS, MAX_PLATE_FRAME_OFFSET, Plate, PlatePattern};
pub use plate_files::{CheckedPlate, PlateFiles, PlateFrame, check_plate, frame_list, load_plate_image};
pub use plate_header::{PictureFormat, PlatePicture, read_plate_header};
pub use read_capped::read_capped;
pub use reference_files::{MAX_REFERENCE_VERTICES, read_references, read_rig, rig_from_bytes};
pub use references::{Attachment, ClipFrames, Follow, NodeAttachment, Reference, SurfaceAttachment};
pub use schema::{Access, Family, MAX_LAYER_VALUE, ParamRange, WaveAxis};
pub use shot_camera::{
    DEFAULT_FOCAL_LENGTH_MM, DEFAULT_SENSOR_WIDTH_MM, ReferenceCamera, ShotCamera, focal_length_from_yfov,
    horizontal_fov_deg,
};
pub use toon::{
    MAX_CREASE_DEG, MAX_INK_WIDTH_PX, MAX_TOON_BANDS, MIN_TOON_BANDS, SrgbColor, ToonSettings, linear_rgb,
    linear_to_srgb, srgb_to_linear,
};
pub use types::*;
pub use validate::*;
