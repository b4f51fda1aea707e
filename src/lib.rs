//! Drape: cloth animation with fake dynamics.
//!
//! Drape follows "Faking Dynamics of Cloth Animation for Animated Films": a grid
//! cloth hangs from pins, is shaped by 3D catenaries between the pins and relaxed
//! into a rest shape; each keyframe is such a rest shape, in-betweens are eased,
//! and layered deformers add motion. Every frame is computed directly from the
//! scene, never from earlier frames.
//!
//! ```text
//! Scene (the document, RON file)
//!   │  per key: cloth grid + pins + fabric (elasticity, stiffness, relaxation)
//!   ▼
//! shape:    catenaries between pins → surface approximation → relaxation  = RestShape
//!   ▼
//! animate:  blend the two rest shapes around t, apply the layer stack      = Mesh at t
//!   ├─► export:   OBJ, PC2/MDD, glTF, USD files of the meshes
//!   └─► picture:  framing + key overlays ─► render (wgpu): meshes, overlays, camera → texture
//!                 (for `drape render`, the editor's viewport and the tests)
//! ```
//!
//! Module boundaries: [`scene`], [`shape`], [`animate`] and [`mesh`] are pure
//! Rust with no GPU or UI. [`render`] draws meshes and plain overlays and
//! imports neither [`shape`] nor [`animate`]; [`picture`] sits above it and
//! turns a scene into what it draws. [`export`] writes files from a
//! [`mesh::Mesh`] and does not import [`render`]: the picture type
//! ([`image`]) and the cloth's look ([`look`]) sit below both.
//!
//! Conventions: right-handed, Y up, gravity along −Y, metres. Grid index
//! `(i, j)` has `i` along the width and `j = 0` on the top edge; vertex order
//! is always `j·cols + i`.

pub mod animate;
pub mod atomic_file;
pub mod editor;
pub mod export;
pub mod image;
pub mod look;
pub mod mesh;
pub mod picture;
pub mod render;
pub mod scene;
pub mod shape;
