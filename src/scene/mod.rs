//! The scene document: serde types, RON load/save, validation and errors.

mod param;
mod types;

pub use param::{Param, ParamKey};
pub use types::*;
