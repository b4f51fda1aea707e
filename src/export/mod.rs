//! Exporters: files for other tools, all written atomically.

pub mod atomic;
pub mod obj;

pub use atomic::write_atomically;
pub use obj::write_obj;
