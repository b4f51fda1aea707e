//! Drape: cloth animation with fake dynamics.
//!
//! Drape follows "Faking Dynamics of Cloth Animation for Animated Films": a grid
//! cloth hangs from pins, is shaped by 3D catenaries between the pins and relaxed
//! into a rest shape; each keyframe is such a rest shape, in-betweens are eased,
//! and layered deformers add motion. Every frame is computed directly from the
//! scene, never from earlier frames.
//!
//! # The folders as the paper's pipeline
//!
//! ```text
//! scene/     the document (a RON file): cloth, keys with pins and fabric, the layer stack
//!   │          (each layer parameter listed once: scene/layers.rs)
//!   ▼
//! shape/     modelling (paper §3.1): catenaries between pins → surface approximation
//!   │          → relaxation = RestShape, one per key
//!   ▼
//! animate/   animation (§3.2–3.3): blend the rest shapes around t with the segment's
//!   │          easing, then the layer stack in order = mesh::Mesh at t
//!   ├─► export/    OBJ, PC2/MDD, glTF, USD, PNG/GIF files of the meshes
//!   └─► picture/   framing and key overlays ─► render/ (wgpu): meshes, overlays, camera → texture
//!
//! render_job/  picture/ and export/ together: a scene to a PNG, a PNG sequence or a GIF,
//!              with progress and cancel (`drape render`, the editor's File ▸ Render…)
//! editor/    the desktop editor (egui): changes the scene through undoable edits,
//!              shows it through picture/, writes it through export/ and render_job/
//! main.rs    the command line: `drape check | export | render`, or the editor
//! ```
//!
//! Beside the pipeline: [`world`] (colliders and referenced glTF rigs as
//! geometry at one moment), [`mesh`] (the grid as triangles), [`image`] (an
//! RGBA picture and PNG decoding), [`look`] (the cloth's tints and textures,
//! so a picture and an export agree) and [`atomic_file`] (writes that never
//! leave a partial file).
//!
//! # Who may import whom
//!
//! A module imports only what its row names, so the math never depends on a
//! GPU or a window, and `tests/architecture.rs` checks every `crate::` path
//! in `src/` against this table:
//!
//! | module | may import |
//! |---|---|
//! | `atomic_file`, `mesh`, `image` | nothing of Drape |
//! | `world` | `image` |
//! | `scene` | `atomic_file`, `image`, `world` |
//! | `shape` | `scene`, `mesh`, `world` |
//! | `animate` | `scene`, `shape`, `mesh`, `world` |
//! | `look` | `scene` |
//! | `render` | `scene`, `mesh`, `image`, `look` |
//! | `picture` | `scene`, `shape`, `animate`, `mesh`, `image`, `render`, `world` |
//! | `export` | `scene`, `animate`, `mesh`, `image`, `look`, `atomic_file` |
//! | `render_job` | `scene`, `image`, `picture`, `render`, `export`, `atomic_file` |
//! | `editor` | `scene`, `shape`, `animate`, `mesh`, `image`, `picture`, `render`, `export`, `render_job`, `atomic_file`, `world` |
//!
//! `render` is a leaf that draws what it is handed: it never imports
//! `world`, `shape` or `animate` (a reference's texture reaches it as an
//! [`image::RgbaImage`], its triangles as numbers).
//!
//! Only [`render`] and [`editor`] touch wgpu, only [`editor`] egui; the
//! command line (`main.rs`) may use everything. Those two, with [`picture`]
//! and [`render_job`], are the cargo feature `editor` (on by default):
//! without it the library builds with no GPU or window crate at all.
//!
//! Conventions: right-handed, Y up, gravity along −Y, metres. Grid index
//! `(i, j)` has `i` along the width and `j = 0` on the top edge; vertex order
//! is always `j·cols + i`.

pub mod animate;
pub mod atomic_file;
#[cfg(feature = "editor")]
pub mod editor;
pub mod export;
pub mod image;
pub mod look;
pub mod mesh;
#[cfg(feature = "editor")]
pub mod picture;
#[cfg(feature = "editor")]
pub mod render;
#[cfg(feature = "editor")]
pub mod render_job;
pub mod scene;
pub mod shape;
pub mod world;
