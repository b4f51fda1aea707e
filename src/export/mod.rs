//! Exporters: files for other tools, all written atomically.

pub mod gif;
pub mod obj;
pub mod png;

pub use crate::atomic_file::write_atomically;
pub use gif::GifWriter;
pub use obj::write_obj;
pub use png::write_png;
