//! Exporters: files for other tools, all written atomically.

pub mod obj;

pub use crate::atomic_file::write_atomically;
pub use obj::write_obj;
