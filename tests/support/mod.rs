//! Code the integration tests share (and the benches, through `#[path]`;
//! `winding.rs` is included by path where it is used).

pub mod equilibrium_cases;
