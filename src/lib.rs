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
//!   ▼
//! export (OBJ, …) · render · editor · tests
//! ```
//!
//! Module boundaries: [`scene`], [`shape`], [`animate`] and [`mesh`] are pure
//! Rust with no GPU or UI; [`export`] writes files from a [`mesh::Mesh`].
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
