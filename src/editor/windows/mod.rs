//! The windows the menus open over the editor: Export (the animation as
//! PC2, MDD, glTF, USD or OBJ) and Render (a PNG, a PNG sequence or a GIF),
//! each running its job off the UI thread ([`worker_job`]), and the manual.

pub(super) mod export;
pub mod manual;
pub(super) mod render;
mod worker_job;
