//! Self-contact: where the cloth passes through itself.

mod broad_phase;
mod crossings;
mod geometry;

pub use crossings::count_crossings;
