//! Code the integration tests share (and the benches, through `#[path]`).

pub mod equilibrium_cases;
