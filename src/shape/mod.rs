//! The modelling phase (paper §3.1), pure math: catenaries between pins, the
//! surface approximation, and relaxation into a rest shape (among colliders,
//! if the scene has any).

pub mod approximate;
pub mod catenary;
pub mod contact;
pub mod equilibrium;
pub mod lay_flat;
pub mod relax;
pub mod rest_shape;
pub mod through;

pub use approximate::{Approximation, CatenaryNetwork, GridSpec, PinLayout, PinPoint, Placement, approximate};
pub use catenary::Catenary;
pub use relax::{Cancelled, RelaxParams, RelaxProgress, RelaxReport, refine, relax, relax_with};
pub use rest_shape::RestShape;
